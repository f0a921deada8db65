#!/usr/bin/env bash
# CLI behaviour of brdf-sh-bake: help, exit codes 0/1/2/3, material errors naming file and key,
# report fields, output files (binary size, JSON layout, GLSL, EXR), determinism across --threads.
# shellcheck source=tests/cli/lib.sh
source "$(dirname "$0")/../cli/lib.sh"
BAKE="$BIN/brdf-sh-bake"
SRC=${INLIGHT_SOURCE_DIR:?}
MAT="$SRC/configs/materials/satin-ggx.toml"

expect_exit 0 "--help" -- "$BAKE" --help
expect_true "--help shows an example" -- grep -q "Example:" "$WORK/stdout"
expect_true "--help lists --max-error" -- grep -q "max-error" "$WORK/stdout"
expect_exit 0 "--version" -- "$BAKE" --version
expect_exit 2 "unknown flag" -- "$BAKE" --material "$MAT" -o "$WORK/x" --frobnicate
expect_exit 2 "missing material file" -- "$BAKE" --material "$WORK/none.toml" -o "$WORK/x"
expect_exit 2 "bands out of range" -- "$BAKE" --material "$MAT" -o "$WORK/x" --sh-bands 9
expect_exit 2 "bad grid" -- "$BAKE" --material "$MAT" -o "$WORK/x" --grid hex:4
expect_stderr "unknown grid 'hex:4'" "bad grid is named"
expect_exit 2 "bad view" -- "$BAKE" --material "$MAT" -o "$WORK/x" --view 0,0
expect_exit 2 "--view and --view-deg exclude each other" -- "$BAKE" --material "$MAT" -o "$WORK/x" \
    --view 0,0,1 --view-deg 10

# Bad material files: exit 1, the message names the file, line and key; no output written.
printf 'specular = "ggx"\nroughness = 0.3\n' > "$WORK/bad_key.toml"
expect_exit 1 "unknown material key" -- "$BAKE" --material "$WORK/bad_key.toml" -o "$WORK/bad"
expect_stderr "bad_key.toml:2: unknown key 'roughness'" "error names file, line and key"
expect_true "no output after a failure" -- test ! -e "$WORK/bad.bin"
printf 'alpha = 1.5\n' > "$WORK/bad_value.toml"
expect_exit 1 "material value out of range" -- "$BAKE" --material "$WORK/bad_value.toml" -o "$WORK/bad"
expect_stderr "bad_value.toml:1: alpha: 1.5 is outside \[0, 1\]" "range error names the key"

# The report's setting: 5x5 grid, 9 coefficients = the report's 225 floats.
expect_exit 0 "report grid bake" -- "$BAKE" --config "$SRC/configs/brdf-sh-bake-report.toml" \
    --material "$SRC/configs/materials/report-cook-torrance.toml" -o "$WORK/rep" --report "$WORK/run.json" -q
expect_true "225 coefficients in the JSON (the report's u_BRDFCoeffs[225])" -- \
    jq -e '.coefficients | length == 225' "$WORK/rep.json"
expect_true "binary is 64 + 4*225 bytes" -- test "$(stat -c %s "$WORK/rep.bin")" -eq 964
expect_true "JSON metadata: model, integrator, grid, view, error" -- jq -e '.metadata |
    .model == "cook-torrance-report" and .integrator == "stratified-mc" and .grid == "report5x5"
    and (.view | length == 3) and (.error.integration_coeff_max_rel | type == "number")' "$WORK/rep.json"
for key in tool version status exit_code argv config seed threads wall_time_s inputs outputs metrics warnings; do
    jq -e "has(\"$key\")" "$WORK/run.json" >/dev/null || fail "report lacks $key"
done
pass "report has every required key"
for key in integration_coeff_max_rel interpolation_radiance_max_rel truncation_radiance_max_rel \
           total_radiance_max_rel reference_error_max_rel bake_time_s coeff_count; do
    jq -e ".metrics | has(\"$key\")" "$WORK/run.json" >/dev/null || fail "metrics lack $key"
done
pass "metrics have the error and time fields"
expect_true "four outputs recorded" -- jq -e '.outputs | length == 4' "$WORK/run.json"
expect_true "GLSL declares the report-sized uniform" -- grep -q "BRDF_ROWS = 5" "$WORK/rep.glsl"
expect_true "texture EXR written" -- test -s "$WORK/rep_texture.exr"
if command -v glslangValidator >/dev/null; then
    { echo "#version 300 es"; cat "$WORK/rep.glsl"; echo "out vec4 o; void main() { float c[BRDF_NCOEFFS]; brdf_sh_lookup(vec3(0.0, 0.0, 1.0), 0, c); o = vec4(c[0]); }"; } > "$WORK/t.frag"
    expect_exit 0 "emitted GLSL compiles (glslangValidator)" -- glslangValidator "$WORK/t.frag"
fi

# Determinism: same seed, same bytes, for 1 and 2 threads (Monte Carlo integrator).
expect_exit 0 "bake, 1 thread" -- "$BAKE" --material "$MAT" --grid octa:5 --integrator stratified-mc \
    --samples 256 -o "$WORK/t1" --threads 1 -q
expect_exit 0 "bake, 2 threads" -- "$BAKE" --material "$MAT" --grid octa:5 --integrator stratified-mc \
    --samples 256 -o "$WORK/t2" --threads 2 -q
expect_true "identical binary for any --threads" -- cmp -s "$WORK/t1.bin" "$WORK/t2.bin"
expect_exit 0 "another seed" -- "$BAKE" --material "$MAT" --grid octa:5 --integrator stratified-mc \
    --samples 256 -o "$WORK/t3" --seed 7 -q
expect_true "a different seed changes the MC table" -- bash -c "! cmp -s '$WORK/t1.bin' '$WORK/t3.bin'"

# --max-error picks the bands and reports them; an impossible budget is a quality-gate failure
# (exit 3) with the outputs still written.
expect_exit 0 "--max-error" -- "$BAKE" --material "$SRC/configs/materials/velvet-charlie.toml" \
    --grid "thetaphi:5x8@60" --max-error 0.5 -o "$WORK/me" --report "$WORK/me_run.json" -q
expect_true "chosen bands reported and used" -- jq -e '.metrics.chosen_sh_bands >= 1 and
    .metrics.chosen_sh_bands == .metrics.sh_bands and
    .metrics.truncation_radiance_max_rel_by_bands[.metrics.sh_bands - 1] <= 0.5' "$WORK/me_run.json"
expect_exit 3 "unreachable --max-error" -- "$BAKE" --material "$MAT" --grid octa:3 \
    --max-error 1e-9 -o "$WORK/gate" --report "$WORK/gate_run.json" -q
expect_true "status quality_gate_failed" -- jq -e '.status == "quality_gate_failed"' "$WORK/gate_run.json"
expect_true "outputs written despite the gate" -- test -s "$WORK/gate.bin"

# The reference check can be skipped: the table is the same bytes (the reference only measures
# it), the table and report say no error was measured, and a default run says what it cost.
expect_exit 0 "bake with the reference check" -- "$BAKE" --material "$MAT" --grid octa:5 -o "$WORK/rc" \
    --report "$WORK/rc_run.json"
expect_stderr "reference check: [0-9.]* s of this run (--no-reference-check skips it" "says what the check costs"
expect_exit 0 "--no-reference-check" -- "$BAKE" --material "$MAT" --grid octa:5 -o "$WORK/norc" \
    --report "$WORK/norc_run.json" --no-reference-check
expect_true "same table bytes without the check" -- cmp -s "$WORK/rc.bin" "$WORK/norc.bin"
expect_true "no reference stage, report says so" -- jq -e '.metrics.reference_check == false and
    (.stage_time_s | has("reference") | not) and (.metrics | has("total_radiance_max_rel") | not)' "$WORK/norc_run.json"
expect_true "the checked run has the stage and its figures" -- jq -e '.metrics.reference_check == true and
    .stage_time_s.reference > 0 and .metrics.total_radiance_max_rel >= 0' "$WORK/rc_run.json"
expect_true "the table's error is null, not a figure" -- jq -e '.error == null' "$WORK/norc.json"
expect_exit 2 "--no-reference-check with --max-error" -- "$BAKE" --material "$MAT" --grid octa:5 \
    -o "$WORK/x1" --no-reference-check --max-error 0.1
expect_stderr "give --sh-bands instead" "says why and what to do"
expect_true "and wrote nothing" -- test ! -e "$WORK/x1.bin"
expect_exit 2 "--no-reference-check with --validate" -- "$BAKE" --material "$MAT" --grid octa:5 \
    -o "$WORK/x2" --no-reference-check --validate

# --config with an unknown key is a usage error.
printf 'grid = "octa:5"\nfrobnicate = 1\n' > "$WORK/bad.toml"
expect_exit 2 "unknown config key" -- "$BAKE" --config "$WORK/bad.toml" --material "$MAT" -o "$WORK/x"
finish
