/* SPDX-License-Identifier: BSD-3-Clause */
/// @file trajectory.h
/// Desired cabin trajectories of the scenarios (docs/validation.md §8): the paper's circle and
/// line, a hold, and the cyclic deploy-and-retrieve move. Poses are (x, y, z [m], α, β, γ [rad])
/// with R = Rz(γ) Ry(β) Rx(α).
///
/// - hold:   a fixed pose.
/// - circle: horizontal circle, centre c, radius r, constant attitude; the path length
///           s(t) grows at `speed` (reached after an optional linear speed ramp of ramp_s);
///           angle θ(t) = θ0 + dir s(t)/r, dir = +1 counter-clockwise seen from above (+z).
/// - line:   every coordinate linear in time from `from` to `to` over duration_s, then held;
///           optionally back to `from` after pause_s (deployment and retrieval).
/// - cyclic: `from` -> `to` -> `from`, repeated (CDPR_TRAJ_CYCLIC, below).
///
/// Pure functions of t; no allocation.
#ifndef CDPR_CONTROL_TRAJECTORY_H
#define CDPR_CONTROL_TRAJECTORY_H

#include "cdpr/cabin.h"

/// Trajectory kinds.
typedef enum {
    CDPR_TRAJ_HOLD = 0,
    CDPR_TRAJ_CIRCLE = 1,
    CDPR_TRAJ_LINE = 2,
    CDPR_TRAJ_CYCLIC = 3 ///< repeated `from` -> `to` -> `from` (deploy and retrieve), see below
} cdpr_traj_type_t;

/// Trajectory parameters (inputs).
typedef struct {
    cdpr_traj_type_t type;
    cdpr_real_t hold_pose[6]; ///< hold: the pose
    /* circle */
    cdpr_real_t centre_m[3];     ///< circle centre [m]
    cdpr_real_t radius_m;        ///< radius [m] (> 0)
    cdpr_real_t speed_m_per_s;   ///< path speed [m/s] (>= 0)
    cdpr_real_t start_angle_rad; ///< θ0: start point c + r (cos θ0, sin θ0, 0)
    cdpr_real_t direction;       ///< +1 counter-clockwise seen from above, -1 clockwise
    cdpr_real_t ramp_s;          ///< speed ramp from 0 [s] (>= 0; 0 = the paper's step)
    cdpr_real_t attitude_rad[3]; ///< constant α, β, γ [rad]
    /* line */
    cdpr_real_t from[6];    ///< start pose
    cdpr_real_t to[6];      ///< end pose
    cdpr_real_t duration_s; ///< time from `from` to `to` [s] (> 0)
    cdpr_real_t pause_s;    ///< wait at `to` before returning [s] (>= 0)
    int back_and_forth;     ///< 1: return to `from` after the pause
    /* cyclic: from, to, duration_s (one leg) and pause_s (at each end) as above; each leg
     * follows the cycloidal profile s(u) = u - sin(2 pi u) / (2 pi), u = leg time / duration_s,
     * so position, velocity and acceleration are continuous everywhere (zero velocity and
     * acceleration at both ends of a leg) and the motion is periodic with period
     * 2 (duration_s + pause_s): out, pause at `to`, back, pause at `from`. */
    long cycles; ///< cyclic: cycles to run, then held at `from` (0: repeats for ever)
} cdpr_traj_t;

/// Desired state at one instant (outputs).
///
/// Accelerations are analytic. Where the trajectory has a kink (the line's start and end,
/// where its velocity steps; the end of the circle's speed ramp; the circle's step start at
/// full speed) they are the one-sided value of the piece that contains t (pieces are closed on
/// the left): the impulse of a velocity step is not represented.
typedef struct {
    cdpr_real_t pose[6];        ///< x, y, z [m], α, β, γ [rad]
    cdpr_real_t rate[6];        ///< time derivative of pose [m/s, rad/s]
    cdpr_real_t accel[6];       ///< second time derivative of pose [m/s^2, rad/s^2]
    cdpr_cabin_motion_t motion; ///< p, q, v (world), ω (body axes)
    cdpr_vec3_t a_m_per_s2;     ///< acceleration of the body origin, world [m/s^2]
    cdpr_vec3_t dw_rad_per_s2;  ///< dω/dt of the body-axes ω [rad/s^2] (= R^T dω_world/dt)
} cdpr_traj_sample_t;

/// Evaluate the trajectory at t [s] (t < 0 gives the start, at rest).
void cdpr_traj_eval(const cdpr_traj_t *tr, cdpr_real_t t_s, cdpr_traj_sample_t *out);

/// Body-axes angular velocity for Euler angles `euler` and their rates (R = Rz Ry Rx).
cdpr_vec3_t cdpr_euler_rates_to_body(const cdpr_real_t euler[3], const cdpr_real_t rates[3]);

/// Body-axes angular acceleration dω/dt for Euler angles, their rates and their second
/// derivatives (R = Rz Ry Rx). Equals R^T dω_world/dt, since d(R^T)/dt ω_world = 0.
cdpr_vec3_t cdpr_euler_accel_to_body(const cdpr_real_t euler[3], const cdpr_real_t rates[3],
                                     const cdpr_real_t accels[3]);

/// Period of a cyclic trajectory, 2 (duration_s + pause_s) [s] (0 for the other types).
cdpr_real_t cdpr_traj_cycle_s(const cdpr_traj_t *tr);

/// Time at which the trajectory stops moving [s] (circle and an endless cyclic: never, +Inf).
cdpr_real_t cdpr_traj_end_time(const cdpr_traj_t *tr);

/// Lap of a periodic trajectory at t [s]: 0, 1, 2, ...; -1 when the trajectory is not periodic
/// (hold, line, a circle at speed 0) or t is outside its laps (t < 0; a cyclic trajectory after
/// its last cycle). Circle: lap i holds the path lengths [2 pi r i, 2 pi r (i + 1)) from the
/// start (the speed ramp included); cyclic: t in [i P, (i + 1) P), P = cdpr_traj_cycle_s.
long cdpr_traj_lap(const cdpr_traj_t *tr, cdpr_real_t t_s);

/// Duration of one lap of a periodic trajectory once it moves at its full speed [s]: circle
/// 2 pi r / speed, cyclic cdpr_traj_cycle_s; 0 when the trajectory is not periodic (the cases
/// where cdpr_traj_lap is always -1). The circle is periodic in time with this period only
/// after its speed ramp (t >= ramp_s).
cdpr_real_t cdpr_traj_lap_s(const cdpr_traj_t *tr);

/// Phase of t within its lap (cdpr_traj_lap), as a fraction in [0, 1): circle, the path
/// length travelled since the lap's start over 2 pi r; cyclic, (t - i P) / P. -1 where
/// cdpr_traj_lap is -1.
cdpr_real_t cdpr_traj_lap_phase(const cdpr_traj_t *tr, cdpr_real_t t_s);

/// Planned transfer from a measured start onto a trajectory (issue 14; controller.transfer_s).
///
/// Over [t0, t0 + T] the offset of the measured start from the trajectory decays:
///   p_r(t) = p_traj(t) + (1 - s(τ)) Δp,  Δp = p0 - p_traj(t0),  τ = (t - t0) / T,
///   v_r = v_traj - ṡ Δp,  a_r = a_traj - s̈ Δp,
/// with the septic blend s(τ) = 35 τ^4 - 84 τ^5 + 70 τ^6 - 20 τ^7 (s, ds/dτ, d²s/dτ² and the
/// jerk vanish at τ = 0; s = 1 and the derivatives vanish at τ = 1), ṡ = ds/dτ / T,
/// s̈ = d²s/dτ² / T². So the reference starts at the measured position with the trajectory's
/// velocity and acceleration (the blend adds none at t0) and joins the trajectory at t0 + T
/// with its position, velocity, acceleration and jerk. The measured velocity is not used: a
/// start at rest onto a trajectory that starts moving (the paper's circle at full speed) keeps
/// that velocity step. (A blend from the held start into the moving trajectory,
/// p_h + s (p_traj - p_h), removes it but cuts across the circle with large accelerations;
/// measured worse on the paper's circle: docs/validation.md §8, "Issue 14, increment 1".)
/// Attitude: the rotation-vector offset θ0 = rotvec(q0 q_traj(t0)^-1) (world axes) decays,
///   q_r(t) = exp((1 - s) θ0) q_traj(t),
///   ω_r,world = -ṡ θ0 + E ω_traj,world,  ω̇_r,world = -s̈ θ0 + (-ṡ θ0) x (E ω_traj,world)
///                + E ω̇_traj,world,  E = rotation of exp((1 - s) θ0).
/// From t0 + T on the sample is exactly cdpr_traj_eval's (before t0, τ is clamped to 0).
/// T = 0 means no transfer.
///
/// From rest (`from_rest`, controller.transfer_from_rest: 1): the trajectory's clock also
/// starts at rest and catches up by t0 + T, and the measured velocity v0 is taken over:
///   w(t) = t0 + (t - t0) s(τ),  w' = s + τ ds/dτ,  w'' = (2 ds/dτ + τ d²s/dτ²) / T,
///   p_r = p_traj(w) + (1 - s) Δp + T h(τ) v0,  h(τ) = τ (1 - τ)^4,
///   v_r = w' v_traj(w) - ṡ Δp + h'(τ) v0,
///   a_r = w'^2 a_traj(w) + w'' v_traj(w) - s̈ Δp + h''(τ) v0 / T,
/// and the attitude as above with the trajectory's rates at w scaled the same way
/// (ω w', ω̇ w'^2 + ω w''). At t0 the reference has the measured position and velocity
/// (w' = 0, h' = 1); at t0 + T, w = t with w' = 1 and w'' = 0, and h, h', h'' vanish, so it
/// joins the trajectory with position, velocity and acceleration. The clock runs at most
/// max(w') = 1.88 times the trajectory's speed (at τ = 5/8) to catch up.
typedef struct {
    cdpr_real_t t0_s;       ///< start of the transfer [s]
    cdpr_real_t duration_s; ///< T [s] (>= 0; 0 = no transfer)
    cdpr_vec3_t offset_m;   ///< Δp = p0 - p_traj(t0), world [m]
    cdpr_vec3_t theta0_rad; ///< rotvec(q0 q_traj(t0)^-1), world [rad]
    int from_rest;          ///< 1: the trajectory's clock starts at rest (see above)
    cdpr_vec3_t v0_m_per_s; ///< measured velocity at t0 (from_rest only), world [m/s]
} cdpr_transfer_t;

/// Septic blend s(τ) and its first two derivatives with respect to τ (τ clamped to [0, 1]).
void cdpr_transfer_blend(cdpr_real_t tau, cdpr_real_t *s, cdpr_real_t *ds_dtau,
                         cdpr_real_t *d2s_dtau2);

/// The transfer that starts at t0_s from the measured pose m0 onto `traj`, over duration_s
/// (>= 0). from_rest 0: m0's velocities are not used; 1: the trajectory's clock starts at
/// rest and m0's velocity is taken over (its angular velocity is not used).
void cdpr_transfer_init(cdpr_transfer_t *x, const cdpr_traj_t *traj, cdpr_real_t t0_s,
                        cdpr_real_t duration_s, const cdpr_cabin_motion_t *m0, int from_rest);

/// Reference at t: the transfer blended into `traj` (see cdpr_transfer_t). `pose`, `motion`,
/// `a_m_per_s2` and `dw_rad_per_s2` are the reference's; `rate`/`accel` hold the position
/// derivatives exactly and, for the angles, the trajectory's Euler rates (not used by the
/// controller).
void cdpr_transfer_eval(const cdpr_transfer_t *x, const cdpr_traj_t *traj, cdpr_real_t t_s,
                        cdpr_traj_sample_t *out);

#endif /* CDPR_CONTROL_TRAJECTORY_H */
