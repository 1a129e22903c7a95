/* SPDX-License-Identifier: BSD-3-Clause */
/// @file test_gsl_statics_dist.c
/// Redundant robots: the sag-aware inverse kinematics of an eight-cable robot with its tension
/// distribution (cdpr_statics_ik_dist) against checks written here with GSL, independent of the
/// core's solver:
/// - balance: every cable's (H, V) solved again from its returned length and spans (a 2 x 2
///   GSL hybrid on the closed-form catenary), the cabin wrench summed from them: 1e-9 of the
///   weight;
/// - bounds: the lowest and highest tension along every cable, from those (H, V), within
///   [t_min, t_max];
/// - the criterion: along the equilibria (two cables' H given, the other six and every (V, L)
///   solved by a 22-unknown GSL hybrid), the criterion sum_j (lowest tension_j - t_ref)^2 has
///   zero slope at the returned solution, and grows into the feasible side of an active bound;
/// - near-massless cables: the closed-form method of Pott, Bruckmann and Mikelsons (2009),
///   t = t_ref + A^T (A A^T)^-1 (w - A t_ref) on the straight chords (GSL LU);
/// - a load that no tension within the bounds can hold is refused, and bad bounds are;
/// - six cables through the same function: cdpr_statics_ik_wrench's result bit for bit.
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_errno.h>
#include <gsl/gsl_linalg.h>
#include <gsl/gsl_matrix.h>
#include <gsl/gsl_multiroots.h>
#include <gsl/gsl_permutation.h>
#include <gsl/gsl_vector.h>

#include "cdpr/catenary.h"
#include "cdpr/robot.h"
#include "cdpr/statics.h"
#include "eight_plant.h"
#include "unity.h"

void setUp(void) {}
void tearDown(void) {}

#if CDPR_MAX_CABLES >= 8

enum { M = 8 };
static cdpr_robot_t robot;

/* The eight-cable robot of docs/robots.md set C (eight_plant.h's geometry): 40 kg cabin, the
 * rope's EA and rho given. */
static void build8(double ea, double rho)
{
    cdpr_robot_params_t p;
    cdpr_robot_params_default(&p);
    p.n_cables = M;
    p.cabin.mass_kg = 40.0;
    for (int j = 0; j < M; ++j) {
        test_eight_geometry(j, &p.cables[j].exit_point_m, &p.cables[j].attach_body_m);
        p.cables[j].cable.ea_N = ea;
        p.cables[j].cable.rho_kg_per_m = rho;
        p.cables[j].n_segments = 8;
        p.cables[j].length_m = 30.0;
    }
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_robot_init(&robot, &p, NULL));
}

static cdpr_cabin_motion_t pose_of(const double x[6])
{
    cdpr_cabin_motion_t m;
    memset(&m, 0, sizeof m);
    m.p_m = cdpr_v3(x[0], x[1], x[2]);
    m.q = cdpr_quat_from_euler(x[3], x[4], x[5]);
    return m;
}

/* Geometry of cable j at a pose: horizontal span l, rise h, horizontal unit e, arm R (b - c). */
typedef struct {
    double l;
    double h;
    cdpr_vec3_t e;
    cdpr_vec3_t arm;
} geo_t;

static geo_t geo(const cdpr_cabin_motion_t *m, int j)
{
    cdpr_mat3_t R;
    cdpr_quat_to_mat3(m->q, &R);
    const cdpr_vec3_t b = robot.p.cables[j].attach_body_m;
    const cdpr_vec3_t P = cdpr_v3_add(m->p_m, cdpr_m3_mul_v3(&R, b));
    const cdpr_vec3_t d = cdpr_v3_sub(robot.p.cables[j].exit_point_m, P);
    geo_t g;
    g.l = sqrt(d.x * d.x + d.y * d.y);
    g.h = d.z;
    g.e = cdpr_v3(d.x / g.l, d.y / g.l, 0.0);
    g.arm = cdpr_m3_mul_v3(&R, cdpr_v3_sub(b, robot.p.cabin.com_body_m));
    return g;
}

static double w_of(int j)
{
    return robot.p.cables[j].cable.rho_kg_per_m * robot.p.g_m_per_s2;
}

static cdpr_catenary_cable_t cat(int j)
{
    const cdpr_catenary_cable_t c = {w_of(j), robot.p.cables[j].cable.ea_N};
    return c;
}

/* Lowest and highest tension along a catenary (V grows by w per unstretched length from the
 * cabin end): written again here from the definition. */
static void tension_range(double H, double V, double w, double L, double *lo, double *hi)
{
    const double vb = V + w * L;
    const double tc = sqrt(H * H + V * V);
    const double tb = sqrt(H * H + vb * vb);
    *lo = (V >= 0.0) ? tc : ((vb <= 0.0) ? tb : H);
    *hi = fmax(tc, tb);
}

/* ---- one cable's (H, V) from its length (2 x 2 GSL hybrid) ------------------------------ */
typedef struct {
    int j;
    double L;
    geo_t g;
} one_t;

static int one_eq(const gsl_vector *x, void *params, gsl_vector *f)
{
    const one_t *p = (const one_t *)params;
    const double H = gsl_vector_get(x, 0);
    if (!(H > 0.0)) {
        return GSL_EDOM;
    }
    const cdpr_catenary_cable_t c = cat(p->j);
    double ls = 0.0;
    double hs = 0.0;
    if (cdpr_catenary_spans(&c, H, gsl_vector_get(x, 1), p->L, &ls, &hs) != CDPR_OK) {
        return GSL_EDOM;
    }
    gsl_vector_set(f, 0, ls - p->g.l);
    gsl_vector_set(f, 1, hs - p->g.h);
    return GSL_SUCCESS;
}

/* (H, V) of cable j of length L at pose m, from the start (H, V). */
static void closure(const cdpr_cabin_motion_t *m, int j, double L, double *H, double *V)
{
    one_t p = {j, L, geo(m, j)};
    gsl_multiroot_function fn = {one_eq, 2, &p};
    gsl_vector *x = gsl_vector_alloc(2);
    gsl_multiroot_fsolver *s = gsl_multiroot_fsolver_alloc(gsl_multiroot_fsolver_hybrids, 2);
    gsl_vector_set(x, 0, *H * (1.0 + 1e-3));
    gsl_vector_set(x, 1, *V + 1e-3 * fabs(*V) + 1e-3);
    TEST_ASSERT_EQUAL_INT(GSL_SUCCESS, gsl_multiroot_fsolver_set(s, &fn, x));
    int conv = 0;
    for (int it = 0; it < 200 && conv == 0; ++it) {
        const int rc = gsl_multiroot_fsolver_iterate(s);
        conv = (gsl_multiroot_test_residual(s->f, 1e-12) == GSL_SUCCESS) ? 1 : 0;
        if (rc != GSL_SUCCESS && conv == 0) {
            break;
        }
    }
    TEST_ASSERT_EQUAL_INT(1, conv);
    *H = gsl_vector_get(s->x, 0);
    *V = gsl_vector_get(s->x, 1);
    gsl_multiroot_fsolver_free(s);
    gsl_vector_free(x);
}

/* Balance and bounds from the independent closures of the returned lengths. Returns the wrench
 * residual norm [N, N m] and fills the lowest/highest tensions. */
static double independent_balance(const cdpr_cabin_motion_t *m, const cdpr_statics_result_t *res,
                                  double *lo, double *hi)
{
    const double weight = robot.p.cabin.mass_kg * robot.p.g_m_per_s2;
    cdpr_vec3_t f = cdpr_v3(0.0, 0.0, -weight);
    cdpr_vec3_t mo = cdpr_v3(0.0, 0.0, 0.0);
    for (int j = 0; j < M; ++j) {
        double H = res->cable[j].H_N;
        double V = res->cable[j].v_cabin_N;
        closure(m, j, res->cable[j].length_m, &H, &V);
        TEST_ASSERT_DOUBLE_WITHIN(1e-7 * H, res->cable[j].H_N, H);
        const geo_t g = geo(m, j);
        const cdpr_vec3_t F = cdpr_v3(H * g.e.x, H * g.e.y, V);
        f = cdpr_v3_add(f, F);
        mo = cdpr_v3_add(mo, cdpr_v3_cross(g.arm, F));
        tension_range(H, V, w_of(j), res->cable[j].length_m, &lo[j], &hi[j]);
    }
    return sqrt(cdpr_v3_dot(f, f) + cdpr_v3_dot(mo, mo));
}

/* ---- equilibria with two cables' H given (22 unknowns, GSL hybrid) ---------------------- */
typedef struct {
    cdpr_cabin_motion_t m;
    int a;
    int b;
    double Ha;
    double Hb;
} fam_t;

/* Unknowns: H of the six other cables, then (V_j, L_j) of all eight. */
static int fam_eq(const gsl_vector *x, void *params, gsl_vector *f)
{
    const fam_t *p = (const fam_t *)params;
    const double weight = robot.p.cabin.mass_kg * robot.p.g_m_per_s2;
    cdpr_vec3_t force = cdpr_v3(0.0, 0.0, -weight);
    cdpr_vec3_t mo = cdpr_v3(0.0, 0.0, 0.0);
    int k = 0;
    for (int j = 0; j < M; ++j) {
        double H = 0.0;
        if (j == p->a) {
            H = p->Ha;
        } else if (j == p->b) {
            H = p->Hb;
        } else {
            H = gsl_vector_get(x, (size_t)k);
            ++k;
        }
        const double V = gsl_vector_get(x, 6u + 2u * (size_t)j);
        const double L = gsl_vector_get(x, 7u + 2u * (size_t)j);
        if (!(H > 0.0) || !(L > 0.0)) {
            return GSL_EDOM;
        }
        const geo_t g = geo(&p->m, j);
        const cdpr_vec3_t F = cdpr_v3(H * g.e.x, H * g.e.y, V);
        force = cdpr_v3_add(force, F);
        mo = cdpr_v3_add(mo, cdpr_v3_cross(g.arm, F));
        const cdpr_catenary_cable_t c = cat(j);
        double ls = 0.0;
        double hs = 0.0;
        if (cdpr_catenary_spans(&c, H, V, L, &ls, &hs) != CDPR_OK) {
            return GSL_EDOM;
        }
        gsl_vector_set(f, 6u + 2u * (size_t)j, (ls - g.l) / 30.0);
        gsl_vector_set(f, 7u + 2u * (size_t)j, (hs - g.h) / 30.0);
    }
    const double r[6] = {force.x, force.y, force.z, mo.x, mo.y, mo.z};
    for (size_t i = 0; i < 6; ++i) {
        gsl_vector_set(f, i, r[i] / weight);
    }
    return GSL_SUCCESS;
}

/* The equilibrium with H_a, H_b given, from the core's solution res: the criterion
 * sum (lo_j - t_ref)^2 and the largest bound violation there (<= 0: within bounds). */
static void along(const cdpr_cabin_motion_t *m, const cdpr_statics_result_t *res, int a, double Ha,
                  int b, double Hb, const cdpr_statics_dist_t *d, double *crit, double *viol)
{
    fam_t p = {*m, a, b, Ha, Hb};
    gsl_multiroot_function fn = {fam_eq, 22, &p};
    gsl_vector *x = gsl_vector_alloc(22);
    gsl_multiroot_fsolver *s = gsl_multiroot_fsolver_alloc(gsl_multiroot_fsolver_hybrids, 22);
    int k = 0;
    for (int j = 0; j < M; ++j) {
        if (j != a && j != b) {
            gsl_vector_set(x, (size_t)k, res->cable[j].H_N);
            ++k;
        }
        gsl_vector_set(x, 6u + 2u * (size_t)j, res->cable[j].v_cabin_N);
        gsl_vector_set(x, 7u + 2u * (size_t)j, res->cable[j].length_m);
    }
    TEST_ASSERT_EQUAL_INT(GSL_SUCCESS, gsl_multiroot_fsolver_set(s, &fn, x));
    int conv = 0;
    for (int it = 0; it < 300 && conv == 0; ++it) {
        const int rc = gsl_multiroot_fsolver_iterate(s);
        conv = (gsl_multiroot_test_residual(s->f, 1e-14) == GSL_SUCCESS) ? 1 : 0;
        if (rc != GSL_SUCCESS && conv == 0) {
            break;
        }
    }
    TEST_ASSERT_EQUAL_INT(1, conv);
    *crit = 0.0;
    *viol = -1e300;
    k = 0;
    for (int j = 0; j < M; ++j) {
        double H = 0.0;
        if (j == a) {
            H = Ha;
        } else if (j == b) {
            H = Hb;
        } else {
            H = gsl_vector_get(s->x, (size_t)k);
            ++k;
        }
        double lo = 0.0;
        double hi = 0.0;
        tension_range(H, gsl_vector_get(s->x, 6u + 2u * (size_t)j), w_of(j),
                      gsl_vector_get(s->x, 7u + 2u * (size_t)j), &lo, &hi);
        *crit += (lo - d->t_ref_N) * (lo - d->t_ref_N);
        *viol = fmax(*viol, fmax(d->t_min_N - lo, hi - d->t_max_N));
    }
    gsl_multiroot_fsolver_free(s);
    gsl_vector_free(x);
}

static void random_pose(double x[6])
{
    x[0] = 10.0 * ((double)rand() / RAND_MAX - 0.5);
    x[1] = 10.0 * ((double)rand() / RAND_MAX - 0.5);
    x[2] = 8.0 + 12.0 * ((double)rand() / RAND_MAX);
    for (int i = 3; i < 6; ++i) {
        x[i] = 0.2 * ((double)rand() / RAND_MAX - 0.5);
    }
}

/* Central slope of the criterion along H_c (H_o held) at the solution [N^2 / N]. */
static double slope(const cdpr_cabin_motion_t *m, const cdpr_statics_result_t *res, int c, int o,
                    const cdpr_statics_dist_t *d)
{
    const double h = 1e-4 * res->cable[c].H_N;
    double cp = 0.0;
    double cm = 0.0;
    double v = 0.0;
    along(m, res, c, res->cable[c].H_N + h, o, res->cable[o].H_N, d, &cp, &v);
    along(m, res, c, res->cable[c].H_N - h, o, res->cable[o].H_N, d, &cm, &v);
    return (cp - cm) / (2.0 * h);
}

static void test_distribution_balances_within_bounds_at_the_optimum(void)
{
    /* 30 poses of a 10 m x 10 m x 12 m box, tilts within 0.1 rad, bounds 25-500 N (reference
     * 262.5 N; a lowest tension of 25 N keeps these 30 m ropes within 1.5 chords): every one
     * solves. Balance from the independent closures: at most 1e-9 of the
     * weight; bounds met to 1e-9 N. Where no bound is active (9 of the first 10 poses), the
     * criterion's slope along one cable's H, with another held and the other six solved, is the
     * first-order optimality the SQP claims: measured at most 3.4e-5 N, asserted below 1e-4 N
     * (the SQP stops when its step would change a tension by less than 1e-7 N + 1.5e-7 of the
     * largest |lowest tension - t_ref|, 4e-5 N here; a solution 1e-3 N off along the
     * equilibria shows a slope of ~3e-3 N, the criterion's gradient components are 10-500 N).
     * At most 20 iterations (measured 2-11). Forward statics at the lengths returns the pose. */
    build8(2.0e6, 0.14);
    gsl_set_error_handler_off();
    cdpr_statics_opts_t o;
    cdpr_statics_opts_default(&o);
    cdpr_statics_dist_t d;
    cdpr_statics_dist_init(&d, 25.0, 500.0);
    const double weight = robot.p.cabin.mass_kg * robot.p.g_m_per_s2;
    const cdpr_vec3_t zero = cdpr_v3(0.0, 0.0, 0.0);
    srand(11);
    int worst_it = 0;
    int checked = 0;
    double worst_slope = 0.0;
    for (int k = 0; k < 30; ++k) {
        double x[6];
        random_pose(x);
        const cdpr_cabin_motion_t m = pose_of(x);
        cdpr_statics_result_t res;
        cdpr_statics_verdict_t why;
        const cdpr_status_t st = cdpr_statics_ik_dist(&robot, &m, zero, zero, &d, &o, &res, &why);
        TEST_ASSERT_EQUAL_INT(CDPR_OK, st);
        TEST_ASSERT_EQUAL_INT(CDPR_STATICS_WHY_NONE, why.why);
        TEST_ASSERT_EQUAL_INT(M, res.n_cables);
        worst_it = (res.iterations > worst_it) ? res.iterations : worst_it;
        double lo[M];
        double hi[M];
        TEST_ASSERT_TRUE(independent_balance(&m, &res, lo, hi) < 1e-9 * weight);
        for (int j = 0; j < M; ++j) {
            TEST_ASSERT_TRUE(lo[j] >= d.t_min_N - 1e-9 && hi[j] <= d.t_max_N + 1e-9);
        }
        int n_active = 0;
        for (int j = 0; j < M; ++j) {
            n_active += (lo[j] - d.t_min_N < 1e-3 || d.t_max_N - hi[j] < 1e-3) ? 1 : 0;
        }
        if (k < 10 && n_active == 0) {
            const int pairs[3][2] = {{0, 1}, {2, 5}, {7, 4}};
            for (int q = 0; q < 3; ++q) {
                const double sa = slope(&m, &res, pairs[q][0], pairs[q][1], &d);
                worst_slope = fmax(worst_slope, fabs(sa));
            }
            ++checked;
            cdpr_real_t L[M];
            for (int j = 0; j < M; ++j) {
                L[j] = res.cable[j].length_m;
            }
            cdpr_cabin_motion_t guess = m;
            guess.p_m = cdpr_v3(m.p_m.x + 0.01, m.p_m.y, m.p_m.z - 0.02);
            cdpr_statics_result_t fw;
            TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_statics_forward(&robot, L, &guess, &o, &fw));
            TEST_ASSERT_TRUE(cdpr_v3_norm(cdpr_v3_sub(fw.pose.p_m, m.p_m)) < 1e-8);
        }
    }
    TEST_ASSERT_TRUE(checked >= 8);
    TEST_ASSERT_TRUE(worst_slope < 1e-4);
    TEST_ASSERT_TRUE(worst_it <= 20);
}

static void test_an_active_bound_is_met_and_binding(void)
{
    /* Bounds 50-300 N: at some poses one cable's lowest tension sits at 50 N (to 1e-6 N; the
     * first three such poses with no other bound within 1e-3 N). Holding that cable's H (so its
     * tension stays at the bound) the slope along another cable is zero; raising that cable's H
     * (into the feasible side) raises the criterion: the bound's multiplier has the sign of a
     * binding lower bound. */
    build8(2.0e6, 0.14);
    gsl_set_error_handler_off();
    cdpr_statics_opts_t o;
    cdpr_statics_opts_default(&o);
    cdpr_statics_dist_t d;
    cdpr_statics_dist_init(&d, 50.0, 300.0);
    const cdpr_vec3_t zero = cdpr_v3(0.0, 0.0, 0.0);
    srand(5);
    int active = 0;
    for (int k = 0; k < 60 && active < 3; ++k) {
        double x[6];
        random_pose(x);
        const cdpr_cabin_motion_t m = pose_of(x);
        cdpr_statics_result_t res;
        if (cdpr_statics_ik_dist(&robot, &m, zero, zero, &d, &o, &res, NULL) != CDPR_OK) {
            continue;
        }
        double lo[M];
        double hi[M];
        (void)independent_balance(&m, &res, lo, hi);
        int j = -1;
        int n_active = 0;
        for (int c = 0; c < M; ++c) {
            if (fabs(lo[c] - d.t_min_N) < 1e-6) {
                j = c;
            }
            n_active += (lo[c] - d.t_min_N < 1e-3 || d.t_max_N - hi[c] < 1e-3) ? 1 : 0;
        }
        if (j < 0 || n_active != 1) {
            continue;
        }
        ++active;
        const int other = (j + 3) % M;
        TEST_ASSERT_TRUE(fabs(slope(&m, &res, other, j, &d)) < 1e-4); /* measured <= 3.2e-7 */
        double c0 = 0.0;
        double c1 = 0.0;
        double v = 0.0;
        along(&m, &res, j, res.cable[j].H_N, other, res.cable[other].H_N, &d, &c0, &v);
        along(&m, &res, j, res.cable[j].H_N * (1.0 + 1e-3), other, res.cable[other].H_N, &d, &c1,
              &v);
        TEST_ASSERT_TRUE(v <= 1e-9); /* the move stays within the bounds */
        TEST_ASSERT_TRUE(c1 > c0);
    }
    TEST_ASSERT_EQUAL_INT(3, active);
}

static void test_near_massless_cables_give_the_closed_form_distribution(void)
{
    /* rho 1e-5 kg/m and EA 1e12 N: the catenaries are nearly straight. With
     * no bound active the distribution is then the closed-form method's (minimum-norm) tensions
     * on the straight chords, computed here with GSL's LU on A A^T. */
    build8(1.0e12, 1.0e-5);
    cdpr_statics_opts_t o;
    cdpr_statics_opts_default(&o);
    cdpr_statics_dist_t d;
    cdpr_statics_dist_init(&d, 10.0, 400.0);
    const cdpr_vec3_t zero = cdpr_v3(0.0, 0.0, 0.0);
    const double x[6] = {2.0, -1.5, 14.0, 0.05, -0.03, 0.08};
    const cdpr_cabin_motion_t m = pose_of(x);
    cdpr_statics_result_t res;
    TEST_ASSERT_EQUAL_INT(CDPR_OK,
                          cdpr_statics_ik_dist(&robot, &m, zero, zero, &d, &o, &res, NULL));
    gsl_matrix *A = gsl_matrix_alloc(6, M);
    gsl_matrix *AAt = gsl_matrix_alloc(6, 6);
    gsl_vector *rhs = gsl_vector_alloc(6);
    gsl_vector *y = gsl_vector_alloc(6);
    gsl_permutation *perm = gsl_permutation_alloc(6);
    for (int j = 0; j < M; ++j) {
        const geo_t g = geo(&m, j);
        const double c = sqrt(g.l * g.l + g.h * g.h);
        const cdpr_vec3_t u = cdpr_v3(g.l * g.e.x / c, g.l * g.e.y / c, g.h / c);
        const cdpr_vec3_t mu = cdpr_v3_cross(g.arm, u);
        const double col[6] = {u.x, u.y, u.z, mu.x, mu.y, mu.z};
        for (size_t i = 0; i < 6; ++i) {
            gsl_matrix_set(A, i, (size_t)j, col[i]);
        }
    }
    const double w[6] = {0.0, 0.0, robot.p.cabin.mass_kg * robot.p.g_m_per_s2, 0.0, 0.0, 0.0};
    for (size_t i = 0; i < 6; ++i) {
        double s = w[i];
        for (size_t j = 0; j < M; ++j) {
            s -= gsl_matrix_get(A, i, j) * d.t_ref_N;
        }
        gsl_vector_set(rhs, i, s);
        for (size_t k = 0; k < 6; ++k) {
            double a = 0.0;
            for (size_t j = 0; j < M; ++j) {
                a += gsl_matrix_get(A, i, j) * gsl_matrix_get(A, k, j);
            }
            gsl_matrix_set(AAt, i, k, a);
        }
    }
    int sign = 0;
    TEST_ASSERT_EQUAL_INT(GSL_SUCCESS, gsl_linalg_LU_decomp(AAt, perm, &sign));
    TEST_ASSERT_EQUAL_INT(GSL_SUCCESS, gsl_linalg_LU_solve(AAt, perm, rhs, y));
    for (int j = 0; j < M; ++j) {
        double t = d.t_ref_N;
        for (size_t i = 0; i < 6; ++i) {
            t += gsl_matrix_get(A, i, (size_t)j) * gsl_vector_get(y, i);
        }
        TEST_ASSERT_TRUE(t > d.t_min_N && t < d.t_max_N); /* no bound active */
        /* Measured 2.2e-5 relative, proportional to rho (2.2e-4 at 1e-4 kg/m): the sag. */
        TEST_ASSERT_DOUBLE_WITHIN(1e-4 * t, t, res.cable[j].tension_cabin_N);
    }
    gsl_permutation_free(perm);
    gsl_vector_free(y);
    gsl_vector_free(rhs);
    gsl_matrix_free(AAt);
    gsl_matrix_free(A);
}

static void test_loads_no_bounded_tension_holds_are_refused(void)
{
    /* The cables' vertical pulls on the cabin sum to its weight M g = 392 N, and each is at
     * most that cable's highest tension: with t_max = 45 N < M g / 8 no equilibrium is within
     * the bounds. The verdict names a cable and its tension above the bound. */
    build8(2.0e6, 0.14);
    cdpr_statics_opts_t o;
    cdpr_statics_opts_default(&o);
    cdpr_statics_dist_t d;
    cdpr_statics_dist_init(&d, 5.0, 45.0);
    const cdpr_vec3_t zero = cdpr_v3(0.0, 0.0, 0.0);
    const double x[6] = {0.0, 0.0, 13.0, 0.0, 0.0, 0.0};
    const cdpr_cabin_motion_t m = pose_of(x);
    cdpr_statics_result_t res;
    memset(&res, 0, sizeof res);
    cdpr_statics_verdict_t why;
    TEST_ASSERT_EQUAL_INT(CDPR_E_INFEASIBLE,
                          cdpr_statics_ik_dist(&robot, &m, zero, zero, &d, &o, &res, &why));
    TEST_ASSERT_EQUAL_INT(CDPR_STATICS_WHY_T_MAX, why.why);
    TEST_ASSERT_TRUE(why.cable >= 0 && why.cable < M);
    TEST_ASSERT_TRUE(why.value > why.limit);
    TEST_ASSERT_EQUAL_DOUBLE(45.0, why.limit);
    TEST_ASSERT_EQUAL_INT(0, res.n_cables); /* nothing written */
    /* The same pose with room: solved. */
    cdpr_statics_dist_init(&d, 5.0, 400.0);
    TEST_ASSERT_EQUAL_INT(CDPR_OK,
                          cdpr_statics_ik_dist(&robot, &m, zero, zero, &d, &o, &res, &why));
}

static void test_bad_distributions_and_calls_are_refused(void)
{
    build8(2.0e6, 0.14);
    cdpr_statics_opts_t o;
    cdpr_statics_opts_default(&o);
    const cdpr_vec3_t zero = cdpr_v3(0.0, 0.0, 0.0);
    const double x[6] = {0.0, 0.0, 13.0, 0.0, 0.0, 0.0};
    const cdpr_cabin_motion_t m = pose_of(x);
    cdpr_statics_result_t res;
    cdpr_statics_dist_t d;
    cdpr_statics_dist_init(&d, 300.0, 100.0); /* T_min > T_max */
    TEST_ASSERT_EQUAL_INT(CDPR_E_OUT_OF_RANGE,
                          cdpr_statics_ik_dist(&robot, &m, zero, zero, &d, &o, &res, NULL));
    cdpr_statics_dist_init(&d, 10.0, 400.0);
    d.t_ref_N = 500.0;
    TEST_ASSERT_EQUAL_INT(CDPR_E_OUT_OF_RANGE,
                          cdpr_statics_ik_dist(&robot, &m, zero, zero, &d, &o, &res, NULL));
    cdpr_statics_dist_init(&d, -1.0, 400.0);
    TEST_ASSERT_EQUAL_INT(CDPR_E_OUT_OF_RANGE,
                          cdpr_statics_ik_dist(&robot, &m, zero, zero, &d, &o, &res, NULL));
    cdpr_statics_dist_init(&d, 10.0, (double)NAN);
    TEST_ASSERT_EQUAL_INT(CDPR_E_NOT_FINITE,
                          cdpr_statics_ik_dist(&robot, &m, zero, zero, &d, &o, &res, NULL));
    /* Eight cables need a distribution; the six-cable entry points refuse them. */
    TEST_ASSERT_EQUAL_INT(CDPR_E_INVALID_ARG,
                          cdpr_statics_ik_dist(&robot, &m, zero, zero, NULL, &o, &res, NULL));
    TEST_ASSERT_EQUAL_INT(CDPR_E_INVALID_ARG, cdpr_statics_ik(&robot, &m, &o, &res));
    TEST_ASSERT_EQUAL_INT(CDPR_E_INVALID_ARG, cdpr_statics_ik_straight(&robot, &m, &res));
}

static void test_six_cables_through_the_distribution_are_bit_identical(void)
{
    /* The 50 m model (six cables): cdpr_statics_ik_dist without bounds is
     * cdpr_statics_ik_wrench bit for bit; with bounds that hold, the same; with t_max below the
     * highest tension, refused naming that cable. */
    static cdpr_plant_params_t pp;
    test_paper_plant_params(&pp, 8); /* paper_plant.h: set A written out */
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_robot_init(&robot, &pp.robot, NULL));
    cdpr_statics_opts_t o;
    cdpr_statics_opts_default(&o);
    const double x[6] = {2.0, 1.0, 16.0, 0.0889, -0.1756, -0.03359};
    const cdpr_cabin_motion_t m = pose_of(x);
    const cdpr_vec3_t f = cdpr_v3(-30.0, 20.0, 15.0);
    const cdpr_vec3_t tau = cdpr_v3(5.0, -3.0, 8.0);
    cdpr_statics_result_t a;
    cdpr_statics_result_t b;
    memset(&a, 0, sizeof a);
    memset(&b, 0, sizeof b);
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_statics_ik_wrench(&robot, &m, f, tau, &o, &a));
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_statics_ik_dist(&robot, &m, f, tau, NULL, &o, &b, NULL));
    TEST_ASSERT_EQUAL_MEMORY(&a, &b, sizeof a);
    cdpr_statics_dist_t d;
    cdpr_statics_dist_init(&d, 1.0, 1000.0);
    memset(&b, 0, sizeof b);
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_statics_ik_dist(&robot, &m, f, tau, &d, &o, &b, NULL));
    TEST_ASSERT_EQUAL_MEMORY(&a, &b, sizeof a);
    int top = 0;
    for (int j = 1; j < 6; ++j) {
        top = (a.cable[j].tension_winch_N > a.cable[top].tension_winch_N) ? j : top;
    }
    cdpr_statics_dist_init(&d, 1.0, a.cable[top].tension_winch_N - 1.0);
    cdpr_statics_verdict_t why;
    TEST_ASSERT_EQUAL_INT(CDPR_E_INFEASIBLE,
                          cdpr_statics_ik_dist(&robot, &m, f, tau, &d, &o, &b, &why));
    TEST_ASSERT_EQUAL_INT(CDPR_STATICS_WHY_T_MAX, why.why);
    TEST_ASSERT_EQUAL_INT(top, why.cable);
    TEST_ASSERT_DOUBLE_WITHIN(1e-9, a.cable[top].tension_winch_N, why.value);
}

#else

static void test_redundant_robots_need_eight_cables_of_capacity(void)
{
    TEST_IGNORE_MESSAGE("built with CDPR_MAX_CABLES < 8");
}

#endif

int main(void)
{
    UNITY_BEGIN();
#if CDPR_MAX_CABLES >= 8
    RUN_TEST(test_distribution_balances_within_bounds_at_the_optimum);
    RUN_TEST(test_an_active_bound_is_met_and_binding);
    RUN_TEST(test_near_massless_cables_give_the_closed_form_distribution);
    RUN_TEST(test_loads_no_bounded_tension_holds_are_refused);
    RUN_TEST(test_bad_distributions_and_calls_are_refused);
    RUN_TEST(test_six_cables_through_the_distribution_are_bit_identical);
#else
    RUN_TEST(test_redundant_robots_need_eight_cables_of_capacity);
#endif
    return UNITY_END() ? 1 : 0;
}
