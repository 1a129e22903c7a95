# SPDX-License-Identifier: BSD-3-Clause
"""app_design: scripts/feedback_design.py and cdpr-design against independent results.

    python3 design_check.py SCRIPT CDPR_DESIGN SCENARIO WORKDIR [--cables N]

With --cables N (app_design_eight: the eight-cable robot, scenarios/eight-line.yaml) checks 1
and 2 on all N rate commands (the closed forms and the nonlinear plant hold for any cable
count) and prints the tension feedback's prediction; 3 and 4 compare with holds measured on
the six-cable paper line.

 1. Feed-forward only (kp = kd = 0): each rate command sees exactly the sampled integrator of
    the length loop, l(z) = k_L T / (z - 1) (the measured length is the integral of the
    payout rate), whose phase margin is 90° - asin(k_L T / 2) and whose smallest return
    difference is |1 - k_L T / 2| at the Nyquist frequency (closed forms).
 2. The linear model's open-loop response to a 1 mm/s step of one winch over 2 s against the
    nonlinear plant (cdpr_plant_step, RKF45): position and rotation within 0.2 % of their
    peak, the lengths (an exact integral) within 1e-9 m (eight cables: 0.1 mm/s, 1e-10 m).
 3. The closed-loop prediction against the measured long holds of docs/validation.md §8: the
    feed-forward alone does not grow (measured bounded over 150 s), kd_s = 0.1 s grows at the
    4-6 Hz cabin-cable modes (measured: cables slack from ~60 s).
 4. The winch tension feedback of docs/validation.md §8 (k_T 1e-3 m/s/N, tension filter
    0.05 s): not growing (measured: bounded over the 600 s holds), the loop-at-a-time margins
    at least the goal's 6 dB / 30°; its α = σ_min(I + L) and the sway's closed-loop damping
    are printed (α is below the 0.5 goal: reported, not checked).
Exit 77 (skip) without numpy/scipy.
"""
import json
import math
import os
import subprocess
import sys

try:
    import numpy  # noqa: F401
    import scipy  # noqa: F401
except ImportError:
    sys.exit(77)


def run(script, exe, scen, out, *settings, step=False, rate=1e-3):
    cmd = [sys.executable, script, scen, *settings, "--out", out, "--bin", exe]
    if step:
        cmd += ["--step-test", "0", "--step-rate", repr(rate)]
    subprocess.run(cmd, check=False, stdout=subprocess.DEVNULL)
    with open(os.path.join(out, "design.json")) as fh:
        return json.load(fh)


def main():
    script, exe, scen, work = sys.argv[1:5]
    cables = int(sys.argv[6]) if len(sys.argv) > 6 and sys.argv[5] == "--cables" else 0
    fails = []
    # The eight-cable robot responds more nonlinearly: at 1 mm/s its position differs from the
    # linear model's by 0.44 % of the peak, at 0.1 mm/s by 0.044 % (quadratic in the rate: the
    # second-order term, not a first-order error), so it is checked at 0.1 mm/s.
    r = run(script, exe, scen, os.path.join(work, "ff"), step=True, rate=1e-4 if cables else 1e-3)
    kl, T = 5.0, 0.01  # paper-line.yaml (and eight-line.yaml): k_length_per_s, run.period_s
    pm = 90.0 - math.degrees(math.asin(kl * T / 2))
    if cables and len(r["channels"]) != cables:
        fails.append("%d loop channels, the robot has %d cables" % (len(r["channels"]), cables))
    for c in r["channels"]:
        if abs(c["pm_deg"] - pm) > 1e-4:
            fails.append("cable %d: phase margin %.6f deg, closed form %.6f" %
                         (c["cable"], c["pm_deg"], pm))
    if abs(r["sigma_min_I_plus_L"] - (1 - kl * T / 2)) > 1e-4:
        fails.append("sigma_min %.6f, closed form %.6f" % (r["sigma_min_I_plus_L"], 1 - kl * T / 2))
    st = r["step_test"]
    for k in ("position", "rotation"):
        if not st[k]["max_err"] <= 2e-3 * st[k]["peak"]:
            fails.append("step %s: error %.3g of peak %.3g" % (k, st[k]["max_err"], st[k]["peak"]))
    if not st["length"]["max_err"] <= (1e-10 if cables else 1e-9):
        fails.append("step length error %.3g m" % st["length"]["max_err"])
    if not r["closed_loop_max_growth_per_s"] <= 1e-5:
        fails.append("feed-forward predicted to grow: %.3g 1/s" % r["closed_loop_max_growth_per_s"])
    print("app_design: step of winch 0: position peak %.4g m, error %.3g; rotation peak %.4g "
          "rad, error %.3g; lengths %.3g m; %d channels, phase margin %.6f deg (closed form "
          "%.6f)" % (st["position"]["peak"], st["position"]["max_err"], st["rotation"]["peak"],
                     st["rotation"]["max_err"], st["length"]["max_err"], len(r["channels"]),
                     min(c["pm_deg"] for c in r["channels"]), pm))
    if cables:
        r = run(script, exe, scen, os.path.join(work, "kt"),
                "controller.tension_gain_m_per_s_per_N=1e-3", "controller.tension_filter_s=0.05")
        lat = r["loop_at_a_time_min"]
        print("app_design: %d cables, tension feedback: growth %.3g 1/s at %.2f Hz, alpha %.3f, "
              "loop-at-a-time %.2f dB / %.1f deg" %
              (cables, r["closed_loop_max_growth_per_s"], r["closed_loop_worst_hz"],
               r["sigma_min_I_plus_L"], lat["gm_db"], lat["pm_deg"]))
        if len(r["channels"]) != cables:
            fails.append("tension feedback: %d channels" % len(r["channels"]))
        for x in fails:
            print("app_design: FAIL:", x)
        print("app_design: %s" % ("ok" if not fails else "%d failures" % len(fails)))
        return 1 if fails else 0
    r = run(script, exe, scen, os.path.join(work, "kd"), "controller.kd_s=0.1")
    g, f = r["closed_loop_max_growth_per_s"], r["closed_loop_worst_hz"]
    if not (g > 0.01 and 4.0 <= f <= 7.0):
        fails.append("kd_s 0.1: growth %.3g 1/s at %.2f Hz, measured: grows at 4-6 Hz" % (g, f))
    r = run(script, exe, scen, os.path.join(work, "kt"),
            "controller.tension_gain_m_per_s_per_N=1e-3", "controller.tension_filter_s=0.05")
    g, f = r["closed_loop_max_growth_per_s"], r["closed_loop_worst_hz"]
    lat = r["loop_at_a_time_min"]
    sway = r["closed_loop_cabin_modes_hz_zeta"][0]
    print("app_design: tension feedback: growth %.3g 1/s at %.2f Hz, alpha %.3f at %.2f Hz, "
          "loop-at-a-time %.2f dB / %.1f deg, sway %.4f Hz zeta %.3g" %
          (g, f, r["sigma_min_I_plus_L"], r["sigma_min_at_hz"], lat["gm_db"], lat["pm_deg"],
           sway[1], sway[2]))
    if not g <= 1e-5:
        fails.append("tension feedback predicted to grow: %.3g 1/s at %.2f Hz" % (g, f))
    if not (lat["gm_db"] >= 6.0 and lat["pm_deg"] >= 30.0):
        fails.append("tension feedback: loop-at-a-time %.2f dB / %.1f deg below 6 dB / 30 deg" %
                     (lat["gm_db"], lat["pm_deg"]))
    for x in fails:
        print("app_design: FAIL:", x)
    print("app_design: %s" % ("ok" if not fails else "%d failures" % len(fails)))
    return 1 if fails else 0


if __name__ == "__main__":
    sys.exit(main())
