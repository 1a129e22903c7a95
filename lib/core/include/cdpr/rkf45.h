/* SPDX-License-Identifier: BSD-3-Clause */
/// @file rkf45.h
/// Adaptive Runge-Kutta-Fehlberg 4(5) integrator over a generic f(t, y, dydt, ctx).
///
/// Propagates the 5th-order solution (local extrapolation, as GSL's rkf45 does) and controls
/// the step with the embedded 4th-order estimate: a step is accepted when
///   max_i |err_i| / (atol_i + rtol * max(|y_i|, |ynew_i|)) <= 1.
/// Memory: the caller provides the workspace (CDPR_RKF45_WORK_PER_DIM * dim_max reals) and,
/// optionally, the per-component absolute tolerances; both pointers are kept (they must outlive
/// the solver). Nothing allocates. Transactional: when a step or advance call fails, y and t
/// are unchanged (the solver's step size and counters may change, as documented per call).
/// Reentrant across solver objects. Pointer arguments must be valid unless a function says it
/// checks them.
#ifndef CDPR_RKF45_H
#define CDPR_RKF45_H

#include "cdpr/config.h"
#include "cdpr/status.h"
#include "cdpr/step_control.h"

/// Workspace reals needed per state component: k1..k6, trial state, new state, backup.
#define CDPR_RKF45_WORK_PER_DIM 9

/// Right-hand side: write dy/dt at (t, y) into dydt. Return CDPR_OK, or a negative status to
/// refuse (the step is then undone and the call returns CDPR_E_RHS).
typedef cdpr_status_t (*cdpr_rhs_fn)(cdpr_real_t t, const cdpr_real_t *y, cdpr_real_t *dydt,
                                     void *ctx);

/// Integrator settings (inputs). Defaults from cdpr_rkf45_params_default().
typedef struct {
    /// Step control (step_control.h); default cdpr_step_control_default(&step, 5): rtol 1e-6,
    /// atol 1e-8, h_init_s 1e-4, h_min_s 1e-12, h_max_s 1, safety 0.9, shrink_min 0.2,
    /// grow_max 5, force_err_max 1845.28125 = 4.5^5 (forced steps of cdpr_rkf45_advance).
    cdpr_step_control_t step;
    /// Step-size controller after an accepted step: 0 (default) the elementary
    /// h * clamp(safety err^-1/5, shrink_min, grow_max); in (0, 0.2] Gustafsson's PI controller
    /// h * clamp(safety err^-(1/5 - 0.75 pi_beta) err_prev^pi_beta, ...) (Hairer's DOPRI5 form;
    /// 0.04 there), err_prev the previous accepted step's error norm (>= 1e-4). Rejections use
    /// the elementary factor either way. 0 gives the same bits as before the option existed.
    cdpr_real_t pi_beta;
} cdpr_rkf45_params_t;

/// Solver object (caller-owned).
typedef struct {
    cdpr_rkf45_params_t p; ///< validated copy
    cdpr_real_t *work;     ///< caller workspace
    int dim_max;           ///< capacity of the workspace in state components
    int dim;               ///< current dimension (<= dim_max)
    cdpr_real_t h_s;       ///< step size to try next [s]
    /// Largest step size that passed the error test [s], counted from the latest step of the
    /// controller's own size (not shortened to land on the end of the interval, not an equal
    /// step of advance) accepted by cdpr_rkf45_step or by an advance call with retry = 0; any
    /// other step that passes the test can only raise it, forced steps leave it alone. 0 after
    /// init and set_dim. An advance call with retry = 1 sizes its equal steps by it.
    cdpr_real_t h_ok_s;
    int retry; ///< 1 after advance returned CDPR_E_SUBSTEP_LIMIT, until an advance call succeeds
    cdpr_real_t last_err;    ///< error norm of the last trial (<= 1: it passed the error test)
    cdpr_real_t err_prev;    ///< error norm of the last accepted step (PI controller; >= 1e-4)
    cdpr_step_stats_t stats; ///< counters (step_control.h), reset by init
} cdpr_rkf45_t;

/// Documented defaults. O(1), cannot fail.
void cdpr_rkf45_params_default(cdpr_rkf45_params_t *p);

/// Validate the settings against `dim` as every scheme does (step_control.h, "The contract
/// every adaptive scheme's functions keep"); this scheme's own error: CDPR_E_NOT_FINITE or
/// CDPR_E_OUT_OF_RANGE: pi_beta NaN/Inf or outside [0, 0.2].
cdpr_status_t cdpr_rkf45_params_validate(const cdpr_rkf45_params_t *p, int dim, cdpr_diag_t *diag);

/// Initialise as every scheme does (step_control.h, "The contract every adaptive scheme's
/// functions keep"), with work_len >= CDPR_RKF45_WORK_PER_DIM * dim_max.
cdpr_status_t cdpr_rkf45_init(cdpr_rkf45_t *s, const cdpr_rkf45_params_t *p, cdpr_real_t *work,
                              int work_len, int dim_max, int dim, cdpr_diag_t *diag);

/// Change the state dimension (after node insertion/removal). The next step restarts from
/// min(h_s, h_init_s) and h_ok_s is cleared: the error history does not describe the new
/// system. retry and the counters are kept. atol_vec is not re-checked: it must hold dim valid
/// entries (cdpr_robot_fill_atol). O(1). CDPR_E_CAPACITY (s unchanged) when s is NULL or dim
/// is outside [1, dim_max]; CDPR_OK otherwise.
cdpr_status_t cdpr_rkf45_set_dim(cdpr_rkf45_t *s, int dim);

/// One RKF45 trial of size h from (t, y) without step-size control: writes the 5th-order
/// solution into y_out and returns the weighted error norm in *err (may be NULL; +Inf when the
/// new state or the norm is not finite), also kept in s->last_err. Used by benchmarks and
/// tests. 6 calls of f plus O(dim); no argument checks. y is not modified; y, y_out and the
/// workspace must not overlap. Returns CDPR_OK, or CDPR_E_RHS when f refused (y_out and *err
/// not written). Counts its calls of f in stats.rhs_evals; the step-size state is not touched.
cdpr_status_t cdpr_rkf45_trial(cdpr_rkf45_t *s, cdpr_rhs_fn f, void *ctx, cdpr_real_t t,
                               const cdpr_real_t *y, cdpr_real_t h, cdpr_real_t *y_out,
                               cdpr_real_t *err);

/// One accepted adaptive step from *t, never past t_end: retries rejected trials with smaller
/// h (a retry reuses f(t, y), so costs 5 calls of f instead of 6). On success y and *t advance.
/// Work: each rejection shrinks h by a factor of at least max(safety, shrink_min), and h_min_s
/// ends it, so at most 2 + ln(h_max_s / h_min_s) / ln(1 / max(safety, shrink_min)) trials
/// (264 with the defaults), each 6 (first) or 5 calls of f plus O(dim).
/// Errors (y, *t unchanged; s->h_s keeps any reduction by rejected trials):
/// - CDPR_E_INVALID_ARG: s, f, t or y is NULL, *t or t_end is NaN/Inf, or t_end <= *t
///   (nothing changed, not counted in stats.failures).
/// - CDPR_E_STATE_NOT_FINITE: y or f(t, y) is not finite.
/// - CDPR_E_STEP_TOO_SMALL: a trial of size <= h_min_s was rejected.
/// - CDPR_E_RHS: f refused.
cdpr_status_t cdpr_rkf45_step(cdpr_rkf45_t *s, cdpr_rhs_fn f, void *ctx, cdpr_real_t *t,
                              cdpr_real_t *y, cdpr_real_t t_end);

/// Advance by exactly dt with at most `max_trials` trials: the bounded-work call of a
/// real-time loop. Work, whatever the outcome: at most max_trials trials of at most 6 calls of
/// f each (<= 6 * max_trials RHS evaluations) plus O(max_trials * (dim + max_trials))
/// arithmetic; no allocation.
///
/// The trials are adaptive steps (as cdpr_rkf45_step) until these no longer fit in the trials
/// left even growing at grow_max per step; the rest of the interval is then covered by equal
/// steps, one per trial left (the fallback). An equal step is accepted when it passes the error
/// test or -- a "forced" step -- when its error norm is at most p.force_err_max; the first
/// equal step above that ends the call with CDPR_E_SUBSTEP_LIMIT. So no step is ever accepted
/// with an error norm above force_err_max: a stiff mode that an over-long step amplifies (an
/// explicit scheme past its stability limit) shows in the error estimate and is refused once
/// it reaches force_err_max times its tolerance, instead of being propagated. (This holds
/// where the estimate is meaningful, as for stiff linear modes; across a discontinuity of f the
/// estimate says less, and p.force_err_max = 1 forbids forced steps altogether.)
/// A call that repeats an interval after CDPR_E_SUBSTEP_LIMIT (s->retry) switches to equal
/// steps earlier: as soon as one more rejection would make them larger than s->h_ok_s (the
/// largest step known to pass the error test; during a repeat it only grows). With s->retry = 0,
/// force_err_max only decides whether an equal step is refused: a call that refuses none takes
/// the same steps, with the same result bits, as with any larger force_err_max.
///
/// Outcomes:
/// - CDPR_OK: *t = t + dt, y advanced, every accepted step passed the error test.
/// - CDPR_WARN_SUBSTEP_LIMIT: *t = t + dt, y advanced; some equal steps were forced (error
///   norm in (1, force_err_max]). Counted in stats.substep_limit_hits and stats.forced_steps.
/// - CDPR_E_SUBSTEP_LIMIT: an equal step was refused (error norm above force_err_max, or
///   NaN/Inf): y and *t are bit-identical to entry. Counted in stats.substep_limit_failures
///   and stats.failures. s->h_s and s->h_ok_s keep what the trials learned (a refused equal
///   step never raises h_s) and s->retry is set. The caller keeps its last good state and
///   calls again for the same interval (in this period if time allows, else the next). The
///   repeat starts from the learned step and, when dt / max_trials <= s->h_ok_s (or once that
///   holds), plans equal steps no larger than steps that passed the error test; that is not a
///   guarantee: an interval the budget cannot cover within force_err_max fails every time
///   (raise max_trials, or accept larger errors with force_err_max).
/// - CDPR_E_INVALID_ARG: s, f, t or y is NULL, *t or dt is NaN/Inf, dt <= 0, or
///   max_trials < 1. Nothing changed, not counted.
/// - Other errors (y, *t bit-identical; s->h_s not raised; counted in stats.failures):
///   CDPR_E_STATE_NOT_FINITE (y or f(t, y) not finite), CDPR_E_STEP_TOO_SMALL (a trial of
///   size <= h_min_s rejected), CDPR_E_RHS (f refused).
cdpr_status_t cdpr_rkf45_advance(cdpr_rkf45_t *s, cdpr_rhs_fn f, void *ctx, cdpr_real_t *t,
                                 cdpr_real_t *y, cdpr_real_t dt, int max_trials);

#endif /* CDPR_RKF45_H */
