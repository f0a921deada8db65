#!/usr/bin/env bash
# gtest_suite.sh BINARY SUITE: one GoogleTest suite run as one ctest test (cmake/inlight.cmake).
# A process per suite, not per test: a test binary takes ~0.6 s to start (its ~260 shared
# libraries, most of them OpenImageIO's, bound at load), which was most of the unit tests' time.
# Exit: GoogleTest's own when a test failed; 77 (ctest's skip code) when a test skipped and none
# failed, its GTEST_SKIP message in the output for tests/skip_reasons.sh; 1 when the suite holds
# no test (renamed since the build listed it); 0 otherwise.
set -uo pipefail
if [ $# -ne 2 ]; then
    echo "usage: gtest_suite.sh BINARY SUITE" >&2
    exit 2
fi
log=$(mktemp) || exit 1
trap 'rm -f "$log"' EXIT
"$1" --gtest_filter="$2.*" --gtest_color=no 2>&1 | tee "$log"
rc=${PIPESTATUS[0]}
[ "$rc" -ne 0 ] && exit "$rc"
if ! grep -qE '^\[==========\] [1-9][0-9]* tests? from' "$log"; then
    echo "gtest_suite.sh: $1 has no test in suite $2" >&2
    exit 1
fi
grep -q '^\[  SKIPPED \]' "$log" && exit 77
exit 0
