/* SPDX-License-Identifier: BSD-3-Clause */
/// @file rkf45.c
/// Runge-Kutta-Fehlberg 4(5) with step control (docs/model.md "Time integration").
///
/// Coefficients: E. Fehlberg, NASA TR R-315 (1969), table III, as exact rationals.
#include "cdpr/rkf45.h"

#include <math.h>
#include <stddef.h>

#include "check.h"
#include "step.h"

/* Nodes c_i and the Butcher tableau a_ij. */
#define C2  CDPR_R(1.0) / CDPR_R(4.0)
#define C3  CDPR_R(3.0) / CDPR_R(8.0)
#define C4  CDPR_R(12.0) / CDPR_R(13.0)
#define C5  CDPR_R(1.0)
#define C6  CDPR_R(1.0) / CDPR_R(2.0)
#define A21 (CDPR_R(1.0) / CDPR_R(4.0))
#define A31 (CDPR_R(3.0) / CDPR_R(32.0))
#define A32 (CDPR_R(9.0) / CDPR_R(32.0))
#define A41 (CDPR_R(1932.0) / CDPR_R(2197.0))
#define A42 (CDPR_R(-7200.0) / CDPR_R(2197.0))
#define A43 (CDPR_R(7296.0) / CDPR_R(2197.0))
#define A51 (CDPR_R(439.0) / CDPR_R(216.0))
#define A52 CDPR_R(-8.0)
#define A53 (CDPR_R(3680.0) / CDPR_R(513.0))
#define A54 (CDPR_R(-845.0) / CDPR_R(4104.0))
#define A61 (CDPR_R(-8.0) / CDPR_R(27.0))
#define A62 CDPR_R(2.0)
#define A63 (CDPR_R(-3544.0) / CDPR_R(2565.0))
#define A64 (CDPR_R(1859.0) / CDPR_R(4104.0))
#define A65 (CDPR_R(-11.0) / CDPR_R(40.0))
/* 5th-order weights (propagated). */
#define B1 (CDPR_R(16.0) / CDPR_R(135.0))
#define B3 (CDPR_R(6656.0) / CDPR_R(12825.0))
#define B4 (CDPR_R(28561.0) / CDPR_R(56430.0))
#define B5 (CDPR_R(-9.0) / CDPR_R(50.0))
#define B6 (CDPR_R(2.0) / CDPR_R(55.0))
/* Error weights: 5th-order minus 4th-order (25/216, 0, 1408/2565, 2197/4104, -1/5, 0). */
#define E1 (CDPR_R(1.0) / CDPR_R(360.0))
#define E3 (CDPR_R(-128.0) / CDPR_R(4275.0))
#define E4 (CDPR_R(-2197.0) / CDPR_R(75240.0))
#define E5 (CDPR_R(1.0) / CDPR_R(50.0))
#define E6 (CDPR_R(2.0) / CDPR_R(55.0))

/* Workspace slots. */
enum { K1 = 0, K2, K3, K4, K5, K6, YTMP, YNEW, YBAK };

static cdpr_real_t *slot(const cdpr_rkf45_t *s, int k)
{
    return s->work + (size_t)k * (size_t)s->dim_max;
}

void cdpr_rkf45_params_default(cdpr_rkf45_params_t *p)
{
    cdpr_step_control_default(&p->step, 5); /* error estimate O(h^5) */
    p->pi_beta = CDPR_R(0.0);
}

cdpr_status_t cdpr_rkf45_params_validate(const cdpr_rkf45_params_t *p, int dim, cdpr_diag_t *diag)
{
    if (p == NULL) {
        return cdpr_diag_set(diag, CDPR_E_INVALID_ARG, "rkf45", -1);
    }
    CDPR_TRY(cdpr_step_control_validate(&p->step, dim, diag));
    CDPR_TRY(check_nonnegative(p->pi_beta, "pi_beta", -1, diag));
    if (p->pi_beta > CDPR_R(0.2)) {
        return cdpr_diag_set(diag, CDPR_E_OUT_OF_RANGE, "pi_beta", -1);
    }
    return cdpr_diag_set(diag, CDPR_OK, "", -1);
}

cdpr_status_t cdpr_rkf45_init(cdpr_rkf45_t *s, const cdpr_rkf45_params_t *p, cdpr_real_t *work,
                              int work_len, int dim_max, int dim, cdpr_diag_t *diag)
{
    CDPR_TRY(step_init_check(s, work, work_len, CDPR_RKF45_WORK_PER_DIM, dim_max, dim, diag));
    CDPR_TRY(cdpr_rkf45_params_validate(p, dim, diag));
    s->p = *p;
    s->work = work;
    s->dim_max = dim_max;
    s->dim = dim;
    s->h_s = step_first(&p->step);
    s->h_ok_s = CDPR_R(0.0);
    s->retry = 0;
    s->last_err = CDPR_R(0.0);
    s->err_prev = CDPR_R(1e-4);
    step_stats_reset(&s->stats);
    return cdpr_diag_set(diag, CDPR_OK, "", -1);
}

cdpr_status_t cdpr_rkf45_set_dim(cdpr_rkf45_t *s, int dim)
{
    if (s == NULL || dim < 1 || dim > s->dim_max) {
        return CDPR_E_CAPACITY;
    }
    s->dim = dim;
    if (s->h_s > s->p.step.h_init_s) {
        s->h_s = s->p.step.h_init_s;
    }
    s->h_ok_s = CDPR_R(0.0);
    s->err_prev = CDPR_R(1e-4);
    return CDPR_OK;
}

/* One counted call of f. */
static cdpr_status_t eval(cdpr_rkf45_t *s, cdpr_rhs_fn f, void *ctx, cdpr_real_t t,
                          const cdpr_real_t *y, cdpr_real_t *dydt)
{
    s->stats.rhs_evals++;
    return (f(t, y, dydt, ctx) < 0) ? CDPR_E_RHS : CDPR_OK;
}

/* One trial; `have_k1` says slot K1 already holds f(t, y) (a retry after a rejection from the
 * same point), which saves one RHS call. The slots never alias each other or y/y_out. */
static cdpr_status_t trial(cdpr_rkf45_t *s, cdpr_rhs_fn f, void *ctx, cdpr_real_t t,
                           const cdpr_real_t *restrict y, cdpr_real_t h,
                           cdpr_real_t *restrict y_out, cdpr_real_t *err, int have_k1)
{
    const int n = s->dim;
    cdpr_real_t *restrict k1 = slot(s, K1);
    cdpr_real_t *restrict k2 = slot(s, K2);
    cdpr_real_t *restrict k3 = slot(s, K3);
    cdpr_real_t *restrict k4 = slot(s, K4);
    cdpr_real_t *restrict k5 = slot(s, K5);
    cdpr_real_t *restrict k6 = slot(s, K6);
    cdpr_real_t *restrict yt = slot(s, YTMP);

    if (have_k1 == 0) {
        CDPR_TRY(eval(s, f, ctx, t, y, k1));
    }
    for (int i = 0; i < n; ++i) {
        yt[i] = y[i] + h * (A21 * k1[i]);
    }
    CDPR_TRY(eval(s, f, ctx, t + C2 * h, yt, k2));
    for (int i = 0; i < n; ++i) {
        yt[i] = y[i] + h * (A31 * k1[i] + A32 * k2[i]);
    }
    CDPR_TRY(eval(s, f, ctx, t + C3 * h, yt, k3));
    for (int i = 0; i < n; ++i) {
        yt[i] = y[i] + h * (A41 * k1[i] + A42 * k2[i] + A43 * k3[i]);
    }
    CDPR_TRY(eval(s, f, ctx, t + C4 * h, yt, k4));
    for (int i = 0; i < n; ++i) {
        yt[i] = y[i] + h * (A51 * k1[i] + A52 * k2[i] + A53 * k3[i] + A54 * k4[i]);
    }
    CDPR_TRY(eval(s, f, ctx, t + C5 * h, yt, k5));
    for (int i = 0; i < n; ++i) {
        yt[i] = y[i] + h * (A61 * k1[i] + A62 * k2[i] + A63 * k3[i] + A64 * k4[i] + A65 * k5[i]);
    }
    CDPR_TRY(eval(s, f, ctx, t + C6 * h, yt, k6));

    /* New state, error estimate, weighted max-norm and finiteness in one pass. */
    const cdpr_real_t rtol = s->p.step.rtol;
    const cdpr_real_t *av = s->p.step.atol_vec;
    const cdpr_real_t atol = s->p.step.atol;
    cdpr_real_t emax = CDPR_R(0.0);
    int bad = 0;
    for (int i = 0; i < n; ++i) {
        const cdpr_real_t yn =
            y[i] + h * (B1 * k1[i] + B3 * k3[i] + B4 * k4[i] + B5 * k5[i] + B6 * k6[i]);
        const cdpr_real_t e = h * (E1 * k1[i] + E3 * k3[i] + E4 * k4[i] + E5 * k5[i] + E6 * k6[i]);
        const cdpr_real_t ay = CDPR_FABS(y[i]);
        const cdpr_real_t an = CDPR_FABS(yn);
        const cdpr_real_t sc = ((av != NULL) ? av[i] : atol) + rtol * ((ay > an) ? ay : an);
        const cdpr_real_t r = CDPR_FABS(e) / sc;
        bad |= !isfinite(yn);
        if (!(r <= emax)) {
            emax = r; /* also propagates NaN */
        }
        y_out[i] = yn;
    }
    if (bad != 0 || !isfinite(emax)) {
        emax = (cdpr_real_t)INFINITY;
    }
    s->last_err = emax;
    if (err != NULL) {
        *err = emax;
    }
    return CDPR_OK;
}

cdpr_status_t cdpr_rkf45_trial(cdpr_rkf45_t *s, cdpr_rhs_fn f, void *ctx, cdpr_real_t t,
                               const cdpr_real_t *y, cdpr_real_t h, cdpr_real_t *y_out,
                               cdpr_real_t *err)
{
    return trial(s, f, ctx, t, y, h, y_out, err, 0);
}

/* Step-size factor from the error norm (error ~ h^5 for the embedded 4th-order estimate). */
static cdpr_real_t rk_factor(const cdpr_rkf45_t *s, cdpr_real_t err)
{
    return step_factor(&s->p.step, err, CDPR_R(-0.2));
}

/* Step-size factor after an accepted step. Elementary controller (the same bits as
 * step_factor) unless pi_beta > 0: then Gustafsson's PI controller in the form of Hairer's
 * DOPRI5, fac = safety err^-(1/5 - 0.75 beta) err_prev^beta, with err_prev the error norm of
 * the previous accepted step (at least 1e-4); err_prev is updated here. */
static cdpr_real_t accept_factor(cdpr_rkf45_t *s, cdpr_real_t err)
{
    cdpr_real_t fac;
    if (!(s->p.pi_beta > CDPR_R(0.0))) {
        fac = rk_factor(s, err);
    } else {
        const cdpr_real_t beta = s->p.pi_beta;
        const cdpr_real_t e = (err > CDPR_R(1e-4)) ? err : CDPR_R(1e-4);
        const cdpr_real_t expo = CDPR_R(0.2) - (CDPR_R(0.75) * beta);
        const cdpr_real_t raw =
            (s->p.step.safety * CDPR_POW(e, -expo)) * CDPR_POW(s->err_prev, beta);
        s->err_prev = e;
        fac = step_clamp(raw, s->p.step.shrink_min, s->p.step.grow_max);
    }
    return fac;
}

/* Classify a trial that produced NaN/Inf: if the starting point itself is not finite (or
 * f(t, y) is not), no smaller step can help. */
static int start_is_bad(const cdpr_rkf45_t *s, const cdpr_real_t *y)
{
    return (step_all_finite(y, s->dim) == 0) || (step_all_finite(slot(s, K1), s->dim) == 0);
}

/* Record a step of size h accepted by the error test (rkf45.h, h_ok_s): it replaces h_ok_s
 * when `replace`, otherwise it can only raise it. */
static void note_accepted(cdpr_rkf45_t *s, cdpr_real_t h, int replace)
{
    if (replace != 0 || h > s->h_ok_s) {
        s->h_ok_s = h;
    }
}

cdpr_status_t cdpr_rkf45_step(cdpr_rkf45_t *s, cdpr_rhs_fn f, void *ctx, cdpr_real_t *t,
                              cdpr_real_t *y, cdpr_real_t t_end)
{
    if (s == NULL || f == NULL || t == NULL || y == NULL || !isfinite(*t) || !isfinite(t_end) ||
        !(t_end > *t)) {
        return CDPR_E_INVALID_ARG;
    }
    cdpr_real_t *yn = slot(s, YNEW);
    int have_k1 = 0;
    /* Bounded: every rejection multiplies h by at most `safety` < 1, and h_min ends it. */
    for (;;) {
        const cdpr_real_t remaining = t_end - *t;
        cdpr_real_t h = step_bounded(&s->p.step, s->h_s);
        const int last = (h >= remaining) ? 1 : 0;
        if (last != 0) {
            h = remaining;
        }
        cdpr_real_t err = CDPR_R(0.0);
        if (trial(s, f, ctx, *t, y, h, yn, &err, have_k1) != CDPR_OK) {
            s->stats.failures++;
            return CDPR_E_RHS;
        }
        have_k1 = 1; /* a retry starts from the same (t, y) */
        if (!isfinite(err)) {
            if (start_is_bad(s, y) != 0) {
                s->stats.failures++;
                return CDPR_E_STATE_NOT_FINITE;
            }
            s->stats.nonfinite_rejected++;
            s->h_s = h * s->p.step.shrink_min;
        } else if (err <= CDPR_R(1.0)) {
            step_copy(y, yn, s->dim);
            *t = (last != 0) ? t_end : *t + h;
            s->stats.steps_accepted++;
            note_accepted(s, h, !last); /* a step shortened to reach t_end only raises it */
            const cdpr_real_t h_next = step_bounded(&s->p.step, h * accept_factor(s, err));
            /* A step clipped to reach t_end says little about the natural step size. */
            s->h_s = (last != 0 && h_next < s->h_s) ? s->h_s : h_next;
            return CDPR_OK;
        } else {
            s->stats.steps_rejected++;
            s->h_s = h * rk_factor(s, err);
        }
        if (s->h_s < s->p.step.h_min_s) {
            s->h_s = s->p.step.h_min_s;
            if (h <= s->p.step.h_min_s) {
                s->stats.failures++;
                return CDPR_E_STEP_TOO_SMALL;
            }
        }
    }
}

/* Next step size after a rejected trial of size h: h * factor. An equal step of advance was
 * not the controller's choice (it is usually longer than h_s): its rejection must not raise
 * h_s. */
static cdpr_real_t shrink_after(const cdpr_rkf45_t *s, cdpr_real_t h, cdpr_real_t factor, int equal)
{
    const cdpr_real_t h_next = h * factor;
    return (equal != 0 && s->h_s < h_next) ? s->h_s : h_next;
}

/* Progress of one cdpr_rkf45_advance call. */
typedef struct {
    cdpr_real_t t0;      /* time at entry */
    cdpr_real_t t_end;   /* t0 + dt */
    cdpr_real_t h_saved; /* s->h_s at entry */
    cdpr_real_t tc;      /* time reached by the accepted steps */
    int trials;          /* trials spent */
    int have_k1;         /* slot K1 holds f(tc, y) */
    int equal;           /* 1: the rest is covered by equal steps, one per trial left */
    int retry;           /* this call repeats one that returned CDPR_E_SUBSTEP_LIMIT */
    int fresh;           /* the next step of the controller's own size resets h_ok_s */
    int missed;          /* forced steps taken */
} advance_t;

/* Size of the next trial of advance with `budget` >= 1 trials left for `remaining`: the
 * controller's step, or remaining / budget once equal steps are due (a->equal then stays set).
 * *last: the trial ends the interval (h = remaining). O(budget), no RHS calls. */
static cdpr_real_t advance_plan(const cdpr_rkf45_t *s, advance_t *a, int budget,
                                cdpr_real_t remaining, int *last)
{
    cdpr_real_t h = step_bounded(&s->p.step, s->h_s);
    const cdpr_real_t h_eq = remaining / (cdpr_real_t)budget;
    if (a->equal == 0) {
        /* Equal steps when the adaptive ones no longer fit even growing at grow_max, or,
         * when repeating an interval, as soon as one more rejection would make them
         * larger than h_ok_s (h_ok_s only grows during a repeat). */
        const int last_chance = (a->retry != 0 && h_eq <= s->h_ok_s &&
                                 (budget == 1 || remaining / (cdpr_real_t)(budget - 1) > s->h_ok_s))
                                    ? 1
                                    : 0;
        if (budget == 1 || last_chance != 0 ||
            step_can_reach(&s->p.step, h, budget, remaining) == 0) {
            a->equal = 1;
        }
    }
    if (a->equal != 0) {
        h = h_eq;
    }
    /* Do not leave a sliver much shorter than the step: take the rest now. */
    *last = (h >= remaining * CDPR_R(0.999)) ? 1 : 0;
    if (*last != 0) {
        h = remaining;
    }
    return h;
}

/* Accept a trial of size h with error norm err (a forced step when err > 1): y takes the new
 * state yn, a->tc advances, h_ok_s and h_s are updated. O(dim). */
static void advance_accept(cdpr_rkf45_t *s, advance_t *a, cdpr_real_t *y, const cdpr_real_t *yn,
                           cdpr_real_t h, int last, cdpr_real_t err)
{
    step_copy(y, yn, s->dim);
    a->have_k1 = 0;
    a->tc = (last != 0) ? a->t_end : a->tc + h;
    s->stats.steps_accepted++;
    if (err > CDPR_R(1.0)) {
        s->stats.forced_steps++;
        a->missed++;
    } else {
        /* A step shortened to reach t_end or an equal step is not the controller's
         * choice: it only raises h_ok_s. */
        const int own = (last == 0 && a->equal == 0) ? 1 : 0;
        note_accepted(s, h, a->fresh & own);
        a->fresh &= !own;
    }
    const cdpr_real_t h_next = step_bounded(&s->p.step, h * accept_factor(s, err));
    s->h_s = (last != 0 && h_next < s->h_s) ? s->h_s : h_next;
}

/* Act on a trial of size h from (a->tc, y) with error norm err and new state yn: accept it
 * (y and a->tc advance) or reject it (h_s shrinks). CDPR_OK to go on, else the error that ends
 * the call: CDPR_E_STATE_NOT_FINITE, CDPR_E_STEP_TOO_SMALL, or CDPR_E_SUBSTEP_LIMIT (an
 * equal step refused). O(dim). */
static cdpr_status_t advance_judge(cdpr_rkf45_t *s, advance_t *a, cdpr_real_t *y,
                                   const cdpr_real_t *yn, cdpr_real_t h, int last, cdpr_real_t err)
{
    cdpr_status_t st = CDPR_OK;
    if (!isfinite(err)) {
        if (start_is_bad(s, y) != 0) {
            st = CDPR_E_STATE_NOT_FINITE;
        } else {
            s->stats.nonfinite_rejected++;
            s->h_s = shrink_after(s, h, s->p.step.shrink_min, a->equal);
        }
    } else if (err <= CDPR_R(1.0) || (a->equal != 0 && err <= s->p.step.force_err_max)) {
        /* An equal step that misses the tolerance is accepted ("forced") only within
         * force_err_max: a mode that the step amplifies is refused as soon as its share of
         * the error estimate reaches that bound, whatever the budget. */
        advance_accept(s, a, y, yn, h, last, err);
    } else {
        s->stats.steps_rejected++;
        s->h_s = shrink_after(s, h, rk_factor(s, err), a->equal);
    }
    if ((st == CDPR_OK) && (s->h_s < s->p.step.h_min_s)) {
        if (h <= s->p.step.h_min_s) {
            st = CDPR_E_STEP_TOO_SMALL;
        } else {
            s->h_s = s->p.step.h_min_s;
        }
    }
    if ((st == CDPR_OK) && (a->equal != 0) && (a->have_k1 != 0)) {
        /* An equal step was refused (have_k1: not accepted): the rest cannot be covered
         * within the budget. Give up now rather than spend the other trials. */
        st = CDPR_E_SUBSTEP_LIMIT;
    }
    return st;
}

/* End of an advance call with loop status st: on an error, y and *t are restored from the
 * backup; on success *t = t_end and a forced step turns CDPR_OK into CDPR_WARN_SUBSTEP_LIMIT.
 * O(dim). */
static cdpr_status_t advance_finish(cdpr_rkf45_t *s, const advance_t *a, cdpr_status_t st,
                                    cdpr_real_t *t, cdpr_real_t *y)
{
    if (st < 0) {
        step_copy(y, slot(s, YBAK), s->dim);
        *t = a->t0;
        if (st == CDPR_E_SUBSTEP_LIMIT) {
            /* Keep h_s and h_ok_s as learned: the next call starts from them instead of
             * repeating the same rejections, and plans its equal steps early (retry). */
            s->retry = 1;
            s->stats.substep_limit_failures++;
        } else {
            s->h_s = (s->h_s < a->h_saved) ? s->h_s : a->h_saved;
        }
        s->stats.failures++;
        return st;
    }
    *t = a->t_end;
    s->retry = 0;
    if (a->missed != 0) {
        s->stats.substep_limit_hits++;
        return CDPR_WARN_SUBSTEP_LIMIT;
    }
    return CDPR_OK;
}

cdpr_status_t cdpr_rkf45_advance(cdpr_rkf45_t *s, cdpr_rhs_fn f, void *ctx, cdpr_real_t *t,
                                 cdpr_real_t *y, cdpr_real_t dt, int max_trials)
{
    if (s == NULL || f == NULL || t == NULL || y == NULL || !isfinite(*t) || !isfinite(dt) ||
        !(dt > CDPR_R(0.0)) || max_trials < 1) {
        return CDPR_E_INVALID_ARG;
    }
    if (step_all_finite(y, s->dim) == 0) {
        s->stats.failures++;
        return CDPR_E_STATE_NOT_FINITE;
    }
    cdpr_real_t *yn = slot(s, YNEW);
    advance_t a;
    a.t0 = *t;
    a.t_end = a.t0 + dt;
    a.h_saved = s->h_s;
    a.tc = a.t0;
    a.trials = 0;
    a.have_k1 = 0;
    a.equal = 0;
    a.retry = s->retry;
    a.fresh = !a.retry;
    a.missed = 0;
    step_copy(slot(s, YBAK), y, s->dim);

    cdpr_status_t st = CDPR_OK;
    while ((st == CDPR_OK) && (a.tc < a.t_end)) {
        const cdpr_real_t remaining = a.t_end - a.tc;
        const int budget = max_trials - a.trials;
        if (budget < 1) {
            st = CDPR_E_SUBSTEP_LIMIT; /* not reached: the last trial is always an equal step */
        } else {
            int last = 0;
            const cdpr_real_t h = advance_plan(s, &a, budget, remaining, &last);
            cdpr_real_t err = CDPR_R(0.0);
            a.trials++;
            if (trial(s, f, ctx, a.tc, y, h, yn, &err, a.have_k1) != CDPR_OK) {
                st = CDPR_E_RHS;
            } else {
                a.have_k1 = 1; /* until a step is accepted, the next trial starts from here */
                st = advance_judge(s, &a, y, yn, h, last, err);
            }
        }
    }
    return advance_finish(s, &a, st, t, y);
}
