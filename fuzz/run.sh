#!/usr/bin/env bash
# fuzz/run.sh BUILD_DIR SECONDS [HARNESS...]: makes the seed corpus, then runs each harness (all by
# default) for SECONDS under libFuzzer with ASan+UBSan, at most FUZZ_JOBS (2) at a time, under
# nice -n 10. The working corpus grows in BUILD_DIR/fuzz/corpus/<h>; crash inputs land in
# BUILD_DIR/fuzz/findings/<h>/ (copy each into fuzz/regressions/<h>/ once fixed); logs in
# BUILD_DIR/fuzz/logs/<h>.log. Prints one line per harness (runs, seconds, coverage, corpus, findings) and
# exits 1 if any harness found something.
set -euo pipefail
build=${1:?usage: fuzz/run.sh BUILD_DIR SECONDS [HARNESS...]}
seconds=${2:?usage: fuzz/run.sh BUILD_DIR SECONDS [HARNESS...]}
shift 2
harnesses=("$@")
[ ${#harnesses[@]} -gt 0 ] || harnesses=(image toml mesh corners sh response btf bundle btfpca lighting brdftable)
jobs=${FUZZ_JOBS:-2}
src=$(cd "$(dirname "$0")/.." && pwd)
bin=$build/fuzz
"$bin/inlight_make_seeds" "$src" "$bin/seeds"
mkdir -p "$bin/logs"
# Leaks inside Debian's libraries are suppressed by name (fuzz/lsan.supp); the name is only on a
# full stack, hence the slow unwinder on malloc.
export LSAN_OPTIONS="suppressions=$src/fuzz/lsan.supp${LSAN_OPTIONS:+:$LSAN_OPTIONS}"
export ASAN_OPTIONS="fast_unwind_on_malloc=0${ASAN_OPTIONS:+:$ASAN_OPTIONS}"

run_one() {
    local h=$1
    mkdir -p "$bin/corpus/$h" "$bin/findings/$h"
    # -close_fd_mask=3: the loaders' own messages would drown the log (crash reports still show).
    # -rss_limit_mb=2048: the machine's share; an input that needs more is a finding.
    nice -n 10 "$bin/${h}_fuzz" -max_total_time="$seconds" -timeout=20 -rss_limit_mb=2048 \
        -close_fd_mask=3 -print_final_stats=1 -artifact_prefix="$bin/findings/$h/" \
        "$bin/corpus/$h" "$bin/seeds/$h" >"$bin/logs/$h.log" 2>&1 || true
}

for h in "${harnesses[@]}"; do
    while [ "$(jobs -rp | wc -l)" -ge "$jobs" ]; do wait -n || true; done
    run_one "$h" &
done
wait

status=0
for h in "${harnesses[@]}"; do
    runs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$bin/logs/$h.log" | grep -o '[0-9]*$' || echo "?")
    time=$(grep -o 'stat::total_time.*\|Done [0-9]* runs in [0-9]* second' "$bin/logs/$h.log" | tail -1 | grep -o '[0-9]* second' | grep -o '[0-9]*' || echo "?")
    # Coverage at the end: libFuzzer's edge counter (cov) and its features (ft) on the last status line.
    cov=$(grep -o ' cov: [0-9]*' "$bin/logs/$h.log" | tail -1 | grep -o '[0-9]*' || echo "?")
    ft=$(grep -o ' ft: [0-9]*' "$bin/logs/$h.log" | tail -1 | grep -o '[0-9]*' || echo "?")
    corpus=$(find "$bin/corpus/$h" -type f | wc -l)
    findings=$(find "$bin/findings/$h" -type f | wc -l)
    echo "$h: ${runs} runs in ${time:-?} s, cov ${cov} ft ${ft}, corpus ${corpus} files, findings ${findings}"
    [ "$findings" -eq 0 ] || status=1
done
exit $status
