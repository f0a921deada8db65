# shellcheck shell=bash
# Helpers of the bad-input suite (sourced after tests/cli/lib.sh). Every case runs a tool on one
# bad input with its outputs aimed at $OUT, a folder that already holds files (a previous run's
# results, a note), and checks three things: the exit code, a message on stderr naming the file
# or option and the problem, and $OUT byte for byte as it was (no new, changed or removed file,
# no temporary left behind).
OUT="$WORK/out"
mkdir -p "$OUT/previous"
echo "results of an earlier run" > "$OUT/previous/keep.txt"
echo "a note" > "$OUT/README"

# Names, sizes, modes and hashes of everything under $OUT.
snapshot() {
    (cd "$OUT" && find . -printf '%p %s %m\n' | sort && find . -type f -exec md5sum {} + | sort)
}

# bad CODE PATTERN DESCRIPTION -- command...: the command exits CODE, its stderr matches the
# grep pattern PATTERN (basic regular expression) and $OUT is unchanged.
bad() {
    local code=$1 pattern=$2 what=$3
    shift 4
    local before
    before=$(snapshot)
    expect_exit "$code" "$what" -- "$@"
    expect_stderr "$pattern" "$what: message"
    if [ "$(snapshot)" = "$before" ]; then pass "$what: output folder unchanged"; else
        fail "$what: output folder changed"; diff <(echo "$before") <(snapshot) | head -10 | sed 's/^/    /'; fi
}

# same_file A B DESCRIPTION: A is byte for byte B (an input that must survive a run).
same_file() {
    if cmp -s "$1" "$2"; then pass "$3"; else fail "$3: $1 differs from $2"; fi
}
