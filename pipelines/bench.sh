#!/usr/bin/env bash
# Runs every Google Benchmark binary in BUILD/bench and prints its table (speed against error
# where the benchmark reports error counters). Figures are recorded in docs/benchmarks.md.
#   pipelines/bench.sh [BUILD]
set -euo pipefail
BUILD=${1:-build}
shopt -s nullglob
benches=("$BUILD"/bench/*)
if [ ${#benches[@]} -eq 0 ]; then
    echo "bench: no benchmark binaries in $BUILD/bench (configure with -DINLIGHT_BUILD_BENCH=ON)" >&2
    exit 1
fi
echo "machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs), $(date -u +%F)"
for b in "${benches[@]}"; do
    [ -x "$b" ] || continue
    echo
    echo "== $(basename "$b")"
    "$b" --benchmark_min_time=0.2 --benchmark_counters_tabular=true
done
