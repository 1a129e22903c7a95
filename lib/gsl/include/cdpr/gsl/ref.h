/* SPDX-License-Identifier: BSD-3-Clause */
/// @file ref.h
/// Host-side reference integration of any cdpr right-hand side with GSL's odeiv2 rkf45: the
/// same RHS the core integrates (docs/model.md §7).
///
/// Licence: GSL is GPL-3. This header and lib/gsl (target `cdpr_gsl`) are for host-side
/// validation, tests and tools only. `cdpr_core` never includes it and never links GSL, and
/// nothing meant for controller firmware may link `cdpr_gsl`.
///
/// What it offers:
///   - an adapter that presents a `cdpr_rhs_fn` + context as a `gsl_odeiv2_system`;
///   - `cdpr_gsl_integrate`: a complete adaptive integration t0 -> t1 (the reference solution);
///   - `cdpr_gsl_stepper_t`: preallocated GSL objects for single steps (benchmarks, tests).
///
/// Memory: unlike the core, this module allocates. `cdpr_gsl_integrate` allocates (GSL's step,
/// control and evolve objects and one backup of y) on every call and frees them before it
/// returns; `cdpr_gsl_stepper_init` allocates once, `cdpr_gsl_stepper_free` releases, and the
/// stepping calls in between make no allocation (GSL's own work arrays are preallocated).
///
/// Errors: GSL's default error handler aborts the process. Every entry point of this module
/// that calls GSL first calls cdpr_gsl_error_handler_off() (idempotent), so GSL errors come
/// back as return codes; that is a process-wide GSL setting.
///
/// Units: whatever the wrapped RHS uses (SI for the robot: t in [s]).
#ifndef CDPR_GSL_REF_H
#define CDPR_GSL_REF_H

#include <stddef.h>

#include <gsl/gsl_odeiv2.h>

#include "cdpr/config.h"
#include "cdpr/rkf45.h"
#include "cdpr/status.h"

/* GSL works in double only: the adapter hands GSL's double arrays straight to the cdpr RHS,
 * which is only valid when cdpr_real_t is double. */
#ifdef CDPR_REAL_IS_FLOAT
#error "cdpr_gsl needs cdpr_real_t == double: build it without CDPR_REAL_IS_FLOAT"
#endif

/// Context of the GSL adapter: which cdpr RHS to call and what happened.
/// Must stay at the same address while a gsl_odeiv2_system built on it is in use.
typedef struct {
    cdpr_rhs_fn f;            ///< wrapped right-hand side (input)
    void *ctx;                ///< its context, e.g. a cdpr_robot_t * (input)
    unsigned long rhs_evals;  ///< calls of f made through the adapter (output)
    cdpr_status_t last_error; ///< last negative status f returned, CDPR_OK if none (output)
} cdpr_gsl_adapter_t;

/// GSL-compatible function: calls the adapter's f. Returns GSL_SUCCESS, or GSL_EBADFUNC when
/// f returns a negative status (GSL then abandons the step with y unchanged; the status is
/// kept in adapter->last_error). `params` is the cdpr_gsl_adapter_t *.
int cdpr_gsl_rhs_eval(double t, const double y[], double dydt[], void *params);

/// Fill `a` and return a gsl_odeiv2_system of dimension `dim` whose function is
/// cdpr_gsl_rhs_eval with `a` as params (no Jacobian: explicit steppers only). No allocation.
gsl_odeiv2_system cdpr_gsl_system(cdpr_gsl_adapter_t *a, cdpr_rhs_fn f, void *ctx, size_t dim);

/// Turn GSL's aborting error handler off, once per process (later calls do nothing).
void cdpr_gsl_error_handler_off(void);

/// Counters of one cdpr_gsl_integrate call (outputs).
typedef struct {
    unsigned long steps_accepted; ///< accepted steps (calls of gsl_odeiv2_evolve_apply)
    unsigned long steps_rejected; ///< trials GSL's control rejected and retried smaller
    unsigned long rhs_evals;      ///< calls of f (GSL 2.7.1: 1 at the start + 6 per trial)
    double h_next_s;              ///< step size GSL proposes next [time unit of f]
} cdpr_gsl_stats_t;

/// Integrate y' = f(t, y) from t0 to t1 (> t0) with GSL's rkf45 stepper, its standard error
/// control and gsl_odeiv2_evolve_apply: the reference solution for cdpr_rkf45 on the same
/// problem. A trial is accepted when, for every component i,
///   |err_i| <= 1.1 * (atol_i + rtol * |y_new_i|)
/// (GSL's hadjust: it only shrinks the step above a ratio of 1.1), where atol_i = atol_vec[i]
/// when atol_vec is not NULL (gsl_odeiv2_control_scaled_new), else atol
/// (gsl_odeiv2_control_y_new). `h0` is the first trial step (> 0).
///
/// `y` (dim values) holds the state at t0 on entry and at t1 on success.
/// Returns CDPR_OK, or (y restored bit-for-bit to its value on entry):
///   CDPR_E_INVALID_ARG   NULL f or y, dim == 0, t1 <= t0, non-positive h0, rtol < 0,
///                        atol <= 0 (when atol_vec is NULL), max_steps == 0, any non-finite
///                        argument;
///   CDPR_E_NOT_FINITE    y on entry is not finite;
///   CDPR_E_RHS           f refused (returned a negative status);
///   CDPR_E_STEP_TOO_SMALL GSL could not make progress (step below round-off);
///   CDPR_E_NO_CONVERGENCE t1 not reached within max_steps accepted steps;
///   CDPR_E_STATE_NOT_FINITE the solution became NaN/Inf;
///   CDPR_E_CAPACITY      an allocation failed (no dedicated out-of-memory status exists).
/// `stats` (may be NULL) is written in every case that gets past argument checking.
/// Work: at most max_steps accepted steps; 6 calls of f per trial plus 1 at the start (GSL
/// 2.7.1's evolve reuses the derivative at the end of a step as the next step's k1).
/// Allocation: GSL step/control/evolve objects and a backup of y, freed before returning.
cdpr_status_t cdpr_gsl_integrate(cdpr_rhs_fn f, void *ctx, size_t dim, double *y, double t0,
                                 double t1, double rtol, double atol, const double *atol_vec,
                                 double h0, unsigned long max_steps, cdpr_gsl_stats_t *stats);

/// Preallocated GSL rkf45 objects for stepping one system (caller-owned struct; it refers to
/// itself, so do not copy or move it between init and free).
typedef struct {
    gsl_odeiv2_step *step;       ///< rkf45 stepper (internal)
    gsl_odeiv2_control *control; ///< standard y-control with the init tolerances (internal)
    gsl_odeiv2_evolve *evolve;   ///< evolve object (internal)
    gsl_odeiv2_system sys;       ///< the wrapped system (internal)
    cdpr_gsl_adapter_t adapter;  ///< adapter; adapter.rhs_evals counts calls of f (output)
    double *yerr;                ///< error estimate of the last apply, dim values (output)
    size_t dim;                  ///< state dimension
} cdpr_gsl_stepper_t;

/// Allocate an rkf45 stepper, a control (atol + rtol |y|, as cdpr_gsl_integrate) and an evolve
/// object for a system of dimension `dim`. On error nothing stays allocated and `s` is
/// left zeroed (cdpr_gsl_stepper_free on it is harmless). Errors: CDPR_E_INVALID_ARG (NULL,
/// dim == 0, bad tolerances), CDPR_E_CAPACITY (allocation failed). Allocation: yes (once).
cdpr_status_t cdpr_gsl_stepper_init(cdpr_gsl_stepper_t *s, cdpr_rhs_fn f, void *ctx, size_t dim,
                                    double rtol, double atol);

/// Release everything cdpr_gsl_stepper_init allocated; `s` is zeroed. NULL is allowed.
void cdpr_gsl_stepper_free(cdpr_gsl_stepper_t *s);

/// One fixed rkf45 step of size h from (t, y) in place, without error control:
/// gsl_odeiv2_step_apply with dydt_in = dydt_out = NULL, i.e. exactly 6 calls of f, as
/// cdpr_rkf45_trial. The error estimate goes to s->yerr. On error (CDPR_E_RHS) y is
/// unchanged. Allocation: none.
cdpr_status_t cdpr_gsl_stepper_apply(cdpr_gsl_stepper_t *s, double t, double h, double *y);

/// One adaptive step with gsl_odeiv2_evolve_apply (what GSL users normally call): advances
/// *t towards t1 by one accepted step, updating *h to GSL's proposal for the next step.
/// Calls of f: 6 per trial, plus 1 on the first call after init or cdpr_gsl_stepper_reset
/// (GSL 2.7.1 keeps the derivative at the end of the step as the next k1 - measured).
/// Errors: CDPR_E_RHS (f refused), CDPR_E_STEP_TOO_SMALL, CDPR_E_INVALID_ARG; y and *t are
/// then unchanged. Allocation: none.
cdpr_status_t cdpr_gsl_stepper_evolve(cdpr_gsl_stepper_t *s, double *t, double t1, double *h,
                                      double *y);

/// Forget GSL's cached derivative and step history (gsl_odeiv2_evolve_reset). Call it whenever
/// y or t changed between cdpr_gsl_stepper_evolve calls for any other reason than the previous
/// call (quaternion renormalisation, node events, a restart): otherwise GSL starts the next
/// step from a stale k1. No allocation.
void cdpr_gsl_stepper_reset(cdpr_gsl_stepper_t *s);

#endif /* CDPR_GSL_REF_H */
