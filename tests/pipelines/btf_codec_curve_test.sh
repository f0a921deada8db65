#!/usr/bin/env bash
# pipelines/btf-codec-curve.sh on the small analytic BTF (24 x 16 px, 8 lights x 5 views): the
# thesis' method and ours at each (k, C), each codec's front, and the comparison at the thesis'
# front points; runs are reused, bad settings are refused before any run. Seconds.
# jq and awk programs use $-variables inside single quotes on purpose.
# shellcheck disable=SC2016
HERE=$(cd "$(dirname "$0")" && pwd)
# shellcheck source=tests/cli/lib.sh
source "$HERE/../cli/lib.sh"
CURVE="$HERE/../../pipelines/btf-codec-curve.sh"
make_small_btf
# A second BTF of the same directions (rank 3, scale 0.9) stands for the reference capture.
"$TBIN/inlight_make_test_btf" "$WORK/ref" 24 16 3 0.9 "$WORK/lights.txt" "$WORK/views.txt" || fail "make_test_btf"
export CURVE_KS="1 5" CURVE_CS="1 2" CURVE_BTF_ARGS="${DIRS[*]}" CURVE_COLOR_SAMPLES=4096 RATIO_MIN=1 RATIO_MAX=100000
export INLIGHT_BIN="$BIN"

expect_exit 0 "the curve of k in {1, 5}, C in {1, 2}" -- "$CURVE" "$WORK/c" "$WORK/btf" "$WORK/ref"
T="$WORK/c/curve.tsv"
expect_true "curve.tsv: 4 thesis points, 4 of ours at fixed C and 4 at equal bytes" -- bash -c \
    "test \$(awk -F'\t' '\$1 == \"thesis\" && \$2 == \"fixed\"' '$T' | wc -l) -eq 4 &&
     test \$(awk -F'\t' '\$1 == \"ours\" && \$2 == \"fixed\"' '$T' | wc -l) -eq 4 &&
     test \$(awk -F'\t' '\$1 == \"ours\" && \$2 == \"equal-bytes\"' '$T' | wc -l) -eq 4"
# Every thesis point is its run's own report: bytes, ratio, MAE Lab and the reference's figure.
for kc in "1 1" "1 2" "5 1" "5 2"; do
    read -r k c <<<"$kc"
    R="$WORK/c/runs/thesis-k$k-c$c.json"
    line=$(awk -F'\t' -v k="$k" -v c="$c" '$1 == "thesis" && $3 == k && $4 == c' "$T")
    expect_true "thesis k=$k C=$c is a --codec thesis run of consecutive groups" -- jq -e \
        '.metrics.pca | .codec == "thesis" and .view_grouping == "consecutive"' "$R"
    expect_true "thesis k=$k C=$c: the line is the report's" -- jq -e --arg l "$line" '($l | split("\t")) as $f | .metrics as $m |
        ($f[4] | tonumber) == $m.thesis_packing.stored_bytes and $m.thesis_packing.stored_bytes < $m.bytes.stored and
        ($f[6] | tonumber) == $m.error.mae_lab and
        ($f[10] | tonumber) == $m.table[0].vs_reference.mae_lab' "$R"
done
expect_true "ours: runs with the default options (lab fit, deflated uint8 V, --quant-noise 0.05), neighbour groups" -- jq -e \
    '.metrics.pca | .codec == "inlight" and .fit_space == "lab" and .weights_format == "uint8-deflate" and .quant_noise == 0.05 and .view_grouping == "neighbours"' \
    "$WORK/c/runs/ours-k1.json"
# The fronts: down each codec's list the ratio falls and the error falls; no point of the curve
# has a ratio at least a front point's and less error than it (nothing left out).
F="$WORK/c/fronts.tsv"
expect_true "fronts: ratio and MAE Lab fall down each codec's list" -- awk -F'\t' 'NR > 1 {
        if ($1 == c && !($2 < r && $3 < e)) bad = 1
        c = $1; r = $2; e = $3 }
    END { exit bad }' "$F"
expect_true "fronts: every point is dominated by its codec's front" -- awk -F'\t' '
    FNR == 1 { next }
    FILENAME == ARGV[1] { n++; fc[n] = $1; fr[n] = $2; fe[n] = $3; next }
    { ok = 0; for (i = 1; i <= n; i++) if (fc[i] == $1 && fr[i] >= $6 && fe[i] <= $7) ok = 1; if (!ok) bad = 1 }
    END { exit bad }' "$F" "$T"
expect_true "compare.md: a row per thesis front point and the count" -- bash -c \
    "test \$(grep -c '^| [0-9]' '$WORK/c/compare.md') -eq \$(awk -F'\t' '\$1 == \"thesis\"' '$F' | wc -l) &&
     grep -qE '^[0-9]+ of [0-9]+ thesis front points from 1:1 to 1:100000 hold' '$WORK/c/compare.md'"
expect_true "compare.md: the noise floor is the input against the reference" -- grep -qE '^Noise floor \(the input against the reference\): MAE Lab [0-9.]+' "$WORK/c/compare.md"
if command -v gnuplot >/dev/null; then
    expect_true "curve.svg: both fronts and the floor" -- bash -c "grep -q 'thesis front' '$WORK/c/curve.svg' && grep -q 'ours front' '$WORK/c/curve.svg' && grep -q 'noise floor' '$WORK/c/curve.svg'"
else
    skip "gnuplot not installed (make deps): curve.svg"
fi

# Again: every run is reused and the table is the same.
cp "$T" "$WORK/curve-1.tsv"
expect_exit 0 "again" -- "$CURVE" "$WORK/c" "$WORK/btf" "$WORK/ref"
expect_true "the 6 runs reused" -- test "$(grep -c 'reusing' "$WORK/stderr")" -eq 6
expect_true "the same curve" -- cmp -s "$T" "$WORK/curve-1.tsv"

# Bad settings: exit 2, named, before any run.
expect_exit 2 "CURVE_KS 0" -- env CURVE_KS=0 "$CURVE" "$WORK/bad" "$WORK/btf"
expect_stderr "CURVE_KS" "names the variable"
expect_exit 2 "RATIO_MIN above RATIO_MAX" -- env RATIO_MIN=300 RATIO_MAX=200 "$CURVE" "$WORK/bad" "$WORK/btf"
expect_stderr "RATIO_MIN" "names the variable"
expect_exit 2 "no such BTF" -- "$CURVE" "$WORK/bad" "$WORK/nothing"
expect_stderr "$WORK/nothing" "names the path"
expect_exit 2 "one argument" -- "$CURVE" "$WORK/bad"
expect_true "nothing written for the refused settings" -- test ! -e "$WORK/bad"
finish
