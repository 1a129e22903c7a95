#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""cdpr-sweep: run a load-case matrix of cdpr-sim scenarios here or through Slurm (docs/sweeps.md).

  cdpr-sweep SWEEP.yaml --out DIR [--jobs N] [--engine local|slurm] [--sim PATH] [--dry-run]

A sweep file names a base scenario and axes over its keys (scenario keys and, in the same
schema, the robot's: a robot file named by the scenario is inlined into every case). The cases
are the product of the axes (a `zip` axis pairs its members). Every case is written as a
resolved scenario (DIR/cases/NNNN/scenario.yaml) and checked by `cdpr-sim --validate` before
any case runs; then N workers run `cdpr-sim` on them (default: the CPU count), or, with
--engine slurm, one Slurm job array does (DIR/slurm/submit-K.sbatch, followed with squeue).
A rerun with the same DIR skips the cases whose outputs are complete and whose resolved input
is unchanged, and reruns an interrupted one. DIR/results.csv and DIR/results.json hold one row
per case. --prepare and --run-case let another runner (GNU parallel) run the cases; --collect
then writes the table.

Exit status: 0 every case completed (status ok or warnings); 1 a case failed or was killed, or
the sweep was interrupted (SIGINT/SIGTERM: the running cases stop with whole outputs and run
again on the next call); 2 a bad sweep file, a case refused by the check, or DIR holds another
sweep (nothing run, nothing written into DIR); 3 an output or input error; 4 Slurm not reachable
or the job array refused (complete cases kept).
"""
import argparse
import concurrent.futures
import copy
import csv
import hashlib
import io
import json
import math
import os
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import threading
import time

try:
    from ruamel.yaml import YAML
    from ruamel.yaml.error import YAMLError
except ImportError:  # pragma: no cover - the set-up installs it
    sys.stderr.write("cdpr-sweep: needs ruamel.yaml (Debian: apt-get install python3-ruamel.yaml)\n")
    sys.exit(3)

PROG = "cdpr-sweep"
SWEEP_KEYS = {"description", "scenario", "set", "axes"}
AXIS_KEYS = {"key", "values", "range"}
RANGE_KEYS = {"from", "to", "step", "count"}
MAX_CASES = 100000
KEY_RE = re.compile(r"^[A-Za-z_][A-Za-z0-9_]*(\[[0-9]+\])*$")


class SweepError(Exception):
    """A bad sweep file or a refused case: exit 2, nothing run."""


class OutputError(Exception):
    """A file that cannot be read or written: exit 3."""


def sha256_bytes(data):
    return hashlib.sha256(data).hexdigest()


def read_bytes(path):
    """A file's bytes, or None when it cannot be read (missing, a directory, no permission)."""
    try:
        with open(path, "rb") as f:
            return f.read()
    except OSError:
        return None


def sha256_file(path):
    data = read_bytes(path)
    return None if data is None else sha256_bytes(data)


# ------------------------------------------------------------------ the sweep file

def number(x):
    return isinstance(x, (int, float)) and not isinstance(x, bool) and math.isfinite(x)


def range_values(where, r):
    if not isinstance(r, dict) or not set(r) <= RANGE_KEYS or "from" not in r or "to" not in r:
        raise SweepError("%s: range: a mapping with from, to and step or count" % where)
    a, b = r["from"], r["to"]
    if not number(a) or not number(b):
        raise SweepError("%s: range: from and to must be finite numbers" % where)
    if ("step" in r) == ("count" in r):
        raise SweepError("%s: range: give step or count (one of them)" % where)
    if "count" in r:
        n = r["count"]
        if not isinstance(n, int) or isinstance(n, bool) or n < 1 or n > MAX_CASES:
            raise SweepError("%s: range: count must be a whole number in [1, %d]" % (where, MAX_CASES))
        if n == 1:
            return [a]
        return [a + (b - a) * i / (n - 1) for i in range(n)]
    s = r["step"]
    if not number(s) or s == 0 or (b - a) * s < 0:
        raise SweepError("%s: range: step must be a non-zero number towards 'to'" % where)
    n = int(math.floor((b - a) / s + 1e-9)) + 1
    if n > MAX_CASES:
        raise SweepError("%s: range: %d values (at most %d)" % (where, n, MAX_CASES))
    vals = [a + s * i for i in range(n)]
    if all(isinstance(v, int) for v in (a, b, s)):
        vals = [int(v) for v in vals]
    return vals


def one_axis(where, ax):
    """(key, values) of an axis mapping {key, values | range}."""
    if not isinstance(ax, dict) or not set(ax) <= AXIS_KEYS or "key" not in ax:
        raise SweepError("%s: an axis is a mapping with key and values (or range)" % where)
    key = ax["key"]
    check_key(where, key)
    if ("values" in ax) == ("range" in ax):
        raise SweepError("%s (%s): give values or range (one of them)" % (where, key))
    if "values" in ax:
        vals = ax["values"]
        if not isinstance(vals, list) or not vals:
            raise SweepError("%s (%s): values must be a non-empty list" % (where, key))
        return key, list(vals)
    return key, range_values("%s (%s)" % (where, key), ax["range"])


def check_key(where, key):
    if not isinstance(key, str) or not key:
        raise SweepError("%s: key must be a dotted key path such as robot.rope.ea_N" % where)
    for part in key.split("."):
        if not KEY_RE.match(part):
            raise SweepError("%s: key '%s': '%s' is not a key name (letters, digits, _; "
                             "[i] for a list entry)" % (where, key, part))


def parse_axes(axes):
    """A list of groups; a group is a list of (key, values) of one length (a zip, or one axis)."""
    if not isinstance(axes, list) or not axes:
        raise SweepError("axes: a non-empty list of axes")
    groups = []
    keys = set()
    for i, ax in enumerate(axes):
        where = "axes[%d]" % i
        if isinstance(ax, dict) and "zip" in ax:
            if set(ax) != {"zip"} or not isinstance(ax["zip"], list) or len(ax["zip"]) < 2:
                raise SweepError("%s: zip: a list of two or more axes (and nothing else)" % where)
            members = [one_axis("%s.zip[%d]" % (where, k), m) for k, m in enumerate(ax["zip"])]
            lengths = {len(v) for _, v in members}
            if len(lengths) != 1:
                raise SweepError("%s: zip: the axes have different lengths (%s)" % (
                    where, ", ".join("%s: %d" % (k, len(v)) for k, v in members)))
            group = members
        else:
            group = [one_axis(where, ax)]
        for k, _ in group:
            if k in keys:
                raise SweepError("%s: key %s is swept twice" % (where, k))
            keys.add(k)
        groups.append(group)
    return groups


def expand(groups):
    """Every case as a list of (key, value), in product order (the last axis fastest)."""
    n = 1
    for g in groups:
        n *= len(g[0][1])
    if n > MAX_CASES:
        raise SweepError("%d cases (at most %d)" % (n, MAX_CASES))
    cases = [[]]
    for g in groups:
        cases = [c + [(k, v[i]) for k, v in g] for c in cases for i in range(len(g[0][1]))]
    return cases


# ------------------------------------------------------------------ the scenario of a case

def split_key(key):
    out = []
    for part in key.split("."):
        name = part.split("[", 1)[0]
        out.append(name)
        out.extend(int(i) for i in re.findall(r"\[([0-9]+)\]", part))
    return out


def set_key(doc, key, value):
    """doc[key] = value for a dotted key path: missing mappings are created (the scenario's
    own check then refuses a key that does not exist), list entries must exist."""
    node = doc
    parts = split_key(key)
    for i, p in enumerate(parts):
        last = i == len(parts) - 1
        if isinstance(p, int):
            if not isinstance(node, list):
                raise SweepError("key %s: '%s' is not a list" % (key, ".".join(map(str, parts[:i]))))
            if p >= len(node):
                raise SweepError("key %s: index %d is outside the list (%d entries)" % (key, p, len(node)))
            if last:
                node[p] = value
            else:
                node = node[p]
            continue
        if not isinstance(node, dict):
            raise SweepError("key %s: '%s' is not a mapping" % (key, p))
        if last:
            node[p] = value
        else:
            if p not in node or node[p] is None:
                node[p] = {}
            node = node[p]


def plain(v):
    """A YAML value (ruamel's round-trip types included) as plain JSON/CSV data."""
    if isinstance(v, bool) or v is None:
        return v
    if isinstance(v, int):
        return int(v)
    if isinstance(v, float):
        return float(v)
    if isinstance(v, (list, tuple)):
        return [plain(x) for x in v]
    if isinstance(v, dict):
        return {str(k): plain(x) for k, x in v.items()}
    return str(v)


def load_yaml(path, what):
    try:
        with open(path, "r", encoding="utf-8") as f:
            return YAML(typ="safe").load(f)
    except OSError as e:
        raise OutputError("%s: cannot read %s: %s" % (path, what, e.strerror))
    except YAMLError as e:
        raise SweepError("%s: not a YAML %s: %s" % (path, what, str(e).splitlines()[0]))


def dump_yaml(doc):
    """A case's scenario as YAML: libyaml's emitter through ruamel.yaml's safe (C) dumper, keys
    in the base's order, short lists in flow style, every float written so that it reads back
    to the same double (1000 cases in well under a second; a round-trip dump that keeps the
    base's comments takes 10 ms a case)."""
    buf = io.StringIO()
    y = YAML(typ="safe")
    y.sort_base_mapping_type_on_output = False
    y.default_flow_style = None
    y.width = 4096
    y.dump(doc, buf)
    return buf.getvalue()


class Sweep:
    def __init__(self, path):
        self.path = path
        try:
            with open(path, "r", encoding="utf-8") as f:
                raw = YAML(typ="safe").load(f)
        except OSError as e:
            raise OutputError("%s: cannot read the sweep file: %s" % (path, e.strerror))
        except YAMLError as e:
            raise SweepError("%s: not a YAML file: %s" % (path, str(e).splitlines()[0]))
        if not isinstance(raw, dict):
            raise SweepError("%s: a sweep file is a mapping (scenario, axes, set)" % path)
        unknown = set(raw) - SWEEP_KEYS
        if unknown:
            raise SweepError("%s: unknown key %s (known: %s)" % (
                path, ", ".join(sorted(unknown)), ", ".join(sorted(SWEEP_KEYS))))
        if not isinstance(raw.get("scenario"), str):
            raise SweepError("%s: scenario: the base scenario file (relative to the sweep file)" % path)
        here = os.path.dirname(os.path.abspath(path))
        self.scenario = os.path.normpath(os.path.join(here, raw["scenario"]))
        self.fixed = raw.get("set") or {}
        if not isinstance(self.fixed, dict):
            raise SweepError("%s: set: a mapping of key paths to values" % path)
        for k in self.fixed:
            check_key("set", k)
        try:
            self.groups = parse_axes(raw.get("axes"))
        except SweepError as e:
            raise SweepError("%s: %s" % (path, e))
        self.keys = [k for g in self.groups for k, _ in g]
        clash = set(self.keys) & set(self.fixed)
        if clash:
            raise SweepError("%s: %s both set and swept" % (path, ", ".join(sorted(clash))))
        self.cases = expand(self.groups)
        self.base_text = read_bytes(self.scenario)
        if self.base_text is None:
            raise OutputError("%s: scenario: cannot read %s" % (path, self.scenario))
        base = load_yaml(self.scenario, "scenario")
        if not isinstance(base, dict):
            raise SweepError("%s: not a scenario (a mapping)" % self.scenario)
        # A robot file is inlined: one schema for both (docs/robots.md), and a case file that
        # stands alone (its hash covers the robot; no relative path to break).
        self.robot_file = None
        self.robot_sha256 = None
        robot = base.get("robot")
        if isinstance(robot, dict) and "file" in robot:
            rf = robot["file"]
            self.robot_file = os.path.normpath(os.path.join(os.path.dirname(self.scenario), str(rf)))
            self.robot_sha256 = sha256_file(self.robot_file)
            if self.robot_sha256 is None:
                raise OutputError("%s: robot.file: cannot read %s" % (self.scenario, self.robot_file))
            base["robot"] = load_yaml(self.robot_file, "robot file")
        self.base = base

    def case_text(self, values):
        doc = copy.deepcopy(self.base)
        for k, v in list(self.fixed.items()) + list(values):
            set_key(doc, k, v)
        head = "# A case of %s (cdpr-sweep):\n%s\n" % (os.path.basename(self.path), "\n".join(
            "#   %s = %s" % (k, json.dumps(plain(v))) for k, v in values))
        return head + dump_yaml(doc)


# ------------------------------------------------------------------ running

def find_sim(given):
    here = os.path.dirname(os.path.realpath(__file__))
    candidates = [given, os.environ.get("CDPR_SIM"), os.path.join(here, "cdpr-sim"),
                  os.path.join(here, "..", "..", "build", "release", "apps", "cdpr-sim"),
                  os.path.join(here, "..", "..", "build", "debug", "apps", "cdpr-sim")]
    for c in candidates:
        if c and os.path.isfile(c) and os.access(c, os.X_OK):
            return os.path.abspath(c)
    if given:
        raise OutputError("--sim %s: not an executable" % given)
    found = shutil.which("cdpr-sim")
    if found:
        return found
    raise OutputError("cdpr-sim not found (next to cdpr-sweep, in build/release or on PATH): "
                      "give --sim PATH")


def validate(sim, files, labels):
    """cdpr-sim --validate on the case files; SweepError naming each refused case."""
    problems = []
    for i in range(0, len(files), 400):
        chunk = files[i:i + 400]
        r = subprocess.run([sim, "--validate", "--quiet"] + chunk, stdout=subprocess.PIPE,
                           stderr=subprocess.PIPE, text=True)
        if r.returncode not in (0, 2):
            raise OutputError("cdpr-sim --validate exited %d: %s" % (r.returncode, r.stderr.strip()))
        for line in r.stderr.splitlines():
            for f in chunk:
                if f in line:
                    line = line.replace("cdpr-sim: ", "")
                    line = re.sub(re.escape(f) + r":([0-9]+):", lambda m: "%s, line %s of its "
                                  "scenario:" % (labels[f], m.group(1)), line)
                    line = line.replace(f, labels[f])
                    break
            problems.append(line)
    if problems:
        raise SweepError("%d case(s) refused before anything ran:\n  %s" % (
            len(problems), "\n  ".join(problems)))


def write_atomic(path, text):
    tmp = path + ".tmp"
    with open(tmp, "w", encoding="utf-8") as f:
        f.write(text)
        f.flush()
        os.fsync(f.fileno())
    os.replace(tmp, path)


def clear_case(d):
    """Remove an earlier, interrupted run's outputs from a case folder (its scenario stays)."""
    for name in os.listdir(d):
        if name != "scenario.yaml":
            p = os.path.join(d, name)
            shutil.rmtree(p) if os.path.isdir(p) else os.remove(p)


def start_sim(sim, d, log):
    return subprocess.Popen([sim, os.path.join(d, "scenario.yaml"), "--out", d, "--no-plot",
                             "--quiet"], stdout=log, stderr=subprocess.STDOUT,
                            start_new_session=True)


def finish_case(d, rc, wall, stopped):
    """Mark a finished case complete (done.json, written atomically) and return its status;
    None for an interrupted run (no done.json: the next call runs it again)."""
    status = "failed"
    try:
        with open(os.path.join(d, "summary.json")) as f:
            status = json.load(f).get("status", "failed")
    except (OSError, ValueError):
        pass
    if stopped or status == "interrupted":
        return None
    text = read_bytes(os.path.join(d, "scenario.yaml"))
    write_atomic(os.path.join(d, "done.json"), json.dumps({
        "status": status, "exit_code": rc, "input_sha256": sha256_bytes(text),
        "wall_s": round(wall, 3)}, indent=2) + "\n")
    return status


def case_complete(d):
    """True when the case folder holds a done.json for its current scenario.yaml."""
    text = read_bytes(os.path.join(d, "scenario.yaml"))
    try:
        with open(os.path.join(d, "done.json")) as f:
            return text is not None and json.load(f).get("input_sha256") == sha256_bytes(text)
    except (OSError, ValueError):
        return False


class Runner:
    def __init__(self, sim, out, jobs, quiet):
        self.sim, self.out, self.jobs, self.quiet = sim, out, jobs, quiet
        self.lock = threading.Lock()
        self.stop = threading.Event()
        self.procs = set()
        self.done = 0
        self.failed = 0
        self.durations = []

    def interrupt(self, signum, frame):
        # Under the lock: a worker either sees the stop before it starts its cdpr-sim, or its
        # cdpr-sim is registered and gets the SIGTERM (main thread only: no worker holds the
        # lock for long, and the main thread never takes it but here).
        with self.lock:
            self.stop.set()
            for p in self.procs:
                try:
                    p.send_signal(signal.SIGTERM)
                except OSError:
                    pass

    def run_case(self, cid, total_left, t0):
        d = os.path.join(self.out, "cases", cid)
        if self.stop.is_set():
            return None
        clear_case(d)
        start = time.monotonic()
        with open(os.path.join(d, "log.txt"), "w") as log:
            with self.lock:
                if self.stop.is_set():
                    return None
                p = start_sim(self.sim, d, log)
                self.procs.add(p)
            rc = p.wait()
            with self.lock:
                self.procs.discard(p)
        wall = time.monotonic() - start
        status = finish_case(d, rc, wall, self.stop.is_set())
        if status is None:
            return None  # not done: the next call runs it again
        with self.lock:
            self.done += 1
            self.durations.append(wall)
            bad = rc != 0 or status not in ("ok", "warnings")
            self.failed += 1 if bad else 0
            if not self.quiet:
                left = total_left - self.done
                mean = sum(self.durations) / len(self.durations)
                eta = mean * left / max(1, min(self.jobs, left)) if left > 0 else 0.0
                sys.stderr.write("%s: [%d/%d] case %s %s (exit %d, %.1f s); %d failed; "
                                 "elapsed %s, ETA %s\n" % (
                                     PROG, self.done, total_left, cid, status, rc, wall,
                                     self.failed, hms(time.monotonic() - t0), hms(eta)))
        return rc

    def run(self, todo):
        t0 = time.monotonic()
        with concurrent.futures.ThreadPoolExecutor(max_workers=self.jobs) as ex:
            futs = [ex.submit(self.run_case, cid, len(todo), t0) for cid in todo]
            # Wait with a timeout, never in one untimed wait: the kernel may deliver SIGINT or
            # SIGTERM to a worker thread (blocked in its cdpr-sim's wait), and Python runs the
            # handler (interrupt) only in the main thread when that thread runs; an untimed
            # wait here never woke for it, and the sweep hung with its cases running (seen
            # once in sweep_local under load).
            pending = set(futs)
            while pending:
                _, pending = concurrent.futures.wait(pending, timeout=0.1)
            for f in futs:
                f.result()


# ------------------------------------------------------------------ the Slurm engine

class EngineError(Exception):
    """Slurm not reachable, or the job array refused: exit 4 (finished cases are kept)."""


def run_case_main(case_dir, sim):
    """`cdpr-sweep --run-case DIR/cases/NNNN`: what one array task of the Slurm engine runs.
    Runs the case as the local engine does and marks it complete; a SIGTERM (Slurm's time limit
    or scancel) is passed on to cdpr-sim, which writes whole outputs, and no done.json is written,
    so that the next call runs the case again. A case already complete is not run twice."""
    d = os.path.abspath(case_dir)
    if not os.path.isfile(os.path.join(d, "scenario.yaml")):
        raise OutputError("%s: not a case folder (no scenario.yaml)" % d)
    if case_complete(d):
        return 0
    stopped = threading.Event()
    proc = []

    def on_signal(signum, frame):
        stopped.set()
        for p in proc:
            try:
                p.send_signal(signal.SIGTERM)
            except OSError:
                pass

    signal.signal(signal.SIGTERM, on_signal)
    signal.signal(signal.SIGINT, on_signal)
    clear_case(d)
    start = time.monotonic()
    with open(os.path.join(d, "log.txt"), "w") as log:
        if stopped.is_set():
            return 143
        proc.append(start_sim(sim, d, log))
        if stopped.is_set():  # a signal while it started: pass it on
            on_signal(signal.SIGTERM, None)
        rc = proc[0].wait()
    status = finish_case(d, rc, time.monotonic() - start, stopped.is_set())
    if status is None:
        sys.stderr.write("%s: case %s interrupted (outputs whole; not complete)\n" % (
            PROG, os.path.basename(d)))
        return 143
    return rc


def slurm_command(args, what):
    """A Slurm client command's stdout; EngineError with its own message when it fails."""
    try:
        r = subprocess.run(args, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                           timeout=120)
    except FileNotFoundError:
        raise EngineError("%s: %s not found: is Slurm's client installed (Debian: slurm-client)?"
                          % (what, args[0]))
    except subprocess.TimeoutExpired:
        raise EngineError("%s: %s did not answer in 120 s" % (what, " ".join(args[:2])))
    if r.returncode != 0:
        msg = " ".join(r.stderr.split()) or "exit %d" % r.returncode
        raise EngineError("%s: %s" % (what, msg))
    return r.stdout


def sh_quote(x):
    return "'" + str(x).replace("'", "'\\''") + "'"


class Slurm:
    """Runs the cases as one Slurm job array per call (docs/sweeps.md): writes a batch script,
    submits it with sbatch, follows the array with squeue and leaves the table to the caller.
    The array's job name is made from the output folder, so that a rerun finds this sweep's
    tasks still queued or running (its own or a user's submission of the script) and follows
    them instead of submitting their cases again."""

    def __init__(self, a, sweep_path, sim, out):
        self.a, self.sim, self.out = a, sim, out
        self.name = "cdpr-sweep-" + sha256_bytes(out.encode("utf-8"))[:10]
        self.dir = os.path.join(out, "slurm")
        self.sweep_path = os.path.abspath(sweep_path)
        self.job = None

    def ping(self):
        """Before anything is written: the controller answers."""
        text = slurm_command(["scontrol", "ping"], "Slurm not reachable (scontrol ping)")
        if "UP" not in text:
            raise EngineError("Slurm not reachable: scontrol ping says: %s" % " ".join(text.split()))

    def active(self):
        """Array tasks of this sweep still in the queue: [(job id, state)]."""
        text = slurm_command(["squeue", "--noheader", "--array", "--name", self.name,
                              "--format", "%i %T"], "squeue")
        return [tuple(line.split()[:2]) for line in text.splitlines() if line.strip()]

    def script(self, k, todo):
        a = self.a
        lines = ["#!/bin/sh",
                 "# Generated by cdpr-sweep for %s: %d case(s), one array task each (the case" % (
                     self.sweep_path, len(todo)),
                 "# ids are the lines of submit-%d.cases). Submitted by cdpr-sweep --engine slurm;" % k,
                 "# to change it, edit and submit it yourself (sbatch %s)," % (
                     os.path.join(self.dir, "submit-%d.sbatch" % k)),
                 "# then run cdpr-sweep again to follow the job and collect the table.",
                 "#SBATCH --job-name=%s" % self.name,
                 "#SBATCH --array=1-%d%s" % (len(todo), "%%%d" % a.jobs if a.jobs else ""),
                 "#SBATCH --output=%s" % os.path.join(self.dir, "%A_%a.out"),
                 "#SBATCH --ntasks=1",
                 "#SBATCH --cpus-per-task=1"]
        for opt, val in (("partition", a.partition), ("time", a.time), ("mem", a.mem)):
            if val:
                lines.append("#SBATCH --%s=%s" % (opt, val))
        for extra in a.slurm_option or []:
            lines.append("#SBATCH %s" % extra)
        lines += ["set -eu",
                  "case_id=$(sed -n \"${SLURM_ARRAY_TASK_ID}p\" %s)" % sh_quote(
                      os.path.join(self.dir, "submit-%d.cases" % k)),
                  "exec %s %s --run-case %s --sim %s" % (
                      sh_quote(sys.executable), sh_quote(os.path.realpath(__file__)),
                      "\"%s/$case_id\"" % os.path.join(self.out, "cases"), sh_quote(self.sim)),
                  ""]
        return "\n".join(lines)

    def submit(self, todo):
        os.makedirs(self.dir, exist_ok=True)
        k = 1
        while os.path.exists(os.path.join(self.dir, "submit-%d.sbatch" % k)):
            k += 1
        write_atomic(os.path.join(self.dir, "submit-%d.cases" % k), "".join(c + "\n" for c in todo))
        path = os.path.join(self.dir, "submit-%d.sbatch" % k)
        write_atomic(path, self.script(k, todo))
        text = slurm_command(["sbatch", "--parsable", path],
                             "the job array was refused (sbatch %s)" % path)
        self.job = text.strip().split(";")[0]
        with open(os.path.join(self.dir, "jobs.txt"), "a") as f:
            f.write("%s submit-%d.sbatch %d\n" % (self.job, k, len(todo)))
        return self.job

    def follow(self, cases, stop, quiet):
        """Poll until no task of this sweep is queued or running; progress from the cases'
        done.json files. On stop (SIGINT/SIGTERM) cancel the array once (its tasks get SIGTERM
        and write whole outputs) and wait for it to drain."""
        t0 = time.monotonic()
        cancelled = False
        seen = -1
        misses = 0
        while True:
            try:
                tasks = self.active()
                misses = 0
            except EngineError:
                misses += 1  # a controller restart: keep asking for a while
                if misses * self.a.poll > 300:
                    raise
                tasks = None
            if stop.is_set() and not cancelled:
                slurm_command(["scancel", "--name", self.name], "scancel")
                cancelled = True
            done = sum(1 for c in cases if case_complete(os.path.join(self.out, "cases", c)))
            if not quiet and tasks is not None and (done != seen or not tasks):
                running = sum(1 for _, st in tasks if st == "RUNNING")
                sys.stderr.write("%s: [%d/%d] complete; %d running, %d queued; elapsed %s\n" % (
                    PROG, done, len(cases), running, len(tasks) - running,
                    hms(time.monotonic() - t0)))
                seen = done
            if tasks == []:
                return
            time.sleep(self.a.poll)

    def timed_out(self):
        """Case ids whose last task log says Slurm killed it at its time limit."""
        out = set()
        if not os.path.isdir(self.dir):
            return out
        for name in os.listdir(self.dir):
            if not name.endswith(".out"):
                continue
            text = read_bytes(os.path.join(self.dir, name)) or b""
            if b"DUE TO TIME LIMIT" in text:
                m = re.match(r"^([0-9]+)_([0-9]+)\.out$", name)
                cases = self.cases_of(m.group(1)) if m else []
                i = int(m.group(2)) - 1 if m else -1
                if 0 <= i < len(cases):
                    out.add(cases[i])
        return out

    def cases_of(self, job):
        try:
            with open(os.path.join(self.dir, "jobs.txt")) as f:
                for line in f:
                    j, script, _ = line.split()
                    if j == job:
                        cases = script.replace(".sbatch", ".cases")
                        with open(os.path.join(self.dir, cases)) as g:
                            return g.read().split()
        except (OSError, ValueError):
            pass
        return []


def hms(s):
    s = int(round(s))
    return "%d:%02d:%02d" % (s // 3600, s // 60 % 60, s % 60)


# ------------------------------------------------------------------ the results table

FIGURES = ["rms_error_m", "max_error_m", "final_error_m", "rms_error_rad", "max_error_rad",
           "max_tension_N", "min_tension_N", "max_payout_m_per_s", "node_insertions",
           "node_removals", "ik_failures", "substep_limit_hits", "capacity_hits", "periods",
           "rhs_evals", "sim_time_s", "wall_time_s"]


def results(sweep, out, ids):
    rows = []
    for cid, values in zip(ids, sweep.cases):
        d = os.path.join(out, "cases", cid)
        row = {"case": cid}
        for k, v in values:
            row[k] = json.dumps(plain(v)) if isinstance(plain(v), (list, dict)) else plain(v)
        done = None
        try:
            with open(os.path.join(d, "done.json")) as f:
                done = json.load(f)
        except (OSError, ValueError):
            pass
        summ = {}
        try:
            with open(os.path.join(d, "summary.json")) as f:
                summ = json.load(f)
        except (OSError, ValueError):
            summ = {}
        if done:
            row["status"] = done["status"]
        else:  # an interrupted run's figures are partial: status only
            row["status"] = "interrupted" if summ.get("status") == "interrupted" else "not run"
            summ = {}
        row["exit_code"] = done["exit_code"] if done else None
        row["input_sha256"] = done["input_sha256"] if done else None
        row["robot_file_sha256"] = sweep.robot_sha256
        row["version"] = summ.get("version")
        row["scenario_sha256"] = summ.get("scenario_sha256")
        for k in FIGURES:
            row[k] = summ.get(k)
        for key, col in (("slack_periods", "slack_periods_%d"),
                         ("rate_limited_periods", "rate_limited_periods_%d"),
                         ("cable_min_tension_N", "T%d_min_N"), ("cable_max_tension_N", "T%d_max_N")):
            per_cable = summ.get(key)
            if isinstance(per_cable, list):
                for j, v in enumerate(per_cable, 1):
                    row[col % j] = v
        row["parameters"] = summ.get("parameters")  # results.json only: the resolved values
        rows.append(row)
    cols = []
    for r in rows:
        for k in r:
            if k not in cols and k != "parameters":
                cols.append(k)
    with open(os.path.join(out, "results.csv.tmp"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=cols, lineterminator="\n")
        w.writeheader()
        for r in rows:
            w.writerow({k: ("" if r.get(k) is None else r.get(k)) for k in cols})
    os.replace(os.path.join(out, "results.csv.tmp"), os.path.join(out, "results.csv"))
    write_atomic(os.path.join(out, "results.json"), json.dumps(rows, indent=1) + "\n")
    return rows


# ------------------------------------------------------------------ figures

PLOTTED = [("rms_error_m", "RMS position error [m]"), ("max_error_m", "max position error [m]"),
           ("rms_error_rad", "RMS attitude error [rad]"), ("max_tension_N", "max tension [N]"),
           ("min_tension_N", "min tension [N]")]


def figures(sweep, out, rows):
    """DIR/figures/METRIC_vs_KEY.{png,svg}: each figure of merit against each swept key, one
    line per combination of the other keys' values (at most 12; categorical values such as
    vectors are placed at equal steps and labelled). Completed cases only. Returns the count."""
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        sys.stderr.write("%s: no figures: matplotlib is missing (python3-matplotlib)\n" % PROG)
        return 0
    ok = [r for r in rows if r["status"] in ("ok", "warnings")]
    if not ok:
        return 0
    d = os.path.join(out, "figures")
    os.makedirs(d, exist_ok=True)
    n = 0
    for key in sweep.keys:
        xs = []
        for r in ok:
            if r[key] not in xs:
                xs.append(r[key])
        numeric = all(isinstance(x, (int, float)) for x in xs)
        pos = {x: (x if numeric else i) for i, x in enumerate(xs)}
        others = [k for k in sweep.keys if k != key]
        for metric, label in PLOTTED:
            lines = {}
            for r in ok:
                if isinstance(r.get(metric), (int, float)):
                    tag = ", ".join("%s = %s" % (k, r[k]) for k in others)
                    lines.setdefault(tag, []).append((pos[r[key]], r[metric]))
            if not lines:
                continue
            fig, ax = plt.subplots(figsize=(7.0, 4.2))
            for i, (tag, pts) in enumerate(sorted(lines.items())[:12]):
                pts.sort()
                ax.plot([p[0] for p in pts], [p[1] for p in pts], marker="o", label=tag or None)
            if not numeric:
                ax.set_xticks(range(len(xs)))
                ax.set_xticklabels([str(x) for x in xs], rotation=30, ha="right", fontsize=8)
            ax.set_xlabel(key)
            ax.set_ylabel(label)
            ax.set_title("%s: %s" % (os.path.basename(sweep.path), label), fontsize=10)
            ax.grid(True, alpha=0.3)
            if len(lines) > 1:
                ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0), frameon=False)
            fig.tight_layout()
            stem = os.path.join(d, "%s_vs_%s" % (metric, re.sub(r"[^A-Za-z0-9_.-]", "_", key)))
            fig.savefig(stem + ".png", dpi=120)
            fig.savefig(stem + ".svg")
            plt.close(fig)
            n += 1
    return n + heat_maps(sweep, d, ok, plt)


def label(v):
    return "%.4g" % v if isinstance(v, float) else str(v)


def heat_maps(sweep, d, ok, plt):
    """DIR/figures/METRIC_map_A_B[_at_K=V...].{png,svg}: each figure of merit over each pair of
    swept keys that are not zipped together (A across, B up), one map per combination of the
    values of the keys outside their axes (the first 4), cells at equal steps labelled with the
    keys' values and, up to 12 x 12, the figure's value. A case that did not complete is a
    blank cell."""
    n = 0
    keys = sweep.keys
    group = {k: i for i, g in enumerate(sweep.groups) for k, _ in g}
    for ia in range(len(keys)):
        for ib in range(ia + 1, len(keys)):
            a, b = keys[ia], keys[ib]
            if group[a] == group[b]:
                continue  # zipped: one moves with the other
            # The keys zipped with a or b move with them; the others are held at each value.
            others = [k for k in keys if group[k] not in (group[a], group[b])]
            xa, xb, combos = [], [], []
            for r in ok:
                xa += [r[a]] if r[a] not in xa else []
                xb += [r[b]] if r[b] not in xb else []
                c = tuple(r[k] for k in others)
                combos += [c] if c not in combos else []
            if len(xa) < 2 or len(xb) < 2:
                continue
            for combo in combos[:4]:
                at = dict(zip(others, combo))
                for metric, title in PLOTTED:
                    grid = [[float("nan")] * len(xa) for _ in xb]
                    for r in ok:
                        if all(r[k] == at[k] for k in others) and \
                                isinstance(r.get(metric), (int, float)):
                            grid[xb.index(r[b])][xa.index(r[a])] = r[metric]
                    if all(math.isnan(v) for row in grid for v in row):
                        continue
                    fig, ax = plt.subplots(figsize=(7.0, 4.8))
                    im = ax.imshow(grid, origin="lower", aspect="auto", cmap="viridis")
                    fig.colorbar(im, ax=ax, label=title)
                    ax.set_xticks(range(len(xa)))
                    ax.set_xticklabels([label(x) for x in xa], rotation=30, ha="right", fontsize=8)
                    ax.set_yticks(range(len(xb)))
                    ax.set_yticklabels([label(x) for x in xb], fontsize=8)
                    ax.set_xlabel(a)
                    ax.set_ylabel(b)
                    if len(xa) <= 12 and len(xb) <= 12:
                        lo = min(v for row in grid for v in row if not math.isnan(v))
                        hi = max(v for row in grid for v in row if not math.isnan(v))
                        for i, row in enumerate(grid):
                            for j, v in enumerate(row):
                                if not math.isnan(v):
                                    dark = hi > lo and (v - lo) / (hi - lo) < 0.5
                                    ax.text(j, i, "%.4g" % v, ha="center", va="center",
                                            fontsize=7, color="white" if dark else "black")
                    where = ", ".join("%s = %s" % (k, label(v)) for k, v in at.items())
                    ax.set_title("%s: %s%s" % (os.path.basename(sweep.path), title,
                                               "\n(%s)" % where if where else ""), fontsize=9)
                    fig.tight_layout()
                    name = "%s_map_%s_%s%s" % (metric, a, b, "".join(
                        "_at_%s=%s" % (k, label(v)) for k, v in at.items()))
                    stem = os.path.join(d, re.sub(r"[^A-Za-z0-9_.=-]", "_", name))
                    fig.savefig(stem + ".png", dpi=120)
                    fig.savefig(stem + ".svg")
                    plt.close(fig)
                    n += 1
    return n


# ------------------------------------------------------------------ main

class Parser(argparse.ArgumentParser):
    """Usage errors as the other apps give them: one line, exit status 2."""

    def error(self, message):
        m = re.match(r"argument (\S+/)?(--[a-z-]+): (expected one argument|ignored explicit "
                     r"argument .*)$", message)
        if m:
            message = ("option '%s' requires an argument" if m.group(3).startswith("expected")
                       else "option '%s' doesn't allow an argument") % m.group(2)
        sys.stderr.write("%s: %s; try '%s --help'\n" % (PROG, message, PROG))
        sys.exit(2)


class Version(argparse.Action):
    """--version: this tool's line with the version of the cdpr-sim it runs."""

    def __call__(self, parser, namespace, values, option_string=None):
        try:
            sim = find_sim(getattr(namespace, "sim", None))
            line = subprocess.run([sim, "--version"], stdout=subprocess.PIPE, text=True).stdout
            print("%s %s" % (PROG, line.strip().split(" ", 1)[1]))
        except (OutputError, IndexError, OSError) as e:
            sys.stderr.write("%s: --version: %s\n" % (PROG, e))
            sys.exit(3)
        sys.exit(0)


def main(argv):
    ap = Parser(prog=PROG, description=__doc__.splitlines()[0],
                formatter_class=argparse.RawDescriptionHelpFormatter,
                epilog="\n".join(__doc__.splitlines()[2:]))
    ap.add_argument("sweep", nargs="?", help="the sweep file (YAML)")
    ap.add_argument("--out", help="output directory (required; created; a rerun resumes)")
    ap.add_argument("--jobs", type=int,
                    help="cases run at once (local default: the CPU count, %d here; slurm: the "
                    "array's throttle, default none)" % (os.cpu_count() or 1))
    ap.add_argument("--engine", choices=["local", "slurm"], default="local",
                    help="where the cases run: this machine (default) or a Slurm job array")
    ap.add_argument("--partition", help="slurm: the partition (sbatch --partition)")
    ap.add_argument("--time", help="slurm: each case's time limit (sbatch --time, e.g. 30 or "
                    "1:00:00); a case killed at it keeps whole outputs and runs again on resume")
    ap.add_argument("--mem", help="slurm: memory per case (sbatch --mem, e.g. 1G)")
    ap.add_argument("--slurm-option", action="append", metavar="OPT",
                    help="slurm: one more #SBATCH line, verbatim (repeatable), e.g. "
                    "--slurm-option=--account=wind")
    ap.add_argument("--no-wait", action="store_true",
                    help="slurm: submit and exit; the same command again follows and collects")
    ap.add_argument("--poll", type=float, default=5.0,
                    help="slurm: seconds between squeue calls (default %(default)s)")
    ap.add_argument("--prepare", action="store_true",
                    help="write the case folders, print those not complete (one a line), run "
                    "nothing: for another runner (GNU parallel with --run-case)")
    ap.add_argument("--collect", action="store_true",
                    help="run nothing: write the table and figures from the complete cases")
    ap.add_argument("--run-case", metavar="CASE_DIR",
                    help="run one case folder (what a Slurm array task runs) and exit")
    ap.add_argument("--sim", help="the cdpr-sim to run (default: next to cdpr-sweep, then "
                    "build/release, then PATH)")
    ap.add_argument("--dry-run", action="store_true",
                    help="expand and check the cases, list them, run nothing")
    ap.add_argument("--quiet", action="store_true", help="no progress lines")
    ap.add_argument("--no-figures", action="store_true",
                    help="no DIR/figures (each figure of merit against each swept key)")
    ap.add_argument("--version", action=Version, nargs=0,
                    help="version and git description (those of the cdpr-sim it runs)")
    a, extra = ap.parse_known_args(argv)
    for x in extra:  # as getopt says it, options first
        if x.startswith("--"):
            ap.error("unrecognized option '%s'" % x)
        if x.startswith("-") and len(x) > 1:
            ap.error("invalid option -- '%s'" % x[1])
    if extra:
        ap.error("one sweep file (got '%s' too)" % extra[0])
    if a.run_case is not None:
        try:
            return run_case_main(a.run_case, find_sim(a.sim))
        except OutputError as e:
            sys.stderr.write("%s: %s\n" % (PROG, e))
            return 3
    if a.sweep is None:
        ap.error("a sweep file is required")
    if a.out is None:
        ap.error("--out DIR is required")
    if a.jobs is not None and a.jobs < 1:
        ap.error("--jobs: at least 1")
    if a.prepare and a.collect:
        ap.error("--prepare and --collect: one of them")
    if (a.prepare or a.collect) and a.engine != "local":
        ap.error("--%s: runs nothing, so takes no --engine" % ("prepare" if a.prepare else
                                                               "collect"))
    if a.engine == "local":
        for opt in ("partition", "time", "mem", "slurm_option", "no_wait"):
            if getattr(a, opt):
                ap.error("--%s: for --engine slurm only" % opt.replace("_", "-"))
        a.jobs = a.jobs or os.cpu_count() or 1
    if not a.poll > 0:
        ap.error("--poll: a positive number of seconds")
    try:
        return sweep_main(a)
    except KeyboardInterrupt:  # before the workers start (expansion, check): nothing written
        sys.stderr.write("%s: interrupted before any case ran\n" % PROG)
        return 1
    except SweepError as e:
        sys.stderr.write("%s: %s\n" % (PROG, e))
        return 2
    except OutputError as e:
        sys.stderr.write("%s: %s\n" % (PROG, e))
        return 3
    except EngineError as e:
        sys.stderr.write("%s: %s; finished cases are kept\n" % (PROG, e))
        return 4


def sweep_main(a):
    t_start = time.monotonic()
    sweep = Sweep(a.sweep)
    sim = find_sim(a.sim)
    n = len(sweep.cases)
    width = max(4, len(str(n)))
    ids = ["%0*d" % (width, i + 1) for i in range(n)]
    texts = [sweep.case_text(v) for v in sweep.cases]
    hashes = [sha256_bytes(t.encode("utf-8")) for t in texts]
    out = os.path.abspath(a.out)
    record_path = os.path.join(out, "sweep.json")
    if os.path.exists(record_path):
        try:
            with open(record_path) as f:
                old = json.load(f)
        except (OSError, ValueError) as e:
            raise SweepError("%s: exists but cannot be read (%s): another sweep's? nothing "
                             "touched" % (record_path, e))
        if [c.get("input_sha256") for c in old.get("cases", [])] != hashes:
            raise SweepError("%s holds another sweep (%s, %d cases): give another --out; "
                             "nothing touched" % (out, old.get("sweep"), len(old.get("cases", []))))
    elif os.path.isdir(out) and os.listdir(out):
        raise SweepError("%s is not empty and holds no sweep: give another --out; nothing "
                         "touched" % out)

    # Check every case before anything runs (in a scratch folder: DIR is not touched yet).
    t_check = time.monotonic()
    scratch = tempfile.mkdtemp(prefix="cdpr-sweep-")
    try:
        files, labels = [], {}
        for cid, values, text in zip(ids, sweep.cases, texts):
            f = os.path.join(scratch, cid + ".yaml")
            with open(f, "w", encoding="utf-8") as fh:
                fh.write(text)
            files.append(f)
            labels[f] = "case %s (%s)" % (cid, ", ".join(
                "%s = %s" % (k, json.dumps(plain(v))) for k, v in values))
        validate(sim, files, labels)
    finally:
        shutil.rmtree(scratch, ignore_errors=True)
    t_check = time.monotonic() - t_check

    if a.dry_run:
        for cid, values in zip(ids, sweep.cases):
            print("%s  %s" % (cid, "  ".join("%s=%s" % (k, json.dumps(plain(v))) for k, v in values)))
        sys.stderr.write("%s: %d cases pass the check (%.2f s); nothing run\n" % (PROG, n, t_check))
        return 0

    slurm = None
    if a.engine == "slurm":
        slurm = Slurm(a, a.sweep, sim, out)
        slurm.ping()  # before anything is written
    stop = threading.Event()
    runner = None
    followed = False  # a call that followed an earlier array submits nothing (one per call)

    def interrupt(signum, frame):
        if runner is not None:
            runner.interrupt(signum, frame)
        stop.set()

    old_int = signal.signal(signal.SIGINT, interrupt)
    old_term = signal.signal(signal.SIGTERM, interrupt)
    try:
        try:
            os.makedirs(os.path.join(out, "cases"), exist_ok=True)
            if not os.path.exists(record_path):
                write_atomic(record_path, json.dumps({
                    "sweep": os.path.abspath(a.sweep), "sweep_sha256": sha256_file(a.sweep),
                    "scenario": sweep.scenario, "scenario_sha256": sha256_bytes(sweep.base_text),
                    "robot_file": sweep.robot_file, "robot_file_sha256": sweep.robot_sha256,
                    "keys": sweep.keys, "set": plain(sweep.fixed),
                    "cases": [{"case": cid, "values": {k: plain(v) for k, v in vals},
                               "input_sha256": h} for cid, vals, h in zip(ids, sweep.cases, hashes)],
                }, indent=1) + "\n")
            if slurm is not None:
                queued = slurm.active()
                if queued:  # an earlier call's array (or the user's): follow it, submit nothing
                    jobs = sorted({j.split("_")[0] for j, _ in queued})
                    sys.stderr.write("%s: job %s of this sweep still has %d task(s) queued or "
                                     "running%s\n" % (PROG, ", ".join(jobs), len(queued),
                                                       "" if a.no_wait else ": following it"))
                    if a.no_wait:
                        return 0
                    slurm.follow(ids, stop, a.quiet)
                    followed = True
            todo = []
            for cid, text, h in zip(ids, texts, hashes):
                d = os.path.join(out, "cases", cid)
                os.makedirs(d, exist_ok=True)
                done = os.path.join(d, "done.json")
                if os.path.exists(done):
                    try:
                        with open(done) as f:
                            if json.load(f).get("input_sha256") == h:
                                continue  # complete, same input: kept
                    except (OSError, ValueError):
                        pass
                    os.remove(done)
                write_atomic(os.path.join(d, "scenario.yaml"), text)
                todo.append(cid)
        except OSError as e:
            raise OutputError("%s: %s" % (e.filename or out, e.strerror))

        if a.prepare:
            for cid in todo:
                print(os.path.join(out, "cases", cid))
            sys.stderr.write("%s: %d cases written, %d not complete (listed); nothing run\n" % (
                PROG, n, len(todo)))
            return 0
        if a.collect:
            sys.stderr.write("%s: %d cases, %d complete; collecting, running nothing\n" % (
                PROG, n, n - len(todo)))
            todo = []
        elif followed:
            sys.stderr.write("%s: %d cases, %d not complete after the earlier job array%s\n" % (
                PROG, n, len(todo), ": run the same command again to submit them" if todo else ""))
        elif not a.quiet:
            sys.stderr.write("%s: %d cases (%d to run, %d complete from before), %s, cdpr-sim %s\n"
                             % (PROG, n, len(todo), n - len(todo),
                                "Slurm job array" if slurm else "%d workers" % min(
                                    a.jobs, max(1, len(todo))), sim))
        if slurm is None:
            runner = Runner(sim, out, min(a.jobs, max(1, len(todo))), a.quiet)
            if stop.is_set():
                runner.stop.set()
            runner.run(todo)
        elif todo and not stop.is_set() and not followed:
            job = slurm.submit(todo)
            sys.stderr.write("%s: submitted job array %s (%d tasks): %s\n" % (
                PROG, job, len(todo), os.path.join(slurm.dir, "jobs.txt")))
            if a.no_wait:
                sys.stderr.write("%s: not waiting: run the same command again to follow the "
                                 "job and collect the table\n" % PROG)
                return 0
            slurm.follow(todo, stop, a.quiet)
    finally:
        signal.signal(signal.SIGINT, old_int)
        signal.signal(signal.SIGTERM, old_term)
    rows = results(sweep, out, ids)
    n_fig = 0 if a.no_figures else figures(sweep, out, rows)
    bad = [r for r in rows if r["status"] not in ("ok", "warnings") or r["exit_code"] not in (0,)]
    if not a.quiet:
        sys.stderr.write("%s: %d of %d cases completed, %d failed or not run; %s/results.csv, "
                         "%d figures in %s/figures (%.1f s in all, check %.2f s)\n" % (
                             PROG, n - len(bad), n, len(bad), out, n_fig, out,
                             time.monotonic() - t_start, t_check))
    if slurm is not None:
        late = sorted(c for c in slurm.timed_out() if not case_complete(
            os.path.join(out, "cases", c)))
        if late:
            sys.stderr.write("%s: killed at the time limit (--time): case %s; their outputs are "
                             "whole; run again (with a longer --time) to rerun them\n" % (
                                 PROG, ", ".join(late)))
    if stop.is_set():
        sys.stderr.write("%s: interrupted: run the same command again to finish\n" % PROG)
        return 1
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
