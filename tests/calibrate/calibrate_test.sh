#!/usr/bin/env bash
# CLI behaviour of calibrate: help, exit codes, the output file contract, hard cases (no board,
# fewer than three views, mixed sizes), corner-file input, quality gate, config files, response
# mode. The slower cases (determinism, image-circle edge, real data) are in calibrate_slow_test.sh.
# jq programs use $variables inside single quotes on purpose.
# shellcheck disable=SC2016
# shellcheck source=tests/cli/lib.sh
source "$(dirname "$0")/../cli/lib.sh"
CAL="$BIN/calibrate"
MK="$TBIN/inlight_calib_make_inputs"

# --- Help, version, usage errors ---------------------------------------------------------------
expect_exit 0 "top-level --help" -- "$CAL" --help
expect_true "top-level help lists both modes" -- grep -q "response" "$WORK/stdout"
expect_exit 2 "no mode is a usage error" -- "$CAL"
expect_exit 0 "--version" -- "$CAL" --version
expect_exit 0 "geometry --help" -- "$CAL" geometry --help
expect_true "geometry help shows an example" -- grep -q "Example:" "$WORK/stdout"
expect_true "geometry help states units (--fov-deg)" -- grep -q -- "--fov-deg" "$WORK/stdout"
expect_exit 0 "response --help" -- "$CAL" response --help
expect_exit 2 "unknown flag" -- "$CAL" geometry x --board 8x6 -o "$WORK/o" --frobnicate
expect_exit 2 "missing --output" -- "$CAL" geometry x --board 8x6
expect_exit 2 "bad --board" -- "$CAL" geometry "$WORK" --board 8 -o "$WORK/o"
expect_stderr "expected COLSxROWS" "bad --board explained"
expect_exit 2 "unknown model" -- "$CAL" geometry "$WORK" --board 8x6 --model kb -o "$WORK/o"
expect_exit 2 "images and corner file together" -- "$CAL" geometry "$WORK" --image-points x.yml --board 8x6 -o "$WORK/o"
expect_exit 2 "bad --image-circle" -- "$CAL" geometry "$WORK" --board 8x6 --image-circle 1,2 -o "$WORK/o"

# --- Synthetic fisheye set: file contract and accuracy ----------------------------------------
"$MK" boards "$WORK/boards" 960 720 20 || fail "make_inputs boards"
expect_exit 0 "synthetic fisheye set" -- "$CAL" geometry "$WORK/boards" --board 9x6 --square-size-m 0.03 \
    --fov-deg 165 --downscale 240x180,120x90 -o "$WORK/out" --report "$WORK/r.json"
O="$WORK/out"
# The console summary (docs/calibrate.md, "Console summary") at the default verbosity.
expect_stderr "calibrate: RMS reprojection error: [0-9.e-]* px over 20 views" "summary: RMS and views"
expect_stderr "calibrate: camera matrix K (px): \\[" "summary: camera matrix"
expect_stderr "calibrate: distortion (fisheye): \\[" "summary: distortion"
# The ROS camera_info.yaml holds the solved intrinsics (17 significant digits; jq prints the
# JSON's doubles exactly too, so 1e-12 relative is only the text round trip).
expect_true "camera_info.yaml: equidistant model, fx and k1 as calibration.json" -- bash -c "
    grep -q '^distortion_model: equidistant$' '$O/camera_info.yaml' &&
    fx=\$(awk '/^camera_matrix:/{f=1} f && /data:/{gsub(/[][,]/, \" \"); print \$2; exit}' '$O/camera_info.yaml') &&
    k1=\$(awk '/^distortion_coefficients:/{f=1} f && /data:/{gsub(/[][,]/, \" \"); print \$2; exit}' '$O/camera_info.yaml') &&
    jq -e --argjson fx \"\$fx\" --argjson k1 \"\$k1\" \
       '((.intrinsics.fx - \$fx) | fabs) <= 1e-12 * .intrinsics.fx and ((.intrinsics.k1 - \$k1) | fabs) <= 1e-12 * (.intrinsics.k1 | fabs)' '$O/calibration.json'"
expect_true "camera_info.yaml: camera_name is the input folder's name" -- grep -qx 'camera_name: boards' "$O/camera_info.yaml"
expect_true "opencv_camera.yml: FileStorage YAML with K and D" -- bash -c \
    "head -1 '$O/opencv_camera.yml' | grep -q '^%YAML:1.0' && grep -q '^K: !!opencv-matrix' '$O/opencv_camera.yml' && grep -q '^D: !!opencv-matrix' '$O/opencv_camera.yml'"
# --camera-name names the camera in camera_info.yaml; a name ROS would refuse is a usage error.
# The same run (the whole set again) shows -q keeping the summary silent.
expect_exit 0 "--camera-name, -q" -- "$CAL" geometry "$WORK/boards" --board 9x6 --fov-deg 165 \
    --downscale 120x90 --camera-name left_fisheye -o "$WORK/named" -q
expect_true "-q keeps the summary silent" -- bash -c "! grep -q 'RMS reprojection' '$WORK/stderr'"
expect_true "camera_info.yaml: camera_name as given" -- grep -qx 'camera_name: left_fisheye' "$WORK/named/camera_info.yaml"
expect_exit 2 "--camera-name with a '-' (ROS refuses it)" -- "$CAL" geometry "$WORK/boards" --board 9x6 \
    --camera-name left-fisheye -o "$WORK/badname"
expect_stderr "--camera-name.*'left-fisheye' is not a ROS camera name" "names the option, the value and the rule"
expect_true "no output after the usage error" -- test ! -e "$WORK/badname"
for f in calibration.json directions.exr solid_angle.exr mask.png image_points.yml object_points.yml \
         camera_info.yaml opencv_camera.yml 240x180/directions.exr 240x180/solid_angle.exr 240x180/mask.png \
         120x90/directions.exr 120x90/solid_angle.exr 120x90/mask.png; do
    [ -s "$O/$f" ] || fail "missing output $f"
done
pass "every output file written"
expect_true "directions.exr: float R,G,B at full size" -- \
    bash -c "oiiotool --info -v '$O/directions.exr' | grep -q '960 x  720, 3 channel, float' && oiiotool --info -v '$O/directions.exr' | grep -q 'channel list: R, G, B'"
expect_true "solid_angle.exr: float channel Y" -- \
    bash -c "oiiotool --info -v '$O/solid_angle.exr' | grep -q '1 channel, float' && oiiotool --info -v '$O/solid_angle.exr' | grep -q 'channel list: Y'"
# --colorcount counts the pixels equal to 0 and to 1 (255 in 8 bits): together they must be all
# 960 x 720 pixels, and both must occur.
expect_true "mask.png: 8-bit, one channel" -- \
    bash -c "oiiotool --info -v '$O/mask.png' | grep -q '960 x  720, 1 channel, uint8'"
expect_true "mask.png: values 0 and 255 only, both present" -- bash -c \
    "oiiotool '$O/mask.png' --colorcount '0:1' | awk '{n[NR] = \$1} END {exit !(NR == 2 && n[1] > 0 && n[2] > 0 && n[1] + n[2] == 960 * 720)}'"
expect_true "calibration.json has the contract's keys" -- jq -e '
    .model == "fisheye" and .image_width == 960 and .image_height == 720 and
    (.intrinsics | has("fx") and has("fy") and has("cx") and has("cy") and has("skew") and has("k4")) and
    (.intrinsics_std | has("fx")) and (.views | length) == 20 and (.views[0] | has("file") and has("reproj_rms_px")) and
    (.dropped_views | type) == "array" and has("fov_deg") and has("image_circle") and has("reproj_rms_px") and
    (.maps | length) == 3' "$O/calibration.json"
# The issue's accuracy targets (also unit-tested): f and c within 0.1 px, k within 1e-3.
expect_true "recovers the rendering model (0.1 px, 1e-3)" -- jq -e --slurpfile t "$WORK/boards/truth.json" '
    .intrinsics as $i | $t[0] as $t |
    ([($i.fx - $t.fx), ($i.fy - $t.fy), ($i.cx - $t.cx), ($i.cy - $t.cy)] | map(fabs) | max) < 0.1 and
    ([($i.k1 - $t.k1), ($i.k2 - $t.k2), ($i.k3 - $t.k3), ($i.k4 - $t.k4)] | map(fabs) | max) < 1e-3' "$O/calibration.json"
expect_true "fov_deg = 165 (the mask's limit; the circle lies inside the frame)" -- \
    jq -e '(.fov_deg - 165 | fabs) < 0.5' "$O/calibration.json"
# Solid angle of a 165-degree cap: 2 pi (1 - cos 82.5 deg); the pixel quads tile it (0.1%).
expect_true "solid angles sum to the field of view's (0.1%)" -- \
    jq -e '(.covered_solid_angle_sr / (2 * 3.141592653589793 * (1 - (82.5 * 3.141592653589793 / 180 | cos))) - 1 | fabs) < 1e-3' "$O/calibration.json"
for key in tool version status exit_code argv config seed threads wall_time_s inputs outputs metrics warnings stage_time_s; do
    jq -e "has(\"$key\")" "$WORK/r.json" >/dev/null || fail "report lacks $key"
done
pass "report has every required key"
expect_true "report times every stage" -- jq -e '.stage_time_s | has("detect_corners") and has("calibrate") and has("refine_corners") and has("direction_maps") and has("downscale") and has("write_outputs")' "$WORK/r.json"
expect_true "report metrics: RMS, per-parameter std, fov" -- jq -e '.metrics.reproj_rms_px < 0.1 and .metrics.intrinsics_std.fx > 0 and .metrics.fov_deg > 0' "$WORK/r.json"

# Corner files written by a run reproduce it without the images.
expect_exit 0 "corner-file input" -- "$CAL" geometry --image-points "$O/image_points.yml" \
    --object-points "$O/object_points.yml" --fov-deg 165 -o "$WORK/corners" -q
expect_true "corner files reproduce the intrinsics" -- bash -c \
    "jq -e --slurpfile a '$O/calibration.json' '[.intrinsics[]] as \$b | [\$a[0].intrinsics[]] as \$a | [range(0; \$a|length)] | all(. as \$i | ((\$a[\$i] - \$b[\$i]) | fabs) < 1e-9)' '$WORK/corners/calibration.json'"

# The runs below check exit codes, the report and the config handling, not accuracy: a small
# set (6 views of 480x360) keeps them fast.
"$MK" boards "$WORK/few" 480 360 6 || fail "make_inputs few"

# Quality gate: outputs written, exit 3.
expect_exit 3 "quality gate" -- "$CAL" geometry "$WORK/few" --board 9x6 --max-reproj-rms-px 0.001 \
    -o "$WORK/gate" --report "$WORK/gate.json" --refine-iterations 0 --downscale 120x90
expect_true "gate: status and outputs" -- bash -c "jq -e '.status == \"quality_gate_failed\"' '$WORK/gate.json' && test -s '$WORK/gate/calibration.json'"

# Config: keys are long options; CLI overrides config; unknown keys are usage errors.
printf 'board = "9x6"\nfov-deg = 150\nrefine-iterations = 0\ndownscale = "120x90"\n' > "$WORK/c.toml"
expect_exit 0 "config file" -- "$CAL" geometry "$WORK/few" --config "$WORK/c.toml" --fov-deg 160 \
    -o "$WORK/cfg" --report "$WORK/cfg.json" -q
expect_true "config applied, CLI wins" -- jq -e '.config.board == "9x6" and .config.fov_deg == 160 and .config.refine_iterations == 0' "$WORK/cfg.json"
SRC=${INLIGHT_SOURCE_DIR:?}
expect_exit 0 "configs/calibrate.toml (the app's lens)" -- "$CAL" geometry "$WORK/few" \
    --config "$SRC/configs/calibrate.toml" --downscale 120x90 -o "$WORK/appcfg" -q
printf 'bord = "9x6"\n' > "$WORK/bad.toml"
expect_exit 2 "unknown config key" -- "$CAL" geometry "$WORK/few" --config "$WORK/bad.toml" -o "$WORK/cfg"

# --- Hard cases --------------------------------------------------------------------------------
"$MK" blank "$WORK/blank" 480 360 3 || fail "make_inputs blank"
expect_exit 1 "no board in any image" -- "$CAL" geometry "$WORK/blank" --board 9x6 -o "$WORK/nb" --report "$WORK/nb.json"
expect_stderr "no chessboard of 9x6 inner corners found in any of the 3 images" "no-board error is clear"
expect_true "no-board report says failed" -- jq -e '.status == "failed" and .exit_code == 1' "$WORK/nb.json"
expect_true "no output after failure" -- test ! -e "$WORK/nb/calibration.json"

mkdir -p "$WORK/two"
cp "$WORK/few/view_00.png" "$WORK/few/view_01.png" "$WORK/blank/blank_00.png" "$WORK/two/"
expect_exit 1 "fewer than three usable views" -- "$CAL" geometry "$WORK/two" --board 9x6 -o "$WORK/two_out"
expect_stderr "only 2 usable views of 3, need at least 3" "too-few-views error is clear"
expect_stderr "blank_00.png: board of 9x6 inner corners not found" "the dropped view is named with its reason"

"$MK" boards "$WORK/small" 640 480 2 || fail "make_inputs small"
mkdir -p "$WORK/mixed"
cp "$WORK/few/view_0"[0-4].png "$WORK/mixed/" && cp "$WORK/small/view_01.png" "$WORK/mixed/small_01.png"
expect_exit 1 "mixed image sizes rejected" -- "$CAL" geometry "$WORK/mixed" --board 9x6 -o "$WORK/mixed_out"
expect_stderr "mixed image sizes" "mixed-size error"
expect_stderr "640x480 (1 file: small_01.png)" "mixed-size error names the odd file"
expect_stderr "480x360 (5 files: view_00.png" "mixed-size error names the others"

# --- Response mode -----------------------------------------------------------------------------
"$MK" bracket "$WORK/bracket" 320 200 || fail "make_inputs bracket"
B="$WORK/bracket"
expect_exit 0 "response from a bracket" -- "$CAL" response --images "$B/exposure_0.png" "$B/exposure_1.png" \
    "$B/exposure_2.png" --exposure-s 0.004 0.016 0.064 -o "$WORK/resp.json" --merged "$WORK/merged.exr" --report "$WORK/rr.json"
expect_true "response file: 3 curves of 256, g(128) = 0" -- jq -e '.format == "inlight_response" and (.g | length) == 3 and (.g[0] | length) == 256 and .g[1][128] == 0' "$WORK/resp.json"
# Gamma 2.2: g(z2) - g(z1) = 2.2 ln(z2 / z1); codes 64 and 192 are well inside the bracket.
expect_true "recovers gamma 2.2 between codes 64 and 192 (within 0.05)" -- \
    jq -e '((.g[0][192] - .g[0][64]) / ((192/64) | log) - 2.2 | fabs) < 0.05' "$WORK/resp.json"
expect_true "merged radiance written" -- test -s "$WORK/merged.exr"
expect_exit 0 "configs/calibrate-response.toml" -- "$CAL" response --config "$SRC/configs/calibrate-response.toml" \
    --images "$B/exposure_0.png" "$B/exposure_1.png" "$B/exposure_2.png" --exposure-s 0.004 0.016 0.064 -o "$WORK/cfgresp.json"
expect_true "response report times its stages" -- jq -e '.stage_time_s | has("recover_response") and has("read_images")' "$WORK/rr.json"
expect_exit 2 "images and exposures must pair up" -- "$CAL" response --images "$B/exposure_0.png" "$B/exposure_1.png" \
    --exposure-s 0.004 -o "$WORK/r2.json"
"$MK" png16 "$WORK/deep.png" 320 200 || fail "make_inputs png16"
expect_exit 1 "16-bit bracket rejected" -- "$CAL" response --images "$WORK/deep.png" "$B/exposure_1.png" \
    --exposure-s 0.004 0.016 -o "$WORK/r3.json"
expect_stderr "deep.png: response recovery needs 8-bit images" "16-bit error names the file"

finish
