#!/usr/bin/python3
"""Reads a short suite's junit.xml with Debian's python3-junitparser (run by /usr/bin/python3: the
Debian module is on its path) and checks what a CI system shows of it: a testcase per run with its
scenario file and properties, the failed criteria and diagnosis in a failure, an error for a
malformed file, skipped for a label left out and for a family's `any` draw, [[ATTACHMENT|path]]
lines for topdown.png and run.mcap (relative to junit.xml's folder, or absolute with
--junit-absolute-paths); and summary.md. Usage: check_junit.py OVPC_PROGRAM. Exit code 0 when every
check holds, 1 otherwise (each failure printed)."""
import json
import os
import re
import subprocess
import sys
import tempfile

try:
    import junitparser
    from junitparser import Error, Failure, JUnitXml, Skipped
except ImportError:
    print("check_junit: python3-junitparser is missing: run scripts/install-deps", file=sys.stderr)
    sys.exit(1)

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
failures = []


def check(condition, what):
    if not condition:
        failures.append(what)
        print("FAILED: " + what)


def properties(case):
    node = case._elem.find("properties")
    return {} if node is None else {p.get("name"): p.get("value") for p in node.findall("property")}


def attachments(case):
    return re.findall(r"\[\[ATTACHMENT\|([^\]]+)\]\]", case.system_out or "")


def write_inputs(d):
    with open(os.path.join(ROOT, "tests", "support", "short_flat.yaml")) as f:
        short = f.read()
    files = {
        "pass.yaml": short + "record: {mcap: true}\n",
        "late.yaml": short.replace("short_flat", "short_late").replace("time_limit_s: 8", "time_limit_s: 3")
                          .replace("max_time_s: 8", "max_time_s: 3"),
        "long.yaml": short.replace("short_flat", "short_long") + "labels: [long]\n",
        "broken.yaml": "name: broken\ntime_limit_s: soon\nroute: [[0, 0]]\n",
        "family.yaml": short.replace("short_flat", "short_family").replace("[6, 0]]", "[$goal_x, 0]]")
                            .replace("x_m: 6.0", "x_m: \"${goal_x}\"")
                            + "parameters:\n  goal_x: {grid: [6]}\nexpect:\n  - {then: any, reason: a made-up draw}\n",
    }
    for name, text in files.items():
        with open(os.path.join(d, name), "w") as f:
            f.write(text)
    return [os.path.join(d, n) for n in ("pass.yaml", "late.yaml", "long.yaml", "broken.yaml", "family.yaml")]


def check_cases(suite_dir, summary):
    xml = JUnitXml.fromfile(os.path.join(suite_dir, "junit.xml"))
    suites = list(xml) if isinstance(xml, JUnitXml) else [xml]
    check(len(suites) == 1, "one testsuite")
    s = suites[0]
    check((s.tests, s.failures, s.errors, s.skipped) == (5, 1, 1, 2),
          "5 tests, 1 failure, 1 error, 2 skipped: %s" % ((s.tests, s.failures, s.errors, s.skipped),))
    cases = {c.classname: c for c in s}
    check(sorted(cases) == ["broken", "short_family", "short_flat", "short_late", "short_long"], "classnames: %s" % sorted(cases))
    for name, c in cases.items():
        check(c._elem.get("file", "").endswith(".yaml"), "%s: a file attribute naming its scenario file" % name)
    build = summary["suite"]["build"]
    ok = cases["short_flat"]
    check(ok.is_passed, "short_flat passed")
    p = properties(ok)
    check(p.get("seed") == "1" and p.get("map") == "ovpc" and p.get("commit") == build, "short_flat's properties: %s" % p)
    found = attachments(ok)
    check(sorted(os.path.basename(a) for a in found) == ["run.mcap", "topdown.png"], "short_flat's attachments: %s" % found)
    check(all(not os.path.isabs(a) and os.path.isfile(os.path.join(suite_dir, a)) for a in found),
          "attachments relative to junit.xml's folder: %s" % found)
    late = [r for r in cases["short_late"].result if isinstance(r, Failure)]
    run = next(r for r in summary["runs"] if r["scenario"] == "short_late")
    check(len(late) == 1, "short_late failed")
    if late:
        check("diagnosis: " + run["result"]["diagnosis"]["summary"] in late[0].text, "the failure holds the diagnosis: " + late[0].text)
        check(re.search(r"^\w+: expected .*, got ", late[0].text, re.M) is not None, "and the failed criteria: " + late[0].text)
    check(any(isinstance(r, Error) for r in cases["broken"].result), "the malformed file is an error")
    skipped = [r for r in cases["short_long"].result if isinstance(r, Skipped)]
    check(len(skipped) == 1 and "--skip-label long" in (skipped[0].message or ""), "short_long skipped by its label")
    family = cases["short_family"]
    check(any(isinstance(r, Skipped) for r in family.result), "the family's any draw is skipped")
    p = properties(family)
    check(p.get("value.goal_x") == "6" and p.get("expectation") == "any" and p.get("family") == "short_family",
          "the family run's properties: %s" % p)
    check(family._elem.get("file", "").endswith("family.yaml"), "a family run's file is its family's file")


def main():
    ovpc = sys.argv[1]
    with tempfile.TemporaryDirectory() as d:
        inputs = write_inputs(d)
        out = os.path.join(d, "suite")
        r = subprocess.run([ovpc, "suite"] + inputs + ["--skip-label", "long", "--jobs", "2", "--samples", "1", "--out", out],
                           capture_output=True, text=True)
        check(r.returncode == 2, "a malformed file among the inputs: exit 2 (%d)\n%s%s" % (r.returncode, r.stdout, r.stderr))
        with open(os.path.join(out, "summary.json")) as f:
            summary = json.load(f)
        check_cases(out, summary)
        with open(os.path.join(out, "summary.md")) as f:
            md = f.read()
        check(md.startswith("# ovpc suite: 2 of 4 runs passed"), "summary.md's title: " + md[:80])
        check("| short_late | 1 | ovpc |" in md and "| broken |" in md, "summary.md lists the runs that did not pass:\n" + md)
        absolute = os.path.join(d, "absolute")
        r = subprocess.run([ovpc, "suite", inputs[0], "--junit-absolute-paths", "--out", absolute], capture_output=True, text=True)
        check(r.returncode == 0, "the passing scenario alone passes: %s%s" % (r.stdout, r.stderr))
        case = next(iter(next(iter(JUnitXml.fromfile(os.path.join(absolute, "junit.xml"))))))
        found = attachments(case)
        check(len(found) == 2 and all(os.path.isabs(a) and os.path.isfile(a) for a in found), "absolute attachments: %s" % found)
    print("check_junit: %s (junitparser %s)" % ("FAILED" if failures else "ok", junitparser.version))
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
