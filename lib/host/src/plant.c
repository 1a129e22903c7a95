/// @file plant.c
/// The plant of a scenario, one control period at a time (see plant.h).
#include "cdpr/host/plant.h"

#include <math.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

#include "cdpr/settle.h"

static double now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* Key that determines the initial pose, for error messages. */
static const char *initial_key(const cdpr_scenario_t *sc)
{
    if (sc->has_initial_pose != 0) {
        return "initial.pose";
    }
    for (int i = 0; i < 6; ++i) {
        if (fabs(sc->initial_offset[i]) > 0.0) {
            return "initial.offset";
        }
    }
    return (sc->traj.type == CDPR_TRAJ_CIRCLE)
               ? "trajectory.circle"
               : ((sc->traj.type == CDPR_TRAJ_LINE) ? "trajectory.line.from"
                                                    : "trajectory.hold.pose");
}

static void fill_atol(cdpr_plant_t *p)
{
    const cdpr_scenario_integrator_t *in = &p->integ;
    cdpr_robot_fill_atol(&p->robot, in->atol_position_m, in->atol_velocity_m_per_s,
                         in->atol_quaternion, in->atol_rate_rad_per_s, p->atol);
}

static int fail_model(const cdpr_scenario_t *sc, const char *key, const char *what,
                      const cdpr_diag_t *d, cdpr_scenario_error_t *err)
{
    char msg[512];
    if (d != NULL) {
        snprintf(msg, sizeof msg, "%s: field '%s': %s", what, d->field, cdpr_status_str(d->status));
    } else {
        snprintf(msg, sizeof msg, "%s", what);
    }
    cdpr_scenario_error(sc, key, msg, err);
    return 2;
}

/* Initial lengths from the IK of the initial pose. */
static int initial_ik(cdpr_plant_t *p, const cdpr_scenario_t *sc, cdpr_scenario_error_t *err)
{
    cdpr_diag_t d;
    memset(&d, 0, sizeof d);
    if (cdpr_preset_build(&sc->robot, NULL, &p->params, NULL, &d) != CDPR_OK ||
        cdpr_robot_init(&p->robot, &p->params, &d) != CDPR_OK) {
        return fail_model(sc, "robot", "rejected by the model", &d, err);
    }
    cdpr_statics_opts_t o;
    cdpr_statics_opts_default(&o);
    double pose[6];
    cdpr_scenario_initial_pose(sc, pose);
    const cdpr_cabin_motion_t m0 = cdpr_pose_to_motion(pose);
    const cdpr_status_t st = cdpr_statics_ik(&p->robot, &m0, &o, &p->initial);
    if (st != CDPR_OK) {
        const char *key = initial_key(sc);
        char what[512];
        snprintf(what, sizeof what,
                 "%s (%g, %g, %g m, %g, %g, %g rad) is not statically reachable "
                 "(no equilibrium with every cable pulling): %s",
                 (strncmp(key, "initial", 7) == 0) ? "initial pose"
                                                   : "start pose of the trajectory",
                 pose[0], pose[1], pose[2], pose[3], pose[4], pose[5], cdpr_status_str(st));
        cdpr_scenario_error(sc, key, what, err);
        return 2;
    }
    return 0;
}

int cdpr_plant_model(cdpr_plant_t *p, const cdpr_scenario_t *sc, cdpr_scenario_error_t *err)
{
    memset(p, 0, sizeof *p);
    const int rc = initial_ik(p, sc, err);
    if (rc != 0) {
        return rc;
    }
    double lengths[CDPR_MAX_CABLES];
    for (int j = 0; j < CDPR_ROBOT_CABLES; ++j) {
        lengths[j] = p->initial.cable[j].length_m;
    }
    cdpr_diag_t d;
    memset(&d, 0, sizeof d);
    if (cdpr_preset_build(&sc->robot, lengths, &p->params, &p->winch_params, &d) != CDPR_OK ||
        cdpr_robot_init(&p->robot, &p->params, &d) != CDPR_OK) {
        return fail_model(sc, "robot", "rejected by the model", &d, err);
    }
    return 0;
}

int cdpr_plant_init(cdpr_plant_t *p, const cdpr_scenario_t *sc, double period_s, int max_trials,
                    cdpr_scenario_error_t *err)
{
    if (!(period_s > 0.0) || period_s > 10.0) {
        memset(p, 0, sizeof *p);
        return fail_model(sc, "controller.period_s", "period must be in (0, 10] s", NULL, err);
    }
    const int rc = cdpr_plant_model(p, sc, err);
    if (rc != 0) {
        return rc;
    }
    p->period_s = period_s;
    p->max_trials = (max_trials > 0) ? max_trials : sc->integrator.max_trials;
    p->integ = sc->integrator;
    const cdpr_winch_params_t wp = p->winch_params;
    cdpr_diag_t d;
    memset(&d, 0, sizeof d);
    cdpr_status_t st = cdpr_statics_place_catenary(&p->robot, &p->initial, p->y);
    if (st != CDPR_OK) {
        char what[512];
        snprintf(what, sizeof what, "cannot place the cables: %s", cdpr_status_str(st));
        return fail_model(sc, initial_key(sc), what, NULL, err);
    }
    /* Settle with tight tolerances: the discrete equilibrium, to 1e-6 m/s^2. */
    cdpr_rkf45_params_t sp;
    cdpr_rkf45_params_default(&sp);
    sp.rtol = 1e-9;
    sp.atol = 1e-10;
    st = cdpr_rkf45_init(&p->rk, &sp, p->work, (int)(sizeof p->work / sizeof p->work[0]),
                         CDPR_ROBOT_STATE_MAX, p->robot.dim, &d);
    if (st != CDPR_OK) {
        return fail_model(sc, "integrator", "settling solver", &d, err);
    }
    cdpr_settle_t cfg;
    cdpr_settle_default(&cfg);
    const double t0 = now_s();
    st = cdpr_settle_robot(&p->robot, &p->rk, p->y, p->scratch, &cfg);
    p->settle_wall_time_s = now_s() - t0;
    p->settle_steps = cfg.steps;
    if (st != CDPR_OK) {
        char what[512];
        snprintf(what, sizeof what,
                 "the initial state did not settle to rest (%s after %ld steps, "
                 "residual %g m/s^2)",
                 cdpr_status_str(st), cfg.steps, cfg.max_acc_m_per_s2);
        return fail_model(sc, initial_key(sc), what, NULL, err);
    }
    for (int j = 0; j < CDPR_ROBOT_CABLES; ++j) {
        if (cdpr_winch_init(&p->winch[j], &wp, &d) != CDPR_OK) {
            return fail_model(sc, "robot.winch", "winch", &d, err);
        }
    }
    p->robot.in.wind_m_per_s =
        cdpr_v3(sc->robot.wind_m_per_s[0], sc->robot.wind_m_per_s[1], sc->robot.wind_m_per_s[2]);
    cdpr_rkf45_params_t ip;
    cdpr_rkf45_params_default(&ip);
    ip.rtol = sc->integrator.rtol;
    ip.h_max_s = sc->integrator.h_max_s;
    fill_atol(p);
    ip.atol_vec = p->atol;
    st = cdpr_rkf45_init(&p->rk, &ip, p->work, (int)(sizeof p->work / sizeof p->work[0]),
                         CDPR_ROBOT_STATE_MAX, p->robot.dim, &d);
    if (st != CDPR_OK) {
        return fail_model(sc, "integrator", "integrator", &d, err);
    }
    p->stats.last_failure = CDPR_OK;
    p->max_attempts = 1;
    return 0;
}

double cdpr_plant_time(const cdpr_plant_t *p)
{
    return (double)p->k * p->period_s;
}

void cdpr_plant_measure(const cdpr_plant_t *p, cdpr_tracker_meas_t *m)
{
    const cdpr_robot_t *r = &p->robot;
    m->t_s = cdpr_plant_time(p);
    cdpr_cabin_get_motion(p->y, &m->cabin);
    m->cabin.q = cdpr_quat_normalize(m->cabin.q);
    for (int j = 0; j < CDPR_MAX_CABLES; ++j) {
        m->length_m[j] =
            (j < r->p.n_cables) ? cdpr_cable_total_length(&r->cable[j], p->y + r->offset[j]) : 0.0;
    }
}

int cdpr_plant_command(cdpr_plant_t *p, cdpr_winch_mode_t mode, const double *value)
{
    cdpr_robot_t *r = &p->robot;
    const int nc = r->p.n_cables;
    int fl = 0;
    memcpy(p->winch_before, p->winch, sizeof p->winch_before);
    memcpy(p->payout_before, r->in.payout_m_per_s, sizeof p->payout_before);
    for (int j = 0; j < nc; ++j) {
        const double len = cdpr_cable_total_length(&r->cable[j], p->y + r->offset[j]);
        (void)cdpr_winch_command(&p->winch[j], mode, value[j]);
        if (cdpr_winch_update(&p->winch[j], len, p->period_s) == CDPR_WARN_MIN_LENGTH) {
            p->stats.min_length_periods++;
            fl |= CDPR_PLANT_MIN_LENGTH;
        }
        r->in.payout_m_per_s[j] = p->winch[j].u_m_per_s;
    }
    p->commanded = 1;
    return fl;
}

cdpr_status_t cdpr_plant_advance(cdpr_plant_t *p, int *flags)
{
    cdpr_robot_t *r = &p->robot;
    const double dt = p->period_s;
    const double t = cdpr_plant_time(p);
    int fl = *flags;
    if (p->commanded == 0) { /* keep the winches' rates: nothing to undo but the state */
        memcpy(p->winch_before, p->winch, sizeof p->winch_before);
        memcpy(p->payout_before, r->in.payout_m_per_s, sizeof p->payout_before);
    }
    p->commanded = 0;
    /* A refused budget (CDPR_E_SUBSTEP_LIMIT) leaves y and t as they were and keeps the
     * learned step size: another attempt over the same period usually passes. */
    cdpr_status_t as = CDPR_OK;
    for (int attempt = 0; attempt < p->max_attempts; ++attempt) {
        double tt = t;
        as = cdpr_rkf45_advance(&p->rk, cdpr_robot_rhs, r, &tt, p->y, dt, p->max_trials);
        if (as != CDPR_E_SUBSTEP_LIMIT) {
            break;
        }
        p->stats.budget_refusals++;
    }
    if (as < 0) {
        memcpy(p->winch, p->winch_before, sizeof p->winch_before);
        memcpy(r->in.payout_m_per_s, p->payout_before, sizeof p->payout_before);
        p->stats.step_failures++;
        p->stats.last_failure = as;
        *flags = CDPR_PLANT_STEP_FAILED;
        return as;
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
        (void)cdpr_rkf45_set_dim(&p->rk, r->dim);
        fill_atol(p);
    }
    *flags = fl;
    return ret;
}

cdpr_status_t cdpr_plant_step(cdpr_plant_t *p, cdpr_winch_mode_t mode, const double *value,
                              int *flags)
{
    *flags = cdpr_plant_command(p, mode, value);
    return cdpr_plant_advance(p, flags);
}
