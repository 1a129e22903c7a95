/* SPDX-License-Identifier: BSD-3-Clause */
/// @file statics.c
/// Sag-aware statics and inverse kinematics (docs/model.md "Sag-aware inverse kinematics, with an
/// external wrench"; see statics.h).
#include "cdpr/statics.h"

#include <math.h>
#include <stddef.h>

#include "cdpr/catenary.h"
#include "check.h"

#define NC 6 /* the wrench has 6 components; the inverse problem needs exactly 6 cables */

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
static int solve_linear(int n, cdpr_real_t A[NC][NC], cdpr_real_t b[NC], cdpr_real_t x[NC],
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
                           cdpr_real_t *dVdH)
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
                                  cdpr_real_t *dVdH)
{
    cdpr_real_t v = *V;
    cdpr_real_t len = *L;
    if (inner(c, g, H, o, &v, &len, dVdH) == CDPR_OK) {
        *V = v;
        *L = len;
        return CDPR_OK;
    }
    if (inextensible_guess(c, g, H, &v, &len) != 0) {
        return CDPR_E_NO_CONVERGENCE;
    }
    CDPR_TRY(inner(c, g, H, o, &v, &len, dVdH));
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
static void set_wrench_column(cdpr_real_t M[NC][NC], int j, cdpr_vec3_t f, cdpr_vec3_t m)
{
    M[0][j] = f.x;
    M[1][j] = f.y;
    M[2][j] = f.z;
    M[3][j] = m.x;
    M[4][j] = m.y;
    M[5][j] = m.z;
}

/* Wrench residual for given H (and its Jacobian if J != NULL): force sum_j F_j + ld->f and
 * moment sum_j arm_j x F_j + ld->m. Updates V, L (warm starts) and dV/dH per cable. */
static cdpr_status_t wrench(const cdpr_robot_t *r, const geom_t *g, const cdpr_real_t *H,
                            const cdpr_statics_opts_t *o, const load_t *ld, cdpr_real_t *V,
                            cdpr_real_t *L, cdpr_real_t res[NC], cdpr_real_t J[NC][NC])
{
    cdpr_vec3_t f = ld->f;
    cdpr_vec3_t m = ld->m;
    for (int j = 0; j < NC; ++j) {
        const cdpr_catenary_cable_t c = cat_of(r, j);
        cdpr_real_t dvdh = CDPR_R(0.0);
        CDPR_TRY(inner_robust(&c, &g[j], H[j], o, &V[j], &L[j], &dvdh));
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

/* Massless straight cables balancing the load `ld` (pose and geometry checked by the caller). */
static cdpr_status_t ik_straight_load(const cdpr_robot_t *r, const cdpr_cabin_motion_t *pose,
                                      const geom_t *g, const load_t *ld, cdpr_statics_result_t *res)
{
    cdpr_real_t A[NC][NC];
    cdpr_real_t b[NC] = {-ld->f.x, -ld->f.y, -ld->f.z, -ld->m.x, -ld->m.y, -ld->m.z};
    cdpr_real_t chord[NC];
    for (int j = 0; j < NC; ++j) {
        chord[j] = CDPR_SQRT(g[j].l * g[j].l + g[j].h * g[j].h);
        const cdpr_vec3_t u =
            cdpr_v3(g[j].l * g[j].e.x / chord[j], g[j].l * g[j].e.y / chord[j], g[j].h / chord[j]);
        set_wrench_column(A, j, u, cdpr_v3_cross(g[j].arm, u));
    }
    cdpr_real_t t[NC];
    if (solve_linear(NC, A, b, t, CDPR_R(0.0)) != 0) {
        return CDPR_E_INFEASIBLE; /* singular: the cables cannot span the wrench */
    }
    for (int j = 0; j < NC; ++j) {
        if (!(t[j] > CDPR_R(0.0))) {
            return CDPR_E_INFEASIBLE;
        }
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
    geom_t g[NC];
    CDPR_TRY(geometry(r, pose, g));
    const cdpr_vec3_t zero = cdpr_v3(CDPR_R(0.0), CDPR_R(0.0), CDPR_R(0.0));
    const load_t ld = make_load(r, zero, zero);
    return ik_straight_load(r, pose, g, &ld, res);
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
    cdpr_real_t A[NC][NC];
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

/* 1 if some exit point is above its attachment. */
static int any_exit_above(const geom_t g[NC])
{
    int any_above = 0;
    for (int j = 0; j < NC; ++j) {
        any_above |= (g[j].h > CDPR_R(0.0)) ? 1 : 0;
    }
    return any_above;
}

/* Unknowns of the outer Newton of the IK and what they give: H, V, L per cable, the wrench
 * residual rv, its Jacobian J (destroyed by each linear solve) and the norm rn of rv. */
typedef struct {
    cdpr_real_t H[NC];
    cdpr_real_t V[NC];
    cdpr_real_t L[NC];
    cdpr_real_t rv[NC];
    cdpr_real_t J[NC][NC];
    cdpr_real_t rn;
} ik_iter_t;

/* Starting point of the outer Newton from the massless tensions of `straight`, or, when it is
 * NULL, an even share of the load per cable. O(cables). */
static void ik_start(const cdpr_robot_t *r, const geom_t *g, const load_t *ld,
                     const cdpr_statics_result_t *straight, ik_iter_t *s)
{
    for (int j = 0; j < NC; ++j) {
        const cdpr_real_t chord = CDPR_SQRT(g[j].l * g[j].l + g[j].h * g[j].h);
        const cdpr_real_t t =
            (straight != NULL) ? straight->cable[j].tension_winch_N : ld->scale / (cdpr_real_t)NC;
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
 * the full step would make some H non-positive; -1 if J is singular (*wants_push untouched). */
static int ik_direction(ik_iter_t *s, cdpr_real_t dH[NC], int *wants_push)
{
    cdpr_real_t b[NC];
    for (int i = 0; i < NC; ++i) {
        b[i] = -s->rv[i];
    }
    const int singular = solve_linear(NC, s->J, b, dH, CDPR_R(0.0));
    if (singular == 0) {
        int push = 0;
        for (int j = 0; j < NC; ++j) {
            push |= (s->H[j] + dH[j] > CDPR_R(0.0)) ? 0 : 1;
        }
        *wants_push = push;
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
        if (positive != 0 && wrench(r, g, n.H, o, ld, n.V, n.L, n.rv, n.J) == CDPR_OK &&
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

/* Outer Newton from s (residual and Jacobian evaluated) until s->rn <= tol, at most
 * o->max_iter iterations (*iterations: the count used, on success). `fail` is the status of a
 * failure that is not attributed to a pushing cable. */
static cdpr_status_t ik_newton(const cdpr_robot_t *r, const geom_t *g, const cdpr_statics_opts_t *o,
                               const load_t *ld, cdpr_real_t tol, cdpr_status_t fail, ik_iter_t *s,
                               int *iterations)
{
    int it = 0;
    int wants_push = 0; /* the last full Newton step would have made some H non-positive */
    while (s->rn > tol) {
        if (it >= o->max_iter) {
            return (wants_push != 0) ? CDPR_E_INFEASIBLE : fail;
        }
        ++it;
        cdpr_real_t dH[NC];
        if (ik_direction(s, dH, &wants_push) != 0) {
            return CDPR_E_INFEASIBLE;
        }
        if (ik_line_search(r, g, o, ld, dH, s) == 0) {
            /* Stuck while the Newton step points through H = 0, or against it: the
             * equilibrium would need a pushing cable. */
            for (int j = 0; j < NC; ++j) {
                wants_push |= (s->H[j] < CDPR_R(1e-6) * ld->scale) ? 1 : 0;
            }
            return (wants_push != 0) ? CDPR_E_INFEASIBLE : fail;
        }
    }
    *iterations = it;
    return CDPR_OK;
}

/* Write the converged IK into res: the cables, the pose at rest, the iteration count. */
static void ik_fill_result(const cdpr_robot_t *r, const cdpr_cabin_motion_t *pose, const geom_t *g,
                           const ik_iter_t *s, int it, cdpr_statics_result_t *res)
{
    res->n_cables = NC;
    for (int j = 0; j < NC; ++j) {
        fill_cable(r, j, &g[j], s->H[j], s->V[j], s->L[j], &res->cable[j]);
    }
    res->pose = *pose;
    res->pose.v_m_per_s = cdpr_v3(CDPR_R(0.0), CDPR_R(0.0), CDPR_R(0.0));
    res->pose.w_rad_per_s = res->pose.v_m_per_s;
    res->iterations = it;
    res->residual = s->rn;
}

cdpr_status_t cdpr_statics_ik_wrench(const cdpr_robot_t *r, const cdpr_cabin_motion_t *pose,
                                     cdpr_vec3_t f_ext_N, cdpr_vec3_t tau_ext_Nm,
                                     const cdpr_statics_opts_t *o, cdpr_statics_result_t *res)
{
    if (r == NULL || pose == NULL || res == NULL || r->p.n_cables != NC) {
        return CDPR_E_INVALID_ARG;
    }
    CDPR_TRY(check_opts(o));
    CDPR_TRY(check_pose(pose));
    if (cdpr_v3_isfinite(f_ext_N) == 0 || cdpr_v3_isfinite(tau_ext_Nm) == 0) {
        return CDPR_E_NOT_FINITE;
    }
    geom_t g[NC];
    CDPR_TRY(geometry(r, pose, g));
    const load_t ld = make_load(r, f_ext_N, tau_ext_Nm);
    /* Tolerance: absolute, plus rounding of the wrench sum relative to the load. */
    const cdpr_real_t tol = o->force_tol_N + CDPR_R(1e3) * CDPR_EPS * ld.scale;

    /* Start from the massless solution where it exists, else an even share of the load. */
    cdpr_statics_result_t straight;
    const int have_straight = (ik_straight_load(r, pose, g, &ld, &straight) == CDPR_OK) ? 1 : 0;
    /* A sagging cable can pull its cabin end upward only if the exit point is above it
     * (V(s) grows along the cable): with every exit point at or below its attachment a load
     * that needs an upward pull (weight above any upward external force) cannot be carried. */
    if (any_exit_above(g) == 0 && ld.f.z < CDPR_R(0.0)) {
        return CDPR_E_INFEASIBLE;
    }
    /* When Newton fails, it is reported as infeasible if the massless model has no
     * all-pulling solution either (the two agree away from the boundary of the set). */
    const cdpr_status_t fail = (have_straight != 0) ? CDPR_E_NO_CONVERGENCE : CDPR_E_INFEASIBLE;
    ik_iter_t s;
    ik_start(r, g, &ld, (have_straight != 0) ? &straight : NULL, &s);
    if (wrench(r, g, s.H, o, &ld, s.V, s.L, s.rv, s.J) != CDPR_OK) {
        return fail;
    }
    s.rn = norm6(s.rv);
    int it = 0;
    const cdpr_status_t st = ik_newton(r, g, o, &ld, tol, fail, &s, &it);
    if (st == CDPR_OK) {
        ik_fill_result(r, pose, g, &s, it, res);
    }
    return st;
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
                                       cdpr_real_t H[NC], cdpr_real_t V[NC])
{
    geom_t g[NC];
    CDPR_TRY(geometry(r, pose, g));
    cdpr_vec3_t f = cdpr_v3(CDPR_R(0.0), CDPR_R(0.0), -r->p.cabin.mass_kg * r->p.g_m_per_s2);
    cdpr_vec3_t m = cdpr_v3(CDPR_R(0.0), CDPR_R(0.0), CDPR_R(0.0));
    for (int j = 0; j < NC; ++j) {
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
    cdpr_real_t H[NC];
    cdpr_real_t V[NC];
    cdpr_real_t rn;
} fwd_iter_t;

/* Jacobian d(wrench)/d(pose) of the forward statics by central differences of size delta. */
static cdpr_status_t fwd_jacobian(const cdpr_robot_t *r, const cdpr_real_t *length_m,
                                  const cdpr_statics_opts_t *o, const cdpr_cabin_motion_t *pose,
                                  cdpr_real_t delta, cdpr_real_t J[NC][NC])
{
    for (int k = 0; k < NC; ++k) {
        cdpr_real_t d[NC] = {CDPR_R(0.0), CDPR_R(0.0), CDPR_R(0.0),
                             CDPR_R(0.0), CDPR_R(0.0), CDPR_R(0.0)};
        cdpr_real_t rp[NC];
        cdpr_real_t rm[NC];
        cdpr_real_t Ht[NC];
        cdpr_real_t Vt[NC];
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
        cdpr_real_t Hn[NC];
        cdpr_real_t Vn[NC];
        if (wrench_at_lengths(r, length_m, &pn, o, rnew, Hn, Vn) == CDPR_OK &&
            norm6(rnew) < s->rn) {
            s->pose = pn;
            for (int i = 0; i < NC; ++i) {
                s->rv[i] = rnew[i];
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

/* Newton iterations on the pose until the wrench residual is below tol. */
static cdpr_status_t fwd_newton(const cdpr_robot_t *r, const cdpr_real_t *length_m,
                                const cdpr_statics_opts_t *o, cdpr_real_t tol, cdpr_real_t delta,
                                fwd_iter_t *s, int *iterations)
{
    int it = 0;
    while (s->rn > tol) {
        if (it >= o->max_iter) {
            return CDPR_E_NO_CONVERGENCE;
        }
        ++it;
        cdpr_real_t J[NC][NC];
        CDPR_TRY(fwd_jacobian(r, length_m, o, &s->pose, delta, J));
        cdpr_real_t b[NC];
        for (int i = 0; i < NC; ++i) {
            b[i] = -s->rv[i];
        }
        cdpr_real_t dx[NC];
        if (solve_linear(NC, J, b, dx, CDPR_R(0.0)) != 0) {
            return CDPR_E_INFEASIBLE; /* no static stiffness in some direction */
        }
        if (fwd_line_search(r, length_m, o, dx, s) == 0) {
            return CDPR_E_NO_CONVERGENCE;
        }
    }
    *iterations = it;
    return CDPR_OK;
}

cdpr_status_t cdpr_statics_forward(const cdpr_robot_t *r, const cdpr_real_t *length_m,
                                   const cdpr_cabin_motion_t *guess, const cdpr_statics_opts_t *o,
                                   cdpr_statics_result_t *res)
{
    if (r == NULL || length_m == NULL || guess == NULL || res == NULL || r->p.n_cables != NC) {
        return CDPR_E_INVALID_ARG;
    }
    CDPR_TRY(check_opts(o));
    CDPR_TRY(check_pose(guess));
    for (int j = 0; j < NC; ++j) {
        CDPR_TRY(check_positive(length_m[j], "length_m", j, NULL));
    }
    const cdpr_real_t weight = r->p.cabin.mass_kg * r->p.g_m_per_s2;
    const cdpr_real_t tol = o->force_tol_N + CDPR_R(1e3) * CDPR_EPS * weight;
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
    CDPR_TRY(fwd_newton(r, length_m, o, tol, delta, &s, &it));
    geom_t g[NC];
    CDPR_TRY(geometry(r, &s.pose, g));
    res->n_cables = NC;
    for (int j = 0; j < NC; ++j) {
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
    geom_t g[CDPR_MAX_CABLES];
    if (r->p.n_cables == NC) {
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
