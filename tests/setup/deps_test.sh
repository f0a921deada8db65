#!/usr/bin/env bash
# Every external command that the pipelines, the test scripts, the fuzz runner, .ci/run, the
# Makefile's recipes and the C++ tests' std::system() calls run comes from a Debian package that
# `make deps` installs (the Makefile's DEB_PACKAGES) or from one that a bare Debian 12 already has
# (Priority: required or Essential: yes: what debootstrap's minbase installs). So a missing
# package fails here on any machine, not only on a bare one where the test using it would break.
# Commands are found by tests/setup/list_commands.pl (a static reading of the scripts) and mapped
# to their package with dpkg -S on the Debian directories only (a pyenv or /usr/local copy does
# not count: a bare machine has none).
HERE=$(cd "$(dirname "$0")" && pwd)
# shellcheck source=tests/cli/lib.sh
source "$HERE/../cli/lib.sh"
ROOT=${INLIGHT_SOURCE_DIR:?}
cd "$ROOT" || exit 1

if ! command -v dpkg-query >/dev/null; then
    skip "not a Debian system (no dpkg-query): the package check needs dpkg"
    finish
fi

read -r -a deb_packages <<< "$(make -s --no-print-directory -C "$ROOT" print-deb-packages)"
expect_true "make print-deb-packages lists the packages (${#deb_packages[@]})" -- test "${#deb_packages[@]}" -gt 10

mapfile -t scripts < <(find pipelines tests fuzz -name '*.sh' -o -name '*.smk' | sort)
scripts+=(.ci/run)
mapfile -t cxx < <(grep -rl 'std::system(' lib apps tests fuzz --include='*.cpp' | sort)
# The Makefile's recipe lines as shell: make's $(VAR) become X, except $(shell CMD) and $(MAKE).
recipes="$WORK/Makefile.sh"
# shellcheck disable=SC2016 # make's $(...) and $$ in sed's program, not the shell's
awk '/^\t/ { if (recipe) { sub(/^\t[@-]*/, ""); print }; next }
     { recipe = ($0 ~ /^[A-Za-z_.%-][^=]*:([^=]|$)/) }' Makefile |
    sed -E 's/\$\(shell ([^)]*)\)/$(\1)/g; s/\$\(MAKE\)/make/g; s/\$\([A-Za-z_]+\)/X/g; s/\$\$/$/g' > "$recipes"

# Shell functions defined by the scripts (tests/cli/lib.sh's pass, fail, ...) are not commands.
mapfile -t functions < <(grep -ohE '^\s*(function\s+)?[A-Za-z_][A-Za-z0-9_]*\s*\(\)' "${scripts[@]}" |
    sed -E 's/^\s*function\s+//; s/[ (){}]//g' | sort -u)
is_function() { local f; for f in "${functions[@]}"; do [ "$f" = "$1" ] && return 0; done; return 1; }
# A package of the list, or one that a listed package depends on directly (slurm-wlm brings
# slurmctld, python3 brings python3-minimal's /usr/bin/python3).
mapfile -t deb_closure < <(printf '%s\n' "${deb_packages[@]}"
    dpkg-query -W -f='${Depends}, ${Pre-Depends}\n' "${deb_packages[@]}" 2>/dev/null |
        tr ',|' '\n' | sed -E 's/\(.*\)//; s/:any//; s/^ +| +$//g' | grep .)
in_deps() { local p; for p in "${deb_closure[@]}"; do [ "$p" = "$1" ] && return 0; done; return 1; }

# package_of PATH: the Debian package that owns PATH, through symlinks (alternatives) and
# merged /usr (dpkg knows /bin/dd, the shell finds /usr/bin/dd).
package_of() {
    local p candidates=("$1" "$(readlink -f "$1")")
    candidates+=("${1/#\/usr\/bin\//\/bin/}" "${1/#\/usr\/sbin\//\/sbin/}")
    for p in "${candidates[@]}"; do
        dpkg -S "$p" 2>/dev/null | grep -v '^diversion' | head -n 1 | cut -d: -f1 | grep . && return 0
    done
    return 1
}

n=0
declare -A seen
while IFS=$'\t' read -r cmd file; do
    [ -n "${seen[$cmd]:-}" ] && continue
    seen[$cmd]=1
    is_function "$cmd" && continue
    [ "$file" = "$recipes" ] && file=Makefile
    n=$((n + 1))
    path=$(PATH=/usr/sbin:/usr/bin:/sbin:/bin type -P "$cmd")
    if [ -z "$path" ]; then
        fail "'$cmd' (run by $file) is not installed from a Debian package: add its package to DEB_PACKAGES"
        continue
    fi
    pkg=$(package_of "$path")
    if [ -z "$pkg" ]; then
        fail "'$cmd' ($path, run by $file) belongs to no Debian package"
        continue
    fi
    if in_deps "$pkg"; then
        pass "$cmd: $pkg (make deps)"
    elif dpkg-query -W -f='${Priority} ${Essential}\n' "$pkg" | grep -qE '^required|yes$'; then
        pass "$cmd: $pkg (on a bare Debian 12)"
    else
        fail "'$cmd' (run by $file) comes from package $pkg, which make deps does not install: add it to DEB_PACKAGES"
    fi
done < <(perl "$HERE/list_commands.pl" "${scripts[@]}" "${cxx[@]}" "$recipes")
expect_true "found the commands the scripts run ($n; at least jq, sqlite3, file)" -- \
    test -n "${seen[jq]:-}" -a -n "${seen[sqlite3]:-}" -a -n "${seen[file]:-}"
finish
