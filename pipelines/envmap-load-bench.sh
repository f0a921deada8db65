#!/usr/bin/env bash
# envmap-load-bench: the whole envmap-project run against OpenImageIO's own read of the same
# file (`oiiotool --stats`: read, decode and summarise), in back-to-back pairs whose order
# alternates, so that the machine's load falls on both alike (issue 13: within 1.2x).
#   pipelines/envmap-load-bench.sh OUT_DIR [PAIRS] [WIDTH]
# Input: blender-data's forest.exr resized by oiiotool to WIDTH x WIDTH/2 float, zip (made once in
# OUT_DIR; not in the repository). Prints each pair and the median, quartiles and range of the
# ratios envmap-project / oiiotool in user CPU time, user + system CPU time and wall time.
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
printf 'pair\toiio_user\toiio_sys\toiio_wall\tours_user\tours_sys\tours_wall\n' > "$OUT/pairs.tsv"
for ((i = 1; i <= PAIRS; i++)); do
    if ((i % 2)); then a=$(oiio); b=$(ours); else b=$(ours); a=$(oiio); fi
    printf '%d\t%s\t%s\n' "$i" "${a// /$'\t'}" "${b// /$'\t'}" >> "$OUT/pairs.tsv"
done
echo "after: load $(cut -d' ' -f1-3 /proc/loadavg)"
awk -F'\t' '
NR == 1 { next }
{
    n++; u[n] = $5 / $2; c[n] = ($5 + $6) / ($2 + $3); w[n] = $7 / $4
    printf "pair %2d: oiiotool %.2f user %.2f sys %.2f wall | envmap-project %.2f user %.2f sys %.2f wall | ratio user %.3f cpu %.3f wall %.3f\n", $1, $2, $3, $4, $5, $6, $7, u[n], c[n], w[n]
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
}' "$OUT/pairs.tsv"
