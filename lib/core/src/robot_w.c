/* SPDX-License-Identifier: BSD-3-Clause */
/// @file robot_w.c
/// Approximate Jacobian of the robot and the block-tridiagonal solve of W (robot_w.h,
/// docs/model.md "The W-matrix of the robot").
#include "cdpr/robot_w.h"

#include <math.h>
#include <stddef.h>

#include "cdpr/cabin.h"
#include "cdpr/cable.h"
#include "cdpr/vec3.h"

cdpr_status_t cdpr_robot_w_init(cdpr_robot_w_t *w, const cdpr_robot_t *r)
{
    if (w == NULL || r == NULL) {
        return CDPR_E_INVALID_ARG;
    }
    w->robot = r;
    w->gamma_h = CDPR_R(0.0);
    w->factored = 0;
    return CDPR_OK;
}

/* Segment slots of w->seg. */
#define S_TL  0
#define S_KMT 1
#define S_TX  2
#define S_TY  3
#define S_TZ  4
#define S_CT  5

/* Linearisation of one segment from node a to node b (robot_w.h): writes T/l, dT/dl - T/l,
 * the tangent and dT/dl' into s. The tension law is that of cable.c (axial_tension). */
static void seg_lin(const cdpr_cable_params_t *p, const cdpr_real_t *ra, const cdpr_real_t *va,
                    const cdpr_real_t *rb, const cdpr_real_t *vb, cdpr_real_t lu,
                    cdpr_real_t lu_rate, cdpr_real_t *s, cdpr_real_t *dT_dlu)
{
    *dT_dlu = CDPR_R(0.0);
    const cdpr_real_t dx = rb[0] - ra[0];
    const cdpr_real_t dy = rb[1] - ra[1];
    const cdpr_real_t dz = rb[2] - ra[2];
    const cdpr_real_t l = CDPR_SQRT(dx * dx + dy * dy + dz * dz);
    if (!(l > CDPR_R(0.0))) {
        /* Coincident nodes: no direction, no force (cable.c); nothing to linearise. */
        for (int i = 0; i < 6; ++i) {
            s[i] = CDPR_R(0.0);
        }
        return;
    }
    const cdpr_real_t inv_l = CDPR_R(1.0) / l;
    const cdpr_real_t tx = dx * inv_l;
    const cdpr_real_t ty = dy * inv_l;
    const cdpr_real_t tz = dz * inv_l;
    const cdpr_real_t inv_lu = CDPR_R(1.0) / lu;
    const cdpr_real_t ratio = l * inv_lu;
    const cdpr_real_t rel = tx * (vb[0] - va[0]) + ty * (vb[1] - va[1]) + tz * (vb[2] - va[2]);
    const cdpr_real_t eps = ratio - CDPR_R(1.0);
    const cdpr_real_t eps_dot = (rel - ratio * lu_rate) * inv_lu;
    const cdpr_real_t elastic = (eps > CDPR_R(0.0)) ? (p->ea_N * eps) : CDPR_R(0.0);
    const cdpr_real_t raw = elastic + p->damping_Ns * eps_dot;
    const int moordyn = (p->slack_law == CDPR_SLACK_MOORDYN) ? 1 : 0;
    const cdpr_real_t T = (moordyn != 0 || raw > CDPR_R(0.0)) ? raw : CDPR_R(0.0);
    const int active = (moordyn != 0 || raw > CDPR_R(0.0)) ? 1 : 0;
    const cdpr_real_t dT_dl = (eps > CDPR_R(0.0) && active != 0) ? p->ea_N * inv_lu : CDPR_R(0.0);
    const cdpr_real_t dT_dldot = (active != 0) ? p->damping_Ns * inv_lu : CDPR_R(0.0);
    if (active != 0) {
        /* dT/dlu: elastic -EA l / lu^2, damper c (-l' / lu^2 + 2 l u / lu^3). */
        const cdpr_real_t el = (eps > CDPR_R(0.0)) ? -p->ea_N * ratio * inv_lu : CDPR_R(0.0);
        *dT_dlu = el + p->damping_Ns * inv_lu * inv_lu * (-rel + CDPR_R(2.0) * ratio * lu_rate);
    }
    const cdpr_real_t tl = T * inv_l;
    s[S_TL] = tl;
    s[S_KMT] = dT_dl - tl;
    s[S_TX] = tx;
    s[S_TY] = ty;
    s[S_TZ] = tz;
    s[S_CT] = dT_dldot;
}

/* P = g B + g^2 A of a segment (symmetric, packed xx xy xz yy yz zz). */
static void seg_p(const cdpr_real_t *s, cdpr_real_t g, cdpr_real_t *P)
{
    const cdpr_real_t g2 = g * g;
    const cdpr_real_t alpha = g2 * s[S_TL];
    const cdpr_real_t beta = g * s[S_CT] + g2 * s[S_KMT];
    const cdpr_real_t tx = s[S_TX];
    const cdpr_real_t ty = s[S_TY];
    const cdpr_real_t tz = s[S_TZ];
    P[0] = alpha + beta * tx * tx;
    P[1] = beta * tx * ty;
    P[2] = beta * tx * tz;
    P[3] = alpha + beta * ty * ty;
    P[4] = beta * ty * tz;
    P[5] = alpha + beta * tz * tz;
}

/* Inverse of a symmetric packed 3x3 by cofactors; 0 when singular or not finite. */
/* A symmetric 3x3 block, packed xx xy xz yy yz zz. */
typedef struct {
    cdpr_real_t a[6];
} sym3_t;

static int sym_inv(const sym3_t *Ds, cdpr_real_t Di[6])
{
    const cdpr_real_t *D = Ds->a;
    const cdpr_real_t c00 = D[3] * D[5] - D[4] * D[4];
    const cdpr_real_t c01 = D[2] * D[4] - D[1] * D[5];
    const cdpr_real_t c02 = D[1] * D[4] - D[2] * D[3];
    const cdpr_real_t det = D[0] * c00 + D[1] * c01 + D[2] * c02;
    if (!isfinite(det) || !(CDPR_FABS(det) > CDPR_R(0.0))) {
        return 0;
    }
    const cdpr_real_t id = CDPR_R(1.0) / det;
    Di[0] = c00 * id;
    Di[1] = c01 * id;
    Di[2] = c02 * id;
    Di[3] = (D[0] * D[5] - D[2] * D[2]) * id;
    Di[4] = (D[1] * D[2] - D[0] * D[4]) * id;
    Di[5] = (D[0] * D[3] - D[1] * D[1]) * id;
    for (int i = 0; i < 6; ++i) {
        if (!isfinite(Di[i])) {
            return 0;
        }
    }
    return 1;
}

/* Q = Di P, Di and P symmetric packed, Q row-major. */
static void sym_mul(const cdpr_real_t *Di, const cdpr_real_t *P, cdpr_real_t *Q)
{
    const cdpr_real_t a[9] = {Di[0], Di[1], Di[2], Di[1], Di[3], Di[4], Di[2], Di[4], Di[5]};
    const cdpr_real_t b[9] = {P[0], P[1], P[2], P[1], P[3], P[4], P[2], P[4], P[5]};
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            Q[3 * i + j] = a[3 * i] * b[j] + a[3 * i + 1] * b[3 + j] + a[3 * i + 2] * b[6 + j];
        }
    }
}

/* Full 3x3 (row-major) from packed symmetric. */
static void unpack(const cdpr_real_t *P, cdpr_real_t *F)
{
    F[0] = P[0];
    F[1] = P[1];
    F[2] = P[2];
    F[3] = P[1];
    F[4] = P[3];
    F[5] = P[4];
    F[6] = P[2];
    F[7] = P[4];
    F[8] = P[5];
}

/* C = A B, 3x3 row-major. */
static void mul33(const cdpr_real_t *A, const cdpr_real_t *B, cdpr_real_t *C)
{
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            C[3 * i + j] = A[3 * i] * B[j] + A[3 * i + 1] * B[3 + j] + A[3 * i + 2] * B[6 + j];
        }
    }
}

/* out = M v (3x3 row-major). */
static void mv33(const cdpr_real_t *M, const cdpr_real_t *v, cdpr_real_t *out)
{
    out[0] = M[0] * v[0] + M[1] * v[1] + M[2] * v[2];
    out[1] = M[3] * v[0] + M[4] * v[1] + M[5] * v[2];
    out[2] = M[6] * v[0] + M[7] * v[1] + M[8] * v[2];
}

/* out = M^T v (3x3 row-major). */
static void mtv33(const cdpr_real_t *M, const cdpr_real_t *v, cdpr_real_t *out)
{
    out[0] = M[0] * v[0] + M[3] * v[1] + M[6] * v[2];
    out[1] = M[1] * v[0] + M[4] * v[1] + M[7] * v[2];
    out[2] = M[2] * v[0] + M[5] * v[1] + M[8] * v[2];
}

/* out = D v, D symmetric packed. */
static void smv(const cdpr_real_t *D, const cdpr_real_t *v, cdpr_real_t *out)
{
    out[0] = D[0] * v[0] + D[1] * v[1] + D[2] * v[2];
    out[1] = D[1] * v[0] + D[3] * v[1] + D[4] * v[2];
    out[2] = D[2] * v[0] + D[4] * v[1] + D[5] * v[2];
}

/* Factor one cable: linearise its segments, then eliminate its nodes from the pulley end
 * (n-1) towards node 1: D'_{n-1} = D_{n-1}, D'_i = D_i - P_i R_i, R_i = D'_{i+1}^-1 P_i, with
 * D_i = m_i I + P_{i-1} + P_i. 0 when a pivot is singular. */
static int factor_cable(cdpr_robot_w_t *w, int j, const cdpr_real_t *yc, cdpr_vec3_t r0,
                        cdpr_vec3_t v0)
{
    const cdpr_robot_t *r = w->robot;
    const cdpr_cable_t *c = &r->cable[j];
    const int n = c->n;
    const int nf = n - 1;
    const cdpr_real_t *pos = yc + 1;
    const cdpr_real_t *vel = yc + 1 + 3 * nf;
    const cdpr_real_t lu_last = yc[0];
    const cdpr_real_t g = w->gamma_h;
    const cdpr_real_t ra0[3] = {r0.x, r0.y, r0.z};
    const cdpr_real_t va0[3] = {v0.x, v0.y, v0.z};
    const cdpr_vec3_t e = r->p.cables[j].exit_point_m;
    const cdpr_real_t rn[3] = {e.x, e.y, e.z};
    const cdpr_real_t vn[3] = {CDPR_R(0.0), CDPR_R(0.0), CDPR_R(0.0)};
    for (int i = 0; i < 1 + 6 * nf; ++i) {
        if (!isfinite(yc[i])) {
            return 0;
        }
    }
    if (!isfinite(r0.x + r0.y + r0.z + v0.x + v0.y + v0.z)) {
        return 0;
    }
    for (int k = 0; k < n; ++k) {
        const cdpr_real_t *ra = (k == 0) ? ra0 : pos + 3 * (k - 1);
        const cdpr_real_t *va = (k == 0) ? va0 : vel + 3 * (k - 1);
        const cdpr_real_t *rb = (k == nf) ? rn : pos + 3 * k;
        const cdpr_real_t *vb = (k == nf) ? vn : vel + 3 * k;
        const cdpr_real_t lu = (k == nf) ? lu_last : c->lu_m[k];
        const cdpr_real_t rate = (k == nf) ? r->in.payout_m_per_s[j] : CDPR_R(0.0);
        cdpr_real_t dT_dlu;
        seg_lin(&c->p, ra, va, rb, vb, lu, rate, w->seg[j][k], &dT_dlu);
        if (k == nf) {
            w->dtdlu[j] = dT_dlu;
        }
    }
    if (nf < 1) {
        return 1; /* no free node: the segment couples the cabin to the exit point only */
    }
    for (int i = 1; i <= nf; ++i) {
        w->mass[j][i - 1] = (i < nf)
                                ? CDPR_R(1.0) / c->inv_m[i]
                                : CDPR_R(0.5) * c->p.rho_kg_per_m * (c->lu_m[nf - 1] + lu_last);
    }
    seg_p(w->seg[j][0], g, w->p0[j]);
    cdpr_real_t p_hi[6]; /* P_i, the segment between node i and i + 1 */
    seg_p(w->seg[j][nf], g, p_hi);
    for (int i = nf; i >= 1; --i) {
        cdpr_real_t p_lo[6]; /* P_{i-1} */
        seg_p(w->seg[j][i - 1], g, p_lo);
        const cdpr_real_t m = w->mass[j][i - 1];
        sym3_t Ds = {{p_lo[0] + p_hi[0] + m, p_lo[1] + p_hi[1], p_lo[2] + p_hi[2],
                      p_lo[3] + p_hi[3] + m, p_lo[4] + p_hi[4], p_lo[5] + p_hi[5] + m}};
        cdpr_real_t *D = Ds.a;
        if (i < nf) {
            /* R_i = D'_{i+1}^-1 P_i; D -= P_i R_i (its symmetric part) */
            cdpr_real_t *Ri = w->q[j][i - 1];
            sym_mul(w->dinv[j][i], p_hi, Ri);
            cdpr_real_t P[9];
            unpack(p_hi, P);
            cdpr_real_t PR[9];
            mul33(P, Ri, PR);
            D[0] -= PR[0];
            D[1] -= CDPR_R(0.5) * (PR[1] + PR[3]);
            D[2] -= CDPR_R(0.5) * (PR[2] + PR[6]);
            D[3] -= PR[4];
            D[4] -= CDPR_R(0.5) * (PR[5] + PR[7]);
            D[5] -= PR[8];
        }
        if (sym_inv(&Ds, w->dinv[j][i - 1]) == 0) {
            return 0;
        }
        for (int a = 0; a < 6; ++a) {
            p_hi[a] = p_lo[a];
        }
    }
    return 1;
}

/* S += Gam^T H Gam for Gam = [I, X], H symmetric packed: the 6x6 blocks H, H X, X^T H,
 * X^T H X. */
static void cabin_add(cdpr_real_t *S, const cdpr_real_t *Hp, const cdpr_real_t *X)
{
    cdpr_real_t H[9];
    unpack(Hp, H);
    cdpr_real_t HX[9];
    mul33(H, X, HX);
    for (int a = 0; a < 3; ++a) {
        for (int b = 0; b < 3; ++b) {
            cdpr_real_t xhx = CDPR_R(0.0);
            for (int k = 0; k < 3; ++k) {
                xhx += X[3 * k + a] * HX[3 * k + b];
            }
            S[6 * a + b] += H[3 * a + b];
            S[6 * a + 3 + b] += HX[3 * a + b];
            S[6 * (3 + a) + b] += HX[3 * b + a];
            S[6 * (3 + a) + 3 + b] += xhx;
        }
    }
}

/* LU with partial pivoting of the 6x6 S in place; 0 when singular or not finite. */
static int lu6(cdpr_real_t *S, int *piv)
{
    for (int k = 0; k < 6; ++k) {
        int p = k;
        for (int i = k + 1; i < 6; ++i) {
            if (CDPR_FABS(S[6 * i + k]) > CDPR_FABS(S[6 * p + k])) {
                p = i;
            }
        }
        piv[k] = p;
        if (!isfinite(S[6 * p + k]) || !(CDPR_FABS(S[6 * p + k]) > CDPR_R(0.0))) {
            return 0;
        }
        if (p != k) {
            for (int jj = 0; jj < 6; ++jj) {
                const cdpr_real_t tmp = S[6 * k + jj];
                S[6 * k + jj] = S[6 * p + jj];
                S[6 * p + jj] = tmp;
            }
        }
        for (int i = k + 1; i < 6; ++i) {
            const cdpr_real_t l = S[6 * i + k] / S[6 * k + k];
            S[6 * i + k] = l;
            for (int jj = k + 1; jj < 6; ++jj) {
                S[6 * i + jj] -= l * S[6 * k + jj];
            }
        }
    }
    for (int i = 0; i < 36; ++i) {
        if (!isfinite(S[i])) {
            return 0;
        }
    }
    return 1;
}

static void lu6_solve(const cdpr_real_t *S, const int *piv, cdpr_real_t *z)
{
    for (int k = 0; k < 6; ++k) {
        const cdpr_real_t tmp = z[k];
        z[k] = z[piv[k]];
        z[piv[k]] = tmp;
        for (int i = k + 1; i < 6; ++i) {
            z[i] -= S[6 * i + k] * z[k];
        }
    }
    for (int i = 5; i >= 0; --i) {
        for (int jj = i + 1; jj < 6; ++jj) {
            z[i] -= S[6 * i + jj] * z[jj];
        }
        z[i] /= S[6 * i + i];
    }
}

/* Cabin part of the factorisation: Gam_j, the generalised mass and the 6x6 Schur complement
 * S = M_c + sum_j Gam_j^T (P_0 - P_0 D'_1^-1 P_0) Gam_j. 0 when singular. */
static int factor_cabin(cdpr_robot_w_t *w, const cdpr_cabin_motion_t *m)
{
    const cdpr_robot_t *r = w->robot;
    const cdpr_quat_t q = cdpr_quat_normalize(m->q);
    w->qhat[0] = q.w;
    w->qhat[1] = q.x;
    w->qhat[2] = q.y;
    w->qhat[3] = q.z;
    cdpr_mat3_t R;
    cdpr_quat_to_mat3(q, &R);
    w->mass_c = r->cabin.mass_kg;
    cdpr_real_t *S = w->s6;
    for (int i = 0; i < 36; ++i) {
        S[i] = CDPR_R(0.0);
    }
    for (int a = 0; a < 3; ++a) {
        S[6 * a + a] = w->mass_c;
        for (int b = 0; b < 3; ++b) {
            w->inertia_c[3 * a + b] = r->cabin.inertia_kg_m2.m[a][b];
            S[6 * (3 + a) + 3 + b] = r->cabin.inertia_kg_m2.m[a][b];
        }
    }
    for (int j = 0; j < r->p.n_cables; ++j) {
        const cdpr_vec3_t arm = cdpr_v3_sub(r->p.cables[j].attach_body_m, r->cabin.com_body_m);
        /* X = -R [a]x */
        const cdpr_real_t ax[9] = {CDPR_R(0.0), -arm.z, arm.y, arm.z,      CDPR_R(0.0),
                                   -arm.x,      -arm.y, arm.x, CDPR_R(0.0)};
        cdpr_real_t Rm[9];
        for (int a = 0; a < 3; ++a) {
            for (int b = 0; b < 3; ++b) {
                Rm[3 * a + b] = R.m[a][b];
            }
        }
        cdpr_real_t *X = w->gam[j];
        mul33(Rm, ax, X);
        for (int i = 0; i < 9; ++i) {
            X[i] = -X[i];
        }
        const int nf = r->cable[j].n - 1;
        cdpr_real_t H[6];
        if (nf < 1) {
            /* One segment: it ends at the fixed exit point; its full P_0 acts on the cabin. */
            seg_p(w->seg[j][0], w->gamma_h, H);
            seg_p(w->seg[j][0], w->gamma_h, w->p0[j]);
        } else {
            cdpr_real_t P[9];
            unpack(w->p0[j], P);
            cdpr_real_t DP[9];
            sym_mul(w->dinv[j][0], w->p0[j], DP);
            cdpr_real_t PDP[9];
            mul33(P, DP, PDP);
            H[0] = w->p0[j][0] - PDP[0];
            H[1] = w->p0[j][1] - CDPR_R(0.5) * (PDP[1] + PDP[3]);
            H[2] = w->p0[j][2] - CDPR_R(0.5) * (PDP[2] + PDP[6]);
            H[3] = w->p0[j][3] - PDP[4];
            H[4] = w->p0[j][4] - CDPR_R(0.5) * (PDP[5] + PDP[7]);
            H[5] = w->p0[j][5] - PDP[8];
        }
        cabin_add(S, H, X);
    }
    return lu6(S, w->piv6);
}

cdpr_status_t cdpr_robot_w_factor(void *ctx, cdpr_real_t t, const cdpr_real_t *y,
                                  cdpr_real_t gamma_h)
{
    cdpr_robot_w_t *w = (cdpr_robot_w_t *)ctx;
    if (w == NULL || w->robot == NULL || y == NULL) {
        return CDPR_E_INVALID_ARG;
    }
    w->factored = 0;
    if (!isfinite(gamma_h) || gamma_h < CDPR_R(0.0)) {
        return CDPR_E_SINGULAR;
    }
    const cdpr_robot_t *r = w->robot;
    w->gamma_h = gamma_h;
    w->cabin_implicit = (r->p.mode == CDPR_CABIN_DYNAMIC) ? 1 : 0;
    cdpr_cabin_motion_t m;
    cdpr_robot_cabin_motion(r, t, y, &m);
    for (int j = 0; j < r->p.n_cables; ++j) {
        cdpr_vec3_t r0;
        cdpr_vec3_t v0;
        cdpr_robot_attachment(r, j, &m, &r0, &v0);
        if (factor_cable(w, j, y + r->offset[j], r0, v0) == 0) {
            return CDPR_E_SINGULAR;
        }
    }
    if (w->cabin_implicit != 0 && factor_cabin(w, &m) == 0) {
        return CDPR_E_SINGULAR;
    }
    w->factored = 1;
    return CDPR_OK;
}

/* out = A d for the segment linearisation s: A = (T/l) I + (dT/dl - T/l) t tT. */
static void seg_apply(const cdpr_real_t *s, const cdpr_real_t *d, cdpr_real_t *out)
{
    const cdpr_real_t td = s[S_TX] * d[0] + s[S_TY] * d[1] + s[S_TZ] * d[2];
    const cdpr_real_t k = s[S_KMT] * td;
    out[0] = s[S_TL] * d[0] + k * s[S_TX];
    out[1] = s[S_TL] * d[1] + k * s[S_TY];
    out[2] = s[S_TL] * d[2] + k * s[S_TZ];
}

/* Gam u = u_p + X u_th (u: 6 generalised cabin components). */
static void gam_apply(const cdpr_real_t X[9], const cdpr_real_t u[6], cdpr_real_t out[3])
{
    out[0] = u[0] + (X[0] * u[3] + X[1] * u[4] + X[2] * u[5]);
    out[1] = u[1] + (X[3] * u[3] + X[4] * u[4] + X[5] * u[5]);
    out[2] = u[2] + (X[6] * u[3] + X[7] * u[4] + X[8] * u[5]);
}

/* acc += Gam^T f = (f, X^T f). */
static void gamt_add(const cdpr_real_t *X, const cdpr_real_t *f, cdpr_real_t *acc)
{
    cdpr_real_t xt[3];
    mtv33(X, f, xt);
    acc[0] += f[0];
    acc[1] += f[1];
    acc[2] += f[2];
    acc[3] += xt[0];
    acc[4] += xt[1];
    acc[5] += xt[2];
}

/* Right-hand sides and the elimination of one cable (pulley end to node 1): z_i kept in xv.
 * br0 is the position-level increment of node 0 (Gam b_u, or 0). Adds Gam^T s_0 to fc
 * (the cabin's share of g K b_u, before the factor g). */
static void cable_eliminate(const cdpr_robot_w_t *w, int j, const cdpr_real_t *b, cdpr_real_t *x,
                            const cdpr_real_t *br0, cdpr_real_t *fc)
{
    const cdpr_cable_t *c = &w->robot->cable[j];
    const int nf = c->n - 1;
    const cdpr_real_t g = w->gamma_h;
    x[0] = b[0]; /* payout row: identity */
    if (nf < 1) {
        if (fc != NULL) {
            const cdpr_real_t *s0l = w->seg[j][0];
            const cdpr_real_t d[3] = {-br0[0], -br0[1], -br0[2]};
            cdpr_real_t s0[3];
            seg_apply(s0l, d, s0);
            const cdpr_real_t f = w->dtdlu[j] * b[0];
            s0[0] += f * s0l[S_TX];
            s0[1] += f * s0l[S_TY];
            s0[2] += f * s0l[S_TZ];
            gamt_add(w->gam[j], s0, fc);
        }
        return;
    }
    const cdpr_real_t *br = b + 1;
    const cdpr_real_t *bv = b + 1 + 3 * nf;
    cdpr_real_t *xv = x + 1 + 3 * nf;
    /* The pulley-side segment's tension also moves with its length: + dT/dlu t b_lu on node
     * n-1 (the payout row is x_lu = b_lu). */
    const cdpr_real_t *sl = w->seg[j][nf];
    const cdpr_real_t flu = w->dtdlu[j] * b[0];
    /* s_k = A_k (br_{k+1} - br_k), br_0 = Gam b_u, br_n = 0; rhs_i = m_i bv_i + g (s_i - s_{i-1});
     * from the pulley end: z_{n-1} = rhs_{n-1}, z_i = rhs_i + R_i^T z_{i+1}. */
    cdpr_real_t s_hi[3];
    {
        const cdpr_real_t *bl = br + 3 * (nf - 1);
        const cdpr_real_t d[3] = {-bl[0], -bl[1], -bl[2]};
        seg_apply(w->seg[j][nf], d, s_hi);
    }
    for (int i = nf; i >= 1; --i) {
        const cdpr_real_t *bri = br + 3 * (i - 1);
        const cdpr_real_t *brl = (i > 1) ? bri - 3 : br0;
        const cdpr_real_t d[3] = {bri[0] - brl[0], bri[1] - brl[1], bri[2] - brl[2]};
        cdpr_real_t s_lo[3];
        seg_apply(w->seg[j][i - 1], d, s_lo);
        const cdpr_real_t m = w->mass[j][i - 1];
        cdpr_real_t *z = xv + 3 * (i - 1);
        const cdpr_real_t *bvi = bv + 3 * (i - 1);
        z[0] = m * bvi[0] + g * (s_hi[0] - s_lo[0]);
        z[1] = m * bvi[1] + g * (s_hi[1] - s_lo[1]);
        z[2] = m * bvi[2] + g * (s_hi[2] - s_lo[2]);
        if (i == nf) {
            z[0] += g * flu * sl[S_TX];
            z[1] += g * flu * sl[S_TY];
            z[2] += g * flu * sl[S_TZ];
        }
        if (i < nf) {
            cdpr_real_t rz[3];
            mtv33(w->q[j][i - 1], z + 3, rz);
            z[0] += rz[0];
            z[1] += rz[1];
            z[2] += rz[2];
        }
        s_hi[0] = s_lo[0];
        s_hi[1] = s_lo[1];
        s_hi[2] = s_lo[2];
    }
    if (fc != NULL) {
        gamt_add(w->gam[j], s_hi, fc); /* s_hi is s_0 now */
    }
}

/* Back substitution of one cable from node 1 to the pulley end, given the cabin velocity
 * increment xc (NULL: none): x_1 = D'_1^-1 (z_1 + P_0 Gam xc), x_{i+1} = D'_{i+1}^-1 z_{i+1} +
 * R_i x_i; then x_r = b_r + g x_v. */
static void cable_backsub(const cdpr_robot_w_t *w, int j, const cdpr_real_t *b, cdpr_real_t *x,
                          const cdpr_real_t *xc)
{
    const cdpr_cable_t *c = &w->robot->cable[j];
    const int nf = c->n - 1;
    const cdpr_real_t g = w->gamma_h;
    if (nf < 1) {
        return;
    }
    const cdpr_real_t *br = b + 1;
    cdpr_real_t *xr = x + 1;
    cdpr_real_t *xv = x + 1 + 3 * nf;
    for (int i = 1; i <= nf; ++i) {
        cdpr_real_t *v = xv + 3 * (i - 1);
        cdpr_real_t zz[3] = {v[0], v[1], v[2]};
        if (i == 1 && xc != NULL) {
            cdpr_real_t gx[3];
            gam_apply(w->gam[j], xc, gx);
            cdpr_real_t pg[3];
            smv(w->p0[j], gx, pg);
            zz[0] += pg[0];
            zz[1] += pg[1];
            zz[2] += pg[2];
        }
        cdpr_real_t o[3];
        smv(w->dinv[j][i - 1], zz, o);
        if (i > 1) {
            cdpr_real_t rx[3];
            mv33(w->q[j][i - 2], v - 3, rx);
            o[0] += rx[0];
            o[1] += rx[1];
            o[2] += rx[2];
        }
        v[0] = o[0];
        v[1] = o[1];
        v[2] = o[2];
        const cdpr_real_t *bri = br + 3 * (i - 1);
        cdpr_real_t *xri = xr + 3 * (i - 1);
        xri[0] = bri[0] + g * o[0];
        xri[1] = bri[1] + g * o[1];
        xri[2] = bri[2] + g * o[2];
    }
}

cdpr_status_t cdpr_robot_w_solve(void *ctx, const cdpr_real_t *b, cdpr_real_t *x)
{
    const cdpr_robot_w_t *w = (const cdpr_robot_w_t *)ctx;
    if (w == NULL || w->robot == NULL || b == NULL || x == NULL) {
        return CDPR_E_INVALID_ARG;
    }
    if (w->factored == 0) {
        return CDPR_E_SINGULAR;
    }
    const cdpr_robot_t *r = w->robot;
    const cdpr_real_t g = w->gamma_h;
    if (w->cabin_implicit == 0) {
        for (int i = 0; i < CDPR_CABIN_STATE_DIM; ++i) {
            x[i] = b[i]; /* cabin rows: identity (prescribed: not integrated) */
        }
        const cdpr_real_t zero[3] = {CDPR_R(0.0), CDPR_R(0.0), CDPR_R(0.0)};
        for (int j = 0; j < r->p.n_cables; ++j) {
            cable_eliminate(w, j, b + r->offset[j], x + r->offset[j], zero, NULL);
            cable_backsub(w, j, b + r->offset[j], x + r->offset[j], NULL);
        }
        return CDPR_OK;
    }
    /* Cabin position-level increments u = (b_p, 2 Xi^T b_q) and velocities (b_v, b_w). */
    const cdpr_real_t *qh = w->qhat;
    const cdpr_real_t *bq = b + CDPR_CABIN_Q;
    cdpr_real_t u[6];
    u[0] = b[CDPR_CABIN_P];
    u[1] = b[CDPR_CABIN_P + 1];
    u[2] = b[CDPR_CABIN_P + 2];
    /* Xi = [[-x,-y,-z],[w,-z,y],[z,w,-x],[-y,x,w]] (q_dot = 1/2 Xi w). */
    u[3] = CDPR_R(2.0) * (-qh[1] * bq[0] + qh[0] * bq[1] + qh[3] * bq[2] - qh[2] * bq[3]);
    u[4] = CDPR_R(2.0) * (-qh[2] * bq[0] - qh[3] * bq[1] + qh[0] * bq[2] + qh[1] * bq[3]);
    u[5] = CDPR_R(2.0) * (-qh[3] * bq[0] + qh[2] * bq[1] - qh[1] * bq[2] + qh[0] * bq[3]);
    const cdpr_real_t *bw = b + CDPR_CABIN_W;
    cdpr_real_t fc[6] = {CDPR_R(0.0), CDPR_R(0.0), CDPR_R(0.0),
                         CDPR_R(0.0), CDPR_R(0.0), CDPR_R(0.0)};
    for (int j = 0; j < r->p.n_cables; ++j) {
        cdpr_real_t br0[3];
        gam_apply(w->gam[j], u, br0);
        cable_eliminate(w, j, b + r->offset[j], x + r->offset[j], br0, fc);
    }
    /* rhs_c = M_c b_V + g sum Gam^T s_0 + sum Gam^T P_0 D'_1^-1 z_1. */
    cdpr_real_t zc[6];
    cdpr_real_t iw[3];
    mv33(w->inertia_c, bw, iw);
    zc[0] = w->mass_c * b[CDPR_CABIN_V] + g * fc[0];
    zc[1] = w->mass_c * b[CDPR_CABIN_V + 1] + g * fc[1];
    zc[2] = w->mass_c * b[CDPR_CABIN_V + 2] + g * fc[2];
    zc[3] = iw[0] + g * fc[3];
    zc[4] = iw[1] + g * fc[4];
    zc[5] = iw[2] + g * fc[5];
    for (int j = 0; j < r->p.n_cables; ++j) {
        const int nf = r->cable[j].n - 1;
        if (nf >= 1) {
            const cdpr_real_t *z1 = x + r->offset[j] + 1 + 3 * nf;
            cdpr_real_t dz[3];
            smv(w->dinv[j][0], z1, dz);
            cdpr_real_t pdz[3];
            smv(w->p0[j], dz, pdz);
            gamt_add(w->gam[j], pdz, zc);
        }
    }
    lu6_solve(w->s6, w->piv6, zc);
    for (int j = 0; j < r->p.n_cables; ++j) {
        cable_backsub(w, j, b + r->offset[j], x + r->offset[j], zc);
    }
    /* Cabin: x_v, x_w from zc; x_p = b_p + g x_v; x_q = b_q + g/2 Xi x_w. */
    for (int a = 0; a < 3; ++a) {
        x[CDPR_CABIN_V + a] = zc[a];
        x[CDPR_CABIN_W + a] = zc[3 + a];
        x[CDPR_CABIN_P + a] = b[CDPR_CABIN_P + a] + g * zc[a];
    }
    const cdpr_real_t hg = CDPR_R(0.5) * g;
    const cdpr_real_t wx = zc[3];
    const cdpr_real_t wy = zc[4];
    const cdpr_real_t wz = zc[5];
    x[CDPR_CABIN_Q] = bq[0] + hg * (-qh[1] * wx - qh[2] * wy - qh[3] * wz);
    x[CDPR_CABIN_Q + 1] = bq[1] + hg * (qh[0] * wx - qh[3] * wy + qh[2] * wz);
    x[CDPR_CABIN_Q + 2] = bq[2] + hg * (qh[3] * wx + qh[0] * wy - qh[1] * wz);
    x[CDPR_CABIN_Q + 3] = bq[3] + hg * (-qh[2] * wx + qh[1] * wy + qh[0] * wz);
    return CDPR_OK;
}
