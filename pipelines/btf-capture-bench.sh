#!/usr/bin/env bash
# The BTF capture benchmark (docs/btf.md, docs/benchmarks.md): a full 81 x 81 UBO2003 capture of
# a sample fabric, its speed (images/s, wall and CPU time, where the time goes) and its noise,
# from the run report. Long (minutes): run it under nice on a shared machine.
#   pipelines/btf-capture-bench.sh [BUILD] [SIZE_PX] [SPP] [FABRIC] [OUT]
set -euo pipefail
# shellcheck source=pipelines/lib.sh
. "$(dirname "$0")/lib.sh"
BUILD=${1:-$ROOT/build}
SIZE=${2:-128}
SPP=${3:-4}
FABRIC=${4:-$ROOT/configs/fabrics/wool-twill.toml}
OUT=${5:-$(mktemp -d)/capture}
echo "machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs), $(date -u +%F), load $(cut -d' ' -f1-3 /proc/loadavg)"
/usr/bin/time -f "cpu: user %U s, sys %S s, wall %e s, max rss %M KB" \
    "$BUILD/bin/render" capture-btf "$FABRIC" -o "$OUT" --width-px "$SIZE" --height-px "$SIZE" \
    --spp "$SPP" --threads 2 --report "$OUT.json" -q
jq '.metrics.capture' "$OUT.json"
echo "images: $(find "$OUT" -name '*.png' | wc -l) in $OUT ($(du -sh "$OUT" | cut -f1))"
