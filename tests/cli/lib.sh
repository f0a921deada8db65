# shellcheck shell=bash
# Shared helpers for the CLI test scripts (sourced). Each check prints what it checked.
set -uo pipefail
export BIN=${INLIGHT_BIN:?INLIGHT_BIN must point at build/bin}
export TBIN=${INLIGHT_TEST_BIN:?}
WORK=$(mktemp -d)
trap 'rm -rf "$WORK"' EXIT
FAILS=0
PASSES=0
SKIPS=0

fail() { echo "FAIL: $*"; FAILS=$((FAILS + 1)); }
pass() { echo "ok: $*"; PASSES=$((PASSES + 1)); }

# expect_exit CODE DESCRIPTION -- command...
expect_exit() {
    local want=$1 what=$2
    shift 3
    local t0=${EPOCHREALTIME//[!0-9]/}  # microseconds, without a process
    "$@" >"$WORK/stdout" 2>"$WORK/stderr"
    local got=$?
    # The step's wall time, so a slow test's log shows where its minutes go.
    local ds=$(( (${EPOCHREALTIME//[!0-9]/} - t0 + 50000) / 100000 ))
    local s="$((ds / 10)).$((ds % 10))"
    if [ "$got" -eq "$want" ]; then pass "$what (exit $got, $s s)"; else
        fail "$what: exit $got, expected $want ($s s)"; sed 's/^/    /' "$WORK/stderr" | head -20; fi
}

expect_stderr() {  # expect_stderr PATTERN DESCRIPTION
    if grep -q -- "$1" "$WORK/stderr"; then pass "$2"; else fail "$2: stderr lacks '$1'"; sed 's/^/    /' "$WORK/stderr" | head -10; fi
}

# expect_summary_number DESCRIPTION ERE JSON JQ: the number that ERE's one group captures in the
# last expect_exit's stderr (a console summary line, docs/report.md) equals the report's JQ value
# to the summary's precision: log::num prints 4 significant digits, so a relative 5e-4 (half a
# unit in the 4th digit) plus 1e-12 for a value of 0; integers match exactly under the same rule.
expect_summary_number() {
    local what=$1 re=$2 json=$3 expr=$4 got want
    got=$(sed -nE "s/.*${re}.*/\1/p" "$WORK/stderr" | head -1)
    want=$(jq -r "$expr" "$json")
    if [ -z "$got" ] || [ -z "$want" ] || [ "$want" = null ]; then
        fail "$what: summary '$got' (pattern $re), report '$want' ($expr)"
        sed 's/^/    /' "$WORK/stderr" | head -10
        return
    fi
    if awk -v g="$got" -v w="$want" 'BEGIN { d = g - w; if (d < 0) d = -d; a = w < 0 ? -w : w
                                            exit !(d <= 5e-4 * a + 1e-12) }'; then
        pass "$what (summary $got, report $want)"
    else
        fail "$what: summary $got, report $want"
    fi
}

expect_true() {  # expect_true DESCRIPTION -- command...
    local what=$1
    shift 2
    if "$@" >/dev/null; then pass "$what"; else fail "$what"; fi
}

# have_shared_data SUB: true when ../shared/data/SUB exists. Without ../shared at all (a clone
# without it) the checks that need it are skipped; with ../shared present a missing data set is a
# failure, so a broken path cannot silently drop the real-data checks.
have_shared_data() {
    local root=${INLIGHT_SHARED_DIR:-}
    if [ -n "$root" ] && [ -e "$root/data/$1" ]; then return 0; fi
    if [ -n "$root" ] && [ -d "$root" ]; then
        fail "$root/data/$1 not found although $root exists (see shared/data/README.md)"
    else
        skip "../shared absent: the checks on data/$1 (see shared/data/README.md)"
    fi
    return 1
}

# have_package_file PATH PACKAGE: true when PATH (from a Debian package of DEB_PACKAGES) exists;
# otherwise the checks that need it are skipped.
have_package_file() {
    if [ -e "$1" ]; then return 0; fi
    skip "$2 not installed ($1; make deps)"
    return 1
}

# make_small_btf: an analytic 24 x 16 BTF folder $WORK/btf on 8 lights and 5 views (the files
# $WORK/lights.txt and $WORK/views.txt), and DIRS, the options that name them.
make_small_btf() {
    printf '0 0\n15 0\n15 120\n30 60\n30 240\n45 0\n60 90\n75 300\n' >"$WORK/lights.txt"
    printf '0 0\n30 0\n30 120\n45 180\n60 270\n' >"$WORK/views.txt"
    # shellcheck disable=SC2034  # used by the sourcing scripts
    DIRS=(--light-directions "$WORK/lights.txt" --view-directions "$WORK/views.txt")
    "$TBIN/inlight_make_test_btf" "$WORK/btf" 24 16 4 1.0 "$WORK/lights.txt" "$WORK/views.txt" || fail "make_test_btf"
}

skip() { echo "skip: $*"; SKIPS=$((SKIPS + 1)); }

# finish: exit 0 when every check passed, 77 (ctest's SKIP_RETURN_CODE, see cmake/inlight.cmake)
# when none failed but some were skipped, 1 on any failure.
finish() {
    echo "$PASSES passed, $FAILS failed, $SKIPS skipped"
    if [ "$FAILS" -ne 0 ]; then return 1; fi
    if [ "$SKIPS" -ne 0 ]; then exit 77; fi
    return 0
}
