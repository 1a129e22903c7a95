/* SPDX-License-Identifier: BSD-3-Clause */
/// @file robot.h
/// The cable robot: up to CDPR_MAX_CABLES lumped-mass cables between fixed pulley exit points
/// and a rigid cabin (docs/model.md "Frames and geometry", "One cable", "Cabin", "Robot").
///
/// State vector layout (dimension cdpr_robot_state_dim()):
///   y[0..12]                 cabin block (cabin.h: p, q, v, w)
///   y[offset[j] ..]          cable j's block (cable.h: lu[n-1], node positions, velocities)
/// The layout changes only when a node is inserted or removed (winch module, between steps).
///
/// Memory: caller-owned, fixed size (see docs/api.md for sizeof at several capacities); the
/// object holds no resources and no function allocates. cdpr_robot_rhs does O(total segments)
/// work. Inputs (payout rates, wind, external loads, prescribed motion) are plain fields of
/// `in` that the caller may change between steps. Pointer arguments must be valid unless a
/// function says it checks them; r must have passed cdpr_robot_init.
#ifndef CDPR_ROBOT_H
#define CDPR_ROBOT_H

#include "cdpr/cabin.h"
#include "cdpr/cable.h"
#include "cdpr/config.h"
#include "cdpr/status.h"
#include "cdpr/vec3.h"

/// How the cabin moves.
typedef enum {
    CDPR_CABIN_DYNAMIC = 0,   ///< rigid body driven by the cables (forward dynamics)
    CDPR_CABIN_PRESCRIBED = 1 ///< pose imposed by in.motion_fn (inverse dynamics), or held
} cdpr_cabin_mode_t;

/// Prescribed cabin motion at time t [s] (docs/model.md "Cabin", prescribed mode: the paper's
/// inverse dynamic formulation). Must fill every field of *m.
typedef void (*cdpr_motion_fn)(cdpr_real_t t_s, void *ctx, cdpr_cabin_motion_t *m);

/// One cable of the robot (inputs).
typedef struct {
    cdpr_cable_params_t cable; ///< physical cable parameters
    cdpr_vec3_t exit_point_m;  ///< pulley exit point A_j, world [m]
    cdpr_vec3_t attach_body_m; ///< attachment b_j on the cabin, body axes [m]
    int n_segments;            ///< initial segment count, 1..CDPR_MAX_SEGMENTS
    cdpr_real_t length_m;      ///< initial unstretched length [m] (> 0)
} cdpr_robot_cable_params_t;

/// Robot parameters (inputs), validated by cdpr_robot_init.
typedef struct {
    int n_cables;                                      ///< 1..CDPR_MAX_CABLES
    cdpr_robot_cable_params_t cables[CDPR_MAX_CABLES]; ///< per cable
    cdpr_cabin_params_t cabin;                         ///< cabin rigid body
    cdpr_real_t g_m_per_s2;                            ///< gravity [m/s^2] (> 0); 9.80665
    cdpr_cabin_mode_t mode;                            ///< dynamic or prescribed
    /// Tension distribution of the statics (statics.h, cdpr_statics_dist_t): every cable's
    /// lowest tension >= tension_min_N, highest <= tension_max_N, the lowest tensions closest
    /// to tension_ref_N. Needed by a robot with more than six cables (its IK has a choice to
    /// make); with six, the bounds are checked. has_tension_dist 0 (default): none.
    int has_tension_dist;
    cdpr_real_t tension_min_N; ///< [N] (>= 0)
    cdpr_real_t tension_max_N; ///< [N] (> tension_min_N)
    cdpr_real_t tension_ref_N; ///< [N] (in [tension_min_N, tension_max_N])
} cdpr_robot_params_t;

/// Inputs that may change between steps.
typedef struct {
    cdpr_real_t payout_m_per_s[CDPR_MAX_CABLES]; ///< winch payout rates u_j [m/s], + = out
    cdpr_vec3_t wind_m_per_s;                    ///< uniform wind J [m/s]
    cdpr_vec3_t ext_force_world_N;               ///< external force on the cabin CoM [N]
    cdpr_vec3_t ext_torque_body_Nm;              ///< external torque, body axes [N m]
    cdpr_motion_fn motion_fn; ///< prescribed mode: motion source; NULL holds the state's pose
    void *motion_ctx;         ///< passed to motion_fn
} cdpr_robot_inputs_t;

/// Forces and tensions at one instant (outputs).
typedef struct {
    cdpr_vec3_t force_on_cabin_N[CDPR_MAX_CABLES]; ///< F_j on the cabin, world [N]
    cdpr_real_t tension_cabin_N[CDPR_MAX_CABLES];  ///< T_0 of cable j [N]
    cdpr_real_t tension_winch_N[CDPR_MAX_CABLES];  ///< T_{n-1} of cable j [N]
    cdpr_vec3_t total_force_N;                     ///< sum of cable forces, world [N]
    cdpr_vec3_t total_torque_Nm; ///< their moment about the combined CoM, body axes [N m]
} cdpr_robot_out_t;

/// The robot (caller-owned).
typedef struct {
    cdpr_robot_params_t p;               ///< validated copy
    cdpr_cable_t cable[CDPR_MAX_CABLES]; ///< discretised cables (internal)
    cdpr_cabin_t cabin;                  ///< combined cabin (internal)
    cdpr_robot_inputs_t in;              ///< inputs, caller-writable between steps
    int offset[CDPR_MAX_CABLES];         ///< state offset of each cable block
    int dim;                             ///< current state dimension
} cdpr_robot_t;

/// Defaults: one cable of default parameters, default cabin, standard gravity, dynamic mode.
/// O(CDPR_MAX_CABLES), cannot fail.
void cdpr_robot_params_default(cdpr_robot_params_t *p);

/// Validate every field and initialise (inputs zeroed). On error `r` is not written and
/// `diag` (may be NULL) names the first bad field. O(n_cables CDPR_MAX_SEGMENTS); stack:
/// CDPR_MAX_CABLES cdpr_cable_t (9.7 kB at the default capacities in double). Returns:
/// - CDPR_E_INVALID_ARG: r ("robot") or p ("params") is NULL.
/// - CDPR_E_CAPACITY: n_cables outside [1, CDPR_MAX_CABLES] ("n_cables", index n_cables).
/// - CDPR_E_NOT_FINITE / CDPR_E_NOT_POSITIVE: g_m_per_s2 NaN/Inf / <= 0 ("g_m_per_s2").
/// - CDPR_E_OUT_OF_RANGE: mode is not a cdpr_cabin_mode_t value ("mode", index mode).
/// - with has_tension_dist: CDPR_E_NOT_FINITE ("tension_min_N", ...), CDPR_E_OUT_OF_RANGE
///   (tension_min_N < 0, tension_max_N <= tension_min_N, tension_ref_N outside them).
/// - CDPR_E_NOT_FINITE: exit_point_m or attach_body_m of cable j ("exit_point_m",
///   "attach_body_m", index j).
/// - every error of cdpr_cable_init for cable j's cable, n_segments and length_m (its field,
///   index j).
/// - every error of cdpr_cabin_init for p->cabin with the cables' node-0 masses (its field and
///   index; in practice those of cdpr_cabin_params_validate).
/// CDPR_OK otherwise. Geometry (an attachment on its exit point) is not checked here.
cdpr_status_t cdpr_robot_init(cdpr_robot_t *r, const cdpr_robot_params_t *p, cdpr_diag_t *diag);

/// Current state dimension. O(1), cannot fail.
int cdpr_robot_state_dim(const cdpr_robot_t *r);

/// Cabin motion the cables see at (t, y): the state in dynamic mode (q as stored); in
/// prescribed mode in.motion_fn(t) with q normalised, or with motion_fn NULL the state's pose
/// at rest. O(1) plus one call of motion_fn; cannot fail.
void cdpr_robot_cabin_motion(const cdpr_robot_t *r, cdpr_real_t t_s, const cdpr_real_t *y,
                             cdpr_cabin_motion_t *m);

/// Recompute the combined cabin mass properties from r->p.cabin and the node-0 segment
/// lengths lu_m[0] (for a one-segment cable: its length at the last node event), after lu_0
/// changed. O(n_cables). Returns what cdpr_cabin_init returns: CDPR_OK for a robot that passed
/// init with r->p.cabin unchanged since; otherwise its error, with r->cabin unchanged.
cdpr_status_t cdpr_robot_refresh_cabin(cdpr_robot_t *r);

/// Recompute the state offsets and r->dim after a cable's node count changed.
/// O(CDPR_MAX_CABLES), cannot fail.
void cdpr_robot_update_layout(cdpr_robot_t *r);

/// World position and velocity of attachment j (0 <= j < n_cables, not checked) for the cabin
/// motion `m` (rotation from the normalised m->q). O(1), cannot fail.
void cdpr_robot_attachment(const cdpr_robot_t *r, int j, const cdpr_cabin_motion_t *m,
                           cdpr_vec3_t *pos_m, cdpr_vec3_t *vel_m_per_s);

/// Write a full state (r->dim components): the cabin at motion `m` (q normalised), every cable
/// straight from its attachment to its exit point with nodes at their unstretched fractions, at
/// rest. O(total nodes). Returns (y untouched on error):
/// - CDPR_E_NOT_FINITE: a component of m is NaN/Inf.
/// - CDPR_E_GEOMETRY: an attachment coincides with its exit point.
/// CDPR_OK otherwise.
cdpr_status_t cdpr_robot_place_straight(const cdpr_robot_t *r, const cdpr_cabin_motion_t *m,
                                        cdpr_real_t *y);

/// Full right-hand side, usable by cdpr_rkf45 and by GSL (ctx is the cdpr_robot_t *; not
/// modified). O(total segments) plus one call of in.motion_fn in prescribed mode; stack: one
/// cable's scratch (cdpr_cable_rhs). Cannot fail: always returns CDPR_OK (NaN/Inf in y
/// propagate to dydt, which the integrator detects).
cdpr_status_t cdpr_robot_rhs(cdpr_real_t t_s, const cdpr_real_t *y, cdpr_real_t *dydt, void *ctx);

/// Cable forces on the cabin and the end tensions at (t, y); the entries of cables
/// n_cables..CDPR_MAX_CABLES-1 are zeroed. O(CDPR_MAX_CABLES), cannot fail.
void cdpr_robot_outputs(const cdpr_robot_t *r, cdpr_real_t t_s, const cdpr_real_t *y,
                        cdpr_robot_out_t *out);

/// Prescribed mode: write the prescribed motion at t into the cabin block of y (call after
/// each accepted step so outputs show the imposed pose). No-op in dynamic mode and when
/// in.motion_fn is NULL (the held pose stays in y). O(1), cannot fail.
void cdpr_robot_sync_prescribed(const cdpr_robot_t *r, cdpr_real_t t_s, cdpr_real_t *y);

/// Renormalise the cabin quaternion of y (after each accepted step, docs/model.md "Cabin").
/// A quaternion of zero or NaN norm becomes the identity (cdpr_quat_normalize). O(1), cannot
/// fail.
void cdpr_robot_normalize(const cdpr_robot_t *r, cdpr_real_t *y);

/// Per-component absolute tolerances for cdpr_rkf45: positions and lengths [m], velocities
/// [m/s], quaternion components [-], body rates [rad/s]. Writes r->dim entries; call again
/// after node events. O(r->dim), cannot fail.
void cdpr_robot_fill_atol(const cdpr_robot_t *r, cdpr_real_t pos_m, cdpr_real_t vel_m_per_s,
                          cdpr_real_t quat, cdpr_real_t rate_rad_per_s, cdpr_real_t *atol);

#endif /* CDPR_ROBOT_H */
