#!/usr/bin/env bash
# envmap-load-bench: the whole envmap-project run against OpenImageIO's own read of the same
# file (`oiiotool --stats`: read, decode and summarise), in back-to-back pairs whose order
# alternates, so that the machine's load falls on both alike (goal: within 1.2x).
#   pipelines/envmap-load-bench.sh OUT_DIR [PAIRS] [WIDTH]
# Input: blender-data's forest.exr resized by oiiotool to WIDTH x WIDTH/2 float, zip (made once in
# OUT_DIR; not in the repository). Prints each pair and the median, quartiles and range of the
# ratios envmap-project / oiiotool in user CPU time, user + system CPU time and wall time.
# BASE_BIN=DIR adds DIR/envmap-project (e.g. a build of main) to every round, the three runs in
# rotating order, and prints envmap-project / base as well: a change's effect within one run.
set -euo pipefail
# shellcheck source=pipelines/lib.sh
. "$(dirname "$0")/lib.sh"
usage_unless $# 1 - "OUT_DIR [PAIRS] [WIDTH]"
OUT=$(out_dir "$1")
PAIRS=${2:-15}
WIDTH=${3:-4096}
BIN=$(tool_bin)
THREADS=${THREADS:-2}
SRC=/usr/share/blender/datafiles/studiolights/world/forest.exr
if [ ! -f "$SRC" ]; then
    echo "envmap-load-bench: $SRC not found (Debian package blender-data); skipped" >&2
    exit 0
fi
MAP="$OUT/forest_${WIDTH}.exr"
[ -s "$MAP" ] || oiiotool "$SRC" --resize "${WIDTH}x$((WIDTH / 2))" -d float --compression zip -o "$MAP"
echo "envmap-load-bench: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs), load $(cut -d' ' -f1-3 /proc/loadavg), $(date -u '+%F %H:%M') UTC"
echo "map: $MAP ($(du -m "$MAP" | cut -f1) MB), envmap-project --threads $THREADS, $PAIRS pairs"

# One timed run: prints "user sys wall" in seconds.
timed() {
    local t="$OUT/time.txt"
    /usr/bin/time -f "%U %S %e" -o "$t" "$@" > /dev/null
    cat "$t"
}
oiio() { timed oiiotool --threads "$THREADS" --stats "$MAP"; }
ours() { timed "$BIN/envmap-project" "$MAP" -o "$OUT/forest_sh.json" --threads "$THREADS" -q; }
ours > /dev/null  # warm the page cache and the loader's caches for both
oiio > /dev/null
if [ -n "${BASE_BIN:-}" ]; then
    BASE=$(cd "$BASE_BIN" && pwd)/envmap-project
    base() { timed "$BASE" "$MAP" -o "$OUT/forest_sh_base.json" --threads "$THREADS" -q; }
    base > /dev/null
    echo "base: $BASE"
fi
printf 'pair\toiio_user\toiio_sys\toiio_wall\tours_user\tours_sys\tours_wall%s\n' \
    "${BASE:+$'\t'base_user$'\t'base_sys$'\t'base_wall}" > "$OUT/pairs.tsv"
for ((i = 1; i <= PAIRS; i++)); do
    if [ -n "${BASE:-}" ]; then  # orders oiio-ours-base, ours-base-oiio, base-oiio-ours
        case $((i % 3)) in
            1) a=$(oiio); b=$(ours); c=$(base) ;;
            2) b=$(ours); c=$(base); a=$(oiio) ;;
            0) c=$(base); a=$(oiio); b=$(ours) ;;
        esac
        printf '%d\t%s\t%s\t%s\n' "$i" "${a// /$'\t'}" "${b// /$'\t'}" "${c// /$'\t'}" >> "$OUT/pairs.tsv"
        continue
    fi
    if ((i % 2)); then a=$(oiio); b=$(ours); else b=$(ours); a=$(oiio); fi
    printf '%d\t%s\t%s\n' "$i" "${a// /$'\t'}" "${b// /$'\t'}" >> "$OUT/pairs.tsv"
done
echo "after: load $(cut -d' ' -f1-3 /proc/loadavg)"
awk -F'\t' '
NR == 1 { next }
{
    n++; u[n] = $5 / $2; c[n] = ($5 + $6) / ($2 + $3); w[n] = $7 / $4
    printf "pair %2d: oiiotool %.2f user %.2f sys %.2f wall | envmap-project %.2f user %.2f sys %.2f wall | ratio user %.3f cpu %.3f wall %.3f\n", $1, $2, $3, $4, $5, $6, $7, u[n], c[n], w[n]
    if (NF >= 10) {
        nb++; bu[n] = $5 / $8; bc[n] = ($5 + $6) / ($8 + $9); bw[n] = $7 / $10
        printf "pair %2d: base %.2f user %.2f sys %.2f wall | ours / base: user %.3f cpu %.3f wall %.3f\n", $1, $8, $9, $10, bu[n], bc[n], bw[n]
    }
}
function sorted(a, m,    i, j, t) { for (i = 2; i <= m; i++) for (j = i; j > 1 && a[j - 1] > a[j]; j--) { t = a[j]; a[j] = a[j - 1]; a[j - 1] = t } }
function q(a, m, p,    x, k) { x = 1 + (m - 1) * p; k = int(x); return k >= m ? a[m] : a[k] + (x - k) * (a[k + 1] - a[k]) }
function show(name, a) {
    sorted(a, n)
    printf "%-16s median %.3f, quartiles %.3f-%.3f, range %.3f-%.3f (%d pairs)\n", name, q(a, n, 0.5), q(a, n, 0.25), q(a, n, 0.75), a[1], a[n], n
}
END {
    print "envmap-project / oiiotool --stats:"
    show("user CPU", u); show("user + sys CPU", c); show("wall", w)
    if (nb > 0) {
        print "envmap-project / base (BASE_BIN):"
        show("user CPU", bu); show("user + sys CPU", bc); show("wall", bw)
    }
}' "$OUT/pairs.tsv"
