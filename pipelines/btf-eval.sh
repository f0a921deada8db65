#!/usr/bin/env bash
# The Table 7.1-style evaluation of btf-pca (docs/btf.md), one Markdown table per fabric for k in
# {1,3,9,81} and C in {1,2,4,8,16,32}, the streaming curve of k=3 C=32 (table and gnuplot SVG)
# and every run's report under $OUT:
#  - woven: the fabrics of configs/fabrics/ captured with render capture-btf (UBO2003 dome,
#    81 x 81, CAP_PX^2, CAP_SPP paths per pixel, 8-bit sRGB PNG); the fabrics in NOISE_FABRICS are
#    captured a second time with another seed, and their tables add the error against that
#    independent capture (btf-pca --reference): the capture noise, the floor no model can go
#    below; $OUT/thesis.md puts the thesis' wool rows beside ours with that floor;
#  - analytic: the rank-6 BTF of lib/btf/synthetic.h at SIZE_PX^2 (8-bit PNG), plain and saturated.
#   pipelines/btf-eval.sh [OUT] [SIZE_PX] [CAP_PX] [CAP_SPP]  (defaults: out/btf-eval, 32, 64, 4)
#   BTF_EVAL_SETS="woven analytic" (default both),
#   BTF_EVAL_FABRICS="wool-twill denim-plain satin" (names in configs/fabrics/, in this order;
#   default all of them), NOISE_FABRICS="wool-twill" (default),
#   BTF_EVAL_KS="1 3 9 81" (the k-runs; thesis.md needs 1 and 3),
#   BTF_PCA_ARGS="" (extra btf-pca options for every run, e.g. "--fit-space srgb"; a run is
#   reused only with the same options), BTF_EVAL_CAPTURES=OUT (where the captures are: several
#   OUTs with other BTF_PCA_ARGS can share one set of captures)
# Per woven fabric, NAME/curve/: the thesis' method (btf-pca --codec thesis) and ours on the same
# capture for the same k and C = 1..32, MAE Lab against the ratio (pipelines/btf-codec-curve.sh:
# curve.tsv, fronts.tsv, compare.md, curve.svg).
# Beside each table.md, table-equal-bytes.md: for each (k, C) row the longest prefix of btf-pca's
# stream (components by energy across groups: C chosen per group by one global budget) within
# that row's bytes (btf-pca's metrics.table_equal_bytes).
# A capture is reused when its report says ok and its capture.json has this CAP_PX, CAP_SPP and
# seed; a capture of other settings under OUT is an error (use another OUT), an unfinished one
# (killed run, no ok report) is done again. Minutes per capture: run it under nice.
set -euo pipefail
# shellcheck source=pipelines/lib.sh
. "$(dirname "$0")/lib.sh"
OUT=${1:-out/btf-eval}
SIZE=${2:-32}
CAP_PX=${3:-64}
CAP_SPP=${4:-4}
SETS=${BTF_EVAL_SETS:-woven analytic}
FABRICS=${BTF_EVAL_FABRICS:-$(for t in "$ROOT"/configs/fabrics/*.toml; do basename "$t" .toml; done)}
NOISE_FABRICS=${NOISE_FABRICS:-wool-twill}
KS=${BTF_EVAL_KS:-1 3 9 81}
read -r -a PCA_ARGS <<<"${BTF_PCA_ARGS:-}"
CAPTURES=${BTF_EVAL_CAPTURES:-$OUT}
BIN=$(tool_bin)
TBIN=${INLIGHT_TEST_BIN:-$ROOT/build/tests}
say() { echo "[btf-eval] $*" >&2; }
die() { echo "btf-eval: $*" >&2; exit "${2:-1}"; }
for v in "$SIZE" "$CAP_PX" "$CAP_SPP"; do
    [[ $v =~ ^[1-9][0-9]*$ ]] || die "SIZE_PX, CAP_PX and CAP_SPP must be positive integers, got '$v'" 2
done
for f in $FABRICS; do
    [ -f "$ROOT/configs/fabrics/$f.toml" ] || die "BTF_EVAL_FABRICS: $ROOT/configs/fabrics/$f.toml not found" 2
done
for k in $KS; do
    [[ $k =~ ^[1-9][0-9]*$ ]] || die "BTF_EVAL_KS must hold positive integers, got '$k'" 2
done
mkdir -p "$OUT"

# table NAME BTF_DIR [REFERENCE_DIR]: $OUT/NAME/table.md from one btf-pca run per k with C = 32;
# the rows for C = 1..16 are that model cut to C components (the same figures as a run with
# that C: test CompressToFolder.TableRowsEqualRunsWithThatManyComponents). A run whose report says
# ok, is newer than BTF_DIR (and the reference) and names the same reference is reused.
# With a reference: its columns, and the model's RMSE from the noise-free BTF estimated as
# sqrt(RMSE_ref^2 - n^2 / 2), n the input's RMSE against the reference (two captures of equal spp
# and independent noise: each carries n^2 / 2 of it, and the reference's is independent of the
# model fitted to the input).
table() {
    local name=$1 btf=$2 ref=${3:-} k run
    local tab="$OUT/$name/table.md" eqb="$OUT/$name/table-equal-bytes.md" extra=() head="" rule=""
    local args="${PCA_ARGS[*]}"
    if [ -n "$ref" ]; then
        extra=(--reference "$ref")
        head=" MAE Lab vs seed 2 | RMSE RGB vs seed 2 | RMSE RGB vs noise-free (est.) |"
        rule=" --- | --- | --- |"
    fi
    {
        echo "| k | C | MAE Lab | MAE RGB (8-bit) | RMSE RGB (8-bit) | mean dE2000 | raw : params float32 | raw : stored | PNG input : stored | stored MiB | run time s (C=32) | peak MiB |$head"
        echo "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |$rule"
    } >"$tab"
    {
        echo "btf-pca options: ${args:-(defaults)}. Each row: the longest prefix of the stream within the bytes of the fixed-C row (k, C); components: total over groups, and per group min-max."
        echo
        echo "| k | bytes of C | components total (per group) | MAE Lab | MAE RGB (8-bit) | RMSE RGB (8-bit) | mean dE2000 | raw : stored | stored MiB | fixed C: MAE Lab | fixed C: RMSE RGB |$head"
        echo "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |$rule"
    } >"$eqb"
    for k in $KS; do
        run="$OUT/$name/k${k}"
        if [ -f "$run.json" ] && [ "$run.json" -nt "$btf" ] && { [ -z "$ref" ] || [ "$run.json" -nt "$ref" ]; } && [ -d "$run" ] \
            && [ "$(cat "$run.args" 2>/dev/null)" = "$args" ] \
            && jq -e --arg r "$ref" '.status == "ok" and (.metrics.reference.path // "") == $r' "$run.json" >/dev/null; then
            say "$name k=$k: reusing $run"
        else
            "$BIN/btf-pca" compress "$btf" -o "$run" -k "$k" -c 32 --table-components 1,2,4,8,16,32 \
                --color-samples 65536 "${extra[@]}" "${PCA_ARGS[@]}" -q --report "$run.json"
            echo "$args" >"$run.args"
        fi
        # shellcheck disable=SC2016  # $k, $m and $n are jq variables
        jq -r --arg k "$k" 'def r2: . * 100 | round / 100;
            .metrics as $m | ($m.reference.input.rmse_rgb8 // 0) as $n | [$m.table, $m.table_equal_bytes] | transpose[] | . as [$f, $e]
            | "| \($k) | \($e.components) | \($e.components_total) (\($e.components_min)-\($e.components_max)) | \($e.mae_lab|r2) | \($e.mae_rgb8|r2) | \($e.rmse_rgb8|r2) | \($e.delta_e2000_mean|r2) | 1:\($e.raw_8bit_to_stored*10|round/10) | \($e.stored_bytes/1048576*1000|round/1000) | \($f.mae_lab|r2) | \($f.rmse_rgb8|r2) |"
            + (if $e.vs_reference then " \($e.vs_reference.mae_lab|r2) | \($e.vs_reference.rmse_rgb8|r2) | \([$e.vs_reference.rmse_rgb8 * $e.vs_reference.rmse_rgb8 - $n * $n / 2, 0] | max | sqrt | r2) |" else "" end)' \
            "$run.json" >>"$eqb"
        # shellcheck disable=SC2016  # $k, $m and $n are jq variables
        jq -r --arg k "$k" 'def r2: . * 100 | round / 100;
            .metrics as $m | ($m.reference.input.rmse_rgb8 // 0) as $n | $m.table[] | "| \($k) | \(.components) | \(.mae_lab|r2) | \(.mae_rgb8|r2) | \(.rmse_rgb8|r2) | \(.delta_e2000_mean|r2) | 1:\(.raw_8bit_to_parameters_float32*10|round/10) | 1:\(.raw_8bit_to_stored*10|round/10) | 1:\(.input_files_to_stored*10|round/10) | \(.stored_bytes/1048576*1000|round/1000) | \($m.time.total_s*10|round/10) | \($m.peak_rss_mib|round) |"
            + (if .vs_reference then " \(.vs_reference.mae_lab|r2) | \(.vs_reference.rmse_rgb8|r2) | \([.vs_reference.rmse_rgb8 * .vs_reference.rmse_rgb8 - $n * $n / 2, 0] | max | sqrt | r2) |" else "" end)' \
            "$run.json" >>"$tab"
    done
    if [ -f "$btf.json" ]; then
        jq -r 'def r2: . * 100 | round / 100; .metrics.capture
            | "\nCapture: \(.width_px) x \(.height_px) px, \(.spp) spp, per-image relative noise (render'"'"'s estimate) median \(.rel_error_median|r2), p90 \(.rel_error_p90|r2)."' \
            "$btf.json" >>"$tab"
    fi
    if [ -n "$ref" ]; then
        jq -r 'def r2: . * 100 | round / 100; .metrics.reference.input
            | "\nThe input itself against the seed-2 capture (the noise floor x sqrt 2 in RMSE): MAE Lab \(.mae_lab|r2), MAE RGB \(.mae_rgb8|r2), RMSE RGB \(.rmse_rgb8|r2), mean dE2000 \(.delta_e2000_mean|r2); one capture'"'"'s noise: RMSE RGB \(.rmse_rgb8 / (2|sqrt)|r2)."' \
            "$OUT/$name/k1.json" >>"$tab"
    fi
    say "$name: $tab"
    (cd "$OUT/$name/k3" && gnuplot streaming.gp) || say "gnuplot failed: no streaming.svg"
}

# thesis NAME...: $OUT/thesis.md, the thesis' three wool rows of Table 7.1 beside the same (k, C)
# of each named fabric: against its input, and, with a seed-2 capture, against that capture, the
# RMSE from the noise-free BTF (estimated as in table) and the noise floor (one capture against
# the other: MAE Lab; RMSE / sqrt 2, one capture's noise).
thesis() {
    local t="$OUT/thesis.md" name
    {
        echo "| fabric | k | C | MAE Lab | MAE RGB | RMSE RGB | MAE Lab vs seed 2 | RMSE RGB vs noise-free (est.) | noise: MAE Lab seed 1 vs 2 | noise: RMSE RGB of one capture | raw : stored | raw : params float32 | thesis (wool, Bonn): MAE Lab, MAE RGB, RMSE RGB at ratio |"
        echo "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |"
        for name in "$@"; do
            # shellcheck disable=SC2016  # $f, $k, $c, $th, $k1, $k3, $in, $n, $m, $row, $lab, $cs are jq variables
            jq -r -n --arg f "$name" --slurpfile k1 "$OUT/$name/k1.json" --slurpfile k3 "$OUT/$name/k3.json" '
                def r2: if type == "number" then . * 100 | round / 100 else "-" end;
                $k1[0].metrics.reference.input as $in | ($in.rmse_rgb8 // null) as $n
                | [[1, 8, "2.14, 5.86, 7.5 at 1:23"], [3, 8, "2.19, 6.83, 8.68 at 1:70"], [3, 32, "2.22, 5.92, 7.5 at 1:17"]][]
                | . as [$k, $c, $th]
                | (if $k == 1 then $k1[0] else $k3[0] end).metrics as $m
                | ([$m.table[] | select(.components == $c) | [., $f, "\($c)"]]
                   + [$m.table_equal_bytes[] | select(.components == $c)
                      | [., "\($f), stream at equal bytes", "bytes of \($c): \(.components_total) (\(.components_min)-\(.components_max))"]])[]
                | . as [$row, $lab, $cs] | $row
                | "| \($lab) | \($k) | \($cs) | \(.mae_lab|r2) | \(.mae_rgb8|r2) | \(.rmse_rgb8|r2) | \(.vs_reference.mae_lab|r2) | \(if $n then [.vs_reference.rmse_rgb8 * .vs_reference.rmse_rgb8 - $n * $n / 2, 0] | max | sqrt else null end|r2) | \($in.mae_lab|r2) | \(if $n then $n / (2|sqrt) else null end|r2) | 1:\(.raw_8bit_to_stored*10|round/10) | 1:\(.raw_8bit_to_parameters_float32*10|round/10) | \($th) |"'
        done
    } >"$t"
    say "thesis comparison: $t"
}

# capture FABRIC_TOML DIR SEED: the UBO2003 capture, unless DIR holds a finished one of these
# settings.
capture() {
    local toml=$1 dir=$2 seed=$3 have
    if [ -f "$dir.json" ] && [ "$(jq -r .status "$dir.json")" = ok ] && [ -f "$dir/capture.json" ]; then
        have=$(jq -r '"\(.width_px) \(.height_px) \(.spp) \(.seed)"' "$dir/capture.json")
        [ "$have" = "$CAP_PX $CAP_PX $CAP_SPP $seed" ] && return 0
        die "$dir: a capture of width, height, spp, seed = $have, not $CAP_PX $CAP_PX $CAP_SPP $seed: use another OUT or delete it"
    fi
    [ -e "$dir" ] && { say "$dir: no finished capture (its report is missing or not ok): capturing again"; rm -rf "$dir"; }
    say "capturing $(basename "$toml") (seed $seed, ${CAP_PX}x${CAP_PX} px, $CAP_SPP spp, 6561 images)"
    "$BIN/render" capture-btf "$toml" -o "$dir" --width-px "$CAP_PX" --height-px "$CAP_PX" --spp "$CAP_SPP" \
        --seed "$seed" -q --report "$dir.json"
}

if [[ " $SETS " == *" woven "* ]]; then
    for name in $FABRICS; do
        toml=$ROOT/configs/fabrics/$name.toml
        mkdir -p "$OUT/$name"
        capture "$toml" "$CAPTURES/$name/capture" 1
        ref=""
        if [[ " $NOISE_FABRICS " == *" $name "* ]]; then
            capture "$toml" "$CAPTURES/$name/capture-seed2" 2
            ref="$CAPTURES/$name/capture-seed2"
        fi
        table "$name" "$CAPTURES/$name/capture" "$ref"
        # The thesis' method run on the same capture beside ours (pipelines/btf-codec-curve.sh):
        # its curve, ours, and where ours stands at each thesis point.
        CURVE_KS="$KS" "$HERE/btf-codec-curve.sh" "$OUT/$name/curve" "$CAPTURES/$name/capture" ${ref:+"$ref"} >/dev/null
        say "$name: $OUT/$name/curve/compare.md"
    done
    # shellcheck disable=SC2086  # FABRICS is a list of names
    thesis $FABRICS
fi

if [[ " $SETS " == *" analytic "* ]]; then
    # fabric: name rank scale (scale > 1 saturates highlights in the 8-bit files)
    for f in "sheen 6 1.0" "saturated 6 2.5"; do
        read -r name rank scale <<<"$f"
        if [ ! -d "$OUT/$name/btf" ]; then
            say "writing $name (rank $rank, scale $scale, ${SIZE}x${SIZE} px, 6561 images)"
            "$TBIN/inlight_make_test_btf" "$OUT/$name/btf" "$SIZE" "$SIZE" "$rank" "$scale"
        fi
        table "$name" "$OUT/$name/btf"
    done
fi
