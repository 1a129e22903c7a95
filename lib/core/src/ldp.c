/* SPDX-License-Identifier: BSD-3-Clause */
/// @file ldp.c
/// Least-distance programming by non-negative least squares (see ldp.h).
///
/// LDP: min ||z|| subject to G z >= h. With E = [G^T; h^T] ((k + 1) x n) and f = e_{k+1},
/// let u >= 0 minimise ||E u - f|| (NNLS) and r = E u - f. The constraints are consistent
/// exactly when r != 0, and then z = -r[0..k-1] / r[k] (Lawson & Hanson 1974, ch. 23, with
/// ||r||^2 = -r[k] at the NNLS solution). NNLS is their active-set algorithm.
#include "ldp.h"

#include <math.h>
#include <stddef.h>

#define LDP_M (CDPR_LDP_MAX_VARS + 1) /* rows of E */
#define LDP_N CDPR_LDP_MAX_ROWS       /* columns of E: the constraints */
#define LDP_C CDPR_LDP_MAX_COLS       /* components of the distribution step */

/* Least squares min ||sum_i c_i E_{idx[i]} - b|| over the p columns idx of E (stored by
 * column: E[j][0..m-1]) by Householder QR. 0 on success, -1 if a column is numerically
 * dependent on the previous ones (its remaining norm below 1e3 eps of its own). */
static int lsq(int m, int p, cdpr_real_t E[LDP_N][LDP_M], const int *idx, const cdpr_real_t *b,
               cdpr_real_t *c)
{
    cdpr_real_t W[LDP_M][LDP_M + 1];
    cdpr_real_t cn[LDP_M];
    if (p > m) {
        return -1;
    }
    for (int i = 0; i < p; ++i) {
        cn[i] = CDPR_R(0.0);
        for (int r = 0; r < m; ++r) {
            W[r][i] = E[idx[i]][r];
            cn[i] += W[r][i] * W[r][i];
        }
        cn[i] = CDPR_SQRT(cn[i]);
    }
    for (int r = 0; r < m; ++r) {
        W[r][p] = b[r];
    }
    for (int k = 0; k < p; ++k) {
        cdpr_real_t nrm = CDPR_R(0.0);
        for (int r = k; r < m; ++r) {
            nrm += W[r][k] * W[r][k];
        }
        nrm = CDPR_SQRT(nrm);
        if (!(nrm > CDPR_R(1e3) * CDPR_EPS * cn[k])) {
            return -1;
        }
        const cdpr_real_t alpha = (W[k][k] > CDPR_R(0.0)) ? -nrm : nrm;
        /* Householder vector v = x - alpha e_k (stored in place below the diagonal). */
        W[k][k] -= alpha;
        cdpr_real_t vtv = CDPR_R(0.0);
        for (int r = k; r < m; ++r) {
            vtv += W[r][k] * W[r][k];
        }
        for (int col = k + 1; col <= p; ++col) {
            cdpr_real_t s = CDPR_R(0.0);
            for (int r = k; r < m; ++r) {
                s += W[r][k] * W[r][col];
            }
            const cdpr_real_t f = CDPR_R(2.0) * s / vtv;
            for (int r = k; r < m; ++r) {
                W[r][col] -= f * W[r][k];
            }
        }
        W[k][k] = alpha;
    }
    for (int i = p - 1; i >= 0; --i) {
        cdpr_real_t s = W[i][p];
        for (int j = i + 1; j < p; ++j) {
            s -= W[i][j] * c[j];
        }
        c[i] = s / W[i][i];
    }
    return 0;
}

/* NNLS inner step: move u toward the least-squares point zfull on the passive set until the
 * first passive component reaches zero, and drop it (with any other at zero). */
static void move_to_zero(int p, const int *idx, const cdpr_real_t *zfull, cdpr_real_t *u,
                         int *passive)
{
    cdpr_real_t alpha = CDPR_R(2.0);
    int jmin = -1;
    for (int i = 0; i < p; ++i) {
        const int j = idx[i];
        if (!(zfull[j] > CDPR_R(0.0))) {
            const cdpr_real_t a = u[j] / (u[j] - zfull[j]);
            if (a < alpha) {
                alpha = a;
                jmin = j;
            }
        }
    }
    for (int i = 0; i < p; ++i) {
        const int j = idx[i];
        u[j] += alpha * (zfull[j] - u[j]);
        if (j == jmin || !(u[j] > CDPR_R(0.0))) {
            u[j] = CDPR_R(0.0);
            passive[j] = 0;
        }
    }
}

/* Lawson-Hanson NNLS: u >= 0 minimising ||E u - b|| (E: n columns of m rows). At most 3 n
 * outer iterations. Returns CDPR_LDP_OK or CDPR_LDP_STALLED. */
static cdpr_ldp_result_t nnls(int m, int n, cdpr_real_t E[LDP_N][LDP_M], const cdpr_real_t *b,
                              cdpr_real_t *u)
{
    int passive[LDP_N];
    int excluded[LDP_N];
    for (int j = 0; j < n; ++j) {
        passive[j] = 0;
        excluded[j] = 0;
        u[j] = CDPR_R(0.0);
    }
    const cdpr_real_t tol_w = CDPR_R(1e3) * CDPR_EPS;
    for (int outer = 0; outer < 3 * n; ++outer) {
        cdpr_real_t res[LDP_M];
        for (int r = 0; r < m; ++r) {
            res[r] = b[r];
            for (int j = 0; j < n; ++j) {
                res[r] -= E[j][r] * u[j];
            }
        }
        int t = -1;
        cdpr_real_t best = tol_w;
        for (int j = 0; j < n; ++j) {
            cdpr_real_t w = CDPR_R(0.0);
            for (int r = 0; r < m; ++r) {
                w += E[j][r] * res[r];
            }
            if (passive[j] == 0 && excluded[j] == 0 && w > best) {
                best = w;
                t = j;
            }
        }
        if (t < 0) {
            return CDPR_LDP_OK; /* Kuhn-Tucker conditions hold */
        }
        passive[t] = 1;
        int moved = 0;
        int inner_done = 0;
        for (int inner = 0; (inner <= n) && (inner_done == 0); ++inner) {
            int idx[LDP_N];
            cdpr_real_t zc[LDP_M];
            for (int r = 0; r < LDP_M; ++r) {
                zc[r] = CDPR_R(0.0);
            }
            int p = 0;
            for (int j = 0; j < n; ++j) {
                if (passive[j] != 0) {
                    idx[p] = j;
                    ++p;
                }
            }
            cdpr_real_t zfull[LDP_N];
            int ok_lsq = lsq(m, p, E, idx, b, zc);
            int tpos = 0;
            for (int j = 0; j < n; ++j) {
                zfull[j] = CDPR_R(0.0);
            }
            for (int i = 0; (ok_lsq == 0) && (i < p); ++i) {
                zfull[idx[i]] = zc[i];
            }
            tpos = (zfull[t] > CDPR_R(0.0)) ? 1 : 0;
            int all_pos = 1;
            for (int i = 0; i < p; ++i) {
                all_pos &= (zc[i] > CDPR_R(0.0)) ? 1 : 0;
            }
            if (ok_lsq != 0 || (inner == 0 && tpos == 0)) {
                /* The new column is dependent, or enters at a non-positive value (rounding):
                 * leave it out until u moves. */
                passive[t] = 0;
                excluded[t] = 1;
                inner_done = 1;
            } else if (all_pos != 0) {
                for (int j = 0; j < n; ++j) {
                    u[j] = zfull[j];
                }
                moved = 1;
                inner_done = 1;
            } else {
                move_to_zero(p, idx, zfull, u, passive);
                moved = 1;
            }
        }
        if (moved != 0) {
            for (int j = 0; j < n; ++j) {
                excluded[j] = 0;
            }
        }
    }
    return CDPR_LDP_STALLED;
}

cdpr_ldp_result_t cdpr_ldp_solve(int k, int n_rows, cdpr_real_t G[][CDPR_LDP_MAX_VARS],
                                 const cdpr_real_t *h, cdpr_real_t *z, int *blame)
{
    *blame = -1;
    for (int i = 0; i < k; ++i) {
        z[i] = CDPR_R(0.0);
    }
    cdpr_real_t nrm[LDP_N];
    cdpr_real_t gmax = CDPR_R(0.0);
    cdpr_real_t hmax = CDPR_R(0.0);
    for (int i = 0; i < n_rows; ++i) {
        cdpr_real_t s = CDPR_R(0.0);
        for (int c = 0; c < k; ++c) {
            s += G[i][c] * G[i][c];
        }
        nrm[i] = CDPR_SQRT(s);
        gmax = (nrm[i] > gmax) ? nrm[i] : gmax;
        hmax = (CDPR_FABS(h[i]) > hmax) ? CDPR_FABS(h[i]) : hmax;
    }
    /* Rows z cannot move are conditions 0 >= h_i; the others are normalised. */
    const cdpr_real_t h_tol = CDPR_R(1e3) * CDPR_EPS * hmax;
    cdpr_real_t E[LDP_N][LDP_M];
    int row_of[LDP_N];
    int n = 0;
    cdpr_real_t worst = h_tol;
    cdpr_real_t hs = CDPR_R(0.0);
    for (int i = 0; i < n_rows; ++i) {
        if (!(nrm[i] > CDPR_R(1e-12) * gmax)) {
            if (h[i] > worst) {
                worst = h[i];
                *blame = i;
            }
        } else {
            for (int c = 0; c < k; ++c) {
                E[n][c] = G[i][c] / nrm[i];
            }
            E[n][k] = h[i] / nrm[i];
            hs = (E[n][k] > hs) ? E[n][k] : hs;
            row_of[n] = i;
            ++n;
        }
    }
    if (*blame >= 0) {
        return CDPR_LDP_INFEASIBLE;
    }
    if (!(hs > CDPR_R(0.0))) {
        return CDPR_LDP_OK; /* every h_i <= 0: z = 0 is feasible and has the least norm */
    }
    for (int j = 0; j < n; ++j) {
        E[j][k] /= hs;
    }
    cdpr_real_t f[LDP_M];
    for (int r = 0; r < k; ++r) {
        f[r] = CDPR_R(0.0);
    }
    f[k] = CDPR_R(1.0);
    cdpr_real_t u[LDP_N];
    if (nnls(k + 1, n, E, f, u) != CDPR_LDP_OK) {
        return CDPR_LDP_STALLED;
    }
    cdpr_real_t r[LDP_M];
    for (int c = 0; c < LDP_M; ++c) {
        r[c] = CDPR_R(0.0);
    }
    for (int c = 0; c <= k; ++c) {
        r[c] = -f[c];
        for (int j = 0; j < n; ++j) {
            r[c] += E[j][c] * u[j];
        }
    }
    if (!(-r[k] > CDPR_R(1e3) * CDPR_EPS)) {
        cdpr_real_t umax = CDPR_R(-1.0);
        for (int j = 0; j < n; ++j) {
            if (u[j] > umax) {
                umax = u[j];
                *blame = row_of[j];
            }
        }
        return CDPR_LDP_INFEASIBLE;
    }
    for (int c = 0; c < k; ++c) {
        z[c] = -r[c] / r[k] * hs;
    }
    return CDPR_LDP_OK;
}

cdpr_ldp_result_t cdpr_ldp_qp(int m, cdpr_real_t E[6][CDPR_LDP_MAX_COLS], const cdpr_real_t f[6],
                              const cdpr_real_t *lo_c, const cdpr_real_t *lo_h,
                              const cdpr_real_t *hi_c, const cdpr_real_t *hi_h, int bounded,
                              cdpr_real_t *u, cdpr_real_t *mu, int *blame)
{
    *blame = -1;
    if (m < 6 || m > LDP_C) {
        return CDPR_LDP_SINGULAR; /* not a distribution problem of this build */
    }
    /* A = E^T (m x 6), reduced in place to R; the reflections are applied to Q = I (m x m),
     * so that Q^T A = [R; 0] and Q = [Q1 Q2]. */
    cdpr_real_t A[LDP_C][6];
    cdpr_real_t Q[LDP_C][LDP_C];
    for (int i = 0; i < m; ++i) {
        for (int c = 0; c < 6; ++c) {
            A[i][c] = E[c][i];
        }
        for (int j = 0; j < m; ++j) {
            Q[i][j] = (i == j) ? CDPR_R(1.0) : CDPR_R(0.0);
        }
    }
    cdpr_real_t rmax = CDPR_R(0.0);
    for (int k = 0; k < 6; ++k) {
        cdpr_real_t nrm = CDPR_R(0.0);
        for (int i = k; i < m; ++i) {
            nrm += A[i][k] * A[i][k];
        }
        nrm = CDPR_SQRT(nrm);
        const cdpr_real_t alpha = (A[k][k] > CDPR_R(0.0)) ? -nrm : nrm;
        cdpr_real_t v[LDP_C];
        cdpr_real_t vtv = CDPR_R(0.0);
        for (int i = k; i < m; ++i) {
            v[i] = A[i][k];
        }
        v[k] -= alpha;
        for (int i = k; i < m; ++i) {
            vtv += v[i] * v[i];
        }
        if (vtv > CDPR_R(0.0)) {
            for (int c = k; c < 6; ++c) {
                cdpr_real_t s = CDPR_R(0.0);
                for (int i = k; i < m; ++i) {
                    s += v[i] * A[i][c];
                }
                const cdpr_real_t fs = CDPR_R(2.0) * s / vtv;
                for (int i = k; i < m; ++i) {
                    A[i][c] -= fs * v[i];
                }
            }
            /* Q <- Q H_k (H_k symmetric): columns k..m-1 of every row. */
            for (int row = 0; row < m; ++row) {
                cdpr_real_t s = CDPR_R(0.0);
                for (int i = k; i < m; ++i) {
                    s += Q[row][i] * v[i];
                }
                const cdpr_real_t fs = CDPR_R(2.0) * s / vtv;
                for (int i = k; i < m; ++i) {
                    Q[row][i] -= fs * v[i];
                }
            }
        }
        rmax = (CDPR_FABS(A[k][k]) > rmax) ? CDPR_FABS(A[k][k]) : rmax;
    }
    for (int k = 0; k < 6; ++k) {
        if (!(CDPR_FABS(A[k][k]) > CDPR_R(1e-12) * rmax) || !isfinite(A[k][k])) {
            return CDPR_LDP_SINGULAR;
        }
    }
    /* E u = f with u = Q1 y: R^T y = f (forward substitution). */
    cdpr_real_t y[6];
    for (int k = 0; k < 6; ++k) {
        y[k] = CDPR_R(0.0);
    }
    for (int k = 0; k < 6; ++k) {
        cdpr_real_t s = f[k];
        for (int i = 0; i < k; ++i) {
            s -= A[i][k] * y[i];
        }
        y[k] = s / A[k][k];
    }
    for (int j = 0; j < m; ++j) {
        u[j] = CDPR_R(0.0);
        for (int k = 0; k < 6; ++k) {
            u[j] += Q[j][k] * y[k];
        }
    }
    if (bounded != 0) {
        const int nz = m - 6;
        cdpr_real_t G[CDPR_LDP_MAX_ROWS][CDPR_LDP_MAX_VARS];
        cdpr_real_t h[CDPR_LDP_MAX_ROWS];
        for (int j = 0; j < m; ++j) {
            for (int c = 0; c < nz; ++c) {
                G[2 * j][c] = lo_c[j] * Q[j][6 + c];
                G[2 * j + 1][c] = hi_c[j] * Q[j][6 + c];
            }
            h[2 * j] = lo_h[j] - lo_c[j] * u[j];
            h[2 * j + 1] = hi_h[j] - hi_c[j] * u[j];
        }
        cdpr_real_t z[CDPR_LDP_MAX_VARS];
        const cdpr_ldp_result_t lr = cdpr_ldp_solve(nz, 2 * m, G, h, z, blame);
        if (lr != CDPR_LDP_OK) {
            return lr;
        }
        for (int j = 0; j < m; ++j) {
            for (int c = 0; c < nz; ++c) {
                u[j] += Q[j][6 + c] * z[c];
            }
        }
    }
    if (mu != NULL) {
        /* E^T = Q1 R: R mu = Q1^T u (back substitution). */
        for (int k = 5; k >= 0; --k) {
            cdpr_real_t s = CDPR_R(0.0);
            for (int j = 0; j < m; ++j) {
                s += Q[j][k] * u[j];
            }
            for (int c = k + 1; c < 6; ++c) {
                s -= A[k][c] * mu[c];
            }
            mu[k] = s / A[k][k];
        }
    }
    return CDPR_LDP_OK;
}
