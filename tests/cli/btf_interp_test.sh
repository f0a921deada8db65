#!/usr/bin/env bash
# btf-pca interpolate: a raw and a compressed BTF evaluated at off-grid (light, view) pairs with
# both schemes, compared with a truth folder; bad input and all-or-nothing outputs.
# jq programs use $-variables inside single quotes on purpose.
# shellcheck disable=SC2016
# shellcheck source=tests/cli/lib.sh
source "$(dirname "$0")/lib.sh"
PCA="$BIN/btf-pca"
MK="$TBIN/inlight_make_test_btf"

# Rings, as the thesis' scheme needs: the pole, 6 lights at 30 deg, 8 at 60; views: pole + 4 at 40.
{ echo "0 0"; for p in 0 60 120 180 240 300; do echo "30 $p"; done; for p in 0 45 90 135 180 225 270 315; do echo "60 $p"; done; } >"$WORK/lights.txt"
printf '0 0\n40 0\n40 90\n40 180\n40 270\n' >"$WORK/views.txt"
DIRS=(--light-directions "$WORK/lights.txt" --view-directions "$WORK/views.txt")
"$MK" "$WORK/btf" 10 8 3 1.0 "$WORK/lights.txt" "$WORK/views.txt" || fail "make_test_btf"
printf '# on-grid pairs\n30 60 40 90\n60 315 0 0\n' >"$WORK/ongrid.txt"
printf '12 33 20 10\n45 350 35 200\n70 100 10 300\n' >"$WORK/offgrid.txt"

for scheme in thesis delaunay; do
    expect_exit 0 "off-grid pairs, $scheme" -- "$PCA" interpolate "$WORK/btf" "${DIRS[@]}" --pairs "$WORK/offgrid.txt" \
        --scheme "$scheme" -o "$WORK/off_$scheme" --report "$WORK/off_$scheme.json"
    expect_true "$scheme: 3 images, weights sum to 1, the 70-deg light off the measured region" -- bash -c "
        test \$(find '$WORK/off_$scheme' -name '*.exr' | wc -l) -eq 3 &&
        jq -e '.metrics.interpolation | .pairs == 3 and .scheme == \"$scheme\" and .pairs_outside_measured_region >= 1 and
            all(.per_pair[]; ((.light.weights | add) - 1 | fabs) < 1e-9 and ((.view.weights | add) - 1 | fabs) < 1e-9)' '$WORK/off_$scheme.json'"
done
expect_exit 0 "off-grid pairs, nearest" -- "$PCA" interpolate "$WORK/btf" "${DIRS[@]}" --pairs "$WORK/offgrid.txt" \
    --scheme nearest -o "$WORK/off_nearest" --report "$WORK/off_nearest.json"
expect_true "nearest: one direction of weight 1 per light and view" -- jq -e '.metrics.interpolation |
    all(.per_pair[]; .light.weights == [1] and .view.weights == [1])' "$WORK/off_nearest.json"
expect_true "the Delaunay report states how far the 70-deg light was moved (> 9 deg)" -- \
    jq -e '.metrics.interpolation.per_pair[2].light.outside_deg > 9' "$WORK/off_delaunay.json"
expect_true "the image of an off-grid pair exists in UBO2003 naming" -- \
    test -s "$WORK/off_delaunay/tv020_pv010/tl012 pl033 tv020 pv010.exr"

# On-grid pairs against the BTF itself as truth: exact for the raw BTF.
expect_exit 0 "on-grid pairs against the BTF" -- "$PCA" interpolate "$WORK/btf" "${DIRS[@]}" --pairs "$WORK/ongrid.txt" \
    --truth "$WORK/btf" -o "$WORK/on" --report "$WORK/on.json"
expect_summary_number "summary: pair count is the report's" "btf-pca: interpolated: ([0-9]+) pairs? " "$WORK/on.json" '.metrics.interpolation.pairs'
expect_true "raw BTF on the grid: zero error, one direction each" -- jq -e '.metrics.interpolation |
    .mean_errors.rmse < 1e-6 and .mean_errors.delta_e2000_mean < 1e-4 and all(.per_pair[]; (.light.directions | length) == 1)' "$WORK/on.json"

# A compressed BTF (float components, full rank 3 + mean) decodes the same pairs.
expect_exit 0 "compress" -- "$PCA" compress "$WORK/btf" "${DIRS[@]}" -o "$WORK/pca" -k 5 -c 4 --format exr-float -q
expect_exit 0 "compressed input" -- "$PCA" interpolate "$WORK/pca" --pairs "$WORK/ongrid.txt" --truth "$WORK/btf" \
    -o "$WORK/con" --report "$WORK/con.json"
# The truth is 8-bit: the rank-3 model of the 8-bit data is within its rounding, half a code.
expect_true "compressed on the grid: within 8-bit rounding" -- jq -e '.metrics.interpolation |
    .compressed == true and .mean_errors.rmse_rgb8 < 0.6' "$WORK/con.json"

# Bad input: usage errors name the option; runtime errors name the file; nothing is written.
expect_exit 2 "--scheme linear" -- "$PCA" interpolate "$WORK/btf" --pairs "$WORK/offgrid.txt" --scheme linear -o "$WORK/bad"
expect_exit 2 "interpolate with -k (a compress option)" -- "$PCA" interpolate "$WORK/btf" --pairs "$WORK/offgrid.txt" -k 3 -o "$WORK/bad"
expect_exit 2 "compress with --truth (an interpolate option)" -- "$PCA" compress "$WORK/btf" --truth "$WORK/btf" -o "$WORK/bad"
expect_stderr "--truth: unknown option" "names the option compress does not have"
expect_exit 2 "interpolate without --pairs" -- "$PCA" interpolate "$WORK/btf" -o "$WORK/bad"
expect_stderr "--pairs" "names the missing option"
printf '30 60 40 nan\n' >"$WORK/nan.txt"
expect_exit 2 "a NaN pair" -- "$PCA" interpolate "$WORK/btf" "${DIRS[@]}" --pairs "$WORK/nan.txt" -o "$WORK/bad"
expect_stderr "--pairs" "the NaN pair names the option"
expect_exit 1 "truth missing a pair" -- "$PCA" interpolate "$WORK/btf" "${DIRS[@]}" --pairs "$WORK/offgrid.txt" \
    --truth "$WORK/btf" -o "$WORK/bad"
expect_stderr "tl012 pl033 tv020 pv010" "the missing truth image is named"
expect_true "no output folder after failures" -- test ! -e "$WORK/bad"
finish
