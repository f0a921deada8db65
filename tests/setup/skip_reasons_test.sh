#!/usr/bin/env bash
# `make test` says why each skipped test did not run (tests/skip_reasons.sh after ctest): a tiny
# ctest project with a CLI-style skip (exit 77 after "skip: ..."), a GoogleTest suite with a
# skipped test run as the unit tests are (tests/gtest_suite.sh over a stand-in binary that prints
# GoogleTest's output: exit 77 with GTEST_SKIP's message), the same stand-in with a failure (a
# failure, not a skip) and a passing test, run by the same ctest; each skipped test's reason is
# printed and the last line is ctest's own summary.
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
add_test(NAME unit.Hdri COMMAND bash ${RUNNER} ${CMAKE_CURRENT_SOURCE_DIR}/fake_gtest.sh Hdri)
add_test(NAME unit.Broken COMMAND bash ${RUNNER} ${CMAKE_CURRENT_SOURCE_DIR}/fake_gtest.sh Broken)
set_tests_properties(unit.Hdri unit.Broken PROPERTIES SKIP_RETURN_CODE 77)
CMAKE
# A stand-in test binary: GoogleTest's output for --gtest_filter=Hdri.* (one test passes, one
# skips) or Broken.* (one skips, one fails, exit 1).
cat > "$P/fake_gtest.sh" <<'FAKE'
#!/usr/bin/env bash
suite=${1#--gtest_filter=}
suite=${suite%.\*}
echo "[==========] 2 tests from 1 test suite ran."
echo "[ RUN      ] $suite.NeedsBlenderData"
echo "lib/x_test.cpp:12: Skipped"
echo "blender-data not installed (make deps)"
echo
echo "[  SKIPPED ] $suite.NeedsBlenderData (0 ms)"
if [ "$suite" = Broken ]; then echo "[  FAILED  ] $suite.Other"; exit 1; fi
echo "[       OK ] $suite.Other (0 ms)"
FAKE
chmod +x "$P/fake_gtest.sh"
expect_exit 0 "configure the tiny project" -- cmake -S "$P" -B "$P/b" -DRUNNER="$ROOT/tests/gtest_suite.sh"
(cd "$P/b" && ctest > ctest.log 2>&1)
expect_exit 0 "skip_reasons.sh" -- "$ROOT/tests/skip_reasons.sh" "$P/b/ctest.log" "$P/b/Testing/Temporary/LastTest.log"
cp "$WORK/stdout" "$WORK/reasons"
expect_true "the CLI skip's reason" -- grep -qx '  cli.needs_shared: ../shared absent: the checks on data/probes' "$WORK/reasons"
expect_true "the GoogleTest skip's message" -- grep -qx '  unit.Hdri: blender-data not installed (make deps)' "$WORK/reasons"
expect_true "the passing test is not listed" -- bash -c "! grep -q 'unit.Passes' '$WORK/reasons'"
expect_true "a suite with a failure fails, whatever else skipped" -- grep -qE '^[[:space:]]+[0-9]+ - unit.Broken \(Failed\)' "$P/b/ctest.log"
expect_true "the last line is ctest's summary" -- bash -c "tail -n 1 '$WORK/reasons' | grep -qx '75% tests passed, 1 tests failed out of 4'"
# No skipped test: nothing printed.
printf '100%% tests passed, 0 tests failed out of 1\n' > "$WORK/none.log"
expect_exit 0 "no skipped tests" -- "$ROOT/tests/skip_reasons.sh" "$WORK/none.log" "$P/b/Testing/Temporary/LastTest.log"
expect_true "prints nothing" -- test ! -s "$WORK/stdout"
finish
