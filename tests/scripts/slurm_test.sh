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
test_name=slurm_test
source "$(dirname "$0")/slurm_cluster.sh"

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
