#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""ctest app_shapes: cdpr-sim --shapes HZ writes every node of every cable (docs/scenarios.md).

  shapes.py CDPR_SIM SOURCE_DIR WORK_DIR

On the paper's line (1 s, snapshots at 2 Hz):
1. DIR/shapes.csv: the header, one row per node (0..n) of every cable per snapshot, a blank line
   after each cable, snapshots at t = 0, 0.5 and 1 s; node n at the cable's exit point exactly
   (summary.json's resolved exit_m), h_m and sag_m 0 at both ends.
2. The settled cables at t = 0 against an independent closed form: a cable's sag below its
   chord is the parabola 4 f x (1 - x) with f = w L_h^2 / (8 H) (w: weight per horizontal
   metre rho g L_c / L_h; H: horizontal tension, the cabin-end tension of timeseries.csv times
   the cosine of the first segment's slope): every node within 3 % of f (measured: 0.7-1.1 %,
   the parabola's own error against the catenary and the segments' discreteness).
3. The figure DIR/shapes.png and .pdf (with gnuplot).
4. --shapes 3 (100 Hz / 3 is not whole): exit 2, the message names --shapes, nothing written.
"""
import csv
import json
import math
import os
import shutil
import subprocess
import sys

SIM, SRC, WORK = sys.argv[1], sys.argv[2], sys.argv[3]
failures = []
passes = []


def check(cond, what):
    print(("ok   " if cond else "FAIL ") + what, flush=True)
    (passes if cond else failures).append(what)


shutil.rmtree(WORK, ignore_errors=True)
os.makedirs(WORK)
out = os.path.join(WORK, "line")
r = subprocess.run([SIM, os.path.join(SRC, "scenarios", "paper-line.yaml"), "--out", out,
                    "--duration", "1", "--shapes", "2", "--quiet"],
                   stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
check(r.returncode == 0, "cdpr-sim --shapes 2 exits 0" + ("" if r.returncode == 0 else
                                                            ": " + r.stderr[-300:]))
with open(os.path.join(out, "shapes.csv")) as f:
    lines = f.read().split("\n")
data = [l for l in lines if not l.startswith("#")]
check(data[0] == "t_s,cable,node,x_m,y_m,z_m,h_m,sag_m", "the header")
rows = [dict(zip(data[0].split(","), map(float, l.split(",")))) for l in data[1:] if l]
summ = json.load(open(os.path.join(out, "summary.json")))
P = summ["parameters"]["robot"]
nc = P["n_cables"]
times = sorted({r["t_s"] for r in rows})
check(times == [0.0, 0.5, 1.0], "snapshots at t = 0, 0.5, 1 s: %s" % times)
per = {}
for r in rows:
    per.setdefault((r["t_s"], int(r["cable"])), []).append(r)
blank = sum(1 for l in data[1:-1] if l == "")
check(len(per) == 3 * nc and blank == 3 * nc and
      all([int(r["node"]) for r in v] == list(range(len(v))) for v in per.values()),
      "every cable's nodes 0..n in order, a blank line after each (%d blocks)" % len(per))
ends = all(v[-1]["x_m"] == P["cables"][j - 1]["exit_m"][0] and
           v[-1]["y_m"] == P["cables"][j - 1]["exit_m"][1] and
           v[-1]["z_m"] == P["cables"][j - 1]["exit_m"][2] and
           v[-1]["h_m"] == 0.0 and abs(v[-1]["sag_m"]) < 1e-12 and abs(v[0]["sag_m"]) < 1e-12
           for (t, j), v in per.items())
check(ends, "node n at the exit point exactly; h_m 0 there, sag_m 0 at both ends")

ts = [x for x in csv.DictReader(l for l in open(os.path.join(out, "timeseries.csv"))
                                 if not l.startswith("#"))]
g = P["gravity_m_per_s2"]
worst = 0.0
for j in range(1, nc + 1):
    v = per[(0.0, j)]
    p = [(r["x_m"], r["y_m"], r["z_m"]) for r in v]
    d = [p[1][i] - p[0][i] for i in range(3)]
    H = float(ts[0]["T_cabin%d_N" % j]) * math.hypot(d[0], d[1]) / math.sqrt(sum(x * x for x in d))
    Lh = v[0]["h_m"]
    w = P["cables"][j - 1]["rope"]["rho_kg_per_m"] * g * math.dist(p[0], p[-1]) / Lh
    f = w * Lh * Lh / (8.0 * H)
    dev = max(abs(r["sag_m"] - 4.0 * f * (r["h_m"] / Lh) * (1.0 - r["h_m"] / Lh)) for r in v)
    worst = max(worst, dev / f)
check(worst < 0.03, "t = 0: every node's sag within 3 %% of the parabola's mid-span sag "
      "(worst %.2f %%)" % (100.0 * worst))

if shutil.which("gnuplot"):
    check(all(os.path.getsize(os.path.join(out, "shapes." + e)) > 0 for e in ("png", "pdf")),
          "the figure shapes.png and shapes.pdf")

bad = os.path.join(WORK, "bad")
r = subprocess.run([SIM, os.path.join(SRC, "scenarios", "paper-line.yaml"), "--out", bad,
                    "--duration", "1", "--shapes", "3", "--quiet", "--no-plot"],
                   stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
check(r.returncode == 2 and "--shapes 3 Hz" in r.stderr and
      not os.path.exists(os.path.join(bad, "timeseries.csv")),
      "--shapes 3 at 100 Hz: exit 2 naming --shapes, nothing written")
print("%d passed, %d failed" % (len(passes), len(failures)))
sys.exit(1 if failures else 0)
