#!/bin/bash
# A real single-node Slurm cluster from Debian's packages (slurm-wlm, munge), configured here in a
# temporary folder: munged, slurmctld and slurmd as this user (root), no systemd, no cgroups. It
# submits deploy/slurm/submit.sh's 4-task array of the queue and the dependent merge, waits for both,
# and checks the merged report against the same seeds run on one machine: every aggregate, rate and
# verdict equal. Exits 77 (ctest: skipped) with the reason when it cannot run here.
#   usage: tests/slurm/slurm_cluster_test.sh HRISIM_BINARY
set -euo pipefail
hrisim=$(realpath "$1")
source_dir=$(cd "$(dirname "$0")/../.." && pwd)
skip() { echo "SKIPPED: $*"; exit 77; }
[ "$(id -u)" = 0 ] || skip "the test cluster's daemons run as root (slurmd starts jobs as their user); run the tests as root"
for program in munged slurmctld slurmd sbatch squeue sinfo scontrol; do
  command -v "$program" >/dev/null || skip "$program is not installed (scripts/setup installs slurm-wlm and munge)"
done

dir=$(mktemp -d /tmp/hrisim-slurm.XXXXXX)
chmod 755 "$dir"
pids=()
mounted=()
cleanup() {
  local status=$?
  for pid in "${pids[@]}"; do kill "$pid" 2>/dev/null || true; done
  sleep 0.5
  for pid in "${pids[@]}"; do kill -9 "$pid" 2>/dev/null || true; done
  if [ $status -ne 0 ] && [ $status -ne 77 ]; then
    for log in "$dir"/*.log "$dir"/results/*.out; do [ -f "$log" ] && { echo "--- $log"; tail -n 30 "$log"; }; done
  fi
  for ((i = ${#mounted[@]} - 1; i >= 0; i--)); do umount "${mounted[$i]}" 2>/dev/null || true; done
  rm -rf "$dir"
}
trap cleanup EXIT

# slurmd 22.05 will not start without a cgroup file system, even with no cgroup plugin asked for.
# Where none is mounted (a chroot or container, as the fresh Debian chroot that checks a clean clone),
# the cgroup v1 hierarchies it looks for are mounted for the test and taken away at its end.
if ! mountpoint -q /sys/fs/cgroup; then
  mkdir -p /sys/fs/cgroup && mount -t tmpfs hrisim-test-cgroup /sys/fs/cgroup ||
    skip "slurmd needs a cgroup file system at /sys/fs/cgroup, and none is mounted nor can be here"
  mounted+=(/sys/fs/cgroup)
  for hierarchy in freezer cpuset memory devices pids none,name=systemd; do
    mountpoint=/sys/fs/cgroup/${hierarchy#none,name=}
    mkdir -p "$mountpoint" && mount -t cgroup -o "$hierarchy" cgroup "$mountpoint" ||
      skip "slurmd needs cgroup hierarchies, and $hierarchy cannot be mounted here"
    mounted+=("$mountpoint")
  done
  echo "mounted cgroup v1 hierarchies at /sys/fs/cgroup for slurmd (taken away at the end)"
fi

free_port() { python3 -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])'; }
node=$(hostname -s)

# munge: a key and a socket of our own.
dd if=/dev/urandom of="$dir/munge.key" bs=1024 count=1 status=none
chmod 400 "$dir/munge.key"
mkdir -p "$dir/munge"
chmod 755 "$dir/munge"
munged --force --foreground --key-file="$dir/munge.key" --socket="$dir/munge/socket" --pid-file="$dir/munge/pid" \
  --seed-file="$dir/munge/seed" >>"$dir/munged.log" 2>&1 &
pids+=($!)
for _ in $(seq 50); do [ -S "$dir/munge/socket" ] && break; sleep 0.1; done
[ -S "$dir/munge/socket" ] || skip "munged did not start here: $(tail -n 3 "$dir/munged.log" 2>/dev/null)"

mkdir -p "$dir/state" "$dir/spool" "$dir/results"
cat >"$dir/slurm.conf" <<CONF
ClusterName=hrisimtest
SlurmctldHost=$node(127.0.0.1)
SlurmctldPort=$(free_port)
SlurmdPort=$(free_port)
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$dir/munge/socket
StateSaveLocation=$dir/state
SlurmdSpoolDir=$dir/spool
SlurmctldPidFile=$dir/slurmctld.pid
SlurmdPidFile=$dir/slurmd.pid
SlurmctldLogFile=$dir/slurmctld.log
SlurmdLogFile=$dir/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
ReturnToService=2
MpiDefault=none
NodeName=$node NodeAddr=127.0.0.1 CPUs=$(nproc) State=UNKNOWN
PartitionName=test Nodes=$node Default=YES MaxTime=INFINITE State=UP
CONF
export SLURM_CONF="$dir/slurm.conf"
slurmctld -D -i -f "$SLURM_CONF" >>"$dir/slurmctld.log" 2>&1 &
pids+=($!)
slurmd -D -f "$SLURM_CONF" -N "$node" >>"$dir/slurmd.log" 2>&1 &
pids+=($!)
for _ in $(seq 100); do
  state=$(sinfo -h -N -o %T 2>/dev/null | head -n 1 || true)
  [ "$state" = idle ] && break
  sleep 0.2
done
[ "${state:-}" = idle ] || skip "the test cluster's node did not come up (state '${state:-none}'): $(tail -n 3 "$dir/slurmd.log")"
echo "cluster up: node $node idle ($(sinfo -h -o '%C') CPUs allocated/idle/other/total)"

# The run as shards on the cluster, and on one machine here.
export HRISIM="$hrisim" HRISIM_SCENARIOS="$source_dir/scenarios"
options=(--max-time 2 --gate 'collisions.max < 5' --name slurm-test)
submitted=$("$source_dir/deploy/slurm/submit.sh" 4 "$source_dir/scenarios/queue.json" 1-200 "$dir/results" "${options[@]}")
echo "$submitted"
for _ in $(seq 600); do
  [ -z "$(squeue -h -o %i)" ] && break
  sleep 0.5
done
[ -z "$(squeue -h -o %i)" ] || { echo "FAILED: jobs still queued after 5 min:"; squeue; exit 1; }
ls "$dir/results"
"$hrisim" run "$source_dir/scenarios/queue.json" --seeds 1-200 "${options[@]}" --jobs 2 >"$dir/one-machine.json" 2>/dev/null
python3 - "$dir/results/report.json" "$dir/one-machine.json" <<'CHECK'
import json, sys
merged, one = (json.load(open(path)) for path in sys.argv[1:3])
assert merged["config"]["sharding"]["merged"] == [1, 2, 3, 4], merged["config"]["sharding"]["merged"]
for key in ("aggregates", "rates", "verdict", "progress"):
    assert merged[key] == one[key], f"{key} differs:\n{merged[key]}\n{one[key]}"
assert [e["seed"] for e in merged["episodes"]] == list(range(1, 201))
print(f"merged report of 4 Slurm tasks equals the one-machine run: {len(merged['episodes'])} episodes, verdict passed={merged['verdict']['passed']}")
CHECK
grep -q '<testsuites tests="1" failures="0">' "$dir/results/report.xml"
echo PASSED
