#!/usr/bin/env bash
# The BTF thesis' method and ours on the same BTF: MAE Lab against the compression ratio (raw
# 8-bit samples / every stored byte), the thesis' curve beside ours (docs/btf-table71.md).
#   pipelines/btf-codec-curve.sh OUT BTF [REFERENCE]
# BTF: a BTF folder or Bonn zip; REFERENCE (optional): an independent capture of the same fabric
# (another seed): every point is also measured against it, and the input against it is the
# noise floor, the error no model of this capture can be told apart from.
#  - thesis: `btf-pca compress --codec thesis`, one run per (k, C) in CURVE_KS x CURVE_CS, its
#    bytes those of the thesis' own files (mean and U as 8-bit PNG, V and Sigma in one texture:
#    metrics.thesis_packing.stored_bytes), without our manifest;
#  - ours: one run per k with C = the largest of CURVE_CS and OURS_ARGS, whose rows are that model
#    cut to each C (fixed C per group) and the longest stream prefix within each of those rows'
#    bytes (C per group from one error budget: btf-pca's metrics.table_equal_bytes).
# Environment: CURVE_KS="1 3 9 27 81", CURVE_CS="1 2 4 8 16 32",
#   OURS_ARGS="--fit-space lab --weights-format uint8-deflate --quant-noise 0.05" (btf-pca
#   options: the fit in the metric, V deflated, every stored matrix rounded to add about 5% of
#   the residual energy; docs/btf-table71.md),
#   CURVE_COLOR_SAMPLES=262144 (colour triples per figure), RATIO_MIN=10, RATIO_MAX=200,
#   CURVE_BTF_ARGS="" (btf-pca options of both codecs' runs, e.g. direction files).
# Writes under OUT: runs/ (every run's folder and report), curve.tsv (one line per point),
# fronts.tsv (each codec's lower envelope: the least MAE Lab at that ratio or more),
# compare.md (at each thesis front point from RATIO_MIN to RATIO_MAX: our MAE Lab at its ratio,
# interpolated on our front in log ratio, and the ratio ours reaches at its MAE Lab; the issue's
# test: at most half its MAE, or three times its ratio), curve.gp and curve.svg (gnuplot).
# A run is reused when its report says ok, is newer than BTF (and REFERENCE) and had the same
# options.
set -euo pipefail
# shellcheck source=pipelines/lib.sh
. "$(dirname "$0")/lib.sh"
usage_unless $# 2 3 "OUT BTF [REFERENCE]"
BTF=$2
REF=${3:-}
KS=${CURVE_KS:-1 3 9 27 81}
CS=${CURVE_CS:-1 2 4 8 16 32}
read -r -a OURS <<<"${OURS_ARGS:---fit-space lab --weights-format uint8-deflate --quant-noise 0.05}"
read -r -a BTF_ARGS <<<"${CURVE_BTF_ARGS:-}"
SAMPLES=${CURVE_COLOR_SAMPLES:-262144}
RMIN=${RATIO_MIN:-10}
RMAX=${RATIO_MAX:-200}
BIN=$(tool_bin)
say() { echo "[btf-codec-curve] $*" >&2; }
die() { echo "btf-codec-curve: $*" >&2; exit "${2:-1}"; }
[ -e "$BTF" ] || die "BTF $BTF: not found" 2
[ -z "$REF" ] || [ -e "$REF" ] || die "REFERENCE $REF: not found" 2
for v in ${KS} ${CS}; do
    [[ $v =~ ^[1-9][0-9]*$ ]] || die "CURVE_KS and CURVE_CS must hold positive integers, got '$v'" 2
done
for v in "$SAMPLES" "$RMIN" "$RMAX"; do
    [[ $v =~ ^[1-9][0-9]*$ ]] || die "CURVE_COLOR_SAMPLES, RATIO_MIN and RATIO_MAX must be positive integers, got '$v'" 2
done
[ "$RMIN" -lt "$RMAX" ] || die "RATIO_MIN $RMIN must be below RATIO_MAX $RMAX" 2
command -v jq >/dev/null || die "jq not found (make deps installs it)"
OUT=$(out_dir "$1")
trap 'rm -f "$OUT/curve.tsv.tmp"' EXIT
read -r -a KA <<<"$KS"
read -r -a CA <<<"$CS"
CMAX=$(printf '%s\n' "${CA[@]}" | sort -n | tail -1)
TABLE=$(printf '%s\n' "${CA[@]}" | sort -n | paste -sd, -)
REF_ARGS=()
[ -z "$REF" ] || REF_ARGS=(--reference "$REF")
mkdir -p "$OUT/runs"

# run NAME ARGS...: btf-pca compress BTF into runs/NAME unless an ok run of the same ARGS is newer.
run() {
    local name=$1 r="$OUT/runs/$1"
    shift
    local args="$* ${BTF_ARGS[*]} ${REF_ARGS[*]} --color-samples $SAMPLES"
    if [ -f "$r.json" ] && [ "$r.json" -nt "$BTF" ] && { [ -z "$REF" ] || [ "$r.json" -nt "$REF" ]; } \
        && [ "$(cat "$r.args" 2>/dev/null)" = "$args" ] && jq -e '.status == "ok"' "$r.json" >/dev/null; then
        say "reusing $r"
        return
    fi
    rm -rf "$r" "$r.json" "$r.args"
    say "$name: btf-pca compress $args"
    "$BIN/btf-pca" compress "$BTF" -o "$r" "$@" "${BTF_ARGS[@]}" "${REF_ARGS[@]}" --color-samples "$SAMPLES" -q --report "$r.json"
    echo "$args" >"$r.args"
}

# Point lines: codec rule k C stored_bytes raw_to_stored mae_lab mae_rgb8 rmse_rgb8 de2000 mae_lab_vs_ref
row='"\(.stored_bytes)\t\(.raw_8bit_to_stored)\t\(.mae_lab)\t\(.mae_rgb8)\t\(.rmse_rgb8)\t\(.delta_e2000_mean)\t\(.vs_reference.mae_lab // "-")"'
{
    printf 'codec\trule\tk\tC\tstored_bytes\traw_to_stored\tmae_lab\tmae_rgb8\trmse_rgb8\tde2000\tmae_lab_vs_ref\n'
    for k in "${KA[@]}"; do
        for c in "${CA[@]}"; do
            # Its one table row is the run itself (all C components), with the bytes of the
            # thesis' own files (metrics.thesis_packing: mean and U as PNG, V and Sigma in one
            # texture), not of our folder's manifest.
            run "thesis-k$k-c$c" --codec thesis -k "$k" -c "$c" --table-components "$c"
            jq -r --arg k "$k" '.metrics as $m | $m.table[] | .stored_bytes = $m.thesis_packing.stored_bytes
                | .raw_8bit_to_stored = $m.bytes.raw_8bit / .stored_bytes
                | "thesis\tfixed\t\($k)\t\(.components)\t" + '"$row" "$OUT/runs/thesis-k$k-c$c.json"
        done
        run "ours-k$k" -k "$k" -c "$CMAX" --table-components "$TABLE" "${OURS[@]}"
        jq -r --arg k "$k" '.metrics | (.table[] | "ours\tfixed\t\($k)\t\(.components)\t" + '"$row"'),
            (.table_equal_bytes[] | "ours\tequal-bytes\t\($k)\t\(.components)\t" + '"$row"')' "$OUT/runs/ours-k$k.json"
    done
} >"$OUT/curve.tsv.tmp"
mv "$OUT/curve.tsv.tmp" "$OUT/curve.tsv"

# Fronts: per codec, points by ratio descending, kept when their MAE Lab is below every point of
# a higher ratio (the least error at that ratio or more).
awk -F'\t' 'NR > 1 { print $1 "\t" $6 "\t" $7 "\t" $3 "\t" $4 "\t" $2 }' "$OUT/curve.tsv" | sort -t$'\t' -k1,1 -k2,2gr \
    | awk -F'\t' 'BEGIN { OFS = "\t"; print "codec", "raw_to_stored", "mae_lab", "k", "C", "rule" }
        $1 != codec { codec = $1; best = 1e300 }
        $3 < best { best = $3; print }' >"$OUT/fronts.tsv"

# The comparison at each thesis front point within [RMIN, RMAX]: our MAE Lab at its ratio
# (linear in log ratio between our front's neighbours) and the ratio our front reaches at its
# MAE Lab (the highest ratio whose interpolated MAE Lab is at most it).
awk -F'\t' -v rmin="$RMIN" -v rmax="$RMAX" '
    NR == 1 { next }
    $1 == "ours" { n++; r[n] = $2; e[n] = $3 }  # ratio descending, MAE ascending
    $1 == "thesis" && $2 >= rmin && $2 <= rmax { m++; tr[m] = $2; te[m] = $3; tk[m] = $4; tc[m] = $5 }
    function mae_at(x,   i, t) {  # our front at ratio x (none above our highest ratio)
        if (x > r[1]) return -1
        for (i = 1; i < n; i++)
            if (x <= r[i] && x >= r[i + 1]) {
                t = (log(r[i]) - log(x)) / (log(r[i]) - log(r[i + 1]))
                return e[i] + t * (e[i + 1] - e[i])
            }
        return e[n]
    }
    function ratio_at(y,   i, t) {  # the highest ratio of our front with MAE Lab <= y
        if (e[1] <= y) return r[1]
        for (i = 1; i < n; i++)
            if (e[i] > y && e[i + 1] <= y) {
                t = (y - e[i]) / (e[i + 1] - e[i])
                return exp(log(r[i]) + t * (log(r[i + 1]) - log(r[i])))
            }
        return -1
    }
    END {
        print "| thesis k | thesis C | thesis raw : stored | thesis MAE Lab | ours at that ratio | ours / thesis | our ratio at its MAE Lab | ratio gain | holds (<= 0.5x or >= 3x) |"
        print "| --- | --- | --- | --- | --- | --- | --- | --- | --- |"
        held = 0
        for (j = 1; j <= m; j++) {
            a = mae_at(tr[j]); b = ratio_at(te[j])
            ok = (a >= 0 && a <= 0.5 * te[j]) || (b >= 3 * tr[j])
            held += ok
            sa = "-"; sg = "-"; sb = "-"; sr = "-"
            if (a >= 0) { sa = sprintf("%.2f", a); sg = sprintf("%.2fx", a / te[j]) }
            if (b >= 0) { sb = sprintf("1:%.1f", b); sr = sprintf("%.2fx", b / tr[j]) }
            printf "| %d | %d | 1:%.1f | %.2f | %s | %s | %s | %s | %s |\n", tk[j], tc[j], tr[j], te[j], sa, sg, sb, sr, (ok ? "yes" : "no")
        }
        printf "\n%d of %d thesis front points from 1:%d to 1:%d hold.\n", held, m, rmin, rmax
    }' "$OUT/fronts.tsv" >"$OUT/compare.md"
floor=""
if [ -n "$REF" ]; then
    first=${KA[0]}
    floor=$(jq -r '.metrics.reference.input.mae_lab' "$OUT/runs/ours-k$first.json")
    jq -r '.metrics.reference.input | "\nNoise floor (the input against the reference): MAE Lab \(.mae_lab * 100 | round / 100), RMSE RGB \(.rmse_rgb8 * 100 | round / 100)."' \
        "$OUT/runs/ours-k$first.json" >>"$OUT/compare.md"
fi

# The plot: every point, both fronts, and the noise floor.
{
    echo "# gnuplot curve.gp -> curve.svg: MAE Lab against raw : stored, the thesis' method and ours"
    echo "set terminal svg size 900,560"
    echo "set output 'curve.svg'"
    echo "set logscale x"
    echo "set xlabel 'raw 8-bit samples : stored bytes'"
    echo "set ylabel 'MAE Lab (against the input)'"
    echo "set grid"
    echo "set key top left"
    echo "set arrow from $RMIN, graph 0 to $RMIN, graph 1 nohead dt 2"
    echo "set arrow from $RMAX, graph 0 to $RMAX, graph 1 nohead dt 2"
    echo "plot 'curve.tsv' using (strcol(1) eq 'thesis' ? \$6 : 1/0):7 with points pt 6 lc rgb '#c04040' title 'thesis (k, C)', \\"
    echo "     'curve.tsv' using (strcol(1) eq 'ours' ? \$6 : 1/0):7 with points pt 2 lc rgb '#4060c0' title 'ours (k, C; equal bytes)', \\"
    echo "     'fronts.tsv' using (strcol(1) eq 'thesis' ? \$2 : 1/0):3 with lines lw 2 lc rgb '#c04040' title 'thesis front', \\"
    echo "     'fronts.tsv' using (strcol(1) eq 'ours' ? \$2 : 1/0):3 with lines lw 2 lc rgb '#4060c0' title 'ours front'${floor:+, \\}"
    [ -z "$floor" ] || echo "     $floor with lines dt 3 lc rgb '#404040' title 'noise floor (seed 1 vs 2)'"
} >"$OUT/curve.gp"
if command -v gnuplot >/dev/null; then
    (cd "$OUT" && gnuplot curve.gp) || say "gnuplot failed: no curve.svg"
else
    say "gnuplot not found: curve.gp written, no curve.svg"
fi
cat "$OUT/compare.md"
say "done: $OUT/curve.tsv, $OUT/fronts.tsv, $OUT/compare.md, $OUT/curve.svg"
