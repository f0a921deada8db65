#!/usr/bin/env bash
# render shade-btf --gles-bands: the compressed BTF drawn through its exported GLES shaders on
# this machine's OpenGL ES (Mesa llvmpipe through EGL) beside the CPU shading, graded against the
# path-traced truth, and a folder that ships its export checked byte for byte against it.
# jq programs use $-variables inside single quotes on purpose.
# shellcheck disable=SC2016
# shellcheck source=tests/cli/lib.sh
source "$(dirname "$0")/../cli/lib.sh"
R="$BIN/render"
FABRIC="${INLIGHT_SOURCE_DIR:?}/configs/fabrics/denim-plain.toml"
"$R" capture-btf "$FABRIC" -o "$WORK/dome" --width-px 8 --height-px 8 --spp 1 --btf-format exr -q ||
    fail "capture"
"$BIN/btf-pca" compress "$WORK/dome" -o "$WORK/pca" -k 3 -c 4 -q || fail "btf-pca"
"$TBIN/inlight_make_test_image" "$WORK/sky.exr" 256 128 1.0
# A sun: one 2e4 pixel of a 128 x 64 map on a uniform 0.2 sky (~97% of the irradiance).
"$TBIN/inlight_make_test_image" "$WORK/sun.exr" 128 64 0.2 40 14 20000
printf '0 0\n37 21\n' >"$WORK/views.txt"
printf '37 21\n' >"$WORK/view1.txt"

expect_exit 0 "compressed, stream prefixes, GLES at 3 bands" -- "$R" shade-btf "$FABRIC" --btf "$WORK/dome" \
    --btf-compressed "$WORK/pca" --shade-stream 0,30 --gles-bands 3 --view-neighbours 3 \
    --shade-views "$WORK/views.txt" --environment "$WORK/sky.exr" --environment "$WORK/sun.exr" -o "$WORK/sh" \
    --spp 2 --report "$WORK/sh.json"
expect_true "the GLES pictures of the whole stream are written" -- test -s "$WORK/sh_sky_tv037_pv021_pca0_btf-es300-highp.exr"
# 4 components per group: two slabs, which both variants read (ES 1.00 with 19 fragment uniform
# vectors, above ES 2.0's guaranteed 16: llvmpipe has more).
expect_true "ES 3.00 and ES 1.00 at every prefix (0, 30, all 108)" -- jq -e '
    [.metrics.btf_shade.results[] | .compressed[0].gles as $g |
    ([$g[] | select(.variant == "btf-es300-highp") | .components_sent] == [0, 30, 108]) and
    ([$g[] | select(.variant == "btf-es100-highp") | .components_sent] == [0, 30, 108])] | length == 4 and all' "$WORK/sh.json"
expect_true "errors against truth, bias and bytes per prefix; bytes grow with the prefix" -- jq -e '
    [.metrics.btf_shade.results[] | [.compressed[0].gles[] | select(.variant == "btf-es300-highp")] |
    all(.mean_rel >= 0 and .mean_de2000 >= 0 and (.mean_luminance_rel_diff | type) == "number") and
    .[0].bytes_sent < .[1].bytes_sent and .[1].bytes_sent < .[2].bytes_sent] | all' "$WORK/sh.json"
# A uniform sky is band 0 alone: the SH lighting is exact, so the GLES picture equals the CPU
# shading of the same components, prefix and 3-view blend up to float32 (the shipped matrices,
# the GPU's sums of terms up to ~10x the pixel): 1e-5 relative RMSE. Measured <= 8e-8 on a
# 256 x 128 sky (a 32 x 16 one puts the two quadratures of the light weights 3e-3 apart); the
# CPU's nearest view instead of the shader's 3-view blend at (37, 21) gives 0.42.
expect_true "uniform sky: GLES = CPU compressed shading within 1e-5 relative RMSE at every prefix" -- jq -e '
    [.metrics.btf_shade.results[] | select(.environment | endswith("sky.exr")) | .compressed[0].gles[].vs_cpu_compressed.rel_rmse]
    | length == 12 and all(. < 1e-5)' \
    "$WORK/sh.json"

# The sun: 3 SH bands smear it (the whole stream's picture 0.17 off the CPU shading of the whole
# map; the means alone do not see where in a group's cells light falls, 3e-3); taken out
# as a dominant light (--gles-lights) and spread over the light directions by the cell rule, with
# the constant residual exact in SH, the picture is the CPU's within 2e-3 (measured 4e-4: the
# sun's pixel and its cap of equal solid angle land in the same cell). The lit run also draws a
# folder that ships its export (as a bundle's btf/: no atlases, docs/btf-gles.md "In the
# bundle"): drawn only when its files are this export's.
expect_true "3 bands alone: the whole stream's picture smeared, > 0.05 off the CPU shading" -- jq -e \
    '[.metrics.btf_shade.results[] | select(.environment | endswith("sun.exr")) | .compressed[0].gles[]
      | select(.components_sent == 108) | .lights == 0 and .vs_cpu_compressed.rel_rmse > 0.05] | length == 4 and all' \
    "$WORK/sh.json"
"$BIN/btf-pca" export-gles "$WORK/pca" -o "$WORK/gles" --atlases none -q \
    || fail "export-gles"
cp -r "$WORK/pca" "$WORK/ship"
cp "$WORK/gles"/* "$WORK/ship/"
expect_exit 0 "the sun as a dominant light, from a folder shipping the same export" -- "$R" shade-btf "$FABRIC" \
    --btf "$WORK/dome" --btf-compressed "$WORK/ship" --gles-bands 3 --gles-lights 1 --view-neighbours 3 \
    --shade-views "$WORK/view1.txt" --environment "$WORK/sun.exr" -o "$WORK/sun1" --spp 1 --report "$WORK/sun1.json"
expect_true "the sun as a dominant light: 1 light, within 2e-3 of the CPU shading, both variants" -- jq -e \
    '[.metrics.btf_shade.results[].compressed[0].gles[] | .lights == 1 and .vs_cpu_compressed.rel_rmse < 2e-3]
     | length == 2 and all' "$WORK/sun1.json"
printf '\n// edited\n' >>"$WORK/ship/btf-es300-highp.frag"
expect_exit 1 "a shipped shader that is not the export drawn" -- "$R" shade-btf "$FABRIC" --btf "$WORK/dome" \
    --btf-compressed "$WORK/ship" --gles-bands 3 --shade-views "$WORK/view1.txt" --environment "$WORK/sky.exr" \
    -o "$WORK/bad" --spp 1
expect_stderr "btf-es300-highp.frag" "the error names the shipped file"

"$BIN/btf-pca" compress "$WORK/dome" -o "$WORK/pcaexr" -k 3 -c 2 --format exr-float -q || fail "btf-pca exr"
expect_exit 1 "float EXR components cannot be drawn by the 8-bit shaders: refused before any shading" -- \
    "$R" shade-btf "$FABRIC" --btf "$WORK/dome" --btf-compressed "$WORK/pcaexr" --gles-bands 3 \
    --environment "$WORK/sky.exr" -o "$WORK/bad" --spp 1
expect_stderr "pcaexr/g000-mean.exr" "the error names the file"
expect_true "no shading was done first" -- bash -c "! grep -q 'shade sky' '$WORK/stderr'"
expect_exit 2 "--gles-bands without --btf-compressed" -- "$R" shade-btf "$FABRIC" --btf "$WORK/dome" \
    --gles-bands 3 --environment "$WORK/sky.exr" -o "$WORK/bad"
expect_exit 2 "--gles-bands 10" -- "$R" shade-btf "$FABRIC" --btf "$WORK/dome" --btf-compressed "$WORK/pca" \
    --gles-bands 10 --environment "$WORK/sky.exr" -o "$WORK/bad"
expect_exit 2 "--gles-lights without --gles-bands" -- "$R" shade-btf "$FABRIC" --btf "$WORK/dome" \
    --btf-compressed "$WORK/pca" --gles-lights 1 --environment "$WORK/sky.exr" -o "$WORK/bad"
expect_true "nothing written after failed runs" -- bash -c "! ls '$WORK'/bad* 2>/dev/null"
finish
