#!/usr/bin/env bash
# render capture-btf through the tool: the full 81 x 81 UBO2003 layout at a tiny size (one
# folder per view, 81 PNGs each, capture.json, images_per_s in the report), direction files
# (off-grid pairs; duplicates, non-unit vectors and NaN are usage errors naming the option and
# the line), a light at the horizon is black, and 1 and 2 threads write identical files.
# shellcheck source=tests/cli/lib.sh
source "$(dirname "$0")/../cli/lib.sh"
R="$BIN/render"
FABRICS="${INLIGHT_SOURCE_DIR:?}/configs/fabrics"
TINY=(--width-px 4 --height-px 4 --spp 1)

expect_exit 0 "full dome at 4x4" -- "$R" capture-btf "$FABRICS/denim-plain.toml" -o "$WORK/dome" \
    "${TINY[@]}" --report "$WORK/dome.json"
expect_summary_number "summary: image count is the report's" "render: captured: ([0-9]+) images? " "$WORK/dome.json" '.metrics.capture.images'
expect_true "81 view folders" -- test "$(find "$WORK/dome" -mindepth 1 -maxdepth 1 -type d | wc -l)" -eq 81
expect_true "6561 PNG images" -- test "$(find "$WORK/dome" -name '*.png' | wc -l)" -eq 6561
expect_true "UBO2003 names in per-view folders" -- test -s "$WORK/dome/tv075_pv345/tl075 pl345 tv075 pv345.png"
expect_true "8-bit sRGB PNG" -- bash -c "oiiotool --info -v '$WORK/dome/tv000_pv000/tl000 pl000 tv000 pv000.png' | grep -q uint8"
expect_true "capture.json states the irradiance" -- jq -e '.irradiance_w_m2 > 3.14 and .images == 6561' "$WORK/dome/capture.json"
expect_true "report has images_per_s" -- jq -e '.metrics.capture.images_per_s > 0 and .metrics.capture.images == 6561' "$WORK/dome.json"

# The raw BTF under environments, against the path-traced truth of the same weave.
MK="$TBIN/inlight_make_test_image"
"$MK" "$WORK/sky.exr" 32 16 1.0
"$MK" "$WORK/sun.exr" 32 16 0.2 10 4 400
expect_exit 0 "btf-shade under a sky and a sun" -- "$R" shade-btf "$FABRICS/denim-plain.toml" --btf "$WORK/dome" \
    --environment "$WORK/sky.exr" --environment "$WORK/sun.exr" -o "$WORK/sh" --spp 4 --report "$WORK/sh.json"
for f in btf.exr truth.exr relerr.exr compare.png; do
    expect_true "shade output $f" -- test -s "$WORK/sh_sun_tv045_pv040_$f"
done
expect_true "metrics per environment and view" -- jq -e '.metrics.btf_shade.results | length == 6' "$WORK/sh.json"
expect_summary_number "summary: the first shading's mean relative error is the report's" \
    "render: shaded BTF vs path-traced truth \\([^)]+\\): mean relative error ([0-9.e+-]+)," "$WORK/sh.json" \
    '.metrics.btf_shade.results[0].mean_rel'
expect_true "metrics as render compare, plus the mean's bias" -- \
    jq -e '.metrics.btf_shade.results[0] | has("mean_rel") and has("mean_de2000") and has("mean_luminance_rel_diff")' "$WORK/sh.json"
expect_exit 2 "btf-shade needs an environment" -- "$R" shade-btf "$FABRICS/denim-plain.toml" --btf "$WORK/dome" -o "$WORK/y"
expect_exit 2 "btf-shade of another fabric's capture" -- "$R" shade-btf "$FABRICS/satin.toml" --btf "$WORK/dome" \
    --environment "$WORK/sky.exr" -o "$WORK/y"
expect_stderr "captured from a" "the repeat mismatch is named"

# Off-grid pairs, EXR, a light at the horizon (black, not noise).
printf '12.5 10 0 0\n90 0 0 0\n40 200 37.5 95\n' >"$WORK/pairs.txt"
expect_exit 0 "pairs file, exr" -- "$R" capture-btf "$FABRICS/satin.toml" -o "$WORK/pairs" \
    --width-px 8 --height-px 8 --spp 2 --btf-pairs "$WORK/pairs.txt" --btf-format exr --report "$WORK/p.json"
expect_true "three images" -- test "$(find "$WORK/pairs" -name '*.exr' | wc -l)" -eq 3
expect_true "off-grid angles in the name" -- test -s "$WORK/pairs/tv037.500_pv095/tl040 pl200 tv037.500 pv095.exr"
expect_true "light at the horizon is black" -- \
    bash -c "oiiotool '$WORK/pairs/tv000_pv000/tl090 pl000 tv000 pv000.exr' --printstats | grep -q 'Max: 0.000000 0.000000 0.000000'"
expect_true "one black image in the report" -- jq -e '.metrics.capture.black_images == 1' "$WORK/p.json"

# Bad direction files: usage errors naming the option, the file and the line.
printf '0 0\n30 60\n30 60\n' >"$WORK/dup.txt"
expect_exit 2 "duplicate light" -- "$R" capture-btf "$FABRICS/satin.toml" -o "$WORK/x" "${TINY[@]}" --btf-lights "$WORK/dup.txt"
expect_stderr "--btf-lights: .*dup.txt:3" "the duplicate's option, file and line are named"
printf '0 0 1\n0.5 0 0.5\n' >"$WORK/nonunit.txt"
expect_exit 2 "non-unit view vector" -- "$R" capture-btf "$FABRICS/satin.toml" -o "$WORK/x" "${TINY[@]}" --btf-views "$WORK/nonunit.txt"
expect_stderr "nonunit.txt:2.*not unit length" "the non-unit vector's line is named"
printf '0 nan\n' >"$WORK/nan.txt"
expect_exit 2 "NaN direction" -- "$R" capture-btf "$FABRICS/satin.toml" -o "$WORK/x" "${TINY[@]}" --btf-lights "$WORK/nan.txt"
printf '90 0\n' >"$WORK/flat.txt"
expect_exit 2 "view in the sample's plane" -- "$R" capture-btf "$FABRICS/satin.toml" -o "$WORK/x" "${TINY[@]}" --btf-views "$WORK/flat.txt"
expect_true "failed runs leave no output folder" -- test ! -e "$WORK/x"
expect_exit 2 "--btf-pairs excludes --btf-lights" -- "$R" capture-btf "$FABRICS/satin.toml" -o "$WORK/x" \
    --btf-pairs "$WORK/pairs.txt" --btf-lights "$WORK/dup.txt"
expect_exit 2 "--btf-lights is capture-btf's, not trace's" -- "$R" trace "$FABRICS/satin.toml" -o "$WORK/x.exr" --btf-lights "$WORK/dup.txt"

# The dome with horizon rings (--btf-light-set ubo2003-horizon): 177 lights, the set written into
# the folder and named by capture.json, so shade-btf and btf-pca index it without being told.
HV="$WORK/hviews.txt"
printf '0 0\n75 0\n' >"$HV"
expect_exit 0 "horizon light set" -- "$R" capture-btf "$FABRICS/wool-twill.toml" -o "$WORK/hz" "${TINY[@]}" \
    --btf-light-set ubo2003-horizon --btf-views "$HV"
expect_true "177 lights for each of 2 views" -- test "$(find "$WORK/hz" -name '*.png' | wc -l)" -eq 354
expect_true "a light at 89 deg" -- test -s "$WORK/hz/tv075_pv000/tl089 pl345 tv075 pv000.png"
expect_true "capture.json names the folder's sets" -- \
    jq -e '.light_directions == "lights.txt" and .view_directions == "views.txt"' "$WORK/hz/capture.json"
expect_true "lights.txt holds the 177 directions" -- test "$(grep -vc '^#' "$WORK/hz/lights.txt")" -eq 177
expect_true "the dome's capture names no set" -- jq -e 'has("light_directions") | not' "$WORK/dome/capture.json"
expect_exit 0 "shade-btf reads the set from the folder" -- "$R" shade-btf "$FABRICS/wool-twill.toml" --btf "$WORK/hz" \
    --environment "$WORK/sun.exr" --shade-views "$HV" -o "$WORK/hzs" --spp 2 --report "$WORK/hzs.json" -q
expect_true "both views shaded" -- jq -e '.metrics.btf_shade.results | length == 2' "$WORK/hzs.json"
expect_exit 2 "--btf-light-set excludes --btf-lights" -- "$R" capture-btf "$FABRICS/satin.toml" -o "$WORK/x" \
    "${TINY[@]}" --btf-light-set ubo2003-horizon --btf-lights "$WORK/dup.txt"
expect_stderr "excludes" "the conflict is named"
expect_exit 2 "an unknown light set" -- "$R" capture-btf "$FABRICS/satin.toml" -o "$WORK/x" "${TINY[@]}" --btf-light-set bonn
expect_stderr "btf-light-set" "the option is named"
# An even spread (--btf-light-set fibonacci-N): N lights down to 89 deg, written into the folder.
expect_exit 0 "fibonacci light set" -- "$R" capture-btf "$FABRICS/wool-twill.toml" -o "$WORK/fib" "${TINY[@]}" \
    --btf-light-set fibonacci-20 --btf-views "$HV"
expect_true "20 lights for each of 2 views" -- test "$(find "$WORK/fib" -name '*.png' | wc -l)" -eq 40
# shellcheck disable=SC2016  # awk's own $1 and $2
expect_true "lights.txt holds the 20 directions, the first at the pole and the last at 89 deg" -- \
    awk '!/^#/ { n++; if (n == 1) first = $1 " " $2; last = $1 } END { exit !(n == 20 && first == "0 0" && last == 89) }' \
    "$WORK/fib/lights.txt"
expect_true "the frontal image the bake takes the albedo from" -- test -s "$WORK/fib/tv000_pv000/tl000 pl000 tv000 pv000.png"
for bad in fibonacci-15 fibonacci-5000 fibonacci-x fibonacci-; do
    expect_exit 2 "light set $bad" -- "$R" capture-btf "$FABRICS/satin.toml" -o "$WORK/x" "${TINY[@]}" --btf-light-set "$bad"
    expect_stderr "btf-light-set.*$bad.*16, 4096" "the option, the value and the range are named"
done
expect_true "failed runs leave no output folder" -- test ! -e "$WORK/x"

# Same files for any thread count.
printf '0 0\n45 120\n' >"$WORK/two.txt"
for t in 1 2; do
    expect_exit 0 "capture, $t thread(s)" -- "$R" capture-btf "$FABRICS/wool-twill.toml" -o "$WORK/t$t" \
        --width-px 8 --height-px 8 --spp 2 --btf-lights "$WORK/two.txt" --btf-views "$WORK/two.txt" --threads "$t" --seed 3
done
expect_true "byte-identical PNGs for 1 and 2 threads" -- diff -r "$WORK/t1" "$WORK/t2"

# The -o folder: an existing empty one is accepted; one holding files, or a file, is refused
# before any work.
mkdir -p "$WORK/empty/sub"
expect_exit 0 "an existing empty folder (with an empty subfolder)" -- "$R" capture-btf "$FABRICS/wool-twill.toml" \
    -o "$WORK/empty" "${TINY[@]}" --btf-lights "$WORK/two.txt" --btf-views "$WORK/two.txt"
expect_true "captured into it" -- test -s "$WORK/empty/capture.json"
expect_exit 2 "a folder that holds files" -- "$R" capture-btf "$FABRICS/wool-twill.toml" -o "$WORK/empty" \
    "${TINY[@]}" --btf-lights "$WORK/two.txt" --btf-views "$WORK/two.txt"
expect_stderr "holds files" "says why"
expect_exit 2 "a file as -o" -- "$R" capture-btf "$FABRICS/wool-twill.toml" -o "$WORK/two.txt" "${TINY[@]}"
expect_stderr "is an existing file: a capture writes a folder" "says a capture writes a folder"

# Interrupted: SIGTERM rolls the capture back (nothing left, exit 143 as a shell reports it);
# SIGKILL cannot be caught and leaves temporaries, which the next capture into the folder removes
# before it runs to the end. The capture takes ~5 s at 16 px and 4 spp (6561 images); each signal
# comes once the capture has staged its first images (polled, up to 60 s on a loaded machine).
KILLCAP=(--width-px 16 --height-px 16 --spp 4)
# wait_for_temporaries DIR PID: until DIR holds a staged temporary (or PID ended, or 60 s).
wait_for_temporaries() {
    local i
    for ((i = 0; i < 600; i++)); do
        [ -n "$(find "$1" -name '*.tmp-*' -print -quit 2>/dev/null)" ] && return 0
        kill -0 "$2" 2>/dev/null || return 1
        sleep 0.1
    done
    return 1
}
"$R" capture-btf "$FABRICS/denim-plain.toml" -o "$WORK/term" "${KILLCAP[@]}" -q 2>"$WORK/term.err" &
pid=$!
wait_for_temporaries "$WORK/term" "$pid"
kill -TERM "$pid"
wait "$pid"
code=$?
if [ "$code" -eq 143 ]; then pass "SIGTERM: exit 143"; else fail "SIGTERM: exit $code, expected 143"; fi
expect_true "SIGTERM: the folder the run made is gone" -- test ! -e "$WORK/term"
expect_true "SIGTERM: said so" -- grep -q "interrupted (Terminated): this run's unfinished outputs are removed" "$WORK/term.err"
mkdir "$WORK/killed"
"$R" capture-btf "$FABRICS/denim-plain.toml" -o "$WORK/killed" "${KILLCAP[@]}" -q &
pid=$!
wait_for_temporaries "$WORK/killed" "$pid"
kill -KILL "$pid"
wait "$pid" 2>/dev/null
left=$(find "$WORK/killed" -name '*.tmp-*' | wc -l)
expect_true "SIGKILL: temporaries left ($left)" -- test "$left" -gt 0
expect_exit 0 "the rerun into the killed capture's folder" -- "$R" capture-btf "$FABRICS/denim-plain.toml" \
    -o "$WORK/killed" "${KILLCAP[@]}"
expect_stderr "removed $left temporary files that a killed capture left" "the rerun removed them and said so"
expect_true "the rerun's capture is whole and clean" -- test "$(find "$WORK/killed" -name '*.png' | wc -l)" -eq 6561 \
    -a "$(find "$WORK/killed" -name '*.tmp-*' | wc -l)" -eq 0
finish
