/* SPDX-License-Identifier: BSD-3-Clause */
/// @file gsl_ref.c
/// GSL odeiv2 rkf45 on a cdpr RHS: adapter, reference integration, preallocated stepper.
/// Host only (GSL is GPL-3); see gsl_ref.h.
#include "cdpr/gsl/ref.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_errno.h>

int cdpr_gsl_rhs_eval(double t, const double y[], double dydt[], void *params)
{
    cdpr_gsl_adapter_t *a = (cdpr_gsl_adapter_t *)params;
    a->rhs_evals++;
    const cdpr_status_t st = a->f(t, y, dydt, a->ctx);
    if (st < 0) {
        a->last_error = st;
        return GSL_EBADFUNC;
    }
    return GSL_SUCCESS;
}

gsl_odeiv2_system cdpr_gsl_system(cdpr_gsl_adapter_t *a, cdpr_rhs_fn f, void *ctx, size_t dim)
{
    a->f = f;
    a->ctx = ctx;
    a->rhs_evals = 0;
    a->last_error = CDPR_OK;
    gsl_odeiv2_system sys;
    sys.function = cdpr_gsl_rhs_eval;
    sys.jacobian = NULL; /* rkf45 is explicit */
    sys.dimension = dim;
    sys.params = a;
    return sys;
}

void cdpr_gsl_error_handler_off(void)
{
    /* Not synchronised: the first call should come from one thread (the write is idempotent,
     * so a race only repeats it). */
    static int done = 0;
    if (done == 0) {
        (void)gsl_set_error_handler_off();
        done = 1;
    }
}

static int all_finite(const double *v, size_t n)
{
    for (size_t i = 0; i < n; ++i) {
        if (!isfinite(v[i])) {
            return 0;
        }
    }
    return 1;
}

/* GSL status of a step (after the adapter saw f) -> cdpr status. */
static cdpr_status_t map_status(int gsl_status)
{
    switch (gsl_status) {
    case GSL_SUCCESS:
        return CDPR_OK;
    case GSL_EBADFUNC:
        return CDPR_E_RHS;
    case GSL_EINVAL:
    case GSL_EFAULT:
        return CDPR_E_INVALID_ARG;
    default:
        /* GSL_FAILURE / GSL_ENOPROG: the step size could not be reduced any further. */
        return CDPR_E_STEP_TOO_SMALL;
    }
}

/* Standard y-control: D_i = atol_i + rtol |y_i| (a_y = 1, a_dydt = 0), per-component atol
 * through the scaled variant. NULL when allocation fails. */
static gsl_odeiv2_control *control_new(double rtol, double atol, const double *atol_vec, size_t dim)
{
    if (atol_vec != NULL) {
        return gsl_odeiv2_control_scaled_new(1.0, rtol, 1.0, 0.0, atol_vec, dim);
    }
    return gsl_odeiv2_control_y_new(atol, rtol);
}

static int tolerances_ok(double rtol, double atol, const double *atol_vec, size_t dim)
{
    if (!isfinite(rtol) || rtol < 0.0) {
        return 0;
    }
    if (atol_vec == NULL) {
        return (isfinite(atol) && atol > 0.0) ? 1 : 0;
    }
    for (size_t i = 0; i < dim; ++i) {
        if (!isfinite(atol_vec[i]) || !(atol_vec[i] > 0.0)) {
            return 0;
        }
    }
    return 1;
}

cdpr_status_t cdpr_gsl_integrate(cdpr_rhs_fn f, void *ctx, size_t dim, double *y, double t0,
                                 double t1, double rtol, double atol, const double *atol_vec,
                                 double h0, unsigned long max_steps, cdpr_gsl_stats_t *stats)
{
    if (f == NULL || y == NULL || dim == 0 || !isfinite(t0) || !isfinite(t1) || !(t1 > t0) ||
        !isfinite(h0) || !(h0 > 0.0) || max_steps == 0 ||
        tolerances_ok(rtol, atol, atol_vec, dim) == 0) {
        return CDPR_E_INVALID_ARG;
    }
    if (stats != NULL) {
        stats->steps_accepted = 0;
        stats->steps_rejected = 0;
        stats->rhs_evals = 0;
        stats->h_next_s = h0;
    }
    if (all_finite(y, dim) == 0) {
        return CDPR_E_NOT_FINITE;
    }
    cdpr_gsl_error_handler_off();

    /* Allocation: GSL objects and the backup that makes the call transactional. */
    gsl_odeiv2_step *step = gsl_odeiv2_step_alloc(gsl_odeiv2_step_rkf45, dim);
    gsl_odeiv2_control *con = control_new(rtol, atol, atol_vec, dim);
    gsl_odeiv2_evolve *ev = gsl_odeiv2_evolve_alloc(dim);
    double *backup = (double *)malloc(dim * sizeof(double));
    cdpr_status_t st = CDPR_OK;
    if (step == NULL || con == NULL || ev == NULL || backup == NULL) {
        st = CDPR_E_CAPACITY;
    } else {
        cdpr_gsl_adapter_t adapter;
        unsigned long accepted = 0;
        double h = h0;
        memcpy(backup, y, dim * sizeof(double));
        const gsl_odeiv2_system sys = cdpr_gsl_system(&adapter, f, ctx, dim);
        double t = t0;
        /* Bounded: each iteration is one accepted step (GSL retries rejected trials inside
         * evolve_apply until the step is accepted or h reaches round-off). */
        while (t < t1) {
            if (accepted >= max_steps) {
                st = CDPR_E_NO_CONVERGENCE;
                break;
            }
            const int gs = gsl_odeiv2_evolve_apply(ev, con, step, &sys, &t, t1, &h, y);
            if (gs != GSL_SUCCESS) {
                st = map_status(gs);
                break;
            }
            accepted++;
        }
        if (st == CDPR_OK && all_finite(y, dim) == 0) {
            st = CDPR_E_STATE_NOT_FINITE;
        }
        if (st != CDPR_OK) {
            memcpy(y, backup, dim * sizeof(double));
        }
        if (stats != NULL) {
            stats->steps_accepted = accepted;
            stats->steps_rejected = ev->failed_steps;
            stats->rhs_evals = adapter.rhs_evals;
            stats->h_next_s = h;
        }
    }
    free(backup);
    if (ev != NULL) {
        gsl_odeiv2_evolve_free(ev);
    }
    if (con != NULL) {
        gsl_odeiv2_control_free(con);
    }
    if (step != NULL) {
        gsl_odeiv2_step_free(step);
    }
    return st;
}

cdpr_status_t cdpr_gsl_stepper_init(cdpr_gsl_stepper_t *s, cdpr_rhs_fn f, void *ctx, size_t dim,
                                    double rtol, double atol)
{
    if (s == NULL) {
        return CDPR_E_INVALID_ARG;
    }
    memset(s, 0, sizeof(*s));
    if (f == NULL || dim == 0 || tolerances_ok(rtol, atol, NULL, dim) == 0) {
        return CDPR_E_INVALID_ARG;
    }
    cdpr_gsl_error_handler_off();
    s->step = gsl_odeiv2_step_alloc(gsl_odeiv2_step_rkf45, dim);
    s->control = control_new(rtol, atol, NULL, dim);
    s->evolve = gsl_odeiv2_evolve_alloc(dim);
    s->yerr = (double *)malloc(dim * sizeof(double));
    if (s->step == NULL || s->control == NULL || s->evolve == NULL || s->yerr == NULL) {
        cdpr_gsl_stepper_free(s);
        return CDPR_E_CAPACITY;
    }
    s->sys = cdpr_gsl_system(&s->adapter, f, ctx, dim);
    s->dim = dim;
    return CDPR_OK;
}

void cdpr_gsl_stepper_free(cdpr_gsl_stepper_t *s)
{
    if (s == NULL) {
        return;
    }
    if (s->evolve != NULL) {
        gsl_odeiv2_evolve_free(s->evolve);
    }
    if (s->control != NULL) {
        gsl_odeiv2_control_free(s->control);
    }
    if (s->step != NULL) {
        gsl_odeiv2_step_free(s->step);
    }
    free(s->yerr);
    memset(s, 0, sizeof(*s));
}

cdpr_status_t cdpr_gsl_stepper_apply(cdpr_gsl_stepper_t *s, double t, double h, double *y)
{
    if (s == NULL || s->step == NULL || y == NULL) {
        return CDPR_E_INVALID_ARG;
    }
    /* dydt_in = dydt_out = NULL: GSL's rkf45 then evaluates k1 itself and skips the derivative
     * at the end, 6 calls of f in all. */
    const int gs = gsl_odeiv2_step_apply(s->step, t, h, y, s->yerr, NULL, NULL, &s->sys);
    return map_status(gs);
}

cdpr_status_t cdpr_gsl_stepper_evolve(cdpr_gsl_stepper_t *s, double *t, double t1, double *h,
                                      double *y)
{
    if (s == NULL || s->evolve == NULL || t == NULL || h == NULL || y == NULL) {
        return CDPR_E_INVALID_ARG;
    }
    const double t_start = *t;
    const int gs = gsl_odeiv2_evolve_apply(s->evolve, s->control, s->step, &s->sys, t, t1, h, y);
    if (gs != GSL_SUCCESS) {
        /* GSL restores y itself, but may leave *t at the end of a rejected trial. */
        *t = t_start;
        return map_status(gs);
    }
    return CDPR_OK;
}

void cdpr_gsl_stepper_reset(cdpr_gsl_stepper_t *s)
{
    if (s != NULL && s->evolve != NULL) {
        (void)gsl_odeiv2_evolve_reset(s->evolve);
    }
}
