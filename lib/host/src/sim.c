/* SPDX-License-Identifier: BSD-3-Clause */
/// @file sim.c
/// Batch closed-loop run of a scenario (see sim.h).
#include "cdpr/host/sim.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cdpr/host/clock.h"
#include "cdpr/host/correction.h"
#include "cdpr/host/feasibility.h"
#include "cdpr/host/fs.h"
#include "cdpr/host/plant.h"
#include "cdpr/winch.h"

/* Everything a run needs, allocated once (about 250 kB at the default capacities). */
typedef struct {
    cdpr_plant_t plant;
    cdpr_robot_t model; /* statics-only model for the feasibility checks */
    cdpr_tracker_t tracker;
    cdpr_record_t rec;
    cdpr_csv_t shapes; /* DIR/shapes.csv (opts.shapes_rate_hz > 0) */
    int shapes_open;
    long shapes_every;                            /* periods between snapshots */
    double node_xyz[3 * (CDPR_MAX_SEGMENTS + 1)]; /* one cable's nodes (write_shapes) */
    cdpr_host_correction_t corr; /* controller.precompensation's file (correction.h) */
} sim_t;

void cdpr_sim_opts_default(cdpr_sim_opts_t *o)
{
    memset(o, 0, sizeof *o);
    o->progress_after_s = 2.0;
}

/* Periods between cable-shape snapshots for `rate_hz` (0: not a whole number of periods). */
static long shapes_every(double rate_hz, double period_s)
{
    const double every = 1.0 / (rate_hz * period_s);
    const long n = cdpr_scenario_count(every);
    return (rate_hz > 0.0 && n >= 1 && fabs(every - (double)n) <= 1e-6 * every) ? n : 0;
}

/* DIR/shapes.csv: its comment lines and header. */
static cdpr_status_t open_shapes(sim_t *s, const cdpr_scenario_t *sc, const cdpr_sim_opts_t *o,
                                 cdpr_scenario_error_t *err)
{
    char path[1100];
    if (cdpr_fs_path(path, sizeof path, o->out_dir, "shapes.csv") != CDPR_OK ||
        cdpr_csv_open(&s->shapes, path) != CDPR_OK) {
        snprintf(err->msg, sizeof err->msg, "%.1000s/shapes.csv: cannot write: %s", o->out_dir,
                 strerror(s->shapes.error != 0 ? s->shapes.error : ENAMETOOLONG));
        return CDPR_E_IO;
    }
    s->shapes_open = 1;
    char rate[64];
    snprintf(rate, sizeof rate, "%.17g", o->shapes_rate_hz);
    cdpr_csv_comment(&s->shapes, "scenario", sc->path);
    cdpr_csv_comment(&s->shapes, "shapes_rate_hz", rate);
    cdpr_csv_comment(&s->shapes, "nodes", "0 = cabin attachment .. n = exit point (segments n)");
    static const char *const cols[] = {"t_s", "cable", "node", "x_m", "y_m", "z_m", "h_m", "sag_m"};
    for (size_t i = 0; i < sizeof cols / sizeof cols[0]; ++i) {
        cdpr_csv_name(&s->shapes, cols[i]);
    }
    cdpr_csv_end_row(&s->shapes);
    return CDPR_OK;
}

/* One snapshot of every cable's nodes at t (a blank line after each cable). */
static void write_shapes(sim_t *s, double t)
{
    const cdpr_robot_t *r = &s->plant.robot;
    double *xyz = s->node_xyz;
    for (int j = 0; j < r->p.n_cables; ++j) {
        const int nodes = cdpr_host_cable_nodes(&s->plant, j, xyz, CDPR_MAX_SEGMENTS + 1);
        const double *e = &xyz[3 * (nodes - 1)]; /* the exit point */
        const double *a = &xyz[0];               /* the attachment: the chord's other end */
        const double h_a = hypot(a[0] - e[0], a[1] - e[1]);
        for (int k = 0; k < nodes; ++k) {
            const double *p = &xyz[3 * k];
            const double h = hypot(p[0] - e[0], p[1] - e[1]);
            /* Below the straight chord exit -> attachment, at the node's horizontal distance
             * (0 for a vertical chord). */
            const double chord_z = (h_a > 0.0) ? e[2] + (a[2] - e[2]) * h / h_a : p[2];
            const double row[] = {t, (double)(j + 1), (double)k, p[0], p[1], p[2],
                                  h, chord_z - p[2]};
            for (size_t c = 0; c < sizeof row / sizeof row[0]; ++c) {
                cdpr_csv_num(&s->shapes, row[c]);
            }
            cdpr_csv_end_row(&s->shapes);
        }
        cdpr_csv_end_row(&s->shapes); /* blank line: the next cable */
    }
}

static void progress(const cdpr_sim_opts_t *o, double t, double total, double wall, int final)
{
    if (o->progress == 0 || o->progress_stream == NULL) {
        return;
    }
    const double pct = 100.0 * t / total;
    const double speed = (wall > 0.0) ? t / wall : 0.0;
    if (o->progress == 1) {
        fprintf(o->progress_stream,
                "\rcdpr-sim: t = %7.2f / %.2f s (%3.0f %%), %.2fx real time  %s", t, total, pct,
                speed, (final != 0) ? "\n" : "");
    } else {
        fprintf(o->progress_stream, "cdpr-sim: t = %.2f / %.2f s (%.0f %%), %.2fx real time\n", t,
                total, pct, speed);
    }
    fflush(o->progress_stream);
}

/* The trajectory's feasibility, the plant (IK lengths -> robot -> catenary placement ->
 * settle) and the controller. Returns CDPR_OK or the error with err filled. */
static cdpr_status_t initialise(sim_t *s, const cdpr_scenario_t *sc, const cdpr_sim_opts_t *o,
                                double duration, cdpr_summary_t *sum, cdpr_scenario_error_t *err)
{
    /* The trajectory first (feasible, lengths within the limits; its error names the time and
     * pose): a statics check per 0.1 s, cheap next to the settle that follows. */
    const cdpr_status_t ts = cdpr_feasibility_check_trajectory(sc, duration, &s->model, err);
    if (ts != CDPR_OK) {
        return ts;
    }
    const cdpr_status_t ps = cdpr_host_plant_init(&s->plant, sc, &sum->settle_wall_time_s, err);
    sum->settle_steps = s->plant.settle.steps;
    if (ps != CDPR_OK) {
        return ps;
    }
    /* The controller, with its own model: the robot with controller.model's factors. */
    cdpr_robot_params_t model;
    const cdpr_status_t ms = cdpr_host_controller_params(sc, &model, err);
    if (ms != CDPR_OK) {
        return ms;
    }
    cdpr_diag_t d;
    cdpr_tracker_gains_t g = sc->gains;
    g.wind_m_per_s = s->plant.pp.wind_m_per_s; /* the wind feed-forward's steady wind */
    if (o->correction != NULL) {
        g.correction = o->correction; /* the caller's (cdpr-precomp's iterates) */
    } else {
        const cdpr_status_t cs = cdpr_correction_for_scenario(sc, &s->corr, &g.correction, err);
        if (cs != CDPR_OK) {
            return cs;
        }
    }
    const cdpr_status_t st =
        cdpr_tracker_init(&s->tracker, &model, &sc->traj, &g, sc->period_s, 0.0, &d);
    if (st != CDPR_OK) {
        char what[512];
        snprintf(what, sizeof what, "controller: field '%s': %s", d.field, cdpr_status_str(st));
        cdpr_scenario_error(sc,
                            (strcmp(d.field, "trajectory") == 0) ? cdpr_scenario_trajectory_key(sc)
                                                                 : "controller",
                            what, err);
        return st;
    }
    return CDPR_OK;
}

static void note(cdpr_summary_t *sum, const char *what)
{
    if (sum->message[0] == '\0') {
        snprintf(sum->message, sizeof sum->message, "%s", what);
    }
}

/* Why the plant stopped, in the words of the scenario. A period that did not fit in its trial
 * budget names the key that bounds it and the trials the step size the integrator had shrunk
 * to would take (the step size it keeps after the refused period). */
static void failure_message(const cdpr_plant_t *p, double t, cdpr_status_t st, char *msg, size_t n)
{
    if (st != CDPR_E_SUBSTEP_LIMIT || p->pp.integrator == CDPR_PLANT_ROS34PW2_FIXED) {
        snprintf(msg, n, "integrator failed at t = %.6g s: %s", t, cdpr_status_str(st));
        return;
    }
    const double h = (p->pp.integrator == CDPR_PLANT_RKF45) ? p->rk.h_s : p->ros.h_s;
    const double need = (h > 0.0) ? ceil((double)p->pp.period_s / h) : (double)INFINITY;
    if (!(need <= (double)CDPR_SCENARIO_MAX_TRIALS)) {
        snprintf(msg, n,
                 "integrator failed at t = %.6g s: %s: a period took more than "
                 "integrator.max_trials = %d trials; at the step size reached (%.3g s) a period "
                 "is more than the largest budget (%d): loosen the tolerances or shorten "
                 "run.period_s",
                 t, cdpr_status_str(st), p->pp.max_trials, h, CDPR_SCENARIO_MAX_TRIALS);
        return;
    }
    snprintf(msg, n,
             "integrator failed at t = %.6g s: %s: a period took more than integrator.max_trials "
             "= %d trials (x max_attempts %d); at the step size reached (%.3g s) a period is up "
             "to %.0f steps: raise integrator.max_trials",
             t, cdpr_status_str(st), p->pp.max_trials, p->pp.max_attempts, h, need);
}

static void collect_counts(const sim_t *s, cdpr_summary_t *sum);

/* The control loop. Returns CDPR_OK (reached the end) or the error that stopped it (a signal:
 * CDPR_E_INTERRUPTED; the CSV: CDPR_E_IO). */
static cdpr_status_t loop(sim_t *s, const cdpr_scenario_t *sc, const cdpr_sim_opts_t *o,
                          double duration, cdpr_summary_t *sum, double wall0)
{
    cdpr_plant_t *p = &s->plant;
    const cdpr_robot_t *r = &p->robot;
    const int nc = r->p.n_cables;
    const double dt = sc->period_s;
    const long n_periods = cdpr_scenario_count(duration / dt);
    double next_progress = wall0 + o->progress_after_s;
    int shown = 0;
    double l_ff[CDPR_MAX_CABLES] = {0.0};
    cdpr_status_t rc = CDPR_OK;
    for (long k = 0;; ++k) {
        const double t = (double)k * dt;
        cdpr_traj_sample_t des;
        cdpr_traj_eval(&sc->traj, t, &des);
        cdpr_tracker_meas_t meas;
        cdpr_robot_out_t out; /* end forces at t_k, for the row below */
        cdpr_plant_measure_out(p, &meas, &out);
        const int last = (k >= n_periods) ? 1 : 0;
        if (sc->wind.given != 0 && last == 0) {
            /* The wind of the coming period, at its midpoint, for the plant and the
             * controller's feed-forward (cdpr_scenario_wind_at). */
            double w[3];
            cdpr_scenario_wind_at(sc, t + 0.5 * dt, w);
            p->robot.in.wind_m_per_s =
                cdpr_v3((cdpr_real_t)w[0], (cdpr_real_t)w[1], (cdpr_real_t)w[2]);
            (void)cdpr_tracker_set_wind(&s->tracker, p->robot.in.wind_m_per_s); /* finite */
        }
        cdpr_tracker_cmd_t cmd;
        if (last == 0) {
            if (cdpr_tracker_step(&s->tracker, &meas, &cmd) != CDPR_OK) {
                note(sum, "non-finite measurement");
                rc = CDPR_E_STATE_NOT_FINITE; /* the plant's state behind it */
                break;
            }
            memcpy(l_ff, cmd.l_ff_m, sizeof l_ff);
        }
        /* The row of t_k: state, tensions and the payout rates of the period that ended at t_k
         * (what the real-time node publishes for state k), L_ff(t_k). */
        int segments[CDPR_MAX_CABLES] = {0};
        for (int j = 0; j < nc; ++j) {
            segments[j] = r->cable[j].n;
        }
        const cdpr_record_row_t row = {t,
                                       &des,
                                       &meas,
                                       out.tension_cabin_N,
                                       out.tension_winch_N,
                                       l_ff,
                                       r->in.payout_m_per_s,
                                       segments};
        if (s->shapes_open != 0 && k % s->shapes_every == 0) {
            write_shapes(s, t);
            if (s->shapes.failed != 0) {
                snprintf(sum->message, sizeof sum->message,
                         "shapes.csv: write failed at t = %.6g s: %s", t,
                         strerror(s->shapes.error));
                rc = CDPR_E_IO;
                break;
            }
        }
        if (o->on_period != NULL) {
            o->on_period(o->on_period_ctx, k, &row, (last == 0) ? &cmd : NULL);
        }
        if (cdpr_record_period(&s->rec, k, last, &row) != CDPR_OK) {
            snprintf(sum->message, sizeof sum->message,
                     "timeseries.csv: write failed at t = %.6g s: %s", t,
                     strerror(cdpr_record_errno(&s->rec)));
            rc = CDPR_E_IO;
            break;
        }
        int flags = 0;
        if (last == 0) {
            flags = cdpr_plant_command(p, CDPR_WINCH_RATE, cmd.rate_m_per_s);
            for (int j = 0; j < nc; ++j) {
                sum->max_payout_m_per_s =
                    fmax(sum->max_payout_m_per_s, fabs(p->winch[j].u_m_per_s));
            }
        }
        if (last != 0) {
            break;
        }
        if (o->stop != NULL && *o->stop != 0) {
            snprintf(sum->message, sizeof sum->message, "interrupted by a signal at t = %.6g s", t);
            rc = CDPR_E_INTERRUPTED;
            break;
        }
        const cdpr_status_t as = cdpr_plant_advance(p, &flags);
        if (as < 0) {
            failure_message(p, t, as, sum->message, sizeof sum->message);
            rc = as;
            break;
        }
        if ((flags & CDPR_PLANT_NODE_CAPACITY) != 0) {
            note(sum, "node capacity reached");
        }
        const double wall = cdpr_clock_now_s();
        if (o->progress != 0 && wall >= next_progress) {
            progress(o, t + dt, duration, wall - wall0, 0);
            shown = 1;
            next_progress = wall + ((o->progress == 1) ? 0.25 : 5.0);
        }
    }
    if (shown != 0) {
        progress(o, sum->sim_time_s, duration, cdpr_clock_now_s() - wall0, 1);
    }
    collect_counts(s, sum);
    return rc;
}

/* The plant's and the controller's counts of the run into the summary. */
static void collect_counts(const sim_t *s, cdpr_summary_t *sum)
{
    const cdpr_plant_t *p = &s->plant;
    for (int j = 0; j < p->robot.p.n_cables; ++j) {
        sum->node_insertions += p->nodes.insertions[j];
        sum->node_removals += p->nodes.removals[j];
        sum->capacity_hits += p->nodes.capacity_hits[j];
    }
    sum->ik_failures = s->tracker.ik_failures;
    cdpr_record_tracker_counts(&s->tracker, sum);
    sum->substep_limit_hits = p->stats.substep_limit_hits;
    sum->min_length_periods = p->stats.min_length_periods;
    sum->max_rhs_per_period = p->stats.max_rhs_evals;
    sum->max_err_norm = (double)NAN;
    sum->err_above_one_periods = 0;
    cdpr_plant_work_t w;
    cdpr_plant_work(p, &w);
    sum->steps_accepted = w.steps_accepted;
    sum->steps_rejected = w.steps_rejected;
    sum->rhs_evals = w.rhs_evals;
    if (p->pp.integrator != CDPR_PLANT_RKF45) {
        sum->substeps = p->substeps;
        sum->max_err_norm = (p->substeps > 0) ? (double)p->stats.max_err_norm : (double)NAN;
        sum->err_above_one_periods = p->stats.err_above_one_periods;
    }
}

/* Status of a run that reached its end or stopped (rc), with the first warning as message. */
static void finish_status(cdpr_status_t rc, cdpr_summary_t *sum)
{
    if (rc == CDPR_E_INTERRUPTED) {
        sum->status = CDPR_SUMMARY_INTERRUPTED;
    } else if (rc == CDPR_E_IO) {
        sum->status = CDPR_SUMMARY_IO_ERROR;
    } else if (rc != CDPR_OK) {
        sum->status = CDPR_SUMMARY_FAILED;
    } else if (sum->substep_limit_hits + sum->ik_failures + sum->capacity_hits +
                   sum->min_length_periods >
               0) {
        sum->status = CDPR_SUMMARY_WARNINGS;
        if (sum->substep_limit_hits > 0) {
            note(sum, "substep limit hit (tolerance not met in some periods)");
        } else if (sum->ik_failures > 0) {
            note(sum, "feed-forward IK failed in some periods (last good value held)");
        } else if (sum->min_length_periods > 0) {
            note(sum, "a winch was held at its minimum length");
        }
    } else {
        sum->status = CDPR_SUMMARY_OK;
    }
}

/* The outputs of a finished, stopped or failed run: close the CSV (its whole rows), then
 * summary.json even when the CSV failed (another file: it may fit; its status says io_error).
 * CDPR_OK or CDPR_E_IO with err naming the file(s) and strerror. */
static cdpr_status_t write_outputs(sim_t *s, const cdpr_scenario_t *sc, const cdpr_sim_opts_t *o,
                                   cdpr_summary_t *sum, cdpr_scenario_error_t *err)
{
    cdpr_status_t rc = CDPR_OK;
    if (s->shapes_open != 0) {
        s->shapes_open = 0;
        if (cdpr_csv_close(&s->shapes) != CDPR_OK) {
            if (sum->status != CDPR_SUMMARY_IO_ERROR) { /* failed at the final flush */
                sum->status = CDPR_SUMMARY_IO_ERROR;
                snprintf(sum->message, sizeof sum->message, "shapes.csv: write failed: %s",
                         strerror(s->shapes.error));
            }
            snprintf(err->msg, sizeof err->msg, "%.1000s/shapes.csv: write failed: %s", o->out_dir,
                     strerror(s->shapes.error));
            rc = CDPR_E_IO;
        }
    }
    if (cdpr_record_close(&s->rec) != CDPR_OK) {
        if (sum->status != CDPR_SUMMARY_IO_ERROR) { /* failed at the final flush */
            sum->status = CDPR_SUMMARY_IO_ERROR;
            snprintf(sum->message, sizeof sum->message, "timeseries.csv: write failed: %s",
                     strerror(cdpr_record_errno(&s->rec)));
        }
        cdpr_record_io_error(&s->rec, err);
        rc = CDPR_E_IO;
    }
    if (o->out_dir == NULL) {
        return rc;
    }
    char path[1100];
    if (cdpr_fs_path(path, sizeof path, o->out_dir, "summary.json") != CDPR_OK ||
        cdpr_summary_write(path, sc, sum) != CDPR_OK ||
        cdpr_fs_path(path, sizeof path, o->out_dir, "laps.csv") != CDPR_OK ||
        cdpr_summary_write_laps(path, sum) != CDPR_OK) {
        const char *why = strerror(errno);
        if (rc != CDPR_OK) {
            const size_t n = strlen(err->msg);
            snprintf(err->msg + n, sizeof err->msg - n, "; %.1100s: cannot write: %s", path, why);
        } else {
            snprintf(err->msg, sizeof err->msg, "%.1100s: cannot write: %s", path, why);
        }
        rc = CDPR_E_IO;
    }
    return rc;
}

cdpr_status_t cdpr_sim_run(const cdpr_scenario_t *sc, const cdpr_sim_opts_t *o, cdpr_summary_t *sum,
                           cdpr_scenario_error_t *err)
{
    memset(sum, 0, sizeof *sum);
    sum->status = CDPR_SUMMARY_FAILED;
    /* Checked once: a scenario changed since its load or override (or built in code) is
     * checked here. */
    const cdpr_status_t cs =
        (cdpr_scenario_is_checked(sc) != 0) ? CDPR_OK : cdpr_scenario_check(sc, err);
    if (cs != CDPR_OK) {
        return cs;
    }
    const double duration = sc->duration_s;
    const double wall0 = cdpr_clock_now_s();
    const long every = shapes_every(o->shapes_rate_hz, sc->period_s);
    if ((o->shapes_rate_hz < 0.0 || o->shapes_rate_hz > 0.0 || isnan(o->shapes_rate_hz)) &&
        every == 0) {
        snprintf(err->msg, sizeof err->msg,
                 "--shapes %g Hz: not the control rate (%g Hz) divided by a whole number",
                 o->shapes_rate_hz, 1.0 / sc->period_s);
        return CDPR_E_OUT_OF_RANGE;
    }
    sim_t *s = calloc(1, sizeof *s);
    if (s == NULL) {
        snprintf(err->msg, sizeof err->msg, "out of memory");
        return CDPR_E_IO;
    }
    cdpr_status_t rc = initialise(s, sc, o, duration, sum, err);
    if (rc == CDPR_OK) {
        rc = cdpr_record_open(&s->rec, sc, &s->plant.pp, o->out_dir, s->plant.robot.p.n_cables, sum,
                              err);
    }
    if (rc == CDPR_OK && o->out_dir != NULL && every > 0) {
        s->shapes_every = every;
        rc = open_shapes(s, sc, o, err);
    }
    if (rc == CDPR_OK) {
        rc = loop(s, sc, o, duration, sum, wall0);
        sum->wall_time_s = cdpr_clock_now_s() - wall0;
        finish_status(rc, sum);
        const cdpr_status_t ws = write_outputs(s, sc, o, sum, err);
        rc = (ws != CDPR_OK) ? ws : rc;
    }
    if (s->rec.csv_open != 0) {
        (void)cdpr_csv_close(&s->rec.csv);
    }
    if (s->shapes_open != 0) {
        (void)cdpr_csv_close(&s->shapes);
    }
    free(s);
    return rc;
}
