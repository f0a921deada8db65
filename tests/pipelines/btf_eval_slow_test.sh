#!/usr/bin/env bash
# Slow-labelled (~25 CPU s, minutes of wall time under load): 3 full-dome captures of 6561 files
# and 6 btf-pca runs over them, and the 12 runs of the thesis' curve beside ours (4 x 4 px).
# pipelines/btf-eval.sh on one woven fabric at 4 x 4 px: the CAP_SPP option reaches both captures
# (seeds 1 and 2), the table gets the seed-2 columns and thesis.md the thesis' rows beside ours
# with the noise floor; a rerun reuses what is finished, refuses captures of other settings under
# the same OUT and redoes an unfinished one; other BTF_PCA_ARGS redo the runs, BTF_EVAL_KS picks
# them; table-equal-bytes.md and thesis.md carry the stream cut at each row's bytes; bad options
# are usage errors.
HERE=$(cd "$(dirname "$0")" && pwd)
# shellcheck source=tests/cli/lib.sh
source "$HERE/../cli/lib.sh"
cd "${INLIGHT_SOURCE_DIR:?}" || exit 1
export BTF_EVAL_SETS=woven BTF_EVAL_FABRICS=wool-twill NOISE_FABRICS=wool-twill
export CURVE_CS="1 8"  # the thesis' curve at two component counts (each run reads 6561 files)
E="$WORK/eval"
W="$E/wool-twill"

expect_exit 0 "btf-eval at 4 x 4 px, 2 spp" -- pipelines/btf-eval.sh "$E" 8 4 2
# shellcheck disable=SC2016  # $s is a jq variable
for c in "capture 1" "capture-seed2 2"; do
    read -r d seed <<<"$c"
    expect_true "$d: 2 spp, 4 x 4 px, seed $seed (capture.json)" -- \
        jq -e --argjson s "$seed" '.spp == 2 and .width_px == 4 and .height_px == 4 and .seed == $s and .images == 6561' "$W/$d/capture.json"
done
rows=$(grep -c '^| [0-9]' "$W/table.md")
expect_true "24 rows (k in 1,3,9,81 x C in 1,2,4,8,16,32), got $rows" -- test "$rows" -eq 24
expect_true "rows carry the three seed-2 columns" -- test "$(grep '^| [0-9]' "$W/table.md" | awk -F'|' '{print NF}' | sort -u)" = 17
expect_true "the table states the capture's spp" -- grep -q '^Capture: 4 x 4 px, 2 spp' "$W/table.md"
# The thesis' method on the same capture (btf-codec-curve.sh): a point per (k, C), its front and
# the comparison with ours.
expect_true "curve.tsv: 8 thesis points (k in 1,3,9,81 x C in 1,8) and ours" -- bash -c \
    "test \$(grep -cP '^thesis\tfixed\t' '$W/curve/curve.tsv') -eq 8 && grep -qP '^ours\tequal-bytes\t' '$W/curve/curve.tsv'"
expect_true "compare.md: the count of thesis points that hold, and the floor" -- bash -c \
    "grep -qE '^[0-9]+ of [0-9]+ thesis front points' '$W/curve/compare.md' && grep -q '^Noise floor' '$W/curve/compare.md'"
floor=$(jq '.metrics.reference.input.mae_lab * 100 | round / 100' "$W/k1.json")
expect_true "thesis.md: the thesis' three rows with the noise floor ($floor) of k1.json" -- \
    test "$(grep -c "^| wool-twill | .* | $floor | .* | 2\.[12][0-9], .* at 1:" "$E/thesis.md")" -eq 3
# Two captures of one fabric differ only by their noise: a positive floor, smaller than the
# model's error at C = 1 against the same second capture.
expect_true "noise floor > 0 and below the k=1 C=1 row against seed 2" -- jq -e \
    '.metrics.reference.input.mae_lab > 0 and .metrics.reference.input.mae_lab < .metrics.table[0].vs_reference.mae_lab' "$W/k1.json"

rows=$(grep -c '^| [0-9]' "$W/table-equal-bytes.md")
expect_true "table-equal-bytes.md: 24 rows, got $rows" -- test "$rows" -eq 24
expect_true "thesis.md: the three rows again at equal bytes" -- \
    test "$(grep -c '^| wool-twill, stream at equal bytes | [13] | bytes of \(8\|32\): ' "$E/thesis.md")" -eq 3

expect_exit 0 "a rerun of the same settings" -- pipelines/btf-eval.sh "$E" 8 4 2
expect_true "reuses both captures and the four runs" -- test "$(grep -c 'capturing' "$WORK/stderr")" -eq 0 -a "$(grep -c '^\[btf-eval\] .*reusing' "$WORK/stderr")" -eq 4
expect_true "... and the curve's 12 runs" -- test "$(grep -c '^\[btf-codec-curve\] reusing' "$WORK/stderr")" -eq 12
expect_exit 1 "a rerun at another CAP_SPP into the same OUT" -- pipelines/btf-eval.sh "$E" 8 4 3
expect_stderr "$W/capture: a capture of width, height, spp, seed = 4 4 2 1, not 4 4 3 1" "names the capture and the settings that differ"
rm "$W/capture-seed2.json"  # as after a killed run: the folder without an ok report
# One k-run (BTF_EVAL_KS=1) is enough to rebuild on the new capture: the four runs of the first
# call each cost as much as a capture and show nothing more here.
expect_exit 0 "a rerun after an unfinished seed-2 capture" -- env BTF_EVAL_KS=1 pipelines/btf-eval.sh "$E" 8 4 2
expect_stderr "capture-seed2: no finished capture" "captures seed 2 again"
expect_true "seed 2 captured again with 2 spp" -- jq -e '.status == "ok" and .metrics.capture.spp == 2' "$W/capture-seed2.json"

# Other btf-pca options: the runs are not reused; BTF_EVAL_KS picks the k-runs.
expect_exit 0 "k = 1 again with 8-bit V" -- env BTF_EVAL_KS=1 BTF_PCA_ARGS="--weights-format uint8" pipelines/btf-eval.sh "$E" 8 4 2
# shellcheck disable=SC2016  # $k3 is a jq variable
expect_true "k1 redone with uint8 V, k3 untouched" -- jq -e --slurpfile k3 "$W/k3.json" \
    '.metrics.pca.weights_format == "uint8" and $k3[0].metrics.pca.weights_format == "float32"' "$W/k1.json"
expect_true "only the k = 1 row block" -- test "$(grep -c '^| [0-9]' "$W/table.md")" -eq 6
expect_exit 2 "BTF_EVAL_KS=0" -- env BTF_EVAL_KS=0 pipelines/btf-eval.sh "$E" 8 4 2
expect_stderr "BTF_EVAL_KS must hold positive integers, got '0'" "names the variable"

expect_exit 2 "CAP_SPP 0" -- pipelines/btf-eval.sh "$E" 8 4 0
expect_stderr "CAP_SPP must be positive integers, got '0'" "names the option"
expect_exit 2 "an unknown fabric" -- env BTF_EVAL_FABRICS=silk pipelines/btf-eval.sh "$E" 8 4 2
expect_stderr "configs/fabrics/silk.toml not found" "names the file"
finish
