#!/usr/bin/env bash
# bake-catalog (Snakemake), labelled slow (over 300 s on the loaded 2-core machine): builds a tiny
# catalogue; a rerun does nothing; a touched but
# unchanged input rebuilds nothing; a changed one rebuilds only what reads it; killed mid-run
# (SIGKILL to the whole process group), the rerun finishes with every bundle intact and
# without redoing the jobs that had finished.
HERE=$(cd "$(dirname "$0")" && pwd)
# shellcheck source=tests/cli/lib.sh
source "$HERE/../cli/lib.sh"
# shellcheck source=tests/pipelines/tiny.sh
source "$HERE/tiny.sh"
tiny_catalog 3
run() { "$PIPE/bake-catalog.sh" -j 1 "$CAT" "$OUT" >"$WORK/run.log" 2>&1; }

# 1. Start, and kill everything once one fabric is done and another is running.
setsid "$PIPE/bake-catalog.sh" -j 1 "$CAT" "$OUT" >"$WORK/killed.log" 2>&1 &
pid=$!
state() {  # prints "DONE RUNNING": fabric ids with a stamp, fabric ids started without one
    local done="" running="" f id
    for f in "$OUT"/logs/fabric-*.log; do
        [ -e "$f" ] || continue
        id=$(basename "$f" .log)
        if [ -f "$OUT/stamps/$id.json" ]; then done+="${id#fabric-} "; else running+="${id#fabric-} "; fi
    done
    echo "$done|$running"
}
for _ in $(seq 1 1200); do
    s=$(state)
    [ "${s%%|*}" != "" ] && [ "${s##*|}" != "" ] && break
    sleep 0.05
done
kill -KILL -- "-$pid" 2>/dev/null
wait "$pid" 2>/dev/null
s=$(state)
read -r -a finished <<<"${s%%|*}"
read -r -a interrupted <<<"${s##*|}"
echo "killed: finished [${finished[*]}], interrupted [${interrupted[*]}]"
expect_true "killed with a fabric done and another running" -- \
    test "${#finished[@]}" -ge 1 -a "${#interrupted[@]}" -ge 1
declare -A sums
for id in "${finished[@]}"; do
    sums[$id]="$(sha256sum "$OUT/stamps/fabric-$id.json") $(stat -c %y "$OUT/stamps/fabric-$id.json")"
done
# Nothing corrupt: every bundle folder a reader can see verifies (unfinished ones are hidden).
expect_exit 0 "bundles visible after the kill all verify" -- "$BIN/bundle" verify "$OUT/bundles" -q

# 2. The rerun finishes, redoes the interrupted fabric and not the finished ones.
expect_exit 0 "rerun after the kill finishes" -- run
for id in "${finished[@]}"; do
    expect_true "$id was not redone (its stamp is untouched)" -- \
        test "$(sha256sum "$OUT/stamps/fabric-$id.json") $(stat -c %y "$OUT/stamps/fabric-$id.json")" = "${sums[$id]}"
    expect_true "the rerun did not run $id's job" -- bash -c "! grep -q 'wildcards: fid=$id\$' '$WORK/run.log'"
done
for id in "${interrupted[@]}"; do
    expect_true "the rerun redid the interrupted $id" -- grep -q "wildcards: fid=$id\$" "$WORK/run.log"
done
expect_exit 0 "every bundle verifies" -- "$BIN/bundle" verify "$OUT/bundles" -q
expect_true "no hidden unfinished bundle folder is left" -- \
    test -z "$(find "$OUT/bundles/fabrics" -mindepth 1 -maxdepth 1 -name '.*')"
expect_true "catalogue lists the three fabrics" -- \
    test "$(sqlite3 "$OUT/bundles/catalog.sqlite" 'SELECT group_concat(id) FROM fabrics ORDER BY id')" = "f1,f2,f3"
expect_true "validation report written" -- test -s "$OUT/validate/index.html" -a -s "$OUT/validate/plots/error_vs_sh_bands.png"
expect_true "summary covers the three pairs" -- test "$(jq length "$OUT/validate/summary.json")" -eq 3

# 3. Incremental by content.
expect_exit 0 "rerun" -- run
expect_true "a rerun does nothing" -- grep -q 'Nothing to be done' "$WORK/run.log"
touch "$CAT/fabrics/f2/material.toml"
expect_exit 0 "rerun after touch" -- run
expect_true "a touched, unchanged input rebuilds nothing" -- grep -q 'Nothing to be done' "$WORK/run.log"
sed -i 's/alpha = 0.3/alpha = 0.35/' "$CAT/fabrics/f2/material.toml"
expect_exit 0 "rerun after an edit" -- run
expect_true "an edited fabric is rebuilt" -- grep -q 'wildcards: fid=f2$' "$WORK/run.log"
expect_true "the others are not" -- bash -c "! grep -Eq 'wildcards: fid=f[13]' '$WORK/run.log'"
expect_true "its new table is in its bundle" -- \
    grep -q 'alpha = 0.35' "$OUT/bundles/fabrics/f2/material.toml"

# 5. A captured-BTF fabric: its capture is a job of its own, run once; a new material rebakes the
#    fabric from the same capture.
make_captured_fabric "$CAT/fabrics/c1" "Captured twill"
expect_exit 0 "rerun with a captured fabric added" -- run
expect_true "the capture and the fabric ran, no other fabric" -- bash -c \
    "grep -q 'rule capture:' '$WORK/run.log' && grep -q 'wildcards: fid=c1\$' '$WORK/run.log' && ! grep -Eq 'wildcards: fid=f[123]\$' '$WORK/run.log'"
expect_true "the catalogue lists its BTF: components and bytes as in its manifest" -- test \
    "$(sqlite3 "$OUT/bundles/catalog.sqlite" "SELECT btf_components || ' ' || btf_bytes FROM fabrics WHERE id = 'c1'")" = \
    "$(jq -r '[.files[] | select(.role | startswith("btf_"))] | "\([.[] | select(.role == "btf_component")] | length) \(map(.bytes) | add)"' "$OUT/bundles/fabrics/c1/manifest.json")"
expect_true "its pair shades the BTF from the workflow's capture, every stream prefix" -- jq -e \
    '(.btf.raw_btf | endswith("/captures/c1/btf")) and ([.btf.views[0].stream[].components_sent] == [0, 3, 6, 9, 12])' "$OUT/validate/pairs/c1/night/summary.json"
expect_true "and no BTF for a BRDF-only fabric" -- test "$(sqlite3 "$OUT/bundles/catalog.sqlite" "SELECT btf_bytes FROM fabrics WHERE id = 'f1'")" = 0
capture_stamp="$(stat -c %y "$OUT/stamps/capture-c1.json")"
sed -i 's/alpha = 0.3/alpha = 0.4/' "$CAT/fabrics/c1/material.toml"
expect_exit 0 "rerun after editing the captured fabric's material" -- run
expect_true "the fabric is rebaked, its capture is not redone" -- bash -c \
    "grep -q 'wildcards: fid=c1\$' '$WORK/run.log' && ! grep -q 'rule capture:' '$WORK/run.log'"
expect_true "capture stamp untouched" -- test "$(stat -c %y "$OUT/stamps/capture-c1.json")" = "$capture_stamp"

# 4. A second bake-catalog on the same folder is refused while one runs.
exec 8>"$OUT/.bake-catalog.lock"
flock -n 8
expect_exit 1 "a concurrent run on the same OUT is refused" -- "$PIPE/bake-catalog.sh" "$CAT" "$OUT"
expect_stderr "another bake-catalog is running" "and says why"
exec 8>&-
finish
