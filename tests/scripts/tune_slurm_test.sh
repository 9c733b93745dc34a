#!/usr/bin/env bash
# scripts/ovpc-tune --slurm on a real one-node Slurm cluster (tests/scripts/slurm_cluster.sh): a study
# of 3 trials on a short flat scenario is submitted as a job array of 2 workers and a finish job after
# them; when squeue shows none of them any more, the journal must hold 3 complete trials, each run by
# an array task, and the finish job must have written best.yaml (a preset ovpc loads), trials.csv and
# report.md with the validation.
#
#   tests/scripts/tune_slurm_test.sh OVPC SOURCE_DIR
# Exit: 0 passed, 1 failed, 77 skipped (no Slurm or munge installed: scripts/install-deps).
set -euo pipefail
ovpc=$(realpath "$1")
src=$(realpath "$2")
test_name=tune_slurm_test
source "$(dirname "$0")/slurm_cluster.sh"

cat >"$tmp/short.yaml" <<'YAML'
name: short_flat
time_limit_s: 8
terrain: {kind: flat, size_m: [40, 20]}
route: [[0, 0], [6, 0]]
criteria:
  goal: {x_m: 6.0, y_m: 0.0, radius_m: 1.0}
  no_collision: true
  max_time_s: 8
YAML
cat >"$tmp/space.yaml" <<'YAML'
parameters:
  - {key: navigator.follower.target_speed_mps, low: 0.6, high: 1.6}
YAML

"$src/scripts/ovpc-tune" --out "$tmp/out" --space "$tmp/space.yaml" --train "$tmp/short.yaml" --trials 3 \
  --startup-trials 1 --workers 2 --ovpc "$ovpc" --slurm --partition test --time 5 || fail "submitting failed"
ids=$(/usr/bin/python3 -c 'import json, sys
s = json.load(open(sys.argv[1]))["submissions"][-1]
print(s["array_job"], s["finish_job"])' "$tmp/out/slurm.json")
for _ in $(seq 600); do
  left=0
  for id in $ids; do
    if squeue -h -o %F | grep -qx "$id"; then left=1; fi
  done
  ((left == 0)) && break
  sleep 0.2
done
((left == 0)) || fail "jobs $ids still queued: $(squeue 2>&1)"

/usr/bin/python3 - "$tmp/out" <<'PY' || fail "the study is not what the workers should have made"
import json, os, sys, warnings
import optuna
optuna.logging.set_verbosity(optuna.logging.WARNING)
warnings.filterwarnings("ignore", category=optuna.exceptions.ExperimentalWarning)
out = sys.argv[1]
st = optuna.storages.JournalStorage(optuna.storages.JournalFileStorage(os.path.join(out, "journal.log")))
trials = optuna.load_study(study_name="ovpc-tune", storage=st).get_trials()
assert [t.state.name for t in trials] == ["COMPLETE"] * 3, [t.state.name for t in trials]
array = str(json.load(open(os.path.join(out, "slurm.json")))["submissions"][-1]["array_job"])
tasks = {t.user_attrs["worker"]["slurm_job"] for t in trials}
assert all(task.startswith(array + "_") for task in tasks), tasks
for name in ("best.yaml", "trials.csv", "history.svg", "report.md"):
    assert os.path.isfile(os.path.join(out, name)), name
assert "validation, best" in open(os.path.join(out, "report.md")).read()
PY
"$ovpc" run "$tmp/short.yaml" --preset "$tmp/out/best.yaml" --print-config >/dev/null || fail "best.yaml does not load"
echo "tune_slurm_test: passed"
