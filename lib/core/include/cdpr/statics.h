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
/// Inverse problem: pose given, unknowns H_j (m cables, 6 wrench equations); for each H_j the
/// catenary through P_j and A_j fixes (V_j, L_j). Six cables: safeguarded Newton, analytic
/// Jacobian, bounded iterations. More than six (redundant): the tension distribution
/// (cdpr_statics_dist_t) picks the equilibrium, by sequential quadratic programming (each
/// step the least-distance problem of the linearised equilibrium and bounds). A pose whose
/// equilibrium needs a pushing cable (H_j <= 0) is outside the wrench-feasible set:
/// CDPR_E_INFEASIBLE. A heavy cable long enough to hang in a loop below its ends pulls its
/// cabin end down with any force, so the catenary equations also have solutions for poses and
/// loads a massless-cable robot cannot hold, with some cable several chords long (e.g. 85 m on
/// a 30 m chord at (3, -2, 12) m tilted; 0.4 km for a sideways load of one cabin weight at the
/// circle's start). The forward statics accepts them as equilibria; the inverse kinematics
/// reports them as CDPR_E_INFEASIBLE (CDPR_STATICS_WHY_LOOP, beyond
/// CDPR_STATICS_MAX_LENGTH_PER_CHORD): no robot works there, and its verdict "infeasible"
/// then agrees with the forward statics within the lengths a robot uses.
///
/// Memory: caller-owned results, no allocation. Work: bounded by the iteration limits, given
/// per function. Pointer arguments must be valid unless a function says it checks them.
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

/// Longest unstretched length, in chords (straight distances from the attachment to the exit
/// point), of a cable in an inverse-kinematics solution. Beyond it a heavy cable hangs in a
/// loop below its ends: an equilibrium of the catenaries that no working pose is near (1-5 %
/// above the chord in the scenarios), and that the forward statics also accepts. The inverse
/// kinematics reports such a pose as CDPR_E_INFEASIBLE (CDPR_STATICS_WHY_LOOP) instead.
#define CDPR_STATICS_MAX_LENGTH_PER_CHORD CDPR_R(1.5)

/// Tension distribution of a redundant robot (m > 6 cables): the equilibrium whose lowest
/// tensions along each cable, t_j, are closest to t_ref_N in the 2-norm,
/// min sum_j (t_j - t_ref_N)^2, subject to t_j >= t_min_N and the highest tension along every
/// cable <= t_max_N. The lowest tension is at the cabin end of a cable that rises from the
/// cabin, at the catenary's vertex if it dips below it; the highest at the upper end. With
/// t_ref_N at mid-range this is the criterion of the closed-form method of Pott, Bruckmann and
/// Mikelsons (2009), here met exactly with the bounds enforced, on sagging cables
/// (docs/model.md). For six cables there is nothing to choose: the bounds are checked.
typedef struct {
    cdpr_real_t t_min_N; ///< lower bound (>= 0) [N]
    cdpr_real_t t_max_N; ///< upper bound (> t_min_N) [N]
    cdpr_real_t t_ref_N; ///< reference of the criterion, in [t_min_N, t_max_N] [N]
} cdpr_statics_dist_t;

/// Why a pose has no equilibrium the inverse kinematics accepts (CDPR_E_INFEASIBLE).
typedef enum {
    CDPR_STATICS_WHY_NONE = 0, ///< a solution was found (or the error was another)
    CDPR_STATICS_WHY_PUSH,     ///< cable `cable` would have to push (H <= 0)
    CDPR_STATICS_WHY_NO_LIFT,  ///< no exit point above its attachment, the load needs a lift
    CDPR_STATICS_WHY_SPAN,     ///< the cables cannot span the wrench (singular directions)
    CDPR_STATICS_WHY_LOOP,     ///< cable `cable` would be longer than the chord limit (loop)
    CDPR_STATICS_WHY_T_MIN,    ///< cable `cable` cannot be kept at or above t_min_N
    CDPR_STATICS_WHY_T_MAX     ///< cable `cable` cannot be kept at or below t_max_N
} cdpr_statics_why_t;

/// The verdict of an inverse-kinematics solve: for CDPR_E_INFEASIBLE the reason, the cable
/// (0-based, -1 when no single cable is to blame), the value that breaks the bound (N, or
/// length per chord for LOOP; NaN when there is none) and the bound.
typedef struct {
    cdpr_statics_why_t why;
    int cable;
    cdpr_real_t value;
    cdpr_real_t limit;
} cdpr_statics_verdict_t;

/// Bounds t_min_N, t_max_N and the reference at mid-range. O(1), cannot fail (not checked
/// here: cdpr_statics_ik_dist checks them).
void cdpr_statics_dist_init(cdpr_statics_dist_t *d, cdpr_real_t t_min_N, cdpr_real_t t_max_N);

/// Sag-aware inverse kinematics: the six cables' forces and unstretched lengths that hold the
/// cabin at `pose` (velocities ignored) against its weight alone: cdpr_statics_ik_wrench with
/// a zero wrench (same work, results and errors).
cdpr_status_t cdpr_statics_ik(const cdpr_robot_t *r, const cdpr_cabin_motion_t *pose,
                              const cdpr_statics_opts_t *o, cdpr_statics_result_t *res);

/// Sag-aware inverse kinematics of a six-cable robot under the cabin's weight plus an external
/// wrench: the cable forces balance -M g z + f_ext_N and tau_ext_Nm (world axes; the torque
/// about the cabin's centre of mass, f_ext_N acting there; see the model above). With a zero
/// wrench it is cdpr_statics_ik (bit for bit); it is cdpr_statics_ik_dist without bounds.
/// Newton on the 6 H_j from the massless solution for the same load; converged when the
/// wrench residual norm <= force_tol_N + 1e3 eps |load|, with
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
///   cannot take at that pose); or the equilibrium has a cable longer than
///   CDPR_STATICS_MAX_LENGTH_PER_CHORD chords (a loop).
/// - CDPR_E_NO_CONVERGENCE: any other failure of the outer Newton or of an inner catenary
///   solve (iteration bound, no descent within 40 step halvings).
/// CDPR_OK otherwise.
cdpr_status_t cdpr_statics_ik_wrench(const cdpr_robot_t *r, const cdpr_cabin_motion_t *pose,
                                     cdpr_vec3_t f_ext_N, cdpr_vec3_t tau_ext_Nm,
                                     const cdpr_statics_opts_t *o, cdpr_statics_result_t *res);

/// Sag-aware inverse kinematics of a robot with m >= 6 cables, with a tension distribution:
/// the equilibrium at `pose` under the weight and the external wrench (as
/// cdpr_statics_ik_wrench) that meets `dist` (cdpr_statics_dist_t: every cable's lowest
/// tension >= t_min_N, highest <= t_max_N, lowest tensions closest to t_ref_N).
/// - dist NULL: the robot's own distribution (robot.h: has_tension_dist, tension_min_N, ...)
///   if it has one, else none.
/// - m == 6: cdpr_statics_ik_wrench's solution, bit for bit, then the bounds (if any) are
///   checked.
/// - m > 6 (a distribution required): sequential quadratic programming on the m H_j from the
/// massless
///   distribution (the same criterion and bounds on straight chords). Each iteration solves the
///   inner catenaries (with dV/dH, dL/dH), linearises the equilibrium (6 equations) and the
///   tension ranges in H, with the Lagrangian's (diagonal) curvature, and takes the step of the
///   least-distance problem (QR of the equilibrium's Jacobian for its null space, then
///   Lawson-Hanson NNLS on the bounds), followed by Newton back onto the equilibria and
///   backtracking on an exact-penalty merit (docs/model.md). Converged when the wrench residual
///   <= force_tol_N + 1e3 eps |load| and the step changes no lowest tension by more than that
///   plus 10 sqrt(eps) max_j |lowest tension_j - t_ref_N|.
/// Work: at most max_iter + 1 iterations, each with one least-distance problem (at most 6 m
/// NNLS iterations of at most 2 m least-squares solves of m - 5 rows), 2 m inner solves for
/// the curvature, and at most 40 trial steps of at most 1 + 8 x 40 wrench evaluations (the
/// step, then at most 8 restoring Newton steps of at most 40 halvings), each m inner catenary
/// solves as in cdpr_statics_ik_wrench; no allocation.
/// `res` is written only on success; `why` (may be NULL) always: the verdict. Returns:
/// - CDPR_E_INVALID_ARG: r, pose, res or o NULL; m < 6 or m > CDPR_MAX_CABLES; m > 6 with no
///   distribution (dist NULL and none in the robot); o->max_iter < 1.
/// - CDPR_E_NOT_FINITE / CDPR_E_NOT_POSITIVE: as cdpr_statics_ik_wrench; CDPR_E_NOT_FINITE
///   or CDPR_E_OUT_OF_RANGE: a bound or the reference NaN/Inf, t_min_N < 0,
///   t_max_N <= t_min_N (T_min > T_max), t_ref_N outside [t_min_N, t_max_N].
/// - CDPR_E_GEOMETRY: as cdpr_statics_ik_wrench.
/// - CDPR_E_INFEASIBLE with why->why: PUSH (a cable would push; the cable named), NO_LIFT,
///   SPAN (the cables cannot span the wrench), LOOP (the first cable longer than
///   CDPR_STATICS_MAX_LENGTH_PER_CHORD chords, value = its length per chord), T_MIN / T_MAX
///   (m == 6: the cable whose tension range leaves the bounds most; m > 6: at an equilibrium
///   the bounds cannot be met along its tangent, the cable of the bound that weighs most in
///   the least-distance problem's certificate; value = its tension there, limit = the bound).
/// - CDPR_E_NO_CONVERGENCE: the iteration bound, no acceptable step, or an inner solve failed.
/// CDPR_OK otherwise.
cdpr_status_t cdpr_statics_ik_dist(const cdpr_robot_t *r, const cdpr_cabin_motion_t *pose,
                                   cdpr_vec3_t f_ext_N, cdpr_vec3_t tau_ext_Nm,
                                   const cdpr_statics_dist_t *dist, const cdpr_statics_opts_t *o,
                                   cdpr_statics_result_t *res, cdpr_statics_verdict_t *why);

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

/// Forward statics: the pose at which the m >= 6 cables of unstretched lengths `length_m[j]`
/// hold the cabin in equilibrium, starting the search at `guess`. Newton on the 6 pose
/// coordinates (position and a rotation vector), Jacobian by central differences; converged
/// when the wrench residual norm <= force_tol_N + 1e3 eps M g, or, once Newton can go no
/// further (iteration bound, no descent), when it is within that plus the residual's rounding
/// floor at the problem's scale, 8 eps sum_j (EA_j / L_j) (|p_guess| + |A_j|): the spans are
/// known to the rounding of the coordinates and the cables' axial stiffness turns that into a
/// force (2e-6 N for the 30 t FAST cabin on 300 m cables, where the fixed tolerance alone left
/// 3-4 of 49 poses unconverged depending on the last bits of the input; 2e-8 N for the 50 m
/// model). Work: at most 1 + 52 max_iter wrench evaluations (12 for the Jacobian, up to 40 in
/// the line search), each m cdpr_catenary_solve calls of at most 3 + 40 max_iter span
/// evaluations; no allocation. `res` is written only on success. Returns:
/// - CDPR_E_INVALID_ARG: r, length_m, guess, res or o is NULL, r->p.n_cables < 6, or
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
///   r->p.n_cables < 6.
/// - CDPR_E_NOT_FINITE: res->pose.p_m or res->pose.q is NaN/Inf.
/// - CDPR_E_GEOMETRY: as cdpr_statics_ik_wrench.
/// CDPR_OK otherwise.
cdpr_status_t cdpr_statics_place_catenary(const cdpr_robot_t *r, const cdpr_statics_result_t *res,
                                          cdpr_real_t *y);

#endif /* CDPR_STATICS_H */
