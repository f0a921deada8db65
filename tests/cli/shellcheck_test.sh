#!/usr/bin/env bash
# Every pipeline and test script passes shellcheck (house style section 8).
set -uo pipefail
ROOT=${INLIGHT_SOURCE_DIR:?}
cd "$ROOT" || exit 1
mapfile -t scripts < <(find pipelines tests fuzz .ci -name '*.sh' -o -path '.ci/run' | sort)
if shellcheck -x "${scripts[@]}"; then
    echo "${#scripts[@]} passed, 0 failed"
else
    echo "shellcheck found problems"; exit 1
fi
