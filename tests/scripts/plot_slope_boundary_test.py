#!/usr/bin/python3
"""Test of scripts/plot-slope-boundary on made-up suite outputs: the table counts the runs that
arrived (goal reached within the time limit) and those that entered a forbidden region, per angle and
height; a run past its time limit is not counted as arrived; bad input (no such folder, a folder
without runs, a family without the ramp's parameters) exits 2 with one line. Exit code 0 when every
check holds, 1 otherwise (each failure printed)."""
import csv
import json
import os
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
SCRIPT = os.path.join(ROOT, "scripts", "plot-slope-boundary")
failures = []


def check(condition, what):
    if not condition:
        failures.append(what)
        print("FAILED: " + what)


def write_run(folder, goal, in_time, entered):
    os.makedirs(folder)
    criteria = [{"name": "goal_reached", "passed": goal}, {"name": "completion_time", "passed": in_time}]
    if entered is not None:
        criteria.append({"name": "never_enter:steep_face", "passed": not entered})
    with open(os.path.join(folder, "result.json"), "w") as f:
        json.dump({"criteria": criteria}, f)


def write_family(root, runs, columns=("angle_deg", "height_m")):
    family = os.path.join(root, "fam")
    os.makedirs(family)
    with open(os.path.join(family, "runs.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["draw", "seed", "settings", "expectation", "verdict", "scenario_file", "out", *columns])
        for i, (angle, height, goal, in_time, entered) in enumerate(runs):
            out = os.path.join(family, f"draw_{i:03d}", "seed_1")
            write_run(out, goal, in_time, entered)
            w.writerow([i, 1, "", "pass", "ok", "x.yaml", out, angle, height])
    return family


def run(*args):
    return subprocess.run([sys.executable, SCRIPT, *args], capture_output=True, text=True)


with tempfile.TemporaryDirectory() as tmp:
    suite = os.path.join(tmp, "suite")
    write_family(suite, [
        (26, 1, True, True, None), (26, 1, True, True, None), (26, 2, True, True, None),
        (28, 1, True, False, None),  # reached the goal after the time limit: not arrived
        (28, 2, True, True, None),
        (32, 1, False, False, True), (32, 1, False, False, False), (32, 2, False, False, False)])
    out = os.path.join(tmp, "fig", "boundary")
    r = run(suite, "--out", out)
    check(r.returncode == 0, f"exit 0 on a good suite output (got {r.returncode}: {r.stderr})")
    for ext in (".svg", ".png", ".csv"):
        check(os.path.isfile(out + ext), f"{ext} written")
    if os.path.isfile(out + ".csv"):
        rows = {(r["angle_deg"], r["height_m"]): r for r in csv.DictReader(open(out + ".csv"))}
        check(rows[("26", "1")]["runs"] == "2" and rows[("26", "1")]["arrived"] == "2", "26 deg 1 m: 2 of 2 arrived")
        check(rows[("28", "1")]["arrived"] == "0", "a late run is not counted as arrived")
        check(rows[("28", "2")]["arrived"] == "1", "28 deg 2 m: arrived")
        check(rows[("32", "1")]["entered_forbidden"] == "1" and rows[("32", "1")]["runs"] == "2",
              "32 deg 1 m: 1 of 2 entered the face")
        check(rows[("32", "2")]["entered_forbidden"] == "0", "32 deg 2 m: none entered")
        check(len(rows) == 6, f"one row per angle and height (got {len(rows)})")

    r = run(os.path.join(tmp, "missing"), "--out", os.path.join(tmp, "x"))
    check(r.returncode == 2 and "no such folder" in r.stderr, "a missing folder: exit 2")
    os.makedirs(os.path.join(tmp, "empty"))
    r = run(os.path.join(tmp, "empty"), "--out", os.path.join(tmp, "x"))
    check(r.returncode == 2 and "no runs.csv" in r.stderr, "a folder without runs: exit 2")
    other = os.path.join(tmp, "other")
    write_family(other, [(1.0, 2.0, True, True, None)], columns=("gap_m", "offset_m"))
    r = run(other, "--out", os.path.join(tmp, "x"))
    check(r.returncode == 2 and "not a ramp family" in r.stderr, "a family without angle_deg and height_m: exit 2")
    check(not os.path.exists(os.path.join(tmp, "x.csv")), "nothing written on bad input")

print("plot-slope-boundary test: " + ("OK" if not failures else f"{len(failures)} failed"))
sys.exit(1 if failures else 0)
