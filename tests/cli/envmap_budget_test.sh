#!/usr/bin/env bash
# envmap-project --max-error: SH bands and dominant lights from an error budget (docs/budget.md).
# shellcheck source=tests/cli/lib.sh
source "$(dirname "$0")/lib.sh"
EP="$BIN/envmap-project"
MK="$TBIN/inlight_make_test_image"

"$MK" "$WORK/const.exr" 64 32 0.75
"$MK" "$WORK/sun.exr" 256 128 1 40 30 30000

expect_exit 0 "--help lists the budget options" -- "$EP" --help
for opt in --max-error --error-metric --max-lights --budget-max-bands --brdf-table --material; do
    grep -q -- "$opt" "$WORK/stdout" || fail "--help lacks $opt"
done
pass "--help names every budget option"

# A sun 30,000x the sky: one light, and the uniform residual needs one band.
expect_exit 0 "sun: budget 1%" -- "$EP" "$WORK/sun.exr" -o "$WORK/sun_sh.json" --max-error 0.01 \
    --report "$WORK/sun.json"
expect_true "one light chosen over 1 band" -- \
    jq -e '.metrics.environments[0].budget | .met and .chosen.lights == 1 and .chosen.sh_bands == 1' "$WORK/sun.json"
# The console summary says what the budget chose, in the singular where it is one.
expect_stderr "envmap-project: sun.exr: --max-error 0.01 (abs-over-mean): met with 1 SH band + 1 light: error " \
    "summary: budget, metric and choice, singular nouns"
expect_summary_number "summary: the achieved error is the report's" "met with .*: error ([0-9.e+-]+) over" \
    "$WORK/sun.json" '.metrics.environments[0].budget.chosen.error'
expect_summary_number "summary: the normals it was measured on are the report's" "error [0-9.e+-]+ over ([0-9]+) normals" \
    "$WORK/sun.json" '.metrics.environments[0].budget.normals'
expect_true "the light is in the output, the SH are of the residual" -- \
    jq -e '(.lights | length) == 1 and .sh_bands == 1 and (.lights[0].flux | length) == 3' "$WORK/sun_sh.json"
expect_true "binary holds the chosen bands (20 + 1*3*4 bytes)" -- test "$(stat -c %s "$WORK/sun_sh.bin")" -eq 32
expect_true "every configuration is reported with its error and cost" -- \
    jq -e '.metrics.environments[0].budget.candidates | length == 18 and all(.[]; .cost.operations > 0 and .irradiance.abs_over_mean >= 0 and .irradiance.mean_rel >= 0)' "$WORK/sun.json"
expect_true "the chosen one is the cheapest that meets the budget" -- \
    jq -e '.metrics.environments[0].budget | .chosen.cost.operations == ([.candidates[] | select(.meets) | .cost.operations] | min)' "$WORK/sun.json"

# Pure SH (--max-lights 0) needs more bands and costs more.
expect_exit 3 "pure SH cannot meet 1% on the sun within 9 bands" -- "$EP" "$WORK/sun.exr" -o "$WORK/pure_sh.json" \
    --max-error 0.01 --max-lights 0 --report "$WORK/pure.json"
expect_true "unmet budget: status and least-error output" -- \
    jq -e '.status == "quality_gate_failed" and (.metrics.environments[0].budget | .met == false and .chosen.lights == 0)' "$WORK/pure.json"
expect_true "outputs written after the failed gate, with no light" -- jq -e '(.lights | length) == 0' "$WORK/pure_sh.json"

# A constant map: no light found, one band exact, zero light cost.
expect_exit 0 "constant map" -- "$EP" "$WORK/const.exr" -o "$WORK/const_sh.json" --max-error 0.001 --report "$WORK/const.json"
expect_true "no light, one band" -- \
    jq -e '.metrics.environments[0].budget | (.lights_found | length) == 0 and .chosen.sh_bands == 1 and .chosen.lights == 0' "$WORK/const.json"

# The other metric is offered and named in the report.
expect_exit 0 "mean-rel metric" -- "$EP" "$WORK/sun.exr" -o "$WORK/mr_sh.json" --max-error 0.01 \
    --error-metric mean-rel --report "$WORK/mr.json"
expect_true "metric named" -- jq -e '.metrics.environments[0].budget.metric == "mean-rel"' "$WORK/mr.json"

# Bad values: usage errors before any work, no outputs.
for bad in nan inf -1 0x; do
    expect_exit 2 "--max-error $bad is a usage error" -- "$EP" "$WORK/sun.exr" -o "$WORK/bad_sh.json" --max-error "$bad"
done
expect_exit 2 "--error-metric must be known" -- "$EP" "$WORK/sun.exr" -o "$WORK/bad_sh.json" --max-error 0.01 --error-metric l2
expect_exit 2 "--brdf-table needs --material" -- "$EP" "$WORK/sun.exr" -o "$WORK/bad_sh.json" --max-error 0.01 \
    --brdf-table "$WORK/sun.exr"
expect_exit 2 "--max-error excludes --validate" -- "$EP" "$WORK/sun.exr" -o "$WORK/bad_sh.json" --max-error 0.01 --validate
printf 'garbage' > "$WORK/bad.bin"
printf 'specular = "ggx"\n' > "$WORK/ggx.toml"
expect_exit 1 "a bad table is a runtime error naming the file" -- "$EP" "$WORK/sun.exr" -o "$WORK/bad_sh.json" \
    --max-error 0.01 --brdf-table "$WORK/bad.bin" --material "$WORK/ggx.toml"
expect_stderr "bad.bin" "error names the table"
expect_true "no output after the failure" -- test ! -e "$WORK/bad_sh.json"

# With a material's BRDF table the outgoing radiance must meet the budget too.
"$BIN/brdf-sh-bake" --material "$WORK/ggx.toml" --grid octa:9 --sh-bands 3 --samples 256 -o "$WORK/ggx" -q
expect_exit 0 "budget with a BRDF table" -- "$EP" "$WORK/sun.exr" -o "$WORK/rad_sh.json" --max-error 0.05 \
    --brdf-table "$WORK/ggx.bin" --material "$WORK/ggx.toml" --report "$WORK/rad.json"
expect_true "radiance errors and table costs reported" -- \
    jq -e '.metrics.environments[0].budget | .radiance_normals > 0 and all(.candidates[]; .radiance.abs_over_mean >= 0 and .cost.texture_fetches > 0)' "$WORK/rad.json"
expect_true "the budget's error is the larger of irradiance and radiance" -- \
    jq -e 'all(.metrics.environments[0].budget.candidates[]; .error == ([.irradiance.abs_over_mean, .radiance.abs_over_mean] | max))' "$WORK/rad.json"

# A camera frame through the response: the clipped lamp is a light whose flux is a lower bound.
"$MK" "$WORK/frame.png" 64 32 0.0196078431372549 10 5 1
jq -n '{format: "inlight_response", version: 1, channels: ["r", "g", "b"],
        g: [range(3) | [range(256) | if . == 0 then (0.5 / 128 | log) else (. / 128 | log) end]]}' \
    > "$WORK/linear_response.json"
expect_exit 0 "camera frame with a clipped lamp" -- "$EP" "$WORK/frame.png" -o "$WORK/frame_sh.json" \
    --response "$WORK/linear_response.json" --exposure-s 0.5 --max-error 0.005 --report "$WORK/frame.json"
expect_true "the lamp is found with its clipped pixel, flux a lower bound" -- \
    jq -e '.metrics.environments[0].budget.lights_found[0] | .saturated_samples == 1 and .flux_is_lower_bound and .saturated_flux_fraction == 1' "$WORK/frame.json"
expect_true "the lamp is chosen as a light (cheaper than 3 bands)" -- \
    jq -e '.metrics.environments[0].budget.chosen.lights == 1' "$WORK/frame.json"
expect_true "the lower bound is stated in the warnings" -- jq -e '[.warnings[] | select(test("lower bound"))] | length >= 1' "$WORK/frame.json"

# Any thread count: identical outputs.
"$EP" "$WORK/sun.exr" -o "$WORK/t1.json" --max-error 0.01 --threads 1 -q
"$EP" "$WORK/sun.exr" -o "$WORK/t2.json" --max-error 0.01 --threads 2 -q
expect_true "identical output for --threads 1 and 2" -- cmp -s "$WORK/t1.json" "$WORK/t2.json"

finish
