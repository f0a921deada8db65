#!/usr/bin/env bash
# btf-pca end to end against its decode floor (docs/benchmarks.md): `btf_bench --write-ubo2003`
# writes the benchmark's BTF (the analytic BTF of btf_bench's in-process figure, rank RANK at
# scale SCALE, clipped at 1) as a UBO2003 folder of real 8-bit sRGB PNGs, one folder per view as
# Bonn ships, and zips it as Bonn distributes it (stored: the PNGs are deflated already). In
# one run: the decode floor (`btf_bench --decode-floor`: every PNG of the zip decoded to its
# 8-bit codes by the same decoder, on the same threads, and nothing else), then btf-pca
# compressing the zip under `/usr/bin/time -v` (wall, CPU and peak RSS of the whole process,
# and the tool's own split: decode, fit, store, measure from its JSON report), then the floor
# again; the ratio is the tool's wall time over the mean of the two floors. Defaults: Bonn size
# (81 x 81 directions, 256 x 256 px: 6561 PNGs) with the tool's defaults k = 3, C = 8, on 2
# threads. Long at Bonn size (a minute or more): run it under nice on a shared machine.
#   pipelines/btf-pca-bench.sh OUT_DIR [SIDE_PX] [DIRECTIONS] [K] [C]
# DIRECTIONS < 81 takes every (81/DIRECTIONS)-th dome direction for lights and views (a small
# size for tests). Environment: RANK (6), SCALE (4), THREADS (2), INLIGHT_BIN (the tools),
# BTF_BENCH (btf_bench; default INLIGHT_BIN/../bench/btf_bench).
# The folder is OUT_DIR/btf and its zip OUT_DIR/btf.zip, made once per (size, directions, rank,
# scale) and reused (generator.json says how they were made, with the 8-bit quantisation
# error); OUT_DIR/pca is the tool's output, OUT_DIR/btf-pca.json its report, OUT_DIR/time.txt
# the `time -v` output, OUT_DIR/floor-1.json and floor-2.json the two floors.
set -euo pipefail
# shellcheck source=pipelines/lib.sh
. "$(dirname "$0")/lib.sh"
usage_unless $# 1 5 "OUT_DIR [SIDE_PX] [DIRECTIONS] [K] [C]"
SIDE=${2:-256}
DIRS=${3:-81}
K=${4:-3}
C=${5:-8}
RANK=${RANK:-6}
SCALE=${SCALE:-4}
THREADS=${THREADS:-2}
BIN=$(tool_bin)
GEN=${BTF_BENCH:-$BIN/../bench/btf_bench}
for t in "$BIN/btf-pca" "$GEN"; do
    if [ ! -x "$t" ]; then
        echo "btf-pca-bench: $t not found (build with -DINLIGHT_BUILD_BENCH=ON)" >&2
        exit 1
    fi
done
for v in SIDE_PX="$SIDE" DIRECTIONS="$DIRS" K="$K" C="$C" RANK="$RANK" THREADS="$THREADS"; do
    if ! [[ ${v#*=} =~ ^[1-9][0-9]*$ ]]; then
        echo "btf-pca-bench: ${v%%=*} ${v#*=}: not a positive integer" >&2
        exit 2
    fi
done
if ! [[ $SCALE =~ ^[0-9]*\.?[0-9]+$ ]] || [[ $SCALE =~ ^[0.]+$ ]]; then
    echo "btf-pca-bench: SCALE $SCALE: not a positive number" >&2
    exit 2
fi

OUT=$(out_dir "$1")
BTF=$OUT/btf
GENJSON=$OUT/generator.json
want=$(jq -nc --argjson s "$SIDE" --argjson d "$DIRS" --argjson r "$RANK" --argjson c "$SCALE" \
    '{side_px: $s, directions: $d, rank: $r, scale: $c}')
have=$(jq -c '{side_px, directions, rank, scale}' "$GENJSON" 2>/dev/null || echo none)
echo "btf-pca-bench: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs), load $(cut -d' ' -f1-3 /proc/loadavg), $(date -u '+%F %H:%M') UTC, commit $(git -C "$ROOT" rev-parse --short HEAD 2>/dev/null || echo unknown)"
if [ "$want" = "$have" ] && [ -d "$BTF" ] && [ -f "$BTF.zip" ]; then
    reused=" (made earlier, reused)"
else
    reused=""
    rm -rf "$BTF" "$BTF.directions.txt" "$BTF.zip" "$GENJSON"
    # The PNGs of smooth images are smaller than the raw 8-bit samples; ask for the raw size.
    need_kb=$(( DIRS * DIRS * SIDE * SIDE * 3 / 1024 + 1024 ))
    avail_kb=$(df -Pk "$OUT" | awk 'NR == 2 { print $4 }')
    if [ "$avail_kb" -lt "$need_kb" ]; then
        echo "btf-pca-bench: $OUT: $((avail_kb / 1024)) MiB free, the images need up to $((need_kb / 1024)) MiB" >&2
        exit 1
    fi
    "$GEN" --write-ubo2003 "$BTF" --side-px "$SIDE" --directions "$DIRS" --rank "$RANK" --scale "$SCALE" \
        --check >"$GENJSON.tmp"
    (cd "$BTF" && zip -q -r -0 ../btf.zip.tmp .)
    mv "$BTF.zip.tmp" "$BTF.zip"
    mv "$GENJSON.tmp" "$GENJSON"
fi
jq -r --arg reused "$reused" '"generated: \(.images) PNGs of \(.side_px) x \(.side_px) px, 8-bit sRGB (\(.directions) x \(.directions) directions, rank \(.rank), scale \(.scale), clipped at 1), \(.stored_bytes / 1048576 * 10 | round / 10) MiB, in \(.write_s) s wall / \(.write_cpu_s) CPU s\($reused); the 8-bit files differ from the analytic values by \(.check.rmse_linear) RMS (linear)"' "$GENJSON"

DIRARGS=()
if [ "$DIRS" -lt 81 ]; then DIRARGS=(--light-directions "$BTF.directions.txt" --view-directions "$BTF.directions.txt"); fi
rm -rf "$OUT/pca"
load_before=$(cut -d' ' -f1 /proc/loadavg)
"$GEN" --decode-floor "$BTF.zip" --threads "$THREADS" >"$OUT/floor-1.json"
/usr/bin/time -v -o "$OUT/time.txt" "$BIN/btf-pca" compress "$BTF.zip" -o "$OUT/pca" -k "$K" -c "$C" --threads "$THREADS" \
    "${DIRARGS[@]}" --report "$OUT/btf-pca.json" -q
"$GEN" --decode-floor "$BTF.zip" --threads "$THREADS" >"$OUT/floor-2.json"
load_after=$(cut -d' ' -f1 /proc/loadavg)

# time -v: "Elapsed (wall clock) time (h:mm:ss or m:ss): 1:02.31" and "Name: value" lines.
tv() { awk -F': ' -v k="$1" 'index($0, k) { print $NF; exit }' "$OUT/time.txt"; }
wall=$(tv "Elapsed (wall clock)" | awk -F: '{ s = 0; for (i = 1; i <= NF; ++i) s = 60 * s + $i; print s }')
user=$(tv "User time (seconds)")
sys=$(tv "System time (seconds)")
rss_kb=$(tv "Maximum resident set size (kbytes)")
jq -r --arg wall "$wall" --arg user "$user" --arg sys "$sys" --arg rss "$rss_kb" --arg lb "$load_before" \
    --arg la "$load_after" --arg k "$K" --arg c "$C" --arg th "$THREADS" '.metrics as $m |
    def r(x): x * 1000 | round / 1000;
    "btf-pca -k \($k) -c \($c) --threads \($th) (decoding \($m.btf.lights * $m.btf.views) PNGs): \($wall) s wall, \(($user | tonumber) + ($sys | tonumber) | . * 100 | round / 100) CPU s (user \($user), sys \($sys)), peak RSS \(($rss | tonumber) / 1024 | round) MiB (time -v; the tool reports \($m.peak_rss_mib | round) MiB), load \($lb) -> \($la)",
    "  split (the tool'"'"'s report): decode \(r($m.time.read_s)) s wall / \(r($m.time.read_cpu_s)) CPU s, fit \(r($m.time.fit_s)) s / \(r($m.time.fit_cpu_s)) CPU s, store \(r($m.time.store_s)) s, measure \(r($m.time.measure_s)) s; the tool'"'"'s total \(r($m.time.total_s)) s",
    "  \($m.pca.groups) groups, \($m.pca.components_total) components (\($m.pca.methods | tostring)), \($m.memory.fit); RMSE (linear) \($m.error.rmse_linear_unquantised) unquantised, \($m.error.rmse_linear) stored; MAE Lab \(r($m.error.mae_lab)), 1:\($m.compression_ratio.raw_8bit_to_stored | . * 10 | round / 10) of the raw 8-bit samples"' \
    "$OUT/btf-pca.json"
jq -rs --arg wall "$wall" --arg th "$THREADS" 'def r(x): x * 1000 | round / 1000;
    ((.[0].decode_s + .[1].decode_s) / 2) as $floor |
    "  decode floor (btf_bench --decode-floor, the same zip, \($th) threads: \(.[0].images) PNGs to 8-bit codes): \(r(.[0].decode_s)) s wall / \(r(.[0].decode_cpu_s)) CPU s before the tool, \(r(.[1].decode_s)) s / \(r(.[1].decode_cpu_s)) CPU s after; btf-pca / floor = \(($wall | tonumber) / $floor | . * 100 | round / 100) x wall (goal: at most 2 x)"' \
    "$OUT/floor-1.json" "$OUT/floor-2.json"
