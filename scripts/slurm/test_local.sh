#!/bin/bash
# End-to-end test of the Slurm scripts on a real single-node Slurm cluster started here:
# installs Debian's slurm-wlm and munge if missing (apt-get, needs root), starts munged,
# slurmctld and slurmd on private sockets, ports and folders, submits submit.sh's job array
# of shards and its dependent merge job on a tiny scene, waits (bounded), and checks the
# merged image is bit-identical to a single render of the same settings. Every daemon it
# started is stopped and every file it wrote removed on exit.
#
#   scripts/slurm/test_local.sh [PPM_BINARY]     (default: target/release/ppm, built if missing)
#
# Exit status 0 when the merged image equals the single render, 1 otherwise.
set -euo pipefail

repo=$(cd "$(dirname "$0")/../.." && pwd)
here="$repo/scripts/slurm"
ppm=${1:-$repo/target/release/ppm}
timeout_s=${SLURM_TEST_TIMEOUT:-240}

log() { echo "[slurm test] $*" >&2; }
fail() {
    log "FAIL: $*"
    exit 1
}

[[ $(id -u) == 0 ]] || fail "must run as root (installs packages, starts slurmd)"
if ! command -v slurmctld >/dev/null || ! command -v munged >/dev/null; then
    log "installing slurm-wlm and munge"
    DEBIAN_FRONTEND=noninteractive apt-get install -y -q slurm-wlm munge >/dev/null ||
        { apt-get update -q >/dev/null && DEBIAN_FRONTEND=noninteractive apt-get install -y -q slurm-wlm munge >/dev/null; }
fi
if [[ ! -x $ppm ]]; then
    log "building $ppm"
    (cd "$repo" && cargo build --release -q -p ppm-cli)
fi
ppm=$(realpath "$ppm")

work=$(mktemp -d /tmp/ppm-slurm-test.XXXXXX)
chmod 755 "$work"
pids=()
cleanup() {
    local status=$?
    # scancel what may still run, then stop the daemons this script started, by pid.
    if [[ -f $work/slurm.conf ]]; then
        SLURM_CONF=$work/slurm.conf scancel --user=root >/dev/null 2>&1 || true
    fi
    for pid in "${pids[@]}"; do
        kill "$pid" 2>/dev/null || true
    done
    for pid in "${pids[@]}"; do
        for _ in $(seq 50); do
            kill -0 "$pid" 2>/dev/null || break
            sleep 0.1
        done
        kill -9 "$pid" 2>/dev/null || true
    done
    if ((status != 0)); then
        for f in "$work"/*.log "$work"/out/*.log; do
            [[ -f $f ]] && { log "--- $f"; tail -n 20 "$f" >&2; }
        done
    fi
    rm -rf "$work"
    exit "$status"
}
trap cleanup EXIT

host=$(hostname -s)
cpus=$(nproc)
mkdir -p "$work/state" "$work/spool" "$work/out" "$work/munge"

# munge: a private key, socket and daemon (the system's munged, if any, is left alone).
dd if=/dev/urandom of="$work/munge/munge.key" bs=1024 count=1 status=none
chmod 400 "$work/munge/munge.key"
munged --force --key-file="$work/munge/munge.key" --socket="$work/munge/munge.socket" \
    --pid-file="$work/munge/munged.pid" --log-file="$work/munge.log" \
    --seed-file="$work/munge/munged.seed" || fail "munged did not start"
for _ in $(seq 50); do [[ -s $work/munge/munged.pid ]] && break; sleep 0.1; done
pids+=("$(cat "$work/munge/munged.pid")")

# Ports away from the defaults (6817/6818), so a real Slurm on this machine is not disturbed.
port=$((20000 + RANDOM % 20000))
cat >"$work/slurm.conf" <<CONF
ClusterName=ppmtest
SlurmctldHost=$host
SlurmctldPort=$port
SlurmdPort=$((port + 1))
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$work/munge/munge.socket
StateSaveLocation=$work/state
SlurmdSpoolDir=$work/spool
SlurmctldPidFile=$work/slurmctld.pid
SlurmdPidFile=$work/slurmd.pid
SlurmctldLogFile=$work/slurmctld.log
SlurmdLogFile=$work/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
MpiDefault=none
ReturnToService=2
SchedulerType=sched/backfill
SchedulerParameters=sched_interval=1
MinJobAge=300
NodeName=$host CPUs=$cpus State=UNKNOWN
PartitionName=test Nodes=$host Default=YES MaxTime=INFINITE State=UP
CONF
export SLURM_CONF=$work/slurm.conf

log "starting slurmctld and slurmd (port $port)"
slurmctld -D -i -f "$SLURM_CONF" >>"$work/slurmctld.log" 2>&1 &
pids+=($!)
slurmd -D -f "$SLURM_CONF" >>"$work/slurmd.log" 2>&1 &
pids+=($!)
deadline=$((SECONDS + 60))
until sinfo -h -o '%T' 2>/dev/null | grep -qE '^(idle|mixed|allocated)'; do
    ((SECONDS < deadline)) || fail "the node did not come up within 60 s"
    sleep 1
done

# A tiny scene and render, so four shards and the merge take seconds.
scene="$repo/scenes/cornell_box.yml"
# --threads: a flag render_shard.sbatch also sets, which the user's flags replace.
flags=(--width 32 --height 32 --photons 2000 --seed 7 --threads 1)
iterations=12 shards=4
log "submitting $shards shards of $iterations iterations and the merge job"
(cd "$work" && PPM=$ppm "$here/submit.sh" "$scene" "$iterations" "$shards" out "${flags[@]}")

deadline=$((SECONDS + timeout_s))
while [[ -n $(squeue -h -o %i 2>/dev/null) ]]; do
    ((SECONDS < deadline)) || fail "jobs still queued or running after ${timeout_s} s: $(squeue -h)"
    sleep 1
done
[[ -f $work/out/merged.exr ]] || fail "the merge job wrote no image"

log "rendering the same $iterations iterations in one run"
"$ppm" "$scene" -n "$iterations" "${flags[@]}" -o "$work/single" 2>"$work/single.log"
"$ppm" compare "$work/out/merged.exr" "$work/single.exr" | tee "$work/compare.txt" >&2
cmp -s "$work/out/merged.png" "$work/single.png" || fail "the merged PNG differs from the single render's"
# Only an exact 0 prints as 0.000000e0 (any difference, however small, has an exponent).
grep -Eq '^RMSE:[[:space:]]+0\.000000e0$' "$work/compare.txt" ||
    fail "the merged EXR differs from the single render's"
log "PASS: the merged image of $shards Slurm shards equals the single render bit for bit"
