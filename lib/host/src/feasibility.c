/* SPDX-License-Identifier: BSD-3-Clause */
/// @file feasibility.c
/// Is a scenario's trajectory feasible for its robot (feasibility.h): the sag-aware IK along the
/// path, the lengths within the winches' range, the slack cables of a start pose.
#include "cdpr/host/feasibility.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "cdpr/control/tracker.h"
#include "cdpr/statics.h"
#include "cdpr/winch.h"

/* Why the IK of the desired motion at t failed, into `what`: the cable whose straight-cable
 * tension is lowest, when it would have to push. */
static void infeasible_reason(const cdpr_robot_t *r, const cdpr_traj_sample_t *ds, double t,
                              cdpr_vec3_t f, cdpr_vec3_t tau, cdpr_status_t st, char *what,
                              size_t cap)
{
    double T[6];
    int worst = 0;
    const int solved =
        (cdpr_statics_straight_tensions(r, &ds->motion, f, tau, T) == CDPR_OK) ? 1 : 0;
    for (int j = 1; j < 6 && solved != 0; ++j) {
        worst = (T[j] < T[worst]) ? j : worst;
    }
    const int n =
        snprintf(what, cap,
                 "desired pose at t = %g s (%g, %g, %g m, %g, %g, %g rad) is not "
                 "reachable (no equilibrium with every cable pulling",
                 t, ds->pose[0], ds->pose[1], ds->pose[2], ds->pose[3], ds->pose[4], ds->pose[5]);
    if (n < 0 || (size_t)n >= cap) {
        return;
    }
    if (solved != 0 && T[worst] <= 0.0) {
        snprintf(what + n, cap - (size_t)n,
                 " under the weight and the feed-forward's inertial load): cable %d would need "
                 "a tension of %.4g N (pushing; straight-cable estimate): %s",
                 worst + 1, T[worst], cdpr_status_str(st));
    } else {
        snprintf(what + n, cap - (size_t)n, "): %s", cdpr_status_str(st));
    }
}

/* The cables a load leaves (nearly) slack, from their straight-cable tensions T: at most 1 % of
 * the cabin's weight. Writes "2 (1.18 N), 3 (1.18 N)" into `list`; returns how many. */
static int slack_cables(const cdpr_robot_t *r, const double T[6], char *list, size_t cap)
{
    const double small = 0.01 * r->p.cabin.mass_kg * r->p.g_m_per_s2;
    int k = 0;
    size_t used = 0;
    list[0] = '\0';
    for (int j = 0; j < 6; ++j) {
        if (T[j] <= small && used < cap) {
            const int n = snprintf(list + used, cap - used, "%s%d (%.3g N)", (k > 0) ? ", " : "",
                                   j + 1, T[j]);
            used += (n > 0) ? (size_t)n : 0U;
            ++k;
        }
    }
    return k;
}

/* Why cable j (0-based) comes out L long for a chord `chord` at t, into `what`: a loop (more
 * than CDPR_STATICS_MAX_LENGTH_PER_CHORD chords, the IK's verdict) or beyond the longest
 * length command; with the straight-cable tensions of the load (the weight plus the
 * feed-forward's inertial load): the cables it leaves slack, or the long cable's own. */
static void long_cable(const cdpr_robot_t *model, const cdpr_traj_sample_t *ds, cdpr_vec3_t f,
                       cdpr_vec3_t tau, double t, int j, double L, double chord, int in_loop,
                       double min_length_m, char *what, size_t cap)
{
    double T[6];
    const int solved = (model->p.n_cables == 6 &&
                        cdpr_statics_straight_tensions(model, &ds->motion, f, tau, T) == CDPR_OK)
                           ? 1
                           : 0;
    char slack[256];
    if (solved != 0 && slack_cables(model, T, slack, sizeof slack) > 0) {
        snprintf(what, cap,
                 "desired pose at t = %g s (%g, %g, %g m, %g, %g, %g rad): the weight and "
                 "the feed-forward's inertial load leave cables %s slack (straight-cable "
                 "tensions; at most 1 %% of the cabin's weight): the equilibrium has cable %d "
                 "%.6g m long for a chord of %.6g m",
                 t, ds->pose[0], ds->pose[1], ds->pose[2], ds->pose[3], ds->pose[4], ds->pose[5],
                 slack, j + 1, L, chord);
    } else if (in_loop != 0 && L <= CDPR_FEASIBILITY_MAX_LENGTH_M) {
        const int n = snprintf(what, cap,
                               "desired pose at t = %g s: cable %d would hang in a loop, "
                               "%.6g m long for a chord of %.6g m (more than %g chords: no "
                               "length to command)",
                               t, j + 1, L, chord, CDPR_STATICS_MAX_LENGTH_PER_CHORD);
        if (solved != 0 && n > 0 && (size_t)n < cap) {
            snprintf(what + n, cap - (size_t)n,
                     "; its straight-cable tension under the weight and the feed-forward's "
                     "inertial load is %.3g N, the cabin's weight %.3g N",
                     T[j], model->p.cabin.mass_kg * model->p.g_m_per_s2);
        }
    } else {
        snprintf(what, cap,
                 "cable %d would be %.6g m long at t = %g s: outside [%g, %g] m (the winch's "
                 "min_length_m, the longest length command)",
                 j + 1, L, t, min_length_m, CDPR_FEASIBILITY_MAX_LENGTH_M);
    }
}

/* Unstretched lengths of an IK result within the winch and length-command limits. */
static cdpr_status_t check_lengths(const cdpr_scenario_t *sc, const cdpr_robot_t *model,
                                   const cdpr_traj_sample_t *ds, cdpr_vec3_t f, cdpr_vec3_t tau,
                                   const cdpr_statics_result_t *res, const cdpr_winch_params_t *w,
                                   double t, cdpr_scenario_error_t *err)
{
    for (int j = 0; j < res->n_cables; ++j) {
        const double L = res->cable[j].length_m;
        const double chord = cdpr_v3_norm(
            cdpr_v3_sub(model->p.cables[j].exit_point_m, res->cable[j].attach_world_m));
        const int too_long = (L > CDPR_FEASIBILITY_MAX_LENGTH_M) ? 1 : 0;
        if (too_long == 0 && L >= w[j].min_length_m) {
            continue;
        }
        char what[768];
        if (too_long != 0) {
            long_cable(model, ds, f, tau, t, j, L, chord, 0, w[j].min_length_m, what, sizeof what);
        } else {
            snprintf(what, sizeof what,
                     "cable %d would be %.6g m long at t = %g s: outside [%g, %g] m (the "
                     "winch's min_length_m, the longest length command)",
                     j + 1, L, t, w[j].min_length_m, CDPR_FEASIBILITY_MAX_LENGTH_M);
        }
        cdpr_scenario_error(sc, cdpr_scenario_trajectory_key(sc), what, err);
        return CDPR_E_OUT_OF_RANGE;
    }
    return CDPR_OK;
}

cdpr_status_t cdpr_feasibility_check_trajectory(const cdpr_scenario_t *sc, double duration,
                                                cdpr_robot_t *model, cdpr_scenario_error_t *err)
{
    cdpr_robot_params_t mp;
    cdpr_winch_params_t w[CDPR_MAX_CABLES];
    cdpr_diag_t d;
    if (cdpr_scenario_build_robot(sc, NULL, &mp, w, &d) != CDPR_OK ||
        cdpr_robot_init(model, &mp, &d) != CDPR_OK) {
        char what[512];
        snprintf(what, sizeof what, "rejected by the model: field '%s': %s", d.field,
                 cdpr_status_str(d.status));
        cdpr_scenario_error(sc, "robot", what, err);
        return d.status;
    }
    cdpr_statics_opts_t o;
    cdpr_statics_opts_default(&o);
    const long n = cdpr_scenario_count(ceil(duration / 0.1));
    for (long k = 0; k <= n; ++k) {
        const double t = (k < n) ? 0.1 * (double)k : duration + sc->period_s;
        cdpr_traj_sample_t ds;
        cdpr_traj_eval(&sc->traj, t, &ds);
        cdpr_vec3_t f = cdpr_v3(0.0, 0.0, 0.0);
        cdpr_vec3_t tau = f;
        if (sc->gains.inertial_ff > 0.0) {
            cdpr_tracker_inertial_wrench(model, &ds, &f, &tau);
            f = cdpr_v3_scale(f, sc->gains.inertial_ff);
            tau = cdpr_v3_scale(tau, sc->gains.inertial_ff);
        }
        cdpr_statics_result_t res;
        cdpr_statics_verdict_t why;
        const cdpr_status_t st =
            cdpr_statics_ik_dist(model, &ds.motion, f, tau, NULL, &o, &res, &why);
        if (st == CDPR_E_INFEASIBLE && why.why == CDPR_STATICS_WHY_LOOP) {
            /* The only equilibrium has a cable hanging in a loop. At the start the
             * controller's first feed-forward refuses it; later it counts a failed
             * feed-forward and holds its last one (docs/scenarios.md). */
            if (k > 0) {
                continue;
            }
            const int j = why.cable;
            cdpr_mat3_t R;
            cdpr_quat_to_mat3(cdpr_quat_normalize(ds.motion.q), &R);
            const cdpr_vec3_t P =
                cdpr_v3_add(ds.motion.p_m, cdpr_m3_mul_v3(&R, model->p.cables[j].attach_body_m));
            const double chord = cdpr_v3_norm(cdpr_v3_sub(model->p.cables[j].exit_point_m, P));
            char what[768];
            long_cable(model, &ds, f, tau, t, j, why.value * chord, chord, 1, w[j].min_length_m,
                       what, sizeof what);
            cdpr_scenario_error(sc, cdpr_scenario_trajectory_key(sc), what, err);
            return CDPR_E_OUT_OF_RANGE;
        }
        if (st != CDPR_OK) {
            char what[768];
            infeasible_reason(model, &ds, t, f, tau, st, what, sizeof what);
            cdpr_scenario_error(sc, cdpr_scenario_trajectory_key(sc), what, err);
            return st;
        }
        const cdpr_status_t ls = check_lengths(sc, model, &ds, f, tau, &res, w, t, err);
        if (ls != CDPR_OK) {
            return ls;
        }
    }
    return CDPR_OK;
}
