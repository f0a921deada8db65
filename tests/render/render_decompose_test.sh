#!/usr/bin/env bash
# render --compare --rt-decompose: the model's error by cause in the report (docs/render.md
# "Where the error comes from"); usage errors before any work.
# shellcheck source=tests/cli/lib.sh
source "$(dirname "$0")/../cli/lib.sh"
R="$BIN/render"
SCENES="${INLIGHT_SOURCE_DIR:?}/configs/scenes"
if [ ! -e /usr/share/blender/datafiles/studiolights/world/city.exr ]; then
    echo "skip: blender-data city.exr not installed"
    exit 0
fi
expect_exit 2 "--rt-decompose needs --compare" -- "$R" "$SCENES/sphere_city.toml" -o "$WORK/x.exr" --rt-decompose
expect_exit 2 "--rt-decompose-map-height out of range" -- "$R" "$SCENES/sphere_city.toml" -o "$WORK/x.exr" \
    --compare --rt-decompose --rt-decompose-map-height 2
expect_exit 0 "decompose a Lambert sphere in perspective" -- "$R" "$SCENES/sphere_city.toml" -o "$WORK/s.exr" \
    --width-px 12 --height-px 12 --spp 32 --no-jitter --compare --rt-decompose --rt-max-bands 3 \
    --rt-bake-samples 64 --rt-decompose-map-height 32 --report "$WORK/s.json"
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
finish
