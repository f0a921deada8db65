#!/usr/bin/env bash
# CLI behaviour of envmap-project: help, exit codes, bad inputs, reports, determinism.
# shellcheck source=tests/cli/lib.sh
source "$(dirname "$0")/lib.sh"
EP="$BIN/envmap-project"
MK="$TBIN/inlight_make_test_image"

"$MK" "$WORK/const.exr" 64 32 0.75
"$MK" "$WORK/bad_aspect.exr" 64 30 1
"$MK" "$WORK/nan.exr" 64 32 1 7 3 nan
"$MK" "$WORK/sun.exr" 256 128 1 40 30 30000

expect_exit 0 "--help" -- "$EP" --help
expect_true "--help shows an example" -- grep -q "Example:" "$WORK/stdout"
expect_true "--help lists --sh-bands" -- grep -q "sh-bands" "$WORK/stdout"
expect_exit 0 "--version" -- "$EP" --version
expect_exit 2 "unknown flag is a usage error" -- "$EP" "$WORK/const.exr" -o "$WORK/x.json" --frobnicate
expect_exit 2 "missing input file is a usage error" -- "$EP" "$WORK/none.exr" -o "$WORK/x.json"
expect_exit 2 "bands out of range" -- "$EP" "$WORK/const.exr" -o "$WORK/x.json" --sh-bands 0

# Constant environment: L00 = 2 sqrt(pi) * 0.75, irradiance = pi * 0.75 exactly.
# The default float row sums: each row sum within B = kFloatRowSumBound = 1.0133e-6 (rounded up)
# of the sum of |terms| (envmap/project.h), so |dL00| <= B L00 and |dL20| <= B sqrt(5) L00 (all
# pixels >= 0), and M33 = c4 L00 - c5 L20 is within (c4 + sqrt(5) c5) B L00.
FLOAT_B=1.0133e-6
expect_exit 0 "constant map" -- "$EP" "$WORK/const.exr" -o "$WORK/const_sh.json" --sh-bands 4 \
    --validate --report "$WORK/r.json"
# The console summary (docs/report.md): bands, and the validation's errors as in the report.
expect_stderr "envmap-project: const.exr: projection: 4 SH bands (16 coefficients per channel)" "summary: bands"
expect_summary_number "summary: mean relative error is the report's" \
    "irradiance error vs brute force \\(relative\\): mean ([0-9.e+-]+)," "$WORK/r.json" '.metrics.environments[0].validation.mean_rel'
expect_summary_number "summary: max relative error is the report's" \
    "irradiance error vs brute force \\(relative\\): .*, max ([0-9.e+-]+) over" "$WORK/r.json" '.metrics.environments[0].validation.max_rel'
expect_summary_number "summary: normal count is the report's" \
    "irradiance error vs brute force .* over ([0-9]+) normals" "$WORK/r.json" '.metrics.environments[0].validation.normals'
# The irradiance matrices are detail (they are in the JSON): printed with -v only.
expect_true "default verbosity: no irradiance matrices on the console" -- bash -c "! grep -q 'M_r =' '$WORK/stderr'"
expect_exit 0 "constant map, -v" -- "$EP" "$WORK/const.exr" -o "$WORK/const_v_sh.json" --sh-bands 4 -v
expect_stderr "M_r =" "-v prints the irradiance matrices"
# shellcheck disable=SC2016  # $l00 and $b are jq variables
expect_true "L00 = 2 sqrt(pi) v within the float bound B L00" -- \
    jq -e --argjson b "$FLOAT_B" '(2*(3.141592653589793|sqrt)*0.75) as $l00 | (.coefficients[0][0] - $l00 | fabs) <= $b * $l00' "$WORK/const_sh.json"
# shellcheck disable=SC2016  # $l00 and $b are jq variables
expect_true "irradiance matrix M33 = c4 L00 = pi v within (c4 + sqrt(5) c5) B L00" -- \
    jq -e --argjson b "$FLOAT_B" '(2*(3.141592653589793|sqrt)*0.75) as $l00 | (.irradiance_matrices.r[3][3] - 3.141592653589793*0.75 | fabs) <= (0.886227 + (5|sqrt)*0.247708) * $b * $l00' "$WORK/const_sh.json"
expect_true "report names the float row sums" -- jq -e '.metrics.environments[0].latlong_precision == "float"' "$WORK/r.json"
# The double path: exact to rounding (1e-12: ~1e3 double operations on O(1) values).
expect_exit 0 "constant map, double row sums" -- "$EP" "$WORK/const.exr" -o "$WORK/const_d_sh.json" \
    --sh-bands 4 --latlong-precision double
expect_true "double: L00 = 2 sqrt(pi) v to 1e-12" -- \
    jq -e '(.coefficients[0][0] - 2*(3.141592653589793|sqrt)*0.75 | fabs) < 1e-12' "$WORK/const_d_sh.json"
expect_true "double: irradiance matrix M33 = c4 L00 = pi v to 1e-12" -- \
    jq -e '(.irradiance_matrices.r[3][3] - 3.141592653589793*0.75 | fabs) < 1e-12' "$WORK/const_d_sh.json"
expect_exit 2 "bad --latlong-precision is a usage error" -- "$EP" "$WORK/const.exr" -o "$WORK/x.json" --latlong-precision half
expect_true "convention stated in the output" -- jq -e '.convention.basis | test("Condon-Shortley")' "$WORK/const_sh.json"
expect_true "binary written beside the JSON (20 + 16*3*4 bytes)" -- test "$(stat -c %s "$WORK/const_sh.bin")" -eq 212
for key in tool version status exit_code argv config seed threads wall_time_s inputs outputs metrics warnings stage_time_s; do
    jq -e "has(\"$key\")" "$WORK/r.json" >/dev/null || fail "report lacks $key"
done
pass "report has every required key"
expect_true "report input has sha256" -- jq -e '.inputs[0].sha256 | length == 64' "$WORK/r.json"
# The SH irradiance is exact here; what remains is the pixel-centre brute force's own error,
# which the report states as reference_self_error (relative to pi): max_abs / (pi v) must equal it.
expect_true "constant map: validation error is the reference's own error" -- \
    jq -e '.metrics.environments[0].validation | (.error_by_sh_bands["4"].max_abs / (3.141592653589793*0.75) - .reference_self_error | fabs) < 1e-9' "$WORK/r.json"

# Bad inputs: clear errors naming the file, exit 1, and no partial output.
expect_exit 1 "non-2:1 lat-long" -- "$EP" "$WORK/bad_aspect.exr" -o "$WORK/bad_sh.json" --report "$WORK/bad.json"
expect_stderr "bad_aspect.exr: expected a 2:1 lat-long map, got 64x30" "error names file and size"
expect_true "no output after failure" -- test ! -e "$WORK/bad_sh.json"
expect_true "report written with status failed" -- jq -e '.status == "failed" and .exit_code == 1' "$WORK/bad.json"
expect_exit 1 "NaN pixel rejected" -- "$EP" "$WORK/nan.exr" -o "$WORK/nan_sh.json"
expect_stderr "nan.exr: pixel (x=7, y=3) channel 0 is NaN" "error gives the NaN's position"
expect_exit 0 "NaN pixel replaced under --nonfinite zero" -- "$EP" "$WORK/nan.exr" -o "$WORK/nan_sh.json" \
    --nonfinite zero --report "$WORK/nan.json"
expect_true "replacement counted in the report" -- \
    jq -e '.metrics.environments[0].nonfinite_values_replaced == 3 and (.warnings | length) == 1' "$WORK/nan.json"

# Config files: keys are long options; unknown keys are usage errors; CLI overrides config.
printf 'sh-bands = 5\nvalidate = true\n' > "$WORK/good.toml"
printf 'sh-bandz = 5\n' > "$WORK/bad.toml"
expect_exit 0 "config file" -- "$EP" "$WORK/const.exr" -o "$WORK/cfg_sh.json" --config "$WORK/good.toml" --report "$WORK/cfg.json"
expect_true "config applied and echoed" -- jq -e '.config.sh_bands == 5 and .config.validate == true' "$WORK/cfg.json"
expect_exit 0 "CLI overrides config" -- "$EP" "$WORK/const.exr" -o "$WORK/cfg_sh.json" --config "$WORK/good.toml" --sh-bands 2 --report "$WORK/cfg.json"
expect_true "override wins" -- jq -e '.config.sh_bands == 2' "$WORK/cfg.json"
expect_exit 2 "unknown config key" -- "$EP" "$WORK/const.exr" -o "$WORK/cfg_sh.json" --config "$WORK/bad.toml"

# Quality gate: a sun of 3e4 at 2 bands cannot meet a 1% mean error budget.
expect_exit 3 "quality gate fails with exit 3" -- "$EP" "$WORK/sun.exr" -o "$WORK/sun_sh.json" --sh-bands 2 \
    --max-mean-rel-error 0.01 --report "$WORK/gate.json"
expect_true "gate status in report, outputs still written" -- \
    jq -e '.status == "quality_gate_failed" and .exit_code == 3' "$WORK/gate.json"
expect_true "outputs exist after a failed gate" -- test -s "$WORK/sun_sh.json"

# Same input, any thread count: byte-identical binary output. The input's SHA-256 is hashed on
# its own thread during the decode with 2 threads and after it with 1: the same digest as
# sha256sum's either way.
"$EP" "$WORK/sun.exr" -o "$WORK/t1.json" --sh-bands 9 --threads 1 -q --report "$WORK/t1r.json"
"$EP" "$WORK/sun.exr" -o "$WORK/t2.json" --sh-bands 9 --threads 2 -q --report "$WORK/t2r.json"
expect_true "identical output for --threads 1 and 2" -- cmp -s "$WORK/t1.bin" "$WORK/t2.bin"
expect_true "identical coefficients in the JSON for --threads 1 and 2" -- \
    cmp -s <(jq -c .coefficients "$WORK/t1.json") <(jq -c .coefficients "$WORK/t2.json")
SUN_SHA=$(sha256sum "$WORK/sun.exr" | cut -d' ' -f1)
# shellcheck disable=SC2016  # $h is a jq variable
for t in 1 2; do
    expect_true "--threads $t: report's input digest is sha256sum's" -- \
        jq -e --arg h "$SUN_SHA" '.inputs == [{path: .inputs[0].path, sha256: $h}]' "$WORK/t${t}r.json"
done
# shellcheck disable=SC2016  # $h is a jq variable
expect_true "failed load: the report still names the input with its digest" -- \
    jq -e --arg h "$(sha256sum "$WORK/bad_aspect.exr" | cut -d' ' -f1)" '.inputs[0].sha256 == $h' "$WORK/bad.json"

# Several inputs into a directory.
expect_exit 0 "two inputs into a directory" -- "$EP" "$WORK/const.exr" "$WORK/sun.exr" -o "$WORK/many" -q \
    --report "$WORK/many.json"
# shellcheck disable=SC2016  # $c and $s are jq variables
expect_true "each input's digest in the report, in order" -- jq -e --arg c "$(sha256sum "$WORK/const.exr" | cut -d' ' -f1)" \
    --arg s "$SUN_SHA" '[.inputs[].sha256] == [$c, $s]' "$WORK/many.json"
expect_true "one file pair per input" -- test -s "$WORK/many/const_sh.json" -a -s "$WORK/many/sun_sh.bin"

# An 8-bit camera frame through a response curve. A linear camera: g(z) = ln(z / 128), so code
# 128 at 0.5 s is radiance 2; one pixel clipped at 255 is reported with the light it hides.
"$MK" "$WORK/frame.png" 64 32 0.50196078431372548 10 5 1
jq -n '{format: "inlight_response", version: 1, channels: ["r", "g", "b"],
        g: [range(3) | [range(256) | if . == 0 then (0.5 / 128 | log) else (. / 128 | log) end]]}' \
    > "$WORK/linear_response.json"
expect_exit 2 "--response needs --exposure-s" -- "$EP" "$WORK/frame.png" -o "$WORK/f.json" \
    --response "$WORK/linear_response.json"
expect_exit 0 "8-bit frame with a response" -- "$EP" "$WORK/frame.png" -o "$WORK/f.json" \
    --response "$WORK/linear_response.json" --exposure-s 0.5 --report "$WORK/f_report.json"
expect_true "one saturated pixel counted" -- \
    jq -e '.metrics.environments[0].camera.saturated_pixels == 1' "$WORK/f_report.json"
expect_true "clipped light reported as a positive lower bound" -- \
    jq -e '.metrics.environments[0].camera.clipped_light_fraction_lower_bound > 0' "$WORK/f_report.json"
expect_true "radiance 2 in every unclipped pixel: L00 within the one clipped pixel of 4 sqrt(pi)" -- \
    jq -e '(.coefficients[0][1] - 4*(3.141592653589793|sqrt) | fabs) < 0.01' "$WORK/f.json"
expect_true "frames in camera RGB are tagged raw_camera" -- jq -e '.color_space == "raw_camera"' "$WORK/f.json"

# --report - puts only JSON on stdout.
"$EP" "$WORK/const.exr" -o "$WORK/s.json" --report - >"$WORK/stdout.json" 2>/dev/null
expect_true "--report - writes JSON alone on stdout" -- jq -e '.tool == "envmap-project"' "$WORK/stdout.json"

finish
