#!/usr/bin/env bash
# render shade-btf with a btf-pca folder beside the raw BTF (--btf-compressed), its stream
# prefixes (--shade-stream) and interpolated views (--view-interp), at a tiny size.
# jq programs use $-variables inside single quotes on purpose.
# shellcheck disable=SC2016
# shellcheck source=tests/cli/lib.sh
source "$(dirname "$0")/../cli/lib.sh"
R="$BIN/render"
FABRIC="${INLIGHT_SOURCE_DIR:?}/configs/fabrics/denim-plain.toml"
"$R" capture-btf "$FABRIC" -o "$WORK/dome" --width-px 4 --height-px 4 --spp 1 --btf-format exr -q ||
    fail "capture"
"$BIN/btf-pca" compress "$WORK/dome" -o "$WORK/pca" -k 81 -c 4 --format exr-float -q || fail "btf-pca"
"$TBIN/inlight_make_test_image" "$WORK/sky.exr" 32 16 1.0
printf '37 21\n45 40\n' >"$WORK/views.txt"

expect_exit 0 "compressed beside raw, stream prefixes, Delaunay views" -- "$R" shade-btf "$FABRIC" --btf "$WORK/dome" \
    --btf-compressed "$WORK/pca" --shade-stream 0,2,1000 --view-interp delaunay --shade-views "$WORK/views.txt" \
    --environment "$WORK/sky.exr" -o "$WORK/sh" --spp 2 --report "$WORK/sh.json"
expect_true "the compressed image is written" -- test -s "$WORK/sh_sky_tv045_pv040_pca0.exr"
expect_true "off-grid view blends 3 measured views, a measured one 1" -- jq -e \
    '.metrics.btf_shade | .view_interp == "delaunay" and .results[0].btf_views == 3 and .results[1].btf_views == 1' "$WORK/sh.json"
expect_true "compressed: C per group, bytes, errors against truth and raw" -- jq -e '.metrics.btf_shade.results[] |
    .compressed[0] | .components_per_group == [4] and .stored_bytes > 0 and .mean_rel >= 0 and .vs_raw.rel_rmse >= 0' "$WORK/sh.json"
expect_true "stream: bytes grow, the whole stream is the full model" -- jq -e '.metrics.btf_shade.results[] |
    .compressed[0] as $c | $c.stream | length == 3 and .[0].components_sent == 0 and .[2].components_sent == 4 and
    .[0].bytes_sent < .[1].bytes_sent and .[1].bytes_sent < .[2].bytes_sent and
    ((.[2].mean_rel - $c.mean_rel) | fabs) < 1e-12' "$WORK/sh.json"

expect_exit 2 "--shade-stream without --btf-compressed" -- "$R" shade-btf "$FABRIC" --btf "$WORK/dome" \
    --shade-stream 1 --environment "$WORK/sky.exr" -o "$WORK/bad"
expect_exit 2 "--view-interp with --view-neighbours" -- "$R" shade-btf "$FABRIC" --btf "$WORK/dome" \
    --view-interp thesis --view-neighbours 3 --environment "$WORK/sky.exr" -o "$WORK/bad"
cp -r "$WORK/pca" "$WORK/other"  # the same files, one light direction moved: another BTF's
jq '.lights[1] = [16, 0]' "$WORK/pca/btf-pca.json" >"$WORK/other/btf-pca.json"
expect_exit 2 "a compressed BTF of other directions" -- "$R" shade-btf "$FABRIC" --btf "$WORK/dome" \
    --btf-compressed "$WORK/other" --environment "$WORK/sky.exr" -o "$WORK/bad"
expect_stderr "btf-compressed" "the mismatch names the option"
expect_true "nothing written after usage errors" -- bash -c "! ls '$WORK'/bad* 2>/dev/null"
finish
