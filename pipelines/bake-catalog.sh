#!/usr/bin/env bash
# bake-catalog: a catalogue folder (fabrics/<id>/, devices/<id>/, catalog.toml) -> OUT/bundles/
# (one verified bundle per fabric and device, catalog.sqlite) and OUT/validate/ (the validation
# report), through the Snakemake workflow pipelines/bake-catalog.smk.
#   pipelines/bake-catalog.sh [-j N] [--slurm] CATALOG OUT [SNAKEMAKE_ARGS...]
#     -j N      jobs in parallel (default: the number of cores; with --slurm: jobs in the queue)
#     --slurm   submit every job to Slurm with sbatch (generic --cluster mode, status through
#               scontrol: no accounting database needed); SBATCH_ARGS adds sbatch options
# Rerun it at any time: only what changed (by content) is rebuilt, and the catalogue and report
# follow the folder (a fabric removed or renamed leaves them); after a kill, the jobs that were
# running are redone and nothing else, once no process of theirs is left (it refuses to start
# while one lives: docs/pipelines.md). Binaries from ${INLIGHT_BIN:-ROOT/build/bin} (ROOT: the repository).
# Quality gate: the [quality] table of CATALOG/catalog.toml (pipelines/catalog_quality.py,
# docs/pipelines.md "Quality gate"); a bad one is a usage error (exit 2) before any job. A pair
# that fails it fails its validation job, so Snakemake starts no new job; the script then names
# each failed fabric and environment with its figures and exits 3 (other failures exit 1).
set -euo pipefail
# shellcheck source=pipelines/lib.sh
. "$(dirname "$0")/lib.sh"
JOBS=$(nproc)
SLURM=0
while [ $# -gt 0 ]; do
    case $1 in
        -j) JOBS=$2; shift 2 ;;
        -j*) JOBS=${1#-j}; shift ;;
        --slurm) SLURM=1; shift ;;
        *) break ;;
    esac
done
usage_unless $# 2 - "[-j N] [--slurm] CATALOG OUT [SNAKEMAKE_ARGS...]"
CATALOG=$(abs_dir "$1")
OUT=$(out_dir "$2")
shift 2
BIN=$(tool_bin)
python3 "$HERE/catalog_quality.py" "$CATALOG"  # exit 2 with the message on a bad [quality]
for t in bundle brdf-sh-bake btf-pca calibrate render; do
    if [ ! -x "$BIN/$t" ]; then
        echo "bake-catalog: $BIN/$t not found: build first (make)" >&2
        exit 1
    fi
done

# One bake-catalog per output folder: this lock is held by this script and its Snakemake.
exec 9>"$OUT/.bake-catalog.lock"
if ! flock -n 9; then
    echo "bake-catalog: another bake-catalog is running on $OUT" >&2
    exit 1
fi
# Killing Snakemake alone releases that lock while its jobs run on. Every job holds a shared lock
# on .bake-catalog.jobs (the workflow's shell prefix), inherited by each process it starts, so it
# is free only when no process of an earlier run's job lives. Only then is a Snakemake lock left
# in OUT stale, and a rerun safe.
JOBS_LOCK="$OUT/.bake-catalog.jobs"
exec 7>>"$JOBS_LOCK"
if ! flock -n -x 7; then
    echo "bake-catalog: jobs of an earlier run on $OUT are still running; wait for them to end or stop them, then run again:" >&2
    for fd in /proc/[0-9]*/fd/*; do  # the processes holding the lock (on this machine)
        if [ "$(readlink "$fd" 2>/dev/null)" = "$JOBS_LOCK" ]; then
            p=${fd#/proc/}
            p=${p%%/*}
            [ "$p" = $$ ] || echo "  pid $p: $(tr '\0' ' ' <"/proc/$p/cmdline" 2>/dev/null | cut -c 1-160)" >&2
        fi
    done
    exit 1
fi
exec 7>&-
common=(-s "$HERE/bake-catalog.smk" --directory "$OUT" --config "catalog=$CATALOG" "bin=$BIN")
# A killed run leaves Snakemake's lock behind (flock above says no run of ours holds it). Only then
# is --unlock worth its Snakemake start-up.
if [ -n "$(ls -A "$OUT/.snakemake/locks" 2>/dev/null)" ]; then
    snakemake "${common[@]}" --unlock -q >/dev/null 2>&1 || true
fi

args=("${common[@]}" --rerun-incomplete --jobs "$JOBS")
if [ "$SLURM" -eq 1 ]; then
    mkdir -p "$OUT/slurm"
    # shellcheck disable=SC2016  # {rule} and {threads} are Snakemake's placeholders
    args+=(--cluster "sbatch --parsable --job-name=inlight-{rule} --cpus-per-task={threads} --output=$OUT/slurm/%j.log ${SBATCH_ARGS:-}"
        --cluster-status "$HERE/slurm-status.sh" --latency-wait 30 --max-status-checks-per-second 2)
else
    args+=(--cores "$JOBS")
fi
# A gate failure of an earlier run is redone (its summary.json was removed with the failed job):
# only the markers this run writes count.
rm -f "$OUT"/validate/pairs/*/*/gate_failed.json
rc=0
snakemake "${args[@]}" "$@" || rc=$?
if [ "$rc" -ne 0 ]; then
    failed=("$OUT"/validate/pairs/*/*/gate_failed.json)
    if [ -e "${failed[0]}" ]; then
        for f in "${failed[@]}"; do
            jq -r '"bake-catalog: quality gate failed: fabric \(.fabric) under \(.environment): \(.error)",
                   (.gate.items // [] | .[] | select(.verdict == "FAILURE")
                    | "  \(.name): mean relative error \(.mean_rel), mean Delta E 2000 \(.mean_de2000)")' "$f" >&2
        done
        echo "bake-catalog: stopped on a failed quality gate (figures in validate/pairs/<fabric>/<environment>/gate_failed.json); a rerun validates the failed pairs again" >&2
        exit 3
    fi
    exit "$rc"
fi
