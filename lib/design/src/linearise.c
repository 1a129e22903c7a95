/* SPDX-License-Identifier: BSD-3-Clause */
/// @file linearise.c
/// The operating point and the linear model of the loop about it (cdpr/design/design.h):
/// central differences of cdpr_robot_rhs and of one real cdpr_tracker_step on copies of the
/// tracker, as cdpr-design wrote them (docs/validation.md §8, "Feedback design").
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cdpr/design/design.h"
#include "cdpr/vec3.h"

#define NZ_MAX CDPR_DESIGN_NZ_MAX
#define NM_MAX CDPR_DESIGN_NM_MAX
#define NU_MAX CDPR_DESIGN_NU_MAX

/* The model's sizes for the point's robot (design.h): nu rate commands, one per cable. */
static int nu_of(const cdpr_design_point_t *pt)
{
    return pt->plant.robot.p.n_cables;
}

/* Perturbation of state component i (relative above 1). */
static double step_of(double y, double rel)
{
    return rel * fmax(1.0, fabs(y));
}

void cdpr_design_outputs(cdpr_design_point_t *pt, const double *y, double o[CDPR_DESIGN_NM_MAX])
{
    cdpr_plant_t *pl = &pt->plant;
    const int n = pl->robot.dim;
    const cdpr_quat_t q0 = cdpr_quat_normalize(pl->pp.initial.q);
    double save[CDPR_ROBOT_STATE_MAX];
    memcpy(save, pl->y, sizeof(double) * (size_t)n);
    memcpy(pl->y, y, sizeof(double) * (size_t)n);
    cdpr_plant_meas_t m;
    cdpr_plant_measure(pl, &m);
    memcpy(pl->y, save, sizeof(double) * (size_t)n);
    const cdpr_quat_t q0i = {q0.w, -q0.x, -q0.y, -q0.z};
    const cdpr_vec3_t th = cdpr_quat_to_rotvec(cdpr_quat_mul(m.cabin.q, q0i));
    cdpr_mat3_t R;
    cdpr_quat_to_mat3(m.cabin.q, &R);
    const cdpr_vec3_t w = cdpr_m3_mul_v3(&R, m.cabin.w_rad_per_s);
    const double v[12] = {
        m.cabin.p_m.x,       m.cabin.p_m.y,       m.cabin.p_m.z,       th.x, th.y, th.z,
        m.cabin.v_m_per_s.x, m.cabin.v_m_per_s.y, m.cabin.v_m_per_s.z, w.x,  w.y,  w.z};
    memcpy(o, v, sizeof v);
    for (int j = 0; j < nu_of(pt); ++j) {
        o[12 + j] = m.length_m[j];
    }
}

/* The tracker's states z of the linear model (nz = 33 + 4 nu), in this order: err_f1 (12),
 * err_f (12), ten_f (nu), integ (6), mass_est_kg, l_ff_m (nu), t_ff_N (nu), mass_res_f1,
 * mass_res_f, ten_w (nu). */
static void z_of_tracker(const cdpr_tracker_t *tr, int nu, double *z)
{
    const size_t m = (size_t)nu;
    memcpy(z, tr->err_f1, sizeof(double) * 12);
    memcpy(z + 12, tr->err_f, sizeof(double) * 12);
    memcpy(z + 24, tr->ten_f, sizeof(double) * m);
    memcpy(z + 24 + m, tr->integ, sizeof tr->integ);
    z[30 + m] = tr->mass_est_kg;
    memcpy(z + 31 + m, tr->l_ff_m, sizeof(double) * m);
    memcpy(z + 31 + 2 * m, tr->t_ff_N, sizeof(double) * m);
    z[31 + 3 * m] = tr->mass_res_f1;
    z[32 + 3 * m] = tr->mass_res_f;
    memcpy(z + 33 + 3 * m, tr->ten_w, sizeof(double) * m);
}

static void z_to_tracker(const double *z, int nu, cdpr_tracker_t *tr)
{
    const size_t m = (size_t)nu;
    memcpy(tr->err_f1, z, sizeof(double) * 12);
    memcpy(tr->err_f, z + 12, sizeof(double) * 12);
    memcpy(tr->ten_f, z + 24, sizeof(double) * m);
    memcpy(tr->integ, z + 24 + m, sizeof tr->integ);
    tr->mass_est_kg = z[30 + m];
    memcpy(tr->l_ff_m, z + 31 + m, sizeof(double) * m);
    memcpy(tr->t_ff_N, z + 31 + 2 * m, sizeof(double) * m);
    tr->mass_res_f1 = z[31 + 3 * m];
    tr->mass_res_f = z[32 + 3 * m];
    memcpy(tr->ten_w, z + 33 + 3 * m, sizeof(double) * m);
}

/* One tracker step from the held tracker with filter state z at plant state y and payout
 * rates in force up: the m rate commands into u, the new filter state into zn (z: err_f1,
 * err_f, ten_f, integ, mass_est_kg, l_ff_m, t_ff_N, mass_res_f1, mass_res_f, ten_w). */
static void ctrl_at(cdpr_design_point_t *pt, const double *y, const double *z, const double *up,
                    double *u, double *zn)
{
    cdpr_plant_t *pl = &pt->plant;
    const int n = pl->robot.dim;
    const int nu = nu_of(pt);
    double save[CDPR_ROBOT_STATE_MAX];
    memcpy(save, pl->y, sizeof(double) * (size_t)n);
    memcpy(pl->y, y, sizeof(double) * (size_t)n);
    for (int j = 0; j < nu; ++j) {
        pl->robot.in.payout_m_per_s[j] = up[j];
    }
    cdpr_plant_meas_t m;
    cdpr_plant_measure(pl, &m);
    for (int j = 0; j < nu; ++j) {
        pl->robot.in.payout_m_per_s[j] = 0.0;
    }
    memcpy(pl->y, save, sizeof(double) * (size_t)n);
    m.t_s = pt->tr0.t_next_s;
    pt->tr = pt->tr0;
    z_to_tracker(z, nu, &pt->tr);
    pt->tr.filter_primed = 1;
    cdpr_tracker_cmd_t cmd;
    (void)cdpr_tracker_step(&pt->tr, &m, &cmd);
    memcpy(u, cmd.rate_m_per_s, sizeof(double) * (size_t)nu);
    z_of_tracker(&pt->tr, nu, zn);
}

/* A and B by central differences of cdpr_robot_rhs (payout rates zero at the settled state). */
static void plant_jacobians(cdpr_design_point_t *pt, double *y, double *fp, double *fm, double *A,
                            double *B)
{
    cdpr_robot_t *r = &pt->plant.robot;
    const int n = r->dim;
    const int nu = nu_of(pt);
    memcpy(y, pt->plant.y, sizeof(double) * (size_t)n);
    for (int j = 0; j < CDPR_MAX_CABLES; ++j) {
        r->in.payout_m_per_s[j] = 0.0;
    }
    for (int i = 0; i < n + nu; ++i) {
        const double h = (i < n) ? step_of(y[i], 1e-6) : 1e-6;
        double *slot = (i < n) ? &y[i] : &r->in.payout_m_per_s[i - n];
        const double y0 = *slot;
        *slot = y0 + h;
        (void)cdpr_robot_rhs(0.0, y, fp, r);
        *slot = y0 - h;
        (void)cdpr_robot_rhs(0.0, y, fm, r);
        *slot = y0;
        for (int k = 0; k < n; ++k) {
            const double d = (fp[k] - fm[k]) / (2.0 * h);
            if (i < n) {
                A[(size_t)k * (size_t)n + (size_t)i] = d;
            } else {
                B[(size_t)k * (size_t)nu + (size_t)(i - n)] = d;
            }
        }
    }
}

/* Kx, Zx, Cm (columns: plant state), Kz, Zz (filter state), Ku, Zu (rates in force) by
 * central differences of the real tracker step and measurement about (y0, z0). */
static void ctrl_jacobians(cdpr_design_point_t *pt, double *y, const double *z0,
                           cdpr_design_model_t *md)
{
    const int n = pt->plant.robot.dim;
    const int nu = nu_of(pt);
    const int nz = CDPR_DESIGN_NZ(nu);
    const int nm = 12 + nu;
    memcpy(y, pt->plant.y, sizeof(double) * (size_t)n);
    double z[NZ_MAX];
    memcpy(z, z0, sizeof(double) * (size_t)nz);
    double u0[NU_MAX];
    memset(u0, 0, sizeof u0);
    double up[NU_MAX], um[NU_MAX], zp[NZ_MAX], zm[NZ_MAX], op[NM_MAX], om[NM_MAX];
    for (int i = 0; i < n + nz + nu; ++i) {
        double *slot = (i < n) ? &y[i] : (i < n + nz) ? &z[i - n] : &u0[i - n - nz];
        const double v0 = *slot;
        const double h = (i < n + nz) ? step_of(v0, 1e-6) : 1e-6;
        *slot = v0 + h;
        ctrl_at(pt, y, z, u0, up, zp);
        if (i < n) {
            cdpr_design_outputs(pt, y, op);
        }
        *slot = v0 - h;
        ctrl_at(pt, y, z, u0, um, zm);
        if (i < n) {
            cdpr_design_outputs(pt, y, om);
        }
        *slot = v0;
        const size_t nc = (i < n) ? (size_t)n : (i < n + nz) ? (size_t)nz : (size_t)nu;
        const size_t c = (i < n)        ? (size_t)i
                         : (i < n + nz) ? (size_t)(i - n)
                                        : (size_t)(i - n - nz);
        double *K = (i < n) ? md->Kx : (i < n + nz) ? md->Kz : md->Ku;
        double *Z = (i < n) ? md->Zx : (i < n + nz) ? md->Zz : md->Zu;
        for (int k = 0; k < nu; ++k) {
            K[(size_t)k * nc + c] = (up[k] - um[k]) / (2.0 * h);
        }
        for (int k = 0; k < nz; ++k) {
            Z[(size_t)k * nc + c] = (zp[k] - zm[k]) / (2.0 * h);
        }
        for (int k = 0; i < n && k < nm; ++k) {
            md->Cm[(size_t)k * nc + c] = (op[k] - om[k]) / (2.0 * h);
        }
    }
}

cdpr_status_t cdpr_design_point_new(const cdpr_scenario_t *sc, double at_s,
                                    const cdpr_rig_scale_t *plant, cdpr_design_point_t **out,
                                    cdpr_design_error_t *err)
{
    *out = NULL;
    err->msg[0] = '\0';
    cdpr_design_point_t *pt = calloc(1, sizeof *pt);
    if (pt == NULL) {
        snprintf(err->msg, sizeof err->msg, "design: out of memory");
        return CDPR_E_CAPACITY;
    }
    pt->sc = *sc;
    double t = at_s;
    if (!isfinite(t)) {
        t = cdpr_traj_end_time(&pt->sc.traj);
        t = isfinite(t) ? t : 0.0;
    }
    cdpr_traj_sample_t s;
    cdpr_traj_eval(&pt->sc.traj, t, &s);
    memcpy(pt->pose, s.pose, sizeof s.pose);
    pt->lap_s = cdpr_traj_lap_s(&pt->sc.traj);
    const double per_lap = floor(pt->lap_s / pt->sc.period_s + 0.5);
    pt->learn_knots =
        (per_lap > (double)CDPR_TRACKER_LEARN_KNOTS) ? (double)CDPR_TRACKER_LEARN_KNOTS : per_lap;
    pt->sc.traj.type = CDPR_TRAJ_HOLD;
    memcpy(pt->sc.traj.hold_pose, s.pose, sizeof s.pose);
    pt->sc.has_initial_pose = 0;
    memset(pt->sc.initial_offset, 0, sizeof pt->sc.initial_offset);
    pt->sc.gains.transfer_s = 0.0;
    cdpr_scenario_error_t se;
    se.msg[0] = '\0';
    /* The controller's model: the scenario's robot with controller.model's factors, whatever
     * the plant's variation. */
    cdpr_status_t st = cdpr_host_controller_params(&pt->sc, &pt->model, &se);
    if (st != CDPR_OK) {
        snprintf(err->msg, sizeof err->msg, "design: the controller's model: %s (%.400s)",
                 cdpr_status_str(st), se.msg);
        free(pt);
        return st;
    }
    pt->plant_scale = (plant != NULL) ? *plant : cdpr_rig_scale_unit();
    cdpr_rig_scale(&pt->sc.rig, &pt->plant_scale);
    st = cdpr_host_plant_init(&pt->plant, &pt->sc, NULL, &se);
    if (st != CDPR_OK) {
        snprintf(err->msg, sizeof err->msg, "design: plant at the held pose: %s (%.400s)",
                 cdpr_status_str(st), se.msg);
        free(pt);
        return st;
    }
    cdpr_tracker_gains_t g = pt->sc.gains;
    g.wind_m_per_s = pt->plant.pp.wind_m_per_s;
    cdpr_diag_t d;
    st = cdpr_tracker_init(&pt->tr0, &pt->model, &pt->sc.traj, &g, pt->sc.period_s, 0.0, &d);
    if (st != CDPR_OK) {
        snprintf(err->msg, sizeof err->msg, "design: controller: field '%.100s': %s", d.field,
                 cdpr_status_str(st));
        free(pt);
        return st;
    }
    *out = pt;
    return CDPR_OK;
}

void cdpr_design_point_free(cdpr_design_point_t *pt)
{
    free(pt);
}

/* Filter state at the operating point: both stages primed with the error of the settled
 * state (the discrete equilibrium's small offset from the IK pose). */
static void operating_filter(cdpr_design_point_t *pt, double *z0)
{
    cdpr_plant_meas_t m;
    cdpr_plant_measure(&pt->plant, &m);
    m.t_s = pt->tr0.t_next_s;
    pt->tr = pt->tr0;
    pt->tr.filter_primed = 0;
    cdpr_tracker_cmd_t cmd;
    (void)cdpr_tracker_step(&pt->tr, &m, &cmd);
    z_of_tracker(&pt->tr, nu_of(pt), z0);
}

/* J: the straight-cable length Jacobian at the settled pose (rows u_j, (R b_j) x u_j). */
static void length_jacobian(cdpr_design_point_t *pt, double *J)
{
    cdpr_plant_meas_t m;
    cdpr_plant_measure(&pt->plant, &m);
    for (int j = 0; j < nu_of(pt); ++j) {
        cdpr_vec3_t u;
        cdpr_vec3_t g;
        cdpr_tracker_jacobian(&pt->tr0.model, j, &m.cabin, &u, &g);
        const double row[6] = {u.x, u.y, u.z, g.x, g.y, g.z};
        memcpy(&J[j * 6], row, sizeof row);
    }
}

void cdpr_design_model_free(cdpr_design_model_t *m)
{
    if (m == NULL) {
        return;
    }
    double **fields[] = {&m->A, &m->B, &m->Kx, &m->Kz, &m->Zx, &m->Zz, &m->Ku, &m->Zu, &m->Cm};
    for (size_t i = 0; i < sizeof fields / sizeof fields[0]; ++i) {
        double **const field = fields[i];
        free(*field);
        *field = NULL;
    }
}

cdpr_status_t cdpr_design_linearise(cdpr_design_point_t *pt, cdpr_design_model_t *m,
                                    cdpr_design_error_t *err)
{
    memset(m, 0, sizeof *m);
    err->msg[0] = '\0';
    const int n = pt->plant.robot.dim;
    const size_t nn = (size_t)n;
    const size_t nu = (size_t)nu_of(pt);
    const size_t nz = (size_t)CDPR_DESIGN_NZ(nu);
    const size_t nm = 12u + nu;
    m->n = n;
    m->nu = (int)nu;
    m->nz = (int)nz;
    m->nm = (int)nm;
    m->period_s = pt->sc.period_s;
    m->A = calloc(nn * nn, sizeof(double));
    m->B = calloc(nn * nu, sizeof(double));
    m->Kx = calloc(nu * nn, sizeof(double));
    m->Zx = calloc(nz * nn, sizeof(double));
    m->Cm = calloc(nm * nn, sizeof(double));
    m->Kz = calloc(nu * nz, sizeof(double));
    m->Zz = calloc(nz * nz, sizeof(double));
    m->Ku = calloc(nu * nu, sizeof(double));
    m->Zu = calloc(nz * nu, sizeof(double));
    double *work = calloc(3 * nn, sizeof(double));
    if (m->A == NULL || m->B == NULL || m->Kx == NULL || m->Zx == NULL || m->Cm == NULL ||
        m->Kz == NULL || m->Zz == NULL || m->Ku == NULL || m->Zu == NULL || work == NULL) {
        free(work);
        cdpr_design_model_free(m);
        snprintf(err->msg, sizeof err->msg, "design: out of memory (n = %d)", n);
        return CDPR_E_CAPACITY;
    }
    double z0[NZ_MAX];
    operating_filter(pt, z0);
    plant_jacobians(pt, work, work + nn, work + 2 * nn, m->A, m->B);
    ctrl_jacobians(pt, work, z0, m);
    free(work);
    length_jacobian(pt, m->J);
    const cdpr_tracker_gains_t *g = &pt->sc.gains;
    m->lap_s = pt->lap_s;
    m->learn_knots = pt->learn_knots;
    m->k_length_per_s = g->k_length_per_s;
    m->learning_gain = g->learning_gain;
    m->learning_lead_s = g->learning_lead_s;
    m->learning_cutoff_hz = g->learning_cutoff_hz;
    return CDPR_OK;
}
