/* SPDX-License-Identifier: BSD-3-Clause */
/// @file settle.h
/// Relaxation of a robot state to its discrete static equilibrium by kinetic damping
/// (dynamic relaxation, Barnes 1977 / Cundall): integrate the true equations of motion and,
/// each time the kinetic energy passes a peak, set every velocity to zero. Drag and
/// strain-rate damping vanish at rest, so the state it converges to is the equilibrium of the
/// lumped-mass model itself, independent of how the energy was removed.
///
/// Use: the "released and damped to rest" validation case and initial states at rest.
/// Work: bounded by `max_steps` accepted steps (each step <= a bounded number of RHS calls);
/// allocation: none. Host or target; not meant for the real-time loop.
#ifndef CDPR_SETTLE_H
#define CDPR_SETTLE_H

#include "cdpr/config.h"
#include "cdpr/rkf45.h"
#include "cdpr/robot.h"
#include "cdpr/status.h"

/// Settings (inputs) and report (outputs).
typedef struct {
    long max_steps;               ///< bound on accepted integrator steps (> 0)
    cdpr_real_t max_step_s;       ///< largest step handed to the integrator [s] (> 0)
    cdpr_real_t acc_tol_m_per_s2; ///< converged when every node and cabin acceleration at
                                  ///< rest is below this [m/s^2] (> 0)
    /* outputs */
    long steps;                   ///< accepted steps taken
    long resets;                  ///< kinetic-energy peaks (velocity resets)
    cdpr_real_t time_s;           ///< simulated time used [s]
    cdpr_real_t max_acc_m_per_s2; ///< largest acceleration at the last check [m/s^2]
} cdpr_settle_t;

/// Defaults: 2e6 steps, 0.01 s, 1e-6 m/s^2 (double) / 1e-2 m/s^2 (float); outputs zeroed.
/// O(1), cannot fail.
///
/// Float: at rest the node accelerations keep the rounding of the segment forces, a few times
/// EA 2 u_f / m_node (u_f = 2^-24). Measured: 2e-3 - 9e-3 m/s^2 on the soft validation cables
/// (EA 2-20 kN, nodes 0.35-1.75 kg), so 1e-3 never converged there; 1e-2 does, and still
/// pins a mode with omega^2 = 6 1/s^2 (the 50 m model's softest) to ~2 mm. Stiff ropes do not
/// settle in float at any tolerance that still means "at rest": the 50 m model's EA = 2 MN
/// leaves 0.6-2.5 m/s^2 on its nodes. Place such robots with cdpr_statics_place_catenary
/// (statics.h), or settle in double.
void cdpr_settle_default(cdpr_settle_t *cfg);

/// The kinetic-energy measure whose peaks trigger the velocity resets [J]: the cable nodes'
/// kinetic energy (lumped masses) plus, in dynamic mode, the cabin's with its origin velocity
/// standing in for the centre-of-mass velocity (a positive-definite measure of motion, exact
/// when the body origin is the centre of mass). O(total nodes); no allocation; cannot fail.
cdpr_real_t cdpr_settle_kinetic_energy(const cdpr_robot_t *r, const cdpr_real_t *y);

/// Relax y (dimension r->dim) to rest: velocities are zeroed at the start and at each
/// kinetic-energy peak; r->in is used as given (zero payout rates keep the lengths). `scratch`
/// holds r->dim reals. The solver's state (h_s, counters) carries over from and into the
/// caller. Work: at most cfg->max_steps calls of cdpr_rkf45_step, each bounded as documented
/// there, plus at most one RHS call and O(total nodes) per step; no allocation.
/// Returns (cfg->steps, resets, time_s and max_acc_m_per_s2 report the run in every case but
/// CDPR_E_INVALID_ARG):
/// - CDPR_OK: converged, y at rest (velocities zero).
/// - CDPR_E_INVALID_ARG: r, solver, y, scratch or cfg is NULL, max_steps < 1, max_step_s or
///   acc_tol_m_per_s2 not > 0, or solver->dim != r->dim (nothing changed).
/// - CDPR_E_NO_CONVERGENCE: max_steps ran out; y is the last state, still valid.
/// - an error of cdpr_rkf45_step (CDPR_E_STATE_NOT_FINITE, CDPR_E_STEP_TOO_SMALL, CDPR_E_RHS):
///   y is the last good state (not the input state: its velocities were zeroed).
cdpr_status_t cdpr_settle_robot(const cdpr_robot_t *r, cdpr_rkf45_t *solver, cdpr_real_t *y,
                                cdpr_real_t *scratch, cdpr_settle_t *cfg);

#endif /* CDPR_SETTLE_H */
