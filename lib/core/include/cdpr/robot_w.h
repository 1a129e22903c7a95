/* SPDX-License-Identifier: BSD-3-Clause */
/// @file robot_w.h
/// The W-matrix of the robot for ros34pw2.h: W = I - gamma h J with an approximate Jacobian J
/// of cdpr_robot_rhs that keeps the stiff part, the axial and transverse segment stiffness and
/// the axial damping inside every cable, and solves W x = b in O(total segments)
/// (docs/model.md "Time integration", "The W-matrix of the robot").
///
/// J, per cable, on the free nodes 1..n-1 (positions r, velocities v):
///   J = [[0, I], [M^-1 K, M^-1 C]],
/// K and C block tridiagonal (3x3 blocks) from the segment forces S_k = T_k t_k:
///   A_k = dS_k/dd_k     = (dT/dl) t tT + (T/l)(I - t tT),   d_k = r_{k+1} - r_k,
///   B_k = dS_k/d(dv_k)  = (dT/dl') t tT,                   dv_k = v_{k+1} - v_k,
/// with the law of cable.h: passive T = max(0, EA max(eps, 0) + c eps'): dT/dl = EA/lu when
/// eps > 0 and T > 0, dT/dl' = c/lu when T > 0; MoorDyn: dT/dl = EA/lu when eps > 0,
/// dT/dl' = c/lu always. The pulley-side segment uses its state length lu = y[offset] and the
/// last free node its state-dependent mass; the column of lu = y[offset] holds dS_{n-1}/dlu =
/// (dT/dlu) t on node n-1 (and on the cabin for a one-segment cable). M = diag(m_i I).
/// The cabin (dynamic mode) is implicit too: node 0 of cable j moves as
/// dr_0 = Gam_j (dp, dth), Gam_j = [I, -R [a_j]x], a_j = b_j - c (attachment about the combined
/// CoM), dth the body rotation increment (dq = 1/2 Xi(q) dth), so segment 0 couples node 1 to
/// the cabin's generalised coordinates with the blocks Gam_jT A_0 Gam_j, Gam_jT A_0 (and B_0),
/// and the cabin's generalised mass is diag(m_c I, I_c). In prescribed mode the cabin rows are
/// identity rows (the cabin state is not integrated) and the coupling is dropped.
/// Dropped (allowed by the W-method, which keeps order 3 for any J; docs/model.md lists why
/// each is small or slow): drag derivatives; the change of the damper force with direction,
/// c (I - t tT) dv / (l lu); d m_{n-1}/dlu of the last free node (dT/dlu of the pulley-side
/// segment is kept: the payout moves that stiff spring's rest length); the payout rows are
/// identity rows, which is exact (d lu/dt = u is constant); for the cabin: the
/// gyroscopic term, the CoM offset terms of the translation (v_dot = F/m_c is used), the
/// change of the torque arm and of R^T with the attitude (T a x dth terms), the velocity
/// dependence of v_0 on the attitude, dq_dot/dq, and the external loads and gravity (constant).
///
/// Solve: with g = gamma h, W x = b is solved through the Schur complement on the velocities
/// (node velocities and the cabin's (v, w)), multiplied by the masses so that it is symmetric
/// positive definite for the passive law:
///   G x_z = M b_z + g K b_u,   G = M - g C - g^2 K,   x_u = b_u + g x_z,
/// (u: positions, cabin p and dth = 2 XiT b_q; x_q = b_q + g/2 Xi x_w). G is an arrowhead of
/// block-tridiagonal cables joined at the cabin: each cable is eliminated by the block Thomas
/// algorithm from the pulley end towards node 1 (block LDL^T without pivoting), which leaves a
/// 6x6 Schur complement on the cabin (LU with partial pivoting); O(n) per cable, O(cables) for
/// the cabin.
///
#ifndef CDPR_ROBOT_W_H
#define CDPR_ROBOT_W_H

#include "cdpr/config.h"
#include "cdpr/robot.h"
#include "cdpr/status.h"

/// Factorisation of W for one (t, y, gamma h) (internal fields; read-only for users).
typedef struct {
    const cdpr_robot_t *robot; ///< the robot whose W this is (not owned)
    cdpr_real_t gamma_h;       ///< gamma h of the last factorisation [s]
    int factored;              ///< 1 after a successful cdpr_robot_w_factor
    /// Per cable j and segment k: T/l [N/m], dT/dl - T/l [N/m], unit tangent (3), dT/dl'
    /// [N s/m]: A_k = (T/l) I + (dT/dl - T/l) t tT, B_k = (dT/dl') t tT.
    cdpr_real_t seg[CDPR_MAX_CABLES][CDPR_MAX_SEGMENTS][6];
    /// Per cable j and free node i (index i - 1): inverse of the pivot block D'_i, symmetric,
    /// packed xx, xy, xz, yy, yz, zz.
    cdpr_real_t dinv[CDPR_MAX_CABLES][CDPR_MAX_SEGMENTS][6];
    /// Per cable j and free node i < n - 1: R_i = D'_{i+1}^-1 P_i (row-major 3x3),
    /// P_i = g B_i + g^2 A_i (the elimination runs from the pulley end to node 1).
    cdpr_real_t q[CDPR_MAX_CABLES][CDPR_MAX_SEGMENTS][9];
    /// Per cable j and free node i: node mass m_i [kg].
    cdpr_real_t mass[CDPR_MAX_CABLES][CDPR_MAX_SEGMENTS];
    cdpr_real_t p0[CDPR_MAX_CABLES][6];  ///< P_0 of cable j (packed symmetric)
    cdpr_real_t dtdlu[CDPR_MAX_CABLES];  ///< dT/dlu of the pulley-side segment [N/m]
    cdpr_real_t gam[CDPR_MAX_CABLES][9]; ///< X_j = -R [a_j]x (row-major): Gam_j = [I, X_j]
    cdpr_real_t qhat[4];                 ///< normalised cabin quaternion (w, x, y, z)
    cdpr_real_t mass_c;                  ///< combined cabin mass [kg]
    cdpr_real_t inertia_c[9];            ///< combined inertia about the CoM, body axes
    cdpr_real_t s6[36];                  ///< LU factors of the cabin Schur complement
    int piv6[6];                         ///< its row pivots
    int cabin_implicit;                  ///< 1: dynamic mode (cabin rows implicit)
} cdpr_robot_w_t;

/// Bind to a robot (not factored yet). O(1). CDPR_E_INVALID_ARG when w or r is NULL;
/// CDPR_OK otherwise.
cdpr_status_t cdpr_robot_w_init(cdpr_robot_w_t *w, const cdpr_robot_t *r);

/// ros34pw2.h factor callback (ctx: cdpr_robot_w_t *): J of the file comment at (t, y) and the
/// block LDL^T of every cable's G for gamma_h. Work: O(total segments): per segment 1 square
/// root and 2 divisions, per free node one 3x3 symmetric inverse and two 3x3 products, plus a
/// 6x6 LU for the cabin; no allocation; one call of the robot's motion_fn in prescribed mode.
/// Returns CDPR_OK, or CDPR_E_SINGULAR when a pivot block or the cabin's Schur complement is
/// singular or not finite (NaN/Inf in y, gamma_h) or gamma_h is not finite and >= 0, or
/// CDPR_E_INVALID_ARG for a NULL argument; on error the object is marked not factored.
cdpr_status_t cdpr_robot_w_factor(void *ctx, cdpr_real_t t, const cdpr_real_t *y,
                                  cdpr_real_t gamma_h);

/// ros34pw2.h solve callback: x = W^-1 b for the last factorisation (robot->dim components;
/// b, x must not overlap). Work: O(total segments), about 80 multiply-adds per free node; no
/// allocation. CDPR_E_SINGULAR when not factored (no factorisation, or the last one failed);
/// CDPR_E_INVALID_ARG for a NULL argument; CDPR_OK otherwise (NaN/Inf in b propagate to x).
cdpr_status_t cdpr_robot_w_solve(void *ctx, const cdpr_real_t *b, cdpr_real_t *x);

#endif /* CDPR_ROBOT_W_H */
