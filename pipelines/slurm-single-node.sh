#!/usr/bin/env bash
# slurm-single-node: a one-node Slurm cluster on this machine for as long as a command runs:
# munge, slurmctld and one slurmd on localhost (Debian's slurm-wlm 22.05 and munge), with its
# configuration, state, spool, pid and log files in a temporary folder, torn down afterwards.
#   pipelines/slurm-single-node.sh COMMAND [ARGS...]      (as root; SLURM_CONF is exported)
# Exits 77 when the daemons cannot start here (not root, packages missing, no node idle within
# 60 s), so a test can report a skip; otherwise with the command's exit code.
# Example: pipelines/slurm-single-node.sh pipelines/bake-catalog.sh --slurm -j 4 samples/catalog out/slurm
set -euo pipefail
# shellcheck source=pipelines/lib.sh
. "$(dirname "$0")/lib.sh"
usage_unless $# 1 - "COMMAND [ARGS...]"
cannot() {
    echo "slurm-single-node: cannot start Slurm here: $*" >&2
    exit 77
}
[ "$(id -u)" -eq 0 ] || cannot "needs root (the daemons run as SlurmUser=root)"
for b in munged munge slurmctld slurmd sinfo sbatch scontrol; do
    command -v "$b" >/dev/null || cannot "$b not found (make deps: munge, slurm-wlm)"
done
S=$(mktemp -d /tmp/inlight-slurm.XXXXXX)
started_munge=0
# shellcheck disable=SC2317  # called by the EXIT trap
cleanup() {
    local f
    for f in "$S/slurmd.pid" "$S/slurmctld.pid"; do
        if [ -f "$f" ]; then kill "$(cat "$f")" 2>/dev/null || true; fi
    done
    if [ "$started_munge" -eq 1 ] && [ -f "$S/munged.pid" ]; then
        kill "$(cat "$S/munged.pid")" 2>/dev/null || true
    fi
    sleep 1
    rm -rf "$S"
}
trap cleanup EXIT

# munge: the key must exist, owned by munge, mode 400; start munged unless one answers already.
if [ ! -f /etc/munge/munge.key ]; then
    mkdir -p /etc/munge
    dd if=/dev/urandom of=/etc/munge/munge.key bs=128 count=1 status=none
    chown munge:munge /etc/munge/munge.key
    chmod 400 /etc/munge/munge.key
fi
mkdir -p /run/munge
chown munge:munge /run/munge 2>/dev/null || true
if ! munge -n </dev/null >/dev/null 2>&1; then
    munged --force --pid-file="$S/munged.pid" 2>"$S/munged.err" || cannot "munged: $(cat "$S/munged.err")"
    started_munge=1
fi

host=$(hostname -s)
port=$((20000 + RANDOM % 20000))
mkdir -p "$S/state" "$S/spool"
cat >"$S/slurm.conf" <<CONF
ClusterName=inlight
SlurmctldHost=$host(127.0.0.1)
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
MpiDefault=none
ReturnToService=2
MinJobAge=86400
StateSaveLocation=$S/state
SlurmdSpoolDir=$S/spool
SlurmctldPidFile=$S/slurmctld.pid
SlurmdPidFile=$S/slurmd.pid
SlurmctldLogFile=$S/slurmctld.log
SlurmdLogFile=$S/slurmd.log
SlurmctldPort=$port
SlurmdPort=$((port + 1))
NodeName=$host NodeAddr=127.0.0.1 NodeHostname=$host CPUs=$(nproc) State=UNKNOWN
PartitionName=inlight Nodes=$host Default=YES MaxTime=INFINITE State=UP
CONF
export SLURM_CONF="$S/slurm.conf"
slurmctld -f "$SLURM_CONF" || cannot "slurmctld did not start: $(tail -n 3 "$S/slurmctld.log" 2>/dev/null)"
slurmd -f "$SLURM_CONF" || cannot "slurmd did not start: $(tail -n 3 "$S/slurmd.log" 2>/dev/null)"
# "idle" exactly: "idle*" is a node the controller has not heard from (slurmd did not register).
for _ in $(seq 1 120); do
    sinfo -h -o '%t' 2>/dev/null | grep -qx 'idle' && break
    sleep 0.5
done
sinfo -h -o '%t' 2>/dev/null | grep -qx 'idle' ||
    cannot "no idle node after 60 s: $(tail -n 3 "$S/slurmctld.log" "$S/slurmd.log" 2>/dev/null)"
echo "slurm-single-node: $(sinfo -h -o '%P %D node %N, %c CPUs, %t') (state in $S)" >&2
set +e
"$@"
code=$?
set -e
exit "$code"
