/* SPDX-License-Identifier: BSD-3-Clause */
/// @file statics.c
/// Sag-aware statics and inverse kinematics (docs/model.md "Sag-aware inverse kinematics, with an
/// external wrench"; see statics.h).
#include "cdpr/statics.h"

#include <math.h>
#include <stddef.h>

#include "cdpr/catenary.h"
#include "check.h"

#define NC 6 /* the wrench has 6 components */
/* Cables of one robot, at least 6 (array sizes). */
#define MC ((CDPR_MAX_CABLES > NC) ? CDPR_MAX_CABLES : NC)

/* The redundant path (more than six cables: the tension distribution's SQP and its
 * least-distance problems) exists only in a build that can hold such a robot; a six-cable
 * build (the Cortex-M presets) carries neither its code nor its stack. */
#if CDPR_MAX_CABLES > NC
#define CDPR_STATICS_REDUNDANT 1
#include "ldp.h"
#else
#define CDPR_STATICS_REDUNDANT 0
#endif

void cdpr_statics_opts_default(cdpr_statics_opts_t *o)
{
    o->max_iter = 50;
#ifdef CDPR_REAL_IS_FLOAT
    /* Measured floors of the float build (50 m model, random poses; statics.h): the
     * inner catenary residual reaches ~5e-5 m on ~30 m spans (1e-5 m fails at 14 % of the
     * poses), the wrench residual ~1e-2 N on tensions up to ~600 N. */
    o->force_tol_N = CDPR_R(2e-2);
    o->span_tol_m = CDPR_R(1e-4);
#else
    o->force_tol_N = CDPR_R(1e-7);
    o->span_tol_m = CDPR_R(1e-10);
#endif
}

/* Solve A x = b (n x n, n <= 6) by Gaussian elimination with partial pivoting; A and b are
 * overwritten. Returns -1 if singular: a pivot not above min_pivot in magnitude, or not finite. */
static int solve_linear(int n, cdpr_real_t A[NC][MC], cdpr_real_t b[NC], cdpr_real_t x[NC],
                        cdpr_real_t min_pivot)
{
    for (int k = 0; k < n; ++k) {
        int piv = k;
        for (int i = k + 1; i < n; ++i) {
            if (CDPR_FABS(A[i][k]) > CDPR_FABS(A[piv][k])) {
                piv = i;
            }
        }
        if (!(CDPR_FABS(A[piv][k]) > min_pivot) || !isfinite(A[piv][k])) {
            return -1;
        }
        if (piv != k) {
            for (int j = 0; j < n; ++j) {
                const cdpr_real_t tmp = A[k][j];
                A[k][j] = A[piv][j];
                A[piv][j] = tmp;
            }
            const cdpr_real_t tb = b[k];
            b[k] = b[piv];
            b[piv] = tb;
        }
        for (int i = k + 1; i < n; ++i) {
            const cdpr_real_t f = A[i][k] / A[k][k];
            for (int j = k; j < n; ++j) {
                A[i][j] -= f * A[k][j];
            }
            b[i] -= f * b[k];
        }
    }
    for (int i = n - 1; i >= 0; --i) {
        cdpr_real_t sum = b[i];
        for (int j = i + 1; j < n; ++j) {
            sum -= A[i][j] * x[j];
        }
        x[i] = sum / A[i][i];
    }
    return 0;
}

/* Geometry of cable j at a pose: attachment P, horizontal unit e toward the exit point,
 * horizontal span l and rise h, lever arm R (b - c) about the cabin CoM. */
typedef struct {
    cdpr_vec3_t P;
    cdpr_vec3_t e;
    cdpr_vec3_t arm;
    cdpr_real_t l;
    cdpr_real_t h;
} geom_t;

static cdpr_status_t geometry(const cdpr_robot_t *r, const cdpr_cabin_motion_t *pose, geom_t *g)
{
    cdpr_mat3_t R;
    cdpr_quat_to_mat3(cdpr_quat_normalize(pose->q), &R);
    for (int j = 0; j < r->p.n_cables; ++j) {
        const cdpr_vec3_t b = r->p.cables[j].attach_body_m;
        const cdpr_vec3_t rb = cdpr_m3_mul_v3(&R, b);
        g[j].P = cdpr_v3_add(pose->p_m, rb);
        g[j].arm = cdpr_m3_mul_v3(&R, cdpr_v3_sub(b, r->p.cabin.com_body_m));
        const cdpr_vec3_t d = cdpr_v3_sub(r->p.cables[j].exit_point_m, g[j].P);
        g[j].l = CDPR_SQRT(d.x * d.x + d.y * d.y);
        g[j].h = d.z;
        /* A vertical cable has no catenary plane (H = 0); not supported by this solver. */
        if (!(g[j].l > CDPR_R(1e-9) * (CDPR_FABS(d.z) + CDPR_R(1.0)))) {
            return CDPR_E_GEOMETRY;
        }
        g[j].e = cdpr_v3(d.x / g[j].l, d.y / g[j].l, CDPR_R(0.0));
    }
    return CDPR_OK;
}

static cdpr_catenary_cable_t cat_of(const cdpr_robot_t *r, int j)
{
    cdpr_catenary_cable_t c;
    c.w_N_per_m = r->p.cables[j].cable.rho_kg_per_m * r->p.g_m_per_s2;
    c.ea_N = r->p.cables[j].cable.ea_N;
    return c;
}

/* Inner problem of one cable: given H, the (V, L) whose catenary spans (l, h); also dV/dH.
 * Newton from (Vg, Lg) with backtracking (L kept positive). */
static cdpr_status_t inner(const cdpr_catenary_cable_t *c, const geom_t *g, cdpr_real_t H,
                           const cdpr_statics_opts_t *o, cdpr_real_t *V, cdpr_real_t *L,
                           cdpr_real_t *dVdH, cdpr_real_t *dLdH)
{
    cdpr_real_t v = *V;
    cdpr_real_t len = *L;
    for (int it = 0; it <= o->max_iter; ++it) {
        cdpr_real_t sp[2];
        cdpr_real_t dH[2];
        cdpr_real_t dV[2];
        cdpr_real_t dL[2];
        cdpr_catenary_spans_jac(c, H, v, len, sp, dH, dV, dL);
        const cdpr_real_t f0 = sp[0] - g->l;
        const cdpr_real_t f1 = sp[1] - g->h;
        const cdpr_real_t det = dV[0] * dL[1] - dL[0] * dV[1];
        if (!(CDPR_FABS(det) > CDPR_R(0.0)) || !isfinite(det)) {
            return CDPR_E_NO_CONVERGENCE;
        }
        const cdpr_real_t fn = CDPR_FABS(f0) + CDPR_FABS(f1);
        if (fn <= o->span_tol_m) {
            *V = v;
            *L = len;
            /* Implicit function theorem: d(V, L)/dH = -J^-1 dG/dH. */
            *dVdH = -(dL[1] * dH[0] - dL[0] * dH[1]) / det;
            *dLdH = -(dV[0] * dH[1] - dV[1] * dH[0]) / det;
            return CDPR_OK;
        }
        const cdpr_real_t sv = -(dL[1] * f0 - dL[0] * f1) / det;
        const cdpr_real_t sl = -(-dV[1] * f0 + dV[0] * f1) / det;
        cdpr_real_t a = CDPR_R(1.0);
        int ok = 0;
        for (int b = 0; b < 40; ++b) {
            const cdpr_real_t vn = v + a * sv;
            const cdpr_real_t ln = len + a * sl;
            if (ln > CDPR_R(0.0)) {
                cdpr_real_t x;
                cdpr_real_t z;
                cdpr_catenary_point(c, H, vn, ln, &x, &z);
                if (CDPR_FABS(x - g->l) + CDPR_FABS(z - g->h) < fn) {
                    v = vn;
                    len = ln;
                    ok = 1;
                    break;
                }
            }
            a *= CDPR_R(0.5);
        }
        if (ok == 0) {
            return CDPR_E_NO_CONVERGENCE;
        }
    }
    return CDPR_E_NO_CONVERGENCE;
}

/* Inextensible catenary through (0, 0) and (l, h) with horizontal tension H (parameter
 * a = H/w): z = a cosh((x - x0)/a) + const, h = 2 a sinh((l - 2 x0)/(2a)) sinh(l/(2a)).
 * Gives V_A = -H sinh(x0/a) and L = a (sinh((l - x0)/a) + sinh(x0/a)): the starting point of
 * the inner Newton when the warm start fails (e.g. small H, deep sag). 0 on success. */
static int inextensible_guess(const cdpr_catenary_cable_t *c, const geom_t *g, cdpr_real_t H,
                              cdpr_real_t *V, cdpr_real_t *L)
{
    const cdpr_real_t a = H / c->w_N_per_m;
    const cdpr_real_t half = g->l / (CDPR_R(2.0) * a);
    if (!(half < CDPR_R(300.0))) {
        return -1; /* sinh would overflow: sag far beyond any robot configuration */
    }
    const cdpr_real_t x0 =
        CDPR_R(0.5) * g->l - a * CDPR_ASINH(g->h / (CDPR_R(2.0) * a * CDPR_SINH(half)));
    const cdpr_real_t len = a * (CDPR_SINH((g->l - x0) / a) + CDPR_SINH(x0 / a));
    const cdpr_real_t v = -H * CDPR_SINH(x0 / a);
    /* Elastic stretch at the mean tension shortens the unstretched length. */
    const cdpr_real_t tm = CDPR_SQRT(H * H + (v + CDPR_R(0.5) * c->w_N_per_m * len) *
                                                 (v + CDPR_R(0.5) * c->w_N_per_m * len));
    *V = v;
    *L = len / (CDPR_R(1.0) + tm / c->ea_N);
    return (isfinite(*V) && isfinite(*L) && *L > CDPR_R(0.0)) ? 0 : -1;
}

/* Inner solve with a warm start, falling back to the inextensible catenary guess. */
static cdpr_status_t inner_robust(const cdpr_catenary_cable_t *c, const geom_t *g, cdpr_real_t H,
                                  const cdpr_statics_opts_t *o, cdpr_real_t *V, cdpr_real_t *L,
                                  cdpr_real_t *dVdH, cdpr_real_t *dLdH)
{
    cdpr_real_t v = *V;
    cdpr_real_t len = *L;
    if (inner(c, g, H, o, &v, &len, dVdH, dLdH) == CDPR_OK) {
        *V = v;
        *L = len;
        return CDPR_OK;
    }
    if (inextensible_guess(c, g, H, &v, &len) != 0) {
        return CDPR_E_NO_CONVERGENCE;
    }
    CDPR_TRY(inner(c, g, H, o, &v, &len, dVdH, dLdH));
    *V = v;
    *L = len;
    return CDPR_OK;
}

/* The load the cables balance, as the constant part of the wrench residual: force
 * -M g z + f_ext (acting at the CoM) and moment tau_ext about the CoM, world axes; `scale`
 * (N, N m) sizes the rounding of the wrench sums for the tolerances. */
typedef struct {
    cdpr_vec3_t f;
    cdpr_vec3_t m;
    cdpr_real_t scale;
} load_t;

static load_t make_load(const cdpr_robot_t *r, cdpr_vec3_t f_ext, cdpr_vec3_t tau_ext)
{
    load_t ld;
    const cdpr_real_t weight = r->p.cabin.mass_kg * r->p.g_m_per_s2;
    ld.f = cdpr_v3(f_ext.x, f_ext.y, f_ext.z - weight);
    ld.m = tau_ext;
    ld.scale = weight + cdpr_v3_norm(f_ext) + cdpr_v3_norm(tau_ext);
    return ld;
}

/* Column j of a 6 x 6 wrench matrix: force f (rows 0-2) and moment m (rows 3-5). */
static void set_wrench_column(cdpr_real_t M[NC][MC], int j, cdpr_vec3_t f, cdpr_vec3_t m)
{
    M[0][j] = f.x;
    M[1][j] = f.y;
    M[2][j] = f.z;
    M[3][j] = m.x;
    M[4][j] = m.y;
    M[5][j] = m.z;
}

/* Wrench residual for given H (and its Jacobian if J != NULL): force sum_j F_j + ld->f and
 * moment sum_j arm_j x F_j + ld->m, over the robot's cables. Updates V, L (warm starts) per
 * cable, and dV/dH, dL/dH when dVdH, dLdH are not NULL. */
static cdpr_status_t wrench(const cdpr_robot_t *r, const geom_t *g, const cdpr_real_t *H,
                            const cdpr_statics_opts_t *o, const load_t *ld, cdpr_real_t *V,
                            cdpr_real_t *L, cdpr_real_t res[NC], cdpr_real_t J[NC][MC],
                            cdpr_real_t *dVdH, cdpr_real_t *dLdH)
{
    cdpr_vec3_t f = ld->f;
    cdpr_vec3_t m = ld->m;
    for (int j = 0; j < r->p.n_cables; ++j) {
        const cdpr_catenary_cable_t c = cat_of(r, j);
        cdpr_real_t dvdh = CDPR_R(0.0);
        cdpr_real_t dldh = CDPR_R(0.0);
        CDPR_TRY(inner_robust(&c, &g[j], H[j], o, &V[j], &L[j], &dvdh, &dldh));
        if (dVdH != NULL && dLdH != NULL) {
            dVdH[j] = dvdh;
            dLdH[j] = dldh;
        }
        const cdpr_vec3_t F = cdpr_v3(H[j] * g[j].e.x, H[j] * g[j].e.y, V[j]);
        f = cdpr_v3_add(f, F);
        m = cdpr_v3_add(m, cdpr_v3_cross(g[j].arm, F));
        if (J != NULL) {
            const cdpr_vec3_t dF = cdpr_v3(g[j].e.x, g[j].e.y, dvdh);
            set_wrench_column(J, j, dF, cdpr_v3_cross(g[j].arm, dF));
        }
    }
    cdpr_v3_store(f, res);
    cdpr_v3_store(m, &res[3]);
    return CDPR_OK;
}

static cdpr_real_t norm6(const cdpr_real_t v[NC])
{
    cdpr_real_t s = CDPR_R(0.0);
    for (int i = 0; i < NC; ++i) {
        s += v[i] * v[i];
    }
    return CDPR_SQRT(s);
}

static cdpr_status_t check_pose(const cdpr_cabin_motion_t *pose)
{
    if (cdpr_v3_isfinite(pose->p_m) == 0 || !isfinite(pose->q.w) || !isfinite(pose->q.x) ||
        !isfinite(pose->q.y) || !isfinite(pose->q.z)) {
        return CDPR_E_NOT_FINITE;
    }
    return CDPR_OK;
}

/* Fill one cable's result from (H, V, L) and its geometry. */
static void fill_cable(const cdpr_robot_t *r, int j, const geom_t *g, cdpr_real_t H, cdpr_real_t V,
                       cdpr_real_t L, cdpr_statics_cable_t *out)
{
    const cdpr_real_t w = r->p.cables[j].cable.rho_kg_per_m * r->p.g_m_per_s2;
    const cdpr_real_t vb = V + w * L;
    out->H_N = H;
    out->v_cabin_N = V;
    out->length_m = L;
    out->tension_cabin_N = CDPR_SQRT(H * H + V * V);
    out->tension_winch_N = CDPR_SQRT(H * H + vb * vb);
    out->force_on_cabin_N = cdpr_v3(H * g->e.x, H * g->e.y, V);
    out->attach_world_m = g->P;
}

/* Massless straight cables balancing the load `ld` (pose and geometry checked by the caller;
 * six cables). On CDPR_E_INFEASIBLE with a solution, *neg_cable (if not NULL) is the cable
 * with the lowest tension, else -1. */
static cdpr_status_t ik_straight_load(const cdpr_robot_t *r, const cdpr_cabin_motion_t *pose,
                                      const geom_t *g, const load_t *ld, cdpr_statics_result_t *res,
                                      int *neg_cable)
{
    cdpr_real_t A[NC][MC];
    cdpr_real_t b[NC] = {-ld->f.x, -ld->f.y, -ld->f.z, -ld->m.x, -ld->m.y, -ld->m.z};
    cdpr_real_t chord[NC];
    for (int j = 0; j < NC; ++j) {
        chord[j] = CDPR_SQRT(g[j].l * g[j].l + g[j].h * g[j].h);
        const cdpr_vec3_t u =
            cdpr_v3(g[j].l * g[j].e.x / chord[j], g[j].l * g[j].e.y / chord[j], g[j].h / chord[j]);
        set_wrench_column(A, j, u, cdpr_v3_cross(g[j].arm, u));
    }
    cdpr_real_t t[NC];
    if (neg_cable != NULL) {
        *neg_cable = -1;
    }
    if (solve_linear(NC, A, b, t, CDPR_R(0.0)) != 0) {
        return CDPR_E_INFEASIBLE; /* singular: the cables cannot span the wrench */
    }
    int lowest = 0;
    for (int j = 1; j < NC; ++j) {
        lowest = (t[j] < t[lowest]) ? j : lowest;
    }
    if (!(t[lowest] > CDPR_R(0.0))) {
        if (neg_cable != NULL) {
            *neg_cable = lowest;
        }
        return CDPR_E_INFEASIBLE;
    }
    res->n_cables = NC;
    for (int j = 0; j < NC; ++j) {
        const cdpr_real_t H = t[j] * g[j].l / chord[j];
        const cdpr_real_t V = t[j] * g[j].h / chord[j];
        const cdpr_real_t L = chord[j] / (CDPR_R(1.0) + t[j] / r->p.cables[j].cable.ea_N);
        fill_cable(r, j, &g[j], H, V, L, &res->cable[j]);
        res->cable[j].tension_winch_N = t[j]; /* massless: same tension at both ends */
    }
    res->pose = *pose;
    res->pose.v_m_per_s = cdpr_v3(CDPR_R(0.0), CDPR_R(0.0), CDPR_R(0.0));
    res->pose.w_rad_per_s = res->pose.v_m_per_s;
    res->iterations = 0;
    res->residual = CDPR_R(0.0);
    return CDPR_OK;
}

cdpr_status_t cdpr_statics_ik_straight(const cdpr_robot_t *r, const cdpr_cabin_motion_t *pose,
                                       cdpr_statics_result_t *res)
{
    if (r == NULL || pose == NULL || res == NULL || r->p.n_cables != NC) {
        return CDPR_E_INVALID_ARG;
    }
    CDPR_TRY(check_pose(pose));
    geom_t g[MC];
    CDPR_TRY(geometry(r, pose, g));
    const cdpr_vec3_t zero = cdpr_v3(CDPR_R(0.0), CDPR_R(0.0), CDPR_R(0.0));
    const load_t ld = make_load(r, zero, zero);
    return ik_straight_load(r, pose, g, &ld, res, NULL);
}

cdpr_status_t cdpr_statics_straight_tensions(const cdpr_robot_t *r, const cdpr_cabin_motion_t *pose,
                                             cdpr_vec3_t f_ext_N, cdpr_vec3_t tau_ext_Nm,
                                             cdpr_real_t *tension_N)
{
    if (r == NULL || pose == NULL || tension_N == NULL || r->p.n_cables != NC) {
        return CDPR_E_INVALID_ARG;
    }
    CDPR_TRY(check_pose(pose));
    if (cdpr_v3_isfinite(f_ext_N) == 0 || cdpr_v3_isfinite(tau_ext_Nm) == 0) {
        return CDPR_E_NOT_FINITE;
    }
    cdpr_mat3_t R;
    cdpr_quat_to_mat3(cdpr_quat_normalize(pose->q), &R);
    cdpr_real_t A[NC][MC];
    cdpr_real_t amax = CDPR_R(0.0);
    for (int j = 0; j < NC; ++j) {
        const cdpr_robot_cable_params_t *c = &r->p.cables[j];
        const cdpr_vec3_t rb = cdpr_m3_mul_v3(&R, c->attach_body_m);
        const cdpr_vec3_t d = cdpr_v3_sub(c->exit_point_m, cdpr_v3_add(pose->p_m, rb));
        const cdpr_real_t l = cdpr_v3_norm(d);
        const cdpr_vec3_t u = (l > CDPR_R(0.0)) ? cdpr_v3_scale(d, CDPR_R(1.0) / l)
                                                : cdpr_v3(CDPR_R(0.0), CDPR_R(0.0), CDPR_R(0.0));
        const cdpr_vec3_t arm =
            cdpr_m3_mul_v3(&R, cdpr_v3_sub(c->attach_body_m, r->p.cabin.com_body_m));
        set_wrench_column(A, j, u, cdpr_v3_cross(arm, u));
        for (int i = 0; i < NC; ++i) {
            amax = (CDPR_FABS(A[i][j]) > amax) ? CDPR_FABS(A[i][j]) : amax;
        }
    }
    /* sum t_j u_j = M g z - f_ext, sum t_j (arm_j x u_j) = -tau_ext. */
    const cdpr_real_t w = r->p.cabin.mass_kg * r->p.g_m_per_s2;
    cdpr_real_t b[NC] = {-f_ext_N.x,    -f_ext_N.y,    w - f_ext_N.z,
                         -tau_ext_Nm.x, -tau_ext_Nm.y, -tau_ext_Nm.z};
    if (solve_linear(NC, A, b, tension_N, CDPR_R(1e-12) * amax) != 0) {
        return CDPR_E_INFEASIBLE; /* the chords do not span the wrench */
    }
    return CDPR_OK;
}

static cdpr_status_t check_opts(const cdpr_statics_opts_t *o)
{
    if (o == NULL || o->max_iter < 1) {
        return CDPR_E_INVALID_ARG;
    }
    CDPR_TRY(check_positive(o->force_tol_N, "force_tol_N", -1, NULL));
    CDPR_TRY(check_positive(o->span_tol_m, "span_tol_m", -1, NULL));
    return CDPR_OK;
}

cdpr_status_t cdpr_statics_ik(const cdpr_robot_t *r, const cdpr_cabin_motion_t *pose,
                              const cdpr_statics_opts_t *o, cdpr_statics_result_t *res)
{
    const cdpr_vec3_t zero = cdpr_v3(CDPR_R(0.0), CDPR_R(0.0), CDPR_R(0.0));
    return cdpr_statics_ik_wrench(r, pose, zero, zero, o, res);
}

/* 1 if some exit point of the n cables is above its attachment. */
static int any_exit_above(const geom_t *g, int n)
{
    int any_above = 0;
    for (int j = 0; j < n; ++j) {
        any_above |= (g[j].h > CDPR_R(0.0)) ? 1 : 0;
    }
    return any_above;
}

/* Unknowns of the outer Newton of the IK and what they give: H, V, L per cable, the wrench
 * residual rv, its Jacobian J (destroyed by each linear solve) and the norm rn of rv. */
typedef struct {
    cdpr_real_t H[MC];
    cdpr_real_t V[MC];
    cdpr_real_t L[MC];
    cdpr_real_t rv[NC];
    cdpr_real_t J[NC][MC];
    cdpr_real_t rn;
} ik_iter_t;

/* Starting point of the outer iteration from massless tensions `tension` (one per cable), or,
 * when it is NULL, an even share of the load per cable. O(cables). */
static void ik_start(const cdpr_robot_t *r, const geom_t *g, const load_t *ld,
                     const cdpr_real_t *tension, ik_iter_t *s)
{
    for (int j = 0; j < r->p.n_cables; ++j) {
        const cdpr_real_t chord = CDPR_SQRT(g[j].l * g[j].l + g[j].h * g[j].h);
        const cdpr_real_t t =
            (tension != NULL) ? tension[j] : ld->scale / (cdpr_real_t)r->p.n_cables;
        const cdpr_real_t w = r->p.cables[j].cable.rho_kg_per_m * r->p.g_m_per_s2;
        s->H[j] = t * g[j].l / chord;
        /* A massless tension near zero means a deep sag in reality: start no lower than the
         * H of a catenary whose sag is about its span (H = w l / 8), where the inner problem
         * is well conditioned; Newton moves it from there. */
        const cdpr_real_t h_floor = w * g[j].l / CDPR_R(8.0);
        s->H[j] = (s->H[j] > h_floor) ? s->H[j] : h_floor;
        s->L[j] = chord / (CDPR_R(1.0) + t / r->p.cables[j].cable.ea_N);
        s->V[j] = t * g[j].h / chord - CDPR_R(0.5) * w * s->L[j];
    }
}

/* Newton step dH from J dH = -rv (s->J is destroyed). 0 on success, with *wants_push = 1 if
 * the full step would make some H non-positive (*push_cable: the one it takes lowest); -1 if
 * J is singular (*wants_push, *push_cable untouched). */
static int ik_direction(ik_iter_t *s, cdpr_real_t dH[NC], int *wants_push, int *push_cable)
{
    cdpr_real_t b[NC];
    for (int i = 0; i < NC; ++i) {
        b[i] = -s->rv[i];
    }
    const int singular = solve_linear(NC, s->J, b, dH, CDPR_R(0.0));
    if (singular == 0) {
        int push = 0;
        int lowest = 0;
        for (int j = 0; j < NC; ++j) {
            push |= (s->H[j] + dH[j] > CDPR_R(0.0)) ? 0 : 1;
            lowest = (s->H[j] + dH[j] < s->H[lowest] + dH[lowest]) ? j : lowest;
        }
        *wants_push = push;
        if (push != 0) {
            *push_cable = lowest;
        }
    }
    return singular;
}

/* Backtracking along dH: halve the step (at most 40 times) until every H stays positive and
 * the residual norm decreases. 1 with s moved there, or 0 with s unchanged. */
static int ik_line_search(const cdpr_robot_t *r, const geom_t *g, const cdpr_statics_opts_t *o,
                          const load_t *ld, const cdpr_real_t dH[NC], ik_iter_t *s)
{
    cdpr_real_t a = CDPR_R(1.0);
    int ok = 0;
    for (int k = 0; k < 40; ++k) {
        ik_iter_t n;
        int positive = 1;
        for (int j = 0; j < NC; ++j) {
            n.H[j] = s->H[j] + a * dH[j];
            n.V[j] = s->V[j];
            n.L[j] = s->L[j];
            positive &= (n.H[j] > CDPR_R(0.0)) ? 1 : 0;
        }
        if (positive != 0 && wrench(r, g, n.H, o, ld, n.V, n.L, n.rv, n.J, NULL, NULL) == CDPR_OK &&
            norm6(n.rv) < s->rn) {
            n.rn = norm6(n.rv);
            *s = n;
            ok = 1;
            break;
        }
        a *= CDPR_R(0.5);
    }
    return ok;
}

/* Record a verdict (v may be NULL). */
static void set_why(cdpr_statics_verdict_t *v, cdpr_statics_why_t why, int cable, cdpr_real_t value,
                    cdpr_real_t limit)
{
    if (v != NULL) {
        v->why = why;
        v->cable = cable;
        v->value = value;
        v->limit = limit;
    }
}

/* Outer Newton from s (residual and Jacobian evaluated) until s->rn <= tol, at most
 * o->max_iter iterations (*iterations: the count used, on success). `fail` is the status of a
 * failure that is not attributed to a pushing cable. Six cables. */
static cdpr_status_t ik_newton(const cdpr_robot_t *r, const geom_t *g, const cdpr_statics_opts_t *o,
                               const load_t *ld, cdpr_real_t tol, cdpr_status_t fail, ik_iter_t *s,
                               int *iterations, cdpr_statics_verdict_t *why)
{
    int it = 0;
    int wants_push = 0; /* the last full Newton step would have made some H non-positive */
    int push_cable = -1;
    while (s->rn > tol) {
        if (it >= o->max_iter) {
            if (wants_push != 0) {
                set_why(why, CDPR_STATICS_WHY_PUSH, push_cable, s->H[push_cable], CDPR_R(0.0));
                return CDPR_E_INFEASIBLE;
            }
            return fail;
        }
        ++it;
        cdpr_real_t dH[NC];
        if (ik_direction(s, dH, &wants_push, &push_cable) != 0) {
            set_why(why, CDPR_STATICS_WHY_SPAN, -1, (cdpr_real_t)NAN, (cdpr_real_t)NAN);
            return CDPR_E_INFEASIBLE;
        }
        if (ik_line_search(r, g, o, ld, dH, s) == 0) {
            /* Stuck while the Newton step points through H = 0, or against it: the
             * equilibrium would need a pushing cable. */
            for (int j = 0; j < NC; ++j) {
                if (s->H[j] < CDPR_R(1e-6) * ld->scale) {
                    wants_push = 1;
                    push_cable = j;
                }
            }
            if (wants_push != 0) {
                set_why(why, CDPR_STATICS_WHY_PUSH, push_cable, s->H[push_cable], CDPR_R(0.0));
                return CDPR_E_INFEASIBLE;
            }
            return fail;
        }
    }
    *iterations = it;
    return CDPR_OK;
}

/* Write the converged IK into res: the cables, the pose at rest, the iteration count. */
static void ik_fill_result(const cdpr_robot_t *r, const cdpr_cabin_motion_t *pose, const geom_t *g,
                           const ik_iter_t *s, int it, cdpr_statics_result_t *res)
{
    res->n_cables = r->p.n_cables;
    for (int j = 0; j < r->p.n_cables; ++j) {
        fill_cable(r, j, &g[j], s->H[j], s->V[j], s->L[j], &res->cable[j]);
    }
    res->pose = *pose;
    res->pose.v_m_per_s = cdpr_v3(CDPR_R(0.0), CDPR_R(0.0), CDPR_R(0.0));
    res->pose.w_rad_per_s = res->pose.v_m_per_s;
    res->iterations = it;
    res->residual = s->rn;
}

/* CDPR_E_INFEASIBLE (LOOP) if some cable of the solution s is longer than
 * CDPR_STATICS_MAX_LENGTH_PER_CHORD chords: the first such cable is named. */
static cdpr_status_t check_loops(const cdpr_robot_t *r, const geom_t *g, const ik_iter_t *s,
                                 cdpr_statics_verdict_t *why)
{
    for (int j = 0; j < r->p.n_cables; ++j) {
        const cdpr_real_t chord = CDPR_SQRT(g[j].l * g[j].l + g[j].h * g[j].h);
        const cdpr_real_t ratio = s->L[j] / chord;
        if (!(ratio <= CDPR_STATICS_MAX_LENGTH_PER_CHORD)) {
            set_why(why, CDPR_STATICS_WHY_LOOP, j, ratio, CDPR_STATICS_MAX_LENGTH_PER_CHORD);
            return CDPR_E_INFEASIBLE;
        }
    }
    return CDPR_OK;
}

/* Lowest and highest tension along a catenary of horizontal tension H, vertical component V
 * at the cabin end, weight w per unstretched length and length L (V grows by w per length
 * toward the upper end), with their derivatives in H given dV/dH and dL/dH. The lowest
 * tension grows with H on every branch (cabin end, vertex, upper end) and is C^1 where the
 * branches meet (V = 0: the cabin-end tension is H there, with slope 1). */
typedef struct {
    cdpr_real_t lo;
    cdpr_real_t dlo;
    cdpr_real_t hi;
    cdpr_real_t dhi;
} tension_range_t;

static tension_range_t tension_range(cdpr_real_t H, cdpr_real_t V, cdpr_real_t w, cdpr_real_t L,
                                     cdpr_real_t dV, cdpr_real_t dL)
{
    tension_range_t t;
    const cdpr_real_t vb = V + w * L;
    const cdpr_real_t tc = CDPR_SQRT(H * H + V * V);
    const cdpr_real_t tb = CDPR_SQRT(H * H + vb * vb);
    const cdpr_real_t dtc = (H + V * dV) / tc;
    const cdpr_real_t dtb = (H + vb * (dV + w * dL)) / tb;
    if (!(V < CDPR_R(0.0))) {
        t.lo = tc; /* rises from the cabin: lowest at the cabin end */
        t.dlo = dtc;
    } else if (!(vb > CDPR_R(0.0))) {
        t.lo = tb; /* falls all the way to the upper end */
        t.dlo = dtb;
    } else {
        t.lo = H; /* dips below the cabin end: lowest at the vertex */
        t.dlo = CDPR_R(1.0);
    }
    if (tc > tb) {
        t.hi = tc;
        t.dhi = dtc;
    } else {
        t.hi = tb;
        t.dhi = dtb;
    }
    return t;
}

#if CDPR_STATICS_REDUNDANT
/* The tension range of cable j of the iterate s, its derivatives from dV, dL. */
static tension_range_t cable_range(const cdpr_robot_t *r, int j, const ik_iter_t *s,
                                   const cdpr_real_t *dV, const cdpr_real_t *dL)
{
    const cdpr_real_t w = r->p.cables[j].cable.rho_kg_per_m * r->p.g_m_per_s2;
    return tension_range(s->H[j], s->V[j], w, s->L[j], dV[j], dL[j]);
}
#endif

/* CDPR_E_INFEASIBLE (T_MIN or T_MAX) if a cable's tension range leaves [t_min - tol,
 * t_max + tol]: the cable with the largest violation is named. */
static cdpr_status_t check_bounds(const cdpr_robot_t *r, const ik_iter_t *s,
                                  const cdpr_statics_dist_t *d, cdpr_real_t tol,
                                  cdpr_statics_verdict_t *why)
{
    cdpr_real_t worst = tol;
    cdpr_statics_why_t kind = CDPR_STATICS_WHY_NONE;
    int cable = -1;
    cdpr_real_t value = CDPR_R(0.0);
    for (int j = 0; j < r->p.n_cables; ++j) {
        const cdpr_real_t w = r->p.cables[j].cable.rho_kg_per_m * r->p.g_m_per_s2;
        const tension_range_t t =
            tension_range(s->H[j], s->V[j], w, s->L[j], CDPR_R(0.0), CDPR_R(0.0));
        if (d->t_min_N - t.lo > worst) {
            worst = d->t_min_N - t.lo;
            kind = CDPR_STATICS_WHY_T_MIN;
            cable = j;
            value = t.lo;
        }
        if (t.hi - d->t_max_N > worst) {
            worst = t.hi - d->t_max_N;
            kind = CDPR_STATICS_WHY_T_MAX;
            cable = j;
            value = t.hi;
        }
    }
    if (cable >= 0) {
        set_why(why, kind, cable, value,
                (kind == CDPR_STATICS_WHY_T_MIN) ? d->t_min_N : d->t_max_N);
        return CDPR_E_INFEASIBLE;
    }
    return CDPR_OK;
}

/* Six cables: Newton on the six H from the massless solution (the inverse problem is square). */
static cdpr_status_t ik_square(const cdpr_robot_t *r, const cdpr_cabin_motion_t *pose,
                               const geom_t *g, const load_t *ld, const cdpr_statics_opts_t *o,
                               cdpr_real_t tol, ik_iter_t *s, int *iterations,
                               cdpr_statics_verdict_t *why)
{
    /* Start from the massless solution where it exists, else an even share of the load. */
    cdpr_statics_result_t straight;
    int neg_cable = -1;
    const int have_straight =
        (ik_straight_load(r, pose, g, ld, &straight, &neg_cable) == CDPR_OK) ? 1 : 0;
    /* A sagging cable can pull its cabin end upward only if the exit point is above it
     * (V(s) grows along the cable): with every exit point at or below its attachment a load
     * that needs an upward pull (weight above any upward external force) cannot be carried. */
    if (any_exit_above(g, NC) == 0 && ld->f.z < CDPR_R(0.0)) {
        set_why(why, CDPR_STATICS_WHY_NO_LIFT, -1, (cdpr_real_t)NAN, (cdpr_real_t)NAN);
        return CDPR_E_INFEASIBLE;
    }
    /* When Newton fails, it is reported as infeasible if the massless model has no
     * all-pulling solution either (the two agree away from the boundary of the set). */
    const cdpr_status_t fail = (have_straight != 0) ? CDPR_E_NO_CONVERGENCE : CDPR_E_INFEASIBLE;
    if (have_straight == 0) {
        set_why(why, (neg_cable >= 0) ? CDPR_STATICS_WHY_PUSH : CDPR_STATICS_WHY_SPAN, neg_cable,
                (cdpr_real_t)NAN, CDPR_R(0.0));
    }
    cdpr_real_t t0[NC];
    for (int j = 0; (have_straight != 0) && (j < NC); ++j) {
        t0[j] = straight.cable[j].tension_winch_N;
    }
    ik_start(r, g, ld, (have_straight != 0) ? t0 : NULL, s);
    if (wrench(r, g, s->H, o, ld, s->V, s->L, s->rv, s->J, NULL, NULL) != CDPR_OK) {
        return fail;
    }
    s->rn = norm6(s->rv);
    return ik_newton(r, g, o, ld, tol, fail, s, iterations, why);
}

#if CDPR_STATICS_REDUNDANT
/* Massless start of the redundant problem: the tensions t along the straight chords closest
 * to t_ref within the bounds (or, when the bounds cannot be met there, closest to t_ref
 * without them), for the load plus the lower half of every cable's weight hanging at its
 * attachment (the classical first approximation of sag: it removes most of the start's
 * residual, 40 % of the weight for the 50 m cabin on eight cables without it). -1 when the
 * chords cannot span the wrench. */
static int start_massless(const cdpr_robot_t *r, const geom_t *g, const load_t *ld,
                          const cdpr_statics_dist_t *d, cdpr_real_t *t)
{
    const int m = r->p.n_cables;
    cdpr_real_t E[NC][MC];
    cdpr_real_t f[NC] = {-ld->f.x, -ld->f.y, -ld->f.z, -ld->m.x, -ld->m.y, -ld->m.z};
    cdpr_real_t lo_c[MC];
    cdpr_real_t lo_h[MC];
    cdpr_real_t hi_c[MC];
    cdpr_real_t hi_h[MC];
    for (int j = 0; j < m; ++j) {
        const cdpr_real_t chord = CDPR_SQRT(g[j].l * g[j].l + g[j].h * g[j].h);
        const cdpr_vec3_t u =
            cdpr_v3(g[j].l * g[j].e.x / chord, g[j].l * g[j].e.y / chord, g[j].h / chord);
        set_wrench_column(E, j, u, cdpr_v3_cross(g[j].arm, u));
        const cdpr_real_t half =
            CDPR_R(0.5) * r->p.cables[j].cable.rho_kg_per_m * r->p.g_m_per_s2 * chord;
        const cdpr_vec3_t mh = cdpr_v3_cross(g[j].arm, cdpr_v3(CDPR_R(0.0), CDPR_R(0.0), -half));
        f[2] += half;
        f[3] -= mh.x;
        f[4] -= mh.y;
        f[5] -= mh.z;
        lo_c[j] = CDPR_R(1.0);
        lo_h[j] = d->t_min_N - d->t_ref_N;
        hi_c[j] = CDPR_R(-1.0);
        hi_h[j] = d->t_ref_N - d->t_max_N;
    }
    /* t = t_ref + u: E u = f - E t_ref. */
    for (int i = 0; i < NC; ++i) {
        for (int j = 0; j < m; ++j) {
            f[i] -= E[i][j] * d->t_ref_N;
        }
    }
    cdpr_real_t u[MC];
    int blame = -1;
    cdpr_ldp_result_t rc = cdpr_ldp_qp(m, E, f, lo_c, lo_h, hi_c, hi_h, 1, u, NULL, &blame);
    if (rc == CDPR_LDP_INFEASIBLE || rc == CDPR_LDP_STALLED) {
        rc = cdpr_ldp_qp(m, E, f, lo_c, lo_h, hi_c, hi_h, 0, u, NULL, &blame);
    }
    if (rc != CDPR_LDP_OK) {
        return -1;
    }
    for (int j = 0; j < m; ++j) {
        t[j] = d->t_ref_N + u[j];
    }
    return 0;
}

/* Iterate of the redundant problem: the square problem's iterate, dV/dH, dL/dH, and the
 * multipliers of the equilibrium from the last step (for the Lagrangian's curvature). */
typedef struct {
    ik_iter_t k;
    cdpr_real_t dV[MC];
    cdpr_real_t dL[MC];
    cdpr_real_t mu[NC];
} sqp_iter_t;

static cdpr_status_t sqp_eval(const cdpr_robot_t *r, const geom_t *g, const cdpr_statics_opts_t *o,
                              const load_t *ld, sqp_iter_t *s)
{
    CDPR_TRY(wrench(r, g, s->k.H, o, ld, s->k.V, s->k.L, s->k.rv, s->k.J, s->dV, s->dL));
    s->k.rn = norm6(s->k.rv);
    return CDPR_OK;
}

/* Proximal weight of the step (dimensionless, against dt/dH ~ 1): keeps the step's QP
 * strictly convex where a tension barely moves with H; it vanishes at a fixed point
 * (d = 0), so the solution is the criterion's own. */
#define SQP_PROX CDPR_R(1e-6)

/* Relative step of the central differences for the second derivatives in H. */
#ifdef CDPR_REAL_IS_FLOAT
#define SQP_FD_REL CDPR_R(1e-2)
#else
#define SQP_FD_REL CDPR_R(1e-5)
#endif

/* d^2V/dH^2 and the derivative of the lowest tension's slope d^2t/dH^2 of cable j at the
 * iterate, by central differences of the inner solve's analytic first derivatives (0 where an
 * inner solve fails: the step then falls back to the Gauss-Newton curvature). */
static void cable_curvature(const cdpr_robot_t *r, const geom_t *g, const cdpr_statics_opts_t *o,
                            const sqp_iter_t *s, int j, cdpr_real_t *v2, cdpr_real_t *t2)
{
    const cdpr_catenary_cable_t c = cat_of(r, j);
    const cdpr_real_t h = SQP_FD_REL * s->k.H[j];
    cdpr_real_t dv[2];
    cdpr_real_t dtw[2];
    *v2 = CDPR_R(0.0);
    *t2 = CDPR_R(0.0);
    for (int k = 0; k < 2; ++k) {
        const cdpr_real_t Hk = s->k.H[j] + ((k == 0) ? h : -h);
        cdpr_real_t V = s->k.V[j];
        cdpr_real_t L = s->k.L[j];
        cdpr_real_t dl = CDPR_R(0.0);
        if (inner_robust(&c, &g[j], Hk, o, &V, &L, &dv[k], &dl) != CDPR_OK) {
            return;
        }
        dtw[k] = tension_range(Hk, V, c.w_N_per_m, L, dv[k], dl).dlo;
    }
    *v2 = (dv[0] - dv[1]) / (CDPR_R(2.0) * h);
    *t2 = (dtw[0] - dtw[1]) / (CDPR_R(2.0) * h);
}

/* What sqp_step solves: the criterion's step with the bounds as given, or with the bounds
 * relaxed to no worse than now where they are broken; or a restoring step (no criterion, no
 * bounds: the minimum-norm step back onto the equilibria). */
#define SQP_BOUNDED 1
#define SQP_RELAXED 2
#define SQP_RESTORE 3

/* One step d of the redundant problem at s: the QP of the linearised equilibrium J d = -rv,
 * the criterion linearised in the lowest tensions, the bounds linearised in the tension
 * ranges, as `mode` says. Returns a cdpr_ldp_qp code (blame: 2 j lower, 2 j + 1 upper
 * bound); *dt: the largest change of a lowest tension the step makes (linearised) [N]. */
static cdpr_ldp_result_t sqp_step(const cdpr_robot_t *r, const geom_t *g,
                                  const cdpr_statics_opts_t *o, const sqp_iter_t *s,
                                  const cdpr_statics_dist_t *d, int mode, cdpr_real_t *dH,
                                  cdpr_real_t *dt, cdpr_real_t *mu, int *blame)
{
    const int m = r->p.n_cables;
    cdpr_real_t E[NC][MC];
    cdpr_real_t f[NC];
    cdpr_real_t sc[MC];
    cdpr_real_t gs[MC];
    cdpr_real_t a[MC];
    cdpr_real_t lo_c[MC];
    cdpr_real_t lo_h[MC];
    cdpr_real_t hi_c[MC];
    cdpr_real_t hi_h[MC];
    for (int j = 0; j < m; ++j) {
        const tension_range_t t = cable_range(r, j, &s->k, s->dV, s->dL);
        /* The QP min 1/2 sum B_j d_j^2 + sum a_j e_j d_j (criterion 1/2 sum e_j^2, e_j the
         * lowest tension minus t_ref) is min 1/2 ||u||^2 with u = sc d + gs, sc = sqrt(B),
         * gs = a e / sc. B: the Lagrangian's curvature, diagonal because each cable's force
         * depends on its own H only: a^2 + e t'' - V'' (mu . dW/dV), with the multipliers of
         * the last step, kept above 1e-2 of its Gauss-Newton part a^2 + prox. Restoration
         * steps use the Gauss-Newton metric and no criterion. */
        a[j] = t.dlo;
        const cdpr_real_t gn = a[j] * a[j] + SQP_PROX;
        cdpr_real_t B = gn;
        if (mode != SQP_RESTORE) {
            cdpr_real_t v2 = CDPR_R(0.0);
            cdpr_real_t t2 = CDPR_R(0.0);
            cable_curvature(r, g, o, s, j, &v2, &t2);
            const cdpr_real_t lam = s->mu[2] + s->mu[3] * g[j].arm.y - s->mu[4] * g[j].arm.x;
            B = gn + (t.lo - d->t_ref_N) * t2 - v2 * lam;
            B = (B > CDPR_R(1e-2) * gn) ? B : CDPR_R(1e-2) * gn;
        }
        sc[j] = CDPR_SQRT(B);
        gs[j] = (mode == SQP_RESTORE) ? CDPR_R(0.0) : a[j] * (t.lo - d->t_ref_N) / sc[j];
        const cdpr_real_t t_min = (mode == SQP_RELAXED && t.lo < d->t_min_N) ? t.lo : d->t_min_N;
        const cdpr_real_t t_max = (mode == SQP_RELAXED && t.hi > d->t_max_N) ? t.hi : d->t_max_N;
        lo_c[j] = t.dlo / sc[j];
        lo_h[j] = t_min - t.lo + lo_c[j] * gs[j];
        hi_c[j] = -t.dhi / sc[j];
        hi_h[j] = t.hi - t_max + hi_c[j] * gs[j];
    }
    for (int i = 0; i < NC; ++i) {
        f[i] = -s->k.rv[i];
        for (int j = 0; j < m; ++j) {
            E[i][j] = s->k.J[i][j] / sc[j];
            f[i] += E[i][j] * gs[j];
        }
    }
    cdpr_real_t u[MC];
    const cdpr_ldp_result_t rc =
        cdpr_ldp_qp(m, E, f, lo_c, lo_h, hi_c, hi_h,
                    (mode == SQP_BOUNDED || mode == SQP_RELAXED) ? 1 : 0, u, mu, blame);
    if (rc == CDPR_LDP_OK) {
        *dt = CDPR_R(0.0);
        for (int j = 0; j < m; ++j) {
            dH[j] = (u[j] - gs[j]) / sc[j];
            const cdpr_real_t c = CDPR_FABS(a[j] * dH[j]);
            *dt = (c > *dt) ? c : *dt;
        }
    }
    return rc;
}

/* Merit of an equilibrium of the redundant problem: the criterion sum e_j^2 plus an exact
 * (l1) penalty on the bound violations, rho sum |violation| with rho = 200 t_max_N, above
 * the criterion's sensitivity to a tension (2 |e| dt/dH, |e| <= t_max_N, dt/dH ~ 1): a step
 * that trades criterion for a smaller violation is progress. */
static cdpr_real_t sqp_merit(const cdpr_robot_t *r, const ik_iter_t *s,
                             const cdpr_statics_dist_t *d)
{
    cdpr_real_t phi = CDPR_R(0.0);
    for (int j = 0; j < r->p.n_cables; ++j) {
        const cdpr_real_t w = r->p.cables[j].cable.rho_kg_per_m * r->p.g_m_per_s2;
        const tension_range_t t =
            tension_range(s->H[j], s->V[j], w, s->L[j], CDPR_R(0.0), CDPR_R(0.0));
        const cdpr_real_t e = t.lo - d->t_ref_N;
        const cdpr_real_t vlo = (t.lo < d->t_min_N) ? d->t_min_N - t.lo : CDPR_R(0.0);
        const cdpr_real_t vhi = (t.hi > d->t_max_N) ? t.hi - d->t_max_N : CDPR_R(0.0);
        phi += e * e + CDPR_R(200.0) * d->t_max_N * (vlo + vhi);
    }
    return phi;
}

/* The iterate s moved by a dH into n and evaluated: 1 if every H stays positive and the inner
 * solves succeed, else 0. */
static int sqp_trial(const cdpr_robot_t *r, const geom_t *g, const cdpr_statics_opts_t *o,
                     const load_t *ld, const sqp_iter_t *s, const cdpr_real_t *dH, cdpr_real_t a,
                     sqp_iter_t *n)
{
    *n = *s;
    int positive = 1;
    for (int j = 0; j < r->p.n_cables; ++j) {
        n->k.H[j] = s->k.H[j] + a * dH[j];
        positive &= (n->k.H[j] > CDPR_R(0.0)) ? 1 : 0;
    }
    return (positive != 0 && sqp_eval(r, g, o, ld, n) == CDPR_OK) ? 1 : 0;
}

/* Optimality tolerance of the redundant problem [N]: tol plus 10 sqrt(eps) times the largest
 * |lowest tension - t_ref|. The step's optimality part is the criterion's gradient projected
 * on the equilibria's tangent, which the inner solves' span tolerance leaves known to ~1e-9 of
 * that gradient in double (measured floor of the step: 3e-9 of the largest |e|). */
static cdpr_real_t sqp_opt_tol(const cdpr_robot_t *r, const ik_iter_t *s,
                               const cdpr_statics_dist_t *d, cdpr_real_t tol)
{
    cdpr_real_t emax = CDPR_R(0.0);
    for (int j = 0; j < r->p.n_cables; ++j) {
        const cdpr_real_t w = r->p.cables[j].cable.rho_kg_per_m * r->p.g_m_per_s2;
        const cdpr_real_t e = CDPR_FABS(
            tension_range(s->H[j], s->V[j], w, s->L[j], CDPR_R(0.0), CDPR_R(0.0)).lo - d->t_ref_N);
        emax = (e > emax) ? e : emax;
    }
    return tol + CDPR_R(10.0) * CDPR_SQRT(CDPR_EPS) * emax;
}

/* Newton back onto the equilibria from s (evaluated): minimum-norm steps of the linearised
 * equilibrium (in the metric of the criterion), halved until the residual decreases, at
 * most 8, down to 1e-3 tol or as far as the residual decreases (its rounding floor, so that
 * the next step is the criterion's alone); 0 if then s->k.rn <= tol, else -1. */
static int sqp_restore(const cdpr_robot_t *r, const geom_t *g, const cdpr_statics_opts_t *o,
                       const load_t *ld, const cdpr_statics_dist_t *d, cdpr_real_t tol,
                       sqp_iter_t *s)
{
    for (int k = 0; k < 8; ++k) {
        if (s->k.rn <= CDPR_R(1e-3) * tol) {
            return 0;
        }
        cdpr_real_t dH[MC];
        cdpr_real_t dt = CDPR_R(0.0);
        int blame = -1;
        cdpr_real_t mu[NC];
        if (sqp_step(r, g, o, s, d, SQP_RESTORE, dH, &dt, mu, &blame) != CDPR_LDP_OK) {
            return -1;
        }
        cdpr_real_t a = CDPR_R(1.0);
        int moved = 0;
        for (int h = 0; (h < 40) && (moved == 0); ++h) {
            sqp_iter_t n;
            if (sqp_trial(r, g, o, ld, s, dH, a, &n) != 0 && n.k.rn < s->k.rn) {
                *s = n;
                moved = 1;
            }
            a *= CDPR_R(0.5);
        }
        if (moved == 0) {
            break;
        }
    }
    return (s->k.rn <= tol) ? 0 : -1;
}

/* Backtracking along dH for the redundant problem: the first step (halving, at most 40
 * times) that keeps every H positive, returns to the equilibria (sqp_restore) and does not
 * raise the merit by more than 1e-9 of it plus its rounding (1e3 eps of it). The 1e-9 is the
 * merit's noise near the optimum (the restoration leaves H known to the residual's rounding,
 * which moves the criterion by ~1e-12 of it; measured), where a step that lowers the
 * criterion by less cannot be told from one that does not. 1 with s moved, else 0. */
static int sqp_line_search(const cdpr_robot_t *r, const geom_t *g, const cdpr_statics_opts_t *o,
                           const load_t *ld, const cdpr_statics_dist_t *d, cdpr_real_t tol,
                           const cdpr_real_t *dH, sqp_iter_t *s)
{
    const cdpr_real_t phi = sqp_merit(r, &s->k, d);
    cdpr_real_t a = CDPR_R(1.0);
    for (int k = 0; k < 40; ++k) {
        sqp_iter_t n;
        if (sqp_trial(r, g, o, ld, s, dH, a, &n) != 0 &&
            sqp_restore(r, g, o, ld, d, tol, &n) == 0 &&
            sqp_merit(r, &n.k, d) <= phi * (CDPR_R(1.0) + CDPR_R(1e-9) + CDPR_R(1e3) * CDPR_EPS)) {
            *s = n;
            return 1;
        }
        a *= CDPR_R(0.5);
    }
    return 0;
}

/* More than six cables: sequential quadratic programming on the m horizontal tensions, on the
 * equilibria (each step is followed by Newton back onto them), from the massless distribution.
 * Converged when the bounded step changes no lowest tension by more than sqp_opt_tol. Where the
 * bounds are broken and the bounded step does not exist, relaxed steps reduce the violation;
 * when no relaxed step moves any more, the bounds cannot be met (the bounded problem's
 * certificate names the cable). */
static cdpr_status_t ik_redundant(const cdpr_robot_t *r, const geom_t *g, const load_t *ld,
                                  const cdpr_statics_dist_t *d, const cdpr_statics_opts_t *o,
                                  cdpr_real_t tol, sqp_iter_t *s, int *iterations,
                                  cdpr_statics_verdict_t *why)
{
    const int m = r->p.n_cables;
    cdpr_real_t t0[MC];
    if (start_massless(r, g, ld, d, t0) != 0) {
        set_why(why, CDPR_STATICS_WHY_SPAN, -1, (cdpr_real_t)NAN, (cdpr_real_t)NAN);
        return CDPR_E_INFEASIBLE;
    }
    ik_start(r, g, ld, t0, &s->k);
    for (int i = 0; i < NC; ++i) {
        s->mu[i] = CDPR_R(0.0);
    }
    if (sqp_eval(r, g, o, ld, s) != CDPR_OK || sqp_restore(r, g, o, ld, d, tol, s) != 0) {
        return CDPR_E_NO_CONVERGENCE;
    }
    for (int it = 0; it <= o->max_iter; ++it) {
        cdpr_real_t dH[MC];
        cdpr_real_t dt = CDPR_R(0.0);
        int blame = -1;
        cdpr_real_t mu[NC];
        cdpr_ldp_result_t rc = sqp_step(r, g, o, s, d, SQP_BOUNDED, dH, &dt, mu, &blame);
        const int bounded_blame = blame;
        const int bounded = (rc == CDPR_LDP_INFEASIBLE) ? 0 : 1;
        if (bounded == 0) {
            rc = sqp_step(r, g, o, s, d, SQP_RELAXED, dH, &dt, mu, &blame);
            if (rc == CDPR_LDP_INFEASIBLE) {
                dt = CDPR_R(0.0); /* not even the bounds as they are: no move is left */
                rc = CDPR_LDP_OK;
            }
        }
        if (rc == CDPR_LDP_SINGULAR) {
            set_why(why, CDPR_STATICS_WHY_SPAN, -1, (cdpr_real_t)NAN, (cdpr_real_t)NAN);
            return CDPR_E_INFEASIBLE;
        }
        if (rc != CDPR_LDP_OK) {
            return CDPR_E_NO_CONVERGENCE;
        }
        const int stuck = (dt <= sqp_opt_tol(r, &s->k, d, tol)) ? 1 : 0;
        if (stuck != 0 && bounded != 0) {
            /* Converged. The last step, below the optimality tolerance, still puts an active
             * bound back on the bound to second order: take it if the merit allows. */
            (void)sqp_line_search(r, g, o, ld, d, tol, dH, s);
            *iterations = it;
            return CDPR_OK;
        }
        if (stuck == 0 && it >= o->max_iter) {
            return CDPR_E_NO_CONVERGENCE;
        }
        if (stuck != 0 || sqp_line_search(r, g, o, ld, d, tol, dH, s) == 0) {
            if (bounded == 0) {
                /* Relaxed steps cannot reduce the violation any more. */
                const int j = bounded_blame / 2;
                const int upper = bounded_blame % 2;
                const tension_range_t t = cable_range(r, j, &s->k, s->dV, s->dL);
                set_why(why, (upper != 0) ? CDPR_STATICS_WHY_T_MAX : CDPR_STATICS_WHY_T_MIN, j,
                        (upper != 0) ? t.hi : t.lo, (upper != 0) ? d->t_max_N : d->t_min_N);
                return CDPR_E_INFEASIBLE;
            }
            int lowest = 0;
            for (int j = 1; j < m; ++j) {
                lowest = (s->k.H[j] + dH[j] < s->k.H[lowest] + dH[lowest]) ? j : lowest;
            }
            if (!(s->k.H[lowest] + dH[lowest] > CDPR_R(0.0))) {
                set_why(why, CDPR_STATICS_WHY_PUSH, lowest, s->k.H[lowest], CDPR_R(0.0));
                return CDPR_E_INFEASIBLE;
            }
            return CDPR_E_NO_CONVERGENCE;
        }
        for (int i = 0; i < NC; ++i) {
            s->mu[i] = mu[i];
        }
    }
    return CDPR_E_NO_CONVERGENCE; /* not reached: the last iteration returns */
}
#endif

static cdpr_status_t check_dist(const cdpr_statics_dist_t *d)
{
    CDPR_TRY(check_nonnegative(d->t_min_N, "t_min_N", -1, NULL));
    CDPR_TRY(check_finite(d->t_max_N, "t_max_N", -1, NULL));
    CDPR_TRY(check_finite(d->t_ref_N, "t_ref_N", -1, NULL));
    if (!(d->t_max_N > d->t_min_N) || d->t_ref_N < d->t_min_N || d->t_ref_N > d->t_max_N) {
        return CDPR_E_OUT_OF_RANGE;
    }
    return CDPR_OK;
}

void cdpr_statics_dist_init(cdpr_statics_dist_t *d, cdpr_real_t t_min_N, cdpr_real_t t_max_N)
{
    d->t_min_N = t_min_N;
    d->t_max_N = t_max_N;
    d->t_ref_N = CDPR_R(0.5) * (t_min_N + t_max_N);
}

/* The checks, geometry, load and tolerance every IK entry point starts with (r, pose, res
 * and o checked by the caller for NULL; dist may be NULL). */
static cdpr_status_t ik_prepare(const cdpr_robot_t *r, const cdpr_cabin_motion_t *pose,
                                cdpr_vec3_t f_ext_N, cdpr_vec3_t tau_ext_Nm,
                                const cdpr_statics_dist_t *dist, const cdpr_statics_opts_t *o,
                                geom_t *g, load_t *ld, cdpr_real_t *tol)
{
    CDPR_TRY(check_opts(o));
    if (dist != NULL) {
        CDPR_TRY(check_dist(dist));
    }
    CDPR_TRY(check_pose(pose));
    if (cdpr_v3_isfinite(f_ext_N) == 0 || cdpr_v3_isfinite(tau_ext_Nm) == 0) {
        return CDPR_E_NOT_FINITE;
    }
    CDPR_TRY(geometry(r, pose, g));
    *ld = make_load(r, f_ext_N, tau_ext_Nm);
    /* Tolerance: absolute, plus rounding of the wrench sum relative to the load. */
    *tol = o->force_tol_N + CDPR_R(1e3) * CDPR_EPS * ld->scale;
    return CDPR_OK;
}

/* Six cables: Newton, then the loop check and the bounds (dist may be NULL); res written on
 * success. Kept apart from the redundant path so that a six-cable caller (the tracker's
 * feed-forward) links neither its code nor its stack. */
static cdpr_status_t ik_six(const cdpr_robot_t *r, const cdpr_cabin_motion_t *pose, const geom_t *g,
                            const load_t *ld, const cdpr_statics_dist_t *dist,
                            const cdpr_statics_opts_t *o, cdpr_real_t tol,
                            cdpr_statics_result_t *res, cdpr_statics_verdict_t *why)
{
    ik_iter_t s;
    int it = 0;
    cdpr_status_t st = ik_square(r, pose, g, ld, o, tol, &s, &it, why);
    if (st == CDPR_OK) {
        set_why(why, CDPR_STATICS_WHY_NONE, -1, (cdpr_real_t)NAN, (cdpr_real_t)NAN);
        st = check_loops(r, g, &s, why);
    }
    if (st == CDPR_OK && dist != NULL) {
        st = check_bounds(r, &s, dist, tol, why);
    }
    if (st == CDPR_OK) {
        ik_fill_result(r, pose, g, &s, it, res);
    }
    return st;
}

cdpr_status_t cdpr_statics_ik_dist(const cdpr_robot_t *r, const cdpr_cabin_motion_t *pose,
                                   cdpr_vec3_t f_ext_N, cdpr_vec3_t tau_ext_Nm,
                                   const cdpr_statics_dist_t *dist, const cdpr_statics_opts_t *o,
                                   cdpr_statics_result_t *res, cdpr_statics_verdict_t *why)
{
    set_why(why, CDPR_STATICS_WHY_NONE, -1, (cdpr_real_t)NAN, (cdpr_real_t)NAN);
    cdpr_statics_dist_t own;
    const cdpr_statics_dist_t *d = dist;
    if (d == NULL && r != NULL && r->p.has_tension_dist != 0) {
        own.t_min_N = r->p.tension_min_N; /* the robot's own (robot.h) */
        own.t_max_N = r->p.tension_max_N;
        own.t_ref_N = r->p.tension_ref_N;
        d = &own;
    }
    if (r == NULL || pose == NULL || res == NULL || r->p.n_cables < NC ||
        r->p.n_cables > CDPR_MAX_CABLES || (d == NULL && r->p.n_cables != NC)) {
        return CDPR_E_INVALID_ARG;
    }
    geom_t g[MC];
    load_t ld;
    cdpr_real_t tol = CDPR_R(0.0);
    CDPR_TRY(ik_prepare(r, pose, f_ext_N, tau_ext_Nm, d, o, g, &ld, &tol));
    if (r->p.n_cables == NC) {
        return ik_six(r, pose, g, &ld, d, o, tol, res, why);
    }
#if CDPR_STATICS_REDUNDANT
    sqp_iter_t s;
    int it = 0;
    cdpr_status_t st = ik_redundant(r, g, &ld, d, o, tol, &s, &it, why);
    if (st == CDPR_OK) {
        set_why(why, CDPR_STATICS_WHY_NONE, -1, (cdpr_real_t)NAN, (cdpr_real_t)NAN);
        st = check_loops(r, g, &s.k, why);
    }
    if (st == CDPR_OK) {
        st = check_bounds(r, &s.k, d, tol, why);
    }
    if (st == CDPR_OK) {
        ik_fill_result(r, pose, g, &s.k, it, res);
    }
    return st;
#else
    return CDPR_E_INVALID_ARG; /* not reached: n_cables <= CDPR_MAX_CABLES = 6 */
#endif
}

cdpr_status_t cdpr_statics_ik_wrench(const cdpr_robot_t *r, const cdpr_cabin_motion_t *pose,
                                     cdpr_vec3_t f_ext_N, cdpr_vec3_t tau_ext_Nm,
                                     const cdpr_statics_opts_t *o, cdpr_statics_result_t *res)
{
    if (r == NULL || pose == NULL || res == NULL || r->p.n_cables != NC) {
        return CDPR_E_INVALID_ARG;
    }
    geom_t g[MC];
    load_t ld;
    cdpr_real_t tol = CDPR_R(0.0);
    CDPR_TRY(ik_prepare(r, pose, f_ext_N, tau_ext_Nm, NULL, o, g, &ld, &tol));
    return ik_six(r, pose, g, &ld, NULL, o, tol, res, NULL);
}
/* Pose displaced from `base` by dx (position) and a rotation vector dth (world frame). */
static void displace(const cdpr_cabin_motion_t *base, const cdpr_real_t d[NC],
                     cdpr_cabin_motion_t *out)
{
    *out = *base;
    out->p_m = cdpr_v3(base->p_m.x + d[0], base->p_m.y + d[1], base->p_m.z + d[2]);
    const cdpr_real_t ang = CDPR_SQRT(d[3] * d[3] + d[4] * d[4] + d[5] * d[5]);
    cdpr_quat_t dq;
    dq.w = CDPR_COS(CDPR_R(0.5) * ang);
    const cdpr_real_t s = (ang > CDPR_R(0.0)) ? CDPR_SIN(CDPR_R(0.5) * ang) / ang : CDPR_R(0.5);
    dq.x = s * d[3];
    dq.y = s * d[4];
    dq.z = s * d[5];
    out->q = cdpr_quat_normalize(cdpr_quat_mul(dq, base->q));
}

/* Wrench residual at a pose for fixed unstretched lengths; fills (H, V) per cable. */
static cdpr_status_t wrench_at_lengths(const cdpr_robot_t *r, const cdpr_real_t *Ls,
                                       const cdpr_cabin_motion_t *pose,
                                       const cdpr_statics_opts_t *o, cdpr_real_t res[NC],
                                       cdpr_real_t H[MC], cdpr_real_t V[MC])
{
    geom_t g[MC];
    CDPR_TRY(geometry(r, pose, g));
    cdpr_vec3_t f = cdpr_v3(CDPR_R(0.0), CDPR_R(0.0), -r->p.cabin.mass_kg * r->p.g_m_per_s2);
    cdpr_vec3_t m = cdpr_v3(CDPR_R(0.0), CDPR_R(0.0), CDPR_R(0.0));
    for (int j = 0; j < r->p.n_cables; ++j) {
        const cdpr_catenary_cable_t c = cat_of(r, j);
        cdpr_catenary_solver_t s;
        cdpr_catenary_solver_default(&s);
        s.max_iter = o->max_iter;
        s.tol_m = o->span_tol_m;
        CDPR_TRY(cdpr_catenary_solve(&c, g[j].l, g[j].h, Ls[j], &s, &H[j], &V[j]));
        const cdpr_vec3_t F = cdpr_v3(H[j] * g[j].e.x, H[j] * g[j].e.y, V[j]);
        f = cdpr_v3_add(f, F);
        m = cdpr_v3_add(m, cdpr_v3_cross(g[j].arm, F));
    }
    cdpr_v3_store(f, res);
    cdpr_v3_store(m, &res[3]);
    return CDPR_OK;
}

/* Forward statics state: the pose iterate, its wrench residual and catenary forces. */
typedef struct {
    cdpr_cabin_motion_t pose;
    cdpr_real_t rv[NC];
    cdpr_real_t H[MC];
    cdpr_real_t V[MC];
    cdpr_real_t rn;
} fwd_iter_t;

/* Jacobian d(wrench)/d(pose) of the forward statics by central differences of size delta. */
static cdpr_status_t fwd_jacobian(const cdpr_robot_t *r, const cdpr_real_t *length_m,
                                  const cdpr_statics_opts_t *o, const cdpr_cabin_motion_t *pose,
                                  cdpr_real_t delta, cdpr_real_t J[NC][MC])
{
    for (int k = 0; k < NC; ++k) {
        cdpr_real_t d[NC] = {CDPR_R(0.0), CDPR_R(0.0), CDPR_R(0.0),
                             CDPR_R(0.0), CDPR_R(0.0), CDPR_R(0.0)};
        cdpr_real_t rp[NC];
        cdpr_real_t rm[NC];
        cdpr_real_t Ht[MC];
        cdpr_real_t Vt[MC];
        cdpr_cabin_motion_t pp;
        d[k] = delta;
        displace(pose, d, &pp);
        CDPR_TRY(wrench_at_lengths(r, length_m, &pp, o, rp, Ht, Vt));
        d[k] = -delta;
        displace(pose, d, &pp);
        CDPR_TRY(wrench_at_lengths(r, length_m, &pp, o, rm, Ht, Vt));
        for (int i = 0; i < NC; ++i) {
            J[i][k] = (rp[i] - rm[i]) / (CDPR_R(2.0) * delta);
        }
    }
    return CDPR_OK;
}

/* Backtracking along the Newton step dx (halving, at most 40 times): the first step that
 * lowers the residual norm is taken. Returns 1 when a step was taken, else 0. */
static int fwd_line_search(const cdpr_robot_t *r, const cdpr_real_t *length_m,
                           const cdpr_statics_opts_t *o, const cdpr_real_t dx[NC], fwd_iter_t *s)
{
    cdpr_real_t a = CDPR_R(1.0);
    for (int k = 0; k < 40; ++k) {
        cdpr_real_t ds[NC];
        for (int i = 0; i < NC; ++i) {
            ds[i] = a * dx[i];
        }
        cdpr_cabin_motion_t pn;
        displace(&s->pose, ds, &pn);
        cdpr_real_t rnew[NC];
        cdpr_real_t Hn[MC];
        cdpr_real_t Vn[MC];
        if (wrench_at_lengths(r, length_m, &pn, o, rnew, Hn, Vn) == CDPR_OK &&
            norm6(rnew) < s->rn) {
            s->pose = pn;
            for (int i = 0; i < NC; ++i) {
                s->rv[i] = rnew[i];
            }
            for (int i = 0; i < r->p.n_cables; ++i) {
                s->H[i] = Hn[i];
                s->V[i] = Vn[i];
            }
            s->rn = norm6(s->rv);
            return 1;
        }
        a *= CDPR_R(0.5);
    }
    return 0;
}

/* Newton iterations on the pose until the wrench residual is below tol; or, when Newton can
 * go no further (iteration bound, no descent), below tol + floor: the residual's rounding
 * floor at this problem's scale (cdpr_statics_forward). */
static cdpr_status_t fwd_newton(const cdpr_robot_t *r, const cdpr_real_t *length_m,
                                const cdpr_statics_opts_t *o, cdpr_real_t tol, cdpr_real_t floor,
                                cdpr_real_t delta, fwd_iter_t *s, int *iterations)
{
    int it = 0;
    int moving = 1;
    while (s->rn > tol && it < o->max_iter && moving != 0) {
        ++it;
        cdpr_real_t J[NC][MC];
        CDPR_TRY(fwd_jacobian(r, length_m, o, &s->pose, delta, J));
        cdpr_real_t b[NC];
        for (int i = 0; i < NC; ++i) {
            b[i] = -s->rv[i];
        }
        cdpr_real_t dx[NC];
        if (solve_linear(NC, J, b, dx, CDPR_R(0.0)) != 0) {
            return CDPR_E_INFEASIBLE; /* no static stiffness in some direction */
        }
        moving = fwd_line_search(r, length_m, o, dx, s);
    }
    if (!(s->rn <= tol + floor)) {
        return CDPR_E_NO_CONVERGENCE;
    }
    *iterations = it;
    return CDPR_OK;
}

cdpr_status_t cdpr_statics_forward(const cdpr_robot_t *r, const cdpr_real_t *length_m,
                                   const cdpr_cabin_motion_t *guess, const cdpr_statics_opts_t *o,
                                   cdpr_statics_result_t *res)
{
    if (r == NULL || length_m == NULL || guess == NULL || res == NULL || r->p.n_cables < NC ||
        r->p.n_cables > CDPR_MAX_CABLES) {
        return CDPR_E_INVALID_ARG;
    }
    CDPR_TRY(check_opts(o));
    CDPR_TRY(check_pose(guess));
    for (int j = 0; j < r->p.n_cables; ++j) {
        CDPR_TRY(check_positive(length_m[j], "length_m", j, NULL));
    }
    const cdpr_real_t weight = r->p.cabin.mass_kg * r->p.g_m_per_s2;
    const cdpr_real_t tol = o->force_tol_N + CDPR_R(1e3) * CDPR_EPS * weight;
    /* Rounding floor of the residual: each cable's span is known to a rounding of its
     * coordinates, ~eps (|P_j| + |A_j|), and its axial stiffness EA_j / L_j turns that into a
     * force. 8 times their sum (measured floors: up to 2.9 times it, FAST poses). */
    cdpr_real_t floor = CDPR_R(0.0);
    for (int j = 0; j < r->p.n_cables; ++j) {
        floor += r->p.cables[j].cable.ea_N / length_m[j] *
                 (cdpr_v3_norm(guess->p_m) + cdpr_v3_norm(r->p.cables[j].exit_point_m));
    }
    floor *= CDPR_R(8.0) * CDPR_EPS;
#ifdef CDPR_REAL_IS_FLOAT
    const cdpr_real_t delta = CDPR_R(1e-3);
#else
    const cdpr_real_t delta = CDPR_R(1e-6);
#endif
    fwd_iter_t s;
    s.pose = *guess;
    s.pose.q = cdpr_quat_normalize(guess->q);
    CDPR_TRY(wrench_at_lengths(r, length_m, &s.pose, o, s.rv, s.H, s.V));
    s.rn = norm6(s.rv);
    int it = 0;
    CDPR_TRY(fwd_newton(r, length_m, o, tol, floor, delta, &s, &it));
    geom_t g[MC];
    CDPR_TRY(geometry(r, &s.pose, g));
    res->n_cables = r->p.n_cables;
    for (int j = 0; j < r->p.n_cables; ++j) {
        fill_cable(r, j, &g[j], s.H[j], s.V[j], length_m[j], &res->cable[j]);
    }
    res->pose = s.pose;
    res->pose.v_m_per_s = cdpr_v3(CDPR_R(0.0), CDPR_R(0.0), CDPR_R(0.0));
    res->pose.w_rad_per_s = res->pose.v_m_per_s;
    res->iterations = it;
    res->residual = s.rn;
    return CDPR_OK;
}

cdpr_status_t cdpr_statics_place_catenary(const cdpr_robot_t *r, const cdpr_statics_result_t *res,
                                          cdpr_real_t *y)
{
    if (r == NULL || res == NULL || y == NULL || res->n_cables != r->p.n_cables) {
        return CDPR_E_INVALID_ARG;
    }
    CDPR_TRY(check_pose(&res->pose));
    geom_t g[MC];
    if (r->p.n_cables >= NC) {
        CDPR_TRY(geometry(r, &res->pose, g));
    } else {
        return CDPR_E_INVALID_ARG;
    }
    cdpr_cabin_set_motion(&res->pose, y);
    for (int j = 0; j < r->p.n_cables; ++j) {
        const cdpr_cable_t *c = &r->cable[j];
        const cdpr_catenary_cable_t cat = cat_of(r, j);
        const int nf = c->n - 1;
        cdpr_real_t *b = y + r->offset[j];
        b[0] = c->lu_m[nf];
        cdpr_real_t s = CDPR_R(0.0);
        for (int i = 1; i <= nf; ++i) {
            s += c->lu_m[i - 1];
            cdpr_real_t x;
            cdpr_real_t z;
            cdpr_catenary_point(&cat, res->cable[j].H_N, res->cable[j].v_cabin_N, s, &x, &z);
            b[1 + 3 * (i - 1) + 0] = g[j].P.x + x * g[j].e.x;
            b[1 + 3 * (i - 1) + 1] = g[j].P.y + x * g[j].e.y;
            b[1 + 3 * (i - 1) + 2] = g[j].P.z + z;
            b[1 + 3 * nf + 3 * (i - 1) + 0] = CDPR_R(0.0);
            b[1 + 3 * nf + 3 * (i - 1) + 1] = CDPR_R(0.0);
            b[1 + 3 * nf + 3 * (i - 1) + 2] = CDPR_R(0.0);
        }
    }
    return CDPR_OK;
}
