/* SPDX-License-Identifier: BSD-3-Clause */
/// @file trajectory.h
/// Desired cabin trajectories of the scenarios (docs/validation.md §8): the paper's circle and
/// line, and a hold. Poses are (x, y, z [m], α, β, γ [rad]) with R = Rz(γ) Ry(β) Rx(α).
///
/// - hold:   a fixed pose.
/// - circle: horizontal circle, centre c, radius r, constant attitude; the path length
///           s(t) grows at `speed` (reached after an optional linear speed ramp of ramp_s);
///           angle θ(t) = θ0 + dir s(t)/r, dir = +1 counter-clockwise seen from above (+z).
/// - line:   every coordinate linear in time from `from` to `to` over duration_s, then held;
///           optionally back to `from` after pause_s (deployment and retrieval).
///
/// Pure functions of t; no allocation.
#ifndef CDPR_HOST_TRAJECTORY_H
#define CDPR_HOST_TRAJECTORY_H

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
    double hold_pose[6]; ///< hold: the pose
    /* circle */
    double centre_m[3];     ///< circle centre [m]
    double radius_m;        ///< radius [m] (> 0)
    double speed_m_per_s;   ///< path speed [m/s] (>= 0)
    double start_angle_rad; ///< θ0: start point c + r (cos θ0, sin θ0, 0)
    double direction;       ///< +1 counter-clockwise seen from above, -1 clockwise
    double ramp_s;          ///< speed ramp from 0 [s] (>= 0; 0 = the paper's step)
    double attitude_rad[3]; ///< constant α, β, γ [rad]
    /* line */
    double from[6];     ///< start pose
    double to[6];       ///< end pose
    double duration_s;  ///< time from `from` to `to` [s] (> 0)
    double pause_s;     ///< wait at `to` before returning [s] (>= 0)
    int back_and_forth; ///< 1: return to `from` after the pause
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
    double pose[6];             ///< x, y, z [m], α, β, γ [rad]
    double rate[6];             ///< time derivative of pose [m/s, rad/s]
    double accel[6];            ///< second time derivative of pose [m/s^2, rad/s^2]
    cdpr_cabin_motion_t motion; ///< p, q, v (world), ω (body axes)
    cdpr_vec3_t a_m_per_s2;     ///< acceleration of the body origin, world [m/s^2]
    cdpr_vec3_t dw_rad_per_s2;  ///< dω/dt of the body-axes ω [rad/s^2] (= R^T dω_world/dt)
} cdpr_traj_sample_t;

/// Evaluate the trajectory at t [s] (t < 0 gives the start, at rest).
void cdpr_traj_eval(const cdpr_traj_t *tr, double t_s, cdpr_traj_sample_t *out);

/// Body-axes angular velocity for Euler angles `euler` and their rates (R = Rz Ry Rx).
cdpr_vec3_t cdpr_euler_rates_to_body(const double euler[3], const double rates[3]);

/// Body-axes angular acceleration dω/dt for Euler angles, their rates and their second
/// derivatives (R = Rz Ry Rx). Equals R^T dω_world/dt, since d(R^T)/dt ω_world = 0.
cdpr_vec3_t cdpr_euler_accel_to_body(const double euler[3], const double rates[3],
                                     const double accels[3]);

/// Period of a cyclic trajectory, 2 (duration_s + pause_s) [s] (0 for the other types).
double cdpr_traj_cycle_s(const cdpr_traj_t *tr);

/// Time at which the trajectory stops moving [s] (circle and an endless cyclic: never, +Inf).
double cdpr_traj_end_time(const cdpr_traj_t *tr);

#endif /* CDPR_HOST_TRAJECTORY_H */
