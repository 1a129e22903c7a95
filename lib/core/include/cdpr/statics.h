/// @file statics.h
/// Sag-aware static equilibrium of the robot (MODEL.md §5): inverse kinematics with elastic
/// catenary cables, the forward problem, the massless straight-cable comparison, and the
/// initial state on the catenaries.
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
/// Memory: caller-owned results, no allocation. Work: bounded by the iteration limits
/// (outer <= max_iter, inner <= max_iter per cable per outer iteration).
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

/// Defaults.
void cdpr_statics_opts_default(cdpr_statics_opts_t *o);

/// Sag-aware inverse kinematics: the six cables' forces and unstretched lengths that hold the
/// cabin at `pose` (velocities ignored) against its weight alone. Requires 6 cables. Errors:
/// CDPR_E_INVALID_ARG, CDPR_E_NOT_FINITE, CDPR_E_GEOMETRY (attachment above/at its exit point
/// horizontally coincident), CDPR_E_INFEASIBLE, CDPR_E_NO_CONVERGENCE; `res` is written only on
/// success.
cdpr_status_t cdpr_statics_ik(const cdpr_robot_t *r, const cdpr_cabin_motion_t *pose,
                              const cdpr_statics_opts_t *o, cdpr_statics_result_t *res);

/// Sag-aware inverse kinematics under the cabin's weight plus an external wrench: the cable
/// forces balance -M g z + f_ext_N and tau_ext_Nm (world axes; the torque about the cabin's
/// centre of mass, f_ext_N acting there; see the model above). With a zero wrench it is
/// cdpr_statics_ik (bit for bit). Same work bound, memory and errors as cdpr_statics_ik, plus
/// CDPR_E_NOT_FINITE for a non-finite wrench; CDPR_E_INFEASIBLE when the loaded equilibrium
/// needs a pushing cable (e.g. a lateral load the cables cannot take at that pose).
cdpr_status_t cdpr_statics_ik_wrench(const cdpr_robot_t *r, const cdpr_cabin_motion_t *pose,
                                     cdpr_vec3_t f_ext_N, cdpr_vec3_t tau_ext_Nm,
                                     const cdpr_statics_opts_t *o, cdpr_statics_result_t *res);

/// Massless straight-cable inverse kinematics for comparison: tensions along the straight
/// chords balancing the cabin weight; lengths are the chords divided by (1 + T/EA).
cdpr_status_t cdpr_statics_ik_straight(const cdpr_robot_t *r, const cdpr_cabin_motion_t *pose,
                                       cdpr_statics_result_t *res);

/// Forward statics: the pose at which cables of unstretched lengths `length_m[j]` hold the
/// cabin in equilibrium, starting the search at `guess`. Newton on the 6 pose coordinates
/// (position and a rotation vector), Jacobian by central differences, bounded iterations.
cdpr_status_t cdpr_statics_forward(const cdpr_robot_t *r, const cdpr_real_t *length_m,
                                   const cdpr_cabin_motion_t *guess, const cdpr_statics_opts_t *o,
                                   cdpr_statics_result_t *res);

/// Place every cable's nodes on its catenary of `res` (from cdpr_statics_ik at the same pose)
/// at their unstretched arclengths, cabin at res->pose, at rest. The robot must have been
/// initialised with length_m[j] = res->cable[j].length_m. Follow with cdpr_settle_robot to
/// reach the discrete chain's own equilibrium.
cdpr_status_t cdpr_statics_place_catenary(const cdpr_robot_t *r, const cdpr_statics_result_t *res,
                                          cdpr_real_t *y);

#endif /* CDPR_STATICS_H */
