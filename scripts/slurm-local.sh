#!/bin/bash
# Proves the sharded Monte Carlo on a real Slurm: installs Slurm and munge from the
# distribution's packages when missing (Debian/Ubuntu, as root), runs a one-node cluster on
# localhost from a private configuration (nothing under /etc/slurm is written), submits a
# K-shard campaign and its merge job for each K in SHARD_COUNTS, waits, and compares the merged
# result with the single-machine run byte for byte. Prints the wall time per K. With SWEEP=1 the
# scene's [sweep] runs instead (separate --sweep), and the merged report folder is compared with
# the single-machine one file by file (diff -r).
#
# Usage: scripts/slurm-local.sh [SCENE] [RUNS] [SEED]
#   defaults: test-specs/paper-stack.toml 59 1; SHARD_COUNTS="1 2 4"; SATQUAL=path/to/satqual
#   (default: target/release/satqual under CARGO_TARGET_DIR or ./target). Exit 0 only when
#   every merged result is byte-identical.
set -euo pipefail

scene=${1:-test-specs/paper-stack.toml}
runs=${2:-59}
seed=${3:-1}
counts=${SHARD_COUNTS:-1 2 4}
repo=$(cd "$(dirname "$0")/.." && pwd)
cd "$repo"
satqual=${SATQUAL:-${CARGO_TARGET_DIR:-$repo/target}/release/satqual}
[ -x "$satqual" ] || { echo "no satqual binary at $satqual: cargo build --release" >&2; exit 2; }

if ! command -v sbatch >/dev/null || ! command -v munged >/dev/null; then
    [ "$(id -u)" = 0 ] || { echo "installing Slurm needs root" >&2; exit 2; }
    apt-get update
    DEBIAN_FRONTEND=noninteractive apt-get install -y slurm-wlm munge
fi

work=${SLURM_LOCAL_DIR:-/tmp/satqual-slurm-local}
mkdir -p "$work/state" "$work/spool" "$work/munge"
host=$(hostname -s)
cpus=$(nproc)
export SLURM_CONF=$work/slurm.conf
cat > "$SLURM_CONF" <<CONF
ClusterName=satqual-local
SlurmctldHost=$host
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
StateSaveLocation=$work/state
SlurmdSpoolDir=$work/spool
SlurmctldPidFile=$work/slurmctld.pid
SlurmdPidFile=$work/slurmd.pid
SlurmctldLogFile=$work/slurmctld.log
SlurmdLogFile=$work/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
ReturnToService=2
MpiDefault=none
NodeName=$host CPUs=$cpus State=UNKNOWN
PartitionName=local Nodes=$host Default=YES MaxTime=INFINITE State=UP
CONF

# Daemons this script starts, stopped on exit by their pid files.
started=()
cleanup() {
    for f in "${started[@]}"; do
        [ -f "$f" ] && kill "$(cat "$f")" 2>/dev/null || true
    done
}
trap cleanup EXIT

if ! pgrep -x munged >/dev/null; then
    mkdir -p /run/munge
    munged --force --pid-file="$work/munge/munged.pid"
    started+=("$work/munge/munged.pid")
fi
slurmctld -f "$SLURM_CONF" -i
started+=("$work/slurmctld.pid")
slurmd -f "$SLURM_CONF"
started+=("$work/slurmd.pid")
for _ in $(seq 60); do
    sinfo -h -o %T 2>/dev/null | grep -qE '^(idle|mixed|allocated)' && break
    sleep 1
done
sinfo

out=$work/results
mkdir -p "$out"
sweep=()
[ "${SWEEP:-0}" = 1 ] && sweep=(--sweep)
start=$(date +%s.%N)
if [ ${#sweep[@]} = 1 ]; then
    rm -rf "$out/single"
    "$satqual" separate "$scene" --sweep --monte-carlo "$runs" --seed "$seed" --out "$out/single" >/dev/null
else
    "$satqual" separate "$scene" --monte-carlo "$runs" --seed "$seed" --json > "$out/single.json"
fi
echo "single machine: $(echo "$(date +%s.%N) - $start" | bc) s"

status=0
for k in $counts; do
    dir=$out/campaign-$k
    rm -rf "$dir"
    "$satqual" campaign "$scene" --slurm --shards "$k" --monte-carlo "$runs" --seed "$seed" \
        --dir "$dir" >/dev/null
    start=$(date +%s.%N)
    array=$(sbatch --parsable "$dir/shards.sbatch")
    merge=$(sbatch --parsable --dependency=afterok:"${array%%;*}" "$dir/merge.sbatch")
    # Poll finely: sbatch --wait polls at growing intervals and would round the wall time up.
    while [ -n "$(squeue -h -j "${array%%;*},${merge%%;*}" 2>/dev/null)" ]; do sleep 0.2; done
    wall=$(echo "$(date +%s.%N) - $start" | bc)
    if { [ ${#sweep[@]} = 1 ] && diff -r "$dir/result" "$out/single" >/dev/null; } ||
       { [ ${#sweep[@]} = 0 ] && cmp -s "$dir/result.json" "$out/single.json"; }; then
        echo "K = $k: merged result byte-identical, wall $wall s"
    else
        echo "K = $k: MERGED RESULT DIFFERS (wall $wall s); logs in $dir/logs" >&2
        tail -n 5 "$dir"/logs/*.log >&2 || true
        status=1
    fi
done
exit $status
