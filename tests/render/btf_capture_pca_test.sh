#!/usr/bin/env bash
# btf-pca on a tiny woven capture (render capture-btf, 8 x 8 px, the full 81 x 81 dome): the
# Table 7.1 rows fall with C, and with C at the data's rank (P = 64 pixels: every group's
# centred matrix has rank <= 64) the only error left is the 8-bit quantisation of the stored
# columns of L, which is predicted exactly from the manifest's scales:
#   V is orthonormal and orthogonal to 1 (A_c 1 = 0), so the squared error of a group is
#   N sum_i e_mean,i^2 + sum_i sum_c e_ic^2 with every rounding error |e| <= step / 2, where
#   step = scale / 255 (manifest: value = offset + scale * code / 255).
# Hence SSE <= bound = sum_g P (N h_mean^2 + sum_c h_c^2), h = step / 2. Each column's minimum and
# maximum are stored exactly (codes 0 and 255) and its other P - 2 rounding errors are uniform on
# [-step/2, step/2], so E[SSE] = (P - 2) / P * bound / 3 with variance
#   sum_g (P - 2) (N^2 step_mean^4 + sum_c step_c^4) / 180      (Var e^2 = step^4 / 180).
# jq programs are single-quoted on purpose (their $variables are jq's):
# shellcheck disable=SC2016
# shellcheck source=tests/cli/lib.sh
source "$(dirname "$0")/../cli/lib.sh"
FABRICS="${INLIGHT_SOURCE_DIR:?}/configs/fabrics"

expect_exit 0 "capture wool-twill, 81 x 81 at 8x8, 2 spp" -- "$BIN/render" capture-btf "$FABRICS/wool-twill.toml" \
    -o "$WORK/cap" --width-px 8 --height-px 8 --spp 2 -q
for k in 1 81; do
    expect_exit 0 "btf-pca k=$k C=64 with Table 7.1 rows" -- "$BIN/btf-pca" compress "$WORK/cap" -o "$WORK/k$k" -k "$k" \
        -c 64 --table-components 1,2,4,8,16,64 -q --report "$WORK/k$k.json"
    # Rows fall with C: each of C = 2, 4, 8, 16 removes error in every measure.
    expect_true "k=$k: RMSE, MAE Lab and dE2000 fall from C=1 to 16" -- jq -e '[.metrics.table[] | select(.components <= 16)] as $t
        | all(range(1; $t | length); $t[.].rmse_linear < $t[. - 1].rmse_linear
              and $t[.].mae_lab < $t[. - 1].mae_lab and $t[.].delta_e2000_mean < $t[. - 1].delta_e2000_mean)' "$WORK/k$k.json"
    # C = 64 reaches the rank: the unquantised model is exact to float rounding (~1e-7 of values <= 1).
    expect_true "k=$k: unquantised RMSE at C=64 below 1e-5 (float rounding)" -- \
        jq -e '.metrics.error.rmse_linear_unquantised < 1e-5' "$WORK/k$k.json"
    # The stored model's squared error against the quantisation bound and its expectation
    # (5 standard deviations: a false failure has probability < 1e-6).
    jq -n --slurpfile m "$WORK/k$k/btf-pca.json" --slurpfile r "$WORK/k$k.json" '
        ($m[0].width * $m[0].height) as $p
        | [$m[0].groups[] | {n: .columns, s: (.mean.scale / 255), c: [.components[].scale / 255]}] as $g
        | {bound: ([$g[] | $p * (.n * (.s / 2) * (.s / 2) + ([.c[] | (. / 2) * (. / 2)] | add // 0))] | add),
           var: ([$g[] | ($p - 2) * (.n * .n * pow(.s; 4) + ([.c[] | pow(.; 4)] | add // 0)) / 180] | add),
           mean: ([$g[] | ($p - 2) * (.n * (.s / 2) * (.s / 2) + ([.c[] | (. / 2) * (. / 2)] | add // 0))] | add / 3),
           sse: (($r[0].metrics.error.rmse_linear | . * .) * $r[0].metrics.btf.samples)}' >"$WORK/q$k.json" \
        || fail "k=$k: quantisation bound from the manifest"
    cat "$WORK/q$k.json"
    expect_true "k=$k: SSE at C=64 within the 8-bit rounding bound of L" -- jq -e '.sse > 0 and .sse <= .bound' "$WORK/q$k.json"
    expect_true "k=$k: SSE at C=64 is its expectation within 5 standard deviations" -- \
        jq -e '(.sse - .mean | fabs) <= 5 * (.var | sqrt)' "$WORK/q$k.json"
done
# The capture's irradiance travels with the compressed BTF (what lights it later divides by it).
expect_true "btf-pca.json records capture.json's irradiance" -- test \
    "$(jq '.irradiance_w_m2' "$WORK/k1/btf-pca.json")" = "$(jq '.irradiance_w_m2' "$WORK/cap/capture.json")"
cp -r "$WORK/cap" "$WORK/badcap"
jq '.irradiance_w_m2 = -1' "$WORK/cap/capture.json" >"$WORK/badcap/capture.json"
expect_exit 1 "a capture.json with a negative irradiance" -- "$BIN/btf-pca" compress "$WORK/badcap" -o "$WORK/bad" -c 4
expect_stderr "badcap/capture.json: irradiance_w_m2" "the error names the file and the key"
expect_true "nothing written" -- test ! -e "$WORK/bad"
finish
