# shellcheck shell=bash
# The opening the pipeline scripts share, held once (sourced right after `set -euo pipefail`):
#   # shellcheck source=pipelines/lib.sh
#   . "$(dirname "$0")/lib.sh"
# Sets HERE (this folder, pipelines/), ROOT (the source tree) and SHARED (../shared beside it,
# or INLIGHT_SHARED_DIR), and gives the argument, folder and tool lookups below.
# shellcheck disable=SC2034  # HERE, ROOT and SHARED are for the scripts that source this
HERE=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
ROOT=$(cd "$HERE/.." && pwd)
# shellcheck disable=SC2034
SHARED=${INLIGHT_SHARED_DIR:-$ROOT/../shared}

# usage_unless NARGS MIN MAX ARGS: exits 2 with "usage: <script> ARGS" unless MIN <= NARGS <= MAX
# (MAX "-": no upper bound).
usage_unless() {
    if [ "$1" -lt "$2" ] || { [ "$3" != - ] && [ "$1" -gt "$3" ]; }; then
        echo "usage: $(basename "$0") $4" >&2
        exit 2
    fi
}

# abs_dir DIR: the absolute path of an existing folder; when it is not one, says so (naming the
# script) and fails, which ends the script under set -e with exit 1.
abs_dir() {
    cd "$1" 2>/dev/null && pwd && return
    echo "$(basename "$0"): $1: not found or not a folder" >&2
    return 1
}

# out_dir DIR: makes the folder if needed and prints its absolute path.
out_dir() { mkdir -p "$1" && abs_dir "$1"; }

# tool_bin: the absolute folder of the inlight binaries, ${INLIGHT_BIN:-ROOT/build/bin}.
tool_bin() { abs_dir "${INLIGHT_BIN:-$ROOT/build/bin}"; }

# check_id ID: exits 2 with a message unless ID is a bundle id (1-64 characters of a-z, 0-9,
# '_', '-', starting with a letter or digit; lib/bundle/manifest.h): found before any step runs,
# not by `bundle pack` after all of them (an ID from a folder named "My Fabric" failed at the end).
check_id() {
    if ! [[ $1 =~ ^[a-z0-9][a-z0-9_-]{0,63}$ ]]; then
        echo "$(basename "$0"): id '$1': expected 1-64 characters of a-z, 0-9, '_', '-', starting with a letter or digit (give ID, or rename the folder)" >&2
        exit 2
    fi
}
