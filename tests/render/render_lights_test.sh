#!/usr/bin/env bash
# render compare --rt-lighting: the real-time model lit by what envmap-project --max-error
# chose (SH of the residual + an extracted sun, shaded analytically) against the path tracer,
# beside pure SH at the same band count (docs/render.md, docs/formats.md).
# shellcheck source=tests/cli/lib.sh
source "$(dirname "$0")/../cli/lib.sh"
R="$BIN/render"
EP="$BIN/envmap-project"

# A sky of 1 with a one-pixel sun of 30,000 at 50 deg from the zenith (row 40 of 128).
"$TBIN/inlight_make_test_image" "$WORK/sun.exr" 256 128 1 40 40 30000
cp "$(dirname "$0")/data/sun_patch.toml" "$WORK/scene.toml"

expect_exit 0 "envmap-project chooses the sun as a light" -- "$EP" "$WORK/sun.exr" -o "$WORK/sun_sh.json" \
    --max-error 0.01 -q
expect_true "the lighting file holds one light" -- jq -e '(.lights | length) == 1' "$WORK/sun_sh.json"

expect_exit 0 "compare with the lighting file" -- "$R" compare "$WORK/scene.toml" -o "$WORK/p.exr" --spp 64 --seed 3 \
    --rt-max-bands 3 --rt-bake-samples 256 --rt-supersample 1 --rt-lighting "$WORK/sun_sh.json" \
    --report "$WORK/p.json"
expect_true "outputs of the lit model written" -- test -s "$WORK/p_rt_lights.exr" -a -s "$WORK/p_compare_lights.png"
expect_true "the lighting file is a recorded input" -- \
    jq -e '[.inputs[].path | select(endswith("sun_sh.json"))] | length == 1' "$WORK/p.json"
expect_true "report: bands, one light, both models and their costs" -- \
    jq -e '.metrics.realtime.lighting_file | .sh_bands >= 1 and (.lights | length) == 1 and
           .with_lights_cost.operations > .pure_sh_cost.operations and .with_lights.mean_rel >= 0' "$WORK/p.json"
# At the same bands, pure SH smears the sun over the sphere; the analytic light does not.
expect_true "the sun as a light is at least 5x closer to the truth than pure SH" -- \
    jq -e '.metrics.realtime.lighting_file | .with_lights.mean_rel * 5 < .pure_sh_same_bands.mean_rel' "$WORK/p.json"
jq '{bands: .metrics.realtime.lighting_file.sh_bands, with_lights: .metrics.realtime.lighting_file.with_lights.mean_rel, pure_sh: .metrics.realtime.lighting_file.pure_sh_same_bands.mean_rel, truth_noise: .metrics.realtime.ground_truth_rel_error}' "$WORK/p.json"

# Bad input: --rt-lighting belongs to compare (usage), a malformed light names the file (runtime, no outputs).
expect_exit 2 "--rt-lighting is compare's, not trace's" -- "$R" trace "$WORK/scene.toml" -o "$WORK/q.exr" --spp 1 \
    --rt-lighting "$WORK/sun_sh.json"
jq '.lights[0].angular_radius_deg = 120' "$WORK/sun_sh.json" > "$WORK/bad_sh.json"
expect_exit 1 "a bad light is a runtime error" -- "$R" compare "$WORK/scene.toml" -o "$WORK/q.exr" --spp 1 \
    --rt-lighting "$WORK/bad_sh.json"
expect_stderr "bad_sh.json: lights\[0\]: light angular_radius_deg must be in \[0, 90\]" "error names the file and light"
expect_true "nothing written after the failure" -- test ! -e "$WORK/q.exr"

finish
