#!/usr/bin/env bash
# bake-catalog never resumes beside a live job of a killed run: with only the Snakemake process
# killed (kill -9) while a fabric job runs, its lock is released but the job runs on; a resume is
# refused, naming the job's processes, until the last of them has exited, and then finishes.
HERE=$(cd "$(dirname "$0")" && pwd)
# shellcheck source=tests/cli/lib.sh
source "$HERE/../cli/lib.sh"
# shellcheck source=tests/pipelines/tiny.sh
source "$HERE/tiny.sh"
require_blender_data
CAT="$WORK/cat"
OUT="$WORK/out"
make_fabric "$CAT/fabrics/f1" "Fabric 1" 0.3
printf 'environments = []\n' > "$CAT/catalog.toml"  # the fabric job and the index only

# The real tools, brdf-sh-bake held at a gate: it records its pid and waits for the test's word,
# so the job surely runs when Snakemake is killed and outlives it as long as the test wants.
G="$WORK/gate"
mkdir -p "$G" "$WORK/bin"
for t in bundle btf-pca calibrate render envmap-project; do ln -s "$BIN/$t" "$WORK/bin/$t"; done
cat > "$WORK/bin/brdf-sh-bake" <<EOF
#!/usr/bin/env bash
echo \$\$ >> "$G/pids"
while [ ! -e "$G/open" ]; do sleep 0.1; done
exec "$BIN/brdf-sh-bake" "\$@"
EOF
chmod +x "$WORK/bin/brdf-sh-bake"
bake() { INLIGHT_BIN="$WORK/bin" "$PIPE/bake-catalog.sh" -j 1 "$CAT" "$OUT"; }

setsid env INLIGHT_BIN="$WORK/bin" "$PIPE/bake-catalog.sh" -j 1 "$CAT" "$OUT" >"$WORK/first.log" 2>&1 &
runner=$!
for _ in $(seq 1 1200); do [ -s "$G/pids" ] && break; sleep 0.1; done
expect_true "the fabric job started (gated brdf-sh-bake running)" -- test -s "$G/pids"
job=$(head -n 1 "$G/pids")
snake=$(pgrep -f "bake-catalog.smk --directory $OUT" | head -n 1)
expect_true "found the run's Snakemake process" -- test -n "$snake"
kill -KILL "$snake"
wait "$runner"
expect_true "bake-catalog ended with its Snakemake" -- test $? -ne 0
expect_true "the job outlives Snakemake" -- kill -0 "$job"

expect_exit 1 "a resume while the killed run's job lives is refused" -- bake
expect_stderr "jobs of an earlier run on $OUT are still running" "says why"
expect_stderr "pid $job: .*/bin/brdf-sh-bake --config" "names the job's processes, brdf-sh-bake's among them"
expect_true "the refused resume started no job" -- test "$(wc -l < "$G/pids")" -eq 1
expect_true "and left the Snakemake lock in place" -- test -n "$(ls -A "$OUT/.snakemake/locks" 2>/dev/null)"

touch "$G/open"
for _ in $(seq 1 3000); do kill -0 "$job" 2>/dev/null || break; sleep 0.1; done
expect_true "the orphaned job finished" -- bash -c "! kill -0 $job 2>/dev/null"
# The job's shell may outlive brdf-sh-bake by its last steps (pack, verify, the stamp): the lock
# is free only when its last process has exited.
flock -x -w 300 "$OUT/.bake-catalog.jobs" true
expect_exit 0 "the resume after the job ended finishes" -- bake
expect_true "the catalogue lists the fabric" -- \
    test "$(sqlite3 "$OUT/bundles/catalog.sqlite" 'SELECT id FROM fabrics')" = f1
expect_exit 0 "its bundle verifies" -- "$BIN/bundle" verify "$OUT/bundles" -q
finish
