/* SPDX-License-Identifier: BSD-3-Clause */
/// @file plant.c
/// The plant, one control period at a time (plant.h).
#include "cdpr/plant.h"

#include <math.h>
#include <stddef.h>
#include <string.h>

#include "check.h"

const char *cdpr_plant_integrator_name(cdpr_plant_integrator_t integrator)
{
    const char *name = NULL;
    if (integrator == CDPR_PLANT_RKF45) {
        name = "rkf45";
    } else if (integrator == CDPR_PLANT_ROS34PW2) {
        name = "ros34pw2";
    } else if (integrator == CDPR_PLANT_ROS34PW2_FIXED) {
        name = "ros34pw2-fixed";
    } else {
        /* not a scheme of this library: no name */
    }
    return name;
}

void cdpr_plant_params_default(cdpr_plant_params_t *pp)
{
    cdpr_robot_params_default(&pp->robot);
    for (int j = 0; j < CDPR_MAX_CABLES; ++j) {
        cdpr_winch_params_default(&pp->winch[j]);
    }
    static const cdpr_real_t origin[6] = {CDPR_R(0.0), CDPR_R(0.0), CDPR_R(0.0),
                                          CDPR_R(0.0), CDPR_R(0.0), CDPR_R(0.0)};
    pp->initial = cdpr_cabin_motion_at_pose(origin);
    pp->wind_m_per_s = cdpr_v3(CDPR_R(0.0), CDPR_R(0.0), CDPR_R(0.0));
    cdpr_statics_opts_default(&pp->ik);
#ifdef CDPR_REAL_IS_FLOAT
    pp->start = CDPR_PLANT_START_CATENARY;
#else
    pp->start = CDPR_PLANT_START_SETTLED;
#endif
    cdpr_settle_default(&pp->settle);
    cdpr_rkf45_params_default(&pp->settle_rkf45);
    pp->settle_rkf45.step.rtol = CDPR_R(1e-9);
    pp->settle_rkf45.step.atol = CDPR_R(1e-10);
    pp->integrator = CDPR_PLANT_RKF45;
    cdpr_rkf45_params_default(&pp->rkf45);
    cdpr_ros_params_default(&pp->ros);
    pp->ros.jac_reuse_max = 4; /* one factorisation per 5 equal steps (docs/model.md §7) */
    pp->atol.position_m = CDPR_R(1e-6);
    pp->atol.velocity_m_per_s = CDPR_R(1e-5);
    pp->atol.quaternion = CDPR_R(1e-8);
    pp->atol.rate_rad_per_s = CDPR_R(1e-6);
    pp->period_s = CDPR_R(0.01);
    pp->max_trials = 50;
    pp->max_attempts = 1;
    pp->substeps = 0;
}

cdpr_status_t cdpr_plant_params_validate(const cdpr_plant_params_t *pp, cdpr_diag_t *diag)
{
    if (pp == NULL) {
        return cdpr_diag_set(diag, CDPR_E_INVALID_ARG, "params", -1);
    }
    if (pp->integrator != CDPR_PLANT_RKF45 && pp->integrator != CDPR_PLANT_ROS34PW2 &&
        pp->integrator != CDPR_PLANT_ROS34PW2_FIXED) {
        return cdpr_diag_set(diag, CDPR_E_INVALID_ARG, "integrator", -1);
    }
    if (pp->start != CDPR_PLANT_START_SETTLED && pp->start != CDPR_PLANT_START_CATENARY) {
        return cdpr_diag_set(diag, CDPR_E_INVALID_ARG, "start", -1);
    }
    if (pp->robot.mode != CDPR_CABIN_DYNAMIC) {
        return cdpr_diag_set(diag, CDPR_E_OUT_OF_RANGE, "robot.mode", -1);
    }
    CDPR_TRY(check_positive(pp->period_s, "period_s", -1, diag));
    if (pp->period_s > CDPR_R(10.0)) {
        return cdpr_diag_set(diag, CDPR_E_OUT_OF_RANGE, "period_s", -1);
    }
    if (pp->max_trials < 1) {
        return cdpr_diag_set(diag, CDPR_E_OUT_OF_RANGE, "max_trials", -1);
    }
    if (pp->max_attempts < 1 || pp->max_attempts > CDPR_PLANT_MAX_ATTEMPTS) {
        return cdpr_diag_set(diag, CDPR_E_OUT_OF_RANGE, "max_attempts", -1);
    }
    if (pp->substeps < 0 || pp->substeps > CDPR_PLANT_MAX_SUBSTEPS) {
        return cdpr_diag_set(diag, CDPR_E_OUT_OF_RANGE, "substeps", CDPR_PLANT_MAX_SUBSTEPS);
    }
    CDPR_TRY(check_finite_v3(pp->wind_m_per_s, "wind_m_per_s", -1, diag));
    const cdpr_cabin_motion_t *m = &pp->initial;
    CDPR_TRY(check_finite_v3(m->p_m, "initial.p_m", -1, diag));
    if (!(isfinite(m->q.w) && isfinite(m->q.x) && isfinite(m->q.y) && isfinite(m->q.z))) {
        return cdpr_diag_set(diag, CDPR_E_NOT_FINITE, "initial.q", -1);
    }
    CDPR_TRY(check_finite_v3(m->v_m_per_s, "initial.v_m_per_s", -1, diag));
    CDPR_TRY(check_finite_v3(m->w_rad_per_s, "initial.w_rad_per_s", -1, diag));
    if (cdpr_v3_norm(m->v_m_per_s) > CDPR_R(0.0) || cdpr_v3_norm(m->w_rad_per_s) > CDPR_R(0.0)) {
        return cdpr_diag_set(diag, CDPR_E_OUT_OF_RANGE, "initial.v_m_per_s", -1);
    }
    return cdpr_diag_set(diag, CDPR_OK, "", -1);
}

cdpr_status_t cdpr_plant_init_model(cdpr_plant_t *p, const cdpr_plant_params_t *pp,
                                    cdpr_diag_t *diag)
{
    if (p == NULL) {
        return cdpr_diag_set(diag, CDPR_E_INVALID_ARG, "plant", -1);
    }
    p->ready = 0;
    CDPR_TRY(cdpr_plant_params_validate(pp, diag));
    p->pp = *pp;
    p->pp.rkf45.step.atol_vec = NULL;
    p->pp.ros.step.atol_vec = NULL;
    p->params = pp->robot;
    CDPR_TRY(cdpr_robot_init(&p->robot, &p->params, diag));
    const cdpr_vec3_t zero = cdpr_v3(CDPR_R(0.0), CDPR_R(0.0), CDPR_R(0.0));
    const cdpr_status_t st =
        cdpr_statics_ik_dist(&p->robot, &pp->initial, zero, zero, NULL, &pp->ik, &p->initial, NULL);
    if (st != CDPR_OK) {
        return cdpr_diag_set(diag, st, "initial", -1);
    }
    for (int j = 0; j < p->params.n_cables; ++j) {
        p->params.cables[j].length_m = p->initial.cable[j].length_m;
    }
    return cdpr_robot_init(&p->robot, &p->params, diag);
}

cdpr_status_t cdpr_plant_fixed_substeps(const cdpr_robot_t *r, const cdpr_winch_params_t *w,
                                        cdpr_real_t period_s, int *n, cdpr_real_t *omega_max)
{
    if (r == NULL || w == NULL || n == NULL || !(period_s > CDPR_R(0.0))) {
        return CDPR_E_INVALID_ARG;
    }
    cdpr_real_t om = CDPR_R(0.0);
    for (int j = 0; j < r->p.n_cables; ++j) {
        const cdpr_cable_t *c = &r->cable[j];
        const cdpr_real_t delta = c->delta_m;
        const cdpr_real_t b_min = CDPR_R(0.5) * delta - w[j].u_max_m_per_s * period_s;
        if (!(b_min > CDPR_R(0.0))) {
            return CDPR_E_OUT_OF_RANGE;
        }
        const cdpr_real_t oj =
            CDPR_R(2.0) * CDPR_SQRT(c->p.ea_N / c->p.rho_kg_per_m) / CDPR_SQRT(delta * b_min);
        om = (oj > om) ? oj : om;
    }
    const cdpr_real_t x = period_s * om / (cdpr_real_t)CDPR_PLANT_FIXED_H_OMEGA;
    if (!(x <= (cdpr_real_t)CDPR_PLANT_MAX_SUBSTEPS)) {
        return CDPR_E_OUT_OF_RANGE;
    }
    int k = (int)x;
    k += ((cdpr_real_t)k < x) ? 1 : 0;
    *n = (k < 1) ? 1 : k;
    if (omega_max != NULL) {
        *omega_max = om;
    }
    return CDPR_OK;
}

/* Fixed mode: the substeps in force, derived, or the user's when not fewer. */
static cdpr_status_t choose_substeps(cdpr_plant_t *p, cdpr_diag_t *diag)
{
    p->substeps = 0;
    if (p->pp.integrator != CDPR_PLANT_ROS34PW2_FIXED) {
        return CDPR_OK;
    }
    int need = 0;
    const cdpr_status_t st =
        cdpr_plant_fixed_substeps(&p->robot, p->pp.winch, p->pp.period_s, &need, NULL);
    if (st != CDPR_OK) {
        return cdpr_diag_set(diag, st, "substeps", -1); /* no count holds */
    }
    if (p->pp.substeps != 0 && p->pp.substeps < need) {
        return cdpr_diag_set(diag, CDPR_E_OUT_OF_RANGE, "substeps", need);
    }
    p->substeps = (p->pp.substeps != 0) ? p->pp.substeps : need;
    return CDPR_OK;
}

/* Per-component absolute tolerances of the run for the current layout. */
static void fill_atol(cdpr_plant_t *p)
{
    const cdpr_plant_atol_t *a = &p->pp.atol;
    cdpr_robot_fill_atol(&p->robot, a->position_m, a->velocity_m_per_s, a->quaternion,
                         a->rate_rad_per_s, p->atol);
}

/* Step 2: nodes on the catenaries and, for a settled start, relaxed to rest. */
static cdpr_status_t place_and_settle(cdpr_plant_t *p, cdpr_diag_t *diag)
{
    cdpr_status_t st = cdpr_statics_place_catenary(&p->robot, &p->initial, p->y);
    if (st != CDPR_OK) {
        return cdpr_diag_set(diag, st, "initial", -1);
    }
    p->settle = p->pp.settle;
    p->settle.steps = 0;
    p->settle.resets = 0;
    p->settle.time_s = CDPR_R(0.0);
    p->settle.max_acc_m_per_s2 = CDPR_R(0.0);
    if (p->pp.start != CDPR_PLANT_START_SETTLED) {
        return CDPR_OK;
    }
    cdpr_diag_t d;
    st = cdpr_rkf45_init(&p->rk, &p->pp.settle_rkf45, p->work,
                         CDPR_PLANT_WORK_PER_DIM * CDPR_ROBOT_STATE_MAX, CDPR_ROBOT_STATE_MAX,
                         p->robot.dim, &d);
    if (st != CDPR_OK) {
        return cdpr_diag_set(diag, st, "settle_rkf45", -1);
    }
    st = cdpr_settle_robot(&p->robot, &p->rk, p->y, p->scratch, &p->settle);
    if (st != CDPR_OK) {
        return cdpr_diag_set(diag, st, "settle", -1);
    }
    return CDPR_OK;
}

/* Step 3: winches at rest, the run's inputs and integrator. */
static cdpr_status_t start_run(cdpr_plant_t *p, cdpr_diag_t *diag)
{
    for (int j = 0; j < p->params.n_cables; ++j) {
        CDPR_TRY(cdpr_winch_init(&p->winch[j], &p->pp.winch[j], diag));
    }
    p->robot.in.wind_m_per_s = p->pp.wind_m_per_s;
    fill_atol(p);
    const int work_len = CDPR_PLANT_WORK_PER_DIM * CDPR_ROBOT_STATE_MAX;
    const int dim_max = CDPR_ROBOT_STATE_MAX;
    cdpr_status_t st;
    const char *name = "rkf45";
    if (p->pp.integrator != CDPR_PLANT_RKF45) {
        cdpr_ros_params_t rp = p->pp.ros;
        rp.step.atol_vec = p->atol;
        (void)cdpr_robot_w_init(&p->w, &p->robot); /* cannot fail: both pointers are valid */
        st = cdpr_ros_init(&p->ros, &rp, p->work, work_len, dim_max, p->robot.dim, diag);
        name = "ros";
    } else {
        cdpr_rkf45_params_t ip = p->pp.rkf45;
        ip.step.atol_vec = p->atol;
        st = cdpr_rkf45_init(&p->rk, &ip, p->work, work_len, dim_max, p->robot.dim, diag);
    }
    if (st != CDPR_OK) {
        return cdpr_diag_set(diag, st, name, (diag != NULL) ? diag->index : -1);
    }
    return CDPR_OK;
}

cdpr_status_t cdpr_plant_init(cdpr_plant_t *p, const cdpr_plant_params_t *pp, cdpr_diag_t *diag)
{
    CDPR_TRY(cdpr_plant_init_model(p, pp, diag));
    CDPR_TRY(choose_substeps(p, diag));
    CDPR_TRY(place_and_settle(p, diag));
    CDPR_TRY(start_run(p, diag));
    /* The counters of a plant that has not stepped: all 0 (0.0 for the reals), last_failure
     * CDPR_OK. */
    (void)memset(&p->stats, 0, sizeof p->stats);
    p->stats.last_failure = CDPR_OK;
    (void)memset(&p->nodes, 0, sizeof p->nodes);
    p->k = 0;
    p->commanded = 0;
    p->ready = 1;
    return cdpr_diag_set(diag, CDPR_OK, "", -1);
}

void cdpr_plant_work(const cdpr_plant_t *p, cdpr_plant_work_t *w)
{
    w->integrator = p->pp.integrator;
    if (p->pp.integrator == CDPR_PLANT_RKF45) {
        w->steps_accepted = p->rk.stats.steps_accepted;
        w->steps_rejected = p->rk.stats.steps_rejected;
        w->nonfinite_rejected = p->rk.stats.nonfinite_rejected;
        w->rhs_evals = p->rk.stats.rhs_evals;
        w->factorisations = 0UL;
        w->solves = 0UL;
    } else {
        w->steps_accepted = p->ros.stats.steps_accepted;
        w->steps_rejected = p->ros.stats.steps_rejected;
        w->nonfinite_rejected = p->ros.stats.nonfinite_rejected;
        w->rhs_evals = p->ros.stats.rhs_evals;
        w->factorisations = p->ros.lin.factorisations;
        w->solves = p->ros.lin.solves;
    }
}

cdpr_real_t cdpr_plant_time(const cdpr_plant_t *p)
{
    return (cdpr_real_t)p->k * p->pp.period_s;
}

void cdpr_plant_measure(const cdpr_plant_t *p, cdpr_plant_meas_t *m)
{
    cdpr_robot_out_t out;
    cdpr_plant_measure_out(p, m, &out);
}

void cdpr_plant_measure_out(const cdpr_plant_t *p, cdpr_plant_meas_t *m, cdpr_robot_out_t *out)
{
    const cdpr_robot_t *r = &p->robot;
    m->t_s = cdpr_plant_time(p);
    cdpr_cabin_get_motion(p->y, &m->cabin);
    m->cabin.q = cdpr_quat_normalize(m->cabin.q);
    for (int j = 0; j < CDPR_MAX_CABLES; ++j) {
        m->length_m[j] = (j < r->p.n_cables)
                             ? cdpr_cable_total_length(&r->cable[j], p->y + r->offset[j])
                             : CDPR_R(0.0);
    }
    cdpr_robot_outputs(r, m->t_s, p->y, out);
    for (int j = 0; j < CDPR_MAX_CABLES; ++j) {
        m->tension_winch_N[j] = out->tension_winch_N[j]; /* 0 past n_cables */
    }
}

void cdpr_plant_outputs(const cdpr_plant_t *p, cdpr_robot_out_t *out)
{
    cdpr_robot_outputs(&p->robot, cdpr_plant_time(p), p->y, out);
}

/* What a failed period restores: the winches and payout rates before it. */
static void save_winches(cdpr_plant_t *p)
{
    for (int j = 0; j < CDPR_MAX_CABLES; ++j) {
        p->winch_before[j] = p->winch[j];
        p->payout_before[j] = p->robot.in.payout_m_per_s[j];
    }
}

static void restore_winches(cdpr_plant_t *p)
{
    for (int j = 0; j < CDPR_MAX_CABLES; ++j) {
        p->winch[j] = p->winch_before[j];
        p->robot.in.payout_m_per_s[j] = p->payout_before[j];
    }
}

int cdpr_plant_command(cdpr_plant_t *p, cdpr_winch_mode_t mode, const cdpr_real_t *value)
{
    if (p == NULL || value == NULL || p->ready == 0) {
        return 0;
    }
    cdpr_robot_t *r = &p->robot;
    int fl = 0;
    save_winches(p);
    for (int j = 0; j < r->p.n_cables; ++j) {
        const cdpr_real_t len = cdpr_cable_total_length(&r->cable[j], p->y + r->offset[j]);
        (void)cdpr_winch_command(&p->winch[j], mode, value[j]);
        if (cdpr_winch_update(&p->winch[j], len, p->pp.period_s) == CDPR_WARN_MIN_LENGTH) {
            p->stats.min_length_periods++;
            fl |= CDPR_PLANT_MIN_LENGTH;
        }
        r->in.payout_m_per_s[j] = p->winch[j].u_m_per_s;
    }
    p->commanded = 1;
    return fl;
}

/* The scheme's advance over exactly one period from t: up to max_attempts calls while the
 * budget is refused (CDPR_E_SUBSTEP_LIMIT keeps y, t and what the steps learned, so another
 * attempt over the same interval usually passes). */
static cdpr_status_t advance_once(cdpr_plant_t *p, cdpr_real_t t)
{
    cdpr_real_t tt = t;
    cdpr_ros_problem_t pb;
    pb.f = cdpr_robot_rhs;
    pb.f_ctx = &p->robot;
    pb.factor = cdpr_robot_w_factor;
    pb.solve = cdpr_robot_w_solve;
    pb.lin_ctx = &p->w;
    switch (p->pp.integrator) {
    case CDPR_PLANT_ROS34PW2:
        return cdpr_ros_advance(&p->ros, &pb, &tt, p->y, p->pp.period_s, p->pp.max_trials);
    case CDPR_PLANT_ROS34PW2_FIXED: {
        cdpr_real_t e = CDPR_R(0.0);
        const cdpr_status_t st =
            cdpr_ros_fixed(&p->ros, &pb, &tt, p->y, p->pp.period_s, p->substeps, &e);
        if (st == CDPR_OK) {
            cdpr_plant_stats_t *s = &p->stats;
            s->last_err_norm = e;
            s->max_err_norm = (e > s->max_err_norm) ? e : s->max_err_norm;
            s->err_above_one_periods += (e > CDPR_R(1.0)) ? 1U : 0U;
        }
        return st;
    }
    case CDPR_PLANT_RKF45:
    default:
        return cdpr_rkf45_advance(&p->rk, cdpr_robot_rhs, &p->robot, &tt, p->y, p->pp.period_s,
                                  p->pp.max_trials);
    }
}

/* Work counters of the run's integrator: RHS evaluations, factorisations, solves. */
static void work_counts(const cdpr_plant_t *p, unsigned long *rhs, unsigned long *fac,
                        unsigned long *sol)
{
    if (p->pp.integrator != CDPR_PLANT_RKF45) {
        *rhs = p->ros.stats.rhs_evals;
        *fac = p->ros.lin.factorisations;
        *sol = p->ros.lin.solves;
    } else {
        *rhs = p->rk.stats.rhs_evals;
        *fac = 0U;
        *sol = 0U;
    }
}

static unsigned long umax(unsigned long a, unsigned long b)
{
    return (a > b) ? a : b;
}

static cdpr_status_t integrate_period(cdpr_plant_t *p, cdpr_real_t t)
{
    unsigned long rhs0;
    unsigned long fac0;
    unsigned long sol0;
    work_counts(p, &rhs0, &fac0, &sol0);
    cdpr_status_t as = CDPR_E_INVALID_ARG;
    for (int attempt = 0; attempt < p->pp.max_attempts; ++attempt) {
        as = advance_once(p, t);
        if (as != CDPR_E_SUBSTEP_LIMIT) {
            break;
        }
        p->stats.budget_refusals++;
    }
    unsigned long rhs1;
    unsigned long fac1;
    unsigned long sol1;
    work_counts(p, &rhs1, &fac1, &sol1);
    cdpr_plant_stats_t *s = &p->stats;
    s->last_rhs_evals = rhs1 - rhs0;
    s->last_factorisations = fac1 - fac0;
    s->last_solves = sol1 - sol0;
    s->max_rhs_evals = umax(s->max_rhs_evals, s->last_rhs_evals);
    s->max_factorisations = umax(s->max_factorisations, s->last_factorisations);
    s->max_solves = umax(s->max_solves, s->last_solves);
    return as;
}

static cdpr_status_t fail_period(cdpr_plant_t *p, cdpr_status_t st, int *flags)
{
    p->stats.step_failures++;
    p->stats.last_failure = st;
    *flags = CDPR_PLANT_STEP_FAILED;
    return st;
}

cdpr_status_t cdpr_plant_advance(cdpr_plant_t *p, int *flags)
{
    if (p == NULL || flags == NULL) {
        return CDPR_E_INVALID_ARG;
    }
    if (p->ready == 0) {
        return fail_period(p, CDPR_E_INVALID_ARG, flags);
    }
    cdpr_robot_t *r = &p->robot;
    const cdpr_real_t dt = p->pp.period_s;
    const cdpr_real_t t = cdpr_plant_time(p);
    int fl = *flags;
    if (p->commanded == 0) { /* the winches keep their rates: nothing to undo but the state */
        save_winches(p);
    }
    p->commanded = 0;
    const cdpr_status_t as = integrate_period(p, t);
    if (as < CDPR_OK) {
        restore_winches(p);
        return fail_period(p, as, flags);
    }
    cdpr_status_t ret = ((fl & CDPR_PLANT_MIN_LENGTH) != 0) ? CDPR_WARN_MIN_LENGTH : CDPR_OK;
    if (as == CDPR_WARN_SUBSTEP_LIMIT) {
        p->stats.substep_limit_hits++;
        fl |= CDPR_PLANT_SUBSTEP_LIMIT;
        ret = as;
    }
    p->k++;
    p->stats.steps++;
    cdpr_robot_normalize(r, p->y);
    int changed = 0;
    const cdpr_status_t ns = cdpr_winch_node_events(r, t + dt, p->y, &p->nodes, &changed);
    if (ns == CDPR_WARN_CAPACITY) {
        p->stats.capacity_periods++;
        fl |= CDPR_PLANT_NODE_CAPACITY;
        ret = (ret == CDPR_OK) ? ns : ret;
    }
    if (changed != 0) {
        if (p->pp.integrator != CDPR_PLANT_RKF45) {
            (void)cdpr_ros_set_dim(&p->ros, r->dim);
        } else {
            (void)cdpr_rkf45_set_dim(&p->rk, r->dim);
        }
        fill_atol(p);
    }
    *flags = fl;
    return ret;
}

cdpr_status_t cdpr_plant_step(cdpr_plant_t *p, cdpr_winch_mode_t mode, const cdpr_real_t *value,
                              int *flags)
{
    if (flags == NULL) {
        return CDPR_E_INVALID_ARG;
    }
    *flags = cdpr_plant_command(p, mode, value);
    return cdpr_plant_advance(p, flags);
}
