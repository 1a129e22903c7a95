/* SPDX-License-Identifier: BSD-3-Clause */
/// @file test_ldp.c
/// The least-distance solver of the tension distribution (lib/core/src/ldp.h, internal)
/// against brute force written here: the minimum-norm point of a polyhedron is the minimum-norm
/// point of the affine hull of some set of at most k of its constraints taken as equalities;
/// enumerating every such set, the feasible candidate of least norm is the solution, and no
/// feasible candidate means no feasible point. The same for the distribution step
/// (cdpr_ldp_qp: 6 equations, one box per component), enumerating the components held at a
/// bound. Random problems with a fixed seed; feasible and infeasible ones both occur.
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../../lib/core/src/ldp.h"
#include "test_real.h"
#include "unity.h"

void setUp(void) {}
void tearDown(void) {}

static double urand(void)
{
    return 2.0 * ((double)rand() / RAND_MAX) - 1.0;
}

/* Solve the n x n system A x = b (n <= 16) by Gaussian elimination with partial pivoting.
 * 0, or -1 if a pivot is below 1e-10. */
static int gauss(int n, double A[16][16], double *b, double *x)
{
    for (int k = 0; k < n; ++k) {
        int p = k;
        for (int i = k + 1; i < n; ++i) {
            p = (fabs(A[i][k]) > fabs(A[p][k])) ? i : p;
        }
        if (fabs(A[p][k]) < 1e-10) {
            return -1;
        }
        for (int j = 0; j < n; ++j) {
            const double t = A[k][j];
            A[k][j] = A[p][j];
            A[p][j] = t;
        }
        const double t = b[k];
        b[k] = b[p];
        b[p] = t;
        for (int i = k + 1; i < n; ++i) {
            const double f = A[i][k] / A[k][k];
            for (int j = k; j < n; ++j) {
                A[i][j] -= f * A[k][j];
            }
            b[i] -= f * b[k];
        }
    }
    for (int i = n - 1; i >= 0; --i) {
        double s = b[i];
        for (int j = i + 1; j < n; ++j) {
            s -= A[i][j] * x[j];
        }
        x[i] = s / A[i][i];
    }
    return 0;
}

/* Minimum-norm x (dim variables) with C x = c (r rows): x = C^T (C C^T)^-1 c. -1 if C C^T is
 * singular. */
static int min_norm(int r, int dim, double C[16][16], const double *c, double *x)
{
    double CCt[16][16];
    double rhs[16];
    double y[16];
    for (int i = 0; i < r; ++i) {
        rhs[i] = c[i];
        for (int k = 0; k < r; ++k) {
            double s = 0.0;
            for (int j = 0; j < dim; ++j) {
                s += C[i][j] * C[k][j];
            }
            CCt[i][k] = s;
        }
    }
    if (gauss(r, CCt, rhs, y) != 0) {
        return -1;
    }
    for (int j = 0; j < dim; ++j) {
        x[j] = 0.0;
        for (int i = 0; i < r; ++i) {
            x[j] += C[i][j] * y[i];
        }
    }
    return 0;
}

static void test_ldp_matches_brute_force(void)
{
    srand(3);
    int feasible = 0;
    int infeasible = 0;
    const int kmax = (CDPR_LDP_MAX_VARS < 2) ? CDPR_LDP_MAX_VARS : 2;
    for (int trial = 0; trial < 400; ++trial) {
        const int k = 1 + trial % kmax;
        const int n = 1 + (trial / 2) % ((CDPR_LDP_MAX_ROWS < 8) ? CDPR_LDP_MAX_ROWS : 8);
        cdpr_real_t G[CDPR_LDP_MAX_ROWS][CDPR_LDP_MAX_VARS];
        cdpr_real_t h[CDPR_LDP_MAX_ROWS];
        for (int i = 0; i < n; ++i) {
            for (int c = 0; c < k; ++c) {
                G[i][c] = (cdpr_real_t)urand();
            }
            h[i] = (cdpr_real_t)urand();
        }
        /* Brute force over the sets of at most k rows (k <= 2). */
        double best = 1e300;
        double zb[2] = {0.0, 0.0};
        for (int a = -1; a < n; ++a) {
            for (int b = a; b < n; ++b) {
                int rows[2] = {0, 0};
                int r = 0;
                if (a >= 0) {
                    rows[r++] = a;
                }
                if (b > a && b >= 0) {
                    rows[r++] = b;
                }
                if (r > k || (a < 0 && b >= 0)) {
                    continue;
                }
                double C[16][16];
                double c[16];
                double z[2] = {0.0, 0.0};
                for (int i = 0; i < r; ++i) {
                    for (int v = 0; v < k; ++v) {
                        C[i][v] = (double)G[rows[i]][v];
                    }
                    c[i] = (double)h[rows[i]];
                }
                if (r > 0 && min_norm(r, k, C, c, z) != 0) {
                    continue;
                }
                int ok = 1;
                for (int i = 0; i < n; ++i) {
                    double s = 0.0;
                    for (int v = 0; v < k; ++v) {
                        s += (double)G[i][v] * z[v];
                    }
                    ok &= (s >= (double)h[i] - 1e-9) ? 1 : 0;
                }
                const double nz = z[0] * z[0] + z[1] * z[1];
                if (ok != 0 && nz < best) {
                    best = nz;
                    zb[0] = z[0];
                    zb[1] = z[1];
                }
            }
        }
        cdpr_real_t z[CDPR_LDP_MAX_VARS];
        int blame = -2;
        const cdpr_ldp_result_t rc = cdpr_ldp_solve(k, n, G, h, z, &blame);
        if (best < 1e300) {
            ++feasible;
            TEST_ASSERT_EQUAL_INT(CDPR_LDP_OK, rc);
            TEST_ASSERT_EQUAL_INT(-1, blame);
            for (int v = 0; v < k; ++v) {
                TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-9, 2e-4) * (1.0 + fabs(zb[v])), zb[v],
                                          (double)z[v]);
            }
        } else {
            ++infeasible;
            TEST_ASSERT_EQUAL_INT(CDPR_LDP_INFEASIBLE, rc);
            TEST_ASSERT_TRUE(blame >= 0 && blame < n);
        }
    }
    TEST_ASSERT_TRUE(feasible > 100);
    TEST_ASSERT_TRUE(infeasible > 20);
}

static void test_constant_rows_decide_alone(void)
{
    /* A row z cannot move is the condition 0 >= h_i: met, it is ignored; broken, it is blamed. */
    cdpr_real_t G[CDPR_LDP_MAX_ROWS][CDPR_LDP_MAX_VARS];
    cdpr_real_t h[CDPR_LDP_MAX_ROWS];
    cdpr_real_t z[CDPR_LDP_MAX_VARS];
    memset(G, 0, sizeof G);
    G[0][0] = CDPR_R(1.0);
    h[0] = CDPR_R(2.0);  /* z0 >= 2 */
    h[1] = CDPR_R(-1.0); /* 0 >= -1: met */
    int blame = -2;
    TEST_ASSERT_EQUAL_INT(CDPR_LDP_OK, cdpr_ldp_solve(1, 2, G, h, z, &blame));
    TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-12, 1e-6), 2.0, (double)z[0]);
    h[1] = CDPR_R(0.5); /* 0 >= 0.5: broken */
    TEST_ASSERT_EQUAL_INT(CDPR_LDP_INFEASIBLE, cdpr_ldp_solve(1, 2, G, h, z, &blame));
    TEST_ASSERT_EQUAL_INT(1, blame);
    /* z0 >= 1 and -z0 >= 1 (z0 <= -1): inconsistent; either row may be blamed. */
    G[1][0] = CDPR_R(-1.0);
    h[0] = CDPR_R(1.0);
    h[1] = CDPR_R(1.0);
    TEST_ASSERT_EQUAL_INT(CDPR_LDP_INFEASIBLE, cdpr_ldp_solve(1, 2, G, h, z, &blame));
    TEST_ASSERT_TRUE(blame == 0 || blame == 1);
}

static void test_distribution_step_matches_brute_force(void)
{
#if CDPR_LDP_MAX_COLS >= 8
    /* m = 7 and 8 components, 6 random equations, boxes lo_j <= u_j <= hi_j. Brute force: hold
     * at most m - 6 components at one of their bounds, take the minimum-norm solution of the
     * equations with those held, keep the feasible one of least norm. */
    srand(9);
    int feasible = 0;
    int infeasible = 0;
    for (int trial = 0; trial < 200; ++trial) {
        const int m = 7 + trial % 2;
        cdpr_real_t E[6][CDPR_LDP_MAX_COLS];
        cdpr_real_t f[6];
        cdpr_real_t lo_c[CDPR_LDP_MAX_COLS];
        cdpr_real_t lo_h[CDPR_LDP_MAX_COLS];
        cdpr_real_t hi_c[CDPR_LDP_MAX_COLS];
        cdpr_real_t hi_h[CDPR_LDP_MAX_COLS];
        double lo[CDPR_LDP_MAX_COLS];
        double hi[CDPR_LDP_MAX_COLS];
        for (int i = 0; i < 6; ++i) {
            for (int j = 0; j < m; ++j) {
                E[i][j] = (cdpr_real_t)urand();
            }
            f[i] = (cdpr_real_t)(0.3 * urand());
        }
        for (int j = 0; j < m; ++j) {
            lo[j] = -0.1 - 0.9 * (0.5 + 0.5 * urand());
            hi[j] = 0.1 + 0.9 * (0.5 + 0.5 * urand());
            lo_c[j] = CDPR_R(1.0);
            lo_h[j] = (cdpr_real_t)lo[j];
            hi_c[j] = CDPR_R(-1.0);
            hi_h[j] = (cdpr_real_t)(-hi[j]);
        }
        double best = 1e300;
        double ub[CDPR_LDP_MAX_COLS];
        /* held sets: none, one component, two components (m = 8), each at lo or hi */
        const int nsets = 1 + 2 * m + ((m == 8) ? 4 * m * m : 0);
        for (int s = 0; s < nsets; ++s) {
            int held[2] = {-1, -1};
            int side[2] = {0, 0};
            int r = 0;
            if (s >= 1 && s < 1 + 2 * m) {
                held[0] = (s - 1) / 2;
                side[0] = (s - 1) % 2;
                r = 1;
            } else if (s >= 1 + 2 * m) {
                const int q = s - 1 - 2 * m;
                held[0] = (q / 4) / m;
                held[1] = (q / 4) % m;
                side[0] = q % 2;
                side[1] = (q / 2) % 2;
                if (held[1] <= held[0]) {
                    continue;
                }
                r = 2;
            }
            double C[16][16];
            double c[16];
            for (int i = 0; i < 6; ++i) {
                for (int j = 0; j < m; ++j) {
                    C[i][j] = (double)E[i][j];
                }
                c[i] = (double)f[i];
            }
            for (int q = 0; q < r; ++q) {
                for (int j = 0; j < m; ++j) {
                    C[6 + q][j] = (j == held[q]) ? 1.0 : 0.0;
                }
                c[6 + q] = (side[q] == 0) ? lo[held[q]] : hi[held[q]];
            }
            double u[CDPR_LDP_MAX_COLS];
            if (min_norm(6 + r, m, C, c, u) != 0) {
                continue;
            }
            int ok = 1;
            double nu = 0.0;
            for (int j = 0; j < m; ++j) {
                ok &= (u[j] >= lo[j] - 1e-9 && u[j] <= hi[j] + 1e-9) ? 1 : 0;
                nu += u[j] * u[j];
            }
            if (ok != 0 && nu < best) {
                best = nu;
                memcpy(ub, u, sizeof ub);
            }
        }
        cdpr_real_t u[CDPR_LDP_MAX_COLS];
        cdpr_real_t mu[6];
        int blame = -2;
        const cdpr_ldp_result_t rc = cdpr_ldp_qp(m, E, f, lo_c, lo_h, hi_c, hi_h, 1, u, mu, &blame);
        if (best < 1e300) {
            ++feasible;
            TEST_ASSERT_EQUAL_INT(CDPR_LDP_OK, rc);
            for (int j = 0; j < m; ++j) {
                TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-8, 1e-3), ub[j], (double)u[j]);
            }
        } else {
            ++infeasible;
            TEST_ASSERT_EQUAL_INT(CDPR_LDP_INFEASIBLE, rc);
            TEST_ASSERT_TRUE(blame >= 0 && blame < 2 * m);
        }
        /* Without the bounds: the minimum-norm solution, and u = E^T mu exactly. */
        TEST_ASSERT_EQUAL_INT(CDPR_LDP_OK,
                              cdpr_ldp_qp(m, E, f, lo_c, lo_h, hi_c, hi_h, 0, u, mu, &blame));
        for (int j = 0; j < m; ++j) {
            double s = 0.0;
            for (int i = 0; i < 6; ++i) {
                s += (double)E[i][j] * (double)mu[i];
            }
            TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-9, 1e-3), s, (double)u[j]);
        }
    }
    TEST_ASSERT_TRUE(feasible > 100); /* 138 and 62 of this seed */
    TEST_ASSERT_TRUE(infeasible > 40);
#else
    TEST_IGNORE_MESSAGE("built with CDPR_MAX_CABLES < 8");
#endif
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_ldp_matches_brute_force);
    RUN_TEST(test_constant_rows_decide_alone);
    RUN_TEST(test_distribution_step_matches_brute_force);
    return UNITY_END() ? 1 : 0;
}
