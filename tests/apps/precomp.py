# SPDX-License-Identifier: BSD-3-Clause
"""precomp: the length pre-compensation end to end (issue 22 item 1; docs/scenarios.md
"Pre-compensation").

    python3 precomp.py CDPR_PRECOMP CDPR_SIM SOURCE_DIR TMP

1. cdpr-precomp iterates a correction for the paper's line over its first 6 s (3 model runs, 2
   linearisation poses): the model's RMS position error after 2 s must fall at least 4-fold
   (12.4 -> 1.55 mm measured).
2. cdpr-sim with that file named by the scenario (controller.precompensation) is an independent
   run through the file: its RMS after 2 s, from timeseries.csv, must be the one cdpr-precomp
   reported (the file's 6 digits).
3. The same file with the gains changed (k_length_per_s 5 -> 4) is refused at load, naming the
   key and why.
4. The shipped scenarios/paper-line-precomp.yaml over its 15 s: the issue's targets as loose
   guards (measured 1.32 mm RMS, 3.32 mm and 1.30 mrad max after 2 s, 34.8 N minimum tension):
   RMS <= 5 mm, max <= 10 mm, <= 3 mrad after 2 s, every cable-end tension >= 20 N.
5. The shipped scenarios/paper-line-full.yaml (the correction with the tension loop and its
   washout, the weight estimate and the integral) against a plant whose cabin is 10 % lighter,
   the controller's model kept nominal (controller.model.cabin_mass_scale undoes it): every
   cable-end tension >= 20 N (measured 31.2 N; 17.1 N with the same stack but no washout, the
   floor the washout restores) and RMS after 2 s <= 7 mm (measured 4.88 mm).
Exit 0 when all hold, 1 otherwise (each failure printed)."""
import csv
import math
import os
import re
import subprocess
import sys


def metrics(path):
    """RMS and max position error [m], max attitude error [rad] after 2 s; min tension [N]."""
    with open(path, encoding="utf-8") as f:
        rows = [line for line in f if not line.startswith("#")]
    reader = csv.DictReader(rows)
    s2, n, emax, rmax, tmin = 0.0, 0, 0.0, 0.0, math.inf
    for r in reader:
        tensions = [float(v) for k, v in r.items() if k.startswith("T_cabin") or
                    k.startswith("T_winch")]
        tmin = min(tmin, min(tensions))
        if float(r["t_s"]) >= 2.0 - 1e-9:
            e = float(r["epos_m"])
            s2 += e * e
            n += 1
            emax = max(emax, e)
            rmax = max(rmax, float(r["erot_rad"]))
    return math.sqrt(s2 / n), emax, rmax, tmin


def report(path):
    text = open(path, encoding="utf-8").read()
    return {k: float(re.search(r"^  %s: (\S+)$" % k, text, re.M).group(1))
            for k in ("rms_before_m", "rms_after_m")}


def main():
    precomp, sim, src, tmp = sys.argv[1:5]
    os.makedirs(tmp, exist_ok=True)
    fails = []
    scen = os.path.join(src, "scenarios", "paper-line-precomp.yaml")
    corr = os.path.join(tmp, "line6.yaml")
    r = subprocess.run([precomp, scen, corr, "--duration", "6", "--runs", "3", "--poses", "2",
                        "--quiet"], capture_output=True, text=True, timeout=900)
    print(r.stdout.strip())
    if r.returncode != 0:
        print("FAIL cdpr-precomp exit %d: %s" % (r.returncode, r.stderr))
        return 1
    rep = report(corr)
    if not rep["rms_after_m"] < rep["rms_before_m"] / 4.0:
        fails.append("the correction does not cut the error 4-fold: %s" % rep)
    # 2. the same correction through cdpr-sim and the scenario key
    text = open(scen, encoding="utf-8").read()
    mine = text.replace("precompensation: corrections/paper-line-precomp.yaml",
                        "precompensation: line6.yaml")
    assert mine != text
    with open(os.path.join(tmp, "line6-scenario.yaml"), "w", encoding="utf-8") as f:
        f.write(mine)
    out = os.path.join(tmp, "out6")
    r = subprocess.run([sim, os.path.join(tmp, "line6-scenario.yaml"), "--duration", "6", "--out",
                        out, "--no-plot", "--quiet"], capture_output=True, text=True, timeout=900)
    if r.returncode != 0:
        fails.append("cdpr-sim with the correction: exit %d: %s" % (r.returncode, r.stderr))
    else:
        rms = metrics(os.path.join(out, "timeseries.csv"))[0]
        print("cdpr-sim with it: RMS after 2 s %.4f mm (cdpr-precomp: %.4f mm)"
              % (1e3 * rms, 1e3 * rep["rms_after_m"]))
        if abs(rms - rep["rms_after_m"]) > 1e-5 * rep["rms_after_m"]:
            fails.append("cdpr-sim's RMS %.9g is not cdpr-precomp's %.9g"
                         % (rms, rep["rms_after_m"]))
    # 3. another controller: refused at load
    other = mine.replace("k_length_per_s: 5.0", "k_length_per_s: 4.0")
    assert other != mine
    with open(os.path.join(tmp, "line6-other.yaml"), "w", encoding="utf-8") as f:
        f.write(other)
    r = subprocess.run([sim, os.path.join(tmp, "line6-other.yaml"), "--duration", "6", "--out",
                        os.path.join(tmp, "out-other"), "--no-plot", "--quiet"],
                       capture_output=True, text=True, timeout=900)
    print("another controller: exit %d: %s" % (r.returncode, r.stderr.strip()[:300]))
    if r.returncode != 2 or "controller.precompensation" not in r.stderr or \
            "made for another controller gains" not in r.stderr:
        fails.append("a correction for other gains was not refused at load as expected")
    # 4. the shipped scenario and correction: the guards
    out = os.path.join(tmp, "shipped")
    r = subprocess.run([sim, scen, "--out", out, "--no-plot", "--quiet"], capture_output=True,
                       text=True, timeout=1800)
    if r.returncode != 0:
        fails.append("the shipped scenario: exit %d: %s" % (r.returncode, r.stderr))
    else:
        rms, emax, rmax, tmin = metrics(os.path.join(out, "timeseries.csv"))
        print("shipped: after 2 s RMS %.3f mm, max %.3f mm, %.3f mrad; min tension %.1f N"
              % (1e3 * rms, 1e3 * emax, 1e3 * rmax, tmin))
        for ok, what in ((rms <= 5e-3, "RMS <= 5 mm"), (emax <= 10e-3, "max <= 10 mm"),
                         (rmax <= 3e-3, "max <= 3 mrad"), (tmin >= 20.0, "tension >= 20 N")):
            if not ok:
                fails.append("shipped paper-line-precomp: not %s" % what)
    # 5. the full stack, the plant's cabin 10 % lighter than the controller's model
    sys.path.insert(0, os.path.join(src, "scripts"))
    from scenario_edit import edit  # pylint: disable=import-outside-toplevel
    full = os.path.join(src, "scenarios", "paper-line-full.yaml")
    lighter = edit(open(full, encoding="utf-8").read(), [
        ("robot.cabin.mass_kg", "36.0"),
        ("robot.cabin.inertia_kg_m2", "[[40.5, 0, 0], [0, 40.5, 0], [0, 0, 81.0]]"),
        ("controller.model.cabin_mass_scale", repr(40.0 / 36.0)),
        ("controller.precompensation",
         os.path.join(src, "scenarios", "corrections", "paper-line-full.yaml"))],
        os.path.dirname(full))
    with open(os.path.join(tmp, "full-lighter.yaml"), "w", encoding="utf-8") as f:
        f.write(lighter)
    out = os.path.join(tmp, "full-lighter")
    r = subprocess.run([sim, os.path.join(tmp, "full-lighter.yaml"), "--out", out, "--no-plot",
                        "--quiet"], capture_output=True, text=True, timeout=1800)
    if r.returncode != 0:
        fails.append("paper-line-full, cabin 10 %% lighter: exit %d: %s"
                     % (r.returncode, r.stderr))
    else:
        rms, emax, rmax, tmin = metrics(os.path.join(out, "timeseries.csv"))
        print("full stack, cabin 10 %% lighter: after 2 s RMS %.3f mm, max %.3f mm, %.3f mrad; "
              "min tension %.1f N" % (1e3 * rms, 1e3 * emax, 1e3 * rmax, tmin))
        for ok, what in ((rms <= 7e-3, "RMS <= 7 mm"), (tmin >= 20.0, "tension >= 20 N")):
            if not ok:
                fails.append("paper-line-full, cabin 10 %% lighter: not %s" % what)
    for f in fails:
        print("FAIL " + f)
    return 1 if fails else 0


if __name__ == "__main__":
    sys.exit(main())
