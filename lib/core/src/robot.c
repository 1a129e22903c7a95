/* SPDX-License-Identifier: BSD-3-Clause */
/// @file robot.c
/// Robot assembly: state layout, full RHS, outputs (docs/model.md "One cable", "Cabin", "Robot").
#include "cdpr/robot.h"

#include <math.h>
#include <stddef.h>

#include "check.h"

void cdpr_robot_params_default(cdpr_robot_params_t *p)
{
    p->n_cables = 1;
    for (int j = 0; j < CDPR_MAX_CABLES; ++j) {
        cdpr_robot_cable_params_t *c = &p->cables[j];
        cdpr_cable_params_default(&c->cable);
        c->exit_point_m = cdpr_v3(CDPR_R(0.0), CDPR_R(0.0), CDPR_R(0.0));
        c->attach_body_m = cdpr_v3(CDPR_R(0.0), CDPR_R(0.0), CDPR_R(0.0));
        c->n_segments = 20;
        c->length_m = CDPR_R(1.0);
    }
    cdpr_cabin_params_default(&p->cabin);
    p->g_m_per_s2 = CDPR_R(9.80665);
    p->mode = CDPR_CABIN_DYNAMIC;
    p->has_tension_dist = 0;
    p->tension_min_N = CDPR_R(0.0);
    p->tension_max_N = CDPR_R(0.0);
    p->tension_ref_N = CDPR_R(0.0);
}

/* The tension distribution's bounds and reference, when given. */
static cdpr_status_t check_tension_dist(const cdpr_robot_params_t *p, cdpr_diag_t *diag)
{
    if (p->has_tension_dist == 0) {
        return CDPR_OK;
    }
    CDPR_TRY(check_nonnegative(p->tension_min_N, "tension_min_N", -1, diag));
    CDPR_TRY(check_value(p->tension_max_N, (p->tension_max_N > p->tension_min_N) ? 0 : 1,
                         CDPR_E_OUT_OF_RANGE, "tension_max_N", -1, diag));
    return check_value(
        p->tension_ref_N,
        (p->tension_ref_N < p->tension_min_N || p->tension_ref_N > p->tension_max_N) ? 1 : 0,
        CDPR_E_OUT_OF_RANGE, "tension_ref_N", -1, diag);
}

/* Node-0 lumped masses rho lu_0 / 2 added to the cabin (docs/model.md "One cable"). */
static cdpr_status_t combine_cabin(cdpr_cabin_t *cab, const cdpr_robot_params_t *p,
                                   const cdpr_cable_t *cables, cdpr_diag_t *diag)
{
    cdpr_real_t m[CDPR_MAX_CABLES];
    cdpr_vec3_t b[CDPR_MAX_CABLES];
    for (int j = 0; j < p->n_cables; ++j) {
        m[j] = CDPR_R(0.5) * cables[j].p.rho_kg_per_m * cables[j].lu_m[0];
        b[j] = p->cables[j].attach_body_m;
    }
    return cdpr_cabin_init(cab, &p->cabin, p->n_cables, m, b, diag);
}

void cdpr_robot_update_layout(cdpr_robot_t *r)
{
    int off = CDPR_CABIN_STATE_DIM;
    for (int j = 0; j < r->p.n_cables; ++j) {
        r->offset[j] = off;
        off += cdpr_cable_state_dim(&r->cable[j]);
    }
    for (int j = r->p.n_cables; j < CDPR_MAX_CABLES; ++j) {
        r->offset[j] = off;
    }
    r->dim = off;
}

cdpr_status_t cdpr_robot_init(cdpr_robot_t *r, const cdpr_robot_params_t *p, cdpr_diag_t *diag)
{
    if (r == NULL || p == NULL) {
        return cdpr_diag_set(diag, CDPR_E_INVALID_ARG, (r == NULL) ? "robot" : "params", -1);
    }
    if (p->n_cables < 1 || p->n_cables > CDPR_MAX_CABLES) {
        return cdpr_diag_set(diag, CDPR_E_CAPACITY, "n_cables", p->n_cables);
    }
    CDPR_TRY(check_positive(p->g_m_per_s2, "g_m_per_s2", -1, diag));
    if (p->mode != CDPR_CABIN_DYNAMIC && p->mode != CDPR_CABIN_PRESCRIBED) {
        return cdpr_diag_set(diag, CDPR_E_OUT_OF_RANGE, "mode", (int)p->mode);
    }
    CDPR_TRY(check_tension_dist(p, diag));
    /* Validate into locals first so a failure leaves *r untouched. */
    cdpr_cable_t cables[CDPR_MAX_CABLES];
    for (int j = 0; j < p->n_cables; ++j) {
        const cdpr_robot_cable_params_t *c = &p->cables[j];
        CDPR_TRY(check_finite_v3(c->exit_point_m, "exit_point_m", j, diag));
        CDPR_TRY(check_finite_v3(c->attach_body_m, "attach_body_m", j, diag));
        cdpr_diag_t d;
        const cdpr_status_t st =
            cdpr_cable_init(&cables[j], &c->cable, c->n_segments, c->length_m, &d);
        if (st != CDPR_OK) {
            return cdpr_diag_set(diag, st, d.field, j); /* index names the cable */
        }
    }
    cdpr_cabin_t cab;
    CDPR_TRY(combine_cabin(&cab, p, cables, diag));

    r->p = *p;
    for (int j = 0; j < p->n_cables; ++j) {
        r->cable[j] = cables[j];
    }
    r->cabin = cab;
    for (int j = 0; j < CDPR_MAX_CABLES; ++j) {
        r->in.payout_m_per_s[j] = CDPR_R(0.0);
    }
    r->in.wind_m_per_s = cdpr_v3(CDPR_R(0.0), CDPR_R(0.0), CDPR_R(0.0));
    r->in.ext_force_world_N = cdpr_v3(CDPR_R(0.0), CDPR_R(0.0), CDPR_R(0.0));
    r->in.ext_torque_body_Nm = cdpr_v3(CDPR_R(0.0), CDPR_R(0.0), CDPR_R(0.0));
    r->in.motion_fn = NULL;
    r->in.motion_ctx = NULL;
    cdpr_robot_update_layout(r);
    return cdpr_diag_set(diag, CDPR_OK, "", -1);
}

int cdpr_robot_state_dim(const cdpr_robot_t *r)
{
    return r->dim;
}

/* Cabin motion seen by the cables at time t: the state (dynamic), or the prescription. */
static void cabin_motion(const cdpr_robot_t *r, cdpr_real_t t, const cdpr_real_t *y,
                         cdpr_cabin_motion_t *m)
{
    if (r->p.mode == CDPR_CABIN_PRESCRIBED) {
        if (r->in.motion_fn != NULL) {
            r->in.motion_fn(t, r->in.motion_ctx, m);
            m->q = cdpr_quat_normalize(m->q);
            return;
        }
        cdpr_cabin_get_motion(y, m);
        m->v_m_per_s = cdpr_v3(CDPR_R(0.0), CDPR_R(0.0), CDPR_R(0.0));
        m->w_rad_per_s = cdpr_v3(CDPR_R(0.0), CDPR_R(0.0), CDPR_R(0.0));
        return;
    }
    cdpr_cabin_get_motion(y, m);
}

void cdpr_robot_cabin_motion(const cdpr_robot_t *r, cdpr_real_t t_s, const cdpr_real_t *y,
                             cdpr_cabin_motion_t *m)
{
    cabin_motion(r, t_s, y, m);
}

cdpr_status_t cdpr_robot_refresh_cabin(cdpr_robot_t *r)
{
    return combine_cabin(&r->cabin, &r->p, r->cable, NULL);
}

/* Attachment position/velocity with a precomputed rotation. */
static void attach(const cdpr_robot_t *r, int j, const cdpr_cabin_motion_t *m, const cdpr_mat3_t *R,
                   cdpr_vec3_t *pos, cdpr_vec3_t *vel)
{
    const cdpr_vec3_t rb = cdpr_m3_mul_v3(R, r->p.cables[j].attach_body_m);
    const cdpr_vec3_t ww = cdpr_m3_mul_v3(R, m->w_rad_per_s);
    *pos = cdpr_v3_add(m->p_m, rb);
    *vel = cdpr_v3_add(m->v_m_per_s, cdpr_v3_cross(ww, rb));
}

void cdpr_robot_attachment(const cdpr_robot_t *r, int j, const cdpr_cabin_motion_t *m,
                           cdpr_vec3_t *pos_m, cdpr_vec3_t *vel_m_per_s)
{
    cdpr_mat3_t R;
    cdpr_quat_to_mat3(cdpr_quat_normalize(m->q), &R);
    attach(r, j, m, &R, pos_m, vel_m_per_s);
}

cdpr_status_t cdpr_robot_place_straight(const cdpr_robot_t *r, const cdpr_cabin_motion_t *m,
                                        cdpr_real_t *y)
{
    if (cdpr_v3_isfinite(m->p_m) == 0 || cdpr_v3_isfinite(m->v_m_per_s) == 0 ||
        cdpr_v3_isfinite(m->w_rad_per_s) == 0 || !isfinite(m->q.w) || !isfinite(m->q.x) ||
        !isfinite(m->q.y) || !isfinite(m->q.z)) {
        return CDPR_E_NOT_FINITE;
    }
    cdpr_mat3_t R;
    cdpr_quat_to_mat3(cdpr_quat_normalize(m->q), &R);
    for (int j = 0; j < r->p.n_cables; ++j) {
        cdpr_vec3_t a;
        cdpr_vec3_t v;
        attach(r, j, m, &R, &a, &v);
        if (!(cdpr_v3_norm(cdpr_v3_sub(r->p.cables[j].exit_point_m, a)) > CDPR_R(0.0))) {
            return CDPR_E_GEOMETRY;
        }
    }
    cdpr_cabin_motion_t mm = *m;
    mm.q = cdpr_quat_normalize(m->q);
    cdpr_cabin_set_motion(&mm, y);
    for (int j = 0; j < r->p.n_cables; ++j) {
        cdpr_vec3_t a;
        cdpr_vec3_t v;
        attach(r, j, &mm, &R, &a, &v);
        cdpr_cable_place_straight(&r->cable[j], a, r->p.cables[j].exit_point_m, y + r->offset[j]);
    }
    return CDPR_OK;
}

static void fill_bc(const cdpr_robot_t *r, int j, const cdpr_cabin_motion_t *m,
                    const cdpr_mat3_t *R, cdpr_cable_bc_t *bc)
{
    attach(r, j, m, R, &bc->r0_m, &bc->v0_m_per_s);
    bc->rn_m = r->p.cables[j].exit_point_m;
    bc->wind_m_per_s = r->in.wind_m_per_s;
    bc->payout_m_per_s = r->in.payout_m_per_s[j];
    bc->g_m_per_s2 = r->p.g_m_per_s2;
}

/* Moment of the world force F applied at body point b about the combined CoM, body axes:
 * (b - c) x (R^T F) (docs/model.md "Cabin"). */
static cdpr_vec3_t moment_body(const cdpr_robot_t *r, int j, const cdpr_mat3_t *R, cdpr_vec3_t F)
{
    const cdpr_vec3_t arm = cdpr_v3_sub(r->p.cables[j].attach_body_m, r->cabin.com_body_m);
    return cdpr_v3_cross(arm, cdpr_m3t_mul_v3(R, F));
}

cdpr_status_t cdpr_robot_rhs(cdpr_real_t t_s, const cdpr_real_t *y, cdpr_real_t *dydt, void *ctx)
{
    const cdpr_robot_t *r = (const cdpr_robot_t *)ctx;
    cdpr_cabin_motion_t m;
    cabin_motion(r, t_s, y, &m);
    cdpr_mat3_t R;
    cdpr_quat_to_mat3(cdpr_quat_normalize(m.q), &R);

    cdpr_vec3_t force = r->in.ext_force_world_N;
    cdpr_vec3_t torque = r->in.ext_torque_body_Nm;
    for (int j = 0; j < r->p.n_cables; ++j) {
        cdpr_cable_bc_t bc;
        cdpr_cable_out_t out;
        fill_bc(r, j, &m, &R, &bc);
        cdpr_cable_rhs(&r->cable[j], y + r->offset[j], &bc, dydt + r->offset[j], &out);
        force = cdpr_v3_add(force, out.force_on_cabin_N);
        torque = cdpr_v3_add(torque, moment_body(r, j, &R, out.force_on_cabin_N));
    }
    if (r->p.mode == CDPR_CABIN_DYNAMIC) {
        cdpr_cabin_rhs(&r->cabin, y, force, torque, r->p.g_m_per_s2, dydt);
    } else {
        /* Prescribed: the cabin block is not integrated; cdpr_robot_sync_prescribed writes it. */
        for (int i = 0; i < CDPR_CABIN_STATE_DIM; ++i) {
            dydt[i] = CDPR_R(0.0);
        }
    }
    return CDPR_OK;
}

void cdpr_robot_outputs(const cdpr_robot_t *r, cdpr_real_t t_s, const cdpr_real_t *y,
                        cdpr_robot_out_t *out)
{
    cdpr_cabin_motion_t m;
    cabin_motion(r, t_s, y, &m);
    cdpr_mat3_t R;
    cdpr_quat_to_mat3(cdpr_quat_normalize(m.q), &R);
    out->total_force_N = cdpr_v3(CDPR_R(0.0), CDPR_R(0.0), CDPR_R(0.0));
    out->total_torque_Nm = cdpr_v3(CDPR_R(0.0), CDPR_R(0.0), CDPR_R(0.0));
    for (int j = 0; j < r->p.n_cables; ++j) {
        cdpr_cable_bc_t bc;
        cdpr_cable_out_t co;
        fill_bc(r, j, &m, &R, &bc);
        cdpr_cable_end_forces(&r->cable[j], y + r->offset[j], &bc, &co);
        out->force_on_cabin_N[j] = co.force_on_cabin_N;
        out->tension_cabin_N[j] = co.tension_cabin_N;
        out->tension_winch_N[j] = co.tension_winch_N;
        out->total_force_N = cdpr_v3_add(out->total_force_N, co.force_on_cabin_N);
        out->total_torque_Nm =
            cdpr_v3_add(out->total_torque_Nm, moment_body(r, j, &R, co.force_on_cabin_N));
    }
    for (int j = r->p.n_cables; j < CDPR_MAX_CABLES; ++j) {
        out->force_on_cabin_N[j] = cdpr_v3(CDPR_R(0.0), CDPR_R(0.0), CDPR_R(0.0));
        out->tension_cabin_N[j] = CDPR_R(0.0);
        out->tension_winch_N[j] = CDPR_R(0.0);
    }
}

void cdpr_robot_sync_prescribed(const cdpr_robot_t *r, cdpr_real_t t_s, cdpr_real_t *y)
{
    if (r->p.mode != CDPR_CABIN_PRESCRIBED || r->in.motion_fn == NULL) {
        return;
    }
    cdpr_cabin_motion_t m;
    cabin_motion(r, t_s, y, &m);
    cdpr_cabin_set_motion(&m, y);
}

void cdpr_robot_normalize(const cdpr_robot_t *r, cdpr_real_t *y)
{
    (void)r;
    cdpr_quat_t q;
    q.w = y[CDPR_CABIN_Q];
    q.x = y[CDPR_CABIN_Q + 1];
    q.y = y[CDPR_CABIN_Q + 2];
    q.z = y[CDPR_CABIN_Q + 3];
    q = cdpr_quat_normalize(q);
    y[CDPR_CABIN_Q] = q.w;
    y[CDPR_CABIN_Q + 1] = q.x;
    y[CDPR_CABIN_Q + 2] = q.y;
    y[CDPR_CABIN_Q + 3] = q.z;
}

void cdpr_robot_fill_atol(const cdpr_robot_t *r, cdpr_real_t pos_m, cdpr_real_t vel_m_per_s,
                          cdpr_real_t quat, cdpr_real_t rate_rad_per_s, cdpr_real_t *atol)
{
    for (int i = 0; i < 3; ++i) {
        atol[CDPR_CABIN_P + i] = pos_m;
        atol[CDPR_CABIN_V + i] = vel_m_per_s;
        atol[CDPR_CABIN_W + i] = rate_rad_per_s;
    }
    for (int i = 0; i < 4; ++i) {
        atol[CDPR_CABIN_Q + i] = quat;
    }
    for (int j = 0; j < r->p.n_cables; ++j) {
        const int nf = r->cable[j].n - 1;
        cdpr_real_t *a = atol + r->offset[j];
        a[0] = pos_m;
        for (int i = 0; i < 3 * nf; ++i) {
            a[1 + i] = pos_m;
            a[1 + 3 * nf + i] = vel_m_per_s;
        }
    }
}
