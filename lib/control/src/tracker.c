/* SPDX-License-Identifier: BSD-3-Clause */
/// @file tracker.c
/// Sag-aware feed-forward (statics plus the d'Alembert load of the desired motion) plus pose
/// feedback through the straight-cable Jacobian.
#include "cdpr/control/tracker.h"

#include <math.h>
#include <string.h>

#include "cdpr/vec3.h"

int cdpr_tracker_has_feedback(const cdpr_tracker_gains_t *g)
{
    const cdpr_real_t zero = CDPR_R(0.0);
    return ((g->kp > zero) || (g->kd_s > zero) || (g->damping_N_s_per_m > zero) ||
            (g->damping_rot_N_m_s > zero) || (g->tension_gain_m_per_s_per_N > zero) ||
            (g->learning_gain > zero) || (g->integral_per_s > zero) ||
            (g->weight_estimate_s > zero))
               ? 1
               : 0;
}

void cdpr_tracker_jacobian(const cdpr_robot_t *model, int j, const cdpr_cabin_motion_t *m,
                           cdpr_vec3_t *u, cdpr_vec3_t *g)
{
    cdpr_mat3_t R;
    cdpr_quat_to_mat3(cdpr_quat_normalize(m->q), &R);
    const cdpr_vec3_t rb = cdpr_m3_mul_v3(&R, model->p.cables[j].attach_body_m);
    const cdpr_vec3_t d = cdpr_v3_sub(model->p.cables[j].exit_point_m, cdpr_v3_add(m->p_m, rb));
    const cdpr_real_t l = cdpr_v3_norm(d);
    *u = (l > CDPR_R(0.0)) ? cdpr_v3_scale(d, CDPR_R(1.0) / l)
                           : cdpr_v3(CDPR_R(0.0), CDPR_R(0.0), CDPR_R(0.0));
    *g = cdpr_v3_cross(rb, *u);
}

void cdpr_tracker_inertial_wrench(const cdpr_robot_t *model, const cdpr_traj_sample_t *d,
                                  cdpr_vec3_t *f_N, cdpr_vec3_t *tau_Nm)
{
    const cdpr_cabin_params_t *cab = &model->p.cabin;
    cdpr_mat3_t R;
    cdpr_quat_to_mat3(cdpr_quat_normalize(d->motion.q), &R);
    const cdpr_vec3_t w = d->motion.w_rad_per_s; /* body axes */
    const cdpr_vec3_t dw = d->dw_rad_per_s2;     /* body axes */
    const cdpr_vec3_t rc = cdpr_m3_mul_v3(&R, cab->com_body_m);
    const cdpr_vec3_t ww = cdpr_m3_mul_v3(&R, w);
    const cdpr_vec3_t dww = cdpr_m3_mul_v3(&R, dw);
    const cdpr_vec3_t a_c =
        cdpr_v3_add(d->a_m_per_s2,
                    cdpr_v3_add(cdpr_v3_cross(dww, rc), cdpr_v3_cross(ww, cdpr_v3_cross(ww, rc))));
    *f_N = cdpr_v3_scale(a_c, -cab->mass_kg);
    /* Rate of the angular momentum about the CoM, body axes: I ω̇ + ω x I ω. */
    const cdpr_vec3_t hdot =
        cdpr_v3_add(cdpr_m3_mul_v3(&cab->inertia_com_kg_m2, dw),
                    cdpr_v3_cross(w, cdpr_m3_mul_v3(&cab->inertia_com_kg_m2, w)));
    *tau_Nm = cdpr_v3_scale(cdpr_m3_mul_v3(&R, hdot), -CDPR_R(1.0));
}

/* Step 8's gains: finite and >= 0, a positive bound when learning is on. */
static cdpr_status_t check_learning(const cdpr_tracker_gains_t *g, cdpr_diag_t *diag)
{
    const cdpr_real_t v[4] = {g->learning_gain, g->learning_lead_s, g->learning_cutoff_hz,
                              g->learning_limit_m};
    static const char *const names[4] = {"learning_gain", "learning_lead_s", "learning_cutoff_hz",
                                         "learning_limit_m"};
    for (int i = 0; i < 4; ++i) {
        if (!isfinite(v[i])) {
            return cdpr_diag_set(diag, CDPR_E_NOT_FINITE, names[i], -1);
        }
        if (v[i] < CDPR_R(0.0)) {
            return cdpr_diag_set(diag, CDPR_E_OUT_OF_RANGE, names[i], -1);
        }
    }
    if (g->learning_gain > CDPR_R(0.0) && !(g->learning_limit_m > CDPR_R(0.0))) {
        return cdpr_diag_set(diag, CDPR_E_OUT_OF_RANGE, "learning_limit_m", -1);
    }
    if (g->learning_settle_laps < 0) {
        return cdpr_diag_set(diag, CDPR_E_OUT_OF_RANGE, "learning_settle_laps", -1);
    }
    return CDPR_OK;
}

/* Steps 2d and 1c: finite, >= 0, and the integral's bound when it is on. */
static cdpr_status_t check_integral_weight(const cdpr_tracker_gains_t *g, cdpr_diag_t *diag)
{
    cdpr_status_t st = CDPR_OK;
    if (!isfinite(g->integral_per_s)) {
        st = cdpr_diag_set(diag, CDPR_E_NOT_FINITE, "integral_per_s", -1);
    } else if (!isfinite(g->integral_limit_m)) {
        st = cdpr_diag_set(diag, CDPR_E_NOT_FINITE, "integral_limit_m", -1);
    } else if (g->integral_per_s < CDPR_R(0.0)) {
        st = cdpr_diag_set(diag, CDPR_E_OUT_OF_RANGE, "integral_per_s", -1);
    } else if (!isfinite(g->weight_estimate_s)) {
        st = cdpr_diag_set(diag, CDPR_E_NOT_FINITE, "weight_estimate_s", -1);
    } else if (g->weight_estimate_s < CDPR_R(0.0)) {
        st = cdpr_diag_set(diag, CDPR_E_OUT_OF_RANGE, "weight_estimate_s", -1);
    } else if ((g->integral_limit_m < CDPR_R(0.0)) ||
               ((g->integral_per_s > CDPR_R(0.0)) && !(g->integral_limit_m > CDPR_R(0.0)))) {
        st = cdpr_diag_set(diag, CDPR_E_OUT_OF_RANGE, "integral_limit_m", -1);
    } else {
        /* valid */
    }
    return st;
}

cdpr_real_t cdpr_tracker_correction_at(const cdpr_tracker_correction_t *c, int j, cdpr_real_t t_s)
{
    const cdpr_real_t x = (t_s - c->start_s) / c->spacing_s;
    cdpr_real_t sum = CDPR_R(0.0);
    /* Outside every basis function's support (and NaN): 0. */
    if ((x > CDPR_R(0.0)) && (x < ((cdpr_real_t)c->n_coef + CDPR_R(3.0)))) {
        const long k = (long)CDPR_FLOOR(x); /* 0 .. n_coef + 2 */
        const cdpr_real_t u = x - (cdpr_real_t)k;
        const cdpr_real_t v = CDPR_R(1.0) - u;
        const cdpr_real_t u2 = u * u;
        const cdpr_real_t u3 = u2 * u;
        /* β(x - i) for i = k, k - 1, k - 2, k - 3: the four pieces of the cubic B-spline. */
        const cdpr_real_t w[4] = {
            u3 / CDPR_R(6.0),
            ((((CDPR_R(-3.0) * u3) + (CDPR_R(3.0) * u2)) + (CDPR_R(3.0) * u)) + CDPR_R(1.0)) /
                CDPR_R(6.0),
            (((CDPR_R(3.0) * u3) - (CDPR_R(6.0) * u2)) + CDPR_R(4.0)) / CDPR_R(6.0),
            ((v * v) * v) / CDPR_R(6.0)};
        const cdpr_real_t *a = &c->coef_m[(long)j * (long)c->n_coef];
        for (long q = 0; q < 4; ++q) {
            const long i = k - q;
            if ((i >= 0) && (i < (long)c->n_coef)) {
                sum += a[i] * w[q];
            }
        }
    }
    return sum;
}

/* gains.correction: made for this robot's cable count and this period, every value finite. */
static cdpr_status_t check_correction(const cdpr_tracker_correction_t *c, int n_cables,
                                      cdpr_real_t period_s, cdpr_diag_t *diag)
{
    cdpr_status_t st = CDPR_OK;
    if (c == NULL) {
        /* none: valid */
    } else if ((c->coef_m == NULL) || (c->n_coef < 1)) {
        st = cdpr_diag_set(diag, CDPR_E_INVALID_ARG, "correction", c->n_coef);
    } else if (c->n_cables != n_cables) {
        st = cdpr_diag_set(diag, CDPR_E_OUT_OF_RANGE, "correction (n_cables)", c->n_cables);
    } else if (!isfinite(c->start_s) || !isfinite(c->spacing_s) || !isfinite(c->period_s)) {
        st = cdpr_diag_set(diag, CDPR_E_NOT_FINITE, "correction", -1);
    } else if (!(c->spacing_s > CDPR_R(0.0)) ||
               !(CDPR_FABS(c->period_s - period_s) <= (CDPR_R(1e-9) * period_s))) {
        st = cdpr_diag_set(diag, CDPR_E_OUT_OF_RANGE, "correction (spacing_s or period_s)", -1);
    } else {
        const long n = (long)c->n_cables * (long)c->n_coef;
        for (long i = 0; (i < n) && (st == CDPR_OK); ++i) {
            if (!isfinite(c->coef_m[i])) {
                st = cdpr_diag_set(diag, CDPR_E_NOT_FINITE, "correction", (int)i);
            }
        }
    }
    return st;
}

static cdpr_status_t check_gains(const cdpr_tracker_gains_t *g, cdpr_real_t period_s,
                                 cdpr_diag_t *diag)
{
    const cdpr_real_t v[14] = {period_s,
                               g->kp,
                               g->kd_s,
                               g->k_length_per_s,
                               g->filter_s,
                               g->inertial_ff,
                               g->damping_N_s_per_m,
                               g->damping_rot_N_m_s,
                               g->transfer_s,
                               g->wind_ff,
                               g->tension_gain_m_per_s_per_N,
                               g->tension_filter_s,
                               g->transfer_from_rest,
                               g->tension_washout_s};
    static const char *const names[14] = {"period_s",
                                          "kp",
                                          "kd_s",
                                          "k_length_per_s",
                                          "filter_s",
                                          "inertial_ff",
                                          "damping_N_s_per_m",
                                          "damping_rot_N_m_s",
                                          "transfer_s",
                                          "wind_ff",
                                          "tension_gain_m_per_s_per_N",
                                          "tension_filter_s",
                                          "transfer_from_rest",
                                          "tension_washout_s"};
    if (!cdpr_v3_isfinite(g->wind_m_per_s)) {
        return cdpr_diag_set(diag, CDPR_E_NOT_FINITE, "wind_m_per_s", -1);
    }
    for (int i = 0; i < 14; ++i) {
        if (!isfinite(v[i])) {
            return cdpr_diag_set(diag, CDPR_E_NOT_FINITE, names[i], -1);
        }
        if (v[i] < CDPR_R(0.0) || (i == 0 && !(v[i] > CDPR_R(0.0)))) {
            return cdpr_diag_set(diag, CDPR_E_OUT_OF_RANGE, names[i], -1);
        }
    }
    const cdpr_status_t st = check_learning(g, diag);
    return (st != CDPR_OK) ? st : check_integral_weight(g, diag);
}

cdpr_status_t cdpr_tracker_set_wind(cdpr_tracker_t *tr, cdpr_vec3_t wind_m_per_s)
{
    cdpr_status_t st = CDPR_E_INVALID_ARG;
    if (tr != NULL) {
        st = CDPR_E_NOT_FINITE;
        if (cdpr_v3_isfinite(wind_m_per_s) != 0) {
            tr->g.wind_m_per_s = wind_m_per_s;
            st = CDPR_OK;
        }
    }
    return st;
}

void cdpr_tracker_wind_wrench(const cdpr_robot_t *model, const cdpr_cabin_motion_t *pose,
                              cdpr_vec3_t wind_m_per_s, cdpr_vec3_t *f_N, cdpr_vec3_t *tau_Nm)
{
    cdpr_mat3_t R;
    cdpr_quat_to_mat3(cdpr_quat_normalize(pose->q), &R);
    const cdpr_vec3_t J = wind_m_per_s;
    *f_N = cdpr_v3(CDPR_R(0.0), CDPR_R(0.0), CDPR_R(0.0));
    *tau_Nm = *f_N;
    for (int j = 0; j < model->p.n_cables; ++j) {
        const cdpr_robot_cable_params_t *c = &model->p.cables[j];
        const cdpr_vec3_t rb = cdpr_m3_mul_v3(&R, c->attach_body_m);
        const cdpr_vec3_t d = cdpr_v3_sub(c->exit_point_m, cdpr_v3_add(pose->p_m, rb));
        const cdpr_real_t l = cdpr_v3_norm(d);
        if (!(l > CDPR_R(0.0))) {
            continue;
        }
        const cdpr_vec3_t t = cdpr_v3_scale(d, CDPR_R(1.0) / l);
        const cdpr_real_t jt = cdpr_v3_dot(J, t);
        const cdpr_vec3_t jn = cdpr_v3_sub(J, cdpr_v3_scale(t, jt));
        const cdpr_real_t k =
            CDPR_R(0.5) * c->cable.rho_air_kg_per_m3 * c->cable.d0_m * c->cable.cd * l;
        const cdpr_vec3_t D =
            cdpr_v3_scale(cdpr_v3_add(cdpr_v3_scale(jn, cdpr_v3_norm(jn)),
                                      cdpr_v3_scale(t, c->cable.cm * CDPR_FABS(jt) * jt)),
                          k);
        const cdpr_vec3_t half = cdpr_v3_scale(D, CDPR_R(0.5));
        const cdpr_vec3_t r =
            cdpr_m3_mul_v3(&R, cdpr_v3_sub(c->attach_body_m, model->p.cabin.com_body_m));
        *f_N = cdpr_v3_add(*f_N, half);
        *tau_Nm = cdpr_v3_add(*tau_Nm, cdpr_v3_cross(r, half));
    }
}

/* External load of the feed-forward IK at time t: the reference (into d), the feed-forward
 * share of the d'Alembert load, the cables' wind load, minus the cable wrench (f_add, tau_add)
 * asked for on top of that (zero for the feed-forward itself). */
static void load_at(const cdpr_tracker_t *tr, cdpr_real_t t, cdpr_vec3_t f_add, cdpr_vec3_t tau_add,
                    cdpr_traj_sample_t *d, cdpr_vec3_t *f, cdpr_vec3_t *tau)
{
    cdpr_tracker_reference(tr, t, d);
    *f = cdpr_v3(CDPR_R(0.0), CDPR_R(0.0), CDPR_R(0.0));
    *tau = *f;
    if (tr->g.inertial_ff > CDPR_R(0.0)) {
        cdpr_tracker_inertial_wrench(&tr->model, d, f, tau);
        *f = cdpr_v3_scale(*f, tr->g.inertial_ff);
        *tau = cdpr_v3_scale(*tau, tr->g.inertial_ff);
    }
    if (tr->g.weight_estimate_s > CDPR_R(0.0)) {
        /* Step 1c: a heavier cabin of the model's shape: its d'Alembert load scaled, its extra
         * weight at the CoM. */
        const cdpr_real_t k = CDPR_R(1.0) + (tr->mass_est_kg / tr->model.p.cabin.mass_kg);
        *f = cdpr_v3_scale(*f, k);
        *tau = cdpr_v3_scale(*tau, k);
        f->z -= tr->mass_est_kg * tr->model.p.g_m_per_s2;
    }
    if (tr->g.wind_ff > CDPR_R(0.0)) {
        cdpr_vec3_t fw;
        cdpr_vec3_t tw;
        cdpr_tracker_wind_wrench(&tr->model, &d->motion, tr->g.wind_m_per_s, &fw, &tw);
        *f = cdpr_v3_add(*f, cdpr_v3_scale(fw, tr->g.wind_ff));
        *tau = cdpr_v3_add(*tau, cdpr_v3_scale(tw, tr->g.wind_ff));
    }
    /* The IK's external load is what the cables must balance: a wrench the cables are to
     * add enters with the opposite sign. */
    *f = cdpr_v3_sub(*f, f_add);
    *tau = cdpr_v3_sub(*tau, tau_add);
}

/* Lengths at time t (and, if T is not NULL, the winch-end tensions): IK of the reference pose
 * under the weight and load_at's load. On failure `L` and `T` are untouched. */
static cdpr_status_t ik_at(const cdpr_tracker_t *tr, cdpr_real_t t, cdpr_vec3_t f_add,
                           cdpr_vec3_t tau_add, cdpr_real_t *L, cdpr_real_t *T)
{
    cdpr_traj_sample_t d;
    cdpr_vec3_t f;
    cdpr_vec3_t tau;
    load_at(tr, t, f_add, tau_add, &d, &f, &tau);
    cdpr_statics_result_t res;
    const cdpr_status_t st =
        cdpr_statics_ik_dist(&tr->model, &d.motion, f, tau, NULL, &tr->ik_opts, &res, NULL);
    if (st != CDPR_OK) {
        return st;
    }
    /* A cable hanging in a loop is not a length to command: the IK itself reports it as
     * CDPR_E_INFEASIBLE (over CDPR_STATICS_MAX_LENGTH_PER_CHORD chords, statics.h). */
    for (int j = 0; j < tr->model.p.n_cables; ++j) {
        L[j] = res.cable[j].length_m;
        if (T != NULL) {
            T[j] = res.cable[j].tension_winch_N;
        }
    }
    return CDPR_OK;
}

/* Tension awareness: the feed-forward at t failed; distribute its load on the straight chords
 * and count every cable whose tension there is <= 0. */
static void slack_demand(cdpr_tracker_t *tr, cdpr_real_t t, cdpr_tracker_cmd_t *cmd)
{
    cdpr_traj_sample_t d;
    cdpr_vec3_t f;
    cdpr_vec3_t tau;
    const cdpr_vec3_t zero = cdpr_v3(CDPR_R(0.0), CDPR_R(0.0), CDPR_R(0.0));
    load_at(tr, t, zero, zero, &d, &f, &tau);
    cdpr_real_t ten[CDPR_MAX_CABLES];
    for (int j = 0; j < CDPR_MAX_CABLES; ++j) {
        ten[j] = CDPR_R(0.0);
    }
    if (cdpr_statics_straight_tensions(&tr->model, &d.motion, f, tau, ten) != CDPR_OK) {
        return;
    }
    for (int j = 0; j < tr->model.p.n_cables; ++j) {
        if (ten[j] <= CDPR_R(0.0)) {
            cmd->slack_demand |= 1U << (unsigned)j;
            tr->slack_demand_periods[j]++;
            if (tr->first_slack_cable < 0) {
                tr->first_slack_cable = j;
                tr->first_slack_t_s = t;
                tr->first_slack_tension_N = ten[j];
            }
        }
    }
    if (cmd->slack_demand != 0U) {
        (void)memcpy(cmd->demand_tension_N, ten, sizeof ten);
    }
}

void cdpr_tracker_reference(const cdpr_tracker_t *tr, cdpr_real_t t_s, cdpr_traj_sample_t *out)
{
    if (tr->transfer_set != 0) {
        cdpr_transfer_eval(&tr->transfer, &tr->traj, t_s, out);
    } else {
        cdpr_traj_eval(&tr->traj, t_s, out);
    }
}

/* Feed-forward lengths (and winch-end tensions, T may be NULL) at time t; on failure `L` and
 * `T` are untouched. */
static cdpr_status_t feedforward(const cdpr_tracker_t *tr, cdpr_real_t t, cdpr_real_t *L,
                                 cdpr_real_t *T)
{
    const cdpr_vec3_t zero = cdpr_v3(CDPR_R(0.0), CDPR_R(0.0), CDPR_R(0.0));
    return ik_at(tr, t, zero, zero, L, T);
}

/* ---------------------------------------------------------------- step 8: learning */

/* Knot k0 = floor(x) mod M, its neighbour k1 and the weight f of k1 at knot coordinate x. */
static void knot_pair(cdpr_real_t x, int M, int *k0, int *k1, cdpr_real_t *f)
{
    const cdpr_real_t k = CDPR_FLOOR(x);
    *f = x - k;
    long i = (long)CDPR_FMOD(k, (cdpr_real_t)M);
    i = (i < 0) ? i + M : i;
    *k0 = (int)i;
    *k1 = (*k0 + 1 < M) ? *k0 + 1 : 0;
}

/* One first-order stage y_i = a y_(i-1) + (1 - a) x_i run around the lap (dir +1 forward,
 * -1 backward) from its exact periodic state: with y_-1 = 0 first, then every output plus
 * a^(k+1) y*, y* = y_(M-1) / (1 - a^M) (the lap is periodic, so y_-1 = y_(M-1)). */
static void circular_stage(cdpr_real_t *x, int M, cdpr_real_t a, int dir)
{
    const cdpr_real_t b = CDPR_R(1.0) - a;
    cdpr_real_t y = CDPR_R(0.0);
    for (int k = 0; k < M; ++k) {
        const int i = (dir > 0) ? k : M - 1 - k;
        y = a * y + b * x[i];
        x[i] = y;
    }
    const cdpr_real_t ys = y / (CDPR_R(1.0) - CDPR_POW(a, (cdpr_real_t)M));
    cdpr_real_t p = a;
    for (int k = 0; k < M; ++k) {
        const int i = (dir > 0) ? k : M - 1 - k;
        x[i] += p * ys;
        p *= a;
    }
}

/* The update at a lap's end: c <- sat(Q[c + γ e_L(φ + lead)]) per cable, from the lap's
 * knot averages (the caller clears the accumulator for the next lap). */
static void learn_update(cdpr_tracker_t *tr)
{
    const int M = tr->learn_knots;
    const cdpr_real_t dphi = tr->learn_lap_s / (cdpr_real_t)M;
    const cdpr_real_t shift = tr->g.learning_lead_s / dphi;
    const cdpr_real_t a =
        (tr->g.learning_cutoff_hz > CDPR_R(0.0))
            ? CDPR_EXP(-CDPR_R(2.0) * (cdpr_real_t)CDPR_PI * tr->g.learning_cutoff_hz * dphi)
            : CDPR_R(0.0);
    const cdpr_real_t lim = tr->g.learning_limit_m;
    for (int j = 0; j < tr->model.p.n_cables; ++j) {
        cdpr_real_t *e = tr->learn_acc[j];
        cdpr_real_t *c = tr->learn_c[j];
        for (int i = 0; i < M; ++i) {
            e[i] = (tr->learn_w[i] > CDPR_R(0.0)) ? e[i] / tr->learn_w[i] : CDPR_R(0.0);
        }
        for (int i = 0; i < M; ++i) {
            int k0;
            int k1;
            cdpr_real_t f;
            knot_pair((cdpr_real_t)i + shift, M, &k0, &k1, &f);
            c[i] += tr->g.learning_gain * ((CDPR_R(1.0) - f) * e[k0] + f * e[k1]);
        }
        if (a > CDPR_R(0.0)) {
            circular_stage(c, M, a, 1);
            circular_stage(c, M, a, -1);
        }
        for (int i = 0; i < M; ++i) {
            if (CDPR_FABS(c[i]) > lim) {
                c[i] = CDPR_COPYSIGN(lim, c[i]);
                tr->learning_saturations++;
            }
        }
    }
    tr->learning_updates++;
}

/* Step 8 per period: at a lap change, the update (if the lap ending was recorded whole) and
 * whether the new lap is recorded; then c at the phase of t into dl (added), and the length
 * error e_L of this measurement onto the knots. Nothing without learning or outside laps. */
static void learn_step(cdpr_tracker_t *tr, const cdpr_tracker_meas_t *m, cdpr_real_t t,
                       const cdpr_real_t raw[12], cdpr_real_t *dl)
{
    if (tr->learn_knots <= 0) {
        return;
    }
    const long lap = cdpr_traj_lap(&tr->traj, t);
    if (lap != tr->learn_lap) {
        if (tr->learn_recording != 0) {
            learn_update(tr);
        }
        tr->learn_recording = (lap >= 0 && tr->learn_lap >= 0 && t >= tr->learn_start_s) ? 1 : 0;
        (void)memset(tr->learn_acc, 0, sizeof tr->learn_acc);
        (void)memset(tr->learn_w, 0, sizeof tr->learn_w);
        tr->learn_lap = lap;
    }
    if (lap < 0) {
        return;
    }
    const int M = tr->learn_knots;
    int k0;
    int k1;
    cdpr_real_t f;
    knot_pair(cdpr_traj_lap_phase(&tr->traj, t) * (cdpr_real_t)M, M, &k0, &k1, &f);
    for (int j = 0; j < tr->model.p.n_cables; ++j) {
        dl[j] += (CDPR_R(1.0) - f) * tr->learn_c[j][k0] + f * tr->learn_c[j][k1];
        if (tr->learn_recording != 0) {
            cdpr_vec3_t u;
            cdpr_vec3_t gj;
            cdpr_tracker_jacobian(&tr->model, j, &m->cabin, &u, &gj);
            const cdpr_real_t e = -(u.x * raw[0] + u.y * raw[1] + u.z * raw[2] + gj.x * raw[3] +
                                    gj.y * raw[4] + gj.z * raw[5]);
            tr->learn_acc[j][k0] += (CDPR_R(1.0) - f) * e;
            tr->learn_acc[j][k1] += f * e;
        }
    }
    if (tr->learn_recording != 0) {
        tr->learn_w[k0] += CDPR_R(1.0) - f;
        tr->learn_w[k1] += f;
    }
}

/* Step 8 at init: the knot count (0: no learning: off, or the trajectory is not periodic). */
static void learn_init(cdpr_tracker_t *tr)
{
    tr->learn_lap = -1;
    tr->learn_lap_s = cdpr_traj_lap_s(&tr->traj);
    if (!(tr->g.learning_gain > CDPR_R(0.0)) || !(tr->learn_lap_s > CDPR_R(0.0))) {
        return;
    }
    const cdpr_real_t per_lap = CDPR_FLOOR(tr->learn_lap_s / tr->period_s + CDPR_R(0.5));
    tr->learn_knots =
        (per_lap > (cdpr_real_t)CDPR_TRACKER_LEARN_KNOTS) ? CDPR_TRACKER_LEARN_KNOTS : (int)per_lap;
    tr->learn_knots = (tr->learn_knots >= 2) ? tr->learn_knots : 0;
}

/* Step 8 at the first step (time t): t_learn. */
static void learn_first_step(cdpr_tracker_t *tr, cdpr_real_t t)
{
    cdpr_real_t t0 = t + tr->g.transfer_s;
    if (tr->traj.type == CDPR_TRAJ_CIRCLE && tr->traj.ramp_s > t0) {
        t0 = tr->traj.ramp_s;
    }
    tr->learn_start_s = t0 + (cdpr_real_t)tr->g.learning_settle_laps * tr->learn_lap_s;
}

cdpr_status_t cdpr_tracker_init(cdpr_tracker_t *tr, const cdpr_robot_params_t *model_params,
                                const cdpr_traj_t *traj, const cdpr_tracker_gains_t *g,
                                cdpr_real_t period_s, cdpr_real_t t0_s, cdpr_diag_t *diag)
{
    if (tr == NULL || model_params == NULL || traj == NULL || g == NULL || !isfinite(t0_s)) {
        return cdpr_diag_set(diag, CDPR_E_INVALID_ARG, "tracker", -1);
    }
    /* The feed-forward is the sag-aware IK (cdpr_statics_ik_dist): six cables, or more with
     * the robot's tension distribution. */
    if (model_params->n_cables < 6 ||
        (model_params->n_cables > 6 && model_params->has_tension_dist == 0)) {
        return cdpr_diag_set(diag, CDPR_E_CAPACITY,
                             "n_cables (the tracker's IK needs 6, or more with the robot's "
                             "tension distribution)",
                             model_params->n_cables);
    }
    cdpr_status_t gs = check_gains(g, period_s, diag);
    if (gs == CDPR_OK) {
        gs = check_correction(g->correction, model_params->n_cables, period_s, diag);
    }
    if (gs != CDPR_OK) {
        return gs;
    }
    (void)memset(tr, 0, sizeof *tr);
    const cdpr_status_t ms = cdpr_robot_init(&tr->model, model_params, diag);
    if (ms != CDPR_OK) {
        return ms;
    }
    tr->traj = *traj;
    tr->g = *g;
    tr->period_s = period_s;
    cdpr_statics_opts_default(&tr->ik_opts);
    const cdpr_status_t st = feedforward(tr, t0_s, tr->l_ff_m, tr->t_ff_N);
    if (st != CDPR_OK) {
        return cdpr_diag_set(diag, st, "trajectory", -1);
    }
    tr->t_next_s = t0_s;
    tr->l_ff_exact = 1;
    tr->first_slack_cable = -1;
    learn_init(tr);
    return cdpr_diag_set(diag, CDPR_OK, "", -1);
}

/* Every measured value finite. */
static int meas_finite(const cdpr_tracker_t *tr, const cdpr_tracker_meas_t *m)
{
    int finite = (isfinite(m->t_s) && (cdpr_v3_isfinite(m->cabin.p_m) != 0) &&
                  (cdpr_v3_isfinite(m->cabin.v_m_per_s) != 0) &&
                  (cdpr_v3_isfinite(m->cabin.w_rad_per_s) != 0) && isfinite(m->cabin.q.w) &&
                  isfinite(m->cabin.q.x) && isfinite(m->cabin.q.y) && isfinite(m->cabin.q.z))
                     ? 1
                     : 0;
    /* the tensions are read only with tension feedback or the weight estimate on */
    const int tensions = ((tr->g.tension_gain_m_per_s_per_N > CDPR_R(0.0)) ||
                          (tr->g.weight_estimate_s > CDPR_R(0.0)))
                             ? 1
                             : 0;
    for (int j = 0; j < tr->model.p.n_cables; ++j) {
        if (!isfinite(m->length_m[j]) || (tensions != 0 && !isfinite(m->tension_winch_N[j]))) {
            finite = 0;
        }
    }
    return finite;
}

/* Step 1: L_ff(t) (prepared by the previous period, unless the caller's clock jumped) and
 * L_ff(t + dt) into l_next, its winch-end tensions into t_next (the last good values when the
 * IK fails). */
static void feedforward_step(cdpr_tracker_t *tr, cdpr_real_t t, cdpr_real_t dt, cdpr_real_t *l_next,
                             cdpr_real_t *t_next, cdpr_tracker_cmd_t *cmd)
{
    if (CDPR_FABS(t - tr->t_next_s) > CDPR_R(1e-9) * (CDPR_R(1.0) + CDPR_FABS(t))) {
        if (feedforward(tr, t, tr->l_ff_m, tr->t_ff_N) != CDPR_OK) {
            tr->ik_failures++;
            tr->l_ff_exact = 0;
        } else {
            tr->l_ff_exact = 1;
        }
    }
    (void)memcpy(l_next, tr->l_ff_m, sizeof(cdpr_real_t) * CDPR_MAX_CABLES);
    (void)memcpy(t_next, tr->t_ff_N, sizeof(cdpr_real_t) * CDPR_MAX_CABLES);
    cmd->ik_status = feedforward(tr, t + dt, l_next, t_next);
    if (cmd->ik_status != CDPR_OK) {
        tr->ik_failures++; /* l_next still holds the last good feed-forward */
        slack_demand(tr, t + dt, cmd);
    }
}

/* Step 2a: pose error (desired - measured) and its rate, world axes, into raw[12] (e_p, e_θ,
 * ė_p, ė_θ) and cmd (desired state, e_p, e_θ). */
static void pose_error(const cdpr_tracker_t *tr, const cdpr_tracker_meas_t *m, cdpr_real_t t,
                       cdpr_tracker_cmd_t *cmd, cdpr_real_t raw[12])
{
    cdpr_tracker_reference(tr, t, &cmd->desired);
    const cdpr_cabin_motion_t *d = &cmd->desired.motion;
    const cdpr_quat_t qm = cdpr_quat_normalize(m->cabin.q);
    const cdpr_quat_t qm_inv = {qm.w, -qm.x, -qm.y, -qm.z};
    const cdpr_vec3_t e_p = cdpr_v3_sub(d->p_m, m->cabin.p_m);
    const cdpr_vec3_t e_th = cdpr_quat_to_rotvec(cdpr_quat_mul(d->q, qm_inv));
    cdpr_mat3_t Rd;
    cdpr_mat3_t Rm;
    cdpr_quat_to_mat3(d->q, &Rd);
    cdpr_quat_to_mat3(qm, &Rm);
    const cdpr_vec3_t e_v = cdpr_v3_sub(d->v_m_per_s, m->cabin.v_m_per_s);
    const cdpr_vec3_t e_w =
        cdpr_v3_sub(cdpr_m3_mul_v3(&Rd, d->w_rad_per_s), cdpr_m3_mul_v3(&Rm, m->cabin.w_rad_per_s));
    cdpr_v3_store(e_p, cmd->err_pos_m);
    cdpr_v3_store(e_th, cmd->err_rot_rad);
    const cdpr_real_t v[12] = {e_p.x, e_p.y, e_p.z, e_th.x, e_th.y, e_th.z,
                               e_v.x, e_v.y, e_v.z, e_w.x,  e_w.y,  e_w.z};
    (void)memcpy(raw, v, sizeof v);
}

/* Step 2b: second-order low-pass (two first-order stages, critically damped) of the 12 error
 * components into tr->err_f; the first sample primes both stages. */
static void filter_errors(cdpr_tracker_t *tr, const cdpr_real_t raw[12], cdpr_real_t dt)
{
    const cdpr_real_t a =
        (tr->g.filter_s > CDPR_R(0.0)) ? CDPR_R(1.0) - CDPR_EXP(-dt / tr->g.filter_s) : CDPR_R(1.0);
    for (int i = 0; i < 12; ++i) {
        if (tr->filter_primed == 0) {
            tr->err_f1[i] = raw[i];
            tr->err_f[i] = raw[i];
        } else {
            tr->err_f1[i] += a * (raw[i] - tr->err_f1[i]);
            tr->err_f[i] += a * (tr->err_f1[i] - tr->err_f[i]);
        }
    }
    tr->filter_primed = 1;
}

/* Step 2d: the integral of the unfiltered pose error (raw[0..5]), each component of k_I I
 * clamped to ±integral_limit_m (a period with a clamp counted). Only with k_I > 0. */
static void integrate_errors(cdpr_tracker_t *tr, const cdpr_real_t raw[12], cdpr_real_t dt)
{
    const cdpr_real_t ki = tr->g.integral_per_s;
    if (ki > CDPR_R(0.0)) {
        const cdpr_real_t bound = tr->g.integral_limit_m / ki;
        int clamped = 0;
        for (int i = 0; i < 6; ++i) {
            cdpr_real_t v = tr->integ[i] + (raw[i] * dt);
            if (v > bound) {
                v = bound;
                clamped = 1;
            } else if (v < -bound) {
                v = -bound;
                clamped = 1;
            } else {
                /* within the bound */
            }
            tr->integ[i] = v;
        }
        if (clamped != 0) {
            tr->integral_saturations++;
        }
    }
}

/* Step 1c: the weight estimate from the winch tensions at t against the feed-forward's at t
 * (before this period's feed-forward, which then carries it). Only with τ_W > 0. */
static void estimate_weight(cdpr_tracker_t *tr, const cdpr_tracker_meas_t *m, cdpr_real_t dt)
{
    const cdpr_real_t tau = tr->g.weight_estimate_s;
    if (tau > CDPR_R(0.0)) {
        cdpr_real_t fz = CDPR_R(0.0);
        for (int j = 0; j < tr->model.p.n_cables; ++j) {
            cdpr_vec3_t u;
            cdpr_vec3_t gj;
            cdpr_tracker_jacobian(&tr->model, j, &m->cabin, &u, &gj);
            fz += (m->tension_winch_N[j] - tr->t_ff_N[j]) * u.z;
        }
        const cdpr_real_t r = fz / tr->model.p.g_m_per_s2;
        if (tr->filter_primed == 0) {
            tr->mass_res_f1 = r;
            tr->mass_res_f = r;
        } else {
            const cdpr_real_t a =
                CDPR_R(1.0) - CDPR_EXP(-(dt * CDPR_TRACKER_WEIGHT_FILTER_RATIO) / tau);
            tr->mass_res_f1 += a * (r - tr->mass_res_f1);
            tr->mass_res_f += a * (tr->mass_res_f1 - tr->mass_res_f);
        }
        const cdpr_real_t bound = CDPR_TRACKER_WEIGHT_LIMIT * tr->model.p.cabin.mass_kg;
        cdpr_real_t v = tr->mass_est_kg + ((dt / tau) * tr->mass_res_f);
        if (v > bound) {
            v = bound;
            tr->weight_saturations++;
        } else if (v < -bound) {
            v = -bound;
            tr->weight_saturations++;
        } else {
            /* within the bound */
        }
        tr->mass_est_kg = v;
    }
}

/* Step 3: wrench-space damping: the lengths that make the cables add c ė_p and c_r ė_θ at the
 * desired pose of t, relative to L_ff(t) (same pose and feed-forward load), into dl_w (zero
 * when off or when its IK fails). */
static void damping_step(cdpr_tracker_t *tr, cdpr_real_t t, cdpr_tracker_cmd_t *cmd,
                         cdpr_real_t *dl_w)
{
    const cdpr_real_t *f = tr->err_f;
    cmd->fb_status = CDPR_OK;
    if (!(tr->g.damping_N_s_per_m > CDPR_R(0.0) || tr->g.damping_rot_N_m_s > CDPR_R(0.0))) {
        return;
    }
    const cdpr_vec3_t f_add = cdpr_v3_scale(cdpr_v3(f[6], f[7], f[8]), tr->g.damping_N_s_per_m);
    const cdpr_vec3_t tau_add = cdpr_v3_scale(cdpr_v3(f[9], f[10], f[11]), tr->g.damping_rot_N_m_s);
    cdpr_real_t l_ref[CDPR_MAX_CABLES];
    cdpr_real_t l_w[CDPR_MAX_CABLES];
    (void)memcpy(l_ref, tr->l_ff_m, sizeof l_ref);
    cmd->fb_status = (tr->l_ff_exact != 0) ? CDPR_OK : feedforward(tr, t, l_ref, NULL);
    if (cmd->fb_status == CDPR_OK) {
        cmd->fb_status = ik_at(tr, t, f_add, tau_add, l_w, NULL);
    }
    if (cmd->fb_status == CDPR_OK) {
        for (int j = 0; j < tr->model.p.n_cables; ++j) {
            dl_w[j] = l_w[j] - l_ref[j];
        }
    } else {
        tr->fb_failures++;
    }
}

/* Steps 2c and 4: length corrections through the straight-cable Jacobian at the measured pose
 * and the payout-rate commands. */
static void rate_commands(const cdpr_tracker_t *tr, const cdpr_tracker_meas_t *m, cdpr_real_t dt,
                          const cdpr_real_t *l_next, const cdpr_real_t *dl_w,
                          cdpr_tracker_cmd_t *cmd)
{
    const cdpr_real_t *f = tr->err_f;
    for (int j = 0; j < tr->model.p.n_cables; ++j) {
        cdpr_vec3_t u;
        cdpr_vec3_t gj;
        cdpr_tracker_jacobian(&tr->model, j, &m->cabin, &u, &gj);
        const cdpr_real_t move =
            u.x * f[0] + u.y * f[1] + u.z * f[2] + gj.x * f[3] + gj.y * f[4] + gj.z * f[5];
        const cdpr_real_t move_rate =
            u.x * f[6] + u.y * f[7] + u.z * f[8] + gj.x * f[9] + gj.y * f[10] + gj.z * f[11];
        const cdpr_real_t *in = tr->integ;
        const cdpr_real_t move_int = ((u.x * in[0]) + (u.y * in[1]) + (u.z * in[2])) +
                                     ((gj.x * in[3]) + (gj.y * in[4]) + (gj.z * in[5]));
        const cdpr_real_t dl = dl_w[j] - ((tr->g.kp * move) + (tr->g.kd_s * move_rate) +
                                          (tr->g.integral_per_s * move_int));
        const cdpr_real_t u_ff = (l_next[j] - tr->l_ff_m[j]) / dt;
        cmd->l_ff_m[j] = tr->l_ff_m[j];
        cmd->u_ff_m_per_s[j] = u_ff;
        cmd->dl_m[j] = dl;
        cmd->rate_m_per_s[j] = u_ff + tr->g.k_length_per_s * (tr->l_ff_m[j] + dl - m->length_m[j]);
        const cdpr_tracker_correction_t *c = tr->g.correction;
        if (c != NULL) { /* step 4c */
            const cdpr_real_t c0 = cdpr_tracker_correction_at(c, j, m->t_s);
            const cdpr_real_t c1 = cdpr_tracker_correction_at(c, j, m->t_s + dt);
            cmd->corr_m[j] = c0;
            cmd->rate_m_per_s[j] += ((c1 - c0) / dt) + (tr->g.k_length_per_s * c0);
        }
        if (tr->g.tension_gain_m_per_s_per_N > CDPR_R(0.0)) {
            cmd->rate_m_per_s[j] +=
                tr->g.tension_gain_m_per_s_per_N * (tr->ten_f[j] - tr->ten_w[j]);
        }
    }
}

/* Step 4b: the tension errors T_j - T_ff,j(t) through one first-order stage into tr->ten_f
 * and, with the washout on, ten_f through another into tr->ten_w (both primed by the first
 * sample with the pose filter; ten_w 0 without the washout). Only with tension feedback on. */
static void filter_tensions(cdpr_tracker_t *tr, const cdpr_tracker_meas_t *m, cdpr_real_t dt)
{
    if (!(tr->g.tension_gain_m_per_s_per_N > CDPR_R(0.0))) {
        return;
    }
    const cdpr_real_t a = (tr->g.tension_filter_s > CDPR_R(0.0))
                              ? CDPR_R(1.0) - CDPR_EXP(-dt / tr->g.tension_filter_s)
                              : CDPR_R(1.0);
    const cdpr_real_t a_w = (tr->g.tension_washout_s > CDPR_R(0.0))
                                ? CDPR_R(1.0) - CDPR_EXP(-dt / tr->g.tension_washout_s)
                                : CDPR_R(0.0);
    for (int j = 0; j < tr->model.p.n_cables; ++j) {
        const cdpr_real_t e = m->tension_winch_N[j] - tr->t_ff_N[j];
        if (tr->filter_primed == 0) {
            tr->ten_f[j] = e;
            tr->ten_w[j] = e;
        } else {
            tr->ten_f[j] += a * (e - tr->ten_f[j]);
            tr->ten_w[j] += a_w * (tr->ten_f[j] - tr->ten_w[j]);
        }
        if (!(a_w > CDPR_R(0.0))) {
            tr->ten_w[j] = CDPR_R(0.0); /* no washout: w stays 0 */
        }
    }
}

/* Step 5: at the first step with transfer_s > 0, the transfer from this measurement; L_ff(t)
 * is then the IK of the measured pose (under the load of the reference's start). */
static void start_transfer(cdpr_tracker_t *tr, const cdpr_tracker_meas_t *m)
{
    if (!(tr->g.transfer_s > CDPR_R(0.0)) || tr->transfer_set != 0) {
        return;
    }
    cdpr_transfer_init(&tr->transfer, &tr->traj, m->t_s, tr->g.transfer_s, &m->cabin,
                       (tr->g.transfer_from_rest > CDPR_R(0.5)) ? 1 : 0);
    tr->transfer_set = 1;
    tr->t_next_s = m->t_s;
    if (feedforward(tr, m->t_s, tr->l_ff_m, tr->t_ff_N) != CDPR_OK) {
        tr->ik_failures++;
        tr->l_ff_exact = 0;
    } else {
        tr->l_ff_exact = 1;
    }
}

cdpr_status_t cdpr_tracker_step(cdpr_tracker_t *tr, const cdpr_tracker_meas_t *m,
                                cdpr_tracker_cmd_t *cmd)
{
    if (tr == NULL || m == NULL || cmd == NULL) {
        return CDPR_E_INVALID_ARG;
    }
    if (!meas_finite(tr, m)) {
        return CDPR_E_NOT_FINITE;
    }
    (void)memset(cmd, 0, sizeof *cmd);
    const cdpr_real_t dt = tr->period_s;
    const cdpr_real_t t = m->t_s;
    cdpr_real_t l_next[CDPR_MAX_CABLES];
    cdpr_real_t t_next[CDPR_MAX_CABLES];
    if (tr->steps == 0) {
        learn_first_step(tr, t);
    }
    start_transfer(tr, m);
    estimate_weight(tr, m, dt);
    feedforward_step(tr, t, dt, l_next, t_next, cmd);
    cdpr_real_t raw[12];
    pose_error(tr, m, t, cmd, raw);
    filter_tensions(tr, m, dt); /* before filter_errors: both prime on the same sample */
    filter_errors(tr, raw, dt);
    integrate_errors(tr, raw, dt);
    cdpr_real_t dl_w[CDPR_MAX_CABLES];
    for (int j = 0; j < CDPR_MAX_CABLES; ++j) {
        dl_w[j] = CDPR_R(0.0);
    }
    damping_step(tr, t, cmd, dl_w);
    learn_step(tr, m, t, raw, dl_w);
    rate_commands(tr, m, dt, l_next, dl_w, cmd);
    (void)memcpy(tr->l_ff_m, l_next, sizeof l_next);
    (void)memcpy(tr->t_ff_N, t_next, sizeof t_next);
    tr->l_ff_exact = (cmd->ik_status == CDPR_OK) ? 1 : 0;
    tr->t_next_s = t + dt;
    tr->steps++;
    return CDPR_OK;
}
