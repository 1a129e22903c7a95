/// @file catenary.h
/// Elastic catenary (Irvine, Cable Structures, 1981, §2.2): a uniform elastic cable hanging
/// under its own weight between two points (MODEL.md §5).
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
#ifndef CDPR_CATENARY_H
#define CDPR_CATENARY_H

#include "cdpr/config.h"
#include "cdpr/status.h"

/// Cable properties for the catenary.
typedef struct {
    cdpr_real_t w_N_per_m; ///< weight per unstretched length rho g [N/m] (> 0)
    cdpr_real_t ea_N;      ///< axial stiffness [N] (> 0)
} cdpr_catenary_cable_t;

/// Position (x, z) at unstretched arclength s [m] for end forces (H, V_A) [N].
void cdpr_catenary_point(const cdpr_catenary_cable_t *c, cdpr_real_t H_N, cdpr_real_t va_N,
                         cdpr_real_t s_m, cdpr_real_t *x_m, cdpr_real_t *z_m);

/// Spans (l, h) of a cable of unstretched length L0 with end forces (H, V_A) (the forward
/// closed form). H must be > 0.
cdpr_status_t cdpr_catenary_spans(const cdpr_catenary_cable_t *c, cdpr_real_t H_N, cdpr_real_t va_N,
                                  cdpr_real_t L0_m, cdpr_real_t *l_m, cdpr_real_t *h_m);

/// Spans (l, h) and their partial derivatives with respect to H, V_A and L0 (for the
/// Newton solvers here and in statics.h). Requires H > 0. O(1).
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

/// Defaults for the solver.
void cdpr_catenary_solver_default(cdpr_catenary_solver_t *s);

/// Inverse problem: end forces (H, V_A) of a cable of unstretched length L0 whose ends are
/// (l, h) apart. Safeguarded Newton (analytic Jacobian, backtracking on the residual, H kept
/// positive) from the better of a taut and a slack initial guess. Works for slack and taut
/// cables and for near-vertical ones (l > 0). CDPR_E_NO_CONVERGENCE after max_iter.
cdpr_status_t cdpr_catenary_solve(const cdpr_catenary_cable_t *c, cdpr_real_t l_m, cdpr_real_t h_m,
                                  cdpr_real_t L0_m, cdpr_catenary_solver_t *s, cdpr_real_t *H_N,
                                  cdpr_real_t *va_N);

#endif /* CDPR_CATENARY_H */
