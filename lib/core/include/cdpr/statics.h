/// @file statics.h
/// Sag-aware static equilibrium of the robot (MODEL.md §5): inverse kinematics with elastic
/// catenary cables, the forward problem, the massless straight-cable comparison, and the
/// initial state on the catenaries.
///
/// Model: each cable j is an elastic catenary (catenary.h) in the vertical plane through its
/// cabin attachment P_j = p + R b_j and its exit point A_j. It pulls the cabin with
/// F_j = H_j e_j + V_j z, e_j the horizontal unit vector from P_j toward A_j, V_j the vertical
/// tension component at the cabin end. Equilibrium of the cabin (mass M, CoM c):
///   sum_j F_j - M g z = 0,   sum_j (R (b_j - c)) x F_j = 0.
/// Inverse problem: pose given, unknowns H_j (6 cables: 6 wrench equations); for each H_j the
/// catenary through P_j and A_j fixes (V_j, L_j). Safeguarded Newton, analytic Jacobian,
/// bounded iterations. A pose whose equilibrium needs a pushing cable (H_j <= 0) is outside
/// the wrench-feasible set: CDPR_E_INFEASIBLE.
///
/// Memory: caller-owned results, no allocation. Work: bounded by the iteration limits
/// (outer <= max_iter, inner <= max_iter per cable per outer iteration).
#ifndef CDPR_STATICS_H
#define CDPR_STATICS_H

#include "cdpr/cabin.h"
#include "cdpr/config.h"
#include "cdpr/robot.h"
#include "cdpr/status.h"

/// Solver settings.
typedef struct {
    int max_iter;            ///< outer Newton iterations (> 0); default 50
    cdpr_real_t force_tol_N; ///< wrench residual tolerance [N and N m] (> 0); default 1e-7
    cdpr_real_t span_tol_m;  ///< per-cable catenary span tolerance [m] (> 0); default 1e-10
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
/// cabin at `pose` (velocities ignored). Requires 6 cables. Errors: CDPR_E_INVALID_ARG,
/// CDPR_E_NOT_FINITE, CDPR_E_GEOMETRY (attachment above/at its exit point horizontally
/// coincident), CDPR_E_INFEASIBLE, CDPR_E_NO_CONVERGENCE; `res` is written only on success.
cdpr_status_t cdpr_statics_ik(const cdpr_robot_t *r, const cdpr_cabin_motion_t *pose,
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
/// initialised with length_m[j] = res->cable[j].length_m. Follow with cdpr_robot_settle to
/// reach the discrete chain's own equilibrium.
cdpr_status_t cdpr_robot_place_catenary(const cdpr_robot_t *r, const cdpr_statics_result_t *res,
                                        cdpr_real_t *y);

#endif /* CDPR_STATICS_H */
