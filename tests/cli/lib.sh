# shellcheck shell=bash
# Shared helpers for the CLI test scripts (sourced). Each check prints what it checked.
set -uo pipefail
export BIN=${INLIGHT_BIN:?INLIGHT_BIN must point at build/bin}
export TBIN=${INLIGHT_TEST_BIN:?}
WORK=$(mktemp -d)
trap 'rm -rf "$WORK"' EXIT
FAILS=0
PASSES=0

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

finish() {
    echo "$PASSES passed, $FAILS failed"
    [ "$FAILS" -eq 0 ]
}
