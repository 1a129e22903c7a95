#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""ctest sweep_slurm: cdpr-sweep's Slurm engine on a real single-node Slurm (docs/sweeps.md).

  sweep_slurm.py SWEEP_TOOL CDPR_SIM WORKDIR

Starts munged, slurmctld and slurmd in WORKDIR/cluster (tests/sweep/slurm_node.sh: its own key,
configuration, ports and logs; root) and stops them at the end, whatever happens.
1. An 8-case sweep as one job array: exit 0, 8 rows with status ok, the table equal to the
   local engine's for the same sweep file, bit for bit (wall times aside); the generated batch
   script carries the array, the job name and the options passed through (--partition, --mem,
   --slurm-option).
2. A case killed while it runs (scancel: SIGTERM to the task, as at a time limit) keeps whole
   outputs (every timeseries row complete, summary status "interrupted") and no done.json; the
   same command again runs only the cases not complete, and the killed case's outputs then equal
   a serial cdpr-sim run of its scenario, byte for byte.
3. A real time limit (--time 1, a case that needs far longer): Slurm kills it, the sweep exits 1
   and names the case as killed at the time limit, the case's outputs are whole and it is not
   complete; the same command again (--no-wait) submits exactly that case again.
4. Refusals: a controller that does not answer (exit 4, the output folder never made); a job
   array refused by sbatch (an unknown partition: exit 4 with sbatch's reason; the cases already
   complete are untouched, and the next call without the bad option completes the sweep).
Every check is on states and counts (rows, exit codes, files, bytes), never on wall time; the
waits are bounded and only wait for a state (a task started, the queue empty).
"""
import csv
import json
import os
import shutil
import subprocess
import sys
import time

TOOL, SIM, WORK = sys.argv[1], sys.argv[2], sys.argv[3]
SRC = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
NODE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "slurm_node.sh")
PY = "/usr/bin/python3"
CLUSTER = os.path.join(WORK, "cluster")
failures = []
passes = []


def check(cond, what):
    print(("ok   " if cond else "FAIL ") + what, flush=True)
    (passes if cond else failures).append(what)


def sweep(path, out, *extra, env=None):
    return subprocess.run([PY, TOOL, path, "--out", out, "--sim", SIM, "--no-figures",
                           "--poll", "0.5"] + list(extra), stdout=subprocess.PIPE,
                          stderr=subprocess.PIPE, text=True, env=env)


def write(name, text):
    p = os.path.join(WORK, name)
    with open(p, "w") as f:
        f.write(text)
    return p


def table(out):
    with open(os.path.join(out, "results.csv"), newline="") as f:
        return [{k: v for k, v in r.items() if k != "wall_time_s"} for r in csv.DictReader(f)]


def wait_for(cond, what, limit_s=300.0):
    """Poll a state (bounded: a hang guard, not a timing assertion)."""
    t = time.monotonic()
    while time.monotonic() - t < limit_s:
        if cond():
            return True
        time.sleep(0.2)
    check(False, "waited %g s for %s" % (limit_s, what))
    return False


def queue(name_or_job):
    r = subprocess.run(["squeue", "--noheader", "--array", "--format", "%i %T"] +
                       (["--jobs", name_or_job] if name_or_job.isdigit() else
                        ["--name", name_or_job]), stdout=subprocess.PIPE,
                       stderr=subprocess.PIPE, text=True)
    return [line for line in r.stdout.splitlines() if line.strip()] if r.returncode == 0 else None


def rows_whole(path):
    """Every data row of a timeseries.csv has the header's field count and a newline."""
    with open(path, "rb") as f:
        data = f.read()
    if not data.endswith(b"\n"):
        return False, 0
    lines = [x for x in data.decode().splitlines() if x and not x.startswith("#")]
    n = len(lines[0].split(","))
    return all(len(x.split(",")) == n for x in lines), len(lines) - 1


def status_of(case_dir):
    try:
        with open(os.path.join(case_dir, "summary.json")) as f:
            return json.load(f).get("status")
    except (OSError, ValueError):
        return None


def last_submission(out):
    """(job id, the case ids it was given) of the last array a sweep folder records."""
    with open(os.path.join(out, "slurm", "jobs.txt")) as f:
        job, script, _ = f.read().splitlines()[-1].split()
    with open(os.path.join(out, "slurm", script.replace(".sbatch", ".cases"))) as f:
        return job, f.read().split()


def main():
    if os.geteuid() != 0:
        print("sweep_slurm: needs root (slurmd starts jobs as their submitter)")
        return 77
    shutil.rmtree(WORK, ignore_errors=True)
    os.makedirs(WORK)
    r = subprocess.run(["sh", NODE, "start", CLUSTER, "2"], stdout=subprocess.PIPE,
                       stderr=subprocess.PIPE, text=True)
    if r.returncode != 0:
        print(r.stdout + r.stderr)
        check(False, "the single-node cluster starts")
        return 1
    os.environ["SLURM_CONF"] = r.stdout.strip().split("=", 1)[1]
    check(True, "a single-node Slurm (munged, slurmctld, slurmd) is up: " + os.environ["SLURM_CONF"])
    try:
        run_checks()
    finally:
        subprocess.run(["sh", NODE, "stop", CLUSTER])
    print("%d passed, %d failed" % (len(passes), len(failures)))
    return 1 if failures else 0


def run_checks():
    base = os.path.join(SRC, "scenarios", "paper-line.yaml")

    # 3 (started first: it holds one of the two CPUs for the 60-90 s until Slurm's limit).
    limit = write("limit.yaml", """
scenario: %s
set: {run.duration_s: 100000.0}
axes:
  - key: controller.kp
    values: [0.5]
""" % base)
    out_t = os.path.join(WORK, "limit")
    p = sweep(limit, out_t, "--engine", "slurm", "--time", "1", "--no-wait")
    check(p.returncode == 0 and "submitted job array" in p.stderr,
          "a sweep with --time 1 is submitted (--no-wait exits 0 at once)" +
          ("" if p.returncode == 0 else ": exit %d %s" % (p.returncode, p.stderr[-400:])))

    # 1. eight cases as one job array == the local engine
    eight = write("eight.yaml", """
scenario: %s
set: {run.duration_s: 0.3}
axes:
  - key: controller.kp
    values: [0.5, 1.0]
  - key: robot.rope.damping_Ns
    values: [170.0, 255.0, 340.0, 425.0]
""" % base)
    out_s = os.path.join(WORK, "slurm8")
    out_l = os.path.join(WORK, "local8")
    p = sweep(eight, out_s, "--engine", "slurm", "--partition", "debug", "--mem", "500M",
              "--slurm-option=--comment=cdpr-test")
    check(p.returncode == 0, "8-case sweep through a Slurm job array exits 0" +
          ("" if p.returncode == 0 else " (exit %d: %s)" % (p.returncode, p.stderr[-400:])))
    q = sweep(eight, out_l, "--jobs", "2")
    check(q.returncode == 0, "the same sweep on the local engine exits 0")
    ts, tl = table(out_s), table(out_l)
    check(len(ts) == 8 and all(r["status"] == "ok" for r in ts), "Slurm table: 8 rows, status ok")
    check(ts == tl, "Slurm table == local table, every column but wall time, bit for bit")
    with open(os.path.join(out_s, "slurm", "submit-1.sbatch")) as f:
        script = f.read()
    check("#SBATCH --array=1-8\n" in script and "#SBATCH --partition=debug\n" in script and
          "#SBATCH --mem=500M\n" in script and "#SBATCH --comment=cdpr-test\n" in script and
          "#SBATCH --job-name=cdpr-sweep-" in script,
          "the batch script: one array of 8 tasks, job name, --partition/--mem/--slurm-option")
    with open(os.path.join(out_s, "slurm", "jobs.txt")) as f:
        check(len(f.read().splitlines()) == 1, "one submission (jobs.txt)")

    # 2. a running case killed (SIGTERM through scancel), then resume
    kill = write("kill.yaml", """
scenario: %s
axes:
  - key: run.duration_s
    values: [0.3, 60.0, 0.5]
""" % base)
    out_k = os.path.join(WORK, "kill")
    p = sweep(kill, out_k, "--engine", "slurm", "--no-wait")
    check(p.returncode == 0, "3-case sweep submitted with --no-wait")
    long_case = os.path.join(out_k, "cases", "0002")
    ts_path = os.path.join(long_case, "timeseries.csv")
    wait_for(lambda: os.path.exists(ts_path) and os.path.getsize(ts_path) > 20000,
             "the 60 s case to be writing rows")
    job, _ = last_submission(out_k)
    subprocess.run(["scancel", job])
    wait_for(lambda: queue(job) == [], "the cancelled array to leave the queue")
    whole, n = rows_whole(ts_path)
    check(not os.path.exists(os.path.join(long_case, "done.json")) and
          status_of(long_case) == "interrupted",
          "the killed case: summary status 'interrupted', no done.json (not complete)")
    check(whole and 0 < n < 6000, "its timeseries.csv: %d whole rows (of 6000), none torn" % n)
    left = [c for c in ("0001", "0002", "0003")
            if not os.path.exists(os.path.join(out_k, "cases", c, "done.json"))]
    done_before = {c: open(os.path.join(out_k, "cases", c, "done.json")).read()
                   for c in ("0001", "0003") if c not in left}
    p = sweep(kill, out_k, "--engine", "slurm")
    check(p.returncode == 0 and "(%d to run, %d complete from before)" % (len(left), 3 - len(left))
          in p.stderr, "the same command again runs only the %d case(s) not complete (%s)" % (
              len(left), ", ".join(left)))
    check(all(open(os.path.join(out_k, "cases", c, "done.json")).read() == t
              for c, t in done_before.items()), "the cases complete before are untouched")
    serial = os.path.join(WORK, "serial-0002")
    subprocess.run([SIM, os.path.join(long_case, "scenario.yaml"), "--out", serial, "--no-plot",
                    "--quiet"])
    same = all(open(os.path.join(long_case, f), "rb").read() ==
               open(os.path.join(serial, f), "rb").read() for f in ("timeseries.csv",))
    check(same and status_of(long_case) == "ok",
          "the rerun case: status ok, timeseries.csv == a serial cdpr-sim run, byte for byte")

    # 3 (continued): follow the time-limited array until Slurm kills it. (Should the limit
    # have struck already, this call submits the case again and follows that array instead.)
    p = sweep(limit, out_t, "--engine", "slurm", "--time", "1")
    case = os.path.join(out_t, "cases", "0001")
    check(p.returncode == 1 and "killed at the time limit (--time): case 0001" in p.stderr,
          "--time 1: the sweep follows the array to its end, exits 1 and names the case killed "
          "at its time limit" + ("" if p.returncode == 1 else " (exit %d: %s)" % (
              p.returncode, p.stderr[-400:])))
    whole, n = rows_whole(os.path.join(case, "timeseries.csv"))
    check(status_of(case) == "interrupted" and not os.path.exists(os.path.join(case, "done.json"))
          and whole and n > 0,
          "the time-limited case: whole outputs (%d rows), status 'interrupted', not complete" % n)
    check([r["status"] for r in table(out_t)] == ["interrupted"],
          "results.csv lists it as 'interrupted'")
    before, _ = last_submission(out_t)
    p = sweep(limit, out_t, "--engine", "slurm", "--time", "1", "--no-wait")
    job, cases = last_submission(out_t)
    check(p.returncode == 0 and "(1 to run, 0 complete from before)" in p.stderr and
          job != before and cases == ["0001"], "the same command again submits that case again")
    subprocess.run(["scancel", job])
    wait_for(lambda: queue(job) == [], "the resubmitted array to leave the queue")

    # 4. refusals
    down = write("down.conf", open(os.environ["SLURM_CONF"]).read().replace(
        "SlurmctldPort=", "SlurmctldPort=1").replace("AuthInfo=", "MessageTimeout=2\nAuthInfo="))
    env = dict(os.environ, SLURM_CONF=down)
    out_d = os.path.join(WORK, "down")
    p = sweep(eight, out_d, "--engine", "slurm", env=env)
    check(p.returncode == 4 and "Slurm not reachable" in p.stderr and not os.path.exists(out_d),
          "a controller that does not answer: exit 4, 'Slurm not reachable', nothing written" +
          ("" if p.returncode == 4 else " (exit %d: %s)" % (p.returncode, p.stderr[-300:])))
    os.remove(os.path.join(out_s, "cases", "0003", "done.json"))
    kept = {c: open(os.path.join(out_s, "cases", c, "done.json")).read()
            for c in os.listdir(os.path.join(out_s, "cases")) if c != "0003"}
    p = sweep(eight, out_s, "--engine", "slurm", "--partition", "nosuch")
    check(p.returncode == 4 and "refused" in p.stderr and "partition" in p.stderr.lower(),
          "a job array refused (unknown partition): exit 4 with sbatch's reason" +
          ("" if p.returncode == 4 else " (exit %d: %s)" % (p.returncode, p.stderr[-300:])))
    check(all(open(os.path.join(out_s, "cases", c, "done.json")).read() == t
              for c, t in kept.items()), "the 7 complete cases are untouched")
    p = sweep(eight, out_s, "--engine", "slurm")
    check(p.returncode == 0 and "(1 to run, 7 complete from before)" in p.stderr and
          table(out_s) == tl, "the next call runs the one case left; the table == local again")


if __name__ == "__main__":
    sys.exit(main())
