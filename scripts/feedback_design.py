#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""Linear analysis of a scenario's feedback loop about a held pose (docs/validation.md §8,
"Feedback design").

    scripts/feedback_design.py SCENARIO [key=value ...] [--at T] [--out DIR] [--step-test J]
        [--step-rate R]

key=value pairs change the scenario (dotted keys, e.g. controller.kd_s=0.1
robot.rope.damping_ratio=0.005) in a copy written to OUT/scenario.yaml. cdpr-design (the C
helper) settles the robot at the trajectory's pose at T (default: where it stops) and writes
the Jacobians of the plant's RHS (A, B: payout rates) and of one real tracker step (Kx, Kz,
Zx, Zz); this script then computes:
  - the plant's modes (eigenvalues of A: frequency, damping ratio) between 0.05 and 20 Hz;
  - the discrete plant: zero-order hold over the control period T_c (exp of [[A, B], [0, 0]]
    T_c; the command computed from the measurement at t_k acts over [t_k, t_k+1): cdpr-sim's
    order), with the tracker's filters and gains as linearised;
  - the closed-loop eigenvalues (largest modulus: < 1 is stable);
  - the loop broken at the rate commands (one per cable), L(z) = -[Kx Kz] (zI - A_o)^-1 [Γ; 0]:
    loop-at-a-time gain and phase margins (channel j open, the other five closed), and the
    minimum over frequency of the smallest singular value α of I + L, with the simultaneous
    margins it guarantees in every channel at once (gain 1/(1+α) .. 1/(1-α), phase
    ±2 asin(α/2); Lehtomaki et al. 1981);
  - with --step-test J: the nonlinear plant's open-loop response to 1 mm/s on cable J over
    2 s against the linear model's;
  - with --learning: the convergence condition of the tracker's learning over laps
    (tracker.h step 8) for the scenario's learning keys (controller.learning_gain γ,
    learning_lead_s λ, learning_cutoff_hz f_c) and lap: the lap-to-lap map of the learned
    correction at frequency ω, M(ω) = Q(ω) (I - γ e^{jωλ} G(e^{jωT_c})), with G the closed
    loop's response (learning off) from the length correction added to δL (u += k_L c) to
    the drop of the length error e_L = J (δp, δθ) (J from cdpr-design's J.bin), Q the
    forward-backward first-order filter over the stored lap (knot spacing T_lap / M):
    Q = (1 - a)^2 / |1 - a e^{-jωΔ}|^2, a = exp(-2π f_c Δ). Reported: the spectral radius
    ρ(M) (asymptotic convergence: < 1) and the largest singular value (monotone in the
    2-norm: < 1) at the lap harmonics k / T_lap up to where Q < 0.01 and on a fine grid over
    the same band, and the bands where ρ >= 1. Exit status 1 also when ρ >= 1 at a harmonic.
Exit status 0; 1 when the closed loop is unstable or below the goal margins (6 dB, 30°).
Needs numpy and scipy (Debian python3-numpy python3-scipy).
"""
import argparse
import json
import os
import subprocess
import sys

import numpy as np
import scipy.linalg as sla

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from scenario_edit import edit  # noqa: E402

GOAL_GM_DB = 6.0
GOAL_PM_DEG = 30.0
GROWTH_TOL = 1e-5  # [1/s]: e-folding over 28 h


def load(d):
    meta = {}
    cables = []
    for line in open(os.path.join(d, "meta.txt")):
        w = line.split()
        if w[0] == "cable":
            cables.append((int(w[3]), int(w[5]), float(w[7])))
        elif w[0] == "pose":
            meta["pose"] = [float(v) for v in w[1:]]
        else:
            meta[w[0]] = float(w[1])
    n, nz, nu, nm = (int(meta[k]) for k in ("n", "nz", "nu", "nm"))
    shapes = {"A": (n, n), "B": (n, nu), "Kx": (nu, n), "Kz": (nu, nz), "Zx": (nz, n),
              "Zz": (nz, nz), "Cm": (nm, n)}
    shapes.update({"Ku": (nu, nu), "Zu": (nz, nu), "J": (nu, 6)})
    m = {k: np.fromfile(os.path.join(d, k + ".bin"), dtype="<f8").reshape(s)
         for k, s in shapes.items()}
    m["T"] = meta["period_s"]
    m["pose"] = meta["pose"]
    for k in ("lap_s", "learn_knots", "k_length_per_s", "learning_gain", "learning_lead_s",
              "learning_cutoff_hz"):
        m[k] = meta.get(k, 0.0)
    m["cables"] = cables
    m["cabin_mass"] = meta["cabin_mass_kg"]
    return m


def discretise(A, B, T):
    n, nu = B.shape
    M = np.zeros((n + nu, n + nu))
    M[:n, :n] = A
    M[:n, n:] = B
    E = sla.expm(M * T)
    return E[:n, :n], E[:n, n:]


def modes(lam, fmin=0.05, fmax=20.0):
    out = []
    for z in lam:
        if z.imag <= 0.0:
            continue
        w = abs(z)
        f = z.imag / (2 * np.pi)
        if fmin <= f <= fmax:
            out.append((f, -z.real / w))
    return sorted(out)


def cabin_modes(loop, m, share_min=0.05, fmax=20.0):
    """Modes with at least share_min of their mass-weighted displacement in the cabin (cabin
    mass x (|dp|^2 + (2 m)^2 |dq_xyz|^2 x 4) against node mass x |node displacement|^2)."""
    n = m["A"].shape[0]
    wpos = np.zeros(n)
    for off, nodes, mass in m["cables"]:
        wpos[off + 1:off + 1 + 3 * (nodes - 1)] = mass
    out = []
    for i, z in enumerate(loop.lam):
        f = z.imag / (2 * np.pi)
        if z.imag <= 0.0 or f > fmax:
            continue
        v = loop.V[:, i]
        cab = m["cabin_mass"] * (np.sum(np.abs(v[0:3]) ** 2) + 16.0 * np.sum(np.abs(v[4:7]) ** 2))
        share = cab / (cab + np.sum(wpos * np.abs(v) ** 2))
        if share >= share_min:
            out.append([round(f, 4), float("%.3g" % (-z.real / abs(z))), round(float(share), 3)])
    return sorted(out)


def cabin_closed_loop(cabin, ev, T, share_min=0.2):
    """For each open-loop mode with a cabin share >= share_min: the closed-loop eigenvalue
    nearest to it (s = ln z / T): frequency [Hz] and damping ratio."""
    s = np.log(ev[(np.abs(ev) > 0.0) & (np.angle(ev) > 0.0)].astype(complex)) / T
    out = []
    for f, _, share in cabin:
        if share < share_min or s.size == 0:
            continue
        k = int(np.argmin(np.abs(s.imag / (2 * np.pi) - f) + np.abs(s.real) / (2 * np.pi)))
        out.append([f, round(float(s[k].imag / (2 * np.pi)), 4),
                    float("%.3g" % (-s[k].real / abs(s[k])))])
    return out


class Loop:
    """The loop broken at the rate commands, evaluated through the modes of A."""

    def __init__(self, m, Phi, Gam):
        self.m = m
        self.T = m["T"]
        lam, V = sla.eig(m["A"])
        self.lam = lam
        self.V = V
        self.mu = np.exp(lam * self.T)
        g = np.where(np.abs(lam * self.T) < 1e-9, self.T,
                     (self.mu - 1.0) / np.where(lam == 0, 1.0, lam))
        self.W = g[:, None] * sla.solve(V, m["B"])  # modal ZOH input
        self.KxV = m["Kx"] @ V
        self.ZxV = m["Zx"] @ V
        self.Phi, self.Gam = Phi, Gam

    def H(self, f_hz):
        """u_out = H u_in (nu x nu per frequency, one rate command per cable)."""
        z = np.exp(1j * 2 * np.pi * np.atleast_1d(f_hz) * self.T)
        nz = self.m["Zz"].shape[0]
        nu = self.m["Ku"].shape[0]
        out = np.empty((z.size, nu, nu), dtype=complex)
        for i, zi in enumerate(z):
            X = self.W / (zi - self.mu)[:, None]  # modal plant state per input
            Zp = sla.solve(zi * np.eye(nz) - self.m["Zz"], self.ZxV @ X + self.m["Zu"] / zi)
            out[i] = self.KxV @ X + self.m["Kz"] @ Zp + self.m["Ku"] / zi
        return out

    def H_direct(self, f_hz):
        z = np.exp(1j * 2 * np.pi * f_hz * self.T)
        n = self.Phi.shape[0]
        X = sla.solve(z * np.eye(n) - self.Phi, self.Gam)
        nz = self.m["Zz"].shape[0]
        Zp = sla.solve(z * np.eye(nz) - self.m["Zz"], self.m["Zx"] @ X + self.m["Zu"] / z)
        return self.m["Kx"] @ X + self.m["Kz"] @ Zp + self.m["Ku"] / z


def closed_loop(m, Phi, Gam, scale=None):
    """Eigenvalues of the loop with state (x, z, u_prev): u_k = Kx x + Kz z + Ku u_{k-1} (the
    payout rates in force at t_k enter the measured tensions)."""
    return sla.eigvals(closed_loop_matrix(m, Phi, Gam, scale))


def channel_loops(H):
    """Scalar loop gain l_j (negative-feedback convention) with the other loops closed."""
    F, nu = H.shape[0], H.shape[1]
    l = np.empty((F, nu), dtype=complex)
    for j in range(nu):
        o = [i for i in range(nu) if i != j]
        for k in range(F):
            Hk = H[k]
            Hoo = Hk[np.ix_(o, o)]
            u_o = sla.solve(np.eye(nu - 1) - Hoo, Hk[o, j])
            l[k, j] = -(Hk[j, j] + Hk[j, o] @ u_o)
    return l


def margins(f, l):
    """Smallest gain margin [dB] (at a -180° crossing of l; negative: a gain reduction
    destabilises) and smallest phase margin [deg] (at |l| = 1), with their frequencies."""
    gm, gm_f, pm, pm_f = np.inf, None, np.inf, None
    for k in range(len(f) - 1):
        a, b = l[k], l[k + 1]
        if a.imag * b.imag < 0.0:  # crossing of the real axis
            s = a.imag / (a.imag - b.imag)
            x = a.real + s * (b.real - a.real)
            if x < 0.0:
                g = -20 * np.log10(-x)
                if abs(g) < abs(gm):
                    gm, gm_f = g, f[k] + s * (f[k + 1] - f[k])
        if (abs(a) - 1.0) * (abs(b) - 1.0) < 0.0:
            s = (abs(a) - 1.0) / (abs(a) - abs(b))
            c = a + s * (b - a)
            p = 180.0 - abs(np.degrees(np.angle(c)))
            if p < pm:
                pm, pm_f = p, f[k] + s * (f[k + 1] - f[k])
    return gm, gm_f, pm, pm_f


def step_check(m, Phi, Gam, path, cable, rate=1e-3):
    data = np.loadtxt(path, delimiter=",")
    nu = m["Ku"].shape[0]
    u = np.zeros(nu)
    u[cable] = rate
    x = np.zeros(Phi.shape[0])
    lin = []
    for _ in range(data.shape[0]):
        lin.append(m["Cm"] @ x)
        x = Phi @ x + Gam @ u
    lin = np.array(lin)
    nl = data[:, 1:]
    res = {}
    for name, sl in (("position", slice(0, 3)), ("rotation", slice(3, 6)),
                     ("length", slice(12, 12 + nu))):
        peak = np.max(np.abs(nl[:, sl]))
        err = np.max(np.abs(nl[:, sl] - lin[:, sl]))
        res[name] = (peak, err)
    return res, data[:, 0], nl, lin


def closed_loop_matrix(m, Phi, Gam, scale=None):
    """The closed loop of closed_loop() as a matrix, state (x, z, u_prev); `scale` multiplies
    each winch's gains (rows of K)."""
    K = np.hstack([m["Kx"], m["Kz"], m["Ku"]])
    if scale is not None:
        K = scale[:, None] * K
    n, nz, nu = Phi.shape[0], m["Zz"].shape[0], m["Ku"].shape[0]
    Acl = np.zeros((n + nz + nu, n + nz + nu))
    Acl[:n, :n] = Phi
    Acl[n:n + nz, :n] = m["Zx"]
    Acl[n:n + nz, n:n + nz] = m["Zz"]
    Acl[n:n + nz, n + nz:] = m["Zu"]
    Acl[:n, :] += Gam @ K
    Acl[n + nz:, :] = K
    return Acl


class LearningPlant:
    """G(z): the length correction c (u += k_L c) to the drop of e_L = J (δp, δθ), closed
    loop without learning, evaluated through the eigenvalues of the closed loop."""

    def __init__(self, m, Phi, Gam):
        Acl = closed_loop_matrix(m, Phi, Gam)
        n, nu = Phi.shape[0], m["Ku"].shape[0]
        N = Acl.shape[0]
        Bc = np.zeros((N, nu))
        Bc[:n, :] = Gam
        Bc[N - nu:, :] = np.eye(nu)  # u_prev carries the command of which c is part
        Bc *= m["k_length_per_s"]
        C = np.zeros((nu, N))
        C[:, :n] = m["J"] @ m["Cm"][0:6, :]
        lam, V = sla.eig(Acl)
        self.lam = lam
        self.CV = C @ V
        self.W = sla.solve(V, Bc)
        self.T = m["T"]
        self.Acl, self.Bc, self.C = Acl, Bc, C

    def G(self, f_hz):
        z = np.exp(1j * 2 * np.pi * f_hz * self.T)
        return -(self.CV / (z - self.lam)[None, :]) @ self.W

    def G_direct(self, f_hz):
        z = np.exp(1j * 2 * np.pi * f_hz * self.T)
        N = self.Acl.shape[0]
        return -self.C @ sla.solve(z * np.eye(N) - self.Acl, self.Bc)


def learning_q(f_hz, fc, dphi):
    if not fc > 0.0:
        return np.ones_like(np.asarray(f_hz, dtype=float))
    a = np.exp(-2 * np.pi * fc * dphi)
    return (1 - a) ** 2 / np.abs(1 - a * np.exp(-1j * 2 * np.pi * np.asarray(f_hz) * dphi)) ** 2


def learning_map(lp, f, gamma, lead, fc, dphi):
    """rho and sigma_max of M(f) = Q (I - gamma e^{j w lead} G), and Q, per frequency."""
    q = learning_q(f, fc, dphi)
    rho = np.empty(len(f))
    smax = np.empty(len(f))
    for i, fi in enumerate(f):
        Gf = lp.G(fi)
        Mf = q[i] * (np.eye(Gf.shape[0]) - gamma * np.exp(1j * 2 * np.pi * fi * lead) * Gf)
        rho[i] = np.max(np.abs(sla.eigvals(Mf)))
        smax[i] = np.linalg.svd(Mf, compute_uv=False)[0]
    return rho, smax, q


def learning_report(m, Phi, Gam):
    lap, knots = m["lap_s"], int(m["learn_knots"])
    gamma, lead, fc = m["learning_gain"], m["learning_lead_s"], m["learning_cutoff_hz"]
    rep = {"lap_s": lap, "knots": knots, "gamma": gamma, "lead_s": lead, "cutoff_hz": fc}
    if not (lap > 0.0 and knots >= 2 and gamma > 0.0):
        rep["note"] = "no learning: trajectory not periodic or learning_gain 0"
        rep["converges_at_harmonics"] = True
        return rep
    dphi = lap / knots
    lp = LearningPlant(m, Phi, Gam)
    fnyq = 0.5 / dphi
    # band: Q >= 0.01 (or up to the knots' Nyquist frequency without a filter)
    fb = np.linspace(1e-3, fnyq, 20000)
    qb = learning_q(fb, fc, dphi)
    ftop = float(fb[np.nonzero(qb >= 0.01)[0][-1]])
    rep["band_top_hz"] = ftop
    rep["G_modal_vs_direct_rel_err"] = float(
        np.linalg.norm(lp.G(0.3) - lp.G_direct(0.3)) / np.linalg.norm(lp.G_direct(0.3)))
    g0 = lp.G(1e-4)
    rep["G_at_0_diag"] = [float("%.4g" % v) for v in np.real(np.diag(g0))]
    harm = np.arange(1, int(np.floor(ftop * lap)) + 1) / lap
    rho_h, smax_h, q_h = learning_map(lp, harm, gamma, lead, fc, dphi)
    rep["harmonics"] = [[round(float(h), 4), round(float(qq), 4), round(float(r), 4),
                         round(float(sm), 4)] for h, qq, r, sm in zip(harm, q_h, rho_h, smax_h)]
    rep["harmonics_columns"] = "f_hz, Q, rho(M), sigma_max(M)"
    rep["max_rho_at_harmonics"] = float(np.max(rho_h)) if harm.size else 0.0
    rep["converges_at_harmonics"] = bool(np.all(rho_h < 1.0))
    f = np.unique(np.concatenate([np.linspace(1e-3, ftop, 4000), harm]))
    rho, smax, q = learning_map(lp, f, gamma, lead, fc, dphi)
    bad = rho >= 1.0
    bands = []
    i = 0
    while i < len(f):
        if bad[i]:
            k = i
            while k + 1 < len(f) and bad[k + 1]:
                k += 1
            bands.append([round(float(f[i]), 4), round(float(f[k]), 4),
                          round(float(np.max(rho[i:k + 1])), 3)])
            i = k + 1
        else:
            i += 1
    rep["fails_in_bands_hz"] = bands  # [from, to, largest rho]
    rep["failing_fraction_of_band"] = float(np.mean(bad))
    rep["max_rho_in_band"] = float(np.max(rho))
    rep["max_rho_at_hz"] = float(f[int(np.argmax(rho))])
    rep["max_sigma_in_band"] = float(np.max(smax))
    return rep


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("scenario")
    ap.add_argument("settings", nargs="*", help="key=value")
    ap.add_argument("--at", type=float, default=None)
    ap.add_argument("--out", default="out/design")
    ap.add_argument("--step-test", type=int, default=None)
    ap.add_argument("--step-rate", type=float, default=1e-3,
                    help="the step test's payout rate [m/s] (default 1 mm/s)")
    ap.add_argument("--bin", default=None, help="cdpr-design (default: build/release)")
    ap.add_argument("--fmax", type=float, default=None, help="top of the grid [Hz]")
    ap.add_argument("--points", type=int, default=3000)
    ap.add_argument("--learning", action="store_true",
                    help="convergence of the learning over laps (tracker.h step 8)")
    a = ap.parse_args()
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    exe = a.bin or os.path.join(root, "build", "release", "apps", "cdpr-design")
    os.makedirs(a.out, exist_ok=True)
    text = edit(open(a.scenario).read(), [tuple(s.split("=", 1)) for s in a.settings],
                os.path.dirname(a.scenario))
    scen = os.path.join(a.out, "scenario.yaml")
    with open(scen, "w") as fh:
        fh.write(text)
    cmd = [exe, scen, a.out]
    if a.at is not None:
        cmd += ["--at", repr(a.at)]
    if a.step_test is not None:
        cmd += ["--step-test", str(a.step_test), "--step-rate", repr(a.step_rate)]
    rc = subprocess.run(cmd, check=False).returncode
    if rc != 0:
        raise SystemExit("feedback_design: cdpr-design exited with %d" % rc)
    m = load(a.out)
    T = m["T"]
    Phi, Gam = discretise(m["A"], m["B"], T)
    loop = Loop(m, Phi, Gam)
    rep = {"scenario": a.scenario, "settings": a.settings, "pose": m["pose"], "n": int(m["A"].shape[0])}
    md = modes(loop.lam)
    rep["modes_hz_zeta"] = [[round(f, 4), float("%.3g" % z)] for f, z in md]
    rep["cabin_modes_hz_zeta_share"] = cabin_modes(loop, m)
    rep["max_re_lambda"] = float(np.max(loop.lam.real))
    ev = closed_loop(m, Phi, Gam)
    rho = float(np.max(np.abs(ev)))
    k = int(np.argmax(np.abs(ev)))
    # Growth rate ln|z| / T of the least stable closed-loop eigenvalue. Undamped modes (the
    # plant's transverse cable modes have zeta ~ 1e-7) sit on the unit circle to within the
    # central differences' accuracy: growth below GROWTH_TOL counts as not growing.
    growth = np.log(np.abs(ev)) / T
    np.save(os.path.join(a.out, "closed_loop_eig.npy"), ev)
    rep["closed_loop_cabin_modes_hz_zeta"] = cabin_closed_loop(rep["cabin_modes_hz_zeta_share"],
                                                              ev, T)
    rep["closed_loop_max_abs_eig"] = rho
    rep["closed_loop_max_growth_per_s"] = float(growth[k])
    rep["closed_loop_worst_hz"] = float(abs(np.angle(ev[k])) / (2 * np.pi * T))
    bad = [(float(g), round(abs(np.angle(e)) / (2 * np.pi * T), 3))
           for g, e in zip(growth, ev) if g > GROWTH_TOL and np.angle(e) >= 0.0]
    rep["closed_loop_growing_per_s_hz"] = sorted(bad, reverse=True)[:20]
    fmax = a.fmax or 0.5 / T
    f = np.logspace(np.log10(0.01), np.log10(fmax * 0.999), a.points)
    # refine around every plant mode in the band
    extra = []
    for fm, _ in modes(loop.lam, 0.01, fmax):
        extra.extend(fm * (1 + np.linspace(-0.02, 0.02, 41)))
    f = np.unique(np.concatenate([f, [x for x in extra if 0.01 < x < fmax]]))
    H = loop.H(f)
    chk = []
    for fc in (0.3, 5.0, min(20.0, 0.4 / T)):
        Hd = loop.H_direct(fc)
        Hm = loop.H(fc)[0]
        chk.append(float(np.linalg.norm(Hd - Hm) / max(np.linalg.norm(Hd), 1e-300)))
    rep["modal_vs_direct_rel_err"] = chk
    nu = H.shape[1]
    ret = np.eye(nu)[None, :, :] - H  # I + L with L = -H
    smin = np.array([np.linalg.svd(r, compute_uv=False)[-1] for r in ret])
    i = int(np.argmin(smin))
    alpha = float(smin[i])
    rep["sigma_min_I_plus_L"] = alpha
    rep["sigma_min_at_hz"] = float(f[i])
    if alpha < 1.0:
        rep["disk_gain_db"] = [float(20 * np.log10(1 / (1 + alpha))),
                               float(20 * np.log10(1 / (1 - alpha)))]
    else:
        rep["disk_gain_db"] = [float(20 * np.log10(1 / (1 + alpha))), float("inf")]
    rep["disk_phase_deg"] = float(np.degrees(2 * np.arcsin(min(alpha, 2.0) / 2)))
    active = np.max(np.abs(H)) > 0.0
    if active:
        l = channel_loops(H)
        rep["channels"] = []
        for j in range(nu):
            gm, gmf, pm, pmf = margins(f, l[:, j])
            rep["channels"].append({"cable": j, "gm_db": gm, "gm_hz": gmf, "pm_deg": pm,
                                    "pm_hz": pmf})
        np.savetxt(os.path.join(a.out, "loop.csv"),
                   np.column_stack([f, smin] + [np.abs(l[:, j]) for j in range(nu)] +
                                   [np.degrees(np.angle(l[:, j])) for j in range(nu)]),
                   delimiter=",", header="f_hz,sigma_min,|l1..%d|,phase1..%d_deg" % (nu, nu))
    if a.step_test is not None:
        res, t, nl, lin = step_check(m, Phi, Gam, os.path.join(a.out, "step.csv"), a.step_test,
                                     a.step_rate)
        rep["step_test"] = {k: {"peak": v[0], "max_err": v[1]} for k, v in res.items()}
        np.savetxt(os.path.join(a.out, "step_lin.csv"), np.column_stack([t, lin]), delimiter=",")
    ok = growth[k] <= GROWTH_TOL
    if active:
        gm_min = min(abs(c["gm_db"]) for c in rep["channels"])
        pm_min = min(c["pm_deg"] for c in rep["channels"])
        rep["loop_at_a_time_min"] = {"gm_db": gm_min, "pm_deg": pm_min}
        ok = ok and gm_min >= GOAL_GM_DB and pm_min >= GOAL_PM_DEG
    if a.learning:
        rep["learning"] = learning_report(m, Phi, Gam)
        ok = ok and rep["learning"]["converges_at_harmonics"]
    rep["meets_goal"] = bool(ok)
    with open(os.path.join(a.out, "design.json"), "w") as fh:
        json.dump(rep, fh, indent=1, default=float)
    json.dump(rep, sys.stdout, indent=1, default=float)
    print()
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
