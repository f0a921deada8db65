#!/usr/bin/env bash
# The six tools share one shape: `--version` prints "<tool> <version> (commit <commit>)" with the
# commit the binary was built from, the run report carries the same commit, and a long option the
# tool does not have is a usage error (exit 2) that names it, with the nearest real option when it
# is a near miss, before any positional argument is looked at.
HERE=$(cd "$(dirname "$0")" && pwd)
# shellcheck source=tests/cli/lib.sh
source "$HERE/../cli/lib.sh"
ROOT=${INLIGHT_SOURCE_DIR:?}

in_git=0
git -C "$ROOT" rev-parse HEAD >/dev/null 2>&1 && in_git=1
for tool in calibrate envmap-project brdf-sh-bake btf-pca render bundle; do
    expect_exit 0 "$tool --version" -- "$BIN/$tool" --version
    line=$(cat "$WORK/stdout")
    if [[ $line =~ ^$tool\ [0-9]+\.[0-9]+\.[0-9]+\ \(commit\ ([0-9a-f]{12}(-dirty)?|unknown)\)$ ]]; then
        pass "$tool --version: '$line'"
        commit=${BASH_REMATCH[1]%-dirty}
        if [ "$in_git" -eq 1 ]; then
            expect_true "$tool: the commit $commit is one of this checkout's" -- \
                git -C "$ROOT" cat-file -e "$commit^{commit}"
        fi
    else
        fail "$tool --version printed '$line', expected '$tool X.Y.Z (commit <12 hex digits>)'"
    fi
done
# Modes print the tool's line, not "calibrate geometry ...".
expect_exit 0 "calibrate geometry --version" -- "$BIN/calibrate" geometry --version
expect_true "a mode's --version names the tool" -- grep -q '^calibrate [0-9]' "$WORK/stdout"
expect_exit 0 "render trace --version" -- "$BIN/render" trace --version
expect_true "render's modes too" -- grep -q '^render [0-9]' "$WORK/stdout"
expect_exit 0 "btf-pca compress --version" -- "$BIN/btf-pca" compress --version
expect_true "btf-pca's modes too" -- grep -q '^btf-pca [0-9]' "$WORK/stdout"

# The report carries the commit --version prints.
expect_exit 0 "render --help" -- "$BIN/render" --help
"$BIN/bundle" verify "$WORK" --report "$WORK/r.json" >/dev/null 2>&1
want=$("$BIN/bundle" --version | sed -E 's/.*\(commit (.*)\)$/\1/')
expect_true "the report's commit equals --version's ($want)" -- \
    jq -e --arg c "$want" ".commit == \$c" "$WORK/r.json"

# Unknown long options: named, exit 2, before the positional arguments are checked.
expect_exit 2 "envmap-project --bandz 3: usage error" -- "$BIN/envmap-project" --bandz 3 nothere.exr -o "$WORK/x.json"
expect_stderr "--bandz: unknown option (did you mean --bands?)" "names the option and the nearest one"
expect_true "not the positional's complaint" -- bash -c "! grep -q 'File does not exist' '$WORK/stderr'"
expect_exit 2 "render trace --frobnicate=1: usage error" -- "$BIN/render" trace --frobnicate=1 nothere.toml
expect_stderr "--frobnicate: unknown option (see --help)" "a far miss gets no suggestion"
expect_exit 2 "bundle pack --kindd: usage error" -- "$BIN/bundle" pack --kindd fabric
expect_stderr "--kindd: unknown option (did you mean --kind?)" "a mode's options are the ones suggested"
expect_exit 2 "calibrate geometry --boards: usage error" -- "$BIN/calibrate" geometry --boards 9x6 nothere
expect_stderr "did you mean --board?" "calibrate's mode too"
expect_exit 2 "btf-pca interpolate --schem: usage error" -- "$BIN/btf-pca" interpolate --schem delaunay nothere --pairs nothere -o x
expect_stderr "--schem: unknown option (did you mean --scheme?)" "btf-pca's mode too"
finish
