/* SPDX-License-Identifier: BSD-3-Clause */
/// @file statics.h
/// Sag-aware static equilibrium of the robot: inverse kinematics with elastic catenary cables,
/// the forward problem, the massless straight-cable comparison, and the initial state on the
/// catenaries (docs/model.md "Sag-aware inverse kinematics, with an external wrench").
///
/// Model: each cable j is an elastic catenary (catenary.h) in the vertical plane through its
/// cabin attachment P_j = p + R b_j and its exit point A_j. It pulls the cabin with
/// F_j = H_j e_j + V_j z, e_j the horizontal unit vector from P_j toward A_j, V_j the vertical
/// tension component at the cabin end. Equilibrium of the cabin (mass M, CoM c, both of the
/// cabin alone: r->p.cabin; the cables' own weight is in the catenaries), with an optional
/// external wrench (f_ext, tau_ext):
///   sum_j F_j - M g z + f_ext = 0,   sum_j (R (b_j - c)) x F_j + tau_ext = 0,
/// all in world axes, moments about the cabin's centre of mass p + R c. f_ext acts at the CoM
/// (a force f applied at another point, world offset d from the CoM, adds d x f to tau_ext).
/// The d'Alembert load of a cabin moving with CoM acceleration a_c, body rates ω, ω̇ is
/// f_ext = -M a_c, tau_ext = -R (I_c ω̇ + ω x I_c ω) (tracker.h).
/// Inverse problem: pose given, unknowns H_j (6 cables: 6 wrench equations); for each H_j the
/// catenary through P_j and A_j fixes (V_j, L_j). Safeguarded Newton, analytic Jacobian,
/// bounded iterations. A pose whose equilibrium needs a pushing cable (H_j <= 0) is outside
/// the wrench-feasible set: CDPR_E_INFEASIBLE. Note that a heavy cable long enough to hang in
/// a loop below its ends pulls its cabin end down with any force: the catenary equations also
/// have solutions, returned as such, for poses and loads a massless-cable robot cannot hold,
/// with some cable several chords long (e.g. 85 m on a 30 m chord at (3, -2, 12) m tilted, in
/// test_gsl_statics; 0.4 km for a sideways load of one cabin weight at the circle's start).
/// Callers that command lengths should check L_j against the chord.
///
/// Memory: caller-owned results, no allocation. Work: bounded by the iteration limits, given
/// per function. Every function requires 6 cables (the wrench has 6 components). Pointer
/// arguments must be valid unless a function says it checks them.
#ifndef CDPR_STATICS_H
#define CDPR_STATICS_H

#include "cdpr/cabin.h"
#include "cdpr/config.h"
#include "cdpr/robot.h"
#include "cdpr/status.h"

/// Solver settings. Defaults depend on the real type (config.h): double 1e-7 N, 1e-10 m;
/// float (CDPR_REAL_IS_FLOAT) 2e-2 N, 1e-4 m. The solvers add 1e3 eps |load| to force_tol_N
/// (0.047 N in float for the 40 kg cabin of the 50 m model).
///
/// The float values are measured floors with margin (50 m model, 2000 and 10 000 random poses
/// of its workspace: x, y within 6 m, z 6-20 m, angles within 0.15 rad; tensions 5-600 N).
/// The inner catenary residual |dl| + |dh| gets down to ~5e-5 m on ~30 m spans (a few ulp of
/// 32 m = 3.8e-6 m); 1e-5 m failed at 14 % of the poses, 5e-5 m at none: span_tol_m = 1e-4 m.
/// With that, the IK wrench residual gets down to ~1e-2 N (the inner solves' stopping points
/// feed the outer Newton, well above u_f sum_j |T_j| ~ 1e-4 N); force_tol_N = 2e-2 N is the
/// smallest value at which float IK converged at every pose where double did, measured
/// without the 1e3 eps |load| term (as for a light cabin). Spans well
/// beyond 100 m need a proportionally larger span_tol_m in float (ulp grows with the span).
///
/// cdpr_statics_forward in float: its residual is a wrench at a rounded pose, and the pose's
/// rounding (u_f |p|, 7e-7 m at 12 m) times the cables' stiffness (~6 EA / L = 4e5 N/m for the
/// 50 m model) is ~0.3 N, above the IK default: pass force_tol_N ~ 0.3 N there. The pose error
/// is then up to that residual over the stiffness of the softest mode (240 N/m: ~1.5e-3 m).
/// Start it within ~0.1 m: a guess that stretches a cable to many times its working tension
/// needs a catenary whose span float resolves only to ~u_f H / w (1.6e-3 m at H = 37 kN,
/// w = 1.4 N/m), above span_tol_m.
typedef struct {
    int max_iter;            ///< outer Newton iterations (> 0); default 50
    cdpr_real_t force_tol_N; ///< wrench residual tolerance [N and N m] (> 0); default above
    cdpr_real_t span_tol_m;  ///< per-cable catenary span tolerance [m] (> 0); default above
} cdpr_statics_opts_t;

/// Equilibrium of one cable (outputs).
typedef struct {
    cdpr_real_t H_N;              ///< horizontal tension [N]
    cdpr_real_t v_cabin_N;        ///< vertical tension component at the cabin end [N]
    cdpr_real_t length_m;         ///< unstretched length L_j [m]
    cdpr_real_t tension_cabin_N;  ///< |T| at the cabin end [N]
    cdpr_real_t tension_winch_N;  ///< |T| at the exit point [N]
    cdpr_vec3_t force_on_cabin_N; ///< F_j [N]
    cdpr_vec3_t attach_world_m;   ///< P_j [m]
} cdpr_statics_cable_t;

/// Result of a statics solve.
typedef struct {
    int n_cables;
    cdpr_statics_cable_t cable[CDPR_MAX_CABLES];
    cdpr_cabin_motion_t pose; ///< the pose solved for (forward) or given (inverse), at rest
    int iterations;           ///< outer iterations used
    cdpr_real_t residual;     ///< final wrench residual norm [N, N m]
} cdpr_statics_result_t;

/// Defaults. O(1), cannot fail.
void cdpr_statics_opts_default(cdpr_statics_opts_t *o);

/// Sag-aware inverse kinematics: the six cables' forces and unstretched lengths that hold the
/// cabin at `pose` (velocities ignored) against its weight alone: cdpr_statics_ik_wrench with
/// a zero wrench (same work, results and errors).
cdpr_status_t cdpr_statics_ik(const cdpr_robot_t *r, const cdpr_cabin_motion_t *pose,
                              const cdpr_statics_opts_t *o, cdpr_statics_result_t *res);

/// Sag-aware inverse kinematics under the cabin's weight plus an external wrench: the cable
/// forces balance -M g z + f_ext_N and tau_ext_Nm (world axes; the torque about the cabin's
/// centre of mass, f_ext_N acting there; see the model above). With a zero wrench it is
/// cdpr_statics_ik (bit for bit). Newton on the 6 H_j from the massless solution for the same
/// load; converged when the wrench residual norm <= force_tol_N + 1e3 eps |load|, with
/// |load| = M g + |f_ext_N| + |tau_ext_Nm|.
/// Work: at most 1 + 40 max_iter wrench evaluations, each 6 inner catenary solves of at most
/// 2 (max_iter + 1) Newton iterations with up to 41 closed-form evaluations each; no
/// allocation. `res` is written only on success. Returns:
/// - CDPR_E_INVALID_ARG: r, pose, res or o is NULL, r->p.n_cables != 6, or o->max_iter < 1.
/// - CDPR_E_NOT_FINITE: o->force_tol_N or o->span_tol_m, pose->p_m, pose->q or the wrench is
///   NaN/Inf; CDPR_E_NOT_POSITIVE: a tolerance <= 0.
/// - CDPR_E_GEOMETRY: an attachment and its exit point are horizontally coincident (span
///   <= 1e-9 (1 + |rise|) m): a vertical cable has no catenary plane.
/// - CDPR_E_INFEASIBLE: the equilibrium needs a pushing cable: every exit point is at or
///   below its attachment while the load needs an upward pull; the Newton Jacobian is
///   singular; Newton stops (iteration bound, or no descent) while its last full step would
///   make some H_j <= 0, or finds no descent with some H_j < 1e-6 |load|; or Newton fails and
///   the massless model has no all-pulling solution either (e.g. a lateral load the cables
///   cannot take at that pose).
/// - CDPR_E_NO_CONVERGENCE: any other failure of the outer Newton or of an inner catenary
///   solve (iteration bound, no descent within 40 step halvings).
/// CDPR_OK otherwise.
cdpr_status_t cdpr_statics_ik_wrench(const cdpr_robot_t *r, const cdpr_cabin_motion_t *pose,
                                     cdpr_vec3_t f_ext_N, cdpr_vec3_t tau_ext_Nm,
                                     const cdpr_statics_opts_t *o, cdpr_statics_result_t *res);

/// Massless straight-cable inverse kinematics for comparison: tensions along the straight
/// chords balancing the cabin weight (same tension at both ends); lengths are the chords
/// divided by (1 + T/EA). One 6x6 linear solve: O(1), no allocation. `res` is written only on
/// success (iterations 0, residual 0). Returns:
/// - CDPR_E_INVALID_ARG: r, pose or res is NULL, or r->p.n_cables != 6.
/// - CDPR_E_NOT_FINITE: pose->p_m or pose->q is NaN/Inf.
/// - CDPR_E_GEOMETRY: as cdpr_statics_ik_wrench.
/// - CDPR_E_INFEASIBLE: the chord directions cannot span the wrench (singular), or some
///   tension would be <= 0.
/// CDPR_OK otherwise.
cdpr_status_t cdpr_statics_ik_straight(const cdpr_robot_t *r, const cdpr_cabin_motion_t *pose,
                                       cdpr_statics_result_t *res);

/// Straight-chord tensions t_j that balance the cabin weight plus an external wrench (f_ext at
/// the CoM, tau_ext about it, world axes) at `pose`: the massless model with straight chords
/// from attachment to exit point, sum t_j u_j = M g z - f_ext, sum t_j (R (b_j - c)) x u_j =
/// -tau_ext. Negative tensions are returned as they are (a cable that would have to push):
/// this is the diagnostic of a load the cables cannot hold, the tension distribution a
/// controller reports, and, with f = tau = 0 and every t_j > 0, the tensions of
/// cdpr_statics_ik_straight. One 6x6 solve (Gaussian elimination, partial pivoting); O(1), no
/// allocation; `tension_N` (6 values) written only on success. Returns:
/// - CDPR_E_INVALID_ARG: a NULL pointer, or r->p.n_cables != 6.
/// - CDPR_E_NOT_FINITE: the pose or the wrench is NaN/Inf.
/// - CDPR_E_INFEASIBLE: the chords do not span the wrench (a pivot below 1e-12 of the largest
///   matrix entry: singular).
/// CDPR_OK otherwise.
cdpr_status_t cdpr_statics_straight_tensions(const cdpr_robot_t *r, const cdpr_cabin_motion_t *pose,
                                             cdpr_vec3_t f_ext_N, cdpr_vec3_t tau_ext_Nm,
                                             cdpr_real_t *tension_N);

/// Forward statics: the pose at which cables of unstretched lengths `length_m[j]` hold the
/// cabin in equilibrium, starting the search at `guess`. Newton on the 6 pose coordinates
/// (position and a rotation vector), Jacobian by central differences; converged when the
/// wrench residual norm <= force_tol_N + 1e3 eps M g. Work: at most 1 + 52 max_iter wrench
/// evaluations (12 for the Jacobian, up to 40 in the line search), each 6 cdpr_catenary_solve
/// calls of at most 3 + 40 max_iter span evaluations; no allocation. `res` is written only on
/// success. Returns:
/// - CDPR_E_INVALID_ARG: r, length_m, guess, res or o is NULL, r->p.n_cables != 6, or
///   o->max_iter < 1.
/// - CDPR_E_NOT_FINITE / CDPR_E_NOT_POSITIVE: a tolerance or length_m[j] NaN/Inf / <= 0;
///   CDPR_E_NOT_FINITE: guess->p_m or guess->q NaN/Inf.
/// - CDPR_E_GEOMETRY (as cdpr_statics_ik_wrench) or an error of cdpr_catenary_solve at the
///   guess or at a pose of the difference Jacobian.
/// - CDPR_E_INFEASIBLE: the Jacobian is singular (no static stiffness in some direction).
/// - CDPR_E_NO_CONVERGENCE: max_iter iterations, or no descent within 40 step halvings.
/// CDPR_OK otherwise.
cdpr_status_t cdpr_statics_forward(const cdpr_robot_t *r, const cdpr_real_t *length_m,
                                   const cdpr_cabin_motion_t *guess, const cdpr_statics_opts_t *o,
                                   cdpr_statics_result_t *res);

/// Place every cable's nodes on its catenary of `res` (from cdpr_statics_ik at the same pose)
/// at their unstretched arclengths, cabin at res->pose, at rest; writes r->dim components.
/// The robot must have been initialised with length_m[j] = res->cable[j].length_m (not
/// checked). Follow with cdpr_settle_robot to reach the discrete chain's own equilibrium.
/// O(total nodes), no allocation. Returns (y untouched on error):
/// - CDPR_E_INVALID_ARG: r, res or y is NULL, res->n_cables != r->p.n_cables, or
///   r->p.n_cables != 6.
/// - CDPR_E_NOT_FINITE: res->pose.p_m or res->pose.q is NaN/Inf.
/// - CDPR_E_GEOMETRY: as cdpr_statics_ik_wrench.
/// CDPR_OK otherwise.
cdpr_status_t cdpr_statics_place_catenary(const cdpr_robot_t *r, const cdpr_statics_result_t *res,
                                          cdpr_real_t *y);

#endif /* CDPR_STATICS_H */
