/* SPDX-License-Identifier: BSD-3-Clause */
/// @file catenary.h
/// Elastic catenary (Irvine, Cable Structures, 1981, §2.2): a uniform elastic cable hanging
/// under its own weight between two points (docs/model.md "Elastic catenary").
///
/// Convention: end A at the origin, end B at horizontal span l >= 0 and height h (B above A
/// when h > 0). s in [0, L0] is the unstretched arclength from A. H > 0 is the horizontal
/// tension component (constant along the cable); V_A is the vertical tension component at A
/// along increasing s (negative when the cable leaves A downward). V(s) = V_A + w s, with w
/// the weight per unstretched length. The cable pulls support A with (H e, V_A) and support B
/// with (-H e, -V_B), e the unit horizontal vector from A to B. T(s) = sqrt(H^2 + V(s)^2).
///
///   x(s) = H s / EA + (H / w) [asinh(V(s)/H) - asinh(V_A/H)]
///   z(s) = (V_A s + w s^2 / 2) / EA + (1 / w) [T(s) - T(0)]
///
/// Pure functions, no allocation; the solver's work is bounded by its iteration limit.
/// Pointer arguments must be valid unless a function says it checks them.
#ifndef CDPR_CATENARY_H
#define CDPR_CATENARY_H

#include "cdpr/config.h"
#include "cdpr/status.h"

/// Cable properties for the catenary.
typedef struct {
    cdpr_real_t w_N_per_m; ///< weight per unstretched length rho g [N/m] (> 0)
    cdpr_real_t ea_N;      ///< axial stiffness [N] (> 0)
} cdpr_catenary_cable_t;

/// Position (x, z) at unstretched arclength s [m] for end forces (H, V_A) [N]. No checks:
/// needs H > 0 and w, EA > 0 (else NaN/Inf results). O(1), cannot fail.
void cdpr_catenary_point(const cdpr_catenary_cable_t *c, cdpr_real_t H_N, cdpr_real_t va_N,
                         cdpr_real_t s_m, cdpr_real_t *x_m, cdpr_real_t *z_m);

/// Spans (l, h) of a cable of unstretched length L0 with end forces (H, V_A) (the forward
/// closed form). O(1). Returns (outputs written only on CDPR_OK):
/// - CDPR_E_INVALID_ARG: c, l_m or h_m is NULL.
/// - CDPR_E_NOT_FINITE: w_N_per_m, ea_N, H_N, va_N or L0_m is NaN/Inf.
/// - CDPR_E_NOT_POSITIVE: w_N_per_m, ea_N, H_N or L0_m <= 0.
cdpr_status_t cdpr_catenary_spans(const cdpr_catenary_cable_t *c, cdpr_real_t H_N, cdpr_real_t va_N,
                                  cdpr_real_t L0_m, cdpr_real_t *l_m, cdpr_real_t *h_m);

/// Spans (l, h) and their partial derivatives with respect to H, V_A and L0 (for the
/// Newton solvers here and in statics.h). No checks: needs H > 0 and w, EA > 0. O(1), cannot
/// fail.
void cdpr_catenary_spans_jac(const cdpr_catenary_cable_t *c, cdpr_real_t H_N, cdpr_real_t va_N,
                             cdpr_real_t L0_m, cdpr_real_t span[2], cdpr_real_t d_dH[2],
                             cdpr_real_t d_dV[2], cdpr_real_t d_dL[2]);

/// Solver settings and report.
typedef struct {
    int max_iter;           ///< iteration bound (> 0); default 50
    cdpr_real_t tol_m;      ///< span residual tolerance [m] (> 0); default 1e-9 (double)
    int iterations;         ///< output: iterations used
    cdpr_real_t residual_m; ///< output: final span residual [m]
} cdpr_catenary_solver_t;

/// Defaults for the solver (outputs zeroed). O(1), cannot fail.
void cdpr_catenary_solver_default(cdpr_catenary_solver_t *s);

/// Inverse problem: end forces (H, V_A) of a cable of unstretched length L0 whose ends are
/// (l, h) apart. Safeguarded Newton (analytic Jacobian, backtracking on the residual, H kept
/// positive) from the better of a taut and a slack initial guess. Works for slack and taut
/// cables and for near-vertical ones (l > 0). Converged when the span residual
/// sqrt(dl^2 + dh^2) <= tol_m.
/// Work: at most 3 + 40 max_iter span evaluations (closed form, O(1) each); no allocation.
/// Returns (*H_N, *va_N written only on CDPR_OK; s->iterations and s->residual_m whenever the
/// iteration ran, i.e. on CDPR_OK and CDPR_E_NO_CONVERGENCE):
/// - CDPR_E_INVALID_ARG: c, s, H_N or va_N is NULL, or s->max_iter < 1.
/// - CDPR_E_NOT_FINITE: w_N_per_m, ea_N, l_m, h_m, L0_m or s->tol_m is NaN/Inf.
/// - CDPR_E_NOT_POSITIVE: w_N_per_m, ea_N, l_m, L0_m or s->tol_m <= 0 (a vertical cable,
///   l = 0, has no catenary plane).
/// - CDPR_E_NO_CONVERGENCE: singular Jacobian, no descent within 40 step halvings, or
///   max_iter iterations without reaching tol_m.
cdpr_status_t cdpr_catenary_solve(const cdpr_catenary_cable_t *c, cdpr_real_t l_m, cdpr_real_t h_m,
                                  cdpr_real_t L0_m, cdpr_catenary_solver_t *s, cdpr_real_t *H_N,
                                  cdpr_real_t *va_N);

#endif /* CDPR_CATENARY_H */
