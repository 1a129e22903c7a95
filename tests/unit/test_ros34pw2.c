/* SPDX-License-Identifier: BSD-3-Clause */
/// @file test_ros34pw2.c
/// The ROS34PW2 Rosenbrock-W integrator (ros34pw2.h, docs/model.md §7) against closed forms:
/// a damped oscillator, a stiff Prothero-Robinson system, the observed order with the exact,
/// a scaled and a zero Jacobian (the W-method property), L-stability on y' = lambda y, and its
/// transactional failure paths (singular W, NaN, refusing RHS), bounds, allocation and
/// determinism. The linear algebra of the tests is a small dense LU with partial pivoting
/// written here, on a Jacobian supplied per problem.
#include "unity.h"

#include "alloc_count.h"
#include "cdpr/ros34pw2.h"
#include "test_real.h"

#include <math.h>
#include <stddef.h>
#include <string.h>

#define DIM_MAX 4

static cdpr_real_t work[CDPR_ROS_WORK_PER_DIM * DIM_MAX];
static cdpr_ros_t solver;

void setUp(void)
{
    memset(work, 0, sizeof work);
    memset(&solver, 0, sizeof solver);
}

void tearDown(void) {}

/* ---------------------------------------------------------------- dense W for the tests */

typedef void (*jac_fn)(cdpr_real_t t, const cdpr_real_t *y, double *J, const void *prob);

typedef struct {
    int n;
    jac_fn jac;       /* exact Jacobian (row-major n x n), or NULL for J = 0 */
    double jac_scale; /* J used = jac_scale * exact (W-method tests) */
    const void *prob; /* problem constants for jac */
    double lu[DIM_MAX * DIM_MAX];
    int piv[DIM_MAX];
    int fail_factor_at; /* factor call number that refuses (0: never) */
    int factor_calls;
    int fail_solve_at; /* solve call number that refuses (0: never) */
    int solve_calls;
} dense_t;

static cdpr_status_t dense_factor(void *ctx, cdpr_real_t t, const cdpr_real_t *y,
                                  cdpr_real_t gamma_h)
{
    dense_t *d = ctx;
    const int n = d->n;
    double J[DIM_MAX * DIM_MAX] = {0.0};
    d->factor_calls++;
    if (d->fail_factor_at != 0 && d->factor_calls >= d->fail_factor_at) {
        return CDPR_E_SINGULAR;
    }
    if (d->jac != NULL) {
        d->jac(t, y, J, d->prob);
    }
    for (int i = 0; i < n; ++i) {
        for (int j = 0; j < n; ++j) {
            d->lu[i * n + j] =
                ((i == j) ? 1.0 : 0.0) - (double)gamma_h * d->jac_scale * J[i * n + j];
        }
    }
    for (int k = 0; k < n; ++k) {
        int p = k;
        for (int i = k + 1; i < n; ++i) {
            if (fabs(d->lu[i * n + k]) > fabs(d->lu[p * n + k])) {
                p = i;
            }
        }
        d->piv[k] = p;
        if (!(fabs(d->lu[p * n + k]) > 0.0) || !isfinite(d->lu[p * n + k])) {
            return CDPR_E_SINGULAR;
        }
        for (int j = 0; j < n; ++j) {
            const double tmp = d->lu[k * n + j];
            d->lu[k * n + j] = d->lu[p * n + j];
            d->lu[p * n + j] = tmp;
        }
        for (int i = k + 1; i < n; ++i) {
            const double l = d->lu[i * n + k] / d->lu[k * n + k];
            d->lu[i * n + k] = l;
            for (int j = k + 1; j < n; ++j) {
                d->lu[i * n + j] -= l * d->lu[k * n + j];
            }
        }
    }
    return CDPR_OK;
}

static cdpr_status_t dense_solve(void *ctx, const cdpr_real_t *b, cdpr_real_t *x)
{
    dense_t *d = ctx;
    const int n = d->n;
    double z[DIM_MAX];
    d->solve_calls++;
    if (d->fail_solve_at != 0 && d->solve_calls >= d->fail_solve_at) {
        return CDPR_E_SINGULAR;
    }
    for (int i = 0; i < n; ++i) {
        z[i] = (double)b[i];
    }
    for (int k = 0; k < n; ++k) {
        const double tmp = z[k];
        z[k] = z[d->piv[k]];
        z[d->piv[k]] = tmp;
        for (int i = k + 1; i < n; ++i) {
            z[i] -= d->lu[i * n + k] * z[k];
        }
    }
    for (int i = n - 1; i >= 0; --i) {
        for (int j = i + 1; j < n; ++j) {
            z[i] -= d->lu[i * n + j] * z[j];
        }
        z[i] /= d->lu[i * n + i];
    }
    for (int i = 0; i < n; ++i) {
        x[i] = (cdpr_real_t)z[i];
    }
    return CDPR_OK;
}

static cdpr_ros_problem_t problem(cdpr_rhs_fn f, void *f_ctx, dense_t *d)
{
    cdpr_ros_problem_t pb;
    pb.f = f;
    pb.f_ctx = f_ctx;
    pb.factor = dense_factor;
    pb.solve = dense_solve;
    pb.lin_ctx = d;
    return pb;
}

static dense_t dense(int n, jac_fn jac, double scale, const void *prob)
{
    dense_t d;
    memset(&d, 0, sizeof d);
    d.n = n;
    d.jac = jac;
    d.jac_scale = scale;
    d.prob = prob;
    return d;
}

static void init_solver(const cdpr_ros_params_t *p, int dim)
{
    cdpr_diag_t d;
    const cdpr_status_t st =
        cdpr_ros_init(&solver, p, work, (int)(sizeof work / sizeof work[0]), DIM_MAX, dim, &d);
    TEST_ASSERT_EQUAL_INT_MESSAGE(CDPR_OK, st, d.field);
}

static cdpr_ros_params_t params_tol(double tol)
{
    cdpr_ros_params_t p;
    cdpr_ros_params_default(&p);
    p.step.rtol = (cdpr_real_t)tol;
    p.step.atol = (cdpr_real_t)tol;
    return p;
}

/* ---------------------------------------------------------------- test problems */

/* Damped oscillator x'' + 2 zeta w x' + w^2 x = 0, x(0) = 1, v(0) = 0. */
typedef struct {
    double w;
    double zeta;
} osc_t;

static cdpr_status_t rhs_osc(cdpr_real_t t, const cdpr_real_t *y, cdpr_real_t *dydt, void *ctx)
{
    const osc_t *o = ctx;
    (void)t;
    dydt[0] = y[1];
    dydt[1] = (cdpr_real_t)(-o->w * o->w * (double)y[0] - 2.0 * o->zeta * o->w * (double)y[1]);
    return CDPR_OK;
}

static void jac_osc(cdpr_real_t t, const cdpr_real_t *y, double *J, const void *prob)
{
    const osc_t *o = prob;
    (void)t;
    (void)y;
    J[0] = 0.0;
    J[1] = 1.0;
    J[2] = -o->w * o->w;
    J[3] = -2.0 * o->zeta * o->w;
}

/* Closed form of the underdamped oscillator. */
static void osc_exact(const osc_t *o, double t, double *x, double *v)
{
    const double wd = o->w * sqrt(1.0 - o->zeta * o->zeta);
    const double s = o->zeta * o->w;
    const double e = exp(-s * t);
    *x = e * (cos(wd * t) + (s / wd) * sin(wd * t));
    *v = -e * (o->w * o->w / wd) * sin(wd * t);
}

/* Prothero-Robinson pair: y1' = -y1 (y1 = e^-t); y2' = -L (y2 - cos t) - sin t
 * (y2 = cos t + (y2(0) - 1) e^{-L t}). */
static cdpr_status_t rhs_pr(cdpr_real_t t, const cdpr_real_t *y, cdpr_real_t *dydt, void *ctx)
{
    const double L = *(const double *)ctx;
    dydt[0] = -y[0];
    dydt[1] = (cdpr_real_t)(-L * ((double)y[1] - cos((double)t)) - sin((double)t));
    return CDPR_OK;
}

static void jac_pr(cdpr_real_t t, const cdpr_real_t *y, double *J, const void *prob)
{
    (void)t;
    (void)y;
    J[0] = -1.0;
    J[1] = 0.0;
    J[2] = 0.0;
    J[3] = -*(const double *)prob;
}

/* Nonlinear: y1' = -y1^2 (y1 = 1/(1+t)), y2' = y1 (y2 = ln(1+t)), y3' = -y3 + y1 y2... kept
 * to the first two, whose closed forms are exact. */
static cdpr_status_t rhs_nl(cdpr_real_t t, const cdpr_real_t *y, cdpr_real_t *dydt, void *ctx)
{
    (void)t;
    (void)ctx;
    dydt[0] = -y[0] * y[0];
    dydt[1] = y[0];
    return CDPR_OK;
}

static void jac_nl(cdpr_real_t t, const cdpr_real_t *y, double *J, const void *prob)
{
    (void)t;
    (void)prob;
    J[0] = -2.0 * (double)y[0];
    J[1] = 0.0;
    J[2] = 1.0;
    J[3] = 0.0;
}

/* Non-autonomous and smooth: y' = cos(t) y (y = exp(sin t)); df/dt is dropped by the method
 * (W-method), which must keep order 3. */
static cdpr_status_t rhs_na(cdpr_real_t t, const cdpr_real_t *y, cdpr_real_t *dydt, void *ctx)
{
    (void)ctx;
    dydt[0] = (cdpr_real_t)(cos((double)t) * (double)y[0]);
    return CDPR_OK;
}

static void jac_na(cdpr_real_t t, const cdpr_real_t *y, double *J, const void *prob)
{
    (void)y;
    (void)prob;
    J[0] = cos((double)t);
}

static cdpr_status_t rhs_lin(cdpr_real_t t, const cdpr_real_t *y, cdpr_real_t *dydt, void *ctx)
{
    (void)t;
    dydt[0] = (cdpr_real_t)(*(const double *)ctx * (double)y[0]);
    return CDPR_OK;
}

static void jac_lin(cdpr_real_t t, const cdpr_real_t *y, double *J, const void *prob)
{
    (void)t;
    (void)y;
    J[0] = *(const double *)prob;
}

/* ---------------------------------------------------------------- accuracy */

/* Adaptive steps over [0, 10] of the oscillator (w = 2 pi, zeta = 0.05): the max error over
 * the accepted steps shrinks with the tolerance and stays within 100 tol (the local-error
 * control does not bound the global error; 100 is the margin for 10 periods). */
static void test_damped_oscillator_against_closed_form(void)
{
    const osc_t o = {2.0 * 3.14159265358979323846, 0.05};
    const double tols[2] = {TOL(1e-6, 1e-4), TOL(1e-9, 1e-5)};
    double emax[2] = {0.0, 0.0};
    unsigned long steps[2] = {0, 0};
    for (int k = 0; k < 2; ++k) {
        dense_t d = dense(2, jac_osc, 1.0, &o);
        const cdpr_ros_problem_t pb = problem(rhs_osc, (void *)&o, &d);
        const cdpr_ros_params_t p = params_tol(tols[k]);
        init_solver(&p, 2);
        cdpr_real_t t = 0.0;
        cdpr_real_t y[2] = {1.0, 0.0};
        while (t < 10.0) {
            TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_ros_step(&solver, &pb, &t, y, 10.0));
            double x, v;
            osc_exact(&o, (double)t, &x, &v);
            const double e = fmax(fabs((double)y[0] - x), fabs((double)y[1] - v) / o.w);
            emax[k] = fmax(emax[k], e);
        }
        steps[k] = solver.stats.steps_accepted;
        TEST_ASSERT_EQUAL_UINT(solver.lin.factorisations,
                               solver.stats.steps_accepted + solver.stats.steps_rejected);
        TEST_ASSERT_EQUAL_UINT(4UL * solver.lin.factorisations, solver.lin.solves);
        TEST_ASSERT_TRUE(emax[k] < 100.0 * tols[k]);
    }
    TEST_ASSERT_TRUE(emax[1] < emax[0]);
    TEST_ASSERT_TRUE(steps[1] > steps[0]);
}

/* Prothero-Robinson with L = 1e6 from y2(0) = 2 (a fast transient e^{-1e6 t}): the implicit
 * method follows the closed form with steps far beyond the explicit limit 2.8/L. */
static void test_stiff_system_against_closed_form(void)
{
    const double L = 1.0e6;
    dense_t d = dense(2, jac_pr, 1.0, &L);
    const cdpr_ros_problem_t pb = problem(rhs_pr, (void *)&L, &d);
    const double tol = TOL(1e-7, 1e-5);
    const cdpr_ros_params_t p = params_tol(tol);
    init_solver(&p, 2);
    cdpr_real_t t = 0.0;
    cdpr_real_t y[2] = {1.0, 2.0};
    double emax = 0.0;
    while (t < 5.0) {
        TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_ros_step(&solver, &pb, &t, y, 5.0));
        const double td = (double)t;
        emax = fmax(emax, fabs((double)y[0] - exp(-td)));
        emax = fmax(emax, fabs((double)y[1] - (cos(td) + exp(-L * td))));
    }
    /* An explicit method would need > 5 / (2.8e-6) = 1.8e6 steps. */
    TEST_ASSERT_TRUE(solver.stats.steps_accepted < 2000UL);
    TEST_ASSERT_TRUE(emax < 50.0 * tol);
}

/* Fixed steps h = T/N of cdpr_ros_trial from the closed form's initial value; error at T. */
static double fixed_step_error(cdpr_rhs_fn f, void *ctx, dense_t *d, cdpr_real_t *y0, int dim,
                               double T, int N, void (*exact)(double, double *))
{
    const cdpr_ros_problem_t pb = problem(f, ctx, d);
    const cdpr_ros_params_t p = params_tol(1e-6);
    init_solver(&p, dim);
    cdpr_real_t y[DIM_MAX], yn[DIM_MAX];
    for (int i = 0; i < dim; ++i) {
        y[i] = y0[i];
    }
    const double h = T / (double)N;
    for (int k = 0; k < N; ++k) {
        TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_ros_trial(&solver, &pb, (cdpr_real_t)(h * k), y,
                                                      (cdpr_real_t)h, yn, NULL));
        for (int i = 0; i < dim; ++i) {
            y[i] = yn[i];
        }
    }
    double ex[DIM_MAX];
    exact(T, ex);
    double e = 0.0;
    for (int i = 0; i < dim; ++i) {
        e = fmax(e, fabs((double)y[i] - ex[i]));
    }
    return e;
}

static void exact_nl(double t, double *y)
{
    y[0] = 1.0 / (1.0 + t);
    y[1] = log(1.0 + t);
}

static void exact_na(double t, double *y)
{
    y[0] = exp(sin(t));
}

/* The finest pair of levels must show order 3 within 0.15; coarser pairs, still
 * pre-asymptotic (measured: 2.75 at h = 0.2 -> 0.1 with half the Jacobian, 2.96 at
 * 0.05 -> 0.025), only more than 2.6. */
static void check_order(double order, int finest, const char *msg)
{
    if (finest != 0) {
        TEST_ASSERT_TRUE_MESSAGE(fabs(order - 3.0) < 0.15, msg);
    } else {
        TEST_ASSERT_TRUE_MESSAGE(order > 2.6 && order < 3.4, msg);
    }
}

/* Observed order log2(e(h) / e(h/2)) on smooth problems: 3 with the exact Jacobian, with half
 * of it and with none (J = 0: the W-method keeps its order for any W), and on a
 * non-autonomous problem whose df/dt the method drops. */
static void test_observed_order_three_any_jacobian(void)
{
    SKIP_IN_FLOAT("the errors of the fine levels (1e-6..1e-9) are at float's rounding");
    const double scales[3] = {1.0, 0.5, 0.0};
    const int n0 = 10;
    const int nlev = 4;
    for (int s = 0; s < 3; ++s) {
        double e[4];
        for (int l = 0; l < nlev; ++l) {
            dense_t d = dense(2, jac_nl, scales[s], NULL);
            cdpr_real_t y0[2] = {1.0, 0.0};
            e[l] = fixed_step_error(rhs_nl, NULL, &d, y0, 2, 2.0, n0 << l, exact_nl);
        }
        for (int l = 1; l < nlev; ++l) {
            const double order = log2(e[l - 1] / e[l]);
            char msg[64];
            (void)snprintf(msg, sizeof msg, "scale %.1f level %d order %.3f", scales[s], l, order);
            check_order(order, l == nlev - 1, msg);
        }
    }
    double e[4];
    for (int l = 0; l < nlev; ++l) {
        dense_t d = dense(1, jac_na, 1.0, NULL);
        cdpr_real_t y0[1] = {1.0};
        e[l] = fixed_step_error(rhs_na, NULL, &d, y0, 1, 3.0, n0 << l, exact_na);
    }
    for (int l = 1; l < nlev; ++l) {
        const double order = log2(e[l - 1] / e[l]);
        char msg[64];
        (void)snprintf(msg, sizeof msg, "non-autonomous level %d order %.3f", l, order);
        check_order(order, l == nlev - 1, msg);
    }
}

/* L-stability: one step of y' = lambda y, y(0) = 1, h = 1 gives R(z), z = lambda. A-stable:
 * |R| <= 1 on the imaginary axis and the left half-plane samples; L-stable: R(z) -> 0 as
 * z -> -inf, like C/z (|z R(z)| bounded); the embedded solution's |R(inf)| is 0.48, so the
 * error estimate of a huge stiff step is not 0. */
static void test_l_stability(void)
{
    const double zs[5] = {-1e2, -1e4, -1e6, -1e9, -1e12};
    double prev = 1.0;
    for (int k = 0; k < 5; ++k) {
        double lam = zs[k];
        dense_t d = dense(1, jac_lin, 1.0, &lam);
        const cdpr_ros_problem_t pb = problem(rhs_lin, &lam, &d);
        const cdpr_ros_params_t p = params_tol(1e-6);
        init_solver(&p, 1);
        cdpr_real_t y[1] = {1.0}, yn[1];
        cdpr_real_t err = 0.0;
        TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_ros_trial(&solver, &pb, 0.0, y, 1.0, yn, &err));
        /* In float, y_new = y + sum m_i u_i (|u_i| ~ 1) carries ~1e-6 of rounding. */
        const double R = fabs((double)yn[0]);
        const double rnd = TOL(0.0, 1e-6);
        TEST_ASSERT_TRUE(R < prev + rnd);
        TEST_ASSERT_TRUE(R < 10.0 / fabs(zs[k]) + rnd);
        prev = R;
        /* err = |y - yhat| / (atol + rtol max(|y|, |ynew|)) with |yhat| -> 0.478. */
        if (k >= 2) {
            TEST_ASSERT_DOUBLE_WITHIN(0.01, 0.478, (double)err * (1e-6 + 1e-6));
        }
    }
    TEST_ASSERT_TRUE(prev < TOL(1e-11, 2e-6));
    /* Purely imaginary z = i w h (oscillator without damping, one step h = 1): |R| <= 1. */
    const double ws[4] = {0.5, 2.0, 50.0, 1e4};
    for (int k = 0; k < 4; ++k) {
        const osc_t o = {ws[k], 0.0};
        dense_t d = dense(2, jac_osc, 1.0, &o);
        const cdpr_ros_problem_t pb = problem(rhs_osc, (void *)&o, &d);
        const cdpr_ros_params_t p = params_tol(1e-6);
        init_solver(&p, 2);
        cdpr_real_t y[2] = {1.0, 0.0}, yn[2];
        TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_ros_trial(&solver, &pb, 0.0, y, 1.0, yn, NULL));
        const double energy =
            (double)yn[0] * (double)yn[0] + (double)yn[1] * (double)yn[1] / (ws[k] * ws[k]);
        TEST_ASSERT_TRUE(energy <= 1.0 + 1e-6);
    }
}

/* ---------------------------------------------------------------- advance and bounds */

/* Advance over 10 ms periods of the stiff system: exactly dt, within the work bound, and each
 * period's factorisations/solves/RHS counted. */
static void test_advance_exact_interval_and_work_bound(void)
{
    const double L = 1.0e6;
    const int budgets[3] = {1, 3, 20};
    for (int b = 0; b < 3; ++b) {
        dense_t d = dense(2, jac_pr, 1.0, &L);
        const cdpr_ros_problem_t pb = problem(rhs_pr, (void *)&L, &d);
        cdpr_ros_params_t p = params_tol(1e-4);
        p.step.h_init_s = 0.01;
        init_solver(&p, 2);
        cdpr_real_t t = 0.0;
        cdpr_real_t y[2] = {1.0, 1.0};
        for (int k = 0; k < 50; ++k) {
            const cdpr_step_stats_t before = solver.stats;
            const cdpr_ros_lin_stats_t lin_before = solver.lin;
            const cdpr_status_t st = cdpr_ros_advance(&solver, &pb, &t, y, 0.01, budgets[b]);
            TEST_ASSERT_TRUE(st == CDPR_OK || st == CDPR_WARN_SUBSTEP_LIMIT ||
                             st == CDPR_E_SUBSTEP_LIMIT);
            const unsigned long fac = solver.lin.factorisations - lin_before.factorisations;
            TEST_ASSERT_TRUE(fac <= (unsigned long)budgets[b]);
            TEST_ASSERT_TRUE(solver.lin.solves - lin_before.solves <=
                             4UL * (unsigned long)budgets[b]);
            TEST_ASSERT_TRUE(solver.stats.rhs_evals - before.rhs_evals <=
                             4UL * (unsigned long)budgets[b]);
            if (st >= 0) {
                TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-12, 1e-6), 0.01 * (k + 1), (double)t);
            }
        }
        TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-3, 1e-3), cos(0.5), (double)y[1]);
    }
}

/* An equal step above force_err_max is refused: state and time bit-identical. */
static void test_advance_refuses_above_force_err_max(void)
{
    const osc_t o = {2.0 * 3.14159265358979323846, 0.0};
    dense_t d = dense(2, jac_osc, 1.0, &o);
    const cdpr_ros_problem_t pb = problem(rhs_osc, (void *)&o, &d);
    cdpr_ros_params_t p = params_tol(1e-10);
    p.step.force_err_max = 1.0;
    init_solver(&p, 2);
    cdpr_real_t t = 0.25;
    cdpr_real_t y[2] = {0.3, -0.7};
    cdpr_real_t y_before[2];
    memcpy(y_before, y, sizeof y);
    const cdpr_real_t t_before = t;
    TEST_ASSERT_EQUAL_INT(CDPR_E_SUBSTEP_LIMIT, cdpr_ros_advance(&solver, &pb, &t, y, 0.5, 2));
    TEST_ASSERT_EQUAL_MEMORY(y_before, y, sizeof y);
    TEST_ASSERT_EQUAL_MEMORY(&t_before, &t, sizeof t);
    TEST_ASSERT_EQUAL_UINT(1u, solver.stats.substep_limit_failures);
    TEST_ASSERT_EQUAL_UINT(1u, solver.stats.failures);
    /* With forced steps allowed (a large bound) the same call passes with a warning. */
    solver.p.step.force_err_max = 1e30;
    TEST_ASSERT_EQUAL_INT(CDPR_WARN_SUBSTEP_LIMIT, cdpr_ros_advance(&solver, &pb, &t, y, 0.5, 2));
    TEST_ASSERT_TRUE(solver.stats.forced_steps >= 1u);
}

/* jac_reuse_max: equal steps share one factorisation for up to 1 + jac_reuse_max trials; the
 * lagged W keeps the result on the closed form (W-method), and set_dim / invalidate force a new
 * factorisation. */
static void test_factorisation_reuse(void)
{
    const double L = 1.0e4;
    dense_t d = dense(2, jac_pr, 1.0, &L);
    const cdpr_ros_problem_t pb = problem(rhs_pr, (void *)&L, &d);
    cdpr_ros_params_t p = params_tol(TOL(1e-6, 1e-4));
    p.jac_reuse_max = 4;
    p.step.h_init_s = 0.01;
    init_solver(&p, 2);
    cdpr_real_t t = 0.0;
    cdpr_real_t y[2] = {1.0, 1.0};
    for (int k = 0; k < 100; ++k) {
        TEST_ASSERT_TRUE(cdpr_ros_advance(&solver, &pb, &t, y, 0.01, 1) >= 0);
    }
    const unsigned long trials = solver.stats.steps_accepted + solver.stats.steps_rejected;
    TEST_ASSERT_EQUAL_UINT(100u, trials);
    TEST_ASSERT_EQUAL_UINT(20u, solver.lin.factorisations);
    TEST_ASSERT_EQUAL_INT(d.factor_calls, (int)solver.lin.factorisations);
    TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-5, 1e-3), exp(-1.0), (double)y[0]);
    TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-5, 1e-3), cos(1.0), (double)y[1]);
    cdpr_ros_invalidate(&solver);
    TEST_ASSERT_TRUE(cdpr_ros_advance(&solver, &pb, &t, y, 0.01, 1) >= 0);
    TEST_ASSERT_EQUAL_UINT(21u, solver.lin.factorisations);
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_ros_set_dim(&solver, 2));
    TEST_ASSERT_TRUE(cdpr_ros_advance(&solver, &pb, &t, y, 0.01, 1) >= 0);
    TEST_ASSERT_EQUAL_UINT(22u, solver.lin.factorisations);
    p.jac_reuse_max = -1;
    TEST_ASSERT_EQUAL_INT(CDPR_E_OUT_OF_RANGE, cdpr_ros_params_validate(&p, 2, NULL));
}

/* The reuse window of gamma h (relative 1e-3, ros34pw2.h): steps that alternate 5e-4 apart
 * share a factorisation, steps 1 % apart never do (issue 26: the window x 100 passed every
 * test, a W for another h still being a W-method matrix). */
static void test_factorisation_reuse_window(void)
{
    const double L = 1.0e4;
    const double apart[2] = {5e-4, 1e-2};
    const unsigned long want[2] = {4u, 20u};
    for (int c = 0; c < 2; ++c) {
        dense_t d = dense(2, jac_pr, 1.0, &L);
        const cdpr_ros_problem_t pb = problem(rhs_pr, (void *)&L, &d);
        cdpr_ros_params_t p = params_tol(TOL(1e-6, 1e-4));
        p.jac_reuse_max = 4;
        p.step.h_init_s = 0.01;
        init_solver(&p, 2);
        cdpr_real_t t = 0.0;
        cdpr_real_t y[2] = {1.0, 1.0};
        for (int k = 0; k < 20; ++k) {
            const double dt = 0.01 * ((k % 2 == 0) ? 1.0 : 1.0 + apart[c]);
            TEST_ASSERT_TRUE(cdpr_ros_advance(&solver, &pb, &t, y, (cdpr_real_t)dt, 1) >= 0);
        }
        TEST_ASSERT_EQUAL_UINT(20u, solver.stats.steps_accepted + solver.stats.steps_rejected);
        TEST_ASSERT_EQUAL_UINT(want[c], solver.lin.factorisations);
    }
}

/* ---------------------------------------------------------------- failure paths */

/* A factorisation or a solve that refuses (singular W) ends step and advance with
 * CDPR_E_SINGULAR, y and t bit-identical, counted. */
static void test_singular_w_leaves_state_bit_identical(void)
{
    const osc_t o = {3.0, 0.1};
    for (int which = 0; which < 4; ++which) {
        dense_t d = dense(2, jac_osc, 1.0, &o);
        /* which: 0 first factor, 1 third factor, 2 second solve, 3 seventh solve */
        d.fail_factor_at = (which == 0) ? 1 : ((which == 1) ? 3 : 0);
        d.fail_solve_at = (which == 2) ? 2 : ((which == 3) ? 7 : 0);
        const cdpr_ros_problem_t pb = problem(rhs_osc, (void *)&o, &d);
        cdpr_ros_params_t p = params_tol(1e-8);
        p.step.h_init_s = 1e-3;
        init_solver(&p, 2);
        cdpr_real_t t = 0.125;
        cdpr_real_t y[2] = {0.5, 0.25};
        cdpr_real_t y_before[2];
        memcpy(y_before, y, sizeof y);
        const cdpr_real_t t_before = t;
        const cdpr_status_t st = (which % 2 == 0) ? cdpr_ros_step(&solver, &pb, &t, y, 1.0)
                                                  : cdpr_ros_advance(&solver, &pb, &t, y, 0.1, 50);
        TEST_ASSERT_EQUAL_INT(CDPR_E_SINGULAR, st);
        TEST_ASSERT_EQUAL_MEMORY(y_before, y, sizeof y);
        TEST_ASSERT_EQUAL_MEMORY(&t_before, &t, sizeof t);
        TEST_ASSERT_EQUAL_UINT(1u, solver.lin.singular_failures);
        TEST_ASSERT_EQUAL_UINT(1u, solver.stats.failures);
    }
}

static cdpr_status_t rhs_refuse_late(cdpr_real_t t, const cdpr_real_t *y, cdpr_real_t *dydt,
                                     void *ctx)
{
    (void)ctx;
    if (t > 0.05) {
        return CDPR_E_RHS;
    }
    dydt[0] = -y[0];
    return CDPR_OK;
}

/* y' = -y that returns NaN for stage states far from the solution (large steps). */
static cdpr_status_t rhs_nan_far(cdpr_real_t t, const cdpr_real_t *y, cdpr_real_t *dydt, void *ctx)
{
    unsigned long *nan_calls = ctx;
    if (fabs((double)y[0] - exp(-(double)t)) > 1e-3) {
        (*nan_calls)++;
        dydt[0] = NAN_R;
    } else {
        dydt[0] = -y[0];
    }
    return CDPR_OK;
}

static void jac_minus_one(cdpr_real_t t, const cdpr_real_t *y, double *J, const void *prob)
{
    (void)t;
    (void)y;
    (void)prob;
    J[0] = -1.0;
}

static void test_nan_and_refusing_rhs(void)
{
    /* NaN in the state: refused, bit-identical, counted. */
    dense_t d = dense(1, jac_minus_one, 1.0, NULL);
    unsigned long nan_calls = 0;
    cdpr_ros_problem_t pb = problem(rhs_nan_far, &nan_calls, &d);
    cdpr_ros_params_t p = params_tol(1e-8);
    p.step.h_init_s = 1.0;
    init_solver(&p, 1);
    const cdpr_real_t t0 = 0.0;
    cdpr_real_t t = t0;
    cdpr_real_t y[1] = {NAN_R};
    cdpr_real_t yb[1];
    memcpy(yb, y, sizeof y);
    TEST_ASSERT_EQUAL_INT(CDPR_E_STATE_NOT_FINITE, cdpr_ros_advance(&solver, &pb, &t, y, 0.1, 10));
    TEST_ASSERT_EQUAL_MEMORY(yb, y, sizeof y);
    TEST_ASSERT_EQUAL_INT(CDPR_E_STATE_NOT_FINITE, cdpr_ros_step(&solver, &pb, &t, y, 1.0));
    TEST_ASSERT_EQUAL_MEMORY(yb, y, sizeof y);
    TEST_ASSERT_EQUAL_UINT(2u, solver.stats.failures);
    TEST_ASSERT_EQUAL_MEMORY(&t0, &t, sizeof t);
    /* NaN from a too-large trial only: rejected, the step shrinks and the result is right. */
    y[0] = 1.0;
    init_solver(&p, 1);
    while (t < 1.0) {
        TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_ros_step(&solver, &pb, &t, y, 1.0));
    }
    TEST_ASSERT_TRUE(solver.stats.nonfinite_rejected >= 1u);
    TEST_ASSERT_TRUE(nan_calls >= 1u);
    TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-5, 1e-4), exp(-1.0), (double)y[0]);
    /* A refusing RHS: CDPR_E_RHS, bit-identical. */
    pb = problem(rhs_refuse_late, NULL, &d);
    init_solver(&p, 1);
    t = 0.0;
    y[0] = 1.0;
    memcpy(yb, y, sizeof y);
    TEST_ASSERT_EQUAL_INT(CDPR_E_RHS, cdpr_ros_advance(&solver, &pb, &t, y, 0.1, 10));
    TEST_ASSERT_EQUAL_MEMORY(yb, y, sizeof y);
    TEST_ASSERT_EQUAL_MEMORY(&t0, &t, sizeof t);
    TEST_ASSERT_EQUAL_UINT(1u, solver.stats.failures);
}

static void test_invalid_arguments_and_parameters(void)
{
    cdpr_ros_params_t p;
    cdpr_ros_params_default(&p);
    cdpr_diag_t dg;
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_ros_params_validate(&p, 1, &dg));
    TEST_ASSERT_EQUAL_INT(CDPR_E_INVALID_ARG, cdpr_ros_params_validate(NULL, 1, &dg));
    p.step.rtol = -1.0;
    TEST_ASSERT_EQUAL_INT(CDPR_E_OUT_OF_RANGE, cdpr_ros_params_validate(&p, 1, &dg));
    TEST_ASSERT_EQUAL_STRING("rtol", dg.field);
    cdpr_ros_params_default(&p);
    p.step.safety = 1.0;
    TEST_ASSERT_EQUAL_INT(CDPR_E_OUT_OF_RANGE, cdpr_ros_params_validate(&p, 1, &dg));
    cdpr_ros_params_default(&p);
    p.step.force_err_max = 0.5;
    TEST_ASSERT_EQUAL_INT(CDPR_E_OUT_OF_RANGE, cdpr_ros_params_validate(&p, 1, &dg));
    cdpr_ros_params_default(&p);
    p.step.h_min_s = 2.0;
    TEST_ASSERT_EQUAL_INT(CDPR_E_OUT_OF_RANGE, cdpr_ros_params_validate(&p, 1, &dg));
    TEST_ASSERT_EQUAL_STRING("h_max_s", dg.field);
    cdpr_ros_params_default(&p);
    const cdpr_real_t bad_atol[2] = {1e-6, 0.0};
    p.step.atol_vec = bad_atol;
    TEST_ASSERT_EQUAL_INT(CDPR_E_NOT_POSITIVE, cdpr_ros_params_validate(&p, 2, &dg));
    TEST_ASSERT_EQUAL_INT(1, dg.index);
    cdpr_ros_params_default(&p);
    TEST_ASSERT_EQUAL_INT(CDPR_E_CAPACITY, cdpr_ros_init(&solver, &p, work, 3, DIM_MAX, 1, &dg));
    TEST_ASSERT_EQUAL_INT(CDPR_E_CAPACITY,
                          cdpr_ros_init(&solver, &p, work, CDPR_ROS_WORK_PER_DIM * DIM_MAX, DIM_MAX,
                                        DIM_MAX + 1, &dg));
    init_solver(&p, 2);
    TEST_ASSERT_EQUAL_INT(CDPR_E_CAPACITY, cdpr_ros_set_dim(&solver, DIM_MAX + 1));
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_ros_set_dim(&solver, 1));
    TEST_ASSERT_EQUAL_INT(1, solver.dim);
    const osc_t o = {1.0, 0.0};
    dense_t d = dense(2, jac_osc, 1.0, &o);
    cdpr_ros_problem_t pb = problem(rhs_osc, (void *)&o, &d);
    cdpr_real_t t = 0.0;
    cdpr_real_t y[2] = {1.0, 0.0};
    TEST_ASSERT_EQUAL_INT(CDPR_E_INVALID_ARG, cdpr_ros_advance(&solver, &pb, &t, y, 0.0, 5));
    TEST_ASSERT_EQUAL_INT(CDPR_E_INVALID_ARG, cdpr_ros_advance(&solver, &pb, &t, y, 0.1, 0));
    TEST_ASSERT_EQUAL_INT(CDPR_E_INVALID_ARG, cdpr_ros_step(&solver, &pb, &t, y, 0.0));
    pb.solve = NULL;
    TEST_ASSERT_EQUAL_INT(CDPR_E_INVALID_ARG, cdpr_ros_step(&solver, &pb, &t, y, 1.0));
    TEST_ASSERT_EQUAL_INT(CDPR_E_INVALID_ARG, cdpr_ros_advance(&solver, NULL, &t, y, 0.1, 5));
    TEST_ASSERT_EQUAL_UINT(0u, solver.stats.failures);
}

/* ---------------------------------------------------------------- allocation, determinism */

static void run_osc(cdpr_real_t *y_out, cdpr_step_stats_t *st_out, cdpr_ros_lin_stats_t *lin_out)
{
    const osc_t o = {5.0, 0.02};
    dense_t d = dense(2, jac_osc, 1.0, &o);
    const cdpr_ros_problem_t pb = problem(rhs_osc, (void *)&o, &d);
    const cdpr_ros_params_t p = params_tol(1e-7);
    init_solver(&p, 2);
    cdpr_real_t t = 0.0;
    y_out[0] = 1.0;
    y_out[1] = 0.0;
    for (int k = 0; k < 100; ++k) {
        TEST_ASSERT_TRUE(cdpr_ros_advance(&solver, &pb, &t, y_out, 0.01, 20) >= 0);
    }
    while (t < 2.0) {
        TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_ros_step(&solver, &pb, &t, y_out, 2.0));
    }
    *st_out = solver.stats;
    *lin_out = solver.lin;
}

static void test_no_heap_allocation(void)
{
    if (!cdpr_alloc_counting_available()) {
        TEST_IGNORE_MESSAGE(cdpr_alloc_unavailable_reason());
    }
    cdpr_real_t y[2];
    cdpr_step_stats_t st;
    cdpr_ros_lin_stats_t lin;
    cdpr_alloc_reset();
    run_osc(y, &st, &lin);
    TEST_ASSERT_EQUAL_UINT(0u, cdpr_alloc_count());
}

/* cdpr_ros_fixed: n equal steps, each what cdpr_ros_trial gives (bit for bit), exactly n
 * factorisations whatever jac_reuse_max says, the largest error norm reported; on the stiff
 * Prothero-Robinson problem with h L = 1e3 (far beyond any explicit limit) it follows the
 * closed form; a non-finite step is refused with the state bit-identical. */
static void test_fixed_equal_steps_exact_work(void)
{
    const double L = 1.0e6;
    dense_t d = dense(2, jac_pr, 1.0, &L);
    const cdpr_ros_problem_t pb = problem(rhs_pr, (void *)&L, &d);
    cdpr_ros_params_t p = params_tol(1e-6);
    p.jac_reuse_max = 4; /* the fixed call renews W anyway */
    init_solver(&p, 2);
    cdpr_real_t t = 0.0;
    cdpr_real_t y[2] = {1.0, 2.0};
    cdpr_real_t yt[2] = {1.0, 2.0};
    double emax = 0.0;
    for (int k = 0; k < 50; ++k) {
        const unsigned long fac0 = solver.lin.factorisations;
        const unsigned long rhs0 = solver.stats.rhs_evals;
        const unsigned long sol0 = solver.lin.solves;
        cdpr_real_t en = -1.0;
        const cdpr_real_t tk = t;
        TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_ros_fixed(&solver, &pb, &t, y, 0.01, 5, &en));
        TEST_ASSERT_EQUAL_UINT(5u, solver.lin.factorisations - fac0);
        TEST_ASSERT_EQUAL_UINT(20u, solver.stats.rhs_evals - rhs0);
        TEST_ASSERT_EQUAL_UINT(20u, solver.lin.solves - sol0);
        TEST_ASSERT_TRUE(en >= 0.0 && isfinite(en));
        /* The same five steps by hand, one trial each from the fixed call's own times. */
        double worst = 0.0;
        for (int i = 0; i < 5; ++i) {
            cdpr_real_t yn[2];
            cdpr_real_t e = 0.0;
            cdpr_ros_invalidate(&solver);
            TEST_ASSERT_EQUAL_INT(
                CDPR_OK, cdpr_ros_trial(&solver, &pb, tk + (cdpr_real_t)i * ((cdpr_real_t)0.01 / 5),
                                        yt, (cdpr_real_t)0.01 / 5, yn, &e));
            yt[0] = yn[0];
            yt[1] = yn[1];
            worst = fmax(worst, (double)e);
        }
        TEST_ASSERT_EQUAL_MEMORY(yt, y, sizeof y);
        TEST_ASSERT_EQUAL_DOUBLE(worst, (double)en);
        const double td = (double)t;
        emax = fmax(emax, fabs((double)y[0] - exp(-td)));
        emax = fmax(emax, fabs((double)y[1] - (cos(td) + exp(-L * td))));
    }
    TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-12, 1e-5), 0.5, (double)t); /* 50 sums of 0.01 */
    TEST_ASSERT_TRUE_MESSAGE(emax < TOL(1e-6, 1e-4), "fixed steps left the closed form");
    /* A non-finite step: refused, state and time bit-identical, counted. */
    dense_t d1 = dense(1, jac_minus_one, 1.0, NULL);
    unsigned long nan_calls = 0;
    const cdpr_ros_problem_t pn = problem(rhs_nan_far, &nan_calls, &d1);
    init_solver(&p, 1);
    cdpr_real_t t1 = 0.0;
    cdpr_real_t y1[1] = {1.0};
    const cdpr_real_t y1b = y1[0];
    cdpr_real_t en = 7.0;
    TEST_ASSERT_EQUAL_INT(CDPR_E_STATE_NOT_FINITE,
                          cdpr_ros_fixed(&solver, &pn, &t1, y1, 1.0, 1, &en));
    TEST_ASSERT_EQUAL_MEMORY(&y1b, y1, sizeof y1b);
    TEST_ASSERT_EQUAL_DOUBLE(0.0, (double)t1);
    TEST_ASSERT_EQUAL_DOUBLE(7.0, (double)en);
    TEST_ASSERT_EQUAL_UINT(1u, solver.stats.nonfinite_rejected);
    TEST_ASSERT_EQUAL_UINT(1u, solver.stats.failures);
    TEST_ASSERT_TRUE(nan_calls >= 1u);
    /* Bad arguments: nothing changed, not counted. */
    TEST_ASSERT_EQUAL_INT(CDPR_E_INVALID_ARG, cdpr_ros_fixed(&solver, &pn, &t1, y1, 1.0, 0, NULL));
    TEST_ASSERT_EQUAL_INT(CDPR_E_INVALID_ARG, cdpr_ros_fixed(&solver, &pn, &t1, y1, 0.0, 1, NULL));
    TEST_ASSERT_EQUAL_INT(CDPR_E_INVALID_ARG, cdpr_ros_fixed(&solver, NULL, &t1, y1, 1.0, 1, NULL));
    TEST_ASSERT_EQUAL_UINT(1u, solver.stats.failures);
}

static void test_two_identical_runs_are_bit_identical(void)
{
    cdpr_real_t y1[2], y2[2];
    cdpr_step_stats_t s1, s2;
    cdpr_ros_lin_stats_t l1, l2;
    run_osc(y1, &s1, &l1);
    run_osc(y2, &s2, &l2);
    TEST_ASSERT_EQUAL_MEMORY(y1, y2, sizeof y1);
    TEST_ASSERT_EQUAL_UINT(s1.steps_accepted, s2.steps_accepted);
    TEST_ASSERT_EQUAL_UINT(s1.rhs_evals, s2.rhs_evals);
    TEST_ASSERT_EQUAL_UINT(l1.solves, l2.solves);
    TEST_ASSERT_EQUAL_UINT(l1.factorisations, l2.factorisations);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_damped_oscillator_against_closed_form);
    RUN_TEST(test_stiff_system_against_closed_form);
    RUN_TEST(test_observed_order_three_any_jacobian);
    RUN_TEST(test_l_stability);
    RUN_TEST(test_advance_exact_interval_and_work_bound);
    RUN_TEST(test_advance_refuses_above_force_err_max);
    RUN_TEST(test_factorisation_reuse);
    RUN_TEST(test_factorisation_reuse_window);
    RUN_TEST(test_singular_w_leaves_state_bit_identical);
    RUN_TEST(test_nan_and_refusing_rhs);
    RUN_TEST(test_invalid_arguments_and_parameters);
    RUN_TEST(test_no_heap_allocation);
    RUN_TEST(test_two_identical_runs_are_bit_identical);
    RUN_TEST(test_fixed_equal_steps_exact_work);
    return UNITY_END() ? 1 : 0;
}
