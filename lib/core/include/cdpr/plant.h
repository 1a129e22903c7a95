/* SPDX-License-Identifier: BSD-3-Clause */
/// @file plant.h
/// The plant: the lumped-mass robot, its integrator and its winches, stepped one control period
/// at a time from winch commands, with rollback on failure. It is what a winch-controller
/// firmware runs, what the real-time node (cdpr-rt) runs and what the batch runner (cdpr-sim)
/// runs, so all three step the model with the same code, in the same order, on the same numbers.
///
/// Initialisation (cdpr_plant_init; not real-time, bounded work):
///  1. the robot is built from `params.robot`; the sag-aware inverse kinematics of the initial
///     pose (cdpr_statics_ik_dist: six cables, or more with the robot's tension distribution,
///     robot.h) gives the unstretched lengths that hold the cabin there at rest, and the
///     robot is built again with them (cdpr_plant_init_model stops here);
///  2. the nodes are placed on the elastic catenaries (cdpr_statics_place_catenary) and, with
///     CDPR_PLANT_START_SETTLED, relaxed to the discrete model's own equilibrium
///     (cdpr_settle_robot), so the run starts at rest;
///  3. the winches start at rest in rate mode; the integrator is set up with the run's
///     tolerances (per-component absolute tolerances, refreshed after node events).
///
/// One period (cdpr_plant_step, or cdpr_plant_command + cdpr_plant_advance), t_k = k Δt to
/// t_{k+1}: command every winch -> cdpr_winch_update from the measured length (speed and
/// acceleration limits, minimum length) -> the integrator over exactly Δt with at most
/// `max_trials` trials, repeated up to `max_attempts` times while it refuses the budget
/// (CDPR_E_SUBSTEP_LIMIT) -> cdpr_robot_normalize -> cdpr_winch_node_events (the integrator is
/// resized and the tolerances refreshed when the layout changed). A failed period leaves the
/// plant exactly as it was before the call -- state, time, winches, payout rates -- except for
/// the failure counters, and says so: the caller keeps the last good state and tries again.
///
/// Integrators: `params.integrator` selects the scheme behind the one advance call:
/// CDPR_PLANT_RKF45 (cdpr_rkf45_advance, the default), CDPR_PLANT_ROS34PW2 (cdpr_ros_advance
/// with the robot's W-matrix of robot_w.h) or CDPR_PLANT_ROS34PW2_FIXED (cdpr_ros_fixed: the
/// same method in exactly `substeps` equal steps, the same work in every period). Adding a
/// scheme adds a value here and a case in plant.c; the contract of the period (exactly Δt,
/// bounded work, transactional) is the plant's, whatever the scheme.
///
/// Fixed-cost stepping (CDPR_PLANT_ROS34PW2_FIXED; docs/model.md "Fixed-cost stepping"): the
/// number of substeps n is derived at init from the stiffest axial mode the discretisation can
/// have during the run, so that h ω_max <= CDPR_PLANT_FIXED_H_OMEGA (cdpr_plant_fixed_substeps);
/// a user may ask for more (params.substeps), never fewer. Every period then costs exactly n
/// factorisations, 4 n solves and 4 n RHS evaluations: that is the worst case, and the mean.
///
/// Memory: caller-owned (sizeof(cdpr_plant_t) is in docs/api.md; about 300 kB at the default
/// capacities in double: declare it static). The plant's integrator points into the plant's own
/// arrays, so a plant must not be copied by assignment or memcpy (the copy would integrate
/// the original's arrays): initialise a second plant instead. No function allocates, keeps a
/// pointer it was not given, or performs I/O. Work of one period: at most max_attempts x max_trials
/// integrator trials (RKF45: 6 robot RHS evaluations each, O(total segments) per evaluation;
/// ROS34PW2: 4 RHS evaluations, 1 factorisation and 4 solves of W, each O(total segments)) plus
/// O(state dimension) for the rollback copy and the node events; fixed mode: exactly `substeps`
/// ROS34PW2 steps (no attempts, no trial bound), fewer only when the period fails.
#ifndef CDPR_PLANT_H
#define CDPR_PLANT_H

#include "cdpr/cabin.h"
#include "cdpr/config.h"
#include "cdpr/rkf45.h"
#include "cdpr/robot.h"
#include "cdpr/robot_w.h"
#include "cdpr/ros34pw2.h"
#include "cdpr/settle.h"
#include "cdpr/statics.h"
#include "cdpr/status.h"
#include "cdpr/winch.h"

/// Bits of the flags of a period (equal to cabin_state_t.FLAG_* of the LCM types).
#define CDPR_PLANT_SUBSTEP_LIMIT 2  ///< the advance met its trial bound (tolerance not met)
#define CDPR_PLANT_NODE_CAPACITY 4  ///< a cable wanted a node at capacity
#define CDPR_PLANT_MIN_LENGTH    8  ///< a winch is held at its minimum length
#define CDPR_PLANT_STEP_FAILED   16 ///< the period failed: the plant is as before the call

/// Integration scheme of the plant.
typedef enum {
    CDPR_PLANT_RKF45 = 0,         ///< adaptive Runge-Kutta-Fehlberg 4(5) (rkf45.h), the reference
    CDPR_PLANT_ROS34PW2 = 1,      ///< L-stable Rosenbrock-W 3(2) (ros34pw2.h) with robot_w.h
    CDPR_PLANT_ROS34PW2_FIXED = 2 ///< the same in `substeps` equal steps per period (fixed cost)
} cdpr_plant_integrator_t;

/// Largest step size times ω_max (cdpr_plant_fixed_substeps) the fixed mode allows. Measured on
/// the paper's circle (docs/model.md "Fixed-cost stepping"): runs held at h ω_max = 5.4 (6 x 16
/// segments at 1 kHz with one substep, 6 x 32 with two) and blew up at the first slack event at
/// 10.9 (6 x 32 at 1 kHz and 6 x 16 at 500 Hz, one substep each); 4 keeps a margin below the
/// largest value that held.
#define CDPR_PLANT_FIXED_H_OMEGA 4.0

/// Most substeps per period of the fixed mode (a model that needs more is refused at init).
#define CDPR_PLANT_MAX_SUBSTEPS 64

/// How the plant starts.
typedef enum {
    /// IK lengths, nodes on the catenaries, then settled to the lumped model's own static
    /// equilibrium (the run starts exactly at rest). Default in double builds.
    CDPR_PLANT_START_SETTLED = 0,
    /// IK lengths, nodes on the catenaries, no settling: starts within the discretisation
    /// error of rest (O(1/N^2), docs/validation.md). Default in float builds, where stiff ropes
    /// cannot settle to a meaningful tolerance (settle.h).
    CDPR_PLANT_START_CATENARY = 1
} cdpr_plant_start_t;

/// Per-component absolute tolerances of the run's integrator (all > 0).
typedef struct {
    cdpr_real_t position_m;       ///< positions and lengths [m]
    cdpr_real_t velocity_m_per_s; ///< velocities [m/s]
    cdpr_real_t quaternion;       ///< quaternion components [-]
    cdpr_real_t rate_rad_per_s;   ///< body rates [rad/s]
} cdpr_plant_atol_t;

/// Plant parameters (inputs), validated by cdpr_plant_init. Defaults from
/// cdpr_plant_params_default.
typedef struct {
    /// Robot: geometry, cables, cabin, gravity (mode must be CDPR_CABIN_DYNAMIC). The cables'
    /// length_m are only a starting value for validation: the IK replaces them.
    cdpr_robot_params_t robot;
    cdpr_winch_params_t winch[CDPR_MAX_CABLES]; ///< limits of winch j (j < robot.n_cables)
    cdpr_cabin_motion_t initial;                ///< initial pose (p_m, q; velocities must be zero)
    cdpr_vec3_t wind_m_per_s;           ///< uniform wind during the run [m/s] (finite); default 0
    cdpr_statics_opts_t ik;             ///< settings of the initial IK
    cdpr_plant_start_t start;           ///< settled or on the catenaries
    cdpr_settle_t settle;               ///< settling bounds (start = SETTLED; outputs unused)
    cdpr_rkf45_params_t settle_rkf45;   ///< settling integrator (default rtol 1e-9, atol 1e-10)
    cdpr_plant_integrator_t integrator; ///< scheme of the run; default CDPR_PLANT_RKF45
    cdpr_rkf45_params_t rkf45;          ///< RKF45 settings of the run (atol_vec: set by the plant)
    cdpr_ros_params_t ros;              ///< ROS34PW2 settings of the run (atol_vec: by the plant)
    cdpr_plant_atol_t atol;             ///< per-component absolute tolerances of the run
    cdpr_real_t period_s;               ///< control period Δt [s], in (0, 10]; default 0.01
    int max_trials;                     ///< integrator trials per attempt, >= 1; default 50
    int max_attempts;                   ///< attempts per period while the budget is refused, in
                                        ///< [1, CDPR_PLANT_MAX_ATTEMPTS]; default 1
    /// Substeps per period of CDPR_PLANT_ROS34PW2_FIXED: 0 (the default) takes the derived n of
    /// cdpr_plant_fixed_substeps; otherwise at least that n and at most
    /// CDPR_PLANT_MAX_SUBSTEPS. Unused by the other schemes.
    int substeps;
} cdpr_plant_params_t;

/// Workspace reals per state component: the larger of the two integrators' needs (both 9).
#define CDPR_PLANT_WORK_PER_DIM CDPR_RKF45_WORK_PER_DIM
#if CDPR_ROS_WORK_PER_DIM > CDPR_PLANT_WORK_PER_DIM
#error "CDPR_PLANT_WORK_PER_DIM must cover CDPR_ROS_WORK_PER_DIM"
#endif

/// Largest max_attempts (the work bound of a period is max_attempts x max_trials trials).
#define CDPR_PLANT_MAX_ATTEMPTS 16

/// Plant counters since init (outputs; plain fields).
typedef struct {
    unsigned long steps;              ///< successful periods
    unsigned long step_failures;      ///< periods that failed (state kept)
    unsigned long substep_limit_hits; ///< periods with CDPR_WARN_SUBSTEP_LIMIT
    unsigned long min_length_periods; ///< winch-periods held at the minimum length
    unsigned long capacity_periods;   ///< periods whose node events met the capacity
    unsigned long budget_refusals;    ///< attempts refused for their trial budget
                                      ///< (CDPR_E_SUBSTEP_LIMIT; retried or failed)
    cdpr_status_t last_failure;       ///< status of the last failed period (CDPR_OK: none)
    /// Work of the last period (every attempt, failed or not) and the largest since init:
    /// robot RHS evaluations, factorisations and solves of W (0 with RKF45).
    unsigned long last_rhs_evals;
    unsigned long max_rhs_evals;       ///< largest last_rhs_evals since init
    unsigned long last_factorisations; ///< factorisations of W in the last period
    unsigned long max_factorisations;  ///< largest last_factorisations since init
    unsigned long last_solves;         ///< solves with W in the last period
    unsigned long max_solves;          ///< largest last_solves since init
    /// Fixed mode: the largest error norm of the last period's substeps (the adaptive scheme's
    /// norm: > 1 is a step it would have rejected), its largest value since init, and the
    /// periods in which it exceeded 1 (a health figure: the fixed mode never refuses a finite
    /// step). 0 with the other schemes.
    cdpr_real_t last_err_norm;
    cdpr_real_t max_err_norm;            ///< largest last_err_norm since init
    unsigned long err_above_one_periods; ///< periods with last_err_norm > 1
} cdpr_plant_stats_t;

/// Measurements at t_k for a controller: what cdpr-rt publishes for state k.
typedef struct {
    cdpr_real_t t_s;                       ///< plant time t_k [s]
    cdpr_cabin_motion_t cabin;             ///< cabin motion (quaternion normalised)
    cdpr_real_t length_m[CDPR_MAX_CABLES]; ///< total unstretched lengths [m] (0 past n_cables)
    cdpr_real_t tension_winch_N[CDPR_MAX_CABLES]; ///< winch-end tensions T_{n-1} with the
                                                  ///< payout rates in force (a load cell at
                                                  ///< the winch; cdpr_robot_outputs) [N]
} cdpr_plant_meas_t;

/// The plant (caller-owned; read the fields, change them only through the functions).
typedef struct {
    cdpr_robot_t robot;                        ///< the robot (inputs in robot.in may be changed
                                               ///< between periods: wind, external loads)
    cdpr_real_t y[CDPR_ROBOT_STATE_MAX];       ///< state at t_k (layout: robot.h)
    cdpr_winch_t winch[CDPR_MAX_CABLES];       ///< winches
    cdpr_rkf45_t rk;                           ///< RKF45 of the run (integrator = RKF45)
    cdpr_ros_t ros;                            ///< ROS34PW2 of the run (integrator = ROS34PW2)
    cdpr_robot_w_t w;                          ///< its W-matrix (integrator = ROS34PW2)
    cdpr_node_stats_t nodes;                   ///< node insertions/removals per cable
    cdpr_plant_stats_t stats;                  ///< counters
    cdpr_robot_params_t params;                ///< robot parameters with the IK lengths
    cdpr_statics_result_t initial;             ///< IK solution of the initial pose
    cdpr_settle_t settle;                      ///< settling report (steps, residual)
    cdpr_plant_params_t pp;                    ///< validated copy of the parameters
    long k;                                    ///< periods stepped; t_k = k Δt
    int substeps;                              ///< substeps per period in force (fixed mode;
                                               ///< 0 with the other schemes)
    int ready;                                 ///< 1 after a successful cdpr_plant_init
    int commanded;                             ///< command applied, advance pending (internal)
    cdpr_real_t atol[CDPR_ROBOT_STATE_MAX];    ///< per-component tolerances (internal)
    cdpr_real_t scratch[CDPR_ROBOT_STATE_MAX]; ///< settling scratch (internal)
    cdpr_real_t work[CDPR_PLANT_WORK_PER_DIM * CDPR_ROBOT_STATE_MAX]; ///< (internal)
    cdpr_winch_t winch_before[CDPR_MAX_CABLES]; ///< winches before the period (internal)
    cdpr_real_t payout_before[CDPR_MAX_CABLES]; ///< payout rates before it (internal)
} cdpr_plant_t;

/// Defaults: the robot of cdpr_robot_params_default (one cable: set six for the IK), default
/// winch limits, cabin at the origin, level, no wind, IK defaults, settled start in double
/// (catenary start in float), settling defaults with rtol 1e-9 / atol 1e-10, RKF45 with its
/// defaults (the run's integrator), ROS34PW2 with its defaults but jac_reuse_max 4, absolute
/// tolerances 1e-6 m, 1e-5 m/s, 1e-8, 1e-6 rad/s, Δt = 0.01 s, 50 trials, 1 attempt. O(cables);
/// cannot fail.
void cdpr_plant_params_default(cdpr_plant_params_t *pp);

/// The integrator's name as the scenario files and the command lines spell it: "rkf45",
/// "ros34pw2", "ros34pw2-fixed"; NULL for a value outside the enumeration. O(1).
const char *cdpr_plant_integrator_name(cdpr_plant_integrator_t integrator);

/// The integrator's work since cdpr_plant_init, whatever the scheme (outputs): what the
/// integrators' own counters (cdpr_step_stats_t, cdpr_ros_lin_stats_t) hold, so a caller need not
/// pick them by the scheme. RKF45 has no factorisations or solves (0).
typedef struct {
    cdpr_plant_integrator_t integrator; ///< the scheme (cdpr_plant_integrator_name)
    unsigned long steps_accepted;       ///< accepted steps (the fixed mode: every substep)
    unsigned long steps_rejected;       ///< trials rejected by the error test
    unsigned long nonfinite_rejected;   ///< trials rejected because they produced NaN/Inf
    unsigned long rhs_evals;            ///< evaluations of the robot's RHS
    unsigned long factorisations;       ///< W factorisations (ROS34PW2)
    unsigned long solves;               ///< W solves (ROS34PW2)
} cdpr_plant_work_t;

/// Validate the plant's own fields of `pp` (not the robot, winch, IK and integrator settings,
/// which cdpr_plant_init validates with their modules' rules). O(1); no allocation.
/// Errors (diag names the field): CDPR_E_INVALID_ARG (NULL, unknown integrator or start),
/// CDPR_E_NOT_FINITE (period_s, wind_m_per_s, initial), CDPR_E_OUT_OF_RANGE (period_s outside
/// (0, 10], max_trials < 1, max_attempts outside [1, CDPR_PLANT_MAX_ATTEMPTS], substeps outside
/// [0, CDPR_PLANT_MAX_SUBSTEPS] (index CDPR_PLANT_MAX_SUBSTEPS), a non-zero
/// initial velocity or rate, robot.mode not dynamic).
cdpr_status_t cdpr_plant_params_validate(const cdpr_plant_params_t *pp, cdpr_diag_t *diag);

/// Step 1 of the initialisation only: validate, build the robot, solve the IK of the initial
/// pose and build the robot again with the IK lengths (`params`, `initial` and `robot` filled;
/// not placed, not settled, not steppable). What a controller in another process needs to
/// build the same model. Work: the IK (bounded iterations, O(cables^3) each). No allocation.
/// Errors: those of cdpr_plant_params_validate; cdpr_robot_init's (diag names the robot's
/// field, index = cable); the IK's (CDPR_E_INFEASIBLE, CDPR_E_NO_CONVERGENCE, ... with
/// diag.field "initial"; CDPR_E_INVALID_ARG there for more than six cables without the
/// robot's has_tension_dist, or fewer than six). On error the plant is not ready (steps are
/// refused).
cdpr_status_t cdpr_plant_init_model(cdpr_plant_t *p, const cdpr_plant_params_t *pp,
                                    cdpr_diag_t *diag);

/// Substeps per period the fixed mode needs for the robot `r` (built, e.g. by
/// cdpr_plant_init_model), its winches `w` and the period: the smallest n with
/// (period_s / n) ω_max <= CDPR_PLANT_FIXED_H_OMEGA, where ω_max bounds the axial frequencies the
/// run can reach. For a node between segments of unstretched lengths a and b, Gershgorin's
/// bound on the chain gives ω^2 <= 4 EA / (ρ a b); the winch keeps the pulley-side segment in
/// [Δ/2, 2Δ] at the end of every period (winch.h) and hauls in at most u_max per second within
/// it, so b >= Δ/2 - u_max period_s next to a segment of Δ: ω_max = 2 sqrt(EA/ρ) / sqrt(Δ b_min),
/// the largest over the cables with more than one segment. Writes n (and ω_max [rad/s], may be
/// NULL). O(cables); no allocation. Errors (*n and *omega_max not written): CDPR_E_INVALID_ARG
/// (NULL r, w or n; period_s not > 0); CDPR_E_OUT_OF_RANGE when a period can haul a whole
/// half-segment in (b_min <= 0: no substep count holds) or n would exceed
/// CDPR_PLANT_MAX_SUBSTEPS.
cdpr_status_t cdpr_plant_fixed_substeps(const cdpr_robot_t *r, const cdpr_winch_params_t *w,
                                        cdpr_real_t period_s, int *n, cdpr_real_t *omega_max);

/// Build the plant (steps 1-3 above). Not real-time: the settling is bounded by
/// pp->settle.max_steps integrator steps. No allocation. On success the plant is at t_0 = 0,
/// k = 0, ready. Errors (the plant is then not ready): those of cdpr_plant_init_model;
/// cdpr_statics_place_catenary's (diag.field "initial"); settling: CDPR_E_NO_CONVERGENCE or
/// an integrator error (diag.field "settle"; p->settle holds steps and residual);
/// cdpr_winch_init's (diag names the winch field); cdpr_rkf45_init's for the settling
/// ("settle_rkf45") or the run ("rkf45"); cdpr_ros_init's for the run ("ros"); fixed mode:
/// cdpr_plant_fixed_substeps's (diag.field "substeps", index -1: no count holds), and
/// CDPR_E_OUT_OF_RANGE for a params.substeps below the derived n (diag "substeps", index = the
/// derived n) -- checked before the settling, so a refusal costs no settle.
cdpr_status_t cdpr_plant_init(cdpr_plant_t *p, const cdpr_plant_params_t *pp, cdpr_diag_t *diag);

/// The integrator's work since init into `w` (cdpr_plant_work_t). O(1); cannot fail.
void cdpr_plant_work(const cdpr_plant_t *p, cdpr_plant_work_t *w);

/// Plant time t_k = k Δt [s]. O(1); cannot fail.
cdpr_real_t cdpr_plant_time(const cdpr_plant_t *p);

/// Measurements at t_k (cabin motion with the quaternion normalised, total unstretched
/// lengths, winch-end tensions as cdpr_plant_outputs gives them). O(total segments); no
/// allocation; cannot fail. Real-time safe.
void cdpr_plant_measure(const cdpr_plant_t *p, cdpr_plant_meas_t *m);

/// cdpr_plant_measure and cdpr_plant_outputs from one evaluation of the end forces (what a
/// loop that needs both calls once per period). Same cost as cdpr_plant_measure; no
/// allocation; cannot fail. Real-time safe.
void cdpr_plant_measure_out(const cdpr_plant_t *p, cdpr_plant_meas_t *m, cdpr_robot_out_t *out);

/// Cable forces on the cabin and end tensions at t_k with the payout rates in force
/// (cdpr_robot_outputs). O(cables); no allocation; cannot fail. Real-time safe.
void cdpr_plant_outputs(const cdpr_plant_t *p, cdpr_robot_out_t *out);

/// First half of a period: command every winch (`mode`, `value[j]` for j < n_cables; a value
/// the winch refuses -- non-finite, a length <= 0 -- keeps that winch's previous command) and
/// update it from the measured length over the coming period; sets the payout rates the
/// advance will use (so cdpr_plant_outputs now shows them). Returns the CDPR_PLANT_MIN_LENGTH
/// flag or 0 (also 0, doing nothing, for a plant that is not ready or NULL arguments).
/// O(total segments); no allocation. Real-time safe.
int cdpr_plant_command(cdpr_plant_t *p, cdpr_winch_mode_t mode, const cdpr_real_t *value);

/// Second half: advance over the period. `*flags` holds what cdpr_plant_command returned (0
/// without a command: the winches keep their rates); on return it holds every flag of the
/// period. Returns as cdpr_plant_step; a failure undoes the command too. Real-time safe.
cdpr_status_t cdpr_plant_advance(cdpr_plant_t *p, int *flags);

/// One period with every winch in `mode` and values `value[j]` (rates [m/s] or lengths [m]).
/// Returns CDPR_OK, or a warning (CDPR_WARN_SUBSTEP_LIMIT, CDPR_WARN_CAPACITY,
/// CDPR_WARN_MIN_LENGTH; every warning that applies is in *flags) with the plant at t_{k+1};
/// or an error with the plant as before the call, CDPR_PLANT_STEP_FAILED in *flags and the
/// failure counted (stats.step_failures, stats.last_failure): CDPR_E_INVALID_ARG (plant not
/// ready, NULL), or the integrator's CDPR_E_SUBSTEP_LIMIT (budget refused on every attempt),
/// CDPR_E_STATE_NOT_FINITE, CDPR_E_STEP_TOO_SMALL, CDPR_E_RHS, CDPR_E_SINGULAR (ROS34PW2).
/// Work: see the file comment.
/// No allocation. Real-time safe.
cdpr_status_t cdpr_plant_step(cdpr_plant_t *p, cdpr_winch_mode_t mode, const cdpr_real_t *value,
                              int *flags);

#endif /* CDPR_PLANT_H */
