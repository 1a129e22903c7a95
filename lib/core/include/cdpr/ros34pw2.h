/* SPDX-License-Identifier: BSD-3-Clause */
/// @file ros34pw2.h
/// L-stable Rosenbrock-W integrator ROS34PW2 (Rang & Angermann 2005) over a generic
/// f(t, y, dydt, ctx), with the linear algebra supplied by the caller.
///
/// Method: 4 stages, order 3 with an embedded order-2 solution, stiffly accurate, L-stable
/// (R(inf) = 0; the embedded solution has |R(inf)| = 0.48), and a W-method: the order holds
/// for any matrix W = I - gamma h J, J an approximation of df/dy (or J = 0), so a Jacobian with
/// dropped terms, and the time derivative df/dt taken as 0, keep order 3 (docs/model.md "Time
/// integration"). Stages, in the transformed variables u_i of Hairer & Wanner IV.7 (7.4'):
///   W u_i = gamma h f(t + alpha_i h, y + sum_{j<i} a_ij u_j) + gamma sum_{j<i} c_ij u_j,
///   y_new = y + sum m_i u_i,   err = sum (m_i - mhat_i) u_i,
/// one factorisation of W per trial, four solves and four calls of f (three on a retry after a
/// rejection, which reuses f(t, y)).
///
/// Step control: a trial is accepted when
///   max_i |err_i| / (atol_i + rtol * max(|y_i|, |ynew_i|)) <= 1
/// (the norm of cdpr_rkf45), and the next step is h * clamp(safety * err^(-1/3), shrink_min,
/// grow_max) within [h_min_s, h_max_s].
///
/// Linear algebra: `factor(ctx, t, y, gamma_h)` prepares W = I - gamma_h J(t, y) (J may be
/// approximate) and `solve(ctx, b, x)` writes x = W^-1 b for the W of the last factor call.
/// A callback that returns a negative status (non-finite or singular W) ends the call with
/// CDPR_E_SINGULAR, state restored.
///
/// Memory: the caller provides the workspace (CDPR_ROS_WORK_PER_DIM * dim_max reals) and,
/// optionally, the per-component absolute tolerances; both pointers are kept (they must outlive
/// the solver). Nothing allocates. Transactional: when a step or advance call fails, y and t
/// are bit-identical to entry (the solver's step size and counters may change, as documented
/// per call). Reentrant across solver objects. Pointer arguments must be valid unless a
/// function says it checks them.
#ifndef CDPR_ROS34PW2_H
#define CDPR_ROS34PW2_H

#include "cdpr/config.h"
#include "cdpr/rkf45.h"
#include "cdpr/status.h"
#include "cdpr/step_control.h"

/// Workspace reals needed per state component: u1..u4, stage state, f(t, y), stage right-hand
/// side, new state, backup.
#define CDPR_ROS_WORK_PER_DIM 9

/// Stages of one trial: factorisations 1, solves 4, RHS calls 4 (3 on a retry).
#define CDPR_ROS_STAGES 4

/// Prepare W = I - gamma_h J(t, y) for the following solves (J: any approximation of df/dy).
/// Return CDPR_OK, or a negative status (CDPR_E_SINGULAR: W singular or not finite).
typedef cdpr_status_t (*cdpr_ros_factor_fn)(void *ctx, cdpr_real_t t, const cdpr_real_t *y,
                                            cdpr_real_t gamma_h);

/// Write x = W^-1 b (dim components; b and x do not overlap, b is not modified). Return
/// CDPR_OK, or a negative status (CDPR_E_SINGULAR).
typedef cdpr_status_t (*cdpr_ros_solve_fn)(void *ctx, const cdpr_real_t *b, cdpr_real_t *x);

/// The problem: right-hand side and linear algebra, with their contexts.
typedef struct {
    cdpr_rhs_fn f;             ///< dy/dt = f(t, y) (rkf45.h)
    void *f_ctx;               ///< passed to f
    cdpr_ros_factor_fn factor; ///< prepares W
    cdpr_ros_solve_fn solve;   ///< applies W^-1
    void *lin_ctx;             ///< passed to factor and solve
} cdpr_ros_problem_t;

/// Integrator settings (inputs). Defaults from cdpr_ros_params_default().
typedef struct {
    /// Step control (step_control.h); default cdpr_step_control_default(&step, 3): rtol 1e-6,
    /// atol 1e-8, h_init_s 1e-4, h_min_s 1e-12, h_max_s 1, safety 0.9, shrink_min 0.2,
    /// grow_max 5, force_err_max 91.125 = 4.5^3 (forced equal steps of cdpr_ros_advance).
    cdpr_step_control_t step;
    /// Reuse one factorisation for up to this many further trials while gamma h is unchanged
    /// within a relative 1e-3 (>= 0; 0: factor every trial, the default). A W-method keeps its
    /// order with a lagged J; the caller must not change what its factor callback reads (its W
    /// object, the layout) without cdpr_ros_set_dim or cdpr_ros_invalidate.
    int jac_reuse_max;
} cdpr_ros_params_t;

/// Counters of the linear algebra (plain fields, read-only for users; reset by cdpr_ros_init).
typedef struct {
    unsigned long factorisations;    ///< calls of factor
    unsigned long solves;            ///< calls of solve
    unsigned long singular_failures; ///< calls ended by factor or solve (CDPR_E_SINGULAR)
} cdpr_ros_lin_stats_t;

/// Solver object (caller-owned).
typedef struct {
    cdpr_ros_params_t p;      ///< validated copy
    cdpr_real_t *work;        ///< caller workspace
    int dim_max;              ///< capacity of the workspace in state components
    int dim;                  ///< current dimension (<= dim_max)
    cdpr_real_t h_s;          ///< step size to try next [s]
    cdpr_real_t last_err;     ///< error norm of the last trial (<= 1: it passed the error test)
    cdpr_real_t w_gh;         ///< gamma h of the factorisation in force [s]
    int w_valid;              ///< 1 while the caller's W may be reused (jac_reuse_max > 0)
    int w_uses;               ///< trials that reused it since it was made
    cdpr_step_stats_t stats;  ///< counters (step_control.h), reset by init
    cdpr_ros_lin_stats_t lin; ///< linear-algebra counters, reset by init
} cdpr_ros_t;

/// Documented defaults. O(1), cannot fail.
void cdpr_ros_params_default(cdpr_ros_params_t *p);

/// Validate the settings against `dim` as every scheme does (step_control.h, "The contract
/// every adaptive scheme's functions keep"); this scheme's own error: CDPR_E_OUT_OF_RANGE:
/// jac_reuse_max < 0.
cdpr_status_t cdpr_ros_params_validate(const cdpr_ros_params_t *p, int dim, cdpr_diag_t *diag);

/// Initialise as every scheme does (step_control.h, "The contract every adaptive scheme's
/// functions keep"), with work_len >= CDPR_ROS_WORK_PER_DIM * dim_max.
cdpr_status_t cdpr_ros_init(cdpr_ros_t *s, const cdpr_ros_params_t *p, cdpr_real_t *work,
                            int work_len, int dim_max, int dim, cdpr_diag_t *diag);

/// Change the state dimension (after node insertion/removal). The step size is kept (unlike
/// cdpr_rkf45_set_dim): an L-stable method has no stability reason to restart small after a
/// node event, and a step that is too long for the new layout fails the error test and is
/// retried shorter. The factorisation in force is forgotten. Counters are kept. atol_vec is not
/// re-checked: it must hold dim valid entries. O(1). CDPR_E_CAPACITY (s unchanged) when s is NULL
/// or dim is outside [1, dim_max]; CDPR_OK otherwise.
cdpr_status_t cdpr_ros_set_dim(cdpr_ros_t *s, int dim);

/// Forget the factorisation in force: the next trial factors (after the caller changed what
/// factor reads). Also done by init, set_dim and any failed factorisation or solve. O(1);
/// s may be NULL (no-op).
void cdpr_ros_invalidate(cdpr_ros_t *s);

/// One trial of size h from (t, y) without step-size control: writes the order-3 solution into
/// y_out and returns the weighted error norm in *err (may be NULL; +Inf when the new state or
/// the norm is not finite), also kept in s->last_err. For tests and benchmarks. 1
/// factorisation (none when one is reused, jac_reuse_max), 4 solves, 4 calls of f plus O(dim);
/// no argument checks. y is not modified unless y_out is y (allowed: the new state is then
/// written in place); neither may overlap the workspace. Returns CDPR_OK, CDPR_E_RHS (f refused) or
/// CDPR_E_SINGULAR (factor or solve refused); on error y_out and *err are not written.
/// Counts its calls in stats; the step-size state is not touched.
cdpr_status_t cdpr_ros_trial(cdpr_ros_t *s, const cdpr_ros_problem_t *pb, cdpr_real_t t,
                             const cdpr_real_t *y, cdpr_real_t h, cdpr_real_t *y_out,
                             cdpr_real_t *err);

/// One accepted adaptive step from *t, never past t_end: retries rejected trials with smaller
/// h. On success y and *t advance. Work: each rejection shrinks h by a factor of at least
/// max(safety, shrink_min), and h_min_s ends it, so at most
/// 2 + ln(h_max_s / h_min_s) / ln(1 / max(safety, shrink_min)) trials (264 with the defaults),
/// each 1 factorisation, 4 solves and 4 (first) or 3 calls of f plus O(dim).
/// Errors (y, *t bit-identical; s->h_s keeps any reduction by rejected trials; counted in
/// stats.failures except CDPR_E_INVALID_ARG):
/// - CDPR_E_INVALID_ARG: s, pb, one of its callbacks, t or y is NULL, *t or t_end is NaN/Inf,
///   or t_end <= *t (nothing changed).
/// - CDPR_E_STATE_NOT_FINITE: y or f(t, y) is not finite.
/// - CDPR_E_STEP_TOO_SMALL: a trial of size <= h_min_s was rejected.
/// - CDPR_E_RHS: f refused.
/// - CDPR_E_SINGULAR: factor or solve refused (also counted in lin.singular_failures).
cdpr_status_t cdpr_ros_step(cdpr_ros_t *s, const cdpr_ros_problem_t *pb, cdpr_real_t *t,
                            cdpr_real_t *y, cdpr_real_t t_end);

/// Advance by exactly dt with at most `max_trials` trials: the bounded-work call of a
/// real-time loop. Work, whatever the outcome: at most max_trials trials, i.e. at most
/// max_trials factorisations (fewer with jac_reuse_max > 0), 4 max_trials solves and 4 max_trials
/// calls of f, plus O(max_trials * (dim + max_trials)) arithmetic; no allocation.
///
/// The trials are adaptive steps (as cdpr_ros_step) until these no longer fit in the trials
/// left even growing at grow_max per step; the rest of the interval is then covered by equal
/// steps, one per trial left. An equal step is accepted when it passes the error test or -- a
/// "forced" step -- when its error norm is at most p.force_err_max (L-stability keeps a
/// forced step bounded on stiff modes; the bound keeps its error bounded); the first equal
/// step above that ends the call with CDPR_E_SUBSTEP_LIMIT.
///
/// Outcomes:
/// - CDPR_OK: *t = t + dt, y advanced, every accepted step passed the error test.
/// - CDPR_WARN_SUBSTEP_LIMIT: *t = t + dt, y advanced; some equal steps were forced (error
///   norm in (1, force_err_max]). Counted in stats.substep_limit_hits and stats.forced_steps.
/// - CDPR_E_SUBSTEP_LIMIT: an equal step was refused: y and *t bit-identical to entry;
///   counted in stats.substep_limit_failures and stats.failures; s->h_s keeps what the trials
///   learned, so a repeat of the interval starts from a smaller step.
/// - CDPR_E_INVALID_ARG: s, pb, one of its callbacks, t or y is NULL, *t or dt is NaN/Inf,
///   dt <= 0, or max_trials < 1. Nothing changed, not counted.
/// - Other errors (y, *t bit-identical; s->h_s not raised; counted in stats.failures):
///   CDPR_E_STATE_NOT_FINITE (y or f(t, y) not finite), CDPR_E_STEP_TOO_SMALL (a trial of
///   size <= h_min_s rejected), CDPR_E_RHS (f refused), CDPR_E_SINGULAR (factor or solve
///   refused; also counted in lin.singular_failures).
cdpr_status_t cdpr_ros_advance(cdpr_ros_t *s, const cdpr_ros_problem_t *pb, cdpr_real_t *t,
                               cdpr_real_t *y, cdpr_real_t dt, int max_trials);

/// Advance by exactly dt in `n` equal steps of h = dt / n, each accepted whatever its error
/// estimate: the fixed-cost call of a real-time loop (plant.h, CDPR_PLANT_ROS34PW2_FIXED). The
/// step size must keep h times the largest frequency of the problem small enough for the
/// linearly implicit stages (the caller derives n; docs/model.md "Fixed-cost stepping"); the
/// error estimates then report how well it did: *err_max (may be NULL) receives the largest
/// weighted error norm of the n steps, the same norm as the adaptive calls (> 1: a step the
/// adaptive control would have rejected).
/// Work of a successful call, always the same: n factorisations (W is renewed every step,
/// whatever jac_reuse_max says), 4 n solves, 4 n calls of f, plus O(n dim) arithmetic; no
/// allocation. A failing call stops at the failing step, so it never does more.
/// Outcomes:
/// - CDPR_OK: *t = t + dt, y advanced by the n steps.
/// - CDPR_E_INVALID_ARG: s, pb, one of its callbacks, t or y is NULL, *t or dt is NaN/Inf,
///   dt <= 0, or n < 1. Nothing changed, not counted.
/// - CDPR_E_STATE_NOT_FINITE: y on entry, or the result of a step, is not finite (a step's is
///   also counted in stats.nonfinite_rejected).
/// - CDPR_E_RHS (f refused), CDPR_E_SINGULAR (factor or solve refused; also counted in
///   lin.singular_failures).
/// On every error but CDPR_E_INVALID_ARG: y and *t bit-identical to entry, *err_max not written,
/// counted in stats.failures. The step-size state (h_s) is never touched.
cdpr_status_t cdpr_ros_fixed(cdpr_ros_t *s, const cdpr_ros_problem_t *pb, cdpr_real_t *t,
                             cdpr_real_t *y, cdpr_real_t dt, int n, cdpr_real_t *err_max);

#endif /* CDPR_ROS34PW2_H */
