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

# The commands, each once, with the first script that runs it; shell functions are not commands.
declare -A where
while IFS=$'\t' read -r cmd file; do
    [ -n "${where[$cmd]:-}" ] && continue
    is_function "$cmd" && continue
    [ "$file" = "$recipes" ] && file=Makefile
    where[$cmd]=$file
done < <(perl "$HERE/list_commands.pl" "${scripts[@]}" "${cxx[@]}" "$recipes")

# Where each command is, and the paths dpkg may know it by: through symlinks (alternatives) and
# merged /usr (dpkg knows /bin/dd, the shell finds /usr/bin/dd). Their owners are read from
# dpkg's file lists in one pass (dpkg -S per path takes seconds for the ~70 commands).
declare -A path_of
for cmd in "${!where[@]}"; do
    path_of[$cmd]=$(PATH=/usr/sbin:/usr/bin:/sbin:/bin type -P "$cmd")
done
candidates() {
    [ -n "$1" ] || return 0
    printf '%s\n' "$1" "$(readlink -f "$1")" "${1/#\/usr\/bin\//\/bin/}" "${1/#\/usr\/sbin\//\/sbin/}"
}
for cmd in "${!path_of[@]}"; do candidates "${path_of[$cmd]}"; done | sort -u > "$WORK/paths"
declare -A owner
while IFS=: read -r list path; do
    pkg=$(basename "$list" .list)
    owner[$path]=${pkg%%:*}
done < <(grep -xF -f "$WORK/paths" /var/lib/dpkg/info/*.list)

for cmd in $(printf '%s\n' "${!where[@]}" | sort); do
    file=${where[$cmd]}
    path=${path_of[$cmd]}
    if [ -z "$path" ]; then
        fail "'$cmd' (run by $file) is not installed from a Debian package: add its package to DEB_PACKAGES"
        continue
    fi
    pkg=
    while read -r p; do
        [ -n "${owner[$p]:-}" ] && { pkg=${owner[$p]}; break; }
    done < <(candidates "$path")
    if [ -z "$pkg" ]; then
        fail "'$cmd' ($path, run by $file) belongs to no Debian package"
    elif in_deps "$pkg"; then
        pass "$cmd: $pkg (make deps)"
    elif dpkg-query -W -f='${Priority} ${Essential}\n' "$pkg" | grep -qE '^required|yes$'; then
        pass "$cmd: $pkg (on a bare Debian 12)"
    else
        fail "'$cmd' (run by $file) comes from package $pkg, which make deps does not install: add it to DEB_PACKAGES"
    fi
done
expect_true "found the commands the scripts run (${#where[@]}; at least jq, sqlite3, file)" -- \
    test -n "${where[jq]:-}" -a -n "${where[sqlite3]:-}" -a -n "${where[file]:-}"
finish
