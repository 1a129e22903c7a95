/* SPDX-License-Identifier: BSD-3-Clause */
/// @file tracker.h
/// Tracking controller: desired cabin trajectory -> winch payout-rate commands.
///
/// Once per control period Δt_c, from the measured cabin motion and unstretched lengths L_j:
///  1. feed-forward: sag-aware inverse kinematics of the desired pose at t + Δt_c gives
///     L_ff(t + Δt_c); the feed-forward rate is u_ff = (L_ff(t + Δt_c) - L_ff(t)) / Δt_c,
///     with L_ff(t) kept from the previous period (one IK per period). The IK
///     (cdpr_statics_ik_dist: six cables, or more with the robot's tension distribution,
///     which resolves the redundancy) balances the weight plus `inertial_ff` times the d'Alembert
///     load of the desired motion (cdpr_tracker_inertial_wrench): the cable forces that make
///     a rigid cabin on quasi-static catenary cables follow the desired acceleration;
///     inertial_ff = 0 gives the static IK. If the IK fails (pose and load outside the
///     wrench-feasible set, or no convergence), or its solution has a cable hanging in a loop
///     (unstretched length above CDPR_TRACKER_MAX_LENGTH_PER_CHORD times the chord: statics.h
///     explains why the catenary equations have such solutions), the last good L_ff is held
///     (u_ff = 0) and `ik_failures` counts it.
///  1c. the cabin's weight estimated from the winch tensions (optional, weight_estimate_s =
///     τ_W > 0): the measured winch-end tensions T_j against the feed-forward's T_ff,j(t) give
///     the vertical force the cables hold beyond what the model expects, through the straight
///     chords at the measured pose (u_j as in step 2; internal forces cancel in the sum):
///       r = Σ_j (T_j - T_ff,j) u_j,z / g,   r_f = low-pass(r),
///       ΔM ← ΔM + (Δt_c / τ_W) r_f,   |ΔM| <= CDPR_TRACKER_WEIGHT_LIMIT M
///     (M the model's cabin mass; a clamped period counts in `weight_saturations`; the low-pass
///     two first-order stages of time constant τ_W / CDPR_TRACKER_WEIGHT_FILTER_RATIO, primed
///     by the first sample: without it the estimate, through L_ff, drives the 8 Hz axial
///     cabin-cable modes of the 50 m model, which the winch tensions see first). The
///     feed-forward load of step 1 then carries the estimate: the weight ΔM g at the CoM and
///     the d'Alembert load scaled by 1 + ΔM/M (a heavier cabin of the model's shape), so T_ff
///     follows the measured tensions and the residual, hence ΔM, settles where the model's
///     weight matches the cabin's: at rest the cables carry the true weight whatever their
///     lengths, so ΔM converges as e^(-t/τ_W) to the mass error, without the pose loop. ΔM
///     starts at 0 at every cdpr_tracker_init. Cost: O(cables).
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
///  2d. integral action (optional, integral_per_s = k_I > 0): the unfiltered pose error is
///     summed over the periods, I ← I + e Δt_c (e = (e_p, e_θ) of this period), each
///     component of k_I I clamped to ±integral_limit_m (by clamping I; a period with any
///     clamp counts in `integral_saturations`), and mapped like kp's term:
///       δL_j += -k_I (u_j·I_p + ((R b_j) x u_j)·I_θ)
///     It removes a steady pose error that the feed-forward leaves (a model error: the cabin
///     heavier or the ropes stiffer than the controller's model believes, the discrete
///     chain's offset from the catenary IK): on a quasi-static robot the error decays as
///     e^(-k_I t) (the length loop's k_L much faster than k_I). I starts at 0 at every
///     cdpr_tracker_init (a plant restart over LCM starts it again).
///  3. wrench-space damping (optional, damping_N_s_per_m / damping_rot_N_m_s > 0): the
///     cables are asked for an extra force c ė_p and torque c_r ė_θ (the filtered rates
///     above, world axes; about the CoM) on top of the feed-forward load: a second
///     cdpr_statics_ik_wrench at the desired pose of t with the load of step 1 minus that
///     wrench gives L_w, and δL_j += L_w,j - L_ff,j(t). Unlike kd_s, which asks every cable
///     for the length change that would move a rigid cabin, this asks the sag-aware statics
///     for the lengths that produce a damping force: small corrections in the directions the
///     cables hold stiffly (bounce, axial modes), larger ones where sag makes them soft
///     (sway). If that IK fails, the period gets no damping correction (`fb_failures`).
///     On the 50 m model it damps the sway well over seconds, but like kd_s it makes lightly
///     damped cabin-cable modes (1-6 Hz) grow over 30-240 s of holding; the paper scenarios
///     do not use it (docs/validation.md §8).
///  4. payout-rate command u_j = u_ff,j + k_L (L_ff,j(t) + δL_j - L_j). The plant's winch
///     (cdpr_winch_update) applies its speed and acceleration limits.
///  4b. winch tension feedback (optional, tension_gain_m_per_s_per_N = k_T > 0): each winch
///     pays out in proportion to its measured winch-end tension above the feed-forward's,
///       u_j += k_T e_T,j,   e_T,j = low-pass(T_j - T_ff,j(t)),
///     T_ff,j(t) the winch-end tension of the feed-forward IK's catenary at t (held with
///     L_ff when the IK fails), the low-pass one first-order stage of time constant
///     tension_filter_s (exact for a signal held over the period; the first sample primes
///     it). Rate in, force out at the same winch: a collocated admittance (a damper 1/k_T in
///     series with each cable, against the length loop's spring k_L/k_T), which damps the
///     cabin-cable modes without the pose loop's phase problem (docs/validation.md §8).
///     With tension_washout_s = τ_wo > 0 the loop sees only the error's changes: a first-order
///     washout (high-pass) of the filtered error,
///       w_j ← w_j + a_w (e_T,j - w_j),   u_j += k_T (e_T,j - w_j),   a_w = 1 - e^(-Δt_c/τ_wo)
///     (w primed with e_T at the first sample), so a steady tension error (a cabin heavier
///     than the model, a wind load, the discrete chain's offset from the catenary) pays out
///     nothing in steady state, where without it it holds the length k_T e_T / k_L off L_ff
///     and moves the cabin: the damping stays, the static offset goes. A step E in e_T gives
///     k_T E e^(-(k - k_0 + 1) Δt_c/τ_wo) at period k >= k_0.
///  4c. pre-compensation (optional, gains.correction, cdpr_tracker_correction_t): a length
///     correction computed offline for this trajectory joins the feed-forward,
///       u_j += (c_j(t + Δt_c) - c_j(t)) / Δt_c + k_L c_j(t),
///     the rate as the feed-forward's own (a forward difference over the period) and the
///     length as a correction of L_ff: the winch follows L_ff + c. cmd->corr_m reports c_j(t).
///     Nothing else sees it (the tension feedback's T_ff, the weight estimate and the pose
///     errors keep to the feed-forward's model: the offline iteration ran against that closed
///     loop). Cost: O(cables), eight coefficients per cable.
///  5. (before step 1) the reference: the desired trajectory, or with transfer_s = T > 0 the
///     planned transfer (trajectory.h, cdpr_transfer_t) from the first measurement (the pose
///     at the first step: in process and over LCM, where a plant restart re-inits the
///     tracker) onto the trajectory over T; every step above (feed-forward with its d'Alembert
///     load, errors, damping) uses the reference. With T = 0 the tracker is bit-identical to
///     one without the transfer. transfer_from_rest = 1 also starts the trajectory's clock
///     at rest and takes over the measured velocity (cdpr_transfer_t "From rest").
///  6. wind (wind_ff > 0): the feed-forward load also holds wind_ff times the steady wind
///     load of the cables at the reference pose (cdpr_tracker_wind_wrench).
///  7. tension awareness: with six cables the six wrench components make the feed-forward's
///     tension distribution unique (with more, the robot's distribution chooses it). When the
///     feed-forward IK of a six-cable robot fails (the load needs a pushing
///     cable, or finds only a cable hanging in a loop) the load is distributed on the straight
///     chords (a 6x6 solve); each cable whose tension there is <= 0 is a "slack demand" of the
///     period: counted per cable (slack_demand_periods), the first one kept (cable, time,
///     tension), reported in cmd->slack_demand / demand_tension_N.
///  8. learning over laps (optional, learning_gain = γ > 0; issue 14 item 3): iterative
///     learning control of a length correction per cable for periodic trajectories (circle,
///     cyclic: cdpr_traj_lap_s > 0; any other trajectory gets no learning: the keys are
///     accepted and do nothing). The lap's phase φ (cdpr_traj_lap_phase: the circle's path
///     position, the cyclic trajectory's time in its cycle) indexes a learned correction
///     c_j(φ), added to δL_j in step 4:
///       δL_j += c_j(φ(t))   (linear interpolation between knots)
///     stored at M = min(CDPR_TRACKER_LEARN_KNOTS, round(T_lap / Δt_c)) knots per lap,
///     spacing Δ_φ = T_lap / M (T_lap = cdpr_traj_lap_s). Over each lap the length error
///       e_L,j = -(u_j·e_p + ((R b_j) x u_j)·e_θ)
///     (step 2 with kp = 1, kd = 0 on the unfiltered error) is averaged onto the knots
///     (each sample split between its two knots with the interpolation's weights). At the
///     first step of the next lap, if the whole lap was recorded, the update
///       c ← sat( Q[ c + γ e_L(φ + lead) ] )
///     runs once: the lap's error shifted by lead = learning_lead_s (a phase advance; linear
///     interpolation between knots), Q a zero-phase low-pass over the stored lap (one first-
///     order stage run forward and then backward around the lap, each from its exact circular
///     steady state, pole a = exp(-2 π f_c Δ_φ), f_c = learning_cutoff_hz; 0 = no filter):
///       Q(e^{jω Δ_φ}) = (1 - a)^2 / |1 - a e^{-jω Δ_φ}|^2   (real, 1 at ω = 0, ~1/2 at f_c),
///     and sat the clamp to ±learning_limit_m, each clamped knot value counted in
///     `learning_saturations`. The first lap recorded is the first that starts at or after
///     t_learn = max(t_first + transfer_s, ramp_s) + learning_settle_laps T_lap (t_first: the
///     first step's time; ramp_s the circle's speed ramp, after which the circle is periodic
///     in time). Outside the laps (a cyclic trajectory after its last cycle) c is not applied
///     and nothing is recorded. Reset: the learned state lives in the tracker, so it starts
///     from zero at every cdpr_tracker_init (a new trajectory, a plant restart over LCM).
///     The lap-to-lap map of the correction at a lap harmonic ω is
///       c_{k+1} = Q(ω) (I - γ e^{jω lead} G(e^{jω Δt_c})) c_k + (terms of the disturbance),
///     with G the response from the length correction to the drop of e_L (linearised loop:
///     scripts/feedback_design.py --learning, docs/validation.md §8 "Learning over laps"):
///     it converges where the spectral radius of that matrix is below 1 in Q's band.
///     Cost: O(cables) per period; at each lap's end O(cables M) (a few 10 µs for M = 512).
///
/// The controller keeps its own robot model (for the IK), the `model_params` it is given (the
/// host apps give it the scenario's robot scaled by controller.model: cdpr_host_controller_params;
/// exactly the plant's by default), so it needs nothing from the plant but measurements: the
/// real-time loop moves it into a separate process unchanged. Memory: caller-owned object, no
/// allocation. Work per step: one cdpr_statics_ik_dist (bounded iterations), a second one when
/// wrench-space damping is on, plus O(cables).
#ifndef CDPR_CONTROL_TRACKER_H
#define CDPR_CONTROL_TRACKER_H

#include "cdpr/plant.h"
#include "cdpr/robot.h"
#include "cdpr/statics.h"
#include "cdpr/status.h"
#include "cdpr/control/trajectory.h"

/// Largest unstretched length, in chords, the tracker commands: the IK's own limit
/// (CDPR_STATICS_MAX_LENGTH_PER_CHORD, beyond which it reports a loop; working cables stay
/// within a few per cent of their chords). 1.5 chords is a sag of about 40 % of the chord.
#define CDPR_TRACKER_MAX_LENGTH_PER_CHORD CDPR_STATICS_MAX_LENGTH_PER_CHORD

/// Bound of the weight estimate (step 1c): |ΔM| <= this fraction of the model's cabin mass.
#define CDPR_TRACKER_WEIGHT_LIMIT CDPR_R(0.5)

/// The weight estimate's residual filter (step 1c): time constant τ_W / this.
#define CDPR_TRACKER_WEIGHT_FILTER_RATIO CDPR_R(10.0)

/// Capacity of the learned correction (step 8): knots per lap and cable. A lap longer than
/// this many control periods is stored decimated (6.28 s at 100 Hz: 512 knots 12.3 ms apart;
/// at 1 kHz the same). The learning arrays (correction, lap accumulator, weights) take
/// (2 CDPR_MAX_CABLES + 1) · 512 · 8 = 53 248 bytes of cdpr_tracker_t.
#define CDPR_TRACKER_LEARN_KNOTS 512

/// A length pre-compensation for a known trajectory (step 4c; issue 22 item 1): per cable a
/// smooth correction c_j(t), a uniform cubic B-spline with knot spacing h from t_s,
///   c_j(t) = Σ_i a_j,i β((t - t_s) / h - i),
/// β the cubic B-spline on [0, 4] (C², β(2) = 2/3), so c_j = 0 before t_s and after
/// t_s + (n_coef + 3) h. Computed offline against a model of the plant (cdpr-precomp,
/// cdpr_design_precompensate: the lengths that make the modelled closed loop follow the
/// trajectory) for one trajectory, robot, controller and period; the host loads it from a
/// file tied to those by their hashes (cdpr/host/correction.h). The coefficients are the
/// caller's (a table in flash on a target): they must outlive every tracker given them.
typedef struct {
    int n_cables;              ///< cables (= the tracker's model's)
    int n_coef;                ///< coefficients per cable (>= 1)
    cdpr_real_t start_s;       ///< t_s: where the first basis function starts [s] (finite)
    cdpr_real_t spacing_s;     ///< h [s] (> 0)
    cdpr_real_t period_s;      ///< the control period it was computed for [s] (= the tracker's)
    const cdpr_real_t *coef_m; ///< a_j,i at coef_m[j n_coef + i] [m] (finite)
} cdpr_tracker_correction_t;

/// c_j(t) [m] of correction `c` (cable j in range; O(1): four coefficients).
cdpr_real_t cdpr_tracker_correction_at(const cdpr_tracker_correction_t *c, int j, cdpr_real_t t_s);

/// Gains (inputs).
typedef struct {
    cdpr_real_t kp;             ///< pose-error gain [-] (>= 0)
    cdpr_real_t kd_s;           ///< pose-error-rate gain [s] (>= 0)
    cdpr_real_t k_length_per_s; ///< length-loop gain k_L [1/s] (>= 0)
    cdpr_real_t filter_s;       ///< time constant of the error low-pass [s] (>= 0; 0 = none)
    cdpr_real_t inertial_ff;    ///< fraction of the d'Alembert load in the feed-forward IK [-]
                             ///< (>= 0; 1 = full inverse dynamics of the rigid cabin, 0 = static)
    cdpr_real_t damping_N_s_per_m; ///< wrench-space damping c of the velocity error [N s/m] (>= 0)
    cdpr_real_t damping_rot_N_m_s; ///< wrench-space damping c_r of the rate error [N m s] (>= 0)
    cdpr_real_t transfer_s;        ///< planned transfer T from the first measurement onto the
                                   ///< trajectory [s] (>= 0; 0 = none: the reference is the
                                   ///< trajectory from the start; cdpr_transfer_t)
    cdpr_real_t wind_ff;           ///< fraction of the cables' steady wind load in the feed-forward
                                   ///< IK [-] (>= 0; 0 = none; cdpr_tracker_wind_wrench)
    cdpr_vec3_t wind_m_per_s;      ///< the steady wind the feed-forward assumes [m/s] (finite; the
                                   ///< plant's robot.wind_m_per_s: an ideal anemometer)
    cdpr_real_t tension_gain_m_per_s_per_N; ///< winch tension feedback k_T [m/s/N] (>= 0; 0 = off)
    cdpr_real_t tension_filter_s;   ///< time constant of the tension error's low-pass [s] (>= 0;
                                    ///< 0 = none)
    cdpr_real_t learning_gain;      ///< learning over laps γ [-] (>= 0; 0 = off; step 8)
    cdpr_real_t learning_lead_s;    ///< phase advance of the learned error [s] (>= 0)
    cdpr_real_t learning_cutoff_hz; ///< cutoff f_c of the zero-phase filter Q [Hz] (>= 0; 0 = none)
    cdpr_real_t learning_limit_m;   ///< bound of |c_j| [m] (> 0 when learning_gain > 0)
    long learning_settle_laps;      ///< whole laps after the transfer before recording (>= 0)
    cdpr_real_t transfer_from_rest; ///< 1: the transfer starts the trajectory's clock at rest and
                                    ///< takes over the measured velocity (cdpr_transfer_t); 0: off
    cdpr_real_t integral_per_s;     ///< integral action k_I on the pose error [1/s] (>= 0; 0 = off;
                                    ///< step 2d)
    cdpr_real_t integral_limit_m;   ///< bound of each component of k_I ∫e [m, rad] (> 0 when
                                    ///< integral_per_s > 0)
    cdpr_real_t weight_estimate_s;  ///< time constant τ_W of the cabin's weight estimate [s]
                                    ///< (>= 0; 0 = off; step 1c)
    const cdpr_tracker_correction_t *correction; ///< length pre-compensation (NULL: none;
                                                 ///< step 4c); the caller's, see its type
    cdpr_real_t tension_washout_s; ///< time constant τ_wo of the washout on the filtered tension
                                   ///< error [s] (>= 0; 0 = none; step 4b)
} cdpr_tracker_gains_t;

/// Measurements at the start of a period (inputs): time, measured pose and velocities,
/// measured total unstretched lengths -- what the plant reports (cdpr_plant_measure).
typedef cdpr_plant_meas_t cdpr_tracker_meas_t;

/// Commands and diagnostics of one period (outputs).
typedef struct {
    cdpr_real_t rate_m_per_s[CDPR_MAX_CABLES]; ///< payout-rate commands u_j [m/s], + = pay out
    cdpr_real_t l_ff_m[CDPR_MAX_CABLES];       ///< feed-forward lengths L_ff(t) [m]
    cdpr_real_t u_ff_m_per_s[CDPR_MAX_CABLES]; ///< feed-forward rates [m/s]
    cdpr_real_t dl_m[CDPR_MAX_CABLES];         ///< feedback length corrections δL [m]
    cdpr_real_t corr_m[CDPR_MAX_CABLES];       ///< pre-compensation c_j(t) [m] (0: none)
    cdpr_traj_sample_t desired;                ///< desired state at t
    cdpr_real_t err_pos_m[3];                  ///< e_p = p_d - p, world [m]
    cdpr_real_t err_rot_rad[3];                ///< e_θ, world [rad]
    cdpr_status_t ik_status;                   ///< status of this period's IK
    cdpr_status_t fb_status;                   ///< status of the damping IK (CDPR_OK if unused)
    unsigned slack_demand; ///< bit j: cable j's demanded tension <= 0 this period
    cdpr_real_t demand_tension_N[CDPR_MAX_CABLES]; ///< straight-cable tensions of the demanded load
                                                   ///< (filled when slack_demand != 0, else 0) [N]
} cdpr_tracker_cmd_t;

/// The controller (caller-owned).
typedef struct {
    cdpr_robot_t model;                  ///< own robot model (statics only)
    cdpr_traj_t traj;                    ///< desired trajectory
    cdpr_tracker_gains_t g;              ///< gains
    cdpr_real_t period_s;                ///< control period Δt_c [s]
    cdpr_statics_opts_t ik_opts;         ///< IK settings
    cdpr_real_t l_ff_m[CDPR_MAX_CABLES]; ///< L_ff at t_next_s (internal)
    cdpr_real_t err_f1[12];              ///< first filter stage (internal)
    cdpr_real_t err_f[12];               ///< filtered e_p, e_θ, ė_p, ė_θ (internal)
    cdpr_real_t ten_f[CDPR_MAX_CABLES];  ///< filtered tension errors T_j - T_ff,j [N] (internal)
    cdpr_real_t ten_w[CDPR_MAX_CABLES];  ///< their washout's low-pass w_j [N] (internal)
    cdpr_real_t t_ff_N[CDPR_MAX_CABLES]; ///< feed-forward winch-end tensions at t_next_s (internal)
    int filter_primed;                   ///< err_f holds a value (internal)
    cdpr_real_t t_next_s;                ///< time L_ff refers to (internal)
    int l_ff_exact;            ///< l_ff_m is the IK at t_next_s, not a held value (internal)
    unsigned long ik_failures; ///< periods whose IK failed (output)
    unsigned long fb_failures; ///< periods whose damping IK failed (output)
    unsigned long steps;       ///< periods run (output)
    cdpr_transfer_t transfer;  ///< the planned transfer (set at the first step; internal)
    int transfer_set;          ///< transfer holds the first measurement (internal)
    unsigned long slack_demand_periods[CDPR_MAX_CABLES]; ///< periods whose feed-forward demanded
                                                         ///< a tension <= 0 of cable j (output)
    int first_slack_cable;             ///< cable (0-based) of the first slack demand (-1: none)
    cdpr_real_t first_slack_t_s;       ///< its time: the feed-forward instant t + Δt_c [s]
    cdpr_real_t first_slack_tension_N; ///< its straight-cable tension [N] (<= 0)
    /* learning over laps (step 8) */
    cdpr_real_t learn_c[CDPR_MAX_CABLES]
                       [CDPR_TRACKER_LEARN_KNOTS]; ///< learned c_j at the knots [m]
    cdpr_real_t learn_acc[CDPR_MAX_CABLES][CDPR_TRACKER_LEARN_KNOTS]; ///< this lap's weighted e_L
                                                                      ///< sums (internal)
    cdpr_real_t learn_w[CDPR_TRACKER_LEARN_KNOTS]; ///< this lap's weight sums per knot (internal)
    int learn_knots;                               ///< M (0: no learning; internal)
    cdpr_real_t learn_lap_s;                       ///< T_lap [s] (internal)
    cdpr_real_t learn_start_s;                     ///< t_learn: first lap recorded starts here [s]
    long learn_lap;                     ///< lap of the previous step (-1: none; internal)
    int learn_recording;                ///< the current lap is recorded whole (internal)
    unsigned long learning_updates;     ///< laps learned (updates of c) (output)
    unsigned long learning_saturations; ///< knot values clamped to ±learning_limit_m
                                        ///< (summed over updates and cables) (output)
    /* integral action (step 2d) */
    cdpr_real_t integ[6];               ///< ∫e_p dt [m s], ∫e_θ dt [rad s], world (internal)
    unsigned long integral_saturations; ///< periods with a component of k_I ∫e clamped (output)
    /* weight estimate (step 1c) */
    cdpr_real_t mass_est_kg;          ///< ΔM: the cabin's mass beyond the model's [kg] (output)
    cdpr_real_t mass_res_f1;          ///< the residual's first filter stage [kg] (internal)
    cdpr_real_t mass_res_f;           ///< the filtered residual r_f [kg] (internal)
    unsigned long weight_saturations; ///< periods with ΔM clamped (output)
} cdpr_tracker_t;

/// Validate and initialise for control period `period_s` (> 0): builds the model from
/// `model_params` (6 cables, or more with the robot's tension distribution, robot.h: other
/// counts are CDPR_E_CAPACITY, diag "n_cables ...") and checks gains.correction when given
/// (diag "correction": another cable count or period, CDPR_E_OUT_OF_RANGE; no coefficients,
/// CDPR_E_INVALID_ARG; a spacing <= 0 or a coefficient NaN/Inf, CDPR_E_NOT_FINITE /
/// CDPR_E_OUT_OF_RANGE), and
/// computes L_ff(t0). Errors: CDPR_E_INVALID_ARG /
/// CDPR_E_NOT_FINITE / CDPR_E_OUT_OF_RANGE for gains and period (`diag` names the field), the
/// model's init errors, or the IK status of the desired pose at t0 (e.g. CDPR_E_INFEASIBLE: the
/// trajectory starts outside the feasible set).
cdpr_status_t cdpr_tracker_init(cdpr_tracker_t *tr, const cdpr_robot_params_t *model_params,
                                const cdpr_traj_t *traj, const cdpr_tracker_gains_t *g,
                                cdpr_real_t period_s, cdpr_real_t t0_s, cdpr_diag_t *diag);

/// One control period from measurements at m->t_s. Always produces commands (holding the last
/// good feed-forward when the IK fails; cmd->ik_status says why). If m->t_s is not the time
/// the previous step prepared for, L_ff(t) is recomputed first (one more IK).
/// Returns CDPR_OK, or CDPR_E_INVALID_ARG / CDPR_E_NOT_FINITE for bad measurements (no
/// command written, state unchanged).
cdpr_status_t cdpr_tracker_step(cdpr_tracker_t *tr, const cdpr_tracker_meas_t *m,
                                cdpr_tracker_cmd_t *cmd);

/// d'Alembert (inertial) load of the desired motion `d` on the cabin of `model` (cabin alone:
/// mass M, CoM c, inertia I_c about c, body axes, as cdpr_statics_ik_wrench uses them), in the
/// form cdpr_statics_ik_wrench takes: f = -M a_c with the CoM acceleration
/// a_c = a + ω̇_w x (R c) + ω_w x (ω_w x (R c)), and tau = -R (I_c ω̇ + ω x I_c ω), the torque
/// about the CoM in world axes (ω, ω̇ in body axes; ω_w = R ω, ω̇_w = R ω̇).
void cdpr_tracker_inertial_wrench(const cdpr_robot_t *model, const cdpr_traj_sample_t *d,
                                  cdpr_vec3_t *f_N, cdpr_vec3_t *tau_Nm);

/// Steady aerodynamic load on the cabin from the cables in a uniform wind J at `pose` (wind
/// only; the model has no cabin drag, docs/model.md §3), in the form cdpr_statics_ik_wrench
/// takes (f at the CoM, tau about it, world axes). Per cable, on its straight chord from the
/// attachment P_j to the exit point A_j (length l_j, unit t_j), the plant's drag law at rest
/// (docs/model.md §2, μ = -J): D_j = ½ ρa d0 Cd l_j (|J_n| J_n + Cm |J_t| J_t), J_t = (J·t_j) t_j,
/// J_n = J - J_t; the cabin end carries half of it (a uniform load on a shallow cable splits
/// equally between its ends, to first order in the sag): f = Σ D_j / 2,
/// tau = Σ (R (b_j - c)) x D_j / 2. Neglected: the sag's change of the local tangent (second
/// order in sag/chord), the stretch (sqrt(l lu) vs l) and the tilt of the catenary plane the
/// drag causes in the cable's own shape (the IK's catenaries stay vertical: statics.h).
void cdpr_tracker_wind_wrench(const cdpr_robot_t *model, const cdpr_cabin_motion_t *pose,
                              cdpr_vec3_t wind_m_per_s, cdpr_vec3_t *f_N, cdpr_vec3_t *tau_Nm);

/// The steady wind the feed-forward assumes from the next step on (gains.wind_m_per_s; with
/// wind_ff > 0): a wind that changes during a run, read by an anemometer. Returns CDPR_OK, or
/// CDPR_E_NOT_FINITE (the tracker keeps its wind) or CDPR_E_INVALID_ARG (NULL). O(1).
cdpr_status_t cdpr_tracker_set_wind(cdpr_tracker_t *tr, cdpr_vec3_t wind_m_per_s);

/// Reference of tracker `tr` at t: the trajectory, or the transfer onto it once the first
/// step has set it (transfer_s > 0).
void cdpr_tracker_reference(const cdpr_tracker_t *tr, cdpr_real_t t_s, cdpr_traj_sample_t *out);

/// 1 when the gains close a loop around the feed-forward (pose feedback kp or kd_s, wrench
/// damping, winch tension feedback, learning over laps, integral action or the weight
/// estimate: any of kp, kd_s, damping_N_s_per_m, damping_rot_N_m_s, tension_gain_m_per_s_per_N,
/// learning_gain, integral_per_s, weight_estimate_s > 0), else 0 (feed-forward only: the length
/// loop k_L alone). What the design check of such a controller analyses.
int cdpr_tracker_has_feedback(const cdpr_tracker_gains_t *g);

/// Straight-cable length Jacobian row of cable j at motion m: dL_j = -(u·dp + g·dθ) with
/// the returned u (unit vector attachment -> exit point) and g = (R b_j) x u.
void cdpr_tracker_jacobian(const cdpr_robot_t *model, int j, const cdpr_cabin_motion_t *m,
                           cdpr_vec3_t *u, cdpr_vec3_t *g);

#endif /* CDPR_CONTROL_TRACKER_H */
