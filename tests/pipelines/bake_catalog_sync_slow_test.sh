#!/usr/bin/env bash
# bake-catalog keeps the catalogue (bundle index, catalog.sqlite), the bundle root and the
# validation report equal to the catalogue folder: after a fabric is moved out, one renamed and
# one added, the rerun lists exactly the folders there now, and nothing of the removed ones is
# left (their stamps go with their bundles, so one moved back is baked again).
HERE=$(cd "$(dirname "$0")" && pwd)
# shellcheck source=tests/cli/lib.sh
source "$HERE/../cli/lib.sh"
# shellcheck source=tests/pipelines/tiny.sh
source "$HERE/tiny.sh"
tiny_catalog 2
run() { "$PIPE/bake-catalog.sh" -j 2 "$CAT" "$OUT" >"$WORK/run.log" 2>&1; }
joined() { paste -sd, -; }
# Each listing, sorted and comma-joined: the catalogue folder, the catalogue's fabrics, the
# bundle root (hidden unfinished folders included: none may stay) and the report's fabrics.
folder_ids() { find "$CAT/fabrics" -mindepth 1 -maxdepth 1 -type d -printf '%f\n' | sort | joined; }
catalog_ids() { sqlite3 "$OUT/bundles/catalog.sqlite" 'SELECT id FROM fabrics ORDER BY id' | joined; }
bundle_ids() { find "$OUT/bundles/fabrics" -mindepth 1 -maxdepth 1 -printf '%f\n' | sort | joined; }
report_ids() { jq -r '[.[].fabric] | unique[]' "$OUT/validate/summary.json" | joined; }
# check WHEN: every listing equals the folder's, the bundles verify, the page links only them.
check() {
    local want
    want=$(folder_ids)
    expect_true "$1: catalogue rows are the folders ($want; got $(catalog_ids))" -- test "$(catalog_ids)" = "$want"
    expect_true "$1: bundle root holds exactly them (got $(bundle_ids))" -- test "$(bundle_ids)" = "$want"
    expect_true "$1: report rows are them (got $(report_ids))" -- test "$(report_ids)" = "$want"
    expect_true "$1: report pages link their pairs only" -- test \
        "$(grep -o 'pairs/[a-z0-9_-]*/' "$OUT/validate/index.html" | sort -u | sed 's|pairs/||; s|/||' | joined)" = "$want"
    expect_true "$1: Markdown summary has their rows only" -- test \
        "$(grep -o '^| [a-z0-9_-]* | night |' "$OUT/validate/summary.md" | cut -d' ' -f2 | sort | joined)" = "$want"
    expect_exit 0 "$1: every bundle verifies" -- "$BIN/bundle" verify "$OUT/bundles" -q
}

expect_exit 0 "bake f1 f2" -- run
check "first bake"

mkdir -p "$WORK/aside"
mv "$CAT/fabrics/f1" "$WORK/aside/f1"
mv "$CAT/fabrics/f2" "$CAT/fabrics/g2"
make_fabric "$CAT/fabrics/f3" "Fabric 3" 0.5
expect_exit 0 "rerun: f1 moved out, f2 renamed g2, f3 added" -- run
check "after remove, rename, add"
expect_true "the renamed bundle carries its new id" -- jq -e '.id == "g2"' "$OUT/bundles/fabrics/g2/manifest.json"
expect_true "g2 and f3 were baked" -- bash -c \
    "grep -q 'wildcards: fid=g2\$' '$WORK/run.log' && grep -q 'wildcards: fid=f3\$' '$WORK/run.log'"
expect_true "nothing of f1 or f2 is left in OUT (stamps, keys, work, pairs)" -- test -z \
    "$(find "$OUT/stamps" "$OUT/keys" "$OUT/work" "$OUT/validate/pairs" -name '*f1*' -o -name '*f2*' | grep -v '/g2')"

expect_exit 0 "rerun with nothing changed" -- run
expect_true "does nothing" -- grep -q 'Nothing to be done' "$WORK/run.log"

finish
