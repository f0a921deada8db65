#!/usr/bin/env bash
# Every pipeline runs from any working directory: it finds the tools, configs and docs from the
# repository root (pipelines/lib.sh's ROOT and tool_bin), never from the caller's folder. Runs
# two from an unrelated folder, and checks that no script defaults a path to a cwd-relative
# build/, configs/, docs/ or samples/.
HERE=$(cd "$(dirname "$0")" && pwd)
# shellcheck source=tests/cli/lib.sh
source "$HERE/../cli/lib.sh"
ROOT=${INLIGHT_SOURCE_DIR:?}
PIPE="$ROOT/pipelines"
mkdir -p "$WORK/elsewhere"
cd "$WORK/elsewhere" || exit 1

# shellcheck disable=SC2016 # the pattern matches ${VAR:-build...} literally
relative=$(grep -nE '\$\{[A-Za-z0-9_]+:-(build|configs|docs|samples)(/|\})' "$PIPE"/*.sh)
if [ -z "$relative" ]; then pass "no pipeline defaults a path to the working directory's build/, configs/, docs/ or samples/"; else
    fail "cwd-relative defaults:"; echo "$relative"; fi
# A script that finds repository files does so through lib.sh (slurm-status.sh needs none).
without_lib=$(grep -L 'lib.sh"$' "$PIPE"/*.sh | grep -v '/lib.sh$' | xargs -r grep -lE '(build|configs|samples|docs)/')
if [ -z "$without_lib" ]; then pass "every pipeline that uses repository files sources lib.sh (ROOT, tool_bin)"; else
    fail "pipelines that use repository files without lib.sh: $without_lib"; fi

if have_shared_data fisheye-ros-mono; then
    expect_exit 0 "calibrate_ros.sh from an unrelated folder" -- "$PIPE/calibrate_ros.sh" "$WORK/cal"
    expect_true "it wrote the calibration and the SH fit" -- \
        test -s "$WORK/cal/calibrate/calibration.json" -a -n "$(find "$WORK/cal" -name '*.json' -path '*sh*' | head -n 1)"
fi
expect_exit 2 "btf-eval.sh from an unrelated folder checks its fabrics against the repository's" -- \
    env BTF_EVAL_FABRICS=nosuch "$PIPE/btf-eval.sh" "$WORK/be"
expect_stderr "$ROOT/configs/fabrics/nosuch.toml not found" "names the path it looked at"
expect_true "and made nothing in the caller's folder" -- test -z "$(ls -A "$WORK/elsewhere")"
finish
