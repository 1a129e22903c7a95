/* SPDX-License-Identifier: BSD-3-Clause */
/// @file test_cabin.c
/// The cabin rigid body (cabin.h, docs/model.md §3) against independent computations: mass
/// properties by the parallel-axis theorem written out per element, Euler's equations in
/// principal axes, a numerically differentiated reference motion of the body origin, the
/// closed-form motion of a spinning body in a constant force field, and Rodrigues' formula
/// for the orientation under a constant body rate. Rounding tolerances are derived for double
/// and scaled for the float build as tests/support/test_real.h explains (TOL); the integrated
/// cases state their float tolerances where they are used.
#include "unity.h"
#include "ref_mat3.h"

#include "cdpr/cabin.h"
#include "cdpr/rkf45.h"
#include "test_real.h"

#include <math.h>
#include <string.h>

#define G_STD 9.80665

void setUp(void) {}

void tearDown(void) {}

/* ---------------------------------------------------------------- test-local linear algebra */

static void mat_vec(const mat_t *a, const double *x, double *out)
{
    for (int i = 0; i < 3; ++i) {
        out[i] = a->m[i][0] * x[0] + a->m[i][1] * x[1] + a->m[i][2] * x[2];
    }
}

static void mat_t_vec(const mat_t *a, const double *x, double *out)
{
    for (int i = 0; i < 3; ++i) {
        out[i] = a->m[0][i] * x[0] + a->m[1][i] * x[1] + a->m[2][i] * x[2];
    }
}

static void cross(const double *a, const double *b, double *out)
{
    const double r0 = a[1] * b[2] - a[2] * b[1];
    const double r1 = a[2] * b[0] - a[0] * b[2];
    const double r2 = a[0] * b[1] - a[1] * b[0];
    out[0] = r0;
    out[1] = r1;
    out[2] = r2;
}

/* exp(skew(phi)) by Rodrigues, with 1 - cos th = 2 sin^2(th/2) (no cancellation). */
static mat_t expm_skew(const double *phi)
{
    const double th = sqrt(phi[0] * phi[0] + phi[1] * phi[1] + phi[2] * phi[2]);
    mat_t r = {{{1.0, 0.0, 0.0}, {0.0, 1.0, 0.0}, {0.0, 0.0, 1.0}}};
    if (!(th > 0.0)) {
        return r;
    }
    const double n[3] = {phi[0] / th, phi[1] / th, phi[2] / th};
    const double k[3][3] = {{0.0, -n[2], n[1]}, {n[2], 0.0, -n[0]}, {-n[1], n[0], 0.0}};
    const double s = sin(th);
    const double c1 = 2.0 * sin(0.5 * th) * sin(0.5 * th);
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            double k2 = 0.0;
            for (int l = 0; l < 3; ++l) {
                k2 += k[i][l] * k[l][j];
            }
            r.m[i][j] += s * k[i][j] + c1 * k2;
        }
    }
    return r;
}

static cdpr_mat3_t to_cdpr(const mat_t *a)
{
    cdpr_mat3_t r;
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            r.m[i][j] = a->m[i][j];
        }
    }
    return r;
}

static mat_t diag3(double a, double b, double c)
{
    const mat_t r = {{{a, 0.0, 0.0}, {0.0, b, 0.0}, {0.0, 0.0, c}}};
    return r;
}

/* Q D Q^T: an inertia with principal axes the columns of Q. */
static mat_t rotated_inertia(const mat_t *q, double d1, double d2, double d3)
{
    const mat_t d = diag3(d1, d2, d3);
    const mat_t qd = mat_mul(q, &d);
    mat_t r;
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            r.m[i][j] = qd.m[i][0] * q->m[j][0] + qd.m[i][1] * q->m[j][1] + qd.m[i][2] * q->m[j][2];
        }
    }
    /* exactly symmetric (the validation tolerates rounding, but keep it clean) */
    for (int i = 0; i < 3; ++i) {
        for (int j = i + 1; j < 3; ++j) {
            r.m[j][i] = r.m[i][j];
        }
    }
    return r;
}

static cdpr_quat_t quat_of(double w, double x, double y, double z)
{
    cdpr_quat_t q;
    q.w = w;
    q.x = x;
    q.y = y;
    q.z = z;
    return q;
}

/* Cabin block y from plain arrays. */
static void make_state(cdpr_real_t *y, const double *p, cdpr_quat_t q, const double *v,
                       const double *w)
{
    for (int i = 0; i < 3; ++i) {
        y[CDPR_CABIN_P + i] = p[i];
        y[CDPR_CABIN_V + i] = v[i];
        y[CDPR_CABIN_W + i] = w[i];
    }
    y[CDPR_CABIN_Q + 0] = q.w;
    y[CDPR_CABIN_Q + 1] = q.x;
    y[CDPR_CABIN_Q + 2] = q.y;
    y[CDPR_CABIN_Q + 3] = q.z;
}

static cdpr_cabin_params_t cabin_params(double mass, const double *com, const mat_t *inertia)
{
    cdpr_cabin_params_t p;
    cdpr_cabin_params_default(&p);
    p.mass_kg = mass;
    p.com_body_m = cdpr_v3(com[0], com[1], com[2]);
    p.inertia_com_kg_m2 = to_cdpr(inertia);
    return p;
}

static void init_cabin(cdpr_cabin_t *cab, const cdpr_cabin_params_t *p)
{
    cdpr_diag_t d;
    TEST_ASSERT_EQUAL_INT_MESSAGE(CDPR_OK, cdpr_cabin_init(cab, p, 0, NULL, NULL, &d), d.field);
}

/* R(q) of the Euler angles, computed by the test (not by cdpr_quat_to_mat3). */
static const double EA_A = 0.3, EA_B = -0.2, EA_G = 0.5;

/* ---------------------------------------------------------------- mass properties */

static void test_combined_mass_properties(void)
{
    /* Cabin: M0 = 40 kg, CoM c0 = (0.1, -0.05, 0.2), non-diagonal inertia about c0; three
     * point masses. Expected by hand: M = M0 + sum m; C = (M0 c0 + sum m b)/M;
     * I_C = I0 + M0 [(d.d) E - d d^T] (d = c0 - C) + sum m [(r.r) E - r r^T] (r = b - C),
     * written per element below (Ixx = sum m (y^2 + z^2), Ixy = -sum m x y, ...). */
    const mat_t I0 = {{{45.0, 1.0, -2.0}, {1.0, 50.0, 0.5}, {-2.0, 0.5, 90.0}}};
    const double c0[3] = {0.1, -0.05, 0.2};
    const double M0 = 40.0;
    const double m[3] = {0.3, 0.5, 0.7};
    const double b[3][3] = {{1.0, 0.0, 0.5}, {-0.5, 0.8, 0.5}, {0.2, -0.9, -0.4}};
    const cdpr_cabin_params_t p = cabin_params(M0, c0, &I0);
    const cdpr_real_t mk[3] = {m[0], m[1], m[2]};
    const cdpr_vec3_t bk[3] = {cdpr_v3(b[0][0], b[0][1], b[0][2]),
                               cdpr_v3(b[1][0], b[1][1], b[1][2]),
                               cdpr_v3(b[2][0], b[2][1], b[2][2])};
    cdpr_cabin_t cab;
    cdpr_diag_t d;
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_cabin_init(&cab, &p, 3, mk, bk, &d));

    const double M = M0 + m[0] + m[1] + m[2];
    double C[3];
    for (int a = 0; a < 3; ++a) {
        C[a] = (M0 * c0[a] + m[0] * b[0][a] + m[1] * b[1][a] + m[2] * b[2][a]) / M;
    }
    /* Element-wise parallel-axis sums over the four bodies (cabin as a point at c0 plus I0). */
    const double masses[4] = {M0, m[0], m[1], m[2]};
    const double *pos[4] = {c0, b[0], b[1], b[2]};
    double Ixx = I0.m[0][0], Iyy = I0.m[1][1], Izz = I0.m[2][2];
    double Ixy = I0.m[0][1], Ixz = I0.m[0][2], Iyz = I0.m[1][2];
    for (int k = 0; k < 4; ++k) {
        const double x = pos[k][0] - C[0], y = pos[k][1] - C[1], z = pos[k][2] - C[2];
        Ixx += masses[k] * (y * y + z * z);
        Iyy += masses[k] * (x * x + z * z);
        Izz += masses[k] * (x * x + y * y);
        Ixy -= masses[k] * x * y;
        Ixz -= masses[k] * x * z;
        Iyz -= masses[k] * y * z;
    }
    /* Mass: 4 additions of exact-ish decimals, 1e-15 relative is already 4 u; use 1e-14. */
    TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-14, 6e-6) * M, M, cab.mass_kg);
    /* CoM: sums of products of O(1) numbers divided by M: error ~ 10 u * max|b|: 1e-15 m;
     * tolerance 1e-13 m. Moving the CoM by a wrong weighting would shift it by > 1e-3 m. */
    TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-13, 6e-5), C[0], cab.com_body_m.x);
    TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-13, 6e-5), C[1], cab.com_body_m.y);
    TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-13, 6e-5), C[2], cab.com_body_m.z);
    /* Inertia: entries up to 90 kg m^2, each a sum of ~10 products: 1e-12 relative to 90. */
    const double tol = TOL(1e-12, 6e-4) * 90.0;
    const double expected[3][3] = {{Ixx, Ixy, Ixz}, {Ixy, Iyy, Iyz}, {Ixz, Iyz, Izz}};
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            TEST_ASSERT_DOUBLE_WITHIN(tol, expected[i][j], cab.inertia_kg_m2.m[i][j]);
        }
    }
    /* The stored inverse really inverts it: I I^-1 = E; condition number ~2, 1e-13. */
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            double s = 0.0;
            for (int k = 0; k < 3; ++k) {
                s += cab.inertia_kg_m2.m[i][k] * cab.inv_inertia.m[k][j];
            }
            TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-13, 6e-5), (i == j) ? 1.0 : 0.0, s);
        }
    }
    /* The cabin-alone parameters are kept. */
    TEST_ASSERT_EQUAL_MEMORY(&p, &cab.p, sizeof p);
}

static void test_no_points_gives_the_cabin_itself(void)
{
    const mat_t I0 = {{{2.0, 0.1, 0.0}, {0.1, 3.0, -0.2}, {0.0, -0.2, 4.0}}};
    const double c0[3] = {0.1, -0.05, 0.2};
    const cdpr_cabin_params_t p = cabin_params(40.0, c0, &I0);
    cdpr_cabin_t cab;
    init_cabin(&cab, &p);
    /* c0 * M / M: two roundings, 1e-16 m; I unchanged up to adding 0: exact within 1e-15. */
    TEST_ASSERT_DOUBLE_WITHIN(0.0, 40.0, cab.mass_kg);
    TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-16, 6e-8), c0[0], cab.com_body_m.x);
    TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-16, 6e-8), c0[1], cab.com_body_m.y);
    TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-16, 6e-8), c0[2], cab.com_body_m.z);
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-15, 6e-7), I0.m[i][j], cab.inertia_kg_m2.m[i][j]);
        }
    }
}

/* ---------------------------------------------------------------- free flight */

static void test_free_fall_without_rotation(void)
{
    /* No force, no rotation: v_dot = -g z exactly (every other term is a product with 0),
     * p_dot = v (copy), q_dot = 0. The CoM offset must not matter when w = 0. */
    const double c0[3] = {0.1, -0.05, 0.2};
    const mat_t I = diag3(2.0, 3.0, 4.0);
    const cdpr_cabin_params_t p = cabin_params(40.0, c0, &I);
    cdpr_cabin_t cab;
    init_cabin(&cab, &p);
    const double pos[3] = {1.0, 2.0, 3.0}, v[3] = {0.5, -0.2, 0.1}, w[3] = {0.0, 0.0, 0.0};
    cdpr_real_t y[13], dydt[13];
    make_state(y, pos, cdpr_quat_from_euler(EA_A, EA_B, EA_G), v, w);
    cdpr_cabin_rhs(&cab, y, cdpr_v3(0.0, 0.0, 0.0), cdpr_v3(0.0, 0.0, 0.0), G_STD, dydt);
    for (int i = 0; i < 3; ++i) {
        /* exact copy of the state's velocity (v rounded to cdpr_real_t by make_state) */
        TEST_ASSERT_DOUBLE_WITHIN(0.0, (cdpr_real_t)v[i], dydt[CDPR_CABIN_P + i]);
        TEST_ASSERT_DOUBLE_WITHIN(0.0, 0.0, dydt[CDPR_CABIN_W + i]);
    }
    for (int i = 0; i < 4; ++i) {
        TEST_ASSERT_DOUBLE_WITHIN(0.0, 0.0, dydt[CDPR_CABIN_Q + i]);
    }
    TEST_ASSERT_DOUBLE_WITHIN(0.0, 0.0, dydt[CDPR_CABIN_V + 0]);
    TEST_ASSERT_DOUBLE_WITHIN(0.0, 0.0, dydt[CDPR_CABIN_V + 1]);
    TEST_ASSERT_DOUBLE_WITHIN(0.0, -(cdpr_real_t)G_STD, dydt[CDPR_CABIN_V + 2]);
    /* A force through the CoM with w = 0: a = F/M - g z (relative 1e-15: one division). */
    cdpr_cabin_rhs(&cab, y, cdpr_v3(8.0, -4.0, 600.0), cdpr_v3(0.0, 0.0, 0.0), G_STD, dydt);
    TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-15, 6e-7), 0.2, dydt[CDPR_CABIN_V + 0]);
    TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-15, 6e-7), -0.1, dydt[CDPR_CABIN_V + 1]);
    TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-14, 6e-6), 15.0 - G_STD, dydt[CDPR_CABIN_V + 2]);
}

static void test_spin_about_principal_axis(void)
{
    /* Diagonal inertia, w = (0, 0, 5) about the z principal axis: w x I w = 0 exactly, so
     * w_dot = 0 exactly. The body yaws by phi about world z (q = (cos phi/2, 0, 0, sin phi/2)),
     * so r_c = Rz(phi) c and w_w = (0, 0, 5): the origin, rigidly attached at -r_c from the
     * CoM, has the centripetal acceleration -w_w x (w_w x r_c) = 25 (r_c.x, r_c.y, 0). */
    const double c0[3] = {0.1, -0.05, 0.2};
    const mat_t I = diag3(2.0, 3.0, 4.0);
    const cdpr_cabin_params_t p = cabin_params(40.0, c0, &I);
    cdpr_cabin_t cab;
    init_cabin(&cab, &p);
    const double phi = 0.7;
    const double pos[3] = {0.0, 0.0, 0.0}, v[3] = {0.0, 0.0, 0.0}, w[3] = {0.0, 0.0, 5.0};
    cdpr_real_t y[13], dydt[13];
    make_state(y, pos, quat_of(cos(0.5 * phi), 0.0, 0.0, sin(0.5 * phi)), v, w);
    cdpr_cabin_rhs(&cab, y, cdpr_v3(0.0, 0.0, 0.0), cdpr_v3(0.0, 0.0, 0.0), G_STD, dydt);
    for (int i = 0; i < 3; ++i) {
        TEST_ASSERT_DOUBLE_WITHIN(0.0, 0.0, dydt[CDPR_CABIN_W + i]);
    }
    const double rcx = cos(phi) * c0[0] - sin(phi) * c0[1];
    const double rcy = sin(phi) * c0[0] + cos(phi) * c0[1];
    /* 25 * 0.11 = 2.8 m/s^2 from ~20 roundings: 1e-14 absolute. */
    TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-14, 6e-6), 25.0 * rcx, dydt[CDPR_CABIN_V + 0]);
    TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-14, 6e-6), 25.0 * rcy, dydt[CDPR_CABIN_V + 1]);
    TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-14, 6e-6), -G_STD, dydt[CDPR_CABIN_V + 2]);

    /* Tilted principal axes: I = Q diag(2, 3, 4) Q^T, w along the first principal axis
     * (first column of Q): w_dot = 0 up to rounding. Scale |w|^2 max(I)/min(I) = 25 * 2,
     * relative 1e-14: 5e-13. */
    const mat_t Q = euler_matrix(0.4, -0.9, 1.3);
    const mat_t Ir = rotated_inertia(&Q, 2.0, 3.0, 4.0);
    const cdpr_cabin_params_t pr = cabin_params(40.0, c0, &Ir);
    init_cabin(&cab, &pr);
    const double wr[3] = {5.0 * Q.m[0][0], 5.0 * Q.m[1][0], 5.0 * Q.m[2][0]};
    make_state(y, pos, cdpr_quat_from_euler(EA_A, EA_B, EA_G), v, wr);
    cdpr_cabin_rhs(&cab, y, cdpr_v3(0.0, 0.0, 0.0), cdpr_v3(0.0, 0.0, 0.0), G_STD, dydt);
    for (int i = 0; i < 3; ++i) {
        TEST_ASSERT_DOUBLE_WITHIN(TOL(5e-13, 3e-4), 0.0, dydt[CDPR_CABIN_W + i]);
    }
}

static void test_torque_free_asymmetric_body(void)
{
    /* Euler's equations in principal axes: I1 w1' = (I2 - I3) w2 w3 (cyclic).
     * I = diag(2, 3, 4), w = (1, -2, 3):
     * w1' = (3 - 4)(-2)(3)/2 = 3, w2' = (4 - 2)(3)(1)/3 = 2, w3' = (2 - 3)(1)(-2)/4 = 0.5.
     * Small integers and halves: the core's result has a few roundings at most: 1e-14. */
    const double c0[3] = {0.0, 0.0, 0.0};
    const mat_t I = diag3(2.0, 3.0, 4.0);
    const cdpr_cabin_params_t p = cabin_params(40.0, c0, &I);
    cdpr_cabin_t cab;
    init_cabin(&cab, &p);
    const double pos[3] = {0.0, 0.0, 0.0}, v[3] = {0.0, 0.0, 0.0}, w[3] = {1.0, -2.0, 3.0};
    cdpr_real_t y[13], dydt[13];
    make_state(y, pos, cdpr_quat_from_euler(EA_A, EA_B, EA_G), v, w);
    cdpr_cabin_rhs(&cab, y, cdpr_v3(0.0, 0.0, 0.0), cdpr_v3(0.0, 0.0, 0.0), G_STD, dydt);
    TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-14, 6e-6), 3.0, dydt[CDPR_CABIN_W + 0]);
    TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-14, 6e-6), 2.0, dydt[CDPR_CABIN_W + 1]);
    TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-14, 6e-6), 0.5, dydt[CDPR_CABIN_W + 2]);

    /* Same body with principal axes tilted by Q (body inertia Q D Q^T, non-diagonal):
     * w_p = Q^T w, Euler's equations in the principal frame, w' = Q w_p'.
     * |w'| ~ 4; matrix products add ~30 u relative to |w|^2 I3/I1 = 28: 1e-13. */
    const mat_t Q = euler_matrix(-0.6, 0.35, 2.1);
    const mat_t Ir = rotated_inertia(&Q, 2.0, 3.0, 4.0);
    const cdpr_cabin_params_t pr = cabin_params(40.0, c0, &Ir);
    init_cabin(&cab, &pr);
    const double wb[3] = {0.7, -1.3, 2.2};
    make_state(y, pos, cdpr_quat_from_euler(EA_A, EA_B, EA_G), v, wb);
    cdpr_cabin_rhs(&cab, y, cdpr_v3(0.0, 0.0, 0.0), cdpr_v3(0.0, 0.0, 0.0), G_STD, dydt);
    double wp[3];
    mat_t_vec(&Q, wb, wp);
    const double D[3] = {2.0, 3.0, 4.0};
    const double wpd[3] = {(D[1] - D[2]) * wp[1] * wp[2] / D[0],
                           (D[2] - D[0]) * wp[2] * wp[0] / D[1],
                           (D[0] - D[1]) * wp[0] * wp[1] / D[2]};
    double wd[3];
    mat_vec(&Q, wpd, wd);
    for (int i = 0; i < 3; ++i) {
        TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-13, 6e-5), wd[i], dydt[CDPR_CABIN_W + i]);
    }
}

static void test_torque_from_rest(void)
{
    /* w = 0: I w' = tau. Checked by multiplying back with the (test's) inertia matrix, so the
     * core's inverse is checked independently. Entries ~50, tau ~10: 1e-13 relative. */
    const double c0[3] = {0.1, 0.0, -0.1};
    const mat_t I = {{{45.0, 1.0, -2.0}, {1.0, 50.0, 0.5}, {-2.0, 0.5, 90.0}}};
    const cdpr_cabin_params_t p = cabin_params(40.0, c0, &I);
    cdpr_cabin_t cab;
    init_cabin(&cab, &p);
    const double pos[3] = {0.0, 0.0, 0.0}, v[3] = {0.0, 0.0, 0.0}, w[3] = {0.0, 0.0, 0.0};
    cdpr_real_t y[13], dydt[13];
    make_state(y, pos, cdpr_quat_from_euler(EA_A, EA_B, EA_G), v, w);
    const double tau[3] = {3.0, -7.0, 11.0};
    cdpr_cabin_rhs(&cab, y, cdpr_v3(0.0, 0.0, 0.0), cdpr_v3(tau[0], tau[1], tau[2]), G_STD, dydt);
    const double wd[3] = {dydt[CDPR_CABIN_W], dydt[CDPR_CABIN_W + 1], dydt[CDPR_CABIN_W + 2]};
    double back[3];
    mat_vec(&I, wd, back);
    for (int i = 0; i < 3; ++i) {
        TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-13, 6e-5) * 11.0, tau[i], back[i]);
    }
}

/* ---------------------------------------------------------------- offset centre of mass */

/* Reference motion of the body origin: CoM on a parabola, orientation
 * R(t) = R0 exp(skew(w t + wd t^2 / 2)) (exact to second order in t: R' = R [w],
 * R'' = R ([w]^2 + [wd]) at t = 0), origin p(t) = x_c(t) - R(t) c. */
typedef struct {
    mat_t R0;
    double c[3], xc0[3], vc0[3], ac[3], w[3], wd[3];
} ref_motion_t;

static void ref_origin(const ref_motion_t *m, double t, double *p)
{
    double phi[3];
    for (int i = 0; i < 3; ++i) {
        phi[i] = m->w[i] * t + 0.5 * m->wd[i] * t * t;
    }
    const mat_t E = expm_skew(phi);
    const mat_t R = mat_mul(&m->R0, &E);
    double rc[3];
    mat_vec(&R, m->c, rc);
    for (int i = 0; i < 3; ++i) {
        p[i] = m->xc0[i] + m->vc0[i] * t + 0.5 * m->ac[i] * t * t - rc[i];
    }
}

static void test_force_through_origin_with_offset_com(void)
{
    /* A force F through the body origin (not the CoM) of a spinning body: torque about the CoM
     * tau = (0 - c) x (R^T F) (body axes). Expected w' from Euler's equations with that
     * torque; expected origin acceleration from a second difference of the reference motion
     * above (Richardson-extrapolated), which needs no formula for v'. */
    const double c[3] = {0.1, -0.05, 0.2};
    const double D[3] = {2.0, 3.0, 4.0};
    const mat_t I = diag3(D[0], D[1], D[2]);
    const double M = 40.0;
    const cdpr_cabin_params_t p = cabin_params(M, c, &I);
    cdpr_cabin_t cab;
    init_cabin(&cab, &p);

    const double pos[3] = {0.3, -0.2, 0.1}, v[3] = {0.5, -0.2, 0.1}, w[3] = {0.4, -0.3, 0.7};
    const double F[3] = {10.0, -20.0, 30.0};
    cdpr_real_t y[13], dydt[13];
    make_state(y, pos, cdpr_quat_from_euler(EA_A, EA_B, EA_G), v, w);
    const mat_t R0 = euler_matrix(EA_A, EA_B, EA_G);
    double Fb[3], tau[3];
    mat_t_vec(&R0, F, Fb);
    const double minus_c[3] = {-c[0], -c[1], -c[2]};
    cross(minus_c, Fb, tau);
    cdpr_cabin_rhs(&cab, y, cdpr_v3(F[0], F[1], F[2]), cdpr_v3(tau[0], tau[1], tau[2]), G_STD,
                   dydt);

    /* Euler: I1 w1' + (I3 - I2) w2 w3 = tau1 (cyclic). O(1) numbers: 1e-14. */
    const double wd[3] = {(tau[0] - (D[2] - D[1]) * w[1] * w[2]) / D[0],
                          (tau[1] - (D[0] - D[2]) * w[2] * w[0]) / D[1],
                          (tau[2] - (D[1] - D[0]) * w[0] * w[1]) / D[2]};
    for (int i = 0; i < 3; ++i) {
        TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-14, 6e-6), wd[i], dydt[CDPR_CABIN_W + i]);
    }

    /* Reference motion consistent with the state: CoM velocity v + w_w x r_c. */
    ref_motion_t m;
    m.R0 = R0;
    double rc[3], ww[3], wxr[3];
    mat_vec(&R0, c, rc);
    mat_vec(&R0, w, ww);
    cross(ww, rc, wxr);
    for (int i = 0; i < 3; ++i) {
        m.c[i] = c[i];
        m.xc0[i] = pos[i] + rc[i];
        m.vc0[i] = v[i] + wxr[i];
        m.ac[i] = F[i] / M - ((i == 2) ? G_STD : 0.0);
        m.w[i] = w[i];
        m.wd[i] = wd[i];
    }
    /* D(h) = (p(h) - 2 p(0) + p(-h)) / h^2 = p'' + K h^2 + O(h^4); Richardson
     * (4 D(h/2) - D(h)) / 3 removes K h^2. Rounding: |p| < 1 is evaluated to ~4 u, so
     * D(h/2) carries 4 * 4e-16 / (5e-4)^2 = 6.4e-9 and the extrapolation ~1e-8; the
     * O(h^4) truncation is ~1e-12. Tolerance 1e-7 m/s^2 on accelerations of ~10 m/s^2;
     * dropping any one term of v' (w' x r_c ~ 0.5, w x (w x r_c) ~ 0.1) fails by far. */
    const double h = 1e-3;
    double p0[3], pp[3], pm[3], pp2[3], pm2[3];
    ref_origin(&m, 0.0, p0);
    ref_origin(&m, h, pp);
    ref_origin(&m, -h, pm);
    ref_origin(&m, 0.5 * h, pp2);
    ref_origin(&m, -0.5 * h, pm2);
    for (int i = 0; i < 3; ++i) {
        /* the reference starts where the state is, moving as the state says */
        TEST_ASSERT_DOUBLE_WITHIN(1e-15, pos[i], p0[i]);
        TEST_ASSERT_DOUBLE_WITHIN(1e-6, v[i], (pp2[i] - pm2[i]) / h);
        const double d1 = (pp[i] - 2.0 * p0[i] + pm[i]) / (h * h);
        const double d2 = (pp2[i] - 2.0 * p0[i] + pm2[i]) / (0.25 * h * h);
        const double acc = (4.0 * d2 - d1) / 3.0;
        /* float: the core's ~30 roundings on accelerations of ~10 m/s^2 are 30 u_f * 10 =
         * 2e-5, which the reference's 1e-8 does not change. */
        TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-7, 2e-5), acc, dydt[CDPR_CABIN_V + i]);
    }
}

typedef struct {
    const cdpr_cabin_t *cab;
    cdpr_vec3_t force;
    cdpr_vec3_t torque;
} cabin_ctx_t;

static cdpr_status_t rhs_cabin(cdpr_real_t t, const cdpr_real_t *y, cdpr_real_t *dydt, void *ctx)
{
    const cabin_ctx_t *c = ctx;
    (void)t;
    cdpr_cabin_rhs(c->cab, y, c->force, c->torque, G_STD, dydt);
    return CDPR_OK;
}

static cdpr_real_t rk_work[CDPR_RKF45_WORK_PER_DIM * CDPR_CABIN_STATE_DIM];

static void init_rk(cdpr_rkf45_t *s, double tol)
{
    cdpr_rkf45_params_t p;
    cdpr_rkf45_params_default(&p);
    p.step.rtol = tol;
    p.step.atol = tol;
    TEST_ASSERT_EQUAL_INT(CDPR_OK,
                          cdpr_rkf45_init(s, &p, rk_work, (int)(sizeof rk_work / sizeof rk_work[0]),
                                          CDPR_CABIN_STATE_DIM, CDPR_CABIN_STATE_DIM, NULL));
}

static void test_offset_com_spinning_in_constant_force_closed_form(void)
{
    /* Constant force through the CoM (no torque), spin w about the body z principal axis:
     * w stays constant, R(t) = R0 Rz(w t), the CoM follows the parabola
     * x_c(t) = x_c0 + v_c0 t + (F/M - g z) t^2 / 2, and the body origin is
     * p(t) = x_c(t) - R(t) c. Integrated with cdpr_rkf45 at tol 1e-11. */
    const double c[3] = {0.1, -0.05, 0.2};
    const mat_t I = diag3(2.0, 3.0, 4.0);
    const double M = 40.0, wz = 1.3;
    const cdpr_cabin_params_t prm = cabin_params(M, c, &I);
    cdpr_cabin_t cab;
    init_cabin(&cab, &prm);
    const mat_t R0 = euler_matrix(EA_A, EA_B, EA_G);
    const double F[3] = {4.0, -8.0, 300.0};
    const double vc0[3] = {0.5, -0.2, 1.0};
    const double p0[3] = {1.0, 2.0, 3.0};
    double rc[3], ww[3], wxr[3];
    mat_vec(&R0, c, rc);
    const double wb[3] = {0.0, 0.0, wz};
    mat_vec(&R0, wb, ww);
    cross(ww, rc, wxr);
    const double v0[3] = {vc0[0] - wxr[0], vc0[1] - wxr[1], vc0[2] - wxr[2]};
    cdpr_real_t y[13];
    make_state(y, p0, cdpr_quat_from_euler(EA_A, EA_B, EA_G), v0, wb);

    cabin_ctx_t ctx = {&cab, cdpr_v3(F[0], F[1], F[2]), cdpr_v3(0.0, 0.0, 0.0)};
    cdpr_rkf45_t rk;
    /* float: 1e-6 is about the smallest request float can honour on |y| <= 25 (u_f |y| =
     * 1.5e-6): asking for less only adds steps whose rounding then dominates (measured on the
     * host float build: 8e-6 m at 1e-11 against 2.4e-6 m at 1e-6). */
    init_rk(&rk, TOL(1e-11, 1e-6));
    cdpr_real_t t = 0.0;
    for (int k = 1; k <= 6; ++k) {
        TEST_ASSERT_EQUAL_INT(CDPR_OK,
                              cdpr_rkf45_advance(&rk, rhs_cabin, &ctx, &t, y, 0.5, 100000));
        const mat_t Rz = {
            {{cos(wz * t), -sin(wz * t), 0.0}, {sin(wz * t), cos(wz * t), 0.0}, {0.0, 0.0, 1.0}}};
        const mat_t R = mat_mul(&R0, &Rz);
        double rct[3];
        mat_vec(&R, c, rct);
        /* Integration error: local tolerance 1e-11 of |y| <= 25 over ~100 steps, i.e.
         * below 1e-8 (see test_rkf45 for the observed global/tolerance ratios); a missing
         * centripetal or Euler term changes p by > 1e-3 m over 3 s.
         * float: no error bound follows from the local tolerance over ~100 steps with rounding
         * of 1.5e-6 m each; the tolerances are 8x the largest error measured on the host float
         * build and on QEMU's Cortex-M4 (2.4e-6 m, w 5e-8 rad/s, R 7e-7), still 50x below the
         * effect of a missing term. */
        for (int i = 0; i < 3; ++i) {
            const double ac = F[i] / M - ((i == 2) ? G_STD : 0.0);
            const double expected = p0[i] + rc[i] + vc0[i] * t + 0.5 * ac * t * t - rct[i];
            TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-8, 2e-5), expected, y[CDPR_CABIN_P + i]);
            TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-9, 4e-7), wb[i], y[CDPR_CABIN_W + i]);
        }
        cdpr_mat3_t Rq;
        cdpr_quat_to_mat3(cdpr_quat_normalize(quat_of(y[CDPR_CABIN_Q], y[CDPR_CABIN_Q + 1],
                                                      y[CDPR_CABIN_Q + 2], y[CDPR_CABIN_Q + 3])),
                          &Rq);
        for (int i = 0; i < 3; ++i) {
            for (int j = 0; j < 3; ++j) {
                TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-9, 6e-6), R.m[i][j], Rq.m[i][j]);
            }
        }
    }
}

static void test_quaternion_kinematics_constant_rate(void)
{
    /* Spherical inertia: w x I w = 0 for any w, so w is constant and
     * R(T) = R0 exp(skew(w T)) (body rate: right multiplication). Integrating
     * q' = q (x) (0, w) / 2 must reproduce it (compared as rotation matrices). */
    const double c[3] = {0.0, 0.0, 0.0};
    const mat_t I = diag3(5.0, 5.0, 5.0);
    const cdpr_cabin_params_t prm = cabin_params(10.0, c, &I);
    cdpr_cabin_t cab;
    init_cabin(&cab, &prm);
    const double w[3] = {0.7, -1.1, 0.4}, pos[3] = {0.0, 0.0, 0.0}, v[3] = {0.0, 0.0, 0.0};
    cdpr_real_t y[13];
    make_state(y, pos, cdpr_quat_from_euler(EA_A, EA_B, EA_G), v, w);
    cabin_ctx_t ctx = {&cab, cdpr_v3(0.0, 0.0, 0.0), cdpr_v3(0.0, 0.0, 0.0)};
    cdpr_rkf45_t rk;
    init_rk(&rk, TOL(1e-12, 1e-6)); /* float: as in the previous test */
    cdpr_real_t t = 0.0;
    const double T = 2.5;
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_rkf45_advance(&rk, rhs_cabin, &ctx, &t, y, T, 100000));
    const double phi[3] = {w[0] * T, w[1] * T, w[2] * T};
    const mat_t R0 = euler_matrix(EA_A, EA_B, EA_G);
    const mat_t E = expm_skew(phi);
    const mat_t expected = mat_mul(&R0, &E);
    cdpr_mat3_t Rq;
    const cdpr_quat_t q =
        quat_of(y[CDPR_CABIN_Q], y[CDPR_CABIN_Q + 1], y[CDPR_CABIN_Q + 2], y[CDPR_CABIN_Q + 3]);
    cdpr_quat_to_mat3(cdpr_quat_normalize(q), &Rq);
    /* Tolerance 1e-12 per step on |q| = 1 over a 3.4 rad rotation: global error well below
     * 1e-9; a sign error in q' (q' = (0, w) (x) q / 2, world rate) fails by O(1).
     * float: 8x the largest error measured in float (R 4e-7, |q|^2 - 1 2e-6). */
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-9, 4e-6), expected.m[i][j], Rq.m[i][j]);
        }
    }
    /* The exact flow keeps |q| = 1; the integrated one to the same accuracy. */
    TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-9, 2e-5), 1.0, q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z);
    /* Body position and velocity untouched (no force, g only on v): x, y stay 0 exactly. */
    TEST_ASSERT_DOUBLE_WITHIN(0.0, 0.0, y[CDPR_CABIN_P + 0]);
    TEST_ASSERT_DOUBLE_WITHIN(0.0, 0.0, y[CDPR_CABIN_V + 1]);
}

static void test_quaternion_derivative_is_orthogonal_to_q(void)
{
    /* q' = q (x) (0, w)/2 has q . q' = 0 (norm-preserving flow): exact up to rounding of
     * O(|w|) terms, 1e-15. Also |q'| = |w|/2 for unit q. */
    const double c[3] = {0.0, 0.0, 0.0};
    const mat_t I = diag3(2.0, 3.0, 4.0);
    const cdpr_cabin_params_t prm = cabin_params(10.0, c, &I);
    cdpr_cabin_t cab;
    init_cabin(&cab, &prm);
    const double w[3] = {0.7, -1.1, 0.4}, pos[3] = {0.0, 0.0, 0.0}, v[3] = {0.0, 0.0, 0.0};
    cdpr_real_t y[13], dydt[13];
    const cdpr_quat_t q = cdpr_quat_from_euler(1.2, -0.4, -2.0);
    make_state(y, pos, q, v, w);
    cdpr_cabin_rhs(&cab, y, cdpr_v3(0.0, 0.0, 0.0), cdpr_v3(0.0, 0.0, 0.0), G_STD, dydt);
    const cdpr_real_t *qd = &dydt[CDPR_CABIN_Q];
    TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-15, 6e-7), 0.0,
                              q.w * qd[0] + q.x * qd[1] + q.y * qd[2] + q.z * qd[3]);
    const double nw = sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
    TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-15, 6e-7), 0.5 * nw,
                              sqrt(qd[0] * qd[0] + qd[1] * qd[1] + qd[2] * qd[2] + qd[3] * qd[3]));
    /* Hand expansion of the w component: q' w = -(x w1 + y w2 + z w3)/2. */
    TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-15, 6e-7), -0.5 * (q.x * w[0] + q.y * w[1] + q.z * w[2]),
                              qd[0]);
}

static void test_motion_get_set_round_trip(void)
{
    cdpr_cabin_motion_t m;
    m.p_m = cdpr_v3(1.0, 2.0, 3.0);
    m.q = quat_of(0.5, -0.5, 0.5, 0.5);
    m.v_m_per_s = cdpr_v3(4.0, 5.0, 6.0);
    m.w_rad_per_s = cdpr_v3(7.0, 8.0, 9.0);
    cdpr_real_t y[13];
    cdpr_cabin_set_motion(&m, y);
    const cdpr_real_t expected[13] = {1.0, 2.0, 3.0, 0.5, -0.5, 0.5, 0.5,
                                      4.0, 5.0, 6.0, 7.0, 8.0,  9.0};
    TEST_ASSERT_EQUAL_MEMORY(expected, y, sizeof y);
    cdpr_cabin_motion_t back;
    cdpr_cabin_get_motion(y, &back);
    TEST_ASSERT_EQUAL_MEMORY(&m, &back, sizeof m);
}

/* ---------------------------------------------------------------- validation */

typedef struct {
    const char *name;
    int what;     /* 0 mass, 1 com.x, 2 inertia element, 3 inertia pair (asymmetric), 4 matrix */
    int i, j;     /* element */
    double value; /* bad value */
    cdpr_status_t status;
    const char *field;
    int index;
} cabin_case_t;

static void test_validation_names_the_field(void)
{
    static const cabin_case_t cases[] = {
        {"mass NaN", 0, 0, 0, NAN_D, CDPR_E_NOT_FINITE, "cabin.mass_kg", -1},
        {"mass Inf", 0, 0, 0, INF_D, CDPR_E_NOT_FINITE, "cabin.mass_kg", -1},
        {"mass 0", 0, 0, 0, 0.0, CDPR_E_NOT_POSITIVE, "cabin.mass_kg", -1},
        {"mass -1", 0, 0, 0, -1.0, CDPR_E_NOT_POSITIVE, "cabin.mass_kg", -1},
        {"com NaN", 1, 0, 0, NAN_D, CDPR_E_NOT_FINITE, "cabin.com_body_m", -1},
        {"com -Inf", 1, 0, 0, -INF_D, CDPR_E_NOT_FINITE, "cabin.com_body_m", -1},
        {"inertia NaN (1,2)", 2, 1, 2, NAN_D, CDPR_E_NOT_FINITE, "cabin.inertia_com_kg_m2", 5},
        {"inertia NaN (0,0)", 2, 0, 0, NAN_D, CDPR_E_NOT_FINITE, "cabin.inertia_com_kg_m2", 0},
        {"inertia Inf (2,0)", 2, 2, 0, INF_D, CDPR_E_NOT_FINITE, "cabin.inertia_com_kg_m2", 6},
        {"asymmetric (0,1)", 3, 0, 1, 2.0, CDPR_E_OUT_OF_RANGE, "cabin.inertia_com_kg_m2", 1},
        {"asymmetric (1,2)", 3, 1, 2, -3.0, CDPR_E_OUT_OF_RANGE, "cabin.inertia_com_kg_m2", 5},
        {"negative diagonal", 2, 2, 2, -1.0, CDPR_E_NOT_POSITIVE, "cabin.inertia_com_kg_m2", -1},
        {"zero diagonal", 2, 0, 0, 0.0, CDPR_E_NOT_POSITIVE, "cabin.inertia_com_kg_m2", -1},
        {"indefinite", 4, 0, 0, 0.0, CDPR_E_NOT_POSITIVE, "cabin.inertia_com_kg_m2", -1},
    };
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; ++k) {
        const cabin_case_t *c = &cases[k];
        cdpr_cabin_params_t p;
        cdpr_cabin_params_default(&p);
        switch (c->what) {
        case 0:
            p.mass_kg = c->value;
            break;
        case 1:
            p.com_body_m.x = c->value;
            break;
        case 2:
            p.inertia_com_kg_m2.m[c->i][c->j] = c->value;
            break;
        case 3: /* (i,j) != (j,i) by more than rounding */
            p.inertia_com_kg_m2.m[c->i][c->j] = c->value;
            p.inertia_com_kg_m2.m[c->j][c->i] = 0.0;
            break;
        default: { /* symmetric, positive diagonal, but det < 0: [[45,50,0],[50,45,0],[0,0,90]] */
            p.inertia_com_kg_m2.m[0][1] = 50.0;
            p.inertia_com_kg_m2.m[1][0] = 50.0;
            break;
        }
        }
        cdpr_diag_t d;
        memset(&d, 0, sizeof d);
        TEST_ASSERT_EQUAL_INT_MESSAGE(c->status, cdpr_cabin_params_validate(&p, &d), c->name);
        TEST_ASSERT_EQUAL_STRING_MESSAGE(c->field, d.field, c->name);
        TEST_ASSERT_EQUAL_INT_MESSAGE(c->index, d.index, c->name);
        /* init reports the same and leaves the object untouched. */
        cdpr_cabin_t cab;
        memset(&cab, 0xA5, sizeof cab);
        cdpr_cabin_t before;
        memcpy(&before, &cab, sizeof cab);
        TEST_ASSERT_EQUAL_INT_MESSAGE(c->status, cdpr_cabin_init(&cab, &p, 0, NULL, NULL, &d),
                                      c->name);
        TEST_ASSERT_EQUAL_STRING_MESSAGE(c->field, d.field, c->name);
        TEST_ASSERT_EQUAL_MEMORY_MESSAGE(&before, &cab, sizeof cab, c->name);
    }
    /* The defaults are valid. */
    cdpr_cabin_params_t p;
    cdpr_cabin_params_default(&p);
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_cabin_params_validate(&p, NULL));
}

static void test_point_mass_validation(void)
{
    cdpr_cabin_params_t p;
    cdpr_cabin_params_default(&p);
    cdpr_real_t m[3] = {0.1, 0.2, 0.3};
    cdpr_vec3_t b[3] = {cdpr_v3(1.0, 0.0, 0.0), cdpr_v3(0.0, 1.0, 0.0), cdpr_v3(0.0, 0.0, 1.0)};
    cdpr_cabin_t cab;
    memset(&cab, 0xA5, sizeof cab);
    cdpr_cabin_t before;
    memcpy(&before, &cab, sizeof cab);
    cdpr_diag_t d;

    m[2] = -0.1;
    TEST_ASSERT_EQUAL_INT(CDPR_E_OUT_OF_RANGE, cdpr_cabin_init(&cab, &p, 3, m, b, &d));
    TEST_ASSERT_EQUAL_STRING("point_mass_kg", d.field);
    TEST_ASSERT_EQUAL_INT(2, d.index);
    m[2] = 0.3;
    m[1] = NAN_R;
    TEST_ASSERT_EQUAL_INT(CDPR_E_NOT_FINITE, cdpr_cabin_init(&cab, &p, 3, m, b, &d));
    TEST_ASSERT_EQUAL_STRING("point_mass_kg", d.field);
    TEST_ASSERT_EQUAL_INT(1, d.index);
    m[1] = 0.2;
    b[1].z = INF_R;
    TEST_ASSERT_EQUAL_INT(CDPR_E_NOT_FINITE, cdpr_cabin_init(&cab, &p, 3, m, b, &d));
    TEST_ASSERT_EQUAL_STRING("point_body_m", d.field);
    TEST_ASSERT_EQUAL_INT(1, d.index);
    b[1].z = 0.0;
    TEST_ASSERT_EQUAL_INT(CDPR_E_INVALID_ARG, cdpr_cabin_init(&cab, &p, -1, m, b, &d));
    TEST_ASSERT_EQUAL_INT(CDPR_E_INVALID_ARG, cdpr_cabin_init(&cab, &p, 3, NULL, b, &d));
    TEST_ASSERT_EQUAL_INT(CDPR_E_INVALID_ARG, cdpr_cabin_init(&cab, &p, 3, m, NULL, &d));
    TEST_ASSERT_EQUAL_INT(CDPR_E_INVALID_ARG, cdpr_cabin_init(NULL, &p, 3, m, b, &d));
    TEST_ASSERT_EQUAL_MEMORY(&before, &cab, sizeof cab);
    /* Zero point masses are allowed (a cable with a vanishing first segment). */
    m[0] = 0.0;
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_cabin_init(&cab, &p, 3, m, b, &d));
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_combined_mass_properties);
    RUN_TEST(test_no_points_gives_the_cabin_itself);
    RUN_TEST(test_free_fall_without_rotation);
    RUN_TEST(test_spin_about_principal_axis);
    RUN_TEST(test_torque_free_asymmetric_body);
    RUN_TEST(test_torque_from_rest);
    RUN_TEST(test_force_through_origin_with_offset_com);
    RUN_TEST(test_offset_com_spinning_in_constant_force_closed_form);
    RUN_TEST(test_quaternion_kinematics_constant_rate);
    RUN_TEST(test_quaternion_derivative_is_orthogonal_to_q);
    RUN_TEST(test_motion_get_set_round_trip);
    RUN_TEST(test_validation_names_the_field);
    RUN_TEST(test_point_mass_validation);
    return UNITY_END() ? 1 : 0;
}
