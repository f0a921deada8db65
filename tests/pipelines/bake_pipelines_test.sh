#!/usr/bin/env bash
# bake-fabric and bake-device on small inputs: each stage's report, the skipped stages' messages,
# the bundles' contents; validate-pair + validate-report on one pair.
HERE=$(cd "$(dirname "$0")" && pwd)
# shellcheck source=tests/cli/lib.sh
source "$HERE/../cli/lib.sh"
# shellcheck source=tests/pipelines/tiny.sh
source "$HERE/tiny.sh"
require_blender_data
make_fabric "$WORK/fab" "Tiny weave" 0.2
expect_exit 0 "bake-fabric" -- "$PIPE/bake-fabric.sh" "$WORK/fab" "$WORK/out" tiny
expect_stderr "btf" "says what happened to the BTF stage"
expect_stderr "export-gles" "says what happened to the shader export"
M="$WORK/out/bundles/fabrics/tiny/manifest.json"
expect_true "fabric bundle roles" -- jq -e '[.files[].role] | sort == ["albedo","brdf_sh_table","brdf_sh_table_json","brdf_sh_texture","material","normal","shader_lookup","thumbnail"]' "$M"
expect_true "properties from the stage reports" -- jq -e '.name == "Tiny weave" and .properties.sh_bands == 3 and .properties.brdf_grid == "thetaphi:5x8" and .properties.tile_size_m == 0.05' "$M"
for step in maps/report.json brdf/report.json pack.json verify.json; do
    expect_true "report $step ok" -- jq -e '.status == "ok"' "$WORK/out/work/fabrics/tiny/$step"
done
mkdir -p "$WORK/nomat"
cp "$WORK/fab/fabric.toml" "$WORK/nomat/"
expect_exit 2 "bake-fabric without material.toml" -- "$PIPE/bake-fabric.sh" "$WORK/nomat" "$WORK/out2"
expect_stderr "material.toml not found" "names the missing file"

printf 'spp = 8\nwidth-px = 16\nheight-px = 16\nrt-max-bands = 4\nrt-supersample = 1\n' > "$WORK/v.toml"
expect_exit 0 "validate-pair" -- env VALIDATE_RENDER_CONFIG="$WORK/v.toml" "$PIPE/validate-pair.sh" \
    "$WORK/out/bundles/fabrics/tiny" "$HDRI_DIR/sunset.exr" "$WORK/val/pairs/tiny/sunset"
expect_true "pair summary: 4 band counts, seed and consistent modes" -- jq -e \
    '(.by_sh_bands | length) == 4 and .consistent.mean_de2000 > 0 and .seed.mean_de2000 > 0 and .environment == "sunset"' \
    "$WORK/val/pairs/tiny/sunset/summary.json"
expect_exit 0 "validate-report" -- "$PIPE/validate-report.sh" "$WORK/val"
expect_true "verdict and advice" -- jq -e '.[0].verdict != null and (.[0].advice | length) > 0' "$WORK/val/summary.json"
for p in error_vs_sh_bands error_vs_frame_time truth_noise error_vs_bytes; do
    expect_true "plot $p is a PNG" -- bash -c "file '$WORK/val/plots/$p.png' | grep -q 'PNG image'"
done
expect_true "page links the pair's images" -- grep -q 'pairs/tiny/sunset/render_compare_consistent.png' "$WORK/val/index.html"

# bake-device on the real ROS fisheye set (skipped when ../shared is absent, failed when only
# the data set is).
DATA="${INLIGHT_SHARED_DIR:-}/data/fisheye-ros-mono"
if have_shared_data fisheye-ros-mono; then
    mkdir -p "$WORK/dev"
    printf 'inputs = ["%s"]\nboard = "8x6"\nsquare-size-m = 0.108\nfov-deg = 180\ndownscale = "100x63"\n' "$DATA" > "$WORK/dev/calibrate.toml"
    expect_exit 0 "bake-device (ROS set)" -- "$PIPE/bake-device.sh" "$WORK/dev" "$WORK/out" ros
    D="$WORK/out/bundles/devices/ros/manifest.json"
    expect_true "device bundle: maps at 800x503 and 100x63, calibration" -- jq -e \
        '([.files[] | select(.role == "directions") | .width_px] | sort == [100, 800]) and (.properties.reproj_rms_px < 1)' "$D"
fi
finish
