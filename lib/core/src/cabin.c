/* SPDX-License-Identifier: BSD-3-Clause */
/// @file cabin.c
/// Rigid-body cabin (docs/model.md "Cabin").
#include "cdpr/cabin.h"

#include <math.h>
#include <stddef.h>

#include "check.h"

void cdpr_cabin_params_default(cdpr_cabin_params_t *p)
{
    p->mass_kg = CDPR_R(40.0);
    p->com_body_m = cdpr_v3(CDPR_R(0.0), CDPR_R(0.0), CDPR_R(0.0));
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            p->inertia_com_kg_m2.m[i][j] = CDPR_R(0.0);
        }
    }
    p->inertia_com_kg_m2.m[0][0] = CDPR_R(45.0);
    p->inertia_com_kg_m2.m[1][1] = CDPR_R(45.0);
    p->inertia_com_kg_m2.m[2][2] = CDPR_R(90.0);
}

cdpr_status_t cdpr_cabin_params_validate(const cdpr_cabin_params_t *p, cdpr_diag_t *diag)
{
    if (p == NULL) {
        return cdpr_diag_set(diag, CDPR_E_INVALID_ARG, "cabin", -1);
    }
    CDPR_TRY(check_positive(p->mass_kg, "cabin.mass_kg", -1, diag));
    CDPR_TRY(check_finite_v3(p->com_body_m, "cabin.com_body_m", -1, diag));
    const cdpr_real_t(*I)[3] = p->inertia_com_kg_m2.m;
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            CDPR_TRY(check_finite(I[i][j], "cabin.inertia_com_kg_m2", 3 * i + j, diag));
        }
    }
    /* Symmetric to rounding, then positive definite by Sylvester's criterion. */
    const cdpr_real_t scale = CDPR_FABS(I[0][0]) + CDPR_FABS(I[1][1]) + CDPR_FABS(I[2][2]);
    for (int i = 0; i < 3; ++i) {
        for (int j = i + 1; j < 3; ++j) {
            if (CDPR_FABS(I[i][j] - I[j][i]) > CDPR_R(1e-6) * scale) {
                return cdpr_diag_set(diag, CDPR_E_OUT_OF_RANGE, "cabin.inertia_com_kg_m2",
                                     3 * i + j);
            }
        }
    }
    const cdpr_real_t m1 = I[0][0];
    const cdpr_real_t m2 = I[0][0] * I[1][1] - I[0][1] * I[1][0];
    const cdpr_real_t m3 = I[0][0] * (I[1][1] * I[2][2] - I[1][2] * I[2][1]) -
                           I[0][1] * (I[1][0] * I[2][2] - I[1][2] * I[2][0]) +
                           I[0][2] * (I[1][0] * I[2][1] - I[1][1] * I[2][0]);
    if (!(m1 > CDPR_R(0.0)) || !(m2 > CDPR_R(0.0)) || !(m3 > CDPR_R(0.0))) {
        return cdpr_diag_set(diag, CDPR_E_NOT_POSITIVE, "cabin.inertia_com_kg_m2", -1);
    }
    return cdpr_diag_set(diag, CDPR_OK, "", -1);
}

/* Add m (r.r I - r r^T) (parallel-axis term of a point mass at r from the reference). */
static void add_point_inertia(cdpr_mat3_t *I, cdpr_real_t m, cdpr_vec3_t r)
{
    const cdpr_real_t rr = cdpr_v3_dot(r, r);
    const cdpr_real_t v[3] = {r.x, r.y, r.z};
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            const cdpr_real_t delta = (i == j) ? rr : CDPR_R(0.0);
            I->m[i][j] += m * (delta - v[i] * v[j]);
        }
    }
}

cdpr_status_t cdpr_cabin_init(cdpr_cabin_t *cab, const cdpr_cabin_params_t *p, int n_points,
                              const cdpr_real_t *m_kg, const cdpr_vec3_t *b_m, cdpr_diag_t *diag)
{
    if (cab == NULL || (n_points > 0 && (m_kg == NULL || b_m == NULL)) || n_points < 0) {
        return cdpr_diag_set(diag, CDPR_E_INVALID_ARG, "cabin", -1);
    }
    CDPR_TRY(cdpr_cabin_params_validate(p, diag));
    for (int i = 0; i < n_points; ++i) {
        CDPR_TRY(check_nonnegative(m_kg[i], "point_mass_kg", i, diag));
        CDPR_TRY(check_finite_v3(b_m[i], "point_body_m", i, diag));
    }
    /* Combined centre of mass. */
    cdpr_real_t mass = p->mass_kg;
    cdpr_vec3_t mc = cdpr_v3_scale(p->com_body_m, p->mass_kg);
    for (int i = 0; i < n_points; ++i) {
        mass += m_kg[i];
        mc = cdpr_v3_add(mc, cdpr_v3_scale(b_m[i], m_kg[i]));
    }
    const cdpr_vec3_t com = cdpr_v3_scale(mc, CDPR_R(1.0) / mass);
    /* Inertia about the combined CoM: the cabin's own, shifted, plus the point masses. */
    cdpr_mat3_t I = p->inertia_com_kg_m2;
    add_point_inertia(&I, p->mass_kg, cdpr_v3_sub(p->com_body_m, com));
    for (int i = 0; i < n_points; ++i) {
        add_point_inertia(&I, m_kg[i], cdpr_v3_sub(b_m[i], com));
    }
    cdpr_mat3_t inv;
    if (cdpr_m3_inverse(&I, CDPR_R(0.0), &inv) != 0) {
        return cdpr_diag_set(diag, CDPR_E_NOT_POSITIVE, "cabin.inertia_com_kg_m2", -1);
    }
    cab->p = *p;
    cab->mass_kg = mass;
    cab->com_body_m = com;
    cab->inertia_kg_m2 = I;
    cab->inv_inertia = inv;
    return cdpr_diag_set(diag, CDPR_OK, "", -1);
}

void cdpr_cabin_get_motion(const cdpr_real_t *y, cdpr_cabin_motion_t *m)
{
    m->p_m = cdpr_v3_load(&y[CDPR_CABIN_P]);
    m->q.w = y[CDPR_CABIN_Q];
    m->q.x = y[CDPR_CABIN_Q + 1];
    m->q.y = y[CDPR_CABIN_Q + 2];
    m->q.z = y[CDPR_CABIN_Q + 3];
    m->v_m_per_s = cdpr_v3_load(&y[CDPR_CABIN_V]);
    m->w_rad_per_s = cdpr_v3_load(&y[CDPR_CABIN_W]);
}

void cdpr_cabin_set_motion(const cdpr_cabin_motion_t *m, cdpr_real_t *y)
{
    cdpr_v3_store(m->p_m, &y[CDPR_CABIN_P]);
    y[CDPR_CABIN_Q] = m->q.w;
    y[CDPR_CABIN_Q + 1] = m->q.x;
    y[CDPR_CABIN_Q + 2] = m->q.y;
    y[CDPR_CABIN_Q + 3] = m->q.z;
    cdpr_v3_store(m->v_m_per_s, &y[CDPR_CABIN_V]);
    cdpr_v3_store(m->w_rad_per_s, &y[CDPR_CABIN_W]);
}

void cdpr_cabin_rhs(const cdpr_cabin_t *cab, const cdpr_real_t *y, cdpr_vec3_t force_world_N,
                    cdpr_vec3_t torque_body_Nm, cdpr_real_t g_m_per_s2, cdpr_real_t *dydt)
{
    cdpr_cabin_motion_t m;
    cdpr_cabin_get_motion(y, &m);
    cdpr_mat3_t R;
    /* The RHS sees trial states whose quaternion drifts off unit length between
     * renormalisations; using the normalised rotation keeps R orthogonal. */
    cdpr_quat_to_mat3(cdpr_quat_normalize(m.q), &R);
    const cdpr_vec3_t w = m.w_rad_per_s;

    /* Rotation about the combined CoM: I w_dot = tau - w x I w. */
    const cdpr_vec3_t Iw = cdpr_m3_mul_v3(&cab->inertia_kg_m2, w);
    const cdpr_vec3_t wdot =
        cdpr_m3_mul_v3(&cab->inv_inertia, cdpr_v3_sub(torque_body_Nm, cdpr_v3_cross(w, Iw)));

    /* Translation of the CoM, then of the body origin: v_dot = a_c - w_dot_w x r_c -
     * w_w x (w_w x r_c), with r_c = R c and w_dot_w = R w_dot. */
    cdpr_vec3_t a_c = cdpr_v3_scale(force_world_N, CDPR_R(1.0) / cab->mass_kg);
    a_c.z -= g_m_per_s2;
    const cdpr_vec3_t r_c = cdpr_m3_mul_v3(&R, cab->com_body_m);
    const cdpr_vec3_t w_w = cdpr_m3_mul_v3(&R, w);
    const cdpr_vec3_t wdot_w = cdpr_m3_mul_v3(&R, wdot);
    const cdpr_vec3_t vdot = cdpr_v3_sub(cdpr_v3_sub(a_c, cdpr_v3_cross(wdot_w, r_c)),
                                         cdpr_v3_cross(w_w, cdpr_v3_cross(w_w, r_c)));

    /* q_dot = 1/2 q (x) (0, w). */
    cdpr_quat_t wq;
    wq.w = CDPR_R(0.0);
    wq.x = w.x;
    wq.y = w.y;
    wq.z = w.z;
    const cdpr_quat_t qd = cdpr_quat_mul(m.q, wq);

    dydt[CDPR_CABIN_P] = m.v_m_per_s.x;
    dydt[CDPR_CABIN_P + 1] = m.v_m_per_s.y;
    dydt[CDPR_CABIN_P + 2] = m.v_m_per_s.z;
    dydt[CDPR_CABIN_Q] = CDPR_R(0.5) * qd.w;
    dydt[CDPR_CABIN_Q + 1] = CDPR_R(0.5) * qd.x;
    dydt[CDPR_CABIN_Q + 2] = CDPR_R(0.5) * qd.y;
    dydt[CDPR_CABIN_Q + 3] = CDPR_R(0.5) * qd.z;
    dydt[CDPR_CABIN_V] = vdot.x;
    dydt[CDPR_CABIN_V + 1] = vdot.y;
    dydt[CDPR_CABIN_V + 2] = vdot.z;
    dydt[CDPR_CABIN_W] = wdot.x;
    dydt[CDPR_CABIN_W + 1] = wdot.y;
    dydt[CDPR_CABIN_W + 2] = wdot.z;
}

cdpr_cabin_motion_t cdpr_cabin_motion_at_pose(const cdpr_real_t pose[6])
{
    cdpr_cabin_motion_t m;
    m.p_m = cdpr_v3(pose[0], pose[1], pose[2]);
    m.q = cdpr_quat_from_euler(pose[3], pose[4], pose[5]);
    m.v_m_per_s = cdpr_v3(CDPR_R(0.0), CDPR_R(0.0), CDPR_R(0.0));
    m.w_rad_per_s = cdpr_v3(CDPR_R(0.0), CDPR_R(0.0), CDPR_R(0.0));
    return m;
}
