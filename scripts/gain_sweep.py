#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""Controller gain sweep over a scenario file (docs/validation.md §8).

Runs cdpr-sim once per combination of the controller keys given on the command line and
prints one Markdown table row per run (RMS / max / final position error, RMS over the second
half, RMS attitude error, tension range, largest payout rate, IK failures). Every run gets its
own copy of the scenario in OUT/<label>/scenario.yaml (only the swept keys differ), so any row
can be rerun and plotted with cdpr-sim directly.

  scripts/gain_sweep.py SCENARIO OUT [--sim PATH] [--jobs N] [--duration S]
                        [--set section.key=VALUE ...] [--plot]
                        kp=0,0.2,0.5 kd_s=0,0.1 filter_s=0.1 inertial_ff=1

Swept keys live in the `controller:` section; --set overrides any other key once for all runs
(dotted path of an existing key, or a new leaf of an existing section), e.g.
--set "initial.offset=[0, 0, 0, 0, 0, 0]" --set trajectory.circle.ramp_s=2.0.
"""
import argparse
import itertools
import json
import os
import re
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor


def set_key(text, dotted, value):
    """Set `a.b.c: value` in YAML text written like the files in scenarios/ (2-space indent,
    one key per line). Replaces an existing leaf or inserts it as the first key of its
    parent block; value None deletes the leaf (an error if it is not there)."""
    parts = dotted.split(".")
    lines = text.split("\n")
    lo, hi = 0, len(lines)
    for depth, name in enumerate(parts):
        pat = re.compile(r"^" + " " * (2 * depth) + re.escape(name) + r":(\s|$)")
        found = None
        for i in range(lo, hi):
            if pat.match(lines[i]):
                found = i
                break
        if found is None:
            if depth == len(parts) - 1 and depth > 0 and value is not None:
                lines.insert(lo, " " * (2 * depth) + name + ": " + value)
                return "\n".join(lines)
            raise SystemExit("gain_sweep: key not found: " + dotted)
        # the block of this key ends at the next line indented <= its own indentation
        end = hi
        for i in range(found + 1, hi):
            s = lines[i]
            if s.strip() and not s.lstrip().startswith("#") and \
                    len(s) - len(s.lstrip()) <= 2 * depth:
                end = i
                break
        if depth == len(parts) - 1 and value is None:
            del lines[found:end]
            return "\n".join(lines)
        if depth == len(parts) - 1:
            comment = ""
            m = re.search(r"\s+#.*$", lines[found])
            if m:
                comment = "  " + m.group(0).strip()
            lines[found] = " " * (2 * depth) + name + ": " + value + comment
            return "\n".join(lines)
        lo, hi = found + 1, end
    return "\n".join(lines)


def run_one(sim, base_text, out, label, settings, duration, plot):
    text = base_text
    for k, v in settings:
        text = set_key(text, k, v)
    d = os.path.join(out, label)
    os.makedirs(d, exist_ok=True)
    path = os.path.join(d, "scenario.yaml")
    with open(path, "w") as f:
        f.write(text)
    # --unchecked-gains: no design check (the default) and no note about it per case
    cmd = [sim, path, "--out", d, "--quiet", "--unchecked-gains"]
    if not plot:
        cmd.append("--no-plot")
    if duration:
        cmd += ["--duration", duration]
    rc = subprocess.run(cmd, check=False).returncode
    try:
        with open(os.path.join(d, "summary.json")) as f:
            return rc, json.load(f)
    except OSError:
        return rc, None


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("scenario")
    ap.add_argument("out")
    ap.add_argument("--sim", default=os.environ.get("CDPR_SIM", "build/release/apps/cdpr-sim"))
    ap.add_argument("--jobs", type=int, default=os.cpu_count() or 1)
    ap.add_argument("--duration", default=None)
    ap.add_argument("--set", action="append", default=[], dest="fixed")
    ap.add_argument("--plot", action="store_true")
    ap.add_argument("sweep", nargs="+", help="controller key=v1,v2,...")
    a = ap.parse_args()
    with open(a.scenario) as f:
        base = f.read()
    fixed = [tuple(s.split("=", 1)) for s in a.fixed]
    keys, values = [], []
    for s in a.sweep:
        k, v = s.split("=", 1)
        keys.append(k)
        values.append(v.split(","))
    combos = list(itertools.product(*values))
    jobs = []
    for c in combos:
        label = "_".join("%s%s" % (k, v) for k, v in zip(keys, c))
        settings = fixed + [("controller." + k, v) for k, v in zip(keys, c)]
        jobs.append((label, c, settings))
    with ThreadPoolExecutor(max_workers=a.jobs) as ex:
        results = list(ex.map(lambda j: run_one(a.sim, base, a.out, j[0], j[2], a.duration,
                                                a.plot), jobs))
    print("| " + " | ".join(keys) + " | RMS / max / final [m] | RMS 2nd half [m] "
          "| attitude RMS [mrad] | tensions [N] | max payout [m/s] | IK failures |")
    print("|" + "---|" * (len(keys) + 6))
    for (label, c, _), (rc, s) in zip(jobs, results):
        if s is None:
            print("| " + " | ".join(c) + " | run failed (exit %d) | | | | | |" % rc)
            continue
        flag = "" if s["status"] == "ok" else " (%s)" % s["status"]
        print("| %s | %.4g / %.4g / %.4g%s | %.4g | %.3g | %.0f-%.0f | %.2f | %d |" % (
            " | ".join(c), s["rms_error_m"], s["max_error_m"], s["final_error_m"], flag,
            s["rms_error_second_half_m"], 1e3 * s["rms_error_rad"], s["min_tension_N"],
            s["max_tension_N"], s["max_payout_m_per_s"], s["ik_failures"]))
    sys.stdout.flush()


if __name__ == "__main__":
    main()
