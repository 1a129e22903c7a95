/* SPDX-License-Identifier: BSD-3-Clause */
/// @file ldp.h
/// Internal (not installed): least-distance programming, min ||z||_2 subject to G z >= h, by
/// Lawson and Hanson's reduction to non-negative least squares (Lawson & Hanson, "Solving Least
/// Squares Problems", 1974, ch. 23). The tension distribution of a redundant robot (statics.c)
/// is one such problem per iteration: z are the null-space coordinates of the cable tensions,
/// the rows of G the tension bounds. Fixed sizes, no allocation, bounded work.
#ifndef CDPR_LDP_H
#define CDPR_LDP_H

#include "cdpr/config.h"

/// Largest problem: z has at most CDPR_MAX_CABLES - 6 components (at least 1 for the array
/// sizes), G at most 2 CDPR_MAX_CABLES rows (a lower and an upper bound per cable).
#define CDPR_LDP_MAX_VARS ((CDPR_MAX_CABLES > 7) ? (CDPR_MAX_CABLES - 6) : 1)
#define CDPR_LDP_MAX_ROWS (2 * CDPR_MAX_CABLES)
/// Columns of the equality constraints of cdpr_ldp_qp (cables; at least the 6 of a wrench).
#define CDPR_LDP_MAX_COLS ((CDPR_MAX_CABLES > 6) ? CDPR_MAX_CABLES : 6)

/// Outcome of cdpr_ldp_solve.
typedef enum {
    CDPR_LDP_OK = 0,         ///< z holds the minimum-norm feasible point
    CDPR_LDP_INFEASIBLE = 1, ///< no z satisfies G z >= h; `blame` names the row weighing most
    CDPR_LDP_STALLED = 2,    ///< the NNLS iteration bound (3 rows) was hit, or a rank failure
    CDPR_LDP_SINGULAR = 3    ///< cdpr_ldp_qp: the equations are rank deficient, or m out of range
} cdpr_ldp_result_t;

/// Minimum-norm z (k components, 0 <= k <= CDPR_LDP_MAX_VARS) with G z >= h (n_rows rows,
/// n_rows <= CDPR_LDP_MAX_ROWS). Rows are normalised first; a row whose coefficients are all
/// below 1e-12 of the largest row's (a bound that z cannot move) is a constant condition
/// 0 >= h_i, checked against a tolerance of 1e3 eps max |h|. Infeasibility is decided by the
/// NNLS residual (Lawson-Hanson: the residual vanishes exactly when the constraints are
/// inconsistent; threshold 1e3 eps on the unit right-hand side), and `*blame` is then the row
/// with the largest weight in the NNLS solution, a member of an inconsistent subset. Work:
/// at most 3 n_rows outer NNLS iterations, each with at most n_rows least-squares solves of
/// (k + 1) rows; no allocation; G is not modified (not const: C99 arrays). On CDPR_LDP_OK,
/// *blame = -1.
cdpr_ldp_result_t cdpr_ldp_solve(int k, int n_rows, cdpr_real_t G[][CDPR_LDP_MAX_VARS],
                                 const cdpr_real_t *h, cdpr_real_t *z, int *blame);

/// The tension-distribution step: min ||u||_2 over u in R^m (6 <= m <= CDPR_LDP_MAX_COLS)
/// subject to the 6 equations E u = f and, when `bounded` != 0, per component j the two
/// bounds lo_c[j] u_j >= lo_h[j] and hi_c[j] u_j >= hi_h[j]. Method: Householder QR of E^T
/// gives the minimum-norm solution u_p of the equations (in the row space of E) and an
/// orthonormal basis N of E's null space; u = u_p + N z with ||u||^2 = ||u_p||^2 + ||z||^2, so
/// z is the LDP of the bounds (cdpr_ldp_solve). On success `mu` (6 values, may be NULL) gets
/// the least-squares multipliers of the equations, E^T mu ~ u (exact when no bound is active:
/// the KKT condition u = E^T mu). Returns CDPR_LDP_OK (u written),
/// CDPR_LDP_INFEASIBLE (*blame = 2 j for the lower bound of component j, 2 j + 1 for its upper
/// bound), CDPR_LDP_STALLED, or CDPR_LDP_SINGULAR when E is rank deficient (a diagonal of R
/// below 1e-12 of the largest) or m is outside [6, CDPR_LDP_MAX_COLS]. Work O(m^2 6) for the QR
/// plus the LDP's; no allocation.
cdpr_ldp_result_t cdpr_ldp_qp(int m, cdpr_real_t E[6][CDPR_LDP_MAX_COLS], const cdpr_real_t f[6],
                              const cdpr_real_t *lo_c, const cdpr_real_t *lo_h,
                              const cdpr_real_t *hi_c, const cdpr_real_t *hi_h, int bounded,
                              cdpr_real_t *u, cdpr_real_t *mu, int *blame);

#endif /* CDPR_LDP_H */
