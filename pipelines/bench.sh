#!/usr/bin/env bash
# Runs every Google Benchmark binary in BUILD/bench and prints its table (speed against error
# where the benchmark reports error counters), then envmap-project against OIIO's read
# (pipelines/envmap-load-bench.sh) and the render convergence table
# (pipelines/render-convergence.sh), and btf-pca end to end on a Bonn-size folder of PNGs
# (pipelines/btf-pca-bench.sh). Figures are recorded in docs/benchmarks.md.
#   pipelines/bench.sh [BUILD]
# BTF_PCA_BENCH_ARGS="SIDE_PX DIRECTIONS K C" sizes the btf-pca run (default "256 81 3 8", Bonn
# size: 6561 PNGs written once into BUILD/btf-pca-bench; e.g. "64 27 3 8" for a quick one).
# BTF_GLES_BENCH_SIDE_PX sizes btf_gles_bench's fabric (default 256, about a minute of btf-pca
# before its table; 128 for a quicker run).
set -euo pipefail
# shellcheck source=pipelines/lib.sh
. "$(dirname "$0")/lib.sh"
BUILD=${1:-$ROOT/build}
shopt -s nullglob
benches=("$BUILD"/bench/*_bench)
if [ ${#benches[@]} -eq 0 ]; then
    echo "bench: no benchmark binaries in $BUILD/bench (configure with -DINLIGHT_BUILD_BENCH=ON)" >&2
    exit 1
fi
echo "machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs), $(date -u +%F)"
for b in "${benches[@]}"; do
    if [ ! -f "$b" ] || [ ! -x "$b" ]; then continue; fi
    echo
    echo "== $(basename "$b")"
    "$b" --benchmark_min_time=0.2 --benchmark_counters_tabular=true
done

# envmap-project's whole run against OIIO's read of the same 4096 x 2048 float EXR.
if [ -x "$BUILD/bin/envmap-project" ]; then
    echo
    echo "== envmap-load-bench (envmap-project / oiiotool --stats, back-to-back pairs)"
    INLIGHT_BIN="$BUILD/bin" "$HERE/envmap-load-bench.sh" "$BUILD/envmap-load-bench" \
        "${ENVMAP_LOAD_PAIRS:-10}" | grep -v '^pair '
fi

# The path tracer's error against samples and time per sampler (minutes): its table.
# Full-size figures (docs/benchmarks.md): pipelines/render-convergence.sh OUT 1024 128 64 4096.
if [ -x "$BUILD/bin/render" ]; then
    echo
    echo "== render-convergence (sphere 64^2, patch 32^2, up to 1024 spp)"
    # shellcheck disable=SC2086 # the arguments are a list of words
    INLIGHT_BIN="$BUILD/bin" "$HERE/render-convergence.sh" "$BUILD/render-convergence" \
        ${RENDER_CONVERGENCE_ARGS:-1024 64 32 1024} | grep -v '^render-convergence: /'
fi

# btf-pca end to end (minutes at Bonn size, and 6561 PNGs on disk, 243 MiB):
# the btf_bench figure's BTF written as real PNGs, then decoded and compressed by the tool.
if [ -x "$BUILD/bin/btf-pca" ] && [ -x "$BUILD/bench/btf_bench" ]; then
    echo
    echo "== btf-pca-bench (btf_bench --write-ubo2003; btf-pca under /usr/bin/time -v against btf_bench --decode-floor)"
    # shellcheck disable=SC2086 # the arguments are a list of words
    INLIGHT_BIN="$BUILD/bin" BTF_BENCH="$BUILD/bench/btf_bench" "$HERE/btf-pca-bench.sh" \
        "$BUILD/btf-pca-bench" ${BTF_PCA_BENCH_ARGS:-256 81 3 8}
fi
