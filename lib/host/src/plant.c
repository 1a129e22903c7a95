/* SPDX-License-Identifier: BSD-3-Clause */
/// @file plant.c
/// The core plant built from a scenario (cdpr/host/plant.h).
#include "cdpr/host/plant.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cdpr/host/clock.h"

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
    static const char *const keys[] = {"trajectory.hold.pose", "trajectory.circle",
                                       "trajectory.line.from", "trajectory.cyclic.from"};
    return keys[(sc->traj.type <= CDPR_TRAJ_CYCLIC) ? sc->traj.type : CDPR_TRAJ_HOLD];
}

static cdpr_status_t fail(const cdpr_scenario_t *sc, const char *key, const char *what,
                          const cdpr_diag_t *d, cdpr_scenario_error_t *err)
{
    char msg[512];
    if (d != NULL) {
        snprintf(msg, sizeof msg, "%s: field '%s': %s", what, d->field, cdpr_status_str(d->status));
    } else {
        snprintf(msg, sizeof msg, "%s", what);
    }
    cdpr_scenario_error(sc, key, msg, err);
    return (d != NULL && d->status != CDPR_OK) ? d->status : CDPR_E_INVALID_ARG;
}

cdpr_status_t cdpr_host_plant_params(const cdpr_scenario_t *sc, cdpr_plant_params_t *pp,
                                     cdpr_scenario_error_t *err)
{
    cdpr_plant_params_default(pp);
    cdpr_diag_t d;
    memset(&d, 0, sizeof d);
    const cdpr_rig_t *rig = &sc->rig;
    if (cdpr_rig_build(rig, NULL, &pp->robot, pp->winch, &d) != CDPR_OK) {
        return fail(sc, "robot", "rejected by the model", &d, err);
    }
    if (rig->n_cables < CDPR_RIG_IK_CABLES) {
        char what[256];
        snprintf(what, sizeof what,
                 "%d cables: the plant starts from the sag-aware inverse kinematics of the "
                 "initial pose (cdpr_statics_ik_dist), which needs at least %d",
                 rig->n_cables, CDPR_RIG_IK_CABLES);
        cdpr_scenario_error(sc, "robot", what, err);
        return CDPR_E_CAPACITY;
    }
    if (rig->n_cables > CDPR_RIG_IK_CABLES && rig->has_tension_distribution == 0) {
        char what[256];
        snprintf(what, sizeof what,
                 "%d cables: a redundant robot's initial pose needs its tension distribution "
                 "(tension_distribution: min_N, max_N; docs/robots.md)",
                 rig->n_cables);
        cdpr_scenario_error(sc, "robot", what, err);
        return CDPR_E_PARSE;
    }
    double pose[6];
    cdpr_scenario_initial_pose(sc, pose);
    pp->initial = cdpr_cabin_motion_at_pose(pose);
    pp->wind_m_per_s = cdpr_v3(rig->wind_m_per_s[0], rig->wind_m_per_s[1], rig->wind_m_per_s[2]);
    const cdpr_scenario_integrator_t *in = &sc->integrator;
    pp->rkf45.step.rtol = in->rtol;
    pp->rkf45.step.h_max_s = in->h_max_s;
    pp->integrator = in->method;
    pp->ros.step.rtol = in->rtol;
    pp->ros.step.h_max_s = in->h_max_s;
    pp->atol.position_m = in->atol_position_m;
    pp->atol.velocity_m_per_s = in->atol_velocity_m_per_s;
    pp->atol.quaternion = in->atol_quaternion;
    pp->atol.rate_rad_per_s = in->atol_rate_rad_per_s;
    pp->period_s = sc->period_s;
    pp->max_trials = in->max_trials;
    pp->max_attempts = in->max_attempts;
    pp->substeps = in->substeps;
    return CDPR_OK;
}

/* The cable whose stiffest axial mode is highest: largest EA / (rho Delta^2), Delta = length /
 * segments (the lengths the model was given; EA / rho alone where a length is not set). */
static int stiffest_cable(const cdpr_robot_params_t *r)
{
    int best = 0;
    double best_k = -1.0;
    for (int j = 0; j < r->n_cables; ++j) {
        const cdpr_robot_cable_params_t *c = &r->cables[j];
        const double delta =
            (c->length_m > 0.0 && c->n_segments > 0) ? (double)c->length_m / c->n_segments : 1.0;
        const double k = (double)c->cable.ea_N / ((double)c->cable.rho_kg_per_m * delta * delta);
        if (k > best_k) {
            best_k = k;
            best = j;
        }
    }
    return best;
}

/* The error of a failed cdpr_plant_init_model / cdpr_plant_init, named by scenario key. */
static cdpr_status_t init_error(const cdpr_plant_t *p, const cdpr_scenario_t *sc,
                                const cdpr_diag_t *d, cdpr_scenario_error_t *err)
{
    char what[512];
    const char *f = d->field;
    if (strcmp(f, "initial") == 0) {
        double pose[6];
        cdpr_scenario_initial_pose(sc, pose);
        const char *key = initial_key(sc);
        snprintf(what, sizeof what,
                 "%s (%g, %g, %g m, %g, %g, %g rad) is not statically reachable "
                 "(no equilibrium with every cable pulling): %s",
                 (strncmp(key, "initial", 7) == 0) ? "initial pose"
                                                   : "start pose of the trajectory",
                 pose[0], pose[1], pose[2], pose[3], pose[4], pose[5], cdpr_status_str(d->status));
        cdpr_scenario_error(sc, key, what, err);
        return d->status;
    }
    if (strcmp(f, "settle") == 0) {
        if (d->status == CDPR_E_NO_CONVERGENCE) {
            /* The stiffest axial mode sets how slowly the chain settles (more damping does
             * not help it: a stiffer damper settles such a rope no faster). */
            const int j = stiffest_cable(&p->pp.robot);
            const cdpr_robot_cable_params_t *c = &p->pp.robot.cables[j];
            char advice[256];
            if (sc->robot_source == CDPR_ROBOT_FROM_PRESET) {
                snprintf(advice, sizeof advice,
                         "lower robot.rope.ea_N (%g N) or robot.segments (%d)",
                         (double)c->cable.ea_N, c->n_segments);
            } else {
                snprintf(advice, sizeof advice,
                         "lower cable %d's rope.ea_N (%g N) or its segments (%d) in %.160s", j + 1,
                         (double)c->cable.ea_N, c->n_segments, sc->rig.name);
            }
            snprintf(what, sizeof what,
                     "the initial state did not settle to rest: gave up after %ld steps (the "
                     "bound; residual %g m/s^2 > %g): the stiffest axial mode settles slowly: %s",
                     p->settle.steps, p->settle.max_acc_m_per_s2, p->pp.settle.acc_tol_m_per_s2,
                     advice);
            cdpr_scenario_error(sc, "robot", what, err);
            return CDPR_E_NO_CONVERGENCE;
        }
        snprintf(what, sizeof what,
                 "the initial state did not settle to rest (%s after %ld steps, "
                 "residual %g m/s^2)",
                 cdpr_status_str(d->status), p->settle.steps, p->settle.max_acc_m_per_s2);
        cdpr_scenario_error(sc, initial_key(sc), what, err);
        /* The scenario cannot start, whatever stopped the settling (the message says which). */
        return CDPR_E_NO_CONVERGENCE;
    }
    if (strcmp(f, "period_s") == 0) {
        return fail(sc, "run.period_s", "period must be in (0, 10] s", d, err);
    }
    if (strcmp(f, "substeps") == 0) {
        if (d->status == CDPR_E_OUT_OF_RANGE && sc->integrator.substeps > 0 &&
            sc->integrator.substeps < d->index) {
            snprintf(what, sizeof what,
                     "%d substeps per period are fewer than this model needs: at least %d at "
                     "period %g s (its stiffest axial mode; omit the key for the derived count)",
                     sc->integrator.substeps, d->index, sc->period_s);
        } else {
            snprintf(what, sizeof what,
                     "the fixed mode cannot hold this model at period %g s: it would need more "
                     "than %d substeps, or a winch hauls a whole half-segment in within one "
                     "period: shorten run.period_s, use fewer robot segments or "
                     "integrator.method ros34pw2",
                     sc->period_s, CDPR_PLANT_MAX_SUBSTEPS);
        }
        cdpr_scenario_error(sc, "integrator.substeps", what, err);
        return CDPR_E_OUT_OF_RANGE;
    }
    if (strcmp(f, "max_trials") == 0 || strcmp(f, "max_attempts") == 0) {
        return fail(sc, (f[4] == 't') ? "integrator.max_trials" : "integrator.max_attempts",
                    "work bound", d, err);
    }
    if (strcmp(f, "rkf45") == 0 || strcmp(f, "ros") == 0 || strcmp(f, "settle_rkf45") == 0 ||
        strcmp(f, "atol") == 0) {
        return fail(sc, "integrator", "integrator", d, err);
    }
    if (strncmp(f, "u_max", 5) == 0 || strncmp(f, "a_max", 5) == 0 || strncmp(f, "kp", 2) == 0 ||
        strncmp(f, "min_length", 10) == 0) {
        return fail(sc, "robot.winch", "winch", d, err);
    }
    return fail(sc, "robot", "rejected by the model", d, err);
}

/* What provably cannot settle, refused before any settling step: a cable with no axial damping
 * (c = 0 and no damping ratio). The kinetic-damping resets alone leave its modes ringing: the
 * deploy-retrieve scenario with robot.rope.damping_Ns: 0 still had 1.8e-4 m/s^2 of residual
 * acceleration after the 2e6 steps of the core's default bound (issue 10, L8). */
static cdpr_status_t check_settleable(const cdpr_plant_params_t *pp, const cdpr_scenario_t *sc,
                                      cdpr_scenario_error_t *err)
{
    const int preset = (sc->robot_source == CDPR_ROBOT_FROM_PRESET) ? 1 : 0;
    for (int j = 0; j < pp->robot.n_cables; ++j) {
        const cdpr_cable_params_t *c = &pp->robot.cables[j].cable;
        if (!(c->damping_Ns > 0.0) && !(c->damping_ratio > 0.0)) {
            char what[512];
            snprintf(what, sizeof what,
                     "cable %d undamped (damping 0): the settle cannot converge; set %s", j + 1,
                     (preset != 0) ? "robot.rope.damping_ratio (or damping_Ns)"
                                   : "rope.damping_ratio (or damping_Ns) of that cable");
            cdpr_scenario_error(sc, (preset != 0) ? "robot.rope" : "robot", what, err);
            return CDPR_E_NO_CONVERGENCE;
        }
    }
    return CDPR_OK;
}

/* Build the model only (full = 0: cdpr_plant_init_model) or the whole plant (cdpr_plant_init),
 * timing it into *wall_s when asked. */
static cdpr_status_t build(cdpr_plant_t *p, const cdpr_scenario_t *sc, int full, double *wall_s,
                           cdpr_scenario_error_t *err)
{
    cdpr_plant_params_t pp;
    memset(p, 0, sizeof *p);
    const cdpr_status_t st = cdpr_host_plant_params(sc, &pp, err);
    if (st != CDPR_OK) {
        return st;
    }
    if (full != 0 && pp.start == CDPR_PLANT_START_SETTLED) {
        const cdpr_status_t ss = check_settleable(&pp, sc, err);
        if (ss != CDPR_OK) {
            return ss;
        }
        pp.settle.max_steps = CDPR_HOST_SETTLE_MAX_STEPS;
    }
    cdpr_diag_t d;
    memset(&d, 0, sizeof d);
    const double t0 = cdpr_clock_now_s();
    const cdpr_status_t is =
        (full != 0) ? cdpr_plant_init(p, &pp, &d) : cdpr_plant_init_model(p, &pp, &d);
    if (wall_s != NULL) {
        *wall_s = cdpr_clock_now_s() - t0;
    }
    return (is != CDPR_OK) ? init_error(p, sc, &d, err) : CDPR_OK;
}

cdpr_status_t cdpr_host_plant_model(cdpr_plant_t *p, const cdpr_scenario_t *sc,
                                    cdpr_scenario_error_t *err)
{
    return build(p, sc, 0, NULL, err);
}

cdpr_status_t cdpr_host_controller_params(const cdpr_scenario_t *sc, cdpr_robot_params_t *model,
                                          cdpr_scenario_error_t *err)
{
    cdpr_scenario_t *scaled = malloc(sizeof *scaled);
    cdpr_plant_t *p = malloc(sizeof *p);
    cdpr_status_t st = CDPR_E_CAPACITY;
    if (scaled == NULL || p == NULL) {
        cdpr_scenario_error(sc, "controller.model", "out of memory for the controller's model",
                            err);
    } else {
        *scaled = *sc;
        cdpr_rig_scale(&scaled->rig, &sc->controller_model);
        st = build(p, scaled, 0, NULL, err);
        if (st == CDPR_OK) {
            *model = p->params;
        }
    }
    free(p);
    free(scaled);
    return st;
}

cdpr_status_t cdpr_host_plant_init(cdpr_plant_t *p, const cdpr_scenario_t *sc, double *wall_s,
                                   cdpr_scenario_error_t *err)
{
    return build(p, sc, 1, wall_s, err);
}

int cdpr_host_cable_nodes(const cdpr_plant_t *p, int j, double *xyz, int cap)
{
    const cdpr_robot_t *r = &p->robot;
    if (j < 0 || j >= r->p.n_cables || cap < r->cable[j].n + 1) {
        return -1;
    }
    const int n = r->cable[j].n;
    cdpr_cabin_motion_t m;
    cdpr_robot_cabin_motion(r, cdpr_plant_time(p), p->y, &m);
    for (int k = 0; k <= n; ++k) {
        cdpr_vec3_t q = r->p.cables[j].exit_point_m;
        if (k == 0) {
            cdpr_vec3_t v;
            cdpr_robot_attachment(r, j, &m, &q, &v);
        } else if (k < n) { /* free node k: the cable block's positions after its lu */
            const int i = r->offset[j] + 1 + 3 * (k - 1);
            q = cdpr_v3(p->y[i], p->y[i + 1], p->y[i + 2]);
        } else {
            /* the exit point */
        }
        xyz[3 * k] = (double)q.x;
        xyz[3 * k + 1] = (double)q.y;
        xyz[3 * k + 2] = (double)q.z;
    }
    return n + 1;
}
