/* SPDX-License-Identifier: BSD-3-Clause */
/// @file cdpr_py.c
/// The C side of the Python package `cdprlib` (docs/python.md): a handful of functions over the
/// host and core libraries with plain C types only (pointers to doubles and ints, a message
/// buffer), so that Python's ctypes can call them without mirroring any struct. Built as the
/// shared library libcdpr_py.so inside the package. One handle holds a scenario, its plant and
/// its controller (allocated once by cdpr_py_open); every other call works on it without
/// allocating. Not part of the installed C API: the Python package is its only user.
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cdpr/catenary.h"
#include "cdpr/host/correction.h"
#include "cdpr/host/plant.h"
#include "cdpr/host/rig.h"
#include "cdpr/host/scenario.h"
#include "cdpr/plant.h"
#include "cdpr/statics.h"
#include "cdpr/control/tracker.h"
#include "cdpr_py.h"

/* The package hands NumPy float64 arrays to these functions. */
typedef char cdpr_py_real_is_double[(sizeof(cdpr_real_t) == sizeof(double)) ? 1 : -1];

struct cdpr_py {
    cdpr_scenario_t sc;
    cdpr_plant_t plant;
    cdpr_tracker_t tracker;
    cdpr_host_correction_t corr; /* controller.precompensation (correction.h) */
};

/* msg[cap] = text (cut to fit). */
static void say(char *msg, size_t cap, const char *text)
{
    if (msg != NULL && cap > 0U) {
        snprintf(msg, cap, "%s", text);
    }
}

/* A failed open: *status = st, msg = text, the handle freed; NULL. */
static void *open_failed(void *h, cdpr_status_t st, const char *text, int *status, char *msg,
                         size_t cap)
{
    *status = (int)st;
    say(msg, cap, text);
    free(h);
    return NULL;
}

CDPR_PY_EXPORT const char *cdpr_py_status_name(int status)
{
    return cdpr_status_str((cdpr_status_t)status);
}

/* Load a scenario, build and settle its plant, and set up its controller (as cdpr-sim does).
 * NULL on failure with *status and msg ("FILE:LINE: KEY: what"). */
CDPR_PY_EXPORT cdpr_py_t *cdpr_py_open(const char *scenario, int *status, char *msg, size_t cap)
{
    cdpr_py_t *h = calloc(1, sizeof *h);
    if (h == NULL) {
        return open_failed(NULL, CDPR_E_IO, "out of memory", status, msg, cap);
    }
    cdpr_scenario_error_t err;
    err.msg[0] = '\0';
    cdpr_status_t st = cdpr_scenario_load(scenario, &h->sc, &err);
    if (st == CDPR_OK) {
        st = cdpr_host_plant_init(&h->plant, &h->sc, NULL, &err);
    }
    cdpr_robot_params_t model;
    if (st == CDPR_OK) {
        st = cdpr_host_controller_params(&h->sc, &model, &err);
    }
    if (st == CDPR_OK) {
        cdpr_tracker_gains_t g = h->sc.gains;
        g.wind_m_per_s = h->plant.pp.wind_m_per_s; /* the wind feed-forward's steady wind */
        cdpr_diag_t d;
        st = cdpr_correction_for_scenario(&h->sc, &h->corr, &g.correction, &err);
        if (st == CDPR_OK) {
            st = cdpr_tracker_init(&h->tracker, &model, &h->sc.traj, &g, h->sc.period_s, 0.0, &d);
            if (st != CDPR_OK) {
                snprintf(err.msg, sizeof err.msg, "%s: controller: field '%s': %s", scenario,
                         d.field, cdpr_status_str(st));
            }
        }
    }
    if (st != CDPR_OK) {
        return open_failed(h, st, err.msg, status, msg, cap);
    }
    *status = (int)CDPR_OK;
    return h;
}

CDPR_PY_EXPORT void cdpr_py_close(cdpr_py_t *h)
{
    free(h);
}

/* ints: n_cables, state dimension, periods of run.duration_s, periods stepped, capacity of
 * segments; reals: period_s, duration_s, time t_k. */
CDPR_PY_EXPORT void cdpr_py_info(const cdpr_py_t *h, long ints[5], double reals[3])
{
    ints[0] = h->plant.robot.p.n_cables;
    ints[1] = h->plant.robot.dim;
    ints[2] = cdpr_scenario_periods(&h->sc);
    ints[3] = h->plant.k;
    ints[4] = CDPR_MAX_SEGMENTS;
    reals[0] = h->sc.period_s;
    reals[1] = h->sc.duration_s;
    reals[2] = (double)cdpr_plant_time(&h->plant);
}

/* The scenario's initial pose (x, y, z [m], alpha, beta, gamma [rad]): the pose the plant was
 * built at by the inverse kinematics before it settled. */
CDPR_PY_EXPORT void cdpr_py_initial_pose(const cdpr_py_t *h, double pose[6])
{
    cdpr_scenario_initial_pose(&h->sc, pose);
}

/* The plant's state vector y (robot.h's layout; its length changes at node events): the
 * memory NumPy views without copying. */
CDPR_PY_EXPORT double *cdpr_py_state(cdpr_py_t *h, int *dim)
{
    *dim = h->plant.robot.dim;
    return h->plant.y;
}

/* The measurements at t_k into out: t, position (3), quaternion w x y z (4), velocity (3),
 * body rates (3), unstretched lengths (n), winch-end and cabin-end tensions (n each).
 * Returns the count written (14 + 3 n), or -1 when cap is too small. */
CDPR_PY_EXPORT int cdpr_py_measure(const cdpr_py_t *h, double *out, int cap)
{
    const int n = h->plant.robot.p.n_cables;
    if (cap < 14 + 3 * n) {
        return -1;
    }
    cdpr_plant_meas_t m;
    cdpr_robot_out_t o;
    cdpr_plant_measure_out(&h->plant, &m, &o);
    const cdpr_cabin_motion_t *c = &m.cabin;
    const double head[14] = {
        m.t_s,          c->p_m.x,         c->p_m.y,         c->p_m.z,        c->q.w,
        c->q.x,         c->q.y,           c->q.z,           c->v_m_per_s.x,  c->v_m_per_s.y,
        c->v_m_per_s.z, c->w_rad_per_s.x, c->w_rad_per_s.y, c->w_rad_per_s.z};
    memcpy(out, head, sizeof head);
    for (int j = 0; j < n; ++j) {
        out[14 + j] = m.length_m[j];
        out[14 + n + j] = m.tension_winch_N[j];
        out[14 + 2 * n + j] = o.tension_cabin_N[j];
    }
    return 14 + 3 * n;
}

/* Cable j's node positions (cdpr_host_cable_nodes): the count, or -1. */
CDPR_PY_EXPORT int cdpr_py_nodes(const cdpr_py_t *h, int j, double *xyz, int cap)
{
    return cdpr_host_cable_nodes(&h->plant, j, xyz, cap);
}

/* The scenario's controller on the current measurements: its payout-rate commands [m/s]
 * (n_cables values). CDPR_OK, or its error. */
CDPR_PY_EXPORT int cdpr_py_control(cdpr_py_t *h, double *rates)
{
    cdpr_plant_meas_t m;
    cdpr_plant_measure(&h->plant, &m);
    cdpr_tracker_cmd_t c;
    const cdpr_status_t st = cdpr_tracker_step(&h->tracker, &m, &c);
    if (st == CDPR_OK) {
        memcpy(rates, c.rate_m_per_s, sizeof(double) * (size_t)h->plant.robot.p.n_cables);
    }
    return (int)st;
}

/* One period with every winch in `mode` (0 rate [m/s], 1 length [m]): cdpr_plant_step. The
 * status (warnings >= 0 with the plant advanced; errors < 0 with the plant as before) and the
 * period's flags. */
CDPR_PY_EXPORT int cdpr_py_step(cdpr_py_t *h, int mode, const double *values, int *flags)
{
    *flags = 0;
    return (int)cdpr_plant_step(&h->plant, (mode == 1) ? CDPR_WINCH_LENGTH : CDPR_WINCH_RATE,
                                values, flags);
}

/* The plant's work so far: accepted steps, rejected steps, right-hand-side evaluations, step
 * failures, node insertions and removals (all cables). */
CDPR_PY_EXPORT void cdpr_py_work(const cdpr_py_t *h, long out[6])
{
    cdpr_plant_work_t w;
    cdpr_plant_work(&h->plant, &w);
    out[0] = (long)w.steps_accepted;
    out[1] = (long)w.steps_rejected;
    out[2] = (long)w.rhs_evals;
    out[3] = (long)h->plant.stats.step_failures;
    out[4] = 0;
    out[5] = 0;
    for (int j = 0; j < h->plant.robot.p.n_cables; ++j) {
        out[4] += (long)h->plant.nodes.insertions[j];
        out[5] += (long)h->plant.nodes.removals[j];
    }
}

/* Sag-aware inverse kinematics of the plant's robot at pose (x, y, z [m], alpha, beta, gamma
 * [rad]) under the cabin's weight: per cable the unstretched length, the cabin-end and
 * winch-end tensions and the horizontal tension. CDPR_OK, or the solver's error. */
CDPR_PY_EXPORT int cdpr_py_ik(const cdpr_py_t *h, const double pose[6], double *length_m,
                              double *tension_cabin_N, double *tension_winch_N, double *H_N)
{
    const cdpr_cabin_motion_t m = cdpr_cabin_motion_at_pose(pose);
    cdpr_statics_opts_t o;
    cdpr_statics_opts_default(&o);
    cdpr_statics_result_t r;
    const cdpr_status_t st = cdpr_statics_ik(&h->plant.robot, &m, &o, &r);
    if (st == CDPR_OK) {
        for (int j = 0; j < r.n_cables; ++j) {
            length_m[j] = r.cable[j].length_m;
            tension_cabin_N[j] = r.cable[j].tension_cabin_N;
            tension_winch_N[j] = r.cable[j].tension_winch_N;
            H_N[j] = r.cable[j].H_N;
        }
    }
    return (int)st;
}

/* The elastic catenary (Irvine): end forces H, V_A [N] of a cable of weight w [N/m] per
 * unstretched metre, axial stiffness EA [N] and unstretched length L0 [m] whose ends are l
 * horizontally and h vertically apart (cdpr_catenary_solve). */
CDPR_PY_EXPORT int cdpr_py_catenary_solve(double w_N_per_m, double ea_N, double l_m, double h_m,
                                          double L0_m, double *H_N, double *va_N)
{
    const cdpr_catenary_cable_t c = {w_N_per_m, ea_N};
    cdpr_catenary_solver_t s;
    cdpr_catenary_solver_default(&s);
    return (int)cdpr_catenary_solve(&c, l_m, h_m, L0_m, &s, H_N, va_N);
}

/* The point (x, z) at unstretched arclength s of that cable for end forces (H, V_A). */
CDPR_PY_EXPORT void cdpr_py_catenary_point(double w_N_per_m, double ea_N, double H_N, double va_N,
                                           double s_m, double *x_m, double *z_m)
{
    const cdpr_catenary_cable_t c = {w_N_per_m, ea_N};
    cdpr_catenary_point(&c, H_N, va_N, s_m, x_m, z_m);
}

/* ---- A robot file's statics (cdprlib.Robot) -------------------------------------------- */

struct cdpr_py_robot {
    cdpr_rig_t rig;
    cdpr_robot_t robot;
};

/* Load a robot file and build its core model (unstretched lengths: placeholders, the statics
 * does not use them). NULL on failure with *status and msg ("FILE:LINE: KEY: what"). */
CDPR_PY_EXPORT cdpr_py_robot_t *cdpr_py_robot_open(const char *path, int *status, char *msg,
                                                   size_t cap)
{
    cdpr_py_robot_t *h = calloc(1, sizeof *h);
    if (h == NULL) {
        return open_failed(NULL, CDPR_E_IO, "out of memory", status, msg, cap);
    }
    cdpr_rig_error_t err;
    err.msg[0] = '\0';
    cdpr_status_t st = cdpr_rig_load(path, &h->rig, &err);
    if (st == CDPR_OK) {
        cdpr_robot_params_t p;
        cdpr_diag_t d;
        st = cdpr_rig_build(&h->rig, NULL, &p, NULL, &d);
        if (st == CDPR_OK) {
            st = cdpr_robot_init(&h->robot, &p, &d);
        }
        if (st != CDPR_OK) {
            snprintf(err.msg, sizeof err.msg, "%s: rejected by the model: field '%s' (%d): %s",
                     path, d.field, d.index, cdpr_status_str(st));
        }
    }
    if (st != CDPR_OK) {
        return open_failed(h, st, err.msg, status, msg, cap);
    }
    *status = (int)CDPR_OK;
    return h;
}

CDPR_PY_EXPORT void cdpr_py_robot_close(cdpr_py_robot_t *h)
{
    free(h);
}

/* Cable count and the nominal pose of the robot file. */
CDPR_PY_EXPORT int cdpr_py_robot_info(const cdpr_py_robot_t *h, double nominal_pose[6])
{
    for (int i = 0; i < 6; ++i) {
        nominal_pose[i] = h->rig.nominal_pose[i];
    }
    return h->robot.p.n_cables;
}

/* cdpr_statics_ik_dist at pose under the weight and (f_ext, tau_ext) (world axes, at and about
 * the centre of mass); bounds[3] = (t_min, t_max, t_ref), or NULL for the robot file's own
 * tension_distribution (none: six cables only).
 * Per cable: length, cabin- and winch-end tensions, H, V at the cabin end. verdict[2] = (why,
 * cable), verdict_v[2] = (value, limit), *iterations. Returns the status. */
CDPR_PY_EXPORT int cdpr_py_robot_ik(const cdpr_py_robot_t *h, const double pose[6],
                                    const double f_ext[3], const double tau_ext[3],
                                    const double *bounds, double *length_m, double *tension_cabin_N,
                                    double *tension_winch_N, double *H_N, double *v_cabin_N,
                                    int verdict[2], double verdict_v[2], int *iterations)
{
    const cdpr_cabin_motion_t m = cdpr_cabin_motion_at_pose(pose);
    cdpr_statics_opts_t o;
    cdpr_statics_opts_default(&o);
    cdpr_statics_dist_t d;
    if (bounds != NULL) {
        d.t_min_N = bounds[0];
        d.t_max_N = bounds[1];
        d.t_ref_N = bounds[2];
    }
    cdpr_statics_result_t r;
    cdpr_statics_verdict_t why;
    const cdpr_status_t st = cdpr_statics_ik_dist(
        &h->robot, &m, cdpr_v3(f_ext[0], f_ext[1], f_ext[2]),
        cdpr_v3(tau_ext[0], tau_ext[1], tau_ext[2]), (bounds != NULL) ? &d : NULL, &o, &r, &why);
    verdict[0] = (int)why.why;
    verdict[1] = why.cable;
    verdict_v[0] = why.value;
    verdict_v[1] = why.limit;
    if (st == CDPR_OK) {
        for (int j = 0; j < r.n_cables; ++j) {
            length_m[j] = r.cable[j].length_m;
            tension_cabin_N[j] = r.cable[j].tension_cabin_N;
            tension_winch_N[j] = r.cable[j].tension_winch_N;
            H_N[j] = r.cable[j].H_N;
            v_cabin_N[j] = r.cable[j].v_cabin_N;
        }
        *iterations = r.iterations;
    }
    return (int)st;
}
