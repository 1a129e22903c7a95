#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""ctest python_statics: cdprlib.Robot, a robot file's statics from Python (docs/python.md),
against an independent solution written here.

  python_statics.py CDPR_SIM SOURCE_DIR WORK_DIR

1. Six cables (robots/paper-50m.yaml): Robot.ik at the nominal pose gives the lengths of
   Plant.ik on the paper's circle (the same robot: bit for bit).
2. Eight cables (a robot file written here: four towers 25 m out, 30 m high, two cables each;
   the 50 m model's rope and 40 kg cabin), bounds 25-500 N: at three poses the distribution
   agrees with scipy's SLSQP on the whole problem written again here (the elastic catenary
   in Irvine's closed form, 8 x (H, V, L) unknowns, wrench and span equations, the criterion
   and bounds on the lowest/highest tension along each cable), started 3 % away from
   cdprlib's answer: the same lengths to 1e-6 m and tensions to 1e-4 N, and scipy's criterion
   no lower than cdprlib's. The catenary here matches cdprlib.catenary_point to 1e-9 m.
3. The shipped eight-cable robot (robots/eight-50m.yaml) through cdpr-sim on the paper's line
   (scenarios/eight-line.yaml: the plant's start and the tracker's feed-forward resolve the
   redundancy with the robot's distribution): no IK failure; the plant's unstretched lengths at
   the end are the distribution's IK at the line's end pose (1e-4 m); holding there, the winch
   tensions averaged over t >= 11 s are the distribution's statics at the mean pose within
   2 % (measured 0.86 %: 20 segments and the ringing's average), a dynamic lumped model
   against the continuous statics.
4. Verdicts as exceptions: t_max below M g / 8 (T_MAX, a cable named), eight cables without
   bounds (CDPR_E_INVALID_ARG), a loop pose of the six-cable robot (LOOP), a missing file
   (CDPR_E_IO naming it).
"""
import csv
import json
import math
import os
import subprocess
import sys

import numpy as np
from scipy.optimize import minimize

import cdprlib

SIM, SRC, WORK = sys.argv[1], sys.argv[2], sys.argv[3]
failures = []


def check(cond, what):
    print(("ok   " if cond else "FAIL ") + what, flush=True)
    if not cond:
        failures.append(what)


os.makedirs(WORK, exist_ok=True)

# 1. six cables: the robot file and the scenario's plant give the same IK.
robot6 = cdprlib.Robot(os.path.join(SRC, "robots", "paper-50m.yaml"))
with cdprlib.Plant(os.path.join(SRC, "scenarios", "paper-circle.yaml")) as plant:
    pose0 = plant.initial_pose()
    a = robot6.ik(pose0)["length_m"]
    b = plant.ik(pose0)["length_m"]
check(robot6.n_cables == 6 and np.array_equal(a, b),
      "paper-50m.yaml: Robot.ik == Plant.ik at the circle's start, bit for bit (%s)" % a)

# 2. eight cables.
W_ROPE = 0.14 * 9.80665
EA = 2.0e6
lines = ['description: "eight cables, four towers (tests/python/python_statics.py)"',
         "gravity_m_per_s2: 9.80665", "air_density_kg_per_m3: 1.225",
         "wind_m_per_s: [0.0, 0.0, 0.0]", "nominal_pose: [0.0, 0.0, 13.0, 0.0, 0.0, 0.0]",
         "cabin:", "  mass_kg: 40.0", "  com_m: [0.0, 0.0, 0.0]", "  inertia_kg_m2:",
         "    - [45.0, 0.0, 0.0]", "    - [0.0, 45.0, 0.0]", "    - [0.0, 0.0, 90.0]",
         "rope:", "  d0_m: 0.006", "  rho_kg_per_m: 0.14", "  ea_N: 2.0e6",
         "  damping_Ns: 170.0", "  slack_law: passive", "  cd: 1.2", "  cm: 0.03",
         "winch:", "  u_max_m_per_s: 4.0", "  a_max_m_per_s2: 5.0", "  kp_per_s: 5.0",
         "  min_length_m: 0.5", "segments: 8", "cables:"]
exits, attach = [], []
for j in range(8):
    side = 1.0 if j % 2 else -1.0
    th = (j // 2) * math.pi / 2 + math.pi / 4 + 0.2 * side
    az = (j // 2) * math.pi / 2 + math.pi / 4 - 0.5 * side
    exits.append(np.array([25.0 * math.cos(th), 25.0 * math.sin(th), 30.0]))
    attach.append(np.array([1.5 * math.cos(az), 1.5 * math.sin(az), 0.5 * side]))
    lines.append("  - exit_m: [%r, %r, %r]" % tuple(exits[-1]))
    lines.append("    attach_m: [%r, %r, %r]" % tuple(attach[-1]))
path8 = os.path.join(WORK, "eight.yaml")
with open(path8, "w") as f:
    f.write("\n".join(lines) + "\n")
robot8 = cdprlib.Robot(path8)
check(robot8.n_cables == 8, "eight.yaml loads with 8 cables")


def span(H, V, L):
    """Irvine's elastic catenary from the cabin end: horizontal and vertical span of a cable
    of unstretched length L with end forces H, V (V upwards toward the other end)."""
    x = H * L / EA + H / W_ROPE * (math.asinh((V + W_ROPE * L) / H) - math.asinh(V / H))
    z = ((V * L + 0.5 * W_ROPE * L * L) / EA
         + (math.hypot(H, V + W_ROPE * L) - math.hypot(H, V)) / W_ROPE)
    return x, z


def tension_range(H, V, L):
    vb = V + W_ROPE * L
    tc, tb = math.hypot(H, V), math.hypot(H, vb)
    lo = tc if V >= 0.0 else (tb if vb <= 0.0 else H)
    return lo, max(tc, tb)


xs, zs = span(80.0, 30.0, 31.0)
xc, zc = cdprlib.catenary_point(W_ROPE, EA, 80.0, 30.0, 31.0)
check(abs(xs - xc) < 1e-9 and abs(zs - zc) < 1e-9,
      "the catenary written here == cdprlib.catenary_point (%.3g, %.3g m)" % (xs - xc, zs - zc))


def rotation(alpha, beta, gamma):
    """R = Rz(gamma) Ry(beta) Rx(alpha) (cdpr_quat_from_euler)."""
    ca, sa, cb, sb, cg, sg = (math.cos(alpha), math.sin(alpha), math.cos(beta), math.sin(beta),
                              math.cos(gamma), math.sin(gamma))
    rx = np.array([[1, 0, 0], [0, ca, -sa], [0, sa, ca]])
    ry = np.array([[cb, 0, sb], [0, 1, 0], [-sb, 0, cb]])
    rz = np.array([[cg, -sg, 0], [sg, cg, 0], [0, 0, 1]])
    return rz @ ry @ rx


def slsqp(pose, start, t_min, t_max, t_ref):
    R = rotation(*pose[3:])
    p = np.array(pose[:3])
    geo = []
    for j in range(8):
        arm = R @ attach[j]
        d = exits[j] - (p + arm)
        l = math.hypot(d[0], d[1])
        geo.append((l, d[2], np.array([d[0] / l, d[1] / l, 0.0]), arm))
    scale = np.array([100.0, 100.0, 30.0] * 8)
    weight = 40.0 * 9.80665

    def unpack(x):
        return (x * scale).reshape(8, 3)

    def crit(x):
        return sum((tension_range(*c)[0] - t_ref) ** 2 for c in unpack(x)) / 1e4

    def equalities(x):
        out = []
        force = np.array([0.0, 0.0, -weight])
        moment = np.zeros(3)
        for (H, V, L), (l, h, e, arm) in zip(unpack(x), geo):
            sx, sz = span(H, V, L)
            out += [(sx - l) / 30.0, (sz - h) / 30.0]
            F = np.array([H * e[0], H * e[1], V])
            force += F
            moment += np.cross(arm, F)
        return np.array(out + list(force / weight) + list(moment / weight))

    def inequalities(x):
        out = []
        for c in unpack(x):
            lo, hi = tension_range(*c)
            out += [(lo - t_min) / 100.0, (t_max - hi) / 100.0]
        return np.array(out)

    bounds = [(1e-3, None), (None, None), (1e-3, None)] * 8
    r = minimize(crit, start / scale, method="SLSQP", bounds=bounds,
                 constraints=[{"type": "eq", "fun": equalities},
                              {"type": "ineq", "fun": inequalities}],
                 options={"ftol": 1e-12, "maxiter": 1000})
    return r, unpack(r.x), crit(r.x) * 1e4


rng = np.random.default_rng(5)
for pose in ([0.0, 0.0, 13.0, 0.0, 0.0, 0.0], [2.0, -1.5, 14.0, 0.05, -0.03, 0.08],
             [-3.0, 2.5, 10.0, -0.04, 0.06, -0.1]):
    ours = robot8.ik(pose, 25.0, 500.0)
    V = ours["v_cabin_N"]
    x0 = np.column_stack([ours["H_N"], V, ours["length_m"]]).ravel()
    res, sol, crit_scipy = slsqp(pose, x0 * (1.0 + 0.03 * rng.uniform(-1, 1, x0.size)), 25.0,
                                 500.0, 262.5)
    crit_ours = sum((tension_range(H, v, L)[0] - 262.5) ** 2
                    for H, v, L in zip(ours["H_N"], V, ours["length_m"]))
    dl = np.max(np.abs(sol[:, 2] - ours["length_m"]))
    lo_ours = np.array([tension_range(*c)[0] for c in zip(ours["H_N"], V, ours["length_m"])])
    dt = np.max(np.abs(np.array([tension_range(*c)[0] for c in sol]) - lo_ours))
    check(res.success and dl < 1e-6 and dt < 1e-4 and crit_scipy >= crit_ours * (1 - 1e-9),
          "8 cables at %s: cdprlib == scipy SLSQP from 3 %% away (lengths %.2g m, tensions "
          "%.2g N, criterion %.9g vs %.9g; %d iterations)" % (
              pose, dl, dt, crit_ours, crit_scipy, ours["iterations"]))
    print("   scipy: success %s, %s; criterion difference %.3g" % (
        res.success, res.message, crit_scipy - crit_ours))

# 3. the shipped eight-cable robot through cdpr-sim on the paper's line.
out = os.path.join(WORK, "eight-line")
run = subprocess.run([SIM, os.path.join(SRC, "scenarios", "eight-line.yaml"), "--out", out,
                      "--no-plot", "--quiet"], capture_output=True, text=True)
check(run.returncode == 0, "cdpr-sim scenarios/eight-line.yaml exits 0 (%s)" % run.stderr.strip())
if run.returncode == 0:
    summary = json.load(open(os.path.join(out, "summary.json")))
    ik_failures = summary.get("ik_failures")
    with open(os.path.join(out, "timeseries.csv")) as f:
        rows = list(csv.reader(line for line in f if not line.startswith("#")))
    head = rows[0]
    data = np.array([[float(x) for x in r] for r in rows[1:]])
    col = {h: i for i, h in enumerate(head)}
    tail = data[:, col["t_s"]] >= 11.0
    pose = [data[tail, col[k]].mean() for k in
            ("x_m", "y_m", "z_m", "alpha_rad", "beta_rad", "gamma_rad")]
    t_mean = np.array([data[tail, col["T_winch%d_N" % (j + 1)]].mean() for j in range(8)])
    shipped = cdprlib.Robot(os.path.join(SRC, "robots", "eight-50m.yaml"))
    at_mean = shipped.ik(pose)  # the robot file's own distribution
    at_end = shipped.ik([2.50, 1.50, 16.2, 0.135, -0.263, -0.02059265358979])
    rel = np.max(np.abs(t_mean / at_mean["tension_winch_N"] - 1.0))
    dl = np.max(np.abs(data[-1, [col["L%d_m" % (j + 1)] for j in range(8)]]
                       - at_end["length_m"]))
    check(rel < 0.02, "eight-line: mean winch tensions over t >= 11 s == the distribution's "
          "statics at the mean pose within %.2g" % rel)
    check(dl < 1e-4, "eight-line: final lengths == the distribution's IK at the end pose (%.2g m)"
          % dl)
    check(ik_failures == 0, "eight-line: no feed-forward IK failure (%s)" % ik_failures)
    shipped.close()

# 4. verdicts.
try:
    robot8.ik([0.0, 0.0, 13.0, 0.0, 0.0, 0.0], 5.0, 45.0)
    check(False, "t_max 45 N < M g / 8: refused")
except cdprlib.CdprError as e:
    check(e.name == "CDPR_E_INFEASIBLE" and e.why == "T_MAX" and 0 <= e.cable < 8
          and e.value > e.limit == 45.0, "t_max 45 N < M g / 8: %s" % e)
try:
    robot8.ik([0.0, 0.0, 13.0, 0.0, 0.0, 0.0])
    check(False, "eight cables without bounds: refused")
except cdprlib.CdprError as e:
    check(e.name == "CDPR_E_INVALID_ARG", "eight cables without bounds: %s" % e)
try:
    robot6.ik([3.0, -2.0, 12.0, 0.05, -0.05, 0.2])
    check(False, "a loop pose: refused")
except cdprlib.CdprError as e:
    check(e.why == "LOOP" and e.value > 1.5, "a loop pose: %s" % e)
try:
    cdprlib.Robot(os.path.join(WORK, "missing.yaml"))
    check(False, "a missing robot file: refused")
except cdprlib.CdprError as e:
    check(e.name == "CDPR_E_IO" and "missing.yaml" in str(e), "a missing robot file: %s" % e)

robot6.close()
robot8.close()
print("%d failure(s)" % len(failures))
sys.exit(1 if failures else 0)
