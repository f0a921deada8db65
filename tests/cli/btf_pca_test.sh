#!/usr/bin/env bash
# btf-pca: compress an analytic BTF folder and zip end to end; bad input and all-or-nothing outputs.
# jq programs use $-variables inside single quotes on purpose.
# shellcheck disable=SC2016
# shellcheck source=tests/cli/lib.sh
source "$(dirname "$0")/lib.sh"
PCA="$BIN/btf-pca"
MK="$TBIN/inlight_make_test_btf"

make_small_btf

# Two modes, each a subcommand with only its own options (docs/btf.md).
expect_exit 0 "--help lists the modes" -- "$PCA" --help
for want in "btf-pca compress wool_btf.zip -o out/wool -k 3 -c 8 --report wool.json" "btf-pca interpolate "; do
    expect_true "--help has the example '$want'" -- grep -qF -- "$want" "$WORK/stdout"
done
expect_exit 0 "compress --help" -- "$PCA" compress --help
for opt in --view-group-size --components --max-rmse --method --format --light-directions --color-samples --max-memory-mib --stream-views --fit-space --weights-format --fit-norm --l1-iterations --codec; do
    grep -q -- "$opt" "$WORK/stdout" || fail "compress --help lacks $opt"
done
expect_true "compress --help has its example" -- grep -qF "btf-pca compress wool_btf.zip -o out/wool" "$WORK/stdout"
for opt in --scheme --truth --pairs "btf-pca interpolate"; do
    expect_true "compress --help lacks '$opt'" -- bash -c "! grep -qF -- '$opt' '$WORK/stdout'"
done
expect_exit 0 "interpolate --help" -- "$PCA" interpolate --help
for opt in --pairs --scheme --truth --light-directions --view-directions --linear-input "btf-pca interpolate "; do
    grep -qF -- "$opt" "$WORK/stdout" || fail "interpolate --help lacks $opt"
done
for opt in "-k," --components --max-rmse --method --table-components "btf-pca compress"; do
    expect_true "interpolate --help lacks '$opt'" -- bash -c "! grep -qF -- '$opt' '$WORK/stdout'"
done

# The spelling before the subcommands is refused with the new one, before anything is written.
printf '0 0 0 0\n' >"$WORK/pairs.txt"
expect_exit 2 "old spelling: btf-pca INPUT -o OUT" -- "$PCA" "$WORK/btf" -o "$WORK/old" -k 3 "${DIRS[@]}" --report "$WORK/old.json"
expect_stderr "btf-pca: modes are subcommands now: use 'btf-pca compress INPUT -o OUT' (see btf-pca --help)" "names the compress spelling"
expect_exit 2 "old spelling: btf-pca INPUT --interpolate PAIRS" -- "$PCA" "$WORK/btf" --interpolate "$WORK/pairs.txt" -o "$WORK/old" --report "$WORK/old.json"
expect_stderr "use 'btf-pca interpolate INPUT --pairs PAIRS -o OUT'" "names the interpolate spelling"
expect_true "the old spellings wrote nothing, not even --report" -- test ! -e "$WORK/old" -a ! -e "$WORK/old.json"
expect_exit 2 "no mode" -- "$PCA"

expect_exit 0 "compress k=3 C=4" -- "$PCA" compress "$WORK/btf" -o "$WORK/out" -k 3 -c 4 "${DIRS[@]}" --report "$WORK/r.json"
# The console summary (docs/report.md): components, bytes, ratio and errors as in the report.
expect_stderr "btf-pca: components: 8 components over 2 view groups (4 per group)" "summary: components per group"
expect_summary_number "summary: stored bytes are the report's" "btf-pca: stored: ([0-9]+) bytes" "$WORK/r.json" '.metrics.bytes.stored'
expect_summary_number "summary: compression ratio is the report's" "compression ratio ([0-9.e+-]+) " \
    "$WORK/r.json" '.metrics.compression_ratio.raw_8bit_to_stored'
expect_summary_number "summary: RMSE is the report's" "error \\(model vs input\\): RMSE ([0-9.e+-]+) " "$WORK/r.json" '.metrics.error.rmse_linear'
expect_summary_number "summary: MAE Lab is the report's" "MAE Lab ([0-9.e+-]+)," "$WORK/r.json" '.metrics.error.mae_lab'
expect_summary_number "summary: mean Delta E 2000 is the report's" "mean Delta E 2000 ([0-9.e+-]+)," "$WORK/r.json" '.metrics.error.delta_e2000_mean'
expect_true "off a terminal no progress bar is drawn (no carriage return)" -- bash -c "! grep -q \$'\\r' '$WORK/stderr'"
# On a terminal (script(1) gives the run a pseudo-terminal) the group fits draw a bar with an ETA.
# A container or chroot without /dev/pts has no pseudo-terminal to give: that is skipped, named.
if command -v script >/dev/null && script -qec true /dev/null >/dev/null 2>&1; then
    script -qec "'$PCA' compress '$WORK/btf' -o '$WORK/tty' -k 3 -c 4 ${DIRS[*]}" /dev/null >"$WORK/tty.log" 2>&1
    expect_true "on a terminal: a progress bar with elapsed time and ETA" -- grep -q "fit view groups \[#*.*ETA" "$WORK/tty.log"
    expect_true "on a terminal: the per-group lines make way for the bar" -- bash -c "! grep -q 'group 1/2:' '$WORK/tty.log'"
else
    skip "no pseudo-terminal here (script(1) absent or /dev/pts not mounted): the progress bar on a terminal"
fi
expect_true "5 views in groups of 3: 2 groups of 4 components" -- \
    jq -e '.status == "ok" and .metrics.pca.groups == 2 and .metrics.pca.components_per_group == [4, 4]' "$WORK/r.json"
expect_true "one mean and 4 component PNGs per group, manifest, weights, streaming table and plot" -- \
    test "$(find "$WORK/out" -name 'g*.png' | wc -l)" -eq 10 -a -s "$WORK/out/btf-pca.json" -a -s "$WORK/out/weights.bin" \
    -a -s "$WORK/out/streaming.tsv" -a -s "$WORK/out/streaming.gp"
# weights.bin holds V of each group: N = 3 channels * 8 lights * views, 4 components, float32.
expect_true "weights.bin size = (3 + 2 views) * 24 * 4 components * 4 bytes" -- test "$(stat -c %s "$WORK/out/weights.bin")" -eq 1920
expect_true "report: Table 7.1 figures, memory, time, ratios, thesis packing" -- jq -e '.metrics |
    (.error | .mae_lab > 0 and .rmse_rgb8 > 0 and .delta_e2000_mean > 0 and .rmse_linear > 0) and
    .peak_rss_bytes > 0 and .time.total_s > 0 and .compression_ratio.raw_8bit_to_stored > 1 and
    .thesis_packing.rmse_rgb8 > .error.rmse_rgb8' "$WORK/r.json"
expect_true "streaming curve: 9 points, bytes rising, error falling to the final figure" -- jq -e '.metrics as $m |
    $m.streaming | (.rmse_linear | length) == 9 and (.bytes_sent | . == sort) and
    .rmse_linear[0] > .rmse_linear[8] and ((.rmse_linear[8] - $m.error.rmse_linear) | fabs) < 1e-9' "$WORK/r.json"
expect_true "streaming.tsv has a header and 9 rows" -- test "$(grep -vc '^#' "$WORK/out/streaming.tsv")" -eq 9

# --fit-space srgb and --weights-format uint8: the manifest says how to decode; V takes one byte
# per value; the equal-bytes rows stay within their fixed-C row's bytes.
expect_exit 0 "srgb fit, 8-bit V" -- "$PCA" compress "$WORK/btf" -o "$WORK/srgb" -k 3 -c 4 --fit-space srgb --weights-format uint8 \
    --table-components 1,2,4 "${DIRS[@]}" --report "$WORK/s.json"
expect_true "manifest: srgb_encoded, uint8 V with v_scale and v_offset" -- jq -e '.color_space == "srgb_encoded" and
    .weights.dtype == "uint8" and (.groups[0].components[0] | has("v_scale") and has("v_offset"))' "$WORK/srgb/btf-pca.json"
expect_true "weights.bin size = (3 + 2 views) * 24 * 4 components * 1 byte" -- test "$(stat -c %s "$WORK/srgb/weights.bin")" -eq 480
expect_true "report: fit space, error space, equal-bytes rows within budget" -- jq -e '.metrics |
    .pca.fit_space == "srgb" and .pca.weights_format == "uint8" and .error_space == "srgb_encoded" and
    (.table_equal_bytes | length) == 3 and all(.table_equal_bytes[]; .stored_bytes - .manifest_bytes <= .byte_budget)' "$WORK/s.json"
expect_exit 2 "--fit-space log" -- "$PCA" compress "$WORK/btf" -o "$WORK/bad" --fit-space log "${DIRS[@]}"
expect_stderr "--fit-space" "names the option"

# --fit-space lab --fit-norm l1: the manifest says cielab_d65, the report the norm; the refit
# lowers MAE at the same C (least absolute error) and cannot lower the RMSE of the PCA.
expect_exit 0 "lab fit, L1 refit" -- "$PCA" compress "$WORK/btf" -o "$WORK/labl1" -k 3 -c 2 --fit-space lab --fit-norm l1 \
    --l1-iterations 4 "${DIRS[@]}" --report "$WORK/l1.json"
expect_exit 0 "lab fit, least squares" -- "$PCA" compress "$WORK/btf" -o "$WORK/labl2" -k 3 -c 2 --fit-space lab "${DIRS[@]}" --report "$WORK/l2.json"
expect_true "manifest cielab_d65; report fit_norm l1 with 4 iterations" -- jq -e '.color_space == "cielab_d65"' "$WORK/labl1/btf-pca.json"
expect_true "L1 refit: MAE below, RMSE not below the PCA's (unquantised)" -- bash -c "jq -e -s '(.[0].metrics | .pca.fit_norm == \"l1\" and .pca.l1_iterations == 4) and
    (.[1].metrics.pca.fit_norm == \"l2\") and .[0].metrics.error.mae_linear < .[1].metrics.error.mae_linear and
    .[0].metrics.error.rmse_linear_unquantised >= .[1].metrics.error.rmse_linear_unquantised' '$WORK/l1.json' '$WORK/l2.json'"
expect_exit 2 "--fit-norm l3" -- "$PCA" compress "$WORK/btf" -o "$WORK/bad" --fit-norm l3 "${DIRS[@]}"
expect_stderr "--fit-norm" "names the option"
expect_exit 2 "--l1-iterations 0" -- "$PCA" compress "$WORK/btf" -o "$WORK/bad" --fit-norm l1 --l1-iterations 0 "${DIRS[@]}"
expect_stderr "--l1-iterations" "names the option"
expect_exit 2 "--l1-iterations without --fit-norm l1" -- "$PCA" compress "$WORK/btf" -o "$WORK/bad" --l1-iterations 4 "${DIRS[@]}"
expect_stderr "applies only to --fit-norm l1" "says why"
expect_exit 2 "--fit-norm l1 with groups out of core" -- "$PCA" compress "$WORK/btf" -o "$WORK/bad" --fit-norm l1 --stream-views 1 "${DIRS[@]}"
expect_stderr "--fit-norm l1" "names the option"

# --codec thesis: the thesis' method as the baseline (lib/btf/pca_run.h). It implies its fit and
# storage, groups consecutive views, streams component-major, and refuses what changes its method.
expect_exit 0 "--codec thesis" -- "$PCA" compress "$WORK/btf" -o "$WORK/thesis" -k 2 -c 2 --codec thesis "${DIRS[@]}" --report "$WORK/th.json"
expect_true "thesis manifest: codec, consecutive groups, srgb_encoded, uint8 V, component-major stream" -- jq -e '.codec == "thesis" and
    .view_grouping == "consecutive" and .color_space == "srgb_encoded" and .weights.dtype == "uint8" and
    ([.groups[].views] == [[0, 1], [2, 3], [4]]) and ([.stream[][1]] == [0, 0, 0, 1, 1, 1]) and
    all(.groups[]; .thesis.sigma_digits | length == 2)' "$WORK/thesis/btf-pca.json"
expect_true "thesis report: its fit (exact Gram, least squares) and codec" -- jq -e '.metrics.pca | .codec == "thesis" and
    .fit_space == "srgb" and .fit_norm == "l2" and .weights_format == "uint8" and (.methods | keys == ["gram"])' "$WORK/th.json"
expect_exit 0 "interpolate reads a thesis folder" -- "$PCA" interpolate "$WORK/thesis" --pairs "$WORK/pairs.txt" -o "$WORK/thesis-int"
for bad in "--fit-space lab:--fit-space srgb" "--fit-norm l1:--fit-norm l2" "--weights-format float16:--weights-format uint8" \
           "--format exr-float:--format png" "--quant-noise 0.1:--quant-noise 0" "--max-rmse 0.01:--max-rmse"; do
    # shellcheck disable=SC2086  # the option and its value are two words
    expect_exit 2 "--codec thesis ${bad%%:*}" -- "$PCA" compress "$WORK/btf" -o "$WORK/bad" --codec thesis ${bad%%:*} "${DIRS[@]}"
    expect_stderr "--codec thesis: " "names the codec"
    expect_stderr "${bad#*:}" "says what the thesis needs"
    expect_true "nothing written" -- test ! -e "$WORK/bad"
done
expect_exit 2 "--codec jpeg" -- "$PCA" compress "$WORK/btf" -o "$WORK/bad" --codec jpeg "${DIRS[@]}"
expect_stderr "--codec" "names the option"

# An error budget: a rank-4 BTF needs at most 4 components above the 8-bit noise.
expect_exit 0 "error budget" -- "$PCA" compress "$WORK/btf" -o "$WORK/budget" -k 5 -c 16 --max-rmse 0.01 "${DIRS[@]}" --report "$WORK/b.json"
expect_true "budget: C chosen <= 4 and met" -- \
    jq -e '.metrics | .pca.components_per_group[0] <= 4 and .error.rmse_linear_unquantised <= 0.01' "$WORK/b.json"

# The same BTF as a zip file, read in place, gives the same components.
(cd "$WORK" && zip -qr btf.zip btf) || fail "zip"
expect_exit 0 "zip input" -- "$PCA" compress "$WORK/btf.zip" -o "$WORK/zout" -k 3 -c 4 "${DIRS[@]}" --report "$WORK/z.json"
expect_true "zip and folder give identical component files" -- cmp "$WORK/out/g001-c03.png" "$WORK/zout/g001-c03.png"
expect_true "1 and 2 threads give identical outputs" -- bash -c \
    "'$PCA' compress '$WORK/btf' -o '$WORK/t1' -k 3 -c 4 --threads 1 ${DIRS[*]} -q && '$PCA' compress '$WORK/btf' -o '$WORK/t2' -k 3 -c 4 --threads 2 ${DIRS[*]} -q && diff -r '$WORK/t1' '$WORK/t2'"

# Out of core: a group streamed from the images a block of views at a time gives the in-core
# result. The floats of every block are the in-core ones (same centring), so the stored files are
# identical; only the double sums run in another order: each figure is a sum of at most
# n = P N = 16384 x 120 = 2.0e6 terms of one sign, relative error <= n u = 2.0e6 x 1.1e-16 = 2.2e-10
# per ordering, hence REL = 5e-10 for two orderings.
"$MK" "$WORK/big" 128 128 4 1.5 "$WORK/lights.txt" "$WORK/views.txt" || fail "make_test_btf 128"
BIG=("$WORK/big" -k 5 -c 4 --method randomized --table-components "1,2" --threads 2 "${DIRS[@]}")
expect_exit 0 "in core" -- "$PCA" compress "${BIG[@]}" -o "$WORK/in" --report "$WORK/in.json"
expect_exit 0 "out of core, 2 views per block" -- "$PCA" compress "${BIG[@]}" -o "$WORK/ooc" --stream-views 2 --report "$WORK/ooc.json"
expect_true "reports say which fit ran" -- jq -e --slurpfile i "$WORK/in.json" '.metrics.memory as $m |
    $m.fit == "out-of-core" and $m.stream_views == 2 and $m.groups_out_of_core == 1 and $m.passes_over_images == 9 and
    $m.peak_rss_mib > 0 and $i[0].metrics.memory.fit == "in-core" and $i[0].metrics.memory.groups_out_of_core == 0' "$WORK/ooc.json"
expect_true "out of core: component images and weights identical to in core" -- bash -c \
    "for f in '$WORK'/in/g*.png '$WORK'/in/weights.bin; do cmp \"\$f\" '$WORK/ooc/'\"\$(basename \"\$f\")\" || exit 1; done"
expect_true "out of core: every error figure within REL = 5e-10 of in core" -- jq -e --slurpfile i "$WORK/in.json" '
    def figs: [.error.rmse_linear, .error.mae_linear, .error.max_abs_linear, .error.rmse_linear_unquantised,
               .error.mae_lab, .error.delta_e2000_mean, .error.rmse_rgb8, .thesis_packing.mae_lab]
              + .streaming.rmse_linear + [.table[] | .rmse_linear, .mae_lab];
    [(.metrics | figs), ($i[0].metrics | figs)] | transpose | length > 10 and
    all(.[]; (.[0] - .[1] | fabs) <= 5e-10 * (.[0] | fabs) + 1e-300)' "$WORK/ooc.json"
# (9 passes: 4 + 2 q for the randomized SVD with q = 2 power iterations, btf/pca.h, and one to measure.)
# The budget chooses the path: below the in-core estimate the group streams, within the budget.
est=$(jq '.metrics.memory.estimate_in_core_mib | ceil' "$WORK/in.json")
expect_exit 0 "--max-memory-mib below the in-core estimate" -- "$PCA" compress "${BIG[@]}" -o "$WORK/budget_ooc" \
    --max-memory-mib "$((est - 1))" --report "$WORK/bo.json"
expect_true "budget: out of core, estimate within the budget, same components" -- bash -c \
    "jq -e '.metrics.memory | .fit == \"out-of-core\" and .stream_views >= 1 and .stream_views < 5 and .estimate_mib <= .budget_mib and .budget_source == \"--max-memory-mib\"' '$WORK/bo.json' &&
     cmp '$WORK/in/g000-c03.png' '$WORK/budget_ooc/g000-c03.png'"
expect_exit 2 "--max-memory-mib 1: not even one view fits" -- "$PCA" compress "${BIG[@]}" -o "$WORK/bad" --max-memory-mib 1
expect_stderr "max-memory-mib" "the budget error names the option"

# Bad input: usage errors (exit 2) name the option; nothing is written.
expect_exit 2 "-k 0" -- "$PCA" compress "$WORK/btf" -o "$WORK/bad" -k 0 "${DIRS[@]}"
expect_stderr "view-group-size" "-k 0 names the option"
expect_exit 2 "--max-rmse nan" -- "$PCA" compress "$WORK/btf" -o "$WORK/bad" --max-rmse nan "${DIRS[@]}"
expect_exit 2 "--format jpeg" -- "$PCA" compress "$WORK/btf" -o "$WORK/bad" --format jpeg "${DIRS[@]}"
expect_exit 2 "output inside the input folder" -- "$PCA" compress "$WORK/btf" -o "$WORK/btf/pca" "${DIRS[@]}"
expect_stderr "inside the input" "output inside the input is refused"
expect_true "no output folder after usage errors" -- test ! -e "$WORK/bad" -a ! -e "$WORK/btf/pca"

# Runtime errors (exit 1) name the file, and leave no partial output.
cp -r "$WORK/btf" "$WORK/holed"
rm "$WORK/holed/tv045_pv180/tl030 pl060 tv045 pv180.png" 2>/dev/null || rm "$(find "$WORK/holed" -name '*tl030*pl060*tv045*pv180*' | head -1)"
expect_exit 1 "a missing image" -- "$PCA" compress "$WORK/holed" -o "$WORK/holed_out" "${DIRS[@]}" --report "$WORK/h.json"
expect_stderr "tv045" "the missing image is named"
expect_true "failed run: no output folder, report says failed" -- bash -c \
    "test ! -e '$WORK/holed_out' && jq -e '.status == \"failed\" and .exit_code == 1' '$WORK/h.json'"
cp -r "$WORK/btf" "$WORK/corrupt"
f=$(find "$WORK/corrupt" -name '*.png' | sort | sed -n 7p)
head -c 100 "$f" >"$f.tmp" && mv "$f.tmp" "$f"
expect_exit 1 "a truncated image" -- "$PCA" compress "$WORK/corrupt" -o "$WORK/corrupt_out" "${DIRS[@]}"
expect_true "no output after a failure mid-run" -- test ! -e "$WORK/corrupt_out"
finish
