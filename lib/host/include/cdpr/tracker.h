/// @file tracker.h
/// Tracking controller: desired cabin trajectory -> winch payout-rate commands.
///
/// Once per control period Δt_c, from the measured cabin motion and unstretched lengths L_j:
///  1. feed-forward: sag-aware inverse kinematics (cdpr_statics_ik) of the desired pose at
///     t + Δt_c gives L_ff(t + Δt_c); the feed-forward rate is
///     u_ff = (L_ff(t + Δt_c) - L_ff(t)) / Δt_c, with L_ff(t) kept from the previous period
///     (one IK per period). If IK fails (pose outside the wrench-feasible set, or no
///     convergence), the last good L_ff is held (u_ff = 0) and `ik_failures` counts it.
///  2. feedback on the pose error e_p = p_d - p and e_θ = rotation vector of q_d q^-1 (world
///     axes), and on their rates ė_p = v_d - v, ė_θ = ω_d - ω (world), each low-pass filtered
///     by two first-order stages of time constant filter_s (exact for a signal held over
///     the period),
///     mapped to length corrections through the straight-cable length Jacobian at the
///     measured pose:
///       δL_j = -( kp (u_j·e_p + ((R b_j) x u_j)·e_θ) + kd (u_j·ė_p + ((R b_j) x u_j)·ė_θ) )
///     with u_j the unit vector from attachment j to its exit point: δL_j is the length
///     change that moves the cabin by the error. The filter (two first-order stages) keeps
///     the loop away from the lightly damped fast axial cable/cabin modes (8-10 Hz for the
///     50 m model): unfiltered, kp = 1 with k_L = 5 1/s makes them grow
///     (docs/validation.md §8).
///  3. payout-rate command u_j = u_ff,j + k_L (L_ff,j(t) + δL_j - L_j). The plant's winch
///     (cdpr_winch_update) applies its speed and acceleration limits.
///
/// The controller keeps its own robot model (for the IK), built from the same parameters as
/// the plant, so it needs nothing from the plant but measurements: the real-time loop moves it
/// into a separate process unchanged. Memory: caller-owned object, no allocation. Work per
/// step: one cdpr_statics_ik (bounded iterations) plus O(cables).
#ifndef CDPR_TRACKER_H
#define CDPR_TRACKER_H

#include "cdpr/robot.h"
#include "cdpr/statics.h"
#include "cdpr/status.h"
#include "cdpr/trajectory.h"

/// Gains and period (inputs).
typedef struct {
    double period_s;       ///< control period Δt_c [s] (> 0)
    double kp;             ///< pose-error gain [-] (>= 0)
    double kd_s;           ///< pose-error-rate gain [s] (>= 0)
    double k_length_per_s; ///< length-loop gain k_L [1/s] (>= 0)
    double filter_s;       ///< time constant of the error low-pass [s] (>= 0; 0 = none)
} cdpr_tracker_gains_t;

/// Measurements at the start of a period (inputs).
typedef struct {
    double t_s;                       ///< time [s]
    cdpr_cabin_motion_t cabin;        ///< measured pose and velocities
    double length_m[CDPR_MAX_CABLES]; ///< measured total unstretched lengths [m]
} cdpr_tracker_meas_t;

/// Commands and diagnostics of one period (outputs).
typedef struct {
    double rate_m_per_s[CDPR_MAX_CABLES]; ///< payout-rate commands u_j [m/s], + = pay out
    double l_ff_m[CDPR_MAX_CABLES];       ///< feed-forward lengths L_ff(t) [m]
    double u_ff_m_per_s[CDPR_MAX_CABLES]; ///< feed-forward rates [m/s]
    double dl_m[CDPR_MAX_CABLES];         ///< feedback length corrections δL [m]
    cdpr_traj_sample_t desired;           ///< desired state at t
    double err_pos_m[3];                  ///< e_p = p_d - p, world [m]
    double err_rot_rad[3];                ///< e_θ, world [rad]
    cdpr_status_t ik_status;              ///< status of this period's IK
} cdpr_tracker_cmd_t;

/// The controller (caller-owned).
typedef struct {
    cdpr_robot_t model;             ///< own robot model (statics only)
    cdpr_traj_t traj;               ///< desired trajectory
    cdpr_tracker_gains_t g;         ///< gains
    cdpr_statics_opts_t ik_opts;    ///< IK settings
    double l_ff_m[CDPR_MAX_CABLES]; ///< L_ff at t_next_s (internal)
    double err_f1[12];              ///< first filter stage (internal)
    double err_f[12];               ///< filtered e_p, e_θ, ė_p, ė_θ (internal)
    int filter_primed;              ///< err_f holds a value (internal)
    double t_next_s;                ///< time L_ff refers to (internal)
    unsigned long ik_failures;      ///< periods whose IK failed (output)
    unsigned long steps;            ///< periods run (output)
} cdpr_tracker_t;

/// Validate and initialise: builds the model from `model_params` (6 cables) and computes
/// L_ff(t0). Errors: CDPR_E_INVALID_ARG / CDPR_E_NOT_FINITE / CDPR_E_OUT_OF_RANGE for gains
/// (`diag` names the field), the model's init errors, or the IK status of the desired pose at
/// t0 (e.g. CDPR_E_INFEASIBLE: the trajectory starts outside the feasible set).
cdpr_status_t cdpr_tracker_init(cdpr_tracker_t *tr, const cdpr_robot_params_t *model_params,
                                const cdpr_traj_t *traj, const cdpr_tracker_gains_t *g, double t0_s,
                                cdpr_diag_t *diag);

/// One control period from measurements at m->t_s. Always produces commands (holding the last
/// good feed-forward when the IK fails; cmd->ik_status says why). If m->t_s is not the time
/// the previous step prepared for, L_ff(t) is recomputed first (one more IK).
/// Returns CDPR_OK, or CDPR_E_INVALID_ARG / CDPR_E_NOT_FINITE for bad measurements (no
/// command written, state unchanged).
cdpr_status_t cdpr_tracker_step(cdpr_tracker_t *tr, const cdpr_tracker_meas_t *m,
                                cdpr_tracker_cmd_t *cmd);

/// Rotation vector θ of the unit quaternion q (|θ| <= π, world axes for q_d q^-1) [rad].
cdpr_vec3_t cdpr_quat_to_rotvec(cdpr_quat_t q);

/// Straight-cable length Jacobian row of cable j at motion m: dL_j = -(u·dp + g·dθ) with
/// the returned u (unit vector attachment -> exit point) and g = (R b_j) x u.
void cdpr_tracker_jacobian(const cdpr_robot_t *model, int j, const cdpr_cabin_motion_t *m,
                           cdpr_vec3_t *u, cdpr_vec3_t *g);

#endif /* CDPR_TRACKER_H */
