#!/usr/bin/python3
"""Test of scripts/ovpc-tune with the real ovpc on a short flat scenario (6 m straight ahead, one run
seed): a study of 2 trials (the first the base preset's values), then SIGINT while the third trial's
suite runs (exit 130; the trial is marked cut off and its values go back into the queue), then the
same command again with --trials 3 resumes it to 3 complete trials in the journal, among them the
cut-off trial's values. The best preset loads with `ovpc run --preset best.yaml --print-config`;
trials.csv, history.svg/png, report.md (with the validation on seed 2) are written; another space
for the same folder, and bad space files, are refused with exit 2 and one line naming the file and
line.

  tests/scripts/tune_test.py OVPC SOURCE_DIR
Needs Debian's python3-optuna (scripts/install-deps). Exit code 0 when every check holds, 1 otherwise."""
import csv
import os
import signal
import subprocess
import sys
import tempfile
import time
import warnings

OVPC, SRC = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
TUNE = os.path.join(SRC, "scripts", "ovpc-tune")
failures = []

SHORT = """name: short_flat
time_limit_s: 8
terrain: {kind: flat, size_m: [40, 20]}
route: [[0, 0], [6, 0]]
criteria:
  goal: {x_m: 6.0, y_m: 0.0, radius_m: 1.0}
  no_collision: true
  max_time_s: 8
"""
SPACE = """parameters:
  - {key: navigator.follower.target_speed_mps, low: 0.6, high: 1.6}
  - {key: navigator.replan.period_s, choices: [0.5, 1, 2]}
"""


def check(condition, what):
    if not condition:
        failures.append(what)
        print("FAILED: " + what, flush=True)


def journal_trials(study_dir):
    import optuna
    optuna.logging.set_verbosity(optuna.logging.WARNING)
    warnings.filterwarnings("ignore", category=optuna.exceptions.ExperimentalWarning)
    path = os.path.join(study_dir, "journal.log")
    st = optuna.storages.JournalStorage(optuna.storages.JournalFileStorage(path))
    return optuna.load_study(study_name="ovpc-tune", storage=st).get_trials(deepcopy=False)


def states(trials):
    return [t.state.name for t in trials]


def main():
    try:
        import optuna  # noqa: F401
    except ImportError:
        print("tune_test: python3-optuna is not installed (scripts/install-deps)")
        return 1
    with tempfile.TemporaryDirectory(prefix="ovpc_tune_test_") as tmp:
        short, space, study = (os.path.join(tmp, n) for n in ("short.yaml", "space.yaml", "study"))
        with open(short, "w") as f:
            f.write(SHORT)
        with open(space, "w") as f:
            f.write(SPACE)
        base = [TUNE, "--out", study, "--space", space, "--train", short, "--seeds", "1", "--ovpc", OVPC,
                "--startup-trials", "1"]

        def tune(trials, **kw):
            return subprocess.run(base + ["--trials", str(trials)], capture_output=True, text=True, **kw)

        # 1. Two trials, then the end: best.yaml, the table, the plot, the validation.
        r = tune(2)
        check(r.returncode == 0, f"a study of 2 trials: exit {r.returncode}: {r.stderr[-2000:]}")
        trials = journal_trials(study)
        check(states(trials) == ["COMPLETE"] * 2, f"2 complete trials in the journal, not {states(trials)}")
        check(trials and trials[0].user_attrs.get("baseline") and trials[0].params ==
              {"navigator.follower.target_speed_mps": 1.0, "navigator.replan.period_s": 1},
              "the first trial is the base preset's values")
        for name in ("best.yaml", "trials.csv", "history.svg", "history.png", "report.md", "report.json"):
            check(os.path.isfile(os.path.join(study, name)), f"{name} is written")

        # 2. Interrupted while the third trial's suite runs: exit 130, the trial is cut off.
        proc = subprocess.Popen(base + ["--trials", "3"], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        log = os.path.join(study, "trials", "trial_0002", "suite.log")
        deadline = time.time() + 30
        while not os.path.isfile(log) and time.time() < deadline and proc.poll() is None:
            time.sleep(0.05)
        time.sleep(0.05)  # the suite has started (a run of the short scenario takes a second or more)
        proc.send_signal(signal.SIGINT)
        out, err = proc.communicate(timeout=60)
        check(proc.returncode == 130, f"SIGINT during a trial: exit 130, not {proc.returncode}: {err[-2000:]}")
        trials = journal_trials(study)
        cut = [t for t in trials if t.user_attrs.get("interrupted")]
        waiting = [t for t in trials if t.state.name == "WAITING"]
        check(len(cut) == 1 and cut[0].state.name == "FAIL", f"one trial cut off and failed: {states(trials)}")
        check(len(waiting) == 1 and cut and waiting[0].system_attrs.get("fixed_params") == cut[0].params,
              "the cut-off trial's values are queued again")

        # 3. The same command resumes the study to 3 complete trials.
        r = tune(3)
        check(r.returncode == 0, f"resuming: exit {r.returncode}: {r.stderr[-2000:]}")
        trials = journal_trials(study)
        complete = [t for t in trials if t.state.name == "COMPLETE"]
        check(len(complete) == 3, f"3 complete trials after the resume, not {states(trials)}")
        check(cut and any(t.params == cut[0].params for t in complete), "the cut-off trial's values ran again")
        with open(os.path.join(study, "trials.csv")) as f:
            rows = list(csv.DictReader(f))
        check(len(rows) == 4 and sum(r["state"] == "complete" for r in rows) == 3,
              f"trials.csv: 3 complete rows and the cut-off one, not {[r['state'] for r in rows]}")
        check(all(r["passed"] == "1" and r["must_pass"] == "1" for r in rows if r["state"] == "complete"),
              "every complete trial passed the short scenario")
        with open(os.path.join(study, "report.md")) as f:
            report = f.read()
        check("validation, best" in report and "validation, base" in report and "run seeds 2-2" in report,
              f"report.md has the validation on seed 2:\n{report}")

        # 4. The best preset loads, and holds the best trial's values.
        r = subprocess.run([OVPC, "run", short, "--preset", os.path.join(study, "best.yaml"), "--print-config"],
                           capture_output=True, text=True)
        check(r.returncode == 0, f"ovpc run --preset best.yaml --print-config: exit {r.returncode}: {r.stderr}")
        best = min(complete, key=lambda t: (t.value, t.number)) if complete else None
        if best:
            speed = f"{best.params['navigator.follower.target_speed_mps']:.6g}"
            check(f"target_speed_mps: {speed}" in r.stdout, f"best.yaml's target speed is the best trial's ({speed})")

        # 5. Refusals: another space for this study; bad space files (one line: file, line, problem).
        other = os.path.join(tmp, "other.yaml")
        with open(other, "w") as f:
            f.write(SPACE.replace("0.6", "0.7"))
        r = subprocess.run([a if a != space else other for a in base] + ["--trials", "4"], capture_output=True, text=True)
        check(r.returncode == 2 and "other settings" in r.stderr, f"another space for the study: exit 2, not {r.returncode}: {r.stderr}")
        bad = {
            "unknown key": ("parameters:\n  - {key: navigator.follower.target_speed, low: 1, high: 2}\n", ":2:", "target_speed_mps"),
            "low above high": ("parameters:\n  - key: navigator.follower.target_speed_mps\n    low: 2\n    high: 1\n", ":4:", "below"),
            "not YAML": ("parameters: [\n  {key: a\n", ":", "not YAML"),
            "log from 0": ("parameters:\n  - {key: navigator.replan.period_s, low: 0, high: 2, log: true}\n", ":2:", "log"),
            "value ovpc refuses": ("parameters:\n\n  - {key: navigator.follower.target_speed_mps, low: -1, high: 2}\n", ":3:", "ovpc refuses"),
        }
        for what, (text, line, word) in bad.items():
            path = os.path.join(tmp, "bad.yaml")
            with open(path, "w") as f:
                f.write(text)
            r = subprocess.run([TUNE, "--out", os.path.join(tmp, "bad_study"), "--space", path, "--train", short,
                                "--trials", "1", "--ovpc", OVPC], capture_output=True, text=True)
            lines = r.stderr.strip().splitlines()
            check(r.returncode == 2 and len(lines) == 1 and lines[0].startswith(f"ovpc-tune: {path}{line}") and word in lines[0],
                  f"{what}: exit 2 and one line naming {path}{line} and '{word}', not {r.returncode}: {r.stderr!r}")
            check(not os.path.exists(os.path.join(tmp, "bad_study", "journal.log")), f"{what}: no study is made")
    print("tune_test: " + ("passed" if not failures else f"{len(failures)} check(s) failed"))
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
