#!/usr/bin/env bash
# scripts/ovpc-slurm on a real Slurm cluster of one node, started here in a temporary folder: munged
# with its own key and socket, slurmctld and slurmd with a minimal slurm.conf on free ports. A suite
# of one short scenario on two seeds is submitted as two shards and a merge job; when squeue shows
# none of them any more, the merged report must be the report of a local unsharded run of the same
# runs. Then one shard's summary.json is removed and --resume must run that shard alone and merge
# again. The daemons are stopped by their process ids, also when a step fails.
#
#   tests/scripts/slurm_test.sh OVPC SOURCE_DIR
# Exit: 0 passed, 1 failed, 77 skipped (no Slurm or munge installed: scripts/install-deps).
set -euo pipefail
ovpc=$(realpath "$1")
src=$(realpath "$2")
for tool in munged slurmctld slurmd sbatch squeue sinfo; do
  command -v "$tool" >/dev/null || { echo "slurm_test: $tool is not installed (scripts/install-deps); skipped"; exit 77; }
done

tmp=$(mktemp -d /tmp/ovpc_slurm_test.XXXXXX)
pids=()
cleanup() {
  local rc=$?
  for pid in "${pids[@]}"; do kill "$pid" 2>/dev/null || true; done
  for pid in "${pids[@]}"; do
    for _ in $(seq 50); do kill -0 "$pid" 2>/dev/null || break; sleep 0.1; done
    kill -9 "$pid" 2>/dev/null || true
  done
  if ((rc != 0)); then
    for log in "$tmp"/*.log "$tmp"/out/slurm/*.log; do [[ -f $log ]] && { echo "--- $log"; tail -20 "$log"; }; done
  fi
  rm -rf "$tmp"
  exit "$rc"
}
trap cleanup EXIT
fail() { echo "slurm_test: FAILED: $*" >&2; exit 1; }

# Two free TCP ports (bound to port 0 by the kernel, released again).
read -r ctld_port slurmd_port < <(python3 -c '
import socket
s = [socket.socket() for _ in range(2)]
for x in s: x.bind(("127.0.0.1", 0))
print(*[x.getsockname()[1] for x in s])')
host=$(hostname -s)
user=$(id -un)

mkdir -p "$tmp/state" "$tmp/spool" "$tmp/munge"
chmod 700 "$tmp/munge"
dd if=/dev/urandom of="$tmp/munge/munge.key" bs=1024 count=1 status=none
chmod 400 "$tmp/munge/munge.key"
munged --foreground --force --key-file="$tmp/munge/munge.key" --socket="$tmp/munge/munge.socket" \
  --pid-file="$tmp/munge/munged.pid" --seed-file="$tmp/munge/munged.seed" >"$tmp/munged.log" 2>&1 &
pids+=($!)
for _ in $(seq 50); do [[ -S $tmp/munge/munge.socket ]] && break; sleep 0.1; done
[[ -S $tmp/munge/munge.socket ]] || fail "munged did not start"

# The node as slurmd sees it (CPUs, memory), so that it is not drained for a mismatch.
node=$(slurmd -C | head -1 | sed "s/^NodeName=[^ ]*/NodeName=$host/")
cat >"$tmp/slurm.conf" <<EOF
ClusterName=ovpctest
SlurmctldHost=$host(127.0.0.1)
SlurmctldPort=$ctld_port
SlurmdPort=$slurmd_port
SlurmUser=$user
SlurmdUser=$user
AuthType=auth/munge
AuthInfo=socket=$tmp/munge/munge.socket
CredType=cred/munge
StateSaveLocation=$tmp/state
SlurmdSpoolDir=$tmp/spool
SlurmctldPidFile=$tmp/slurmctld.pid
SlurmdPidFile=$tmp/slurmd.pid
SlurmctldLogFile=$tmp/slurmctld.log
SlurmdLogFile=$tmp/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
MpiDefault=none
ReturnToService=2
SchedulerParameters=sched_interval=1
$node NodeAddr=127.0.0.1 State=UNKNOWN
PartitionName=test Nodes=$host Default=YES MaxTime=INFINITE State=UP
EOF
export SLURM_CONF=$tmp/slurm.conf
slurmctld -D -c -f "$SLURM_CONF" >"$tmp/slurmctld.out" 2>&1 &
pids+=($!)
slurmd -D -N "$host" -f "$SLURM_CONF" >"$tmp/slurmd.out" 2>&1 &
pids+=($!)
for _ in $(seq 150); do
  [[ $(sinfo -h -o %T 2>/dev/null) == idle ]] && break
  sleep 0.2
done
[[ $(sinfo -h -o %T 2>/dev/null) == idle ]] || fail "the node is not idle: $(sinfo -h -o '%T %E' 2>&1)"

cat >"$tmp/short.yaml" <<'EOF'
name: short_flat
time_limit_s: 8
terrain: {kind: flat, size_m: [40, 20]}
route: [[0, 0], [6, 0]]
criteria:
  goal: {x_m: 6.0, y_m: 0.0, radius_m: 1.0}
  no_collision: true
  max_time_s: 8
EOF

# Waits until squeue lists none of the jobs slurm.json records (at most 90 s).
wait_for_jobs() {
  local ids
  ids=$(python3 -c 'import json, sys
s = json.load(open(sys.argv[1]))["submissions"][-1]
print(" ".join(str(j) for j in (s.get("array_job"), s.get("merge_job")) if j))' "$tmp/out/slurm.json")
  for _ in $(seq 450); do
    local left=0
    for id in $ids; do
      if squeue -h -o %F | grep -qx "$id"; then left=1; fi
    done
    ((left == 0)) && return 0
    sleep 0.2
  done
  fail "jobs $ids still queued: $(squeue 2>&1)"
}

# The merged report against a local unsharded run: the same testcases and verdicts.
check_report() {
  python3 - "$tmp/local" "$tmp/out" <<'EOF'
import json, re, sys
local, merged = sys.argv[1], sys.argv[2]
# without the wall-clock times and the attachments (a merged report's are in the shards' folders)
def cases(folder):
    text = re.sub(r' time="[^"]*"', "", open(f"{folder}/junit.xml").read())
    return re.sub(r"<system-out>[^<]*</system-out>", "", text)
def verdicts(folder):
    s = json.load(open(f"{folder}/summary.json"))
    return [(r["index"], r["scenario"], r["seed"], r["passed"], r["exit_code"]) for r in s["runs"]]
assert cases(local) == cases(merged), "junit.xml testcases differ"
assert verdicts(local) == verdicts(merged), (verdicts(local), verdicts(merged))
assert len(verdicts(merged)) == 2
EOF
}

"$ovpc" suite "$tmp/short.yaml" --seeds 2 --jobs 1 --out "$tmp/local" >"$tmp/local.log" 2>&1 || fail "the local suite failed"
"$src/scripts/ovpc-slurm" --out "$tmp/out" --shards 2 --partition test --time 5 --cpus-per-task 1 --ovpc "$ovpc" \
  -- "$tmp/short.yaml" --seeds 2 || fail "submitting failed"
wait_for_jobs
[[ -f $tmp/out/summary.json ]] || fail "no merged summary.json"
check_report || fail "the merged report is not the local one"
for k in 1 2; do
  [[ $(python3 -c 'import json, sys; print(len(json.load(open(sys.argv[1]))["runs"]))' "$tmp/out/shard_$k/summary.json") == 1 ]] ||
    fail "shard $k does not hold one run"
done

# One shard lost: --resume runs it alone and merges again.
rm "$tmp/out/shard_2/summary.json" "$tmp/out/summary.json"
"$src/scripts/ovpc-slurm" --out "$tmp/out" --resume || fail "resuming failed"
[[ $(python3 -c 'import json, sys; print(json.load(open(sys.argv[1]))["submissions"][-1]["shards"])' "$tmp/out/slurm.json") == "[2]" ]] ||
  fail "resume did not submit shard 2 alone: $(cat "$tmp/out/slurm.json")"
wait_for_jobs
check_report || fail "the report merged after --resume is not the local one"
echo "slurm_test: passed"
