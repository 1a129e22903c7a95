# SPDX-License-Identifier: BSD-3-Clause
"""app_design_xcheck: the C analysis of the check at load (lib/design, `cdpr-design --check`)
against scripts/feedback_design.py (numpy/scipy) on the same linear model.

    python3 design_xcheck.py SCRIPT CDPR_DESIGN SOURCE_DIR WORKDIR [--eight]

For each case feedback_design.py writes design.json from cdpr-design's matrices; then
`cdpr-design --check` re-linearises the same scenario copy (the matrices must be
byte-identical: the linearisation is deterministic) and prints its own analysis. Compared:
  - the zero-order hold (first case, --zoh): Phi, Gam against scipy.linalg.expm, 1e-10
    relative (Frobenius);
  - growth ln|λ|/T of the least stable closed-loop eigenvalue: 1e-6 relative + 1e-8 1/s
    (stable designs sit at 1e-9, the differences' noise); its frequency where it grows;
  - α = min σ_min(I + L) (1e-6 relative) and its grid frequency (1e-12);
  - per channel the gain and phase margins (1e-6 relative + 1e-9) and their frequencies
    (interpolated in the same grid interval: 1e-6 relative); the loop-at-a-time minima;
  - the learning (--learning): the band, the harmonics, ρ(M) and σ_max(M) at each harmonic
    (recomputed here with feedback_design's LearningPlant/learning_map at full precision,
    design.json rounds them) and G(0): 1e-6 relative.
With --eight (a build that holds eight cables) also two cases of the eight-cable robot: its
tension feedback on the line and its learning on the circle, every quantity on all eight rate
commands. The documented numbers (docs/validation.md §8) are checked to their printed digits.
Exit 77 (skip) without numpy/scipy.
"""
import json
import math
import os
import subprocess
import sys

try:
    import numpy as np
    import scipy.linalg as sla
except ImportError:
    sys.exit(77)

CASES = [
    # name, scenario, settings, learning
    ("ff", "paper-line.yaml", [], False),
    ("kd", "paper-line.yaml", ["controller.kd_s=0.1"], False),
    ("kt", "paper-line.yaml", ["controller.tension_gain_m_per_s_per_N=1e-3",
                               "controller.tension_filter_s=0.05"], False),
    ("learn03", "paper-circle.yaml", ["controller.learning_gain=0.3",
                                      "controller.learning_lead_s=0.7",
                                      "controller.learning_cutoff_hz=1"], True),
    ("learn02", "paper-circle.yaml", ["controller.learning_gain=0.2",
                                      "controller.learning_lead_s=0.7",
                                      "controller.learning_cutoff_hz=0.5"], True),
]
EIGHT = [
    ("kt8", "eight-line.yaml", ["controller.tension_gain_m_per_s_per_N=1e-3",
                                "controller.tension_filter_s=0.05"], False),
    ("learn8", "eight-circle.yaml", ["controller.learning_gain=0.2",
                                     "controller.learning_lead_s=0.7",
                                     "controller.learning_cutoff_hz=0.5"], True),
]
MATS = ("A", "B", "Kx", "Kz", "Zx", "Zz", "Ku", "Zu", "Cm", "J")

fails = []


def close(what, c, p, rel, ab=0.0):
    if p is None or c is None or (isinstance(p, float) and math.isinf(p)):
        if not (p == c):
            fails.append("%s: C %r, Python %r" % (what, c, p))
        return
    if not abs(c - p) <= rel * abs(p) + ab:
        fails.append("%s: C %.12g, Python %.12g (rel %.3g)" %
                     (what, c, p, abs(c - p) / max(abs(p), 1e-300)))


def main():
    script, exe, src, work = sys.argv[1:5]
    cases = CASES + (EIGHT if "--eight" in sys.argv[5:] else [])
    sys.path.insert(0, os.path.dirname(os.path.abspath(script)))
    import feedback_design as fd  # noqa: E402
    times = {}
    for name, scen, settings, learn in cases:
        pdir = os.path.join(work, name, "py")
        cdir = os.path.join(work, name, "c")
        os.makedirs(cdir, exist_ok=True)
        cmd = [sys.executable, script, os.path.join(src, "scenarios", scen), *settings,
               "--out", pdir, "--bin", exe] + (["--learning"] if learn else [])
        subprocess.run(cmd, check=False, stdout=subprocess.DEVNULL)
        with open(os.path.join(pdir, "design.json")) as fh:
            py = json.load(fh)
        ccmd = [exe, os.path.join(pdir, "scenario.yaml"), cdir, "--check"]
        if name == "ff":
            ccmd.append("--zoh")
        out = subprocess.run(ccmd, check=False, stdout=subprocess.PIPE)
        if out.returncode != 0:
            fails.append("%s: cdpr-design --check exited with %d" % (name, out.returncode))
            continue
        c = json.loads(out.stdout)
        times[name] = c["check_s"]
        for k in MATS:
            with open(os.path.join(pdir, k + ".bin"), "rb") as a, \
                    open(os.path.join(cdir, k + ".bin"), "rb") as b:
                if a.read() != b.read():
                    fails.append("%s: %s.bin differs between the two linearisations" % (name, k))
        m = fd.load(pdir)
        Phi, Gam = fd.discretise(m["A"], m["B"], m["T"])
        if name == "ff":
            n = m["A"].shape[0]
            P = np.fromfile(os.path.join(cdir, "Phi.bin")).reshape(n, n)
            G = np.fromfile(os.path.join(cdir, "Gam.bin")).reshape(n, m["Ku"].shape[0])
            ep = np.linalg.norm(P - Phi) / np.linalg.norm(Phi)
            eg = np.linalg.norm(G - Gam) / np.linalg.norm(Gam)
            print("app_design_xcheck: expm against scipy: Phi %.2g, Gam %.2g relative" % (ep, eg))
            if not (ep <= 1e-10 and eg <= 1e-10):
                fails.append("zero-order hold: Phi %.3g, Gam %.3g relative to scipy" % (ep, eg))
        tag = name + ": "
        close(tag + "growth", c["closed_loop_max_growth_per_s"], py["closed_loop_max_growth_per_s"],
              1e-6, 1e-8)
        if py["closed_loop_max_growth_per_s"] > 1e-5:
            close(tag + "growth Hz", c["closed_loop_worst_hz"], py["closed_loop_worst_hz"], 1e-6)
        close(tag + "alpha", c["sigma_min_I_plus_L"], py["sigma_min_I_plus_L"], 1e-6)
        close(tag + "alpha Hz", c["sigma_min_at_hz"], py["sigma_min_at_hz"], 1e-12)
        for cc, pc in zip(c["channels"], py["channels"]):
            j = "%scable %d " % (tag, pc["cable"])
            close(j + "gm_db", cc["gm_db"], pc["gm_db"], 1e-6, 1e-9)
            close(j + "gm_hz", cc["gm_hz"], pc["gm_hz"], 1e-6)
            close(j + "pm_deg", cc["pm_deg"], pc["pm_deg"], 1e-6, 1e-9)
            close(j + "pm_hz", cc["pm_hz"], pc["pm_hz"], 1e-6)
        if len(c["channels"]) != len(py["channels"]) or len(c["channels"]) != m["Ku"].shape[0]:
            fails.append(tag + "channels: C %d, Python %d" % (len(c["channels"]),
                                                              len(py["channels"])))
        if "loop_at_a_time_min" in py:
            close(tag + "min gm", c["loop_at_a_time_min"]["gm_db"],
                  py["loop_at_a_time_min"]["gm_db"], 1e-6, 1e-9)
            close(tag + "min pm", c["loop_at_a_time_min"]["pm_deg"],
                  py["loop_at_a_time_min"]["pm_deg"], 1e-6, 1e-9)
        line = ("%s growth %.6g 1/s at %.4g Hz (Python %.6g at %.4g), alpha %.6g (%.6g)" %
                (name, c["closed_loop_max_growth_per_s"], c["closed_loop_worst_hz"],
                 py["closed_loop_max_growth_per_s"], py["closed_loop_worst_hz"],
                 c["sigma_min_I_plus_L"], py["sigma_min_I_plus_L"]))
        if "loop_at_a_time_min" in py:
            line += ", loop-at-a-time %.6g dB / %.6g deg (%.6g / %.6g)" % (
                c["loop_at_a_time_min"]["gm_db"], c["loop_at_a_time_min"]["pm_deg"],
                py["loop_at_a_time_min"]["gm_db"], py["loop_at_a_time_min"]["pm_deg"])
        if learn:
            pl, cl = py["learning"], c["learning"]
            if not cl["analysed"]:
                fails.append(tag + "learning not analysed by C")
                continue
            close(tag + "band top", cl["band_top_hz"], pl["band_top_hz"], 1e-12)
            close(tag + "max rho", cl["max_rho_at_harmonics"], pl["max_rho_at_harmonics"], 1e-6)
            lp = fd.LearningPlant(m, Phi, Gam)
            lap, knots = m["lap_s"], int(m["learn_knots"])
            harm = np.arange(1, int(np.floor(pl["band_top_hz"] * lap)) + 1) / lap
            rho, smax, q = fd.learning_map(lp, harm, m["learning_gain"], m["learning_lead_s"],
                                           m["learning_cutoff_hz"], lap / knots)
            if len(cl["harmonics"]) != len(harm):
                fails.append(tag + "harmonics: C %d, Python %d" % (len(cl["harmonics"]), len(harm)))
            for k, (h, row) in enumerate(zip(harm, cl["harmonics"])):
                close(tag + "harmonic %d Hz" % (k + 1), row[0], float(h), 1e-12)
                close(tag + "harmonic %d Q" % (k + 1), row[1], float(q[k]), 1e-9)
                close(tag + "harmonic %d rho" % (k + 1), row[2], float(rho[k]), 1e-6)
                close(tag + "harmonic %d sigma_max" % (k + 1), row[3], float(smax[k]), 1e-6)
            g0 = np.real(np.diag(lp.G(1e-4)))
            if len(cl["G_at_0_diag"]) != len(g0):
                fails.append(tag + "G(0): C %d, Python %d" % (len(cl["G_at_0_diag"]), len(g0)))
            for i in range(min(len(g0), len(cl["G_at_0_diag"]))):
                close(tag + "G(0)[%d]" % i, cl["G_at_0_diag"][i], float(g0[i]), 1e-6)
            worst = int(np.argmax(rho)) + 1
            if cl["worst_harmonic"] != worst:
                fails.append(tag + "worst harmonic: C %d, Python %d" % (cl["worst_harmonic"], worst))
            line += ", rho at harmonics %s (max %.6g at %d; Python max %.6g)" % (
                " ".join("%.4f" % r[2] for r in cl["harmonics"][:6]), cl["max_rho_at_harmonics"],
                cl["worst_harmonic"], pl["max_rho_at_harmonics"])
            c["rho"] = [r[2] for r in cl["harmonics"]]
        print("app_design_xcheck:", line)
        times[name] = (c["check_s"], c)
    # The numbers docs/validation.md §8 quotes, to their printed digits.
    doc = {n: v[1] for n, v in times.items() if isinstance(v, tuple)}
    if "kd" in doc:
        g = doc["kd"]
        if not (round(g["closed_loop_max_growth_per_s"], 3) == 0.131 and
                round(g["closed_loop_worst_hz"], 2) == 5.68):
            fails.append("kd_s 0.1: not 0.131 1/s at 5.68 Hz")
    if "kt" in doc:
        g = doc["kt"]
        lat = g["loop_at_a_time_min"]
        if not (g["closed_loop_max_growth_per_s"] <= 1e-5 and round(lat["gm_db"], 1) == 8.3 and
                round(lat["pm_deg"], 1) == 36.7 and round(g["sigma_min_I_plus_L"], 3) == 0.226):
            fails.append("tension feedback: not stable at 8.3 dB / 36.7 deg, alpha 0.226")
    if "learn03" in doc:
        r = doc["learn03"]["rho"]
        if not ([k + 1 for k, v in enumerate(r) if v >= 1.0] == [2, 3, 6] and
                [round(r[k], 2) for k in (1, 2, 5)] == [1.08, 1.18, 2.21]):
            fails.append("learning 0.3/0.7/1: rho >= 1 not at harmonics 2, 3, 6 (1.08 1.18 2.21)")
    if "learn02" in doc:
        if not round(doc["learn02"]["learning"]["max_rho_at_harmonics"], 2) == 0.81:
            fails.append("learning 0.2/0.7/0.5: max rho not 0.81")
    print("app_design_xcheck: check time [s] (cdpr-design --check: load, settle, linearise, "
          "analyse): " + ", ".join("%s %.2f" % (n, v[0] if isinstance(v, tuple) else v)
                                    for n, v in times.items()))
    for x in fails:
        print("app_design_xcheck: FAIL:", x)
    print("app_design_xcheck: %s" % ("ok" if not fails else "%d failures" % len(fails)))
    return 1 if fails else 0


if __name__ == "__main__":
    sys.exit(main())
