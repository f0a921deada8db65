#!/usr/bin/env bash
# End to end on real data: calibrate the ROS fisheye set, then light from one of its frames (a room
# with ceiling lights): envmap-project fits SH to the frame with the direction and solid-angle maps.
#   pipelines/calibrate_ros.sh [OUT] [FRAME]    (binaries from ${INLIGHT_BIN:-ROOT/build/bin})
set -euo pipefail
OUT=${1:-out/calibrate_ros}
# shellcheck source=pipelines/lib.sh
. "$(dirname "$0")/lib.sh"
BIN=$(tool_bin)
DATA="$SHARED/data/fisheye-ros-mono"
FRAME=${2:-$DATA/left-0000.png}
if [ ! -d "$DATA" ]; then
    echo "calibrate_ros: $DATA not found (see shared/data/README.md)" >&2
    exit 1
fi
mkdir -p "$OUT/calibrate" "$OUT/envmap-project"

# 1. Geometry: intrinsics, direction / solid-angle / mask maps at full size and 1/4, 1/8.
"$BIN/calibrate" geometry "$DATA" --config "$ROOT/configs/calibrate-ros.toml" -q \
    -o "$OUT/calibrate" --report "$OUT/calibrate/report.json"
jq -r '"calibrate: \(.model), RMS \(.reproj_rms_px * 1000 | round / 1000) px over \(.views_used) views, " +
       "f = \(.intrinsics.fx * 100 | round / 100) / \(.intrinsics.fy * 100 | round / 100) px, " +
       "c = (\(.intrinsics.cx * 100 | round / 100), \(.intrinsics.cy * 100 | round / 100)), " +
       "FOV \(.fov_deg * 10 | round / 10) deg, \(.covered_solid_angle_sr * 1000 | round / 1000) sr"' \
    "$OUT/calibrate/calibration.json"
jq -r '.stage_time_s | to_entries | map("\(.key) \(.value * 1000 | round) ms") | "  stages: " + join(", ")' \
    "$OUT/calibrate/report.json"

# 2. Lighting: SH of the frame in the device frame (+z toward the viewer, +y up).
name=$(basename "$FRAME" .png)
"$BIN/envmap-project" "$FRAME" --input-kind fisheye --directions "$OUT/calibrate/directions.exr" \
    --solid-angle "$OUT/calibrate/solid_angle.exr" --sh-bands 3 -q \
    -o "$OUT/envmap-project/${name}_sh.json" --report "$OUT/envmap-project/report.json"
jq -r '"envmap-project: \(.coefficients | length) coefficients; L00 = \(.coefficients[0][0] * 1e4 | round / 1e4), " +
       "L1 (y, z, x) = (\(.coefficients[1][0] * 1e4 | round / 1e4), \(.coefficients[2][0] * 1e4 | round / 1e4), " +
       "\(.coefficients[3][0] * 1e4 | round / 1e4))"' "$OUT/envmap-project/${name}_sh.json"
echo "outputs in $OUT"
