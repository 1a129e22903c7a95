#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""Fit a rope's axial stiffness EA to measured sags, with scipy and the library's elastic
catenary (cdprlib, docs/python.md).

  examples/python/fit_rope.py [--ea-true N] [--noise-mm MM]

A cable of known weight and unstretched length hangs between two points 25 m apart
horizontally and 14.1 m vertically (the paper's robot: 0.14 kg/m rope). Its sag below the
straight chord is "measured" at a quarter, half and three quarters of its length -- here made
from the catenary with --ea-true, plus optional Gaussian noise (seeded) -- and EA is found by
scipy.optimize.least_squares over log10(EA), each residual a model sag (cdprlib.catenary_solve
for the end forces, cdprlib.catenary_point for the points) minus a measured one.

Prints the fit and exits 0 when it converged (1 otherwise).
"""
import argparse
import math
import sys

import numpy as np
from scipy.optimize import least_squares

import _cdpr_path  # noqa: F401  (sys.path fallback for a source tree)
import cdprlib

W = 0.14 * 9.80665     # weight per unstretched metre [N/m]
L0 = 28.70             # unstretched length [m]: about the chord, a taut rope
SPAN = (25.0, 14.1)    # end B from end A: horizontal, vertical [m]
AT = (0.25, 0.5, 0.75)  # where along the cable the sag is measured (fractions of L0)


def sags(ea):
    """Sag below the chord [m] at the fractions AT of the unstretched length."""
    H, V = cdprlib.catenary_solve(W, ea, SPAN[0], SPAN[1], L0)
    out = []
    for f in AT:
        x, z = cdprlib.catenary_point(W, ea, H, V, f * L0)
        out.append(SPAN[1] * x / SPAN[0] - z)
    return np.array(out)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--ea-true", type=float, default=2.0e6, help="EA of the 'measured' rope [N]")
    ap.add_argument("--noise-mm", type=float, default=0.0, help="measurement noise, 1 sigma [mm]")
    a = ap.parse_args()
    measured = sags(a.ea_true) + np.random.default_rng(1).normal(0.0, a.noise_mm * 1e-3, len(AT))
    fit = least_squares(lambda p: sags(10.0 ** p[0]) - measured, x0=[5.0], bounds=([4.0], [9.0]),
                        x_scale=[1.0], xtol=1e-12, ftol=1e-15, gtol=1e-15)
    ea = 10.0 ** fit.x[0]
    print("measured sags [mm]: %s" % ", ".join("%.3f" % (1e3 * s) for s in measured))
    print("fitted EA = %.6g N (true %.6g N, %+.2e relative); residual %.3g mm; %s" % (
        ea, a.ea_true, ea / a.ea_true - 1.0, 1e3 * math.sqrt(2.0 * fit.cost), fit.message))
    return 0 if fit.success else 1


if __name__ == "__main__":
    sys.exit(main())
