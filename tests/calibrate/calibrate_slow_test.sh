#!/usr/bin/env bash
# The slower CLI cases of calibrate (label "slow"): identical outputs for any thread count, boards
# at the edge of a lens' image circle, and the real data sets (skipped when absent).
# jq programs use $variables inside single quotes on purpose.
# shellcheck disable=SC2016
# shellcheck source=tests/cli/lib.sh
source "$(dirname "$0")/../cli/lib.sh"
CAL="$BIN/calibrate"
MK="$TBIN/inlight_calib_make_inputs"
SHARED=${INLIGHT_SHARED_DIR:-}

"$MK" boards "$WORK/boards" 960 720 20 || fail "make_inputs boards"
# Same inputs, any thread count: identical outputs.
expect_exit 0 "one thread" -- "$CAL" geometry "$WORK/boards" --board 9x6 --square-size-m 0.03 --fov-deg 165 \
    --downscale 240x180 -o "$WORK/t1" --threads 1 -q
expect_exit 0 "two threads" -- "$CAL" geometry "$WORK/boards" --board 9x6 --square-size-m 0.03 --fov-deg 165 \
    --downscale 240x180 -o "$WORK/t2" --threads 2 -q
for f in calibration.json directions.exr solid_angle.exr mask.png 240x180/directions.exr image_points.yml; do
    cmp -s "$WORK/t1/$f" "$WORK/t2/$f" || fail "$f differs between 1 and 2 threads"
done
pass "outputs identical for 1 and 2 threads"

# Boards at the edge of the lens' image circle: views cut by it are dropped with a reason, the
# rest calibrate, and the mask follows the circle found in the images.
"$MK" boards "$WORK/circle" 960 720 20 300 || fail "make_inputs circle"
expect_exit 0 "boards at the image circle's edge" -- "$CAL" geometry "$WORK/circle" --board 9x6 \
    -o "$WORK/circle_out" --report "$WORK/circle.json" -q
expect_true "some views dropped, named with a reason" -- jq -e '(.dropped_views | length) > 0 and all(.dropped_views[]; (.file | test("view_")) and (.reason | length) > 0)' "$WORK/circle_out/calibration.json"
expect_true "image circle found within 2 px of the rendered 300 px" -- jq -e '.image_circle.source == "auto" and ((.image_circle.radius_px - 300) | fabs) <= 2' "$WORK/circle_out/calibration.json"
expect_true "still accurate (f, c within 0.2 px)" -- jq -e --slurpfile t "$WORK/circle/truth.json" '
    .intrinsics as $i | $t[0] as $t | ([($i.fx - $t.fx), ($i.cx - $t.cx), ($i.cy - $t.cy)] | map(fabs) | max) < 0.2' "$WORK/circle_out/calibration.json"

# --- Real data (skipped when ../shared is absent; a data set missing from it is a failure) -----
if have_shared_data fisheye-ros-mono; then
    ROS="$SHARED/data/fisheye-ros-mono"
    expect_exit 0 "ROS fisheye set, default pipeline (configs/calibrate-ros.toml)" -- "$CAL" geometry "$ROS" \
        --config "${INLIGHT_SOURCE_DIR:?}/configs/calibrate-ros.toml" -o "$WORK/ros" --report "$WORK/ros.json" -q
    # Default detection + refinement differs from ost.yaml's ROS procedure but must agree with it
    # within two of our own standard deviations on every parameter.
    expect_true "default pipeline agrees with ost.yaml within 2 sigma" -- jq -e '
        .intrinsics as $i | .intrinsics_std as $s |
        {fx: 290.050152, fy: 289.392837, cx: 399.938345, cy: 273.885669, k1: -0.030464, k2: -0.019695, k3: 0.002098, k4: 0.001030}
        | to_entries | all(((.value - $i[.key]) | fabs) < 2 * $s[.key])' "$WORK/ros/calibration.json"
    expect_exit 0 "ROS fisheye set, ROS procedure" -- "$CAL" geometry "$ROS" --board 8x6 --detector ros \
        --refine-iterations 0 -o "$WORK/ros2" -q
    expect_true "ROS procedure reproduces ost.yaml (0.5 px, 0.003)" -- jq -e '
        .intrinsics as $i |
        ([($i.fx - 290.050152), ($i.fy - 289.392837), ($i.cx - 399.938345), ($i.cy - 273.885669)] | map(fabs) | max) < 0.5 and
        ([($i.k1 + 0.030464), ($i.k2 + 0.019695), ($i.k3 - 0.002098), ($i.k4 - 0.001030)] | map(fabs) | max) < 0.003' "$WORK/ros2/calibration.json"
fi
if have_shared_data fisheye-opencv-jy-points; then
    JY="$SHARED/data/fisheye-opencv-jy-points"
    expect_exit 2 "corner file without a size" -- "$CAL" geometry --image-points "$JY/left.xml" \
        --object-points "$JY/object.xml" -o "$WORK/jy"
    expect_stderr "does not state the image size" "size error explained"
    expect_exit 0 "JY corner files" -- "$CAL" geometry --image-points "$JY/left.xml" --object-points "$JY/object.xml" \
        --image-size 1280x800 -o "$WORK/jy" -q
    expect_true "JY: OpenCV's reference K (0.01 px)" -- jq -e '(.intrinsics.fx - 558.478087865323 | fabs) < 0.01 and (.intrinsics.cy - 381.939424848348 | fabs) < 0.01' "$WORK/jy/calibration.json"
fi
LEFT=/usr/share/doc/opencv-doc/examples/data
if have_package_file "$LEFT/left01.jpg" opencv-doc; then
    expect_exit 0 "pinhole: OpenCV's left01-14.jpg" -- "$CAL" geometry "$LEFT"/left0[1-9].jpg "$LEFT"/left1[1-4].jpg \
        --board 9x6 --square-size-m 0.025 --model pinhole --fix-aspect-ratio -o "$WORK/left" -q
    # OpenCV's sample calibration of these images (left_intrinsics.yml: f 535.92, c 342.28, 235.57,
    # RMS 0.39 px with one view at 1.18 px) used coarser corners; ours reach RMS ~0.17 px.
    expect_true "pinhole: RMS < 0.25 px, all 13 views, f within 1% and c within 3 px of OpenCV's sample" -- jq -e '
        .reproj_rms_px < 0.25 and .views_used == 13 and ((.intrinsics.fx / 535.9157 - 1) | fabs) < 0.01 and
        ((.intrinsics.cx - 342.2832) | fabs) < 3 and ((.intrinsics.cy - 235.5708) | fabs) < 3' "$WORK/left/calibration.json"
fi

finish
