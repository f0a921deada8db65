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
    "$@" >"$WORK/stdout" 2>"$WORK/stderr"
    local got=$?
    if [ "$got" -eq "$want" ]; then pass "$what (exit $got)"; else
        fail "$what: exit $got, expected $want"; sed 's/^/    /' "$WORK/stderr" | head -20; fi
}

expect_stderr() {  # expect_stderr PATTERN DESCRIPTION
    if grep -q -- "$1" "$WORK/stderr"; then pass "$2"; else fail "$2: stderr lacks '$1'"; sed 's/^/    /' "$WORK/stderr" | head -10; fi
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

skip() { echo "skip: $*"; SKIPS=$((SKIPS + 1)); }

# finish: exit 0 when every check passed, 77 (ctest's SKIP_RETURN_CODE, see cmake/inlight.cmake)
# when none failed but some were skipped, 1 on any failure.
finish() {
    echo "$PASSES passed, $FAILS failed, $SKIPS skipped"
    if [ "$FAILS" -ne 0 ]; then return 1; fi
    if [ "$SKIPS" -ne 0 ]; then exit 77; fi
    return 0
}
