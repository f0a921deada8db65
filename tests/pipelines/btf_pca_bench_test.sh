#!/usr/bin/env bash
# pipelines/btf-pca-bench.sh at a small size (9 x 9 directions, 16 x 16 px): the generator
# (btf_bench --write-ubo2003) writes real 8-bit PNGs in UBO2003 naming and btf-pca decodes and
# compresses them. The images are the analytic BTF of rank R = 3 at scale 1 (below 0.95, so
# nothing clips): the BTF matrix has rank <= R, and the best model of C >= R components of the
# decoded images is at least as close to them as the analytic BTF is (Eckart-Young; the
# mean-centred PCA is the best affine rank-C model), so its unquantised RMSE is at most the
# 8-bit quantisation RMS the generator measures. Seconds.
# jq programs use $-variables inside single quotes on purpose.
# shellcheck disable=SC2016
HERE=$(cd "$(dirname "$0")" && pwd)
# shellcheck source=tests/cli/lib.sh
source "$HERE/../cli/lib.sh"
PB="$HERE/../../pipelines/btf-pca-bench.sh"
export BTF_BENCH="$BIN/../bench/btf_bench"
R=3

if [ ! -x "$BTF_BENCH" ]; then
    skip "$BTF_BENCH not built (INLIGHT_BUILD_BENCH=OFF): the generator of the end-to-end benchmark"
    finish
    exit
fi

expect_exit 0 "9 x 9 directions, 16 px, rank $R, k = 1, C = $R" -- env RANK=$R SCALE=1 "$PB" "$WORK/b" 16 9 1 $R
out=$(cat "$WORK/stdout")
expect_true "the summary gives wall, CPU, peak RSS and the decode/fit split" -- \
    grep -qE 'decoding 81 PNGs\): [0-9.]+ s wall, [0-9.]+ CPU s .*peak RSS [0-9]+ MiB' <<<"$out"
expect_true "... and the split" -- grep -qE 'split .*: decode [0-9.e-]+ s wall / [0-9.e-]+ CPU s, fit ' <<<"$out"
expect_true "... and the decode floor of the same zip with the ratio" -- \
    grep -qE 'decode floor .*81 PNGs to 8-bit codes\): [0-9.]+ s wall .* btf-pca / floor = [0-9.]+ x wall' <<<"$out"
# The floor decoded every image of the zip the tool read: 81 images of 16 x 16 x 3 samples.
expect_true "both floors decoded the 81 PNGs of btf.zip, 81 x 16 x 16 x 3 samples" -- jq -se \
    'length == 2 and all(.[]; .images == 81 and .samples == 81 * 16 * 16 * 3 and (.path | endswith("btf.zip")))' \
    "$WORK/b/floor-1.json" "$WORK/b/floor-2.json"
G="$WORK/b/generator.json"
REP="$WORK/b/btf-pca.json"
expect_true "81 PNG files in 9 per-view folders, UBO2003 names" -- bash -c \
    "test \$(find '$WORK/b/btf' -name 'tl* pl* tv* pv*.png' | wc -l) -eq 81 && test \$(find '$WORK/b/btf' -mindepth 1 -type d | wc -l) -eq 9"
expect_true "generator: 81 images, nothing clipped (largest value < 1), quantisation RMS > 0" -- jq -e \
    '.images == 81 and .check.clipped_samples == 0 and .check.max_value_unclipped < 1 and .check.rmse_linear > 0' "$G"
expect_true "the tool read 8-bit PNGs: 9 lights x 9 views of 16 x 16, 9 groups of $R components" -- jq -e \
    '.metrics | .input.format == "png" and .input.bits_per_channel == 8 and .btf.lights == 9 and .btf.views == 9 and
     .btf.width == 16 and .pca.groups == 9 and .pca.components_total == 27' "$REP"
# REL = 1e-4: the analytic values and the centred data are floats, each within half an ulp
# (3e-8) of the exact ones, against a quantisation RMS of ~1e-3: at most 6e-5 of the bound.
expect_true "C = R: unquantised RMSE <= the 8-bit quantisation RMS (x (1 + 1e-4))" -- jq -e --slurpfile g "$G" \
    '.metrics.error.rmse_linear_unquantised <= $g[0].check.rmse_linear * (1 + 1e-4)' "$REP"

# One component fewer than the rank: the data's R-th component is missing, so the error rises
# well above the quantisation (x 2 at least; a BTF of rank < R would stay under the bound).
BTF="$WORK/b/btf"
D=(--light-directions "$BTF.directions.txt" --view-directions "$BTF.directions.txt")
expect_exit 0 "C = R - 1 on the same folder" -- "$BIN/btf-pca" compress "$BTF" -o "$WORK/c2" -k 1 -c $((R - 1)) "${D[@]}" --report "$WORK/c2.json" -q
expect_true "C = R - 1: unquantised RMSE > 2 x the quantisation RMS" -- jq -e --slurpfile g "$G" \
    '.metrics.error.rmse_linear_unquantised > 2 * $g[0].check.rmse_linear' "$WORK/c2.json"

# Called again with the same size the folder is reused, not rewritten; the tool's figures repeat.
cp "$REP" "$WORK/first.json"
expect_exit 0 "the same call again" -- env RANK=$R SCALE=1 "$PB" "$WORK/b" 16 9 1 $R
expect_true "the folder is reused" -- grep -q "reused" "$WORK/stdout"
expect_true "same errors as the first call" -- jq -e --slurpfile f "$WORK/first.json" \
    '.metrics.error == $f[0].metrics.error' "$REP"
# Another rank writes a new folder.
expect_exit 0 "rank 2 into the same OUT" -- env RANK=2 SCALE=1 "$PB" "$WORK/b" 16 9 1 2
expect_true "a new folder was made for rank 2" -- bash -c "! grep -q reused '$WORK/stdout' && jq -e '.rank == 2' '$G'"

# Bad arguments: exit 2, named.
expect_exit 2 "a size that is not a number" -- "$PB" "$WORK/bad" 16x 9
expect_stderr "SIDE_PX 16x" "the bad argument is named"
expect_true "nothing made after a bad argument" -- test ! -e "$WORK/bad"
expect_exit 2 "generator: --rank 7" -- "$BTF_BENCH" --write-ubo2003 "$WORK/g7" --rank 7
expect_stderr "rank" "the generator names the option"
expect_exit 2 "decode floor: an unknown option" -- "$BTF_BENCH" --decode-floor "$WORK/b/btf.zip" --fast
expect_stderr "--fast: unknown option" "the floor names the option"
expect_exit 2 "decode floor: --threads x" -- "$BTF_BENCH" --decode-floor "$WORK/b/btf.zip" --threads x
expect_stderr "--threads x" "the floor names the bad value"
mkdir -p "$WORK/bad-png/tv000_pv000"
printf 'not a png' >"$WORK/bad-png/tv000_pv000/tl000 pl000 tv000 pv000.png"
expect_exit 1 "decode floor: a file that does not decode" -- "$BTF_BENCH" --decode-floor "$WORK/bad-png"
expect_stderr "tl000 pl000 tv000 pv000.png" "the floor names the file"
mkdir -p "$WORK/no-images"
expect_exit 1 "decode floor: a folder without images" -- "$BTF_BENCH" --decode-floor "$WORK/no-images"
expect_stderr "no images" "the floor says why"
expect_exit 1 "generator: an existing folder is not overwritten" -- "$BTF_BENCH" --write-ubo2003 "$BTF" --side-px 4 --directions 2
expect_stderr "exists" "the generator refuses an existing folder"
expect_true "the existing folder is untouched" -- test "$(find "$BTF" -name '*.png' | wc -l)" -eq 81
finish
