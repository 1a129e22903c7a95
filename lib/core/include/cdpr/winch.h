/* SPDX-License-Identifier: BSD-3-Clause */
/// @file winch.h
/// Winches: payout-rate commands with speed/acceleration limits, and node insertion/removal
/// at the pulley end of each cable (docs/model.md "Winch and node events", paper §3.2-3.3).
///
/// Sign: u > 0 pays cable out (the paper's v_d = -u). Only the pulley-side segment changes
/// length continuously (d lu[n-1]/dt = u, a state of the ODE). Between accepted steps,
/// cdpr_winch_node_events keeps that segment in [Delta/2, 2 Delta]:
///  - insert when lu[n-1] > 2 Delta and n < CDPR_MAX_SEGMENTS: a node at unstretched
///    distance Delta from node n-1 on the straight last segment (position and velocity
///    interpolated), so the old part keeps Delta and the new last segment lu[n-1] - Delta;
///  - remove when lu[n-1] < Delta/2 and n > 1: node n-1 disappears, its segment merges into
///    the previous one and the surviving neighbour takes the mass-weighted mean velocity.
/// Both conserve the total unstretched length exactly. At capacity nothing is inserted: the
/// last segment keeps growing, the call returns CDPR_WARN_CAPACITY and counts it.
///
/// Memory: caller-owned objects, no allocation. Work: O(state dimension) per event (the state
/// vector is shifted in place), O(cables) otherwise. Pointer arguments must be valid unless a
/// function says it checks them.
#ifndef CDPR_WINCH_H
#define CDPR_WINCH_H

#include "cdpr/config.h"
#include "cdpr/robot.h"
#include "cdpr/status.h"

/// Command modes.
typedef enum {
    CDPR_WINCH_RATE = 0,  ///< command is a payout rate [m/s]
    CDPR_WINCH_LENGTH = 1 ///< command is a total unstretched length setpoint [m]
} cdpr_winch_mode_t;

/// Winch limits (inputs).
typedef struct {
    cdpr_real_t u_max_m_per_s;  ///< speed limit (> 0); default 4
    cdpr_real_t a_max_m_per_s2; ///< acceleration limit (> 0); default 5
    cdpr_real_t kp_per_s;       ///< length-mode proportional gain (> 0); default 5
    cdpr_real_t min_length_m;   ///< shortest total unstretched length (> 0); default 0.5
} cdpr_winch_params_t;

/// One winch (caller-owned).
typedef struct {
    cdpr_winch_params_t p;  ///< validated copy
    cdpr_winch_mode_t mode; ///< current command mode (input)
    cdpr_real_t command;    ///< rate [m/s] or length [m] (input, held between periods)
    cdpr_real_t u_m_per_s;  ///< payout rate applied in the current period (output)
    int at_min_length;      ///< 1 while stopped at min_length_m (output)
} cdpr_winch_t;

/// Node-event counters per cable (outputs; plain fields).
typedef struct {
    unsigned long insertions[CDPR_MAX_CABLES];
    unsigned long removals[CDPR_MAX_CABLES];
    unsigned long capacity_hits[CDPR_MAX_CABLES]; ///< calls that wanted to insert but could not
} cdpr_node_stats_t;

/// Defaults of docs/robots.md set A (`paper-50m`): 4 m/s, 5 m/s^2, 5 1/s, 0.5 m. O(1), cannot
/// fail.
void cdpr_winch_params_default(cdpr_winch_params_t *p);

/// Validate and initialise: rate mode, command 0, at rest. O(1). On error `w` is not written.
/// Returns (diag, may be NULL, names the first bad field by its member name, index -1):
/// - CDPR_E_INVALID_ARG: w or p is NULL ("winch").
/// - CDPR_E_NOT_FINITE / CDPR_E_NOT_POSITIVE: u_max_m_per_s, a_max_m_per_s2, kp_per_s or
///   min_length_m NaN/Inf / <= 0.
/// CDPR_OK otherwise.
cdpr_status_t cdpr_winch_init(cdpr_winch_t *w, const cdpr_winch_params_t *p, cdpr_diag_t *diag);

/// Set a new command (a rate is limited by cdpr_winch_update, not here). O(1). Returns
/// (the previous command kept on error):
/// - CDPR_E_INVALID_ARG: w is NULL.
/// - CDPR_E_NOT_FINITE: value is NaN/Inf.
/// - CDPR_E_OUT_OF_RANGE: mode is not a cdpr_winch_mode_t value, or a length <= 0.
/// CDPR_OK otherwise.
cdpr_status_t cdpr_winch_command(cdpr_winch_t *w, cdpr_winch_mode_t mode, cdpr_real_t value);

/// Payout rate for the next period of length dt_s given the current total unstretched length:
/// the commanded (or length-tracking) rate, its change clamped to +-a_max dt, then the rate to
/// +-u_max, then, when hauling in, raised (to at most 0) so that the length does not go below
/// min_length_m within the period; that clamp overrides the acceleration limit. Writes
/// w->u_m_per_s and w->at_min_length. O(1). Returns:
/// - CDPR_WARN_MIN_LENGTH: the minimum-length clamp acted (held at the minimum).
/// - CDPR_E_INVALID_ARG: w is NULL, length_m NaN/Inf, or dt_s NaN/Inf or <= 0 (w unchanged).
/// CDPR_OK otherwise.
cdpr_status_t cdpr_winch_update(cdpr_winch_t *w, cdpr_real_t length_m, cdpr_real_t dt_s);

/// Node insertion/removal for every cable of the robot after an accepted step (see above).
/// Rewrites y in place (dimension r->dim before, r->dim after: y must have room for the grown
/// state, CDPR_ROBOT_STATE_MAX always suffices) and updates r's cables, layout and, when lu_0
/// changed, its combined cabin; t_s is the time of y (cabin motion, for a first free node).
/// The caller then resizes the integrator (cdpr_rkf45_set_dim) and refreshes per-component
/// tolerances when `*changed`. Work: O(r->dim) per event, at most CDPR_MAX_SEGMENTS events per
/// cable; no allocation. Returns:
/// - CDPR_WARN_CAPACITY: some cable at capacity wanted a node (stats->capacity_hits counts
///   it); the other events were done.
/// - CDPR_E_INVALID_ARG: r, y, stats or changed is NULL (nothing changed).
/// CDPR_OK otherwise.
cdpr_status_t cdpr_winch_node_events(cdpr_robot_t *r, cdpr_real_t t_s, cdpr_real_t *y,
                                     cdpr_node_stats_t *stats, int *changed);

#endif /* CDPR_WINCH_H */
