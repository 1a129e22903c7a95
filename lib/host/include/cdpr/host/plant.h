/// @file plant.h
/// The plant of a scenario: the lumped-mass robot, its integrator and its winches, stepped one
/// control period at a time from winch commands. The batch runner (sim.h) and the real-time
/// node (apps/cdpr-rt) both use it, so a closed loop over LCM and the in-process loop step the
/// model with the same code, in the same order, on the same numbers.
///
/// Initialisation (cdpr_plant_init, not real-time): sag-aware IK at the scenario's initial pose
/// gives the unstretched lengths; the robot is built with them, its nodes placed on the
/// catenaries (cdpr_statics_place_catenary) and settled to the discrete model's own static
/// equilibrium (cdpr_settle_robot), so it starts at rest; winches at rest in rate mode; the
/// run's RKF45 with the scenario's tolerances.
///
/// One period (cdpr_plant_step, real-time safe), from t_k = k Δt to t_{k+1}:
///   command each winch (rate or length mode) -> cdpr_winch_update from the measured length
///   (speed/acceleration limits, minimum length) -> cdpr_rkf45_advance over exactly Δt with at
///   most max_trials trials -> cdpr_robot_normalize -> cdpr_winch_node_events (resize the
///   integrator and refresh the per-component tolerances when the layout changed).
/// A failed advance (integrator error, or a trial budget that cannot cover Δt stably) leaves
/// the plant exactly as it was before the call (state, time, winches) and says so: the caller
/// keeps the last good state and tries again next period.
///
/// Memory: caller-owned (about 200 kB at the default capacities: declare it static or
/// allocate it once). cdpr_plant_step and cdpr_plant_measure make no allocation, no system
/// call, no I/O; work per step is bounded by 6 max_trials robot RHS evaluations plus
/// O(state dimension).
#ifndef CDPR_HOST_PLANT_H
#define CDPR_HOST_PLANT_H

#include "cdpr/rkf45.h"
#include "cdpr/robot.h"
#include "cdpr/host/scenario.h"
#include "cdpr/statics.h"
#include "cdpr/host/tracker.h"
#include "cdpr/winch.h"

/// Bits of the `flags` returned by cdpr_plant_step (equal to cabin_state_t.FLAG_* of lcmtypes).
enum {
    CDPR_PLANT_SUBSTEP_LIMIT = 2, ///< the advance met its trial bound (tolerance not met)
    CDPR_PLANT_NODE_CAPACITY = 4, ///< a cable wanted a node at capacity
    CDPR_PLANT_MIN_LENGTH = 8,    ///< a winch is held at its minimum length
    CDPR_PLANT_STEP_FAILED = 16   ///< the step failed: the plant is as before the call
};

/// Plant counters since init (outputs; plain fields).
typedef struct {
    unsigned long steps;              ///< successful periods
    unsigned long step_failures;      ///< periods whose advance failed (state kept)
    unsigned long substep_limit_hits; ///< periods with CDPR_WARN_SUBSTEP_LIMIT
    unsigned long min_length_periods; ///< winch-periods held at the minimum length
    unsigned long capacity_periods;   ///< periods whose node events met the capacity
    unsigned long budget_refusals;    ///< advances refused for their trial budget
                                      ///< (CDPR_E_SUBSTEP_LIMIT, state kept; retried or failed)
    cdpr_status_t last_failure;       ///< status of the last failed advance (CDPR_OK: none)
} cdpr_plant_stats_t;

/// The plant (caller-owned; read the fields, change them only through the functions).
typedef struct {
    cdpr_robot_t robot;
    cdpr_real_t y[CDPR_ROBOT_STATE_MAX];
    cdpr_real_t scratch[CDPR_ROBOT_STATE_MAX];
    cdpr_real_t atol[CDPR_ROBOT_STATE_MAX];
    cdpr_real_t work[CDPR_RKF45_WORK_PER_DIM * CDPR_ROBOT_STATE_MAX];
    cdpr_rkf45_t rk;
    cdpr_winch_t winch[CDPR_MAX_CABLES];
    cdpr_node_stats_t nodes;
    cdpr_plant_stats_t stats;
    cdpr_robot_params_t params;       ///< the robot's parameters (a controller model's too)
    cdpr_winch_params_t winch_params; ///< the winches' limits
    cdpr_statics_result_t initial;    ///< IK solution of the initial pose
    cdpr_scenario_integrator_t integ; ///< tolerances (copy)
    double period_s;                  ///< Δt [s]
    int max_trials;                   ///< RKF45 trials per period
    int max_attempts;  ///< advances per period when the budget is refused (CDPR_E_SUBSTEP_LIMIT);
                       ///< default 1 (the real-time work bound); cdpr_sim_run uses 3
    long k;            ///< periods stepped successfully; t = k Δt
    long settle_steps; ///< accepted steps of the initial settling
    cdpr_winch_t winch_before[CDPR_MAX_CABLES]; ///< winches before the period (internal)
    cdpr_real_t payout_before[CDPR_MAX_CABLES]; ///< payout rates before it (internal)
    int commanded;                              ///< command applied, advance pending (internal)
    double settle_wall_time_s;                  ///< wall time of the settling [s]
} cdpr_plant_t;

/// Build and settle the plant of scenario `sc` (checked) with control period `period_s` and
/// `max_trials` trials per period (<= 0: the scenario's integrator.max_trials). Not
/// real-time. Returns 0, or 2 with `err` naming the scenario key (unreachable initial pose,
/// parameters the core rejects, settling failure).
int cdpr_plant_init(cdpr_plant_t *p, const cdpr_scenario_t *sc, double period_s, int max_trials,
                    cdpr_scenario_error_t *err);

/// The first part of cdpr_plant_init only: IK of the initial pose, `params`, `winch_params`
/// and `initial` filled, the robot initialised (not placed, not settled). What a controller in
/// another process needs to build the same model. Returns 0 or 2 with `err` filled.
int cdpr_plant_model(cdpr_plant_t *p, const cdpr_scenario_t *sc, cdpr_scenario_error_t *err);

/// Plant time t_k = k Δt [s].
double cdpr_plant_time(const cdpr_plant_t *p);

/// Measurements at t_k for the controller: cabin motion (quaternion normalised) and total
/// unstretched lengths. This is exactly what cdpr-rt publishes (cabin_state_t,
/// cable_tensions_t.length_m). Real-time safe.
void cdpr_plant_measure(const cdpr_plant_t *p, cdpr_tracker_meas_t *m);

/// First half of cdpr_plant_step: command every winch (`mode`, `value[j]`) and update it
/// from the measured length over the coming period; sets the payout rates the advance will
/// use (so cdpr_robot_outputs at t_k now sees them). Returns the CDPR_PLANT_MIN_LENGTH flag
/// or 0. Real-time safe.
int cdpr_plant_command(cdpr_plant_t *p, cdpr_winch_mode_t mode, const double *value);

/// Second half: advance over the period. `*flags` holds what cdpr_plant_command returned (0
/// without a command: the winches keep their rates); on return it holds every flag of the
/// period. A failure undoes the command too. Returns as cdpr_plant_step. Real-time safe.
cdpr_status_t cdpr_plant_advance(cdpr_plant_t *p, int *flags);

/// One period with every winch in `mode` and values `value[j]` (rates [m/s] or lengths [m];
/// a value the winch refuses (non-finite, length <= 0) keeps that winch's previous command).
/// Returns CDPR_OK or a warning (CDPR_WARN_SUBSTEP_LIMIT, CDPR_WARN_CAPACITY,
/// CDPR_WARN_MIN_LENGTH; every warning that applies is in *flags) with the plant at t_{k+1};
/// or the integrator's error with the plant unchanged and CDPR_PLANT_STEP_FAILED in *flags.
/// Real-time safe.
cdpr_status_t cdpr_plant_step(cdpr_plant_t *p, cdpr_winch_mode_t mode, const double *value,
                              int *flags);

#endif /* CDPR_HOST_PLANT_H */
