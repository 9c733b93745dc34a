#!/usr/bin/env python3
"""Test of scripts/compare-backends with a stand-in for `ovpc suite` that writes made-up runs: a
finished suite leaves a record, the report reads the records alone, the tables hold only the seeds
finished for every backend, count passes, times to goal, family expectations and failures by their
diagnosis, count runs under the roof from the paths (a record without them: unknown), and draw the
roof-height figure; a resume keeps the records and refuses another program or edited scenarios. Exit code 0 when every check holds, 1 otherwise (each failure printed)."""
import gzip
import json
import os
import shutil
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


# A stand-in for `ovpc suite`: writes made-up runs for its --map and --first-seed into --out
# (summary.json, and a cycles.csv per run), or stops without a summary, as a suite cut off part-way.
FAKE_OVPC = r'''
import json, os, sys
a = sys.argv
m, seed, out = a[a.index("--map") + 1], int(a[a.index("--first-seed") + 1]), a[a.index("--out") + 1]
with open(os.path.join(os.path.dirname(os.path.abspath(a[0])), "calls.txt"), "a") as f:  # for the test
    f.write(f"{m} {seed} {a[a.index('--seed') + 1]}\n")
OUTCOMES = {  # (map, seed): (underpass passed, time [s], carport family passed, verdict, map update [ms])
    ("ovpc", 1): (True, 25.0, True, "ok", 7.0), ("ovpc", 2): (False, 60.0, False, "violated", 8.0),
    ("octomap", 1): (True, 27.0, True, "ok", 50.0), ("elevation", 1): (False, 60.0, True, "ok", 14.0)}
if (m, seed) not in OUTCOMES:
    sys.exit(1)
suite_ok, t, fam_ok, verdict, map_ms = OUTCOMES[(m, seed)]
runs = []
for name, passed, time_s in (("underpass_2p5", suite_ok, t), ("carport_height_000", fam_ok, 30.0)):
    run_dir = os.path.join(out, name)
    os.makedirs(run_dir)
    with open(os.path.join(run_dir, "cycles.csv"), "w") as f:
        f.write("t,map_ms,plan_ms,map_cpu_ms,plan_cpu_ms\n" +  # wall clock 3x the CPU time: a loaded machine
                "".join(f"{0.2 * i:.1f},{3 * map_ms},{2.0},{map_ms + 0.001 * i},{1.5}\n" for i in range(10)))
    criteria = [{"name": "goal_reached", "passed": passed}]
    runs.append({"scenario": name, "passed": passed, "out": run_dir,
                 "result": {"passed": passed, "sim_time_s": time_s, "criteria": criteria, "collision_steps": 0,
                            "diagnosis": {"verdict": "arrived" if passed else "stalled"}}})
runs[1]["family"] = {"family": "carport_height", "verdict": verdict,
                    "values": {"roof_height_m": 2.5, "offset_m": 0.5, "yaw_deg": 10.0}}
# The carport run's path: straight under the roof (x 0 to 24 along y = 0), or round it for the
# elevation map (y = 4, clear of the 4.5 m wide roof centred on y = 0.5).
with open(os.path.join(runs[1]["out"], "trajectory.csv"), "w") as f:
    y = 4.0 if m == "elevation" else 0.0
    f.write("time_s,true_x_m,true_y_m\n" + "".join(f"{0.1 * i:.3f},{0.024 * i},{y}\n" for i in range(1001)))
with open(os.path.join(out, "summary.json"), "w") as f:
    json.dump({"runs": runs}, f)
'''


def compare(*args):
    return subprocess.run([sys.executable, SCRIPT, *args], capture_output=True, text=True)


with tempfile.TemporaryDirectory() as tmp:
    fake = os.path.join(tmp, "ovpc")
    with open(fake, "w") as f:
        f.write("#!" + sys.executable + "\n" + FAKE_OVPC)
    os.chmod(fake, 0o755)
    scenario = os.path.join(tmp, "underpass_2p5.yaml")
    with open(scenario, "w") as f:
        f.write("name: underpass_2p5\n")
    out, records = os.path.join(tmp, "out"), os.path.join(tmp, "records")
    # Seeds 1-2; seed 2 finishes for ovpc only (a comparison stopped part-way).
    proc = compare(scenario, "--ovpc", fake, "--seeds", "2", "--out", out, "--records", records)
    check(proc.returncode == 0, f"exit code 0, got {proc.returncode}: {proc.stderr}")
    check(sorted(os.listdir(os.path.join(records, "ovpc"))) == ["seed_1.json.gz", "seed_2.json.gz"],
          f"a record per finished suite, got {os.listdir(os.path.join(records, 'ovpc'))}")
    check(not os.path.exists(os.path.join(records, "octomap", "seed_2.json.gz")), "no record of an unfinished suite")
    with open(os.path.join(tmp, "calls.txt")) as f:
        calls = sorted(f.read().split("\n")[:-1])
    check(calls == ["elevation 1 1", "elevation 2 2", "octomap 1 1", "octomap 2 2", "ovpc 1 1", "ovpc 2 2"],
          f"one suite per backend and seed, each family drawn from its run seed, got {calls}")

    # The report needs only the records: the suites' outputs are gone.
    shutil.rmtree(out)
    proc = compare("--report-only", "--out", out, "--records", records)
    check(proc.returncode == 0, f"report from the records: exit code 0, got {proc.returncode}: {proc.stderr}")
    with open(os.path.join(records, "comparison.json")) as f:
        data = json.load(f)
    check(data["seeds"] == [1], f"seeds [1] (seed 2 is not finished for every backend), got {data['seeds']}")
    scenes = data["suite_scenarios"]["underpass_2p5"]
    check(scenes["ovpc"]["runs"] == 1 and scenes["ovpc"]["passed"] == 1, f"ovpc 1/1 on seed 1, got {scenes['ovpc']}")
    check(scenes["elevation"]["passed"] == 0, f"elevation 0 passed, got {scenes['elevation']}")
    check(abs(scenes["octomap"]["mean_time_to_goal_s"] - 27.0) < 1e-9, f"octomap 27 s to goal, got {scenes['octomap']}")
    family = data["groups"]["carport_height"]["ovpc"]
    check(family["expectation_held"] == 1 and family["expectation_counted"] == 1, f"ovpc family 1/1 held, got {family}")
    octomap = data["groups"]["suite"]["octomap"]
    check(octomap["map_cycles"] == 10 and abs(octomap["map_update_median_ms"] - 50.0) < 0.02
          and octomap["planning_p99_ms"] == 1.5 and octomap["clock"] == "thread CPU",
          f"the map cycles' thread CPU times come from the record, got {octomap}")
    check(data["failed_as"]["suite"]["elevation"] == {"stalled": 1} and data["failed_as"]["suite"]["ovpc"] == {},
          f"failed runs by their diagnosis: the elevation map's underpass run stalled, got {data['failed_as']}")
    by_roof = [b for b in data["carport_height_by_roof"] if b["roof_height_m"][0] <= 2.5 < b["roof_height_m"][1]]
    check(len(by_roof) == 1 and by_roof[0]["ovpc"]["under"] == 1 and by_roof[0]["octomap"]["under"] == 1
          and by_roof[0]["elevation"]["under"] == 0 and by_roof[0]["elevation"]["passed"] == 1,
          f"under the roof: ovpc and octomap yes, the elevation map round it, got {by_roof}")
    with open(os.path.join(records, "comparison.md")) as f:
        text = f.read()
    check("left out, finished for some backends only: 2" in text, "the left-out seed is named in comparison.md")
    check(os.path.exists(os.path.join(records, "pass_rate_roof_height.svg")), "the roof-height figure is written")

    # A record without the path (an older compare-backends): its runs are not counted as "not under".
    # Seed 2 here: seed 1's records again, ovpc's without the path.
    pathless = os.path.join(tmp, "pathless")
    shutil.copytree(records, pathless)
    for m in ("ovpc", "octomap", "elevation"):
        with gzip.open(os.path.join(pathless, m, "seed_1.json.gz")) as f:
            data = json.load(f)
        data["seed"] = 2
        if m == "ovpc":
            for run in data["runs"]:
                run.pop("path_xy", None)
        with gzip.open(os.path.join(pathless, m, "seed_2.json.gz"), "wt") as f:
            json.dump(data, f)
    proc = compare("--report-only", "--records", pathless)
    with open(os.path.join(pathless, "comparison.md")) as f:
        text = f.read()
    check(proc.returncode == 0 and "| 2, 1 of 1 with a path / 2 | 2, 2 / 2 | 2, 0 / 2 |" in text,
          f"runs without a path are not counted as 'not under', got {proc.stderr} {text}")

    # A resume with the same program keeps the records and runs nothing new for them.
    proc = compare(scenario, "--ovpc", fake, "--seeds", "1", "--out", out, "--records", records)
    check(proc.returncode == 0 and proc.stdout.count("done before, kept") == 3,
          f"a resume keeps the three records of seed 1, got {proc.returncode}: {proc.stdout} {proc.stderr}")
    check(not os.path.exists(os.path.join(out, "ovpc", "seed_1")), "a kept record's suite is not run again")

    # --family-seed N: the same draws on every seed (and another setting than the records', refused).
    fixed = os.path.join(tmp, "fixed")
    os.remove(os.path.join(tmp, "calls.txt"))
    proc = compare(scenario, "--ovpc", fake, "--seeds", "2", "--family-seed", "7", "--out", fixed, "--maps", "ovpc")
    with open(os.path.join(tmp, "calls.txt")) as f:
        calls = sorted(f.read().split("\n")[:-1])
    check(proc.returncode == 0 and calls == ["ovpc 1 7", "ovpc 2 7"], f"--family-seed 7 on every seed, got {calls}")
    proc = compare(scenario, "--ovpc", fake, "--seeds", "1", "--family-seed", "7", "--out", out, "--records", records)
    check(proc.returncode == 2 and "family_seed" in proc.stderr, f"a resume with other draws is refused, got {proc.stderr}")

    # Another program, or an edited scenario file, resuming into the same records is refused before
    # any run (exit code 2).
    other = os.path.join(tmp, "ovpc2")
    shutil.copy(fake, other)
    with open(other, "a") as f:
        f.write("# another program\n")
    proc = compare(scenario, "--ovpc", other, "--seeds", "3", "--out", out, "--records", records)
    check(proc.returncode == 2 and "manifest.json" in proc.stderr and "ovpc_sha256" in proc.stderr,
          f"a resume with another program is refused with exit code 2, got {proc.returncode}: {proc.stderr}")
    with open(scenario, "a") as f:
        f.write("# edited\n")
    proc = compare(scenario, "--ovpc", fake, "--seeds", "3", "--out", out, "--records", records)
    check(proc.returncode == 2 and "input_sha256" in proc.stderr,
          f"a resume on edited scenario files is refused with exit code 2, got {proc.returncode}: {proc.stderr}")
    check(not os.path.exists(os.path.join(records, "ovpc", "seed_3.json.gz")), "nothing run after a refusal")

print("compare_backends_test: " + ("all checks hold" if not failures else f"{len(failures)} failed"))
sys.exit(1 if failures else 0)
