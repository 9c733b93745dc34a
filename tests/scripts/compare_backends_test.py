#!/usr/bin/env python3
"""Test of scripts/compare-backends' report (--report-only) on made-up suite outputs: the tables hold
only the seeds finished for every backend, count passes, times to goal and family expectations, and
draw the roof-height figure. Exit code 0 when every check holds, 1 otherwise (each failure printed)."""
import json
import os
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
SCRIPT = os.path.join(ROOT, "scripts", "compare-backends")
failures = []


def check(condition, what):
    if not condition:
        failures.append(what)
        print("FAILED: " + what)


def suite_run(scenario, passed, time_s):
    criteria = [{"name": "goal_reached", "passed": passed}]
    return {"scenario": scenario, "passed": passed, "out": "/nonexistent",
            "result": {"passed": passed, "sim_time_s": time_s, "criteria": criteria, "collision_steps": 0}}


def family_run(roof_m, passed, verdict):
    run = suite_run("carport_height_000", passed, 30.0)
    run["family"] = {"family": "carport_height", "verdict": verdict, "values": {"roof_height_m": roof_m}}
    return run


def write(out, m, seed, runs):
    folder = os.path.join(out, m, f"seed_{seed}")
    os.makedirs(folder)
    with open(os.path.join(folder, "summary.json"), "w") as f:
        json.dump({"runs": runs}, f)


with tempfile.TemporaryDirectory() as out:
    # Seed 1 finished for all three backends, seed 2 for ovpc only (a comparison stopped part-way).
    write(out, "ovpc", 1, [suite_run("underpass_2p5", True, 25.0), family_run(2.5, True, "ok")])
    write(out, "ovpc", 2, [suite_run("underpass_2p5", False, 60.0), family_run(2.5, False, "violated")])
    write(out, "octomap", 1, [suite_run("underpass_2p5", True, 27.0), family_run(2.5, True, "ok")])
    write(out, "elevation", 1, [suite_run("underpass_2p5", False, 60.0), family_run(2.5, True, "ok")])
    proc = subprocess.run([sys.executable, SCRIPT, "--report-only", "--out", out], capture_output=True, text=True)
    check(proc.returncode == 0, f"exit code 0, got {proc.returncode}: {proc.stderr}")
    with open(os.path.join(out, "comparison.json")) as f:
        data = json.load(f)
    check(data["seeds"] == [1], f"seeds [1] (seed 2 is not finished for every backend), got {data['seeds']}")
    scenes = data["suite_scenarios"]["underpass_2p5"]
    check(scenes["ovpc"]["runs"] == 1 and scenes["ovpc"]["passed"] == 1, f"ovpc 1/1 on seed 1, got {scenes['ovpc']}")
    check(scenes["elevation"]["passed"] == 0, f"elevation 0 passed, got {scenes['elevation']}")
    check(abs(scenes["octomap"]["mean_time_to_goal_s"] - 27.0) < 1e-9, f"octomap 27 s to goal, got {scenes['octomap']}")
    family = data["groups"]["carport_height"]["ovpc"]
    check(family["expectation_held"] == 1 and family["expectation_counted"] == 1, f"ovpc family 1/1 held, got {family}")
    with open(os.path.join(out, "comparison.md")) as f:
        text = f.read()
    check("left out, finished for some backends only: 2" in text, "the left-out seed is named in comparison.md")
    check(os.path.exists(os.path.join(out, "pass_rate_roof_height.svg")), "the roof-height figure is written")

    # Another program resuming into the same folder is refused before any run (exit code 2).
    with open(os.path.join(out, "manifest.json"), "w") as f:
        json.dump({"ovpc_sha256": "0" * 64}, f)
    proc = subprocess.run([sys.executable, SCRIPT, "--out", out, "--ovpc", sys.executable, "--seeds", "1"],
                          capture_output=True, text=True)
    check(proc.returncode == 2 and "manifest.json" in proc.stderr,
          f"a resume with another program is refused with exit code 2, got {proc.returncode}: {proc.stderr}")

print("compare_backends_test: " + ("all checks hold" if not failures else f"{len(failures)} failed"))
sys.exit(1 if failures else 0)
