#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""compare_runs: runs of cdpr-sim / cdpr-tracker side by side (scripts/demo.sh: the paper's line
with and without the length pre-compensation).

    compare_runs.py [--after S] [--out PREFIX] "LABEL=DIR" ...

For each DIR (holding a timeseries.csv), over t >= S (default 0): the RMS and largest position
error, the largest attitude error, and over the whole run the smallest cable-end tension; printed
as a table. With --out, PREFIX.png and PREFIX.pdf: the position error of every run against time
(matplotlib). Exit 0, or 2 when a DIR has no readable timeseries.csv."""
import argparse
import csv
import math
import sys


def load(path):
    with open(path, encoding="utf-8") as f:
        rows = [line for line in f if not line.startswith("#")]
    t, e, r, tmin = [], [], [], math.inf
    for row in csv.DictReader(rows):
        t.append(float(row["t_s"]))
        e.append(float(row["epos_m"]))
        r.append(float(row["erot_rad"]))
        tmin = min([tmin] + [float(v) for k, v in row.items()
                             if k.startswith("T_cabin") or k.startswith("T_winch")])
    return t, e, r, tmin


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--after", type=float, default=0.0)
    ap.add_argument("--out")
    ap.add_argument("runs", nargs="+")
    a = ap.parse_args()
    runs = []
    for spec in a.runs:
        label, _, d = spec.rpartition("=")
        try:
            runs.append((label or d, load(d + "/timeseries.csv")))
        except (OSError, KeyError, ValueError) as ex:
            print("compare_runs: %s: %s" % (d, ex), file=sys.stderr)
            return 2
    print("%-44s %11s %11s %11s %12s" % ("after %g s" % a.after, "RMS [mm]", "max [mm]",
                                         "max [mrad]", "min T [N]"))
    for label, (t, e, r, tmin) in runs:
        late = [i for i, ti in enumerate(t) if ti >= a.after - 1e-9]
        rms = math.sqrt(sum(e[i] ** 2 for i in late) / len(late))
        print("%-44s %11.2f %11.2f %11.2f %12.1f" % (label, 1e3 * rms,
                                                    1e3 * max(e[i] for i in late),
                                                    1e3 * max(r[i] for i in late), tmin))
    if a.out:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, ax = plt.subplots(figsize=(8, 4))
        for label, (t, e, _, _) in runs:
            ax.plot(t, [1e3 * v for v in e], label=label)
        ax.set_xlabel("t [s]")
        ax.set_ylabel("position error [mm]")
        ax.grid(True, alpha=0.3)
        ax.legend()
        fig.tight_layout()
        for ext in ("png", "pdf"):
            fig.savefig("%s.%s" % (a.out, ext), dpi=120)
        print("figure: %s.png (and .pdf)" % a.out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
