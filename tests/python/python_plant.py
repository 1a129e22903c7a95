#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""ctest python_plant: the Python package cdprlib in-process (docs/python.md).

  python_plant.py CDPR_SIM SOURCE_DIR WORK_DIR

1. Bit for bit against cdpr-sim: the paper's line, 1 s (100 control periods), the scenario's
   controller stepped from Python (measure, control, step: the order of cdpr-sim's loop): at
   every one of the 101 rows of cdpr-sim's timeseries.csv the cabin position, the unstretched
   lengths and both ends' tensions equal cdpr-sim's exactly (the CSV's %.17g reads back to
   the same double).
2. No copy: state() is a view of the C plant's memory (not owning its data) that shows the
   next step's state without being fetched again.
3. The inverse kinematics at the initial pose gives the plant's initial lengths (the plant is
   built from the same solve; its length is the sum of its segments': 1e-14 m apart); node n of
   every cable is its exit point; a pose it cannot hold raises CdprError CDPR_E_INFEASIBLE.
4. Errors as exceptions with the core's status name and the key: a scenario with a NaN EA
   (CDPR_E_NOT_FINITE naming robot.rope.ea_N), a period over its trial budget
   (CDPR_E_SUBSTEP_LIMIT; the plant's time unchanged), wrong-length commands (ValueError).
5. The scipy example (examples/python/fit_rope.py) recovers the EA its data were made with.
6. The README's Python block runs as pasted.
"""
import csv
import os
import re
import shutil
import subprocess
import sys

import numpy as np

import cdprlib

SIM, SRC, WORK = sys.argv[1], sys.argv[2], sys.argv[3]
failures = []
passes = []


def check(cond, what):
    print(("ok   " if cond else "FAIL ") + what, flush=True)
    (passes if cond else failures).append(what)


shutil.rmtree(WORK, ignore_errors=True)
os.makedirs(WORK)
line = os.path.join(SRC, "scenarios", "paper-line.yaml")

# 1. bit for bit against cdpr-sim
out = os.path.join(WORK, "sim")
r = subprocess.run([SIM, line, "--out", out, "--duration", "1", "--no-plot", "--quiet"],
                   stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
check(r.returncode == 0, "cdpr-sim on the line, 1 s")
rows = list(csv.DictReader(l for l in open(os.path.join(out, "timeseries.csv"))
                           if not l.startswith("#")))
p = cdprlib.Plant(line)
n = p.n_cables
differ = []
for k, row in enumerate(rows):
    m = p.measure()
    got = list(m.position_m) + list(m.length_m) + list(m.tension_cabin_N) + \
        list(m.tension_winch_N)
    want = [float(row[c]) for c in ["x_m", "y_m", "z_m"] +
            ["L%d_m" % j for j in range(1, n + 1)] + ["T_cabin%d_N" % j for j in range(1, n + 1)] +
            ["T_winch%d_N" % j for j in range(1, n + 1)]]
    if got != want or m.t_s != float(row["t_s"]):
        differ.append(k)
    if k < len(rows) - 1:
        p.step(p.control())
check(len(rows) == 101 and not differ,
      "101 rows: position, lengths and both ends' tensions == cdpr-sim's, bit for bit%s" % (
          "" if not differ else " (first difference at row %d)" % differ[0]))

# 2. the state without a copy
y = p.state()
before = y.copy()
p.step(p.control())
check(not y.flags.owndata and y.ctypes.data == p.state().ctypes.data and
      not np.array_equal(y, before), "state(): a view of the plant's memory that follows a step")

# 3. statics and cable nodes
q = cdprlib.Plant(line)
ik = q.ik(q.initial_pose())
check(np.allclose(ik["length_m"], q.measure().length_m, rtol=0.0, atol=1e-12),
      "ik() at the initial pose: the plant's initial unstretched lengths (to 1e-12 m)")
ends = all(np.array_equal(q.nodes(j)[-1], p.nodes(j)[-1]) for j in range(n))
check(ends and q.nodes(0).shape[1] == 3, "nodes(): (n + 1) x 3, the last row the exit point")
try:
    q.ik([0.0, 0.0, 60.0, 0.0, 0.0, 0.0])
    check(False, "a pose above the towers raises CdprError")
except cdprlib.CdprError as e:
    check(e.name == "CDPR_E_INFEASIBLE", "a pose above the towers: CdprError %s" % e.name)

# 4. errors as exceptions
bad = os.path.join(WORK, "bad.yaml")
text = open(line).read()
with open(bad, "w") as f:
    f.write(re.sub(r"(\n    ea_N: )[^ \n]+", r"\1.nan", text, count=1))
try:
    cdprlib.Plant(bad)
    check(False, "a NaN EA raises CdprError")
except cdprlib.CdprError as e:
    check(e.name == "CDPR_E_NOT_FINITE" and "robot.rope.ea_N" in str(e) and bad in str(e),
          "a NaN EA: CdprError %s naming the file and robot.rope.ea_N" % e.name)
tight = os.path.join(WORK, "tight.yaml")
with open(tight, "w") as f:
    f.write(re.sub(r"(\n  max_trials: )[0-9]+", r"\g<1>1", text, count=1))
t = cdprlib.Plant(tight)
try:
    t.step(t.control())
    check(False, "a period over its trial budget raises CdprError")
except cdprlib.CdprError as e:
    check(e.name == "CDPR_E_SUBSTEP_LIMIT" and t.t_s == 0.0 and t.k == 0,
          "a period over its budget: CdprError %s, the plant still at t = 0" % e.name)
try:
    p.step([0.0, 0.0])
    check(False, "two commands for six winches raise ValueError")
except ValueError:
    check(True, "two commands for six winches: ValueError")

# 5. the scipy example
r = subprocess.run([sys.executable, os.path.join(SRC, "examples", "python", "fit_rope.py")],
                   stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
m = re.search(r"fitted EA = ([0-9.e+]+) N", r.stdout)
check(r.returncode == 0 and m is not None and abs(float(m.group(1)) / 2.0e6 - 1.0) < 1e-6,
      "fit_rope.py (scipy) recovers EA = 2e6 N: %s" % (m.group(1) if m else r.stderr[-200:]))
# 6. the README's Python block, as a user would paste it (from the source tree)
readme = open(os.path.join(SRC, "README.md")).read()
block = re.search(r"## From Python\n.*?```python\n(.*?)```", readme, re.S)
r = subprocess.run([sys.executable, "-c", block.group(1) if block else "raise SystemExit(3)"],
                   cwd=SRC, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
check(r.returncode == 0 and "t = 1.00 s" in r.stdout and "(21, 3)" in r.stdout,
      "the README's Python block runs: %s" % (r.stdout.strip().splitlines() or [r.stderr[-200:]])[0])
print("%d passed, %d failed" % (len(passes), len(failures)))
sys.exit(1 if failures else 0)
