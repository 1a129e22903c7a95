/* SPDX-License-Identifier: BSD-3-Clause */
/// @file cable.c
/// Lumped-mass cable: node forces and the right-hand side of one cable (docs/model.md "One cable").
#include "cdpr/cable.h"

#include <math.h>
#include <stddef.h>

#include "check.h"

void cdpr_cable_params_default(cdpr_cable_params_t *p)
{
    /* docs/robots.md set A: 6 mm steel wire rope of the 50 m model. */
    p->d0_m = CDPR_R(0.006);
    p->rho_kg_per_m = CDPR_R(0.14);
    p->ea_N = CDPR_R(2.0e6);
    p->damping_Ns = CDPR_R(170.0);
    p->cd = CDPR_R(1.2);
    p->cm = CDPR_R(0.03);
    p->rho_air_kg_per_m3 = CDPR_R(1.225);
    p->damping_ratio = CDPR_R(0.0);
    p->damping_ref_hz = CDPR_R(5.0);
    p->slack_law = CDPR_SLACK_PASSIVE;
}

cdpr_status_t cdpr_cable_params_validate(const cdpr_cable_params_t *p, cdpr_diag_t *diag)
{
    if (p == NULL) {
        return cdpr_diag_set(diag, CDPR_E_INVALID_ARG, "params", -1);
    }
    CDPR_TRY(check_positive(p->d0_m, "d0_m", -1, diag));
    CDPR_TRY(check_positive(p->rho_kg_per_m, "rho_kg_per_m", -1, diag));
    CDPR_TRY(check_positive(p->ea_N, "ea_N", -1, diag));
    CDPR_TRY(check_nonnegative(p->damping_Ns, "damping_Ns", -1, diag));
    CDPR_TRY(check_nonnegative(p->cd, "cd", -1, diag));
    CDPR_TRY(check_nonnegative(p->cm, "cm", -1, diag));
    CDPR_TRY(check_nonnegative(p->rho_air_kg_per_m3, "rho_air_kg_per_m3", -1, diag));
    CDPR_TRY(check_nonnegative(p->damping_ratio, "damping_ratio", -1, diag));
    if (p->damping_ratio > CDPR_R(1.0)) {
        return cdpr_diag_set(diag, CDPR_E_OUT_OF_RANGE, "damping_ratio", -1);
    }
    CDPR_TRY(check_positive(p->damping_ref_hz, "damping_ref_hz", -1, diag));
    if ((p->damping_ratio > CDPR_R(0.0)) && (p->damping_Ns > CDPR_R(0.0))) {
        /* Two damping values: which one is meant cannot be guessed. */
        return cdpr_diag_set(diag, CDPR_E_INVALID_ARG, "damping_ratio", -1);
    }
    if ((p->slack_law != CDPR_SLACK_PASSIVE) && (p->slack_law != CDPR_SLACK_MOORDYN)) {
        return cdpr_diag_set(diag, CDPR_E_INVALID_ARG, "slack_law", -1);
    }
    return cdpr_diag_set(diag, CDPR_OK, "", -1);
}

cdpr_real_t cdpr_cable_damping_from_ratio(cdpr_real_t ea_N, cdpr_real_t zeta, cdpr_real_t f_hz)
{
    return zeta * ea_N / ((cdpr_real_t)CDPR_PI * f_hz);
}

cdpr_status_t cdpr_cable_init(cdpr_cable_t *c, const cdpr_cable_params_t *p, int n_segments,
                              cdpr_real_t length_m, cdpr_diag_t *diag)
{
    if (c == NULL) {
        return cdpr_diag_set(diag, CDPR_E_INVALID_ARG, "cable", -1);
    }
    CDPR_TRY(cdpr_cable_params_validate(p, diag));
    if ((n_segments < 1) || (n_segments > CDPR_MAX_SEGMENTS)) {
        return cdpr_diag_set(diag, CDPR_E_CAPACITY, "n_segments", n_segments);
    }
    CDPR_TRY(check_positive(length_m, "length_m", -1, diag));

    c->p = *p;
    if (p->damping_ratio > CDPR_R(0.0)) {
        c->p.damping_Ns =
            cdpr_cable_damping_from_ratio(p->ea_N, p->damping_ratio, p->damping_ref_hz);
    }
    c->n = n_segments;
    c->delta_m = length_m / (cdpr_real_t)n_segments;
    for (int k = 0; k < CDPR_MAX_SEGMENTS; ++k) {
        c->lu_m[k] = (k < n_segments) ? c->delta_m : CDPR_R(0.0);
    }
    cdpr_cable_refresh(c);
    return cdpr_diag_set(diag, CDPR_OK, "", -1);
}

void cdpr_cable_refresh(cdpr_cable_t *c)
{
    const int n = c->n;
    for (int k = 0; k < CDPR_MAX_SEGMENTS; ++k) {
        c->inv_lu[k] = (k < n - 1) ? CDPR_R(1.0) / c->lu_m[k] : CDPR_R(0.0);
        c->inv_m[k] = CDPR_R(0.0);
    }
    /* docs/model.md "One cable", paper eq. (3.1): m_i = rho (lu_{i-1} + lu_i) / 2 for free nodes.
     * Node n-1 touches the pulley-side segment whose length is a state: computed in the RHS. */
    for (int i = 1; i < n - 1; ++i) {
        c->inv_m[i] = CDPR_R(2.0) / (c->p.rho_kg_per_m * (c->lu_m[i - 1] + c->lu_m[i]));
    }
    c->drag_k = CDPR_R(0.5) * c->p.rho_air_kg_per_m3 * c->p.d0_m * c->p.cd;
}

int cdpr_cable_state_dim(const cdpr_cable_t *c)
{
    return 1 + 6 * (c->n - 1);
}

cdpr_real_t cdpr_cable_total_length(const cdpr_cable_t *c, const cdpr_real_t *y)
{
    cdpr_real_t sum = CDPR_R(0.0);
    for (int k = 0; k < c->n - 1; ++k) {
        sum += c->lu_m[k];
    }
    return sum + y[0];
}

void cdpr_cable_place_straight(const cdpr_cable_t *c, cdpr_vec3_t r0_m, cdpr_vec3_t rn_m,
                               cdpr_real_t *y)
{
    const int n = c->n;
    const cdpr_real_t total = cdpr_cable_total_length(c, &c->lu_m[n - 1]);
    cdpr_real_t *pos = y + 1;
    cdpr_real_t *vel = y + 1 + 3 * (n - 1);
    cdpr_real_t s = CDPR_R(0.0);
    y[0] = c->lu_m[n - 1];
    for (int i = 1; i < n; ++i) {
        s += c->lu_m[i - 1];
        const cdpr_real_t f = s / total;
        pos[3 * (i - 1) + 0] = r0_m.x + f * (rn_m.x - r0_m.x);
        pos[3 * (i - 1) + 1] = r0_m.y + f * (rn_m.y - r0_m.y);
        pos[3 * (i - 1) + 2] = r0_m.z + f * (rn_m.z - r0_m.z);
        vel[3 * (i - 1) + 0] = CDPR_R(0.0);
        vel[3 * (i - 1) + 1] = CDPR_R(0.0);
        vel[3 * (i - 1) + 2] = CDPR_R(0.0);
    }
}

/* Result of one segment inside the RHS: elastic force vector S = T t, drag F, tension T. */
typedef struct {
    cdpr_real_t sx;
    cdpr_real_t sy;
    cdpr_real_t sz;
    cdpr_real_t fx;
    cdpr_real_t fy;
    cdpr_real_t fz;
    cdpr_real_t t;
} seg_t;

/* Constants of the segment model, hoisted out of the loop. */
typedef struct {
    cdpr_real_t ea;
    cdpr_real_t c;
    cdpr_real_t floor; /* lower bound of T: 0 (passive) or -inf (MoorDyn, may push) */
    cdpr_real_t drag_k;
    cdpr_real_t cm;
    cdpr_real_t wx;
    cdpr_real_t wy;
    cdpr_real_t wz;
} seg_k_t;

static void seg_constants(const cdpr_cable_params_t *p, cdpr_real_t drag_k, cdpr_vec3_t wind,
                          seg_k_t *k)
{
    k->ea = p->ea_N;
    k->c = p->damping_Ns;
    k->floor = (p->slack_law == CDPR_SLACK_MOORDYN) ? -(cdpr_real_t)INFINITY : CDPR_R(0.0);
    k->drag_k = drag_k;
    k->cm = p->cm;
    k->wx = wind.x;
    k->wy = wind.y;
    k->wz = wind.z;
}

/* Axial tension of a segment: T = max(floor, EA max(eps, 0) + c eps_dot), eps = ratio - 1
 * (docs/model.md "Slack, snap and damping"). */
static inline cdpr_real_t axial_tension(const seg_k_t *k, cdpr_real_t ratio, cdpr_real_t eps_dot)
{
    const cdpr_real_t eps = ratio - CDPR_R(1.0);
    const cdpr_real_t elastic = (eps > CDPR_R(0.0)) ? (k->ea * eps) : CDPR_R(0.0);
    const cdpr_real_t raw = elastic + (k->c * eps_dot);
    return (raw > k->floor) ? raw : k->floor;
}

/* docs/model.md "One cable" for one segment from node a to node b. Written on scalars so the
 * compiler keeps everything in registers; this is the hot loop of the whole library. */
static inline void seg_eval(const seg_k_t *k, const cdpr_real_t *ra, const cdpr_real_t *va,
                            const cdpr_real_t *rb, const cdpr_real_t *vb, cdpr_real_t lu,
                            cdpr_real_t inv_lu, cdpr_real_t lu_rate, seg_t *s)
{
    const cdpr_real_t dx = rb[0] - ra[0];
    const cdpr_real_t dy = rb[1] - ra[1];
    const cdpr_real_t dz = rb[2] - ra[2];
    const cdpr_real_t l = CDPR_SQRT(dx * dx + dy * dy + dz * dz);
    /* Coincident nodes have no direction: no elastic force, no tangential split. */
    const cdpr_real_t inv_l = (l > CDPR_R(0.0)) ? CDPR_R(1.0) / l : CDPR_R(0.0);
    const cdpr_real_t tx = dx * inv_l;
    const cdpr_real_t ty = dy * inv_l;
    const cdpr_real_t tz = dz * inv_l;
    const cdpr_real_t ratio = l * inv_lu; /* l / lu = 1 + strain */
    const cdpr_real_t mvx = CDPR_R(0.5) * (va[0] + vb[0]);
    const cdpr_real_t mvy = CDPR_R(0.5) * (va[1] + vb[1]);
    const cdpr_real_t mvz = CDPR_R(0.5) * (va[2] + vb[2]);

    /* Tension (axial_tension) with eps_dot = t.(v_b - v_a)/lu - (l/lu^2) d lu/dt. */
    const cdpr_real_t rel = tx * (vb[0] - va[0]) + ty * (vb[1] - va[1]) + tz * (vb[2] - va[2]);
    const cdpr_real_t eps_dot = (rel - ratio * lu_rate) * inv_lu;
    const cdpr_real_t tension = axial_tension(k, ratio, eps_dot);
    s->t = tension;
    s->sx = tension * tx;
    s->sy = tension * ty;
    s->sz = tension * tz;

    /* Drag: F = -1/2 rho_a d0 sqrt(l/lu) lu (Cd |mu_n| mu_n + Cm Cd |mu_t| mu_t), with
     * mu = mean segment velocity - wind; drag_k = 1/2 rho_a d0 Cd and sqrt(l/lu) lu = sqrt(l lu).
     */
    if (k->drag_k > CDPR_R(0.0)) {
        const cdpr_real_t mux = mvx - k->wx;
        const cdpr_real_t muy = mvy - k->wy;
        const cdpr_real_t muz = mvz - k->wz;
        const cdpr_real_t mt = mux * tx + muy * ty + muz * tz;
        const cdpr_real_t nx = mux - mt * tx;
        const cdpr_real_t ny = muy - mt * ty;
        const cdpr_real_t nz = muz - mt * tz;
        const cdpr_real_t mn = CDPR_SQRT(nx * nx + ny * ny + nz * nz);
        const cdpr_real_t area = k->drag_k * CDPR_SQRT(l * lu);
        const cdpr_real_t ct = k->cm * CDPR_FABS(mt) * mt;
        s->fx = -area * (mn * nx + ct * tx);
        s->fy = -area * (mn * ny + ct * ty);
        s->fz = -area * (mn * nz + ct * tz);
    } else {
        s->fx = CDPR_R(0.0);
        s->fy = CDPR_R(0.0);
        s->fz = CDPR_R(0.0);
    }
}

void cdpr_cable_segment_eval(const cdpr_cable_params_t *p, cdpr_vec3_t ra, cdpr_vec3_t va,
                             cdpr_vec3_t rb, cdpr_vec3_t vb, cdpr_real_t lu_m,
                             cdpr_real_t lu_rate_m_per_s, cdpr_vec3_t wind_m_per_s,
                             cdpr_segment_t *out)
{
    seg_k_t k;
    seg_constants(p, CDPR_R(0.5) * p->rho_air_kg_per_m3 * p->d0_m * p->cd, wind_m_per_s, &k);
    const cdpr_real_t a_r[3] = {ra.x, ra.y, ra.z};
    const cdpr_real_t a_v[3] = {va.x, va.y, va.z};
    const cdpr_real_t b_r[3] = {rb.x, rb.y, rb.z};
    const cdpr_real_t b_v[3] = {vb.x, vb.y, vb.z};
    seg_t s;
    seg_eval(&k, a_r, a_v, b_r, b_v, lu_m, CDPR_R(1.0) / lu_m, lu_rate_m_per_s, &s);
    const cdpr_vec3_t d = cdpr_v3_sub(rb, ra);
    out->length_m = cdpr_v3_norm(d);
    out->strain = out->length_m / lu_m - CDPR_R(1.0);
    out->tension_N = s.t;
    out->tangent = (s.t > CDPR_R(0.0)) ? cdpr_v3_scale(cdpr_v3(s.sx, s.sy, s.sz), CDPR_R(1.0) / s.t)
                   : (out->length_m > CDPR_R(0.0)) ? cdpr_v3_scale(d, CDPR_R(1.0) / out->length_m)
                                                   : cdpr_v3(CDPR_R(0.0), CDPR_R(0.0), CDPR_R(0.0));
    out->drag_N = cdpr_v3(s.fx, s.fy, s.fz);
}

/* Structure-of-arrays scratch for one RHS call (on the stack: 13 arrays of
 * CDPR_MAX_SEGMENTS + 1 reals, 6.8 KB for 64 segments in double). */
typedef struct {
    cdpr_real_t x[CDPR_MAX_SEGMENTS + 1];
    cdpr_real_t y[CDPR_MAX_SEGMENTS + 1];
    cdpr_real_t z[CDPR_MAX_SEGMENTS + 1];
    cdpr_real_t vx[CDPR_MAX_SEGMENTS + 1];
    cdpr_real_t vy[CDPR_MAX_SEGMENTS + 1];
    cdpr_real_t vz[CDPR_MAX_SEGMENTS + 1];
    cdpr_real_t sx[CDPR_MAX_SEGMENTS];
    cdpr_real_t sy[CDPR_MAX_SEGMENTS];
    cdpr_real_t sz[CDPR_MAX_SEGMENTS];
    cdpr_real_t fx[CDPR_MAX_SEGMENTS];
    cdpr_real_t fy[CDPR_MAX_SEGMENTS];
    cdpr_real_t fz[CDPR_MAX_SEGMENTS];
    cdpr_real_t t[CDPR_MAX_SEGMENTS];
} soa_t;

/* Pass 1 over the fixed-length segments k = 0..m-1 (d lu/dt = 0): the same arithmetic as
 * seg_eval, in the same order (so results are bit-identical), written branch-free on separate
 * coordinate arrays so the compiler can vectorise it (docs/performance.md). */
static void segments_soa(const seg_k_t *k, const cdpr_real_t *lu, const cdpr_real_t *inv_lu, int m,
                         soa_t *w)
{
    for (int s = 0; s < m; ++s) {
        const cdpr_real_t dx = w->x[s + 1] - w->x[s];
        const cdpr_real_t dy = w->y[s + 1] - w->y[s];
        const cdpr_real_t dz = w->z[s + 1] - w->z[s];
        const cdpr_real_t l = CDPR_SQRT(dx * dx + dy * dy + dz * dz);
        const cdpr_real_t inv_l = (l > CDPR_R(0.0)) ? CDPR_R(1.0) / l : CDPR_R(0.0);
        const cdpr_real_t tx = dx * inv_l;
        const cdpr_real_t ty = dy * inv_l;
        const cdpr_real_t tz = dz * inv_l;
        const cdpr_real_t ratio = l * inv_lu[s];
        const cdpr_real_t mvx = CDPR_R(0.5) * (w->vx[s] + w->vx[s + 1]);
        const cdpr_real_t mvy = CDPR_R(0.5) * (w->vy[s] + w->vy[s + 1]);
        const cdpr_real_t mvz = CDPR_R(0.5) * (w->vz[s] + w->vz[s + 1]);
        const cdpr_real_t rel = tx * (w->vx[s + 1] - w->vx[s]) + ty * (w->vy[s + 1] - w->vy[s]) +
                                tz * (w->vz[s + 1] - w->vz[s]);
        const cdpr_real_t eps_dot = rel * inv_lu[s];
        const cdpr_real_t tension = axial_tension(k, ratio, eps_dot);
        w->t[s] = tension;
        w->sx[s] = tension * tx;
        w->sy[s] = tension * ty;
        w->sz[s] = tension * tz;
        const cdpr_real_t mux = mvx - k->wx;
        const cdpr_real_t muy = mvy - k->wy;
        const cdpr_real_t muz = mvz - k->wz;
        const cdpr_real_t mt = mux * tx + muy * ty + muz * tz;
        const cdpr_real_t nx = mux - mt * tx;
        const cdpr_real_t ny = muy - mt * ty;
        const cdpr_real_t nz = muz - mt * tz;
        const cdpr_real_t mn = CDPR_SQRT(nx * nx + ny * ny + nz * nz);
        const cdpr_real_t area = k->drag_k * CDPR_SQRT(l * lu[s]);
        const cdpr_real_t ct = k->cm * CDPR_FABS(mt) * mt;
        w->fx[s] = -area * (mn * nx + ct * tx);
        w->fy[s] = -area * (mn * ny + ct * ty);
        w->fz[s] = -area * (mn * nz + ct * tz);
    }
}

void cdpr_cable_rhs(const cdpr_cable_t *c, const cdpr_real_t *y, const cdpr_cable_bc_t *bc,
                    cdpr_real_t *dydt, cdpr_cable_out_t *out)
{
    const int n = c->n;
    const int nf = n - 1; /* free nodes */
    const cdpr_real_t lu_last = y[0];
    const cdpr_real_t u = bc->payout_m_per_s;
    const cdpr_real_t g = bc->g_m_per_s2;
    const cdpr_real_t *pos = y + 1;
    const cdpr_real_t *vel = y + 1 + 3 * nf;
    cdpr_real_t *dpos = dydt + 1;
    cdpr_real_t *dvel = dydt + 1 + 3 * nf;
    seg_k_t k;
    seg_constants(&c->p, c->drag_k, bc->wind_m_per_s, &k);

    dydt[0] = u; /* payout: d lu[n-1]/dt = u */
    for (int i = 0; i < 3 * nf; ++i) {
        dpos[i] = vel[i];
    }

    /* Nodes 0..n in coordinate arrays: cabin attachment, free nodes, fixed exit point. */
    soa_t w;
    w.x[0] = bc->r0_m.x;
    w.y[0] = bc->r0_m.y;
    w.z[0] = bc->r0_m.z;
    w.vx[0] = bc->v0_m_per_s.x;
    w.vy[0] = bc->v0_m_per_s.y;
    w.vz[0] = bc->v0_m_per_s.z;
    for (int i = 1; i <= nf; ++i) {
        const int a = 3 * (i - 1);
        w.x[i] = pos[a];
        w.y[i] = pos[a + 1];
        w.z[i] = pos[a + 2];
        w.vx[i] = vel[a];
        w.vy[i] = vel[a + 1];
        w.vz[i] = vel[a + 2];
    }
    w.x[n] = bc->rn_m.x;
    w.y[n] = bc->rn_m.y;
    w.z[n] = bc->rn_m.z;
    w.vx[n] = CDPR_R(0.0);
    w.vy[n] = CDPR_R(0.0);
    w.vz[n] = CDPR_R(0.0);

    /* Segments 0..n-2 (fixed lengths) vectorised; the pulley-side segment n-1, whose length
     * is the state y[0] and changes at rate u, with the scalar seg_eval. */
    segments_soa(&k, c->lu_m, c->inv_lu, nf, &w);
    {
        const cdpr_real_t ra[3] = {w.x[nf], w.y[nf], w.z[nf]};
        const cdpr_real_t va[3] = {w.vx[nf], w.vy[nf], w.vz[nf]};
        const cdpr_real_t rb[3] = {w.x[n], w.y[n], w.z[n]};
        const cdpr_real_t vb[3] = {CDPR_R(0.0), CDPR_R(0.0), CDPR_R(0.0)};
        seg_t last;
        seg_eval(&k, ra, va, rb, vb, lu_last, CDPR_R(1.0) / lu_last, u, &last);
        w.t[nf] = last.t;
        w.sx[nf] = last.sx;
        w.sy[nf] = last.sy;
        w.sz[nf] = last.sz;
        w.fx[nf] = last.fx;
        w.fy[nf] = last.fy;
        w.fz[nf] = last.fz;
    }

    /* Pass 2, paper eqs. (3.1)-(3.4): a_i = (S_i - S_{i-1} + (F_{i-1} + F_i)/2) / m_i - g z,
     * free nodes 1..n-2 with cached masses, node n-1 with the state-dependent one. */
    for (int i = 1; i < nf; ++i) {
        const cdpr_real_t im = c->inv_m[i];
        cdpr_real_t *acc = dvel + 3 * (i - 1);
        acc[0] = im * (w.sx[i] - w.sx[i - 1] + CDPR_R(0.5) * (w.fx[i - 1] + w.fx[i]));
        acc[1] = im * (w.sy[i] - w.sy[i - 1] + CDPR_R(0.5) * (w.fy[i - 1] + w.fy[i]));
        acc[2] = im * (w.sz[i] - w.sz[i - 1] + CDPR_R(0.5) * (w.fz[i - 1] + w.fz[i])) - g;
    }
    if (nf >= 1) {
        const cdpr_real_t im = CDPR_R(2.0) / (c->p.rho_kg_per_m * (c->lu_m[nf - 1] + lu_last));
        cdpr_real_t *acc = dvel + 3 * (nf - 1);
        acc[0] = im * (w.sx[nf] - w.sx[nf - 1] + CDPR_R(0.5) * (w.fx[nf - 1] + w.fx[nf]));
        acc[1] = im * (w.sy[nf] - w.sy[nf - 1] + CDPR_R(0.5) * (w.fy[nf - 1] + w.fy[nf]));
        acc[2] = im * (w.sz[nf] - w.sz[nf - 1] + CDPR_R(0.5) * (w.fz[nf - 1] + w.fz[nf])) - g;
    }
    if (out != NULL) {
        out->force_on_cabin_N =
            cdpr_v3(w.sx[0] + CDPR_R(0.5) * w.fx[0], w.sy[0] + CDPR_R(0.5) * w.fy[0],
                    w.sz[0] + CDPR_R(0.5) * w.fz[0]);
        out->tension_cabin_N = w.t[0];
        out->tension_winch_N = w.t[nf];
    }
}

void cdpr_cable_end_forces(const cdpr_cable_t *c, const cdpr_real_t *y, const cdpr_cable_bc_t *bc,
                           cdpr_cable_out_t *out)
{
    const int nf = c->n - 1;
    const cdpr_real_t lu_last = y[0];
    const cdpr_real_t *pos = y + 1;
    const cdpr_real_t *vel = y + 1 + 3 * nf;
    const cdpr_real_t r0[3] = {bc->r0_m.x, bc->r0_m.y, bc->r0_m.z};
    const cdpr_real_t v0[3] = {bc->v0_m_per_s.x, bc->v0_m_per_s.y, bc->v0_m_per_s.z};
    const cdpr_real_t rn[3] = {bc->rn_m.x, bc->rn_m.y, bc->rn_m.z};
    const cdpr_real_t vn[3] = {CDPR_R(0.0), CDPR_R(0.0), CDPR_R(0.0)};
    seg_k_t k;
    seg_constants(&c->p, c->drag_k, bc->wind_m_per_s, &k);
    seg_t first;
    seg_t last;
    if (nf == 0) {
        seg_eval(&k, r0, v0, rn, vn, lu_last, CDPR_R(1.0) / lu_last, bc->payout_m_per_s, &first);
        last = first;
    } else {
        seg_eval(&k, r0, v0, pos, vel, c->lu_m[0], c->inv_lu[0], CDPR_R(0.0), &first);
        const int a = 3 * (nf - 1);
        seg_eval(&k, pos + a, vel + a, rn, vn, lu_last, CDPR_R(1.0) / lu_last, bc->payout_m_per_s,
                 &last);
    }
    out->force_on_cabin_N =
        cdpr_v3(first.sx + CDPR_R(0.5) * first.fx, first.sy + CDPR_R(0.5) * first.fy,
                first.sz + CDPR_R(0.5) * first.fz);
    out->tension_cabin_N = first.t;
    out->tension_winch_N = last.t;
}
