#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""ctest sweep_local: cdpr-sweep's local engine against serial cdpr-sim runs (docs/sweeps.md).

  sweep_local.py SWEEP_TOOL CDPR_SIM WORKDIR

1. A 2 x 2 sweep (plus a zip of two keys) on 2 workers: every case's timeseries.csv and
   summary.json equal, byte for byte (wall times aside), a serial `cdpr-sim` run of the case's
   resolved scenario.yaml; results.csv has one row per case with the axis values.
2. Resume: the same call again runs nothing and writes the same table; a case whose done.json
   is removed and whose outputs are torn (an interrupted case) runs again, alone, to the same
   bytes.
3. An interruption (SIGINT once the first case is reported) exits 1; the next call finishes
   the rest; the table equals the uninterrupted one.
4. Refusals before anything runs (exit 2, the output folder untouched or never made): a value
   out of range names the case and the key; a folder holding another sweep; zipped axes of
   different lengths; an empty axis; an unknown sweep key.
5. A case that fails (a substep budget of one trial) is recorded with its status while the
   others complete; the sweep exits 1.
6. Another runner: --prepare lists the case folders without running them, `--run-case` runs
   each (xargs -P 2 standing in for GNU parallel), --collect writes the same table.
Every check counts events the code controls (cases run, bytes written), never wall time.
"""
import csv
import json
import os
import shutil
import signal
import subprocess
import sys

TOOL, SIM, WORK = sys.argv[1], sys.argv[2], sys.argv[3]
SRC = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
PY = "/usr/bin/python3"
failures = []
passes = []


def check(cond, what):
    print(("ok   " if cond else "FAIL ") + what, flush=True)
    (passes if cond else failures).append(what)


def sweep(path, out, *extra):
    """One cdpr-sweep call; figures only where asked for ("--figures": a test option here)."""
    extra = list(extra)
    if "--figures" in extra:
        extra.remove("--figures")
    else:
        extra.append("--no-figures")
    return subprocess.run([PY, TOOL, path, "--out", out, "--sim", SIM] + extra,
                          stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)


def write(name, text):
    p = os.path.join(WORK, name)
    with open(p, "w") as f:
        f.write(text)
    return p


def table(out, drop=("wall_time_s",)):
    with open(os.path.join(out, "results.csv"), newline="") as f:
        return [{k: v for k, v in r.items() if k not in drop} for r in csv.DictReader(f)]


def summary_wo_wall(path):
    with open(path) as f:
        s = json.load(f)
    for k in ("wall_time_s", "settle_wall_time_s"):
        s.pop(k, None)
    return s


def ran(proc):
    """Cases a call ran, from its opening line '(N to run, ...)'."""
    for line in proc.stderr.splitlines():
        if "to run" in line:
            return int(line.split("(", 1)[1].split(" ", 1)[0])
    return -1


shutil.rmtree(WORK, ignore_errors=True)
os.makedirs(WORK)
base = os.path.join(SRC, "scenarios", "paper-line.yaml")
good = write("good.yaml", """
scenario: %s
set: {run.duration_s: 0.3}
axes:
  - key: controller.kp
    values: [0.5, 1.0]
  - zip:
      - {key: robot.rope.damping_Ns, values: [170.0, 340.0]}
      - {key: robot.segments, values: [12, 16]}
""" % base)

# 1. parallel == serial, byte for byte
out = os.path.join(WORK, "a")
p = sweep(good, out, "--jobs", "2", "--figures")
check(p.returncode == 0, "4-case sweep on 2 workers exits 0" +
      ("" if p.returncode == 0 else " (exit %d: %s)" % (p.returncode, p.stderr[-300:])))
check(ran(p) == 4, "it ran 4 cases")
rows = table(out)
check(len(rows) == 4 and all(r["status"] == "ok" for r in rows), "results.csv: 4 rows, status ok")
check([(r["controller.kp"], r["robot.rope.damping_Ns"], r["robot.segments"]) for r in rows] ==
      [("0.5", "170.0", "12"), ("0.5", "340.0", "16"), ("1.0", "170.0", "12"), ("1.0", "340.0", "16")],
      "the rows carry the axis values in product order (zip members paired)")
figs = sorted(os.listdir(os.path.join(out, "figures")))
maps = [f for f in figs if "_map_" in f and f.endswith(".png")]
check(len([f for f in figs if f.endswith(".png")]) == 25 and
      len([f for f in figs if f.endswith(".svg")]) == 25 and
      "rms_error_m_vs_robot.segments.svg" in figs and len(maps) == 10 and
      "max_tension_N_map_controller.kp_robot.rope.damping_Ns.svg" in figs and
      not any("robot.rope.damping_Ns_robot.segments" in f for f in maps),
      "figures: 5 figures of merit x 3 swept keys, and heat maps over the 2 pairs of keys that "
      "are not zipped together, PNG and SVG (%d files)" % len(figs))
same = 0
for r in rows:
    d = os.path.join(out, "cases", r["case"])
    s = os.path.join(WORK, "serial", r["case"])
    q = subprocess.run([SIM, os.path.join(d, "scenario.yaml"), "--out", s, "--no-plot", "--quiet"])
    with open(os.path.join(d, "timeseries.csv"), "rb") as f1, \
            open(os.path.join(s, "timeseries.csv"), "rb") as f2:
        ts_same = f1.read() == f2.read()
    sm_same = summary_wo_wall(os.path.join(d, "summary.json")) == \
        summary_wo_wall(os.path.join(s, "summary.json"))
    same += 1 if (q.returncode == 0 and ts_same and sm_same) else 0
check(same == 4, "every case's timeseries.csv and summary.json == a serial cdpr-sim run (%d/4)" % same)
with open(os.path.join(out, "results.json")) as f:
    jrows = json.load(f)
resolved = [(j["parameters"]["controller"]["kp"],
             {c["rope"]["damping_Ns"] for c in j["parameters"]["robot"]["cables"]},
             {c["segments"] for c in j["parameters"]["robot"]["cables"]},
             j["parameters"]["run"]["duration_s"]) for j in jrows]
check(resolved == [(0.5, {170.0}, {12}, 0.3), (0.5, {340.0}, {16}, 0.3), (1.0, {170.0}, {12}, 0.3),
                   (1.0, {340.0}, {16}, 0.3)],
      "results.json: each case's resolved parameters (summary.json) hold its axis values, on "
      "every cable, and the set key")

# 1b. a case whose values are the base's own: the same run as cdpr-sim on the base file itself
# (the case file is the base re-written by the YAML library; its data lines must not differ).
kp = [l.split(":")[1].split("#")[0].strip() for l in open(base) if l.startswith("  kp:")][0]
same_as_base = write("base-values.yaml", """
scenario: %s
set: {run.duration_s: 0.3}
axes:
  - key: controller.kp
    values: [%s]
""" % (base, kp))
out_s = os.path.join(WORK, "base-values")
p = sweep(same_as_base, out_s)
q = subprocess.run([SIM, base, "--out", os.path.join(WORK, "base-run"), "--duration", "0.3",
                    "--no-plot", "--quiet"], stderr=subprocess.DEVNULL)


def data_lines(path):
    with open(path) as f:
        return [line for line in f if not line.startswith("#")]


check(p.returncode == 0 and q.returncode == 0 and
      data_lines(os.path.join(out_s, "cases", "0001", "timeseries.csv")) ==
      data_lines(os.path.join(WORK, "base-run", "timeseries.csv")),
      "a case with the base's own values == cdpr-sim on the base file (timeseries data lines)")

# 2. resume
before = {r["case"]: os.stat(os.path.join(out, "cases", r["case"], "done.json")).st_mtime_ns
          for r in rows}
p = sweep(good, out, "--jobs", "2")
check(p.returncode == 0 and ran(p) == 0, "rerun: nothing to run, exit 0")
check(table(out) == rows, "rerun: the same table")
after = {c: os.stat(os.path.join(out, "cases", c, "done.json")).st_mtime_ns for c in before}
check(after == before, "rerun: no case touched")
torn = os.path.join(out, "cases", "0002")
ref = open(os.path.join(torn, "timeseries.csv"), "rb").read()
os.remove(os.path.join(torn, "done.json"))
with open(os.path.join(torn, "timeseries.csv"), "r+b") as f:
    f.truncate(len(ref) // 2)
p = sweep(good, out, "--jobs", "2")
check(p.returncode == 0 and ran(p) == 1, "an interrupted case (no done.json) runs again, alone")
check(open(os.path.join(torn, "timeseries.csv"), "rb").read() == ref, "... to the same bytes")
check(table(out) == rows, "... and the same table")

# 3. interruption and resume. One worker; case 0002 waits at a gate (a wrapper around cdpr-sim
# that never opens it), so the SIGINT sent once case 0001 is reported finds 0002 running and
# 0003, 0004 not started, whatever the machine's speed.
out_i = os.path.join(WORK, "interrupted")
gated = write("gated-sim.sh", """#!/bin/sh
case "$1" in */0002/*) while [ ! -e "%s" ]; do sleep 0.05; done ;; esac
exec "%s" "$@"
""" % (os.path.join(WORK, "never-opened"), SIM))
os.chmod(gated, 0o755)
proc = subprocess.Popen([PY, TOOL, good, "--out", out_i, "--sim", gated, "--jobs", "1",
                         "--no-figures"],
                        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
for line in proc.stderr:
    if "] case 0001 " in line:
        proc.send_signal(signal.SIGINT)
        break
# A guard against a hang, not a time assertion: the sweep answers a SIGINT at once (once, a
# sweep whose main thread sat in an untimed wait ran the handler only when case 0002 ended,
# i.e. never with this gate).
try:
    proc.wait(timeout=300)  # what it still writes (a few lines) fits the pipe
except subprocess.TimeoutExpired:
    proc.kill()
    proc.wait()
    check(False, "SIGINT: the sweep did not stop within 300 s (hung)")
rest = proc.stderr.read()
done = [c for c in sorted(before) if os.path.exists(os.path.join(out_i, "cases", c, "done.json"))]
check(proc.returncode == 1 and "interrupted" in rest, "SIGINT: exit 1, 'interrupted' said")
check(done == ["0001"], "SIGINT: case 0001 complete, 0002 (running) and 0003, 0004 not: %s" % done)
done_n = len(done)
p = sweep(good, out_i, "--jobs", "2")
check(p.returncode == 0 and ran(p) == 4 - done_n, "the next call runs the %d others" % (4 - done_n))
check(table(out_i) == rows, "the interrupted-then-resumed table == the uninterrupted one")

# 4. refusals before anything runs
bad = write("bad-value.yaml", """
scenario: %s
set: {run.duration_s: 0.3}
axes:
  - key: controller.kp
    values: [0.5, -1.0]
""" % base)
out_b = os.path.join(WORK, "b")
p = sweep(bad, out_b)
check(p.returncode == 2 and "case 0002" in p.stderr and "controller.kp" in p.stderr
      and "case 0001" not in p.stderr.split("refused", 1)[1],
      "a value out of range: exit 2 naming case 0002 and the key")
check(not os.path.exists(out_b), "... and the output folder is not made")
rec = open(os.path.join(out, "sweep.json"), "rb").read()
other = write("other.yaml", open(good).read().replace("[0.5, 1.0]", "[0.25, 1.0]"))
p = sweep(other, out)
check(p.returncode == 2 and "another sweep" in p.stderr, "a folder holding another sweep: exit 2")
check(open(os.path.join(out, "sweep.json"), "rb").read() == rec and table(out) == rows,
      "... and nothing in it changed")
for name, text, needle in [
        ("zip.yaml", "scenario: %s\naxes:\n  - zip:\n     - {key: controller.kp, values: [1, 2]}\n"
         "     - {key: robot.segments, values: [12]}\n" % base, "different lengths"),
        ("empty.yaml", "scenario: %s\naxes:\n  - {key: controller.kp, values: []}\n" % base,
         "non-empty"),
        ("unknown.yaml", "scenario: %s\nscenarios: x\naxes: []\n" % base, "unknown key")]:
    p = sweep(write(name, text), os.path.join(WORK, "never"))
    check(p.returncode == 2 and needle in p.stderr and not os.path.exists(os.path.join(WORK, "never")),
          "%s: exit 2, says '%s', nothing made" % (name, needle))

# 5. a failing case among good ones
fail = write("fail.yaml", """
scenario: %s
set: {run.duration_s: 0.3}
axes:
  - key: integrator.max_trials
    values: [2000, 1]
""" % base)
out_f = os.path.join(WORK, "f")
p = sweep(fail, out_f, "--jobs", "2")
rows_f = table(out_f)
check(p.returncode == 1, "a failing case: the sweep exits 1")
check([r["status"] for r in rows_f] == ["ok", "failed"] and rows_f[1]["exit_code"] == "1",
      "... the good case completes, the failed one is recorded (status failed, exit 1)")

# 6. another runner (docs/sweeps.md, GNU parallel): --prepare lists the case folders, each is
# run by `--run-case` (here two at a time by xargs, as parallel would), --collect writes the
# table, running nothing: the same table as the local engine's.
out_p = os.path.join(WORK, "prepared")
p = sweep(good, out_p, "--prepare")
listed = p.stdout.split()
check(p.returncode == 0 and listed == [os.path.join(out_p, "cases", c) for c in sorted(before)]
      and not any(os.path.exists(os.path.join(d, "done.json")) for d in listed),
      "--prepare: exit 0, the 4 case folders listed, none run")
x = subprocess.run(["xargs", "-P", "2", "-n", "1", PY, TOOL, "--sim", SIM, "--run-case"],
                   input=p.stdout, text=True)
p = sweep(good, out_p, "--collect")
check(x.returncode == 0 and p.returncode == 0 and "running nothing" in p.stderr and
      table(out_p) == rows, "--run-case on each (xargs -P 2), then --collect: the same table")
p = sweep(good, out_p, "--prepare")
check(p.returncode == 0 and p.stdout == "", "--prepare again: nothing left to list")

print("%d passed, %d failed" % (len(passes), len(failures)))
sys.exit(1 if failures else 0)
