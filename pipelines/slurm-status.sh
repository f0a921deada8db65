#!/usr/bin/env bash
# Snakemake --cluster-status for Slurm without an accounting database: the state of one job
# from `scontrol show job`, as Snakemake wants it: running | success | failed.
#   pipelines/slurm-status.sh JOBID
set -euo pipefail
if [ $# -ne 1 ] || [ -z "$1" ]; then  # was "$1: unbound variable"
    echo "usage: slurm-status.sh JOBID" >&2
    exit 2
fi
if ! info=$(scontrol show job "$1" 2>/dev/null); then
    # Forgotten by the controller (MinJobAge passed) or never known: say so, and let Snakemake
    # treat it as failed (it then checks the job's outputs and reruns it if they are missing).
    echo "slurm-status: job $1 unknown to scontrol" >&2
    echo failed
    exit 0
fi
state=$(grep -o 'JobState=[A-Z_]*' <<<"$info" | head -n 1 | cut -d= -f2)
case $state in
    COMPLETED) echo success ;;
    PENDING | CONFIGURING | RUNNING | COMPLETING | SUSPENDED | REQUEUED | RESIZING) echo running ;;
    *) echo failed ;;
esac
