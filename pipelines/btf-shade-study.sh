#!/usr/bin/env bash
# What the BTF's 81-direction sampling costs (docs/btf.md): captures a fabric's full UBO2003 BTF
# as float EXR (no 8-bit clipping), shades it under each environment and compares it with the
# path-traced truth of the same weave; prints one row per environment and view.
#   pipelines/btf-shade-study.sh [BUILD] [OUT] [SIZE_PX] [CAPTURE_SPP] [TRUTH_SPP] [FABRIC] [ENV...]
# BTF_SHADE_ARGS adds render options to the shading (e.g. "--light-cells constant").
# BTF_GLES_BANDS=N also compresses the capture (configs/btf-pca.toml, 8-bit linear components)
# and draws it through its exported GLES shaders at N SH bands of each environment (render
# shade-btf --gles-bands, docs/btf-gles.md), at stream prefixes 0, 27 and 81 and the whole stream;
# a second table gives those pictures against the truth. BTF_GLES_LIGHTS=L lights them with up
# to L dominant lights taken out of each environment plus the residual's SH (--gles-lights).
# BTF_LIGHT_SET=ubo2003-horizon captures the dome plus its horizon rings (render capture-btf
# --btf-light-set; docs/btf.md "Light beyond the last ring") instead of the 81-direction dome.
# BTF_LIGHT_SET=fibonacci-N captures N directions of equal solid angle instead (600 holds every
# fabric within 2%). BTF_CAPTURE_VIEWS=FILE captures only these views (render capture-btf
# --btf-views), e.g. the three the shading is graded at: same figures, a fraction of the images.
# Environments default to blender-data's studio lights and a synthetic sun (a 0.2 sky with one
# 2e4 pixel of a 128 x 64 map at theta 41, phi 66 deg, 0.0016 sr: ~97% of the irradiance).
set -euo pipefail
# shellcheck source=pipelines/lib.sh
. "$(dirname "$0")/lib.sh"
BUILD=${1:-$ROOT/build}
OUT=${2:-out/btf-shade}
SIZE=${3:-64}
CSPP=${4:-8}
TSPP=${5:-256}
FABRIC=${6:-$ROOT/configs/fabrics/wool-twill.toml}
shift $(( $# < 6 ? $# : 6 ))
mkdir -p "$OUT"
W=/usr/share/blender/datafiles/studiolights/world
ENVS=("$@")
if [ ${#ENVS[@]} -eq 0 ]; then
    "$BUILD/tests/inlight_make_test_image" "$OUT/sun.exr" 128 64 0.2 40 14 20000
    ENVS=("$W/city.exr" "$W/forest.exr" "$W/studio.exr" "$W/sunrise.exr" "$OUT/sun.exr")
fi
if [ ! -s "$OUT/btf/capture.json" ]; then
    "$BUILD/bin/render" capture-btf "$FABRIC" -o "$OUT/btf" --btf-format exr \
        --width-px "$SIZE" --height-px "$SIZE" --spp "$CSPP" --btf-light-set "${BTF_LIGHT_SET:-ubo2003}" \
        --threads 2 --report "$OUT/capture.json" -q ${BTF_CAPTURE_VIEWS:+--btf-views "$BTF_CAPTURE_VIEWS"}
fi
args=()
for e in "${ENVS[@]}"; do args+=(--environment "$e"); done
if [ -n "${BTF_GLES_BANDS:-}" ]; then
    if [ ! -s "$OUT/pca/btf-pca.json" ]; then
        "$BUILD/bin/btf-pca" compress "$OUT/btf" --config "$ROOT/configs/btf-pca.toml" -o "$OUT/pca" -q
    fi
    args+=(--btf-compressed "$OUT/pca" --shade-stream "0,27,81" --gles-bands "$BTF_GLES_BANDS"
        --gles-lights "${BTF_GLES_LIGHTS:-0}")
fi
# BTF_SHADE_ARGS: more render options for the shading, e.g. "--light-cells constant".
read -r -a extra <<<"${BTF_SHADE_ARGS:-}"
"$BUILD/bin/render" shade-btf "$FABRIC" --btf "$OUT/btf" "${args[@]}" -o "$OUT/shade" --spp "$TSPP" \
    --threads 2 --report "$OUT/shade.json" -q "${extra[@]}"
echo "| environment | view (deg) | mean rel. error | mean dE2000 | mean luminance, BTF vs truth | truth noise |"
echo "| --- | --- | --- | --- | --- | --- |"
jq -r '.metrics.btf_shade.results[] | "| \(.environment | split("/") | last) | \(.view_deg[0]), \(.view_deg[1]) | \(.mean_rel * 1000 | round / 1000) | \(.mean_de2000 * 100 | round / 100) | \(.mean_luminance_rel_diff * 1000 | round / 10)% | \(.truth_rel_error * 1000 | round / 1000) |"' "$OUT/shade.json"
if [ -n "${BTF_GLES_BANDS:-}" ]; then
    echo
    echo "The compressed BTF drawn by its GLES shaders ($BTF_GLES_BANDS SH bands, up to ${BTF_GLES_LIGHTS:-0} dominant lights) against the truth, per stream prefix"
    echo "(components sent: mean rel. error / mean dE2000 / mean luminance vs truth; bytes: the btf-pca files received)"
    echo
    jq -r '.metrics.btf_shade.results[0].compressed[0].gles | map(select(.variant == "btf-es300-highp")) |
        "| environment | view (deg) | " + (map("\(.components_sent) sent, \(.bytes_sent) B") | join(" | ")) + " | ES 1.00, whole stream |",
        "| --- | --- | " + (map("---") | join(" | ")) + " | --- |"' "$OUT/shade.json"
    jq -r '.metrics.btf_shade.results[] | .compressed[0].gles as $g |
        "| \(.environment | split("/") | last) | \(.view_deg[0]), \(.view_deg[1]) | " +
        ($g | map(select(.variant == "btf-es300-highp")) |
            map("\(.mean_rel * 1000 | round / 1000) / \(.mean_de2000 * 100 | round / 100) / \(.mean_luminance_rel_diff * 1000 | round / 10)%") | join(" | ")) +
        " | " + ($g | map(select(.variant == "btf-es100-highp")) | if length == 0 then "" else max_by(.components_sent) |
            "\(.mean_rel * 1000 | round / 1000) / \(.mean_de2000 * 100 | round / 100)" end) + " |"' "$OUT/shade.json"
fi
