#!/usr/bin/env bash
# A real one-node Slurm on localhost running `skelseg batch` as a 4-task job
# array (issue 10). Usage: tests/cluster/test_slurm_array.sh SKELSEG_BINARY
#
# Writes its own slurm.conf and munge key in a temporary folder, starts
# munged, slurmctld and slurmd as root (each with its own socket, ports,
# state and log files, so nothing of a system installation is touched),
# submits the array over 16 generated shapes, cancels one task with scancel
# while it runs, waits, resubmits the array, waits, and checks:
#   every shape done exactly once (the markers written by the first
#   submission are unchanged; the second one segmented only the rest), and
#   `skelseg batch --merge` reports nothing missing.
# The daemons it started are stopped on exit (trap). Exit 77 (ctest SKIP)
# when Slurm or munge are not installed and cannot be, or when not root.
set -euo pipefail

skelseg="$(realpath "${1:?usage: $0 SKELSEG_BINARY}")"
skip() { echo "SKIP: $*"; exit 77; }

[ "$(id -u)" -eq 0 ] || skip "the daemons run as root here; run as root (CI does)"
if ! command -v slurmctld >/dev/null || ! command -v munged >/dev/null; then
  echo "slurm-wlm/munge missing; trying apt-get install (tools/install-deps.sh lists them)"
  DEBIAN_FRONTEND=noninteractive timeout 600 apt-get install -y -qq slurm-wlm munge >/dev/null 2>&1 ||
    skip "slurm-wlm and munge are not installed and could not be installed"
fi

work="$(mktemp -d /tmp/skelseg-slurm.XXXXXX)"
chmod 700 "$work"
pids=()
cleanup() {
  local status=$?
  # Stop only what this script started, newest first.
  for ((i = ${#pids[@]} - 1; i >= 0; i--)); do kill "${pids[i]}" 2>/dev/null || true; done
  for pid in "${pids[@]}"; do
    for _ in $(seq 50); do kill -0 "$pid" 2>/dev/null || break; sleep 0.1; done
    kill -9 "$pid" 2>/dev/null || true
  done
  if [ $status -ne 0 ] && [ $status -ne 77 ]; then
    echo "--- logs (test failed) ---"
    tail -n 30 "$work"/*.log 2>/dev/null || true
    tail -n 30 "$work"/out-*.txt 2>/dev/null || true
  fi
  rm -rf "$work"
}
trap cleanup EXIT

free_port() { /usr/bin/python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1",0)); print(s.getsockname()[1])'; }

# --- munge: our own key, socket and files -------------------------------------
mkdir -p "$work/munge"
chmod 700 "$work/munge"
dd if=/dev/urandom of="$work/munge/munge.key" bs=1024 count=1 status=none
chmod 400 "$work/munge/munge.key"
munged --force --foreground --key-file="$work/munge/munge.key" \
  --socket="$work/munge/munge.socket" --pid-file="$work/munge/munged.pid" \
  --log-file="$work/munged.log" --seed-file="$work/munge/munge.seed" >"$work/munged.out" 2>&1 &
pids+=($!)
for _ in $(seq 50); do [ -S "$work/munge/munge.socket" ] && break; sleep 0.1; done
[ -S "$work/munge/munge.socket" ] || { echo "munged did not start"; exit 1; }

# --- slurm.conf ---------------------------------------------------------------
mkdir -p "$work/state" "$work/spool"
export SLURM_CONF="$work/slurm.conf"
cat > "$SLURM_CONF" <<CONF
ClusterName=skelsegtest
SlurmctldHost=localhost
SlurmUser=root
SlurmdUser=root
SlurmctldPort=$(free_port)
SlurmdPort=$(free_port)
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
JobCompType=jobcomp/none
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
SchedulerType=sched/builtin
MpiDefault=none
MailProg=/bin/true
ReturnToService=2
SlurmdTimeout=30
InactiveLimit=0
KillWait=5
NodeName=localhost CPUs=2 RealMemory=1000 State=UNKNOWN
PartitionName=debug Nodes=localhost Default=YES MaxTime=INFINITE State=UP
CONF

slurmctld -D -i -f "$SLURM_CONF" >"$work/slurmctld.out" 2>&1 &
pids+=($!)
slurmd -D -N localhost -f "$SLURM_CONF" >"$work/slurmd.out" 2>&1 &
pids+=($!)
for _ in $(seq 100); do
  state="$(sinfo -h -N -o '%T' 2>/dev/null | head -n1 || true)"
  [ "$state" = "idle" ] && break
  sleep 0.2
done
[ "$state" = "idle" ] || { echo "the node did not come up (state '$state')"; exit 1; }
echo "slurm up: $(sinfo -h -o '%P %a %D %T')"

# --- inputs: 16 generated shapes ----------------------------------------------
mkdir -p "$work/in"
shapes=(disc-limbs y-arms t-body slab box-tubes torus-limb figure capsule cylinder sphere box torus)
: > "$work/list.txt"
for i in $(seq 0 15); do
  shape="${shapes[$((i % ${#shapes[@]}))]}"
  "$skelseg" generate "$shape" -o "$work/in/$shape-$i.nrrd" --size $((28 + 2 * (i % 4))) --pose 0
  echo "in/$shape-$i.nrrd" >> "$work/list.txt"
done
out="$work/out"

cat > "$work/array.sh" <<JOB
#!/bin/bash
#SBATCH --array=0-3
#SBATCH --cpus-per-task=1
#SBATCH --output=$work/out-%A_%a.txt
exec "$skelseg" batch "$work/list.txt" -o "$out" --threads 1
JOB

wait_for_job() {  # job id: until no task of it is left in the queue
  for _ in $(seq 600); do
    [ -z "$(squeue -h -j "$1" 2>/dev/null)" ] && return 0
    sleep 0.2
  done
  echo "job $1 did not finish in time"; squeue; return 1
}

# --- first submission; cancel task 1 while it runs ----------------------------
job="$(sbatch --parsable "$work/array.sh")"
echo "submitted array job $job"
cancelled=""
for _ in $(seq 600); do
  if [ "$(squeue -h -j "${job}_1" -o '%T' 2>/dev/null)" = "RUNNING" ] &&
    [ -n "$(ls "$out"/*/done.json 2>/dev/null)" ]; then
    scancel "${job}_1"
    cancelled=yes
    break
  fi
  [ -z "$(squeue -h -j "$job" 2>/dev/null)" ] && break
  sleep 0.1
done
[ -n "$cancelled" ] || { echo "task ${job}_1 finished before it could be cancelled"; exit 1; }
echo "cancelled ${job}_1"
wait_for_job "$job"

declare -A before
for marker in "$out"/*/done.json; do before["$marker"]="$(md5sum < "$marker")"; done
total=$(wc -l < "$work/list.txt")
echo "after the first submission: ${#before[@]} of $total done"
[ "${#before[@]}" -lt "$total" ] || { echo "the cancelled task lost nothing: scancel came too late"; exit 1; }
if "$skelseg" batch --merge "$out" > /dev/null 2>&1; then
  echo "--merge reported nothing missing after a cancelled task"; exit 1
fi

# --- resubmit the array -------------------------------------------------------
job2="$(sbatch --parsable "$work/array.sh")"
echo "resubmitted as $job2"
wait_for_job "$job2"

fail=0
for f in "$work/in"/*.nrrd; do
  name="$(basename "$f" .nrrd)"
  [ -f "$out/$name/done.json" ] || { echo "not done: $name"; fail=1; }
done
for marker in "${!before[@]}"; do
  [ "$(md5sum < "$marker")" = "${before[$marker]}" ] || { echo "redone although done: $marker"; fail=1; }
done
# The resubmission segmented exactly the shapes that were missing.
redone=$(/usr/bin/python3 - "$out" <<'PY'
import json, sys, glob
n = 0
for f in glob.glob(sys.argv[1] + "/summary.shard-*-of-4.json"):
    n += sum(1 for e in json.load(open(f))["entries"] if e["status"] == "done")
print(n)
PY
)
echo "the resubmission segmented $redone shapes; $((total - ${#before[@]})) were missing"
[ "$redone" -eq $((total - ${#before[@]})) ] || fail=1
leftovers="$(find "$out" -name '.skelseg-staging-*' -o -name '.*.tmp-*')"
[ -z "$leftovers" ] || { echo "stray files: $leftovers"; fail=1; }

"$skelseg" batch --merge "$out" || { echo "--merge reports missing inputs"; fail=1; }
[ $fail -eq 0 ] && echo "PASS: $total shapes done once over 2 submissions, merge complete"
exit $fail
