#!/usr/bin/env bash
# bake-device on the real ROS fisheye set (../shared/data): the device bundle's maps at every size
# calibrate wrote and the calibration's reprojection error.
HERE=$(cd "$(dirname "$0")" && pwd)
# shellcheck source=tests/cli/lib.sh
source "$HERE/../cli/lib.sh"
# shellcheck source=tests/pipelines/tiny.sh
source "$HERE/tiny.sh"

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
