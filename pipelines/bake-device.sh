#!/usr/bin/env bash
# bake-device: chessboard photos of a device and lens -> calibrate -> the direction, solid-angle
# and mask maps (full size and downscaled) and the calibration in a device bundle, verified.
#   pipelines/bake-device.sh DEVICE_DIR OUT [ID]         (binaries from ${INLIGHT_BIN:-ROOT/build/bin})
# DEVICE_DIR holds calibrate.toml: `calibrate geometry` options, including `inputs` (the photos
# or their folders; relative paths are relative to DEVICE_DIR) and optionally name.txt (one
# line: the device's name for the catalogue). Each step writes OUT/work/devices/ID/<step>/ with
# its --report; the bundle goes to OUT/bundles/devices/ID/.
set -euo pipefail
# shellcheck source=pipelines/lib.sh
. "$(dirname "$0")/lib.sh"
usage_unless $# 2 - "DEVICE_DIR OUT [ID]"
DEVICE=$(abs_dir "$1")
ID=${3:-$(basename "$DEVICE")}
check_id "$ID"
OUT=$(out_dir "$2")
BIN=$(tool_bin)
W="$OUT/work/devices/$ID"
say() { echo "[bake-device $ID] $*" >&2; }
if [ ! -f "$DEVICE/calibrate.toml" ]; then
    echo "bake-device: $DEVICE/calibrate.toml not found" >&2
    exit 2
fi
name=$ID
[ -f "$DEVICE/name.txt" ] && name=$(head -n 1 "$DEVICE/name.txt")
mkdir -p "$W"

# 1. Geometry: intrinsics, then direction / solid-angle / mask maps in the device frame.
say "calibrate geometry"
(cd "$DEVICE" && "$BIN/calibrate" geometry --config calibrate.toml -o "$W/calibrate" -q \
    --report "$W/calibrate/report.json")
C="$W/calibrate/calibration.json"
say "$(jq -r '"\(.model): RMS \(.reproj_rms_px * 1000 | round / 1000) px over \(.views_used) views, FOV \(.fov_deg * 10 | round / 10) deg"' "$C")"

# 2. Every map size calibrate wrote (calibration.json lists them), each in its folder.
files=(--file "calibration=$C")
while IFS=$'\t' read -r dir; do
    for role in directions solid_angle mask; do
        file=$(jq -r --arg r "$role" '.files[$r]' "$C")
        if [ "$dir" = "." ]; then dest=$file; else dest="$dir/$file"; fi
        files+=(--file "$role=$W/calibrate/$dest@$dest")
    done
done < <(jq -r '.maps[].dir' "$C")

# 3. The bundle, then an independent verification of what was written.
say "pack"
"$BIN/bundle" pack --kind device --id "$ID" --name "$name" "${files[@]}" \
    --property "model=$(jq -r '.model' "$C")" \
    --property "fov_deg=$(jq '.fov_deg' "$C")" \
    --property "reproj_rms_px=$(jq '.reproj_rms_px' "$C")" \
    --property "image_width_px=$(jq '.image_width' "$C")" \
    --property "image_height_px=$(jq '.image_height' "$C")" \
    --property "covered_solid_angle_sr=$(jq '.covered_solid_angle_sr' "$C")" \
    -o "$OUT/bundles" -q --report "$W/pack.json"
"$BIN/bundle" verify "$OUT/bundles/devices/$ID" -q --report "$W/verify.json"
say "$(jq -r '.metrics | "bundle \(.bundle): \(.file_count) files, \(.total_bytes) bytes"' "$W/pack.json")"
