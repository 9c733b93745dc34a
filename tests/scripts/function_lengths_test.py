#!/usr/bin/env python3
"""Test of scripts/function-lengths: on a made-up file it measures a long function, leaves out
lambdas, control blocks, classes and initialisers, and exits 1 past --max; on the repository's
library and program folders no function is longer than 100 lines (exit 0). Exit code 0 when every
check holds, 1 otherwise (each failure printed)."""
import os
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
SCRIPT = os.path.join(ROOT, "scripts", "function-lengths")
failures = []


def check(condition, what):
    if not condition:
        failures.append(what)
        print("FAILED: " + what)


def run(*args):
    p = subprocess.run([sys.executable, SCRIPT] + list(args), capture_output=True, text=True)
    return p.returncode, p.stdout + p.stderr


body = "\n".join("  x += %d;  // a line with { braces } in a comment" % i for i in range(115))
made_up = """
namespace demo {
struct Config {
  int a = 0;
  void Validate() const { if (a < 0) { throw 1; } }
};
int Long(int x) {
%s
  const auto twice = [](int y) {
    return 2 * y;
  };
  if (x > 0) {
    x = twice(x);
  }
  const char* s = "{ not a brace";
  return x;
}
int Short(int x) { return x + 1; }
}  // namespace demo
""" % body

with tempfile.TemporaryDirectory() as d:
    with open(os.path.join(d, "demo.cc"), "w") as f:
        f.write(made_up)
    code, out = run("--max", "100", d)
    check(code == 1, "a function of 125 lines is over 100 (exit %d): %s" % (code, out))
    check(" Long" in out and "125" in out, "the long function is named with its length: " + out)
    check("Short" not in out and "twice" not in out, "short functions and lambdas are not listed: " + out)
    check("3 functions" in out, "Validate, Long and Short, the lambda inside Long not counted apart: " + out)
    code, out = run("--max", "130", d)
    check(code == 0, "nothing over 130 (exit %d): %s" % (code, out))
    code, out = run("--max", "0", d)
    check(code == 2, "--max 0 is bad usage (exit %d)" % code)

code, out = run()
check(code == 0, "no function in the library and program folders is over 100 lines:\n" + out)

print("%d failed" % len(failures) if failures else "all checks passed")
sys.exit(1 if failures else 0)
