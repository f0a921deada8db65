#!/usr/bin/env bash
# render compare --decompose: the model's error by cause in the report (docs/render.md
# "Where the error comes from"); usage errors before any work.
# shellcheck source=tests/cli/lib.sh
source "$(dirname "$0")/../cli/lib.sh"
R="$BIN/render"
SCENES="${INLIGHT_SOURCE_DIR:?}/configs/scenes"
if [ ! -e /usr/share/blender/datafiles/studiolights/world/city.exr ]; then
    echo "skip: blender-data city.exr not installed"
    exit 0
fi
expect_exit 2 "--decompose is compare's, not trace's" -- "$R" trace "$SCENES/sphere_city.toml" -o "$WORK/x.exr" --decompose
expect_exit 2 "--decompose-map-height out of range" -- "$R" compare "$SCENES/sphere_city.toml" -o "$WORK/x.exr" \
    --decompose --decompose-map-height 2
expect_exit 0 "decompose a Lambert sphere in perspective" -- "$R" compare "$SCENES/sphere_city.toml" -o "$WORK/s.exr" \
    --width-px 12 --height-px 12 --spp 32 --no-jitter --decompose --rt-max-bands 3 \
    --rt-bake-samples 64 --decompose-map-height 32 --report "$WORK/s.json"
expect_true "every part per band count and the shared parts" -- jq -e '.metrics.realtime.decomposition
    | (.by_sh_bands | length == 3 and all(.[]; has("grid_interpolation") and has("sh_truncation_diffuse")
       and has("sh_truncation_specular") and has("total") and has("noise_to_model_error")))
      and has("visibility") and has("fixed_view") and has("truth_noise") and .map_height == 32' "$WORK/s.json"
expect_true "the truth's noise in the decomposition is the render's rel_error" -- \
    jq -e '.metrics.realtime.decomposition.truth_noise == .metrics.rel_error' "$WORK/s.json"
expect_true "Lambert: no specular truncation, truncation falls from 1 to 3 bands" -- \
    jq -e '.metrics.realtime.decomposition.by_sh_bands | .[0].sh_truncation_specular == 0
           and .[2].sh_truncation_diffuse < .[0].sh_truncation_diffuse' "$WORK/s.json"
expect_true "the decomposition is a timed stage of the run" -- jq -e '.stage_time_s | has("decompose")' "$WORK/s.json"

# The SH + lights model (--rt-lighting): the same parts, the lights' shading as one more, and the
# residual's truncation in place of the map's. A sky of 1 with a one-pixel sun of 30,000 (as in
# render_lights_test.sh) over a GGX patch facing an orthographic camera.
"$TBIN/inlight_make_test_image" "$WORK/sun.exr" 256 128 1 40 40 30000
cp "$(dirname "$0")/data/sun_patch.toml" "$WORK/sun.toml"
"$BIN/envmap-project" "$WORK/sun.exr" -o "$WORK/sun_sh.json" --max-error 0.01 -q
expect_true "the budget took the sun as a light" -- jq -e '(.lights | length) == 1' "$WORK/sun_sh.json"
expect_exit 0 "decompose the SH + lights model" -- "$R" compare "$WORK/sun.toml" -o "$WORK/l.exr" --width-px 8 --height-px 8 \
    --spp 64 --no-jitter \
    --decompose --rt-max-bands 3 --rt-bake-samples 64 --decompose-map-height 128 \
    --rt-lighting "$WORK/sun_sh.json" --report "$WORK/l.json"
# shellcheck disable=SC2016  # $vars in the single-quoted jq programs are jq's own
expect_true "every part at the file's bands, the lights' shading and the noise ratio" -- \
    jq -e --slurpfile f "$WORK/sun_sh.json" '.metrics as $m | $m.realtime.decomposition_lighting_file
    | .lights == 1 and (.by_sh_bands | length == $f[0].sh_bands
        and all(.[]; has("sh_truncation_diffuse") and has("noise_to_model_error")))
      and .light_shading_diffuse >= 0 and .light_shading_specular > 0 and has("visibility")
      and .truth_noise == $m.rel_error' "$WORK/l.json"
# With the sun taken out the residual is the uniform sky: its diffuse truncation at the file's
# bands is far below that of pure SH of the map at the same bands (the sun's ringing).
# shellcheck disable=SC2016
expect_true "the residual's truncation is 10x below pure SH's at the same bands" -- \
    jq -e '.metrics.realtime | (.decomposition_lighting_file.by_sh_bands | last) as $l
    | .decomposition.by_sh_bands[$l.sh_bands - 1].sh_truncation_diffuse > 10 * $l.sh_truncation_diffuse' "$WORK/l.json"
finish
