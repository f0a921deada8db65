#!/usr/bin/env bash
# bake-catalog through Slurm: a one-node cluster (pipelines/slurm-single-node.sh) runs a tiny
# catalogue with `bake-catalog.sh --slurm` (generic --cluster sbatch mode, status from
# scontrol). Every job must have run as a Slurm job and the bundles must verify. Skips (77)
# where the daemons cannot start (not root, packages missing).
HERE=$(cd "$(dirname "$0")" && pwd)
# shellcheck source=tests/cli/lib.sh
source "$HERE/../cli/lib.sh"
# shellcheck source=tests/pipelines/tiny.sh
source "$HERE/tiny.sh"
tiny_catalog 2
"$PIPE/slurm-single-node.sh" "$PIPE/bake-catalog.sh" --slurm -j 4 "$CAT" "$OUT" >"$WORK/slurm.log" 2>&1
code=$?
if [ "$code" -eq 77 ]; then
    grep 'slurm-single-node' "$WORK/slurm.log"
    echo "skip: Slurm cannot start here"
    exit 77
fi
if [ "$code" -eq 0 ]; then pass "bake-catalog --slurm finished (exit 0)"; else
    fail "bake-catalog --slurm: exit $code"; tail -n 30 "$WORK/slurm.log"; fi
grep 'slurm-single-node:' "$WORK/slurm.log"
# Jobs: 2 fabrics, 2 validation pairs, one convergence study (`all`, `report` and `index` are
# local rules: bookkeeping run by the submitting Snakemake).
n=$(find "$OUT/slurm" -name '*.log' | wc -l)
expect_true "five jobs ran as Slurm jobs (found $n job logs)" -- test "$n" -eq 5
expect_true "Snakemake submitted them with sbatch" -- grep -q 'Submitted job .* with external jobid' "$WORK/slurm.log"
expect_exit 0 "bundles verify" -- "$BIN/bundle" verify "$OUT/bundles" -q
expect_true "catalogue and report written" -- test -s "$OUT/bundles/catalog.sqlite" -a -s "$OUT/validate/index.html"
finish
