/* SPDX-License-Identifier: BSD-3-Clause */
/// @file test_vec3.c
/// Vector, matrix and quaternion helpers (vec3.h) and the status names (status.h).
///
/// Every expectation is computed independently in the test: rotation matrices as explicit
/// products Rz(gamma) Ry(beta) Rx(alpha) (docs/model.md §1), Rodrigues' formula for axis-angle
/// rotations, integer arithmetic for the hand cases, vector identities for cross and dot.
/// The tolerances are rounding bounds derived for double; the float build scales them as
/// tests/support/test_real.h explains (TOL).
#include "unity.h"
#include "ref_mat3.h"

#include "cdpr/status.h"
#include "cdpr/vec3.h"
#include "test_real.h"

#include <math.h>
#include <string.h>

/* Slack on the angle ranges: atan2/asin of the real type may return pi (resp. pi/2) rounded
 * to that type, which exceeds the exact value by up to half an ulp (float: 8.7e-8 at pi). */
#define PI_SLACK TOL(1e-15, 2e-7)

/* pi (PI_D is not C99). */
#define PI_D 3.14159265358979323846

void setUp(void) {}

void tearDown(void) {}

/* ---------------------------------------------------------------- test-local helpers */

/* Rodrigues: R = I + sin(th) K + (1 - cos(th)) K^2, K = skew(unit axis n). */
static mat_t rodrigues(double nx, double ny, double nz, double th)
{
    const double k[3][3] = {{0.0, -nz, ny}, {nz, 0.0, -nx}, {-ny, nx, 0.0}};
    mat_t r;
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            double k2 = 0.0;
            for (int l = 0; l < 3; ++l) {
                k2 += k[i][l] * k[l][j];
            }
            r.m[i][j] = ((i == j) ? 1.0 : 0.0) + sin(th) * k[i][j] + (1.0 - cos(th)) * k2;
        }
    }
    return r;
}

#define ASSERT_MAT_WITHIN(tol, expected, actual)                                                   \
    assert_mat_within((tol), (expected), (actual), __LINE__)

static void assert_mat_within(double tol, const mat_t *e, const cdpr_mat3_t *a, int line)
{
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            UNITY_TEST_ASSERT_DOUBLE_WITHIN(tol, e->m[i][j], a->m[i][j], (UNITY_LINE_TYPE)line,
                                            "matrix element");
        }
    }
}

static mat_t from_cdpr(const cdpr_mat3_t *a)
{
    mat_t r;
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            r.m[i][j] = a->m[i][j];
        }
    }
    return r;
}

/* Angle grids: alpha and gamma cover (-pi, pi) without touching the +-pi seam (where atan2
 * may legitimately return either sign); beta stays inside (-pi/2, pi/2) away from gimbal lock
 * (|beta| <= 1.55, cos(beta) >= 0.0208). */
static const double grid_ag[] = {-3.1, -2.4, -1.3, -0.45, 0.0, 0.2, 0.9, 1.7, 2.6, 3.1};
static const double grid_b[] = {-1.55, -1.2, -0.7, -0.1, 0.0, 0.35, 0.8, 1.3, 1.55};
#define N_AG ((int)(sizeof grid_ag / sizeof grid_ag[0]))
#define N_B  ((int)(sizeof grid_b / sizeof grid_b[0]))

/* ---------------------------------------------------------------- Euler and quaternions */

static void test_quat_from_euler_matches_explicit_matrix_product(void)
{
    /* Tolerance 1e-14 on matrix entries in [-1, 1]: both sides are ~10-20 roundings of unit
     * size (libm sin/cos are within 1 ulp, the quaternion products and the quadratic forms in
     * cdpr_quat_to_mat3 add ~20 more), so the difference is below ~40 u = 4.4e-15. A wrong
     * convention (e.g. Rx Ry Rz, or a transposed matrix) differs by O(0.1) on this grid. */
    for (int ia = 0; ia < N_AG; ++ia) {
        for (int ib = 0; ib < N_B; ++ib) {
            for (int ig = 0; ig < N_AG; ++ig) {
                const double a = grid_ag[ia], b = grid_b[ib], g = grid_ag[ig];
                const mat_t expected = euler_matrix(a, b, g);
                cdpr_mat3_t r;
                cdpr_quat_to_mat3(cdpr_quat_from_euler(a, b, g), &r);
                ASSERT_MAT_WITHIN(TOL(1e-14, 6e-6), &expected, &r);
            }
        }
    }
}

static void test_quat_from_euler_is_unit(void)
{
    /* |q|^2 = 1 up to the ~12 roundings of the half-angle products: 1e-15 > 12 u. */
    for (int ia = 0; ia < N_AG; ++ia) {
        for (int ib = 0; ib < N_B; ++ib) {
            const cdpr_quat_t q =
                cdpr_quat_from_euler(grid_ag[ia], grid_b[ib], grid_ag[N_AG - 1 - ia]);
            const double n2 = q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z;
            TEST_ASSERT_DOUBLE_WITHIN(TOL(2e-15, 2e-6), 1.0, n2);
        }
    }
}

static void test_euler_round_trip_over_grid(void)
{
    /* to_euler(from_euler(a, b, g)) == (a, b, g). The matrix entries carry ~4e-15 absolute
     * error; alpha = atan2(cb sa, cb ca) and gamma likewise amplify it by 1/cos(beta) <= 48,
     * beta = asin(-R20) by the same factor: < 2.2e-13. Tolerance 1e-12; a wrong axis order or
     * sign gives O(0.1) errors on this grid. */
    for (int ia = 0; ia < N_AG; ++ia) {
        for (int ib = 0; ib < N_B; ++ib) {
            for (int ig = 0; ig < N_AG; ++ig) {
                const double a = grid_ag[ia], b = grid_b[ib], g = grid_ag[ig];
                cdpr_real_t a2 = 99.0, b2 = 99.0, g2 = 99.0;
                cdpr_quat_to_euler(cdpr_quat_from_euler(a, b, g), &a2, &b2, &g2);
                TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-12, 6e-4), a, a2);
                TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-12, 6e-4), b, b2);
                TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-12, 6e-4), g, g2);
            }
        }
    }
}

static void test_quat_to_euler_to_quat_same_rotation(void)
{
    /* Arbitrary, non-normalised quaternions (to_euler normalises): q -> angles -> q' must
     * describe the same rotation. Compared as matrices (q and -q are the same rotation).
     * Same error budget as above (beta not near +-pi/2 for these q): 1e-13. */
    const double qs[][4] = {{0.9, 0.1, -0.3, 0.2},  {-0.2, 0.7, 0.1, -0.6}, {2.0, -1.0, 0.5, 0.25},
                            {0.1, -0.2, 0.3, -0.9}, {1.0, 0.0, 0.0, 0.0},   {0.0, 0.0, 0.0, 3.0}};
    for (size_t i = 0; i < sizeof qs / sizeof qs[0]; ++i) {
        cdpr_quat_t q;
        q.w = qs[i][0];
        q.x = qs[i][1];
        q.y = qs[i][2];
        q.z = qs[i][3];
        cdpr_real_t a, b, g;
        cdpr_quat_to_euler(q, &a, &b, &g);
        TEST_ASSERT_TRUE(a > -PI_D - PI_SLACK && a <= PI_D + PI_SLACK);
        TEST_ASSERT_TRUE(b >= -PI_D / 2.0 - PI_SLACK && b <= PI_D / 2.0 + PI_SLACK);
        TEST_ASSERT_TRUE(g > -PI_D - PI_SLACK && g <= PI_D + PI_SLACK);
        const mat_t expected = euler_matrix(a, b, g);
        cdpr_mat3_t r;
        cdpr_quat_to_mat3(cdpr_quat_normalize(q), &r);
        ASSERT_MAT_WITHIN(TOL(1e-13, 6e-5), &expected, &r);
    }
}

static void test_quat_to_mat3_axis_angle_matches_rodrigues(void)
{
    /* q = (cos(th/2), n sin(th/2)) is the rotation by th about n; Rodrigues' formula gives
     * the same matrix independently. Tolerance as in the Euler test: 1e-14. */
    const double axes[][3] = {
        {1.0, 0.0, 0.0}, {0.0, 1.0, 0.0}, {0.0, 0.0, 1.0}, {0.48, -0.36, 0.8}, {-0.6, 0.0, 0.8}};
    const double angles[] = {-2.9, -1.0, 0.3, 1.5707963267948966, 2.5};
    for (size_t i = 0; i < sizeof axes / sizeof axes[0]; ++i) {
        for (size_t k = 0; k < sizeof angles / sizeof angles[0]; ++k) {
            const double th = angles[k];
            cdpr_quat_t q;
            q.w = cos(0.5 * th);
            q.x = axes[i][0] * sin(0.5 * th);
            q.y = axes[i][1] * sin(0.5 * th);
            q.z = axes[i][2] * sin(0.5 * th);
            const mat_t expected = rodrigues(axes[i][0], axes[i][1], axes[i][2], th);
            cdpr_mat3_t r;
            cdpr_quat_to_mat3(q, &r);
            ASSERT_MAT_WITHIN(TOL(1e-14, 6e-6), &expected, &r);
        }
    }
}

static void test_quat_mul_composes_rotations(void)
{
    /* R(a (x) b) = R(a) R(b) (Hamilton product, body -> world). Entries in [-1, 1]; each side
     * ~30 roundings of unit size: 1e-14. A reversed product order fails by O(0.1). */
    const cdpr_quat_t a = cdpr_quat_from_euler(0.3, -0.7, 1.9);
    const cdpr_quat_t b = cdpr_quat_from_euler(-1.2, 0.4, -2.2);
    cdpr_mat3_t ra, rb, rab;
    cdpr_quat_to_mat3(a, &ra);
    cdpr_quat_to_mat3(b, &rb);
    cdpr_quat_to_mat3(cdpr_quat_mul(a, b), &rab);
    const mat_t ma = from_cdpr(&ra);
    const mat_t mb = from_cdpr(&rb);
    const mat_t expected = mat_mul(&ma, &mb);
    ASSERT_MAT_WITHIN(TOL(1e-14, 6e-6), &expected, &rab);
}

static void test_quat_mul_hand_case(void)
{
    /* Hamilton basis rules, exact in floating point: i j = k, j i = -k, i i = -1,
     * and (1,2,3,4)(5,6,7,8) = (-60, 12, 30, 24) by hand expansion. */
    cdpr_quat_t i = {0.0, 1.0, 0.0, 0.0};
    cdpr_quat_t j = {0.0, 0.0, 1.0, 0.0};
    const cdpr_quat_t ij = cdpr_quat_mul(i, j);
    const cdpr_quat_t ji = cdpr_quat_mul(j, i);
    const cdpr_quat_t ii = cdpr_quat_mul(i, i);
    TEST_ASSERT_DOUBLE_WITHIN(0.0, 0.0, ij.w);
    TEST_ASSERT_DOUBLE_WITHIN(0.0, 0.0, ij.x);
    TEST_ASSERT_DOUBLE_WITHIN(0.0, 0.0, ij.y);
    TEST_ASSERT_DOUBLE_WITHIN(0.0, 1.0, ij.z);
    TEST_ASSERT_DOUBLE_WITHIN(0.0, -1.0, ji.z);
    TEST_ASSERT_DOUBLE_WITHIN(0.0, -1.0, ii.w);
    const cdpr_quat_t a = {1.0, 2.0, 3.0, 4.0};
    const cdpr_quat_t b = {5.0, 6.0, 7.0, 8.0};
    const cdpr_quat_t ab = cdpr_quat_mul(a, b);
    /* w = 5 - 12 - 21 - 32; x = 6 + 10 + 24 - 28; y = 7 - 16 + 15 + 24; z = 8 + 14 - 18 + 20 */
    TEST_ASSERT_DOUBLE_WITHIN(0.0, -60.0, ab.w);
    TEST_ASSERT_DOUBLE_WITHIN(0.0, 12.0, ab.x);
    TEST_ASSERT_DOUBLE_WITHIN(0.0, 30.0, ab.y);
    TEST_ASSERT_DOUBLE_WITHIN(0.0, 24.0, ab.z);
}

static void test_quat_normalize(void)
{
    /* Zero quaternion -> identity (documented); exact. */
    const cdpr_quat_t zero = {0.0, 0.0, 0.0, 0.0};
    const cdpr_quat_t id = cdpr_quat_normalize(zero);
    TEST_ASSERT_DOUBLE_WITHIN(0.0, 1.0, id.w);
    TEST_ASSERT_DOUBLE_WITHIN(0.0, 0.0, id.x);
    TEST_ASSERT_DOUBLE_WITHIN(0.0, 0.0, id.y);
    TEST_ASSERT_DOUBLE_WITHIN(0.0, 0.0, id.z);
    /* (1, 2, 2, 4) has norm 5 exactly (sqrt(25)); each component is then multiplied by
     * fl(1/5): two roundings, <= 2 u relative on values <= 0.8, so within 4e-16. */
    const cdpr_quat_t q = {1.0, 2.0, 2.0, 4.0};
    const cdpr_quat_t n = cdpr_quat_normalize(q);
    TEST_ASSERT_DOUBLE_WITHIN(TOL(4e-16, 3e-7), 0.2, n.w);
    TEST_ASSERT_DOUBLE_WITHIN(TOL(4e-16, 3e-7), 0.4, n.x);
    TEST_ASSERT_DOUBLE_WITHIN(TOL(4e-16, 3e-7), 0.4, n.y);
    TEST_ASSERT_DOUBLE_WITHIN(TOL(4e-16, 3e-7), 0.8, n.z);
    /* A NaN norm fails the "n > 0" test like a zero norm does: the documented identity. */
    const cdpr_quat_t bad = {NAN_R, 0.0, 0.0, 0.0};
    const cdpr_quat_t nb = cdpr_quat_normalize(bad);
    TEST_ASSERT_DOUBLE_WITHIN(0.0, 1.0, nb.w);
}

static void test_rotation_matrix_is_orthonormal(void)
{
    /* R R^T = I and det R = +1 for unit q: each entry of R R^T is a 3-term sum of products of
     * entries carrying ~10 u: 1e-14. */
    for (int ia = 0; ia < N_AG; ++ia) {
        const cdpr_quat_t q =
            cdpr_quat_from_euler(grid_ag[ia], grid_b[ia % N_B], 0.5 * grid_ag[ia]);
        cdpr_mat3_t r;
        cdpr_quat_to_mat3(q, &r);
        for (int i = 0; i < 3; ++i) {
            for (int j = 0; j < 3; ++j) {
                double s = 0.0;
                for (int k = 0; k < 3; ++k) {
                    s += r.m[i][k] * r.m[j][k];
                }
                TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-14, 6e-6), (i == j) ? 1.0 : 0.0, s);
            }
        }
        const double det = r.m[0][0] * (r.m[1][1] * r.m[2][2] - r.m[1][2] * r.m[2][1]) -
                           r.m[0][1] * (r.m[1][0] * r.m[2][2] - r.m[1][2] * r.m[2][0]) +
                           r.m[0][2] * (r.m[1][0] * r.m[2][1] - r.m[1][1] * r.m[2][0]);
        TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-14, 6e-6), 1.0, det);
    }
}

/* ---------------------------------------------------------------- vectors */

static void test_cross_dot_norm_hand_cases(void)
{
    /* Small integers: every product and sum is exact in double, so equality is exact. */
    const cdpr_vec3_t a = cdpr_v3(1.0, 2.0, 3.0);
    const cdpr_vec3_t b = cdpr_v3(4.0, 5.0, 6.0);
    const cdpr_vec3_t c = cdpr_v3_cross(a, b); /* (2*6-3*5, 3*4-1*6, 1*5-2*4) */
    TEST_ASSERT_DOUBLE_WITHIN(0.0, -3.0, c.x);
    TEST_ASSERT_DOUBLE_WITHIN(0.0, 6.0, c.y);
    TEST_ASSERT_DOUBLE_WITHIN(0.0, -3.0, c.z);
    TEST_ASSERT_DOUBLE_WITHIN(0.0, 32.0, cdpr_v3_dot(a, b)); /* 4 + 10 + 18 */
    /* Right-handed basis: x cross y = z. */
    const cdpr_vec3_t z = cdpr_v3_cross(cdpr_v3(1.0, 0.0, 0.0), cdpr_v3(0.0, 1.0, 0.0));
    TEST_ASSERT_DOUBLE_WITHIN(0.0, 0.0, z.x);
    TEST_ASSERT_DOUBLE_WITHIN(0.0, 0.0, z.y);
    TEST_ASSERT_DOUBLE_WITHIN(0.0, 1.0, z.z);
    /* |(3, 4, 12)| = 13: 169 is exact and sqrt is correctly rounded, so exact. */
    TEST_ASSERT_DOUBLE_WITHIN(0.0, 13.0, cdpr_v3_norm(cdpr_v3(3.0, 4.0, 12.0)));
    TEST_ASSERT_DOUBLE_WITHIN(0.0, 13.0, cdpr_v3_norm(cdpr_v3(-3.0, -4.0, -12.0)));
    /* add/sub/scale on exact binary values. */
    const cdpr_vec3_t s = cdpr_v3_scale(cdpr_v3_sub(cdpr_v3_add(a, b), a), 0.5);
    TEST_ASSERT_DOUBLE_WITHIN(0.0, 2.0, s.x);
    TEST_ASSERT_DOUBLE_WITHIN(0.0, 2.5, s.y);
    TEST_ASSERT_DOUBLE_WITHIN(0.0, 3.0, s.z);
}

static void test_cross_dot_identities(void)
{
    const double vals[][3] = {
        {0.3, -1.7, 2.2}, {4.1, 0.05, -0.9}, {-2.5, 3.3, 1.25}, {1e-3, 2e3, -7.0}, {0.0, 0.0, 1.0}};
    const int nv = (int)(sizeof vals / sizeof vals[0]);
    for (int i = 0; i < nv; ++i) {
        for (int j = 0; j < nv; ++j) {
            const cdpr_vec3_t a = cdpr_v3(vals[i][0], vals[i][1], vals[i][2]);
            const cdpr_vec3_t b = cdpr_v3(vals[j][0], vals[j][1], vals[j][2]);
            const cdpr_vec3_t c = cdpr_v3(vals[(i + j + 1) % nv][0], vals[(i + j + 1) % nv][1],
                                          vals[(i + j + 1) % nv][2]);
            const double na = cdpr_v3_norm(a), nb = cdpr_v3_norm(b), nc = cdpr_v3_norm(c);
            const cdpr_vec3_t axb = cdpr_v3_cross(a, b);
            const cdpr_vec3_t bxa = cdpr_v3_cross(b, a);
            /* Anti-commutativity is exact: fl(p - q) = -fl(q - p) for the same products. */
            TEST_ASSERT_DOUBLE_WITHIN(0.0, -axb.x, bxa.x);
            TEST_ASSERT_DOUBLE_WITHIN(0.0, -axb.y, bxa.y);
            TEST_ASSERT_DOUBLE_WITHIN(0.0, -axb.z, bxa.z);
            /* a . (a x b) = 0 and b . (a x b) = 0: each term is |a|^2 |b| sized with a few
             * roundings; tolerance 8 u |a|^2 |b| (resp. |a| |b|^2). */
            TEST_ASSERT_DOUBLE_WITHIN(8.0 * U_REAL * na * na * nb, 0.0, cdpr_v3_dot(a, axb));
            TEST_ASSERT_DOUBLE_WITHIN(8.0 * U_REAL * na * nb * nb, 0.0, cdpr_v3_dot(b, axb));
            /* Lagrange: |a x b|^2 = |a|^2 |b|^2 - (a.b)^2; both sides are |a|^2 |b|^2 sized
             * with ~10 roundings: tolerance 16 u |a|^2 |b|^2. */
            const double ab = cdpr_v3_dot(a, b);
            const double lhs = cdpr_v3_dot(axb, axb);
            const double rhs = na * na * nb * nb - ab * ab;
            TEST_ASSERT_DOUBLE_WITHIN(16.0 * U_REAL * na * na * nb * nb, rhs, lhs);
            /* BAC-CAB: a x (b x c) = b (a.c) - c (a.b); terms |a||b||c| sized: 16 u. */
            const cdpr_vec3_t l = cdpr_v3_cross(a, cdpr_v3_cross(b, c));
            const cdpr_vec3_t r = cdpr_v3_sub(cdpr_v3_scale(b, cdpr_v3_dot(a, c)),
                                              cdpr_v3_scale(c, cdpr_v3_dot(a, b)));
            const double tol = 16.0 * U_REAL * na * nb * nc;
            TEST_ASSERT_DOUBLE_WITHIN(tol, r.x, l.x);
            TEST_ASSERT_DOUBLE_WITHIN(tol, r.y, l.y);
            TEST_ASSERT_DOUBLE_WITHIN(tol, r.z, l.z);
        }
    }
}

static void test_v3_isfinite(void)
{
    /* A large finite value of the real type (1e300 overflows float). */
    TEST_ASSERT_EQUAL_INT(1, cdpr_v3_isfinite(cdpr_v3(1.0, -2.0, TOL(1e300, 1e38))));
    TEST_ASSERT_EQUAL_INT(0, cdpr_v3_isfinite(cdpr_v3(NAN_R, 0.0, 0.0)));
    TEST_ASSERT_EQUAL_INT(0, cdpr_v3_isfinite(cdpr_v3(0.0, INF_R, 0.0)));
    TEST_ASSERT_EQUAL_INT(0, cdpr_v3_isfinite(cdpr_v3(0.0, 0.0, -INF_R)));
}

/* ---------------------------------------------------------------- matrices */

static void test_mat_vec_products_hand_case(void)
{
    /* Integer entries: exact. m = [[1,2,3],[4,5,6],[7,8,10]], a = (1,-1,2). */
    const cdpr_mat3_t m = {{{1.0, 2.0, 3.0}, {4.0, 5.0, 6.0}, {7.0, 8.0, 10.0}}};
    const cdpr_vec3_t a = cdpr_v3(1.0, -1.0, 2.0);
    const cdpr_vec3_t ma = cdpr_m3_mul_v3(&m, a);   /* (1-2+6, 4-5+12, 7-8+20) */
    const cdpr_vec3_t mta = cdpr_m3t_mul_v3(&m, a); /* (1-4+14, 2-5+16, 3-6+20) */
    TEST_ASSERT_DOUBLE_WITHIN(0.0, 5.0, ma.x);
    TEST_ASSERT_DOUBLE_WITHIN(0.0, 11.0, ma.y);
    TEST_ASSERT_DOUBLE_WITHIN(0.0, 19.0, ma.z);
    TEST_ASSERT_DOUBLE_WITHIN(0.0, 11.0, mta.x);
    TEST_ASSERT_DOUBLE_WITHIN(0.0, 13.0, mta.y);
    TEST_ASSERT_DOUBLE_WITHIN(0.0, 17.0, mta.z);
}

static void test_mat_inverse_hand_case(void)
{
    /* m = [[4,7,2],[3,6,1],[2,5,3]], det = 4*13 - 7*7 + 2*3 = 9; adjugate by hand:
     * inv = (1/9) [[13,-11,-5],[-7,8,2],[3,-6,3]]. Entries ~1: each is (cofactor, exact in
     * integers) * fl(1/9), so within 2 u relative: 1e-15. */
    const cdpr_mat3_t m = {{{4.0, 7.0, 2.0}, {3.0, 6.0, 1.0}, {2.0, 5.0, 3.0}}};
    const mat_t expected = {{{13.0 / 9.0, -11.0 / 9.0, -5.0 / 9.0},
                             {-7.0 / 9.0, 8.0 / 9.0, 2.0 / 9.0},
                             {3.0 / 9.0, -6.0 / 9.0, 3.0 / 9.0}}};
    cdpr_mat3_t inv;
    TEST_ASSERT_EQUAL_INT(0, cdpr_m3_inverse(&m, 0.0, &inv));
    ASSERT_MAT_WITHIN(TOL(1e-15, 6e-7), &expected, &inv);
    /* m * inv = I, independent of the adjugate above: 3-term sums of ~1e-15-accurate
     * products of size <= 10: 1e-13. */
    const mat_t mm = from_cdpr(&m);
    const mat_t mi = from_cdpr(&inv);
    const mat_t prod = mat_mul(&mm, &mi);
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-13, 6e-5), (i == j) ? 1.0 : 0.0, prod.m[i][j]);
        }
    }
}

static void test_mat_inverse_general(void)
{
    /* A symmetric inertia-like matrix and a rotation (inverse = transpose). */
    const cdpr_mat3_t s = {{{45.0, -1.5, 2.0}, {-1.5, 50.0, 0.7}, {2.0, 0.7, 90.0}}};
    cdpr_mat3_t inv;
    TEST_ASSERT_EQUAL_INT(0, cdpr_m3_inverse(&s, 0.0, &inv));
    const mat_t ms = from_cdpr(&s);
    const mat_t mi = from_cdpr(&inv);
    const mat_t prod = mat_mul(&ms, &mi);
    /* Condition number ~2: s * inv = I within ~20 u * cond: 1e-14. */
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-14, 6e-6), (i == j) ? 1.0 : 0.0, prod.m[i][j]);
        }
    }
    cdpr_mat3_t r;
    cdpr_quat_to_mat3(cdpr_quat_from_euler(0.4, -1.1, 2.7), &r);
    TEST_ASSERT_EQUAL_INT(0, cdpr_m3_inverse(&r, 0.5, &inv));
    /* inverse of a rotation is its transpose: entries within ~20 u: 1e-14. */
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-14, 6e-6), r.m[j][i], inv.m[i][j]);
        }
    }
}

static void test_mat_inverse_singular_leaves_out_unchanged(void)
{
    /* Rows 1 and 3 proportional: det = 0 exactly in integers. */
    const cdpr_mat3_t sing = {{{1.0, 2.0, 3.0}, {0.0, 1.0, 4.0}, {2.0, 4.0, 6.0}}};
    cdpr_mat3_t out;
    memset(&out, 0x5A, sizeof out);
    cdpr_mat3_t before;
    memcpy(&before, &out, sizeof out);
    TEST_ASSERT_EQUAL_INT(-1, cdpr_m3_inverse(&sing, 0.0, &out));
    TEST_ASSERT_EQUAL_MEMORY(&before, &out, sizeof out);

    /* Threshold: |det| must be strictly above min_abs_det. det = 9 (hand case above). */
    const cdpr_mat3_t m = {{{4.0, 7.0, 2.0}, {3.0, 6.0, 1.0}, {2.0, 5.0, 3.0}}};
    TEST_ASSERT_EQUAL_INT(-1, cdpr_m3_inverse(&m, 9.0, &out));
    TEST_ASSERT_EQUAL_MEMORY(&before, &out, sizeof out);
    TEST_ASSERT_EQUAL_INT(0, cdpr_m3_inverse(&m, 8.5, &out));

    /* NaN entries make det NaN: refused, out unchanged. */
    cdpr_mat3_t nanm = m;
    nanm.m[1][2] = NAN_R;
    memcpy(&out, &before, sizeof out);
    TEST_ASSERT_EQUAL_INT(-1, cdpr_m3_inverse(&nanm, 0.0, &out));
    TEST_ASSERT_EQUAL_MEMORY(&before, &out, sizeof out);
}

/* ---------------------------------------------------------------- status */

static const cdpr_status_t all_status[] = {CDPR_OK,
                                           CDPR_WARN_SUBSTEP_LIMIT,
                                           CDPR_WARN_CAPACITY,
                                           CDPR_WARN_MIN_LENGTH,
                                           CDPR_E_INVALID_ARG,
                                           CDPR_E_NOT_FINITE,
                                           CDPR_E_NOT_POSITIVE,
                                           CDPR_E_OUT_OF_RANGE,
                                           CDPR_E_CAPACITY,
                                           CDPR_E_GEOMETRY,
                                           CDPR_E_STATE_NOT_FINITE,
                                           CDPR_E_STEP_TOO_SMALL,
                                           CDPR_E_RHS,
                                           CDPR_E_NO_CONVERGENCE,
                                           CDPR_E_INFEASIBLE,
                                           CDPR_E_SUBSTEP_LIMIT,
                                           CDPR_E_SINGULAR};
#define N_STATUS ((int)(sizeof all_status / sizeof all_status[0]))

static void test_status_str_never_null_and_distinct(void)
{
    const char *unknown = cdpr_status_str((cdpr_status_t)42);
    TEST_ASSERT_NOT_NULL(unknown);
    TEST_ASSERT_TRUE(strlen(unknown) > 0u);
    TEST_ASSERT_NOT_NULL(cdpr_status_str((cdpr_status_t)-99));
    TEST_ASSERT_NOT_NULL(cdpr_status_str((cdpr_status_t)4));
    TEST_ASSERT_NOT_NULL(cdpr_status_str((cdpr_status_t)-13));
    for (int i = 0; i < N_STATUS; ++i) {
        const char *si = cdpr_status_str(all_status[i]);
        TEST_ASSERT_NOT_NULL(si);
        TEST_ASSERT_TRUE(strlen(si) > 0u);
        /* Distinct from the unknown-value name ... */
        TEST_ASSERT_TRUE(strcmp(si, unknown) != 0);
        /* ... and from every other known value. */
        for (int j = i + 1; j < N_STATUS; ++j) {
            TEST_ASSERT_TRUE(strcmp(si, cdpr_status_str(all_status[j])) != 0);
        }
    }
    TEST_ASSERT_EQUAL_STRING("CDPR_OK", cdpr_status_str(CDPR_OK));
    TEST_ASSERT_EQUAL_STRING("CDPR_E_RHS", cdpr_status_str(CDPR_E_RHS));
}

static void test_status_sign_convention(void)
{
    /* status.h: zero success, positive warnings, negative errors. */
    TEST_ASSERT_EQUAL_INT(0, (int)CDPR_OK);
    TEST_ASSERT_TRUE((int)CDPR_WARN_SUBSTEP_LIMIT > 0);
    TEST_ASSERT_TRUE((int)CDPR_WARN_CAPACITY > 0);
    TEST_ASSERT_TRUE((int)CDPR_WARN_MIN_LENGTH > 0);
    for (int i = 4; i < N_STATUS; ++i) {
        TEST_ASSERT_TRUE((int)all_status[i] < 0);
    }
}

static void test_diag_set(void)
{
    cdpr_diag_t d;
    d.status = CDPR_OK;
    d.field = "x";
    d.index = 7;
    TEST_ASSERT_EQUAL_INT(CDPR_E_GEOMETRY, cdpr_diag_set(&d, CDPR_E_GEOMETRY, "exit_point_m", 3));
    TEST_ASSERT_EQUAL_INT(CDPR_E_GEOMETRY, d.status);
    TEST_ASSERT_EQUAL_STRING("exit_point_m", d.field);
    TEST_ASSERT_EQUAL_INT(3, d.index);
    /* NULL field becomes "", never NULL. */
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_diag_set(&d, CDPR_OK, NULL, -1));
    TEST_ASSERT_NOT_NULL(d.field);
    TEST_ASSERT_EQUAL_STRING("", d.field);
    /* NULL diag: just returns the status. */
    TEST_ASSERT_EQUAL_INT(CDPR_E_RHS, cdpr_diag_set(NULL, CDPR_E_RHS, "f", 1));
}

/* cdpr_quat_to_rotvec against the axis-angle quaternion built here, q = (cos(a/2), sin(a/2) n),
 * from a tiny angle (the first-order branch) to just below pi; -q is the same rotation. Double:
 * a few roundings of |θ| <= pi (1e-12); float: atan2f and the norm of sin(a/2) n, a few u_f
 * of pi (2e-6). */
static void test_quat_to_rotvec_is_axis_times_angle(void)
{
    const double n[3] = {0.36, -0.48, 0.8}; /* unit */
    const double angles[4] = {1e-9, 0.3, 2.5, PI_D - 1e-3};
    for (int k = 0; k < 4; ++k) {
        const double a = angles[k];
        const cdpr_quat_t q = {(cdpr_real_t)cos(0.5 * a), (cdpr_real_t)(sin(0.5 * a) * n[0]),
                               (cdpr_real_t)(sin(0.5 * a) * n[1]),
                               (cdpr_real_t)(sin(0.5 * a) * n[2])};
        const cdpr_quat_t qn = {-q.w, -q.x, -q.y, -q.z};
        const cdpr_vec3_t r[2] = {cdpr_quat_to_rotvec(q), cdpr_quat_to_rotvec(qn)};
        for (int s = 0; s < 2; ++s) {
            TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-12, 2e-6), a * n[0], (double)r[s].x);
            TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-12, 2e-6), a * n[1], (double)r[s].y);
            TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-12, 2e-6), a * n[2], (double)r[s].z);
        }
    }
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_quat_from_euler_matches_explicit_matrix_product);
    RUN_TEST(test_quat_from_euler_is_unit);
    RUN_TEST(test_euler_round_trip_over_grid);
    RUN_TEST(test_quat_to_euler_to_quat_same_rotation);
    RUN_TEST(test_quat_to_mat3_axis_angle_matches_rodrigues);
    RUN_TEST(test_quat_mul_composes_rotations);
    RUN_TEST(test_quat_mul_hand_case);
    RUN_TEST(test_quat_normalize);
    RUN_TEST(test_rotation_matrix_is_orthonormal);
    RUN_TEST(test_cross_dot_norm_hand_cases);
    RUN_TEST(test_cross_dot_identities);
    RUN_TEST(test_v3_isfinite);
    RUN_TEST(test_mat_vec_products_hand_case);
    RUN_TEST(test_mat_inverse_hand_case);
    RUN_TEST(test_mat_inverse_general);
    RUN_TEST(test_mat_inverse_singular_leaves_out_unchanged);
    RUN_TEST(test_status_str_never_null_and_distinct);
    RUN_TEST(test_status_sign_convention);
    RUN_TEST(test_diag_set);
    RUN_TEST(test_quat_to_rotvec_is_axis_times_angle);
    return UNITY_END() ? 1 : 0;
}
