#!/usr/bin/env bash
# `make test` says why each skipped test did not run (tests/skip_reasons.sh after ctest): a tiny
# ctest project with a CLI-style skip (exit 77 after "skip: ..."), a GoogleTest-style skip
# (GTEST_SKIP's message, caught by SKIP_REGULAR_EXPRESSION as gtest_discover_tests sets it) and a
# passing test, run by the same ctest; each skipped test's reason is printed and the last line is
# ctest's own summary.
HERE=$(cd "$(dirname "$0")" && pwd)
# shellcheck source=tests/cli/lib.sh
source "$HERE/../cli/lib.sh"
ROOT=${INLIGHT_SOURCE_DIR:?}
P="$WORK/project"
mkdir -p "$P"
cat > "$P/CMakeLists.txt" <<'CMAKE'
cmake_minimum_required(VERSION 3.20)
project(skips NONE)
enable_testing()
add_test(NAME cli.needs_shared COMMAND bash -c "echo 'ok: one check'; echo 'skip: ../shared absent: the checks on data/probes'; exit 77")
set_tests_properties(cli.needs_shared PROPERTIES SKIP_RETURN_CODE 77)
add_test(NAME unit.Passes COMMAND bash -c "echo fine")
add_test(NAME unit.Hdri.NeedsBlenderData COMMAND bash -c "echo '[ RUN      ] Hdri.NeedsBlenderData'; echo 'lib/x_test.cpp:12: Skipped'; echo 'blender-data not installed (make deps)'; echo; echo '[  SKIPPED ] Hdri.NeedsBlenderData (0 ms)'")
set_tests_properties(unit.Hdri.NeedsBlenderData PROPERTIES SKIP_REGULAR_EXPRESSION "\\[  SKIPPED \\]")
CMAKE
expect_exit 0 "configure the tiny project" -- cmake -S "$P" -B "$P/b"
(cd "$P/b" && ctest > ctest.log 2>&1)
expect_exit 0 "skip_reasons.sh" -- "$ROOT/tests/skip_reasons.sh" "$P/b/ctest.log" "$P/b/Testing/Temporary/LastTest.log"
cp "$WORK/stdout" "$WORK/reasons"
expect_true "the CLI skip's reason" -- grep -qx '  cli.needs_shared: ../shared absent: the checks on data/probes' "$WORK/reasons"
expect_true "the GoogleTest skip's message" -- grep -qx '  unit.Hdri.NeedsBlenderData: blender-data not installed (make deps)' "$WORK/reasons"
expect_true "the passing test is not listed" -- bash -c "! grep -q 'unit.Passes' '$WORK/reasons'"
expect_true "the last line is ctest's summary" -- bash -c "tail -n 1 '$WORK/reasons' | grep -qx '100% tests passed, 0 tests failed out of 3'"
# No skipped test: nothing printed.
printf '100%% tests passed, 0 tests failed out of 1\n' > "$WORK/none.log"
expect_exit 0 "no skipped tests" -- "$ROOT/tests/skip_reasons.sh" "$WORK/none.log" "$P/b/Testing/Temporary/LastTest.log"
expect_true "prints nothing" -- test ! -s "$WORK/stdout"
finish
