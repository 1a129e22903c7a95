/// @file sim.c
/// Batch closed-loop run of a scenario (see sim.h).
#include "cdpr/host/sim.h"

#include <cyaml/cyaml.h>
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>
#include <time.h>

#include "cdpr/host/csv.h"
#include "cdpr/host/clock.h"
#include "cdpr/host/plant.h"
#include "cdpr/rkf45.h"
#include "cdpr/settle.h"
#include "cdpr/statics.h"
#include "cdpr/winch.h"

static const double PI = 3.14159265358979323846;

/* Everything a run needs, allocated once (about 250 kB at the default capacities). */
typedef struct {
    cdpr_plant_t plant;
    cdpr_robot_t model; /* statics-only model for the feasibility checks */
    cdpr_tracker_t tracker;
    cdpr_sim_rec_t rec;
} sim_t;

void cdpr_sim_opts_default(cdpr_sim_opts_t *o)
{
    memset(o, 0, sizeof *o);
    o->progress_after_s = 2.0;
}

const char *cdpr_sim_status_name(cdpr_sim_status_t st)
{
    switch (st) {
    case CDPR_SIM_OK:
        return "ok";
    case CDPR_SIM_WARNINGS:
        return "warnings";
    default:
        return "failed";
    }
}

static int mkdir_p(const char *dir)
{
    char buf[1024];
    if (snprintf(buf, sizeof buf, "%s", dir) >= (int)sizeof buf) {
        errno = ENAMETOOLONG;
        return -1;
    }
    for (char *p = buf + 1; *p != '\0'; ++p) {
        if (*p == '/') {
            *p = '\0';
            if (mkdir(buf, 0775) != 0 && errno != EEXIST) {
                return -1;
            }
            *p = '/';
        }
    }
    return (mkdir(buf, 0775) != 0 && errno != EEXIST) ? -1 : 0;
}

static double wrap_pi(double a)
{
    while (a > PI) {
        a -= 2.0 * PI;
    }
    while (a <= -PI) {
        a += 2.0 * PI;
    }
    return a;
}

static const char *traj_key(const cdpr_scenario_t *sc)
{
    return (sc->traj.type == CDPR_TRAJ_CIRCLE)
               ? "trajectory.circle"
               : ((sc->traj.type == CDPR_TRAJ_LINE) ? "trajectory.line" : "trajectory.hold");
}

/* The trajectory (every 0.1 s and at the end) must be statically feasible (the initial pose is
 * checked by cdpr_plant_init); returns 0 or 2 with err filled. */
static int check_reachable(sim_t *s, const cdpr_scenario_t *sc, double duration,
                           cdpr_scenario_error_t *err)
{
    cdpr_robot_params_t mp;
    cdpr_diag_t d;
    if (cdpr_preset_build(&sc->robot, NULL, &mp, NULL, &d) != CDPR_OK ||
        cdpr_robot_init(&s->model, &mp, &d) != CDPR_OK) {
        char what[512];
        snprintf(what, sizeof what, "rejected by the model: field '%s': %s", d.field,
                 cdpr_status_str(d.status));
        cdpr_scenario_error(sc, "robot", what, err);
        return 2;
    }
    cdpr_statics_opts_t o;
    cdpr_statics_opts_default(&o);
    const long n = (long)ceil(duration / 0.1);
    for (long k = 0; k <= n; ++k) {
        const double t = (k < n) ? 0.1 * (double)k : duration + sc->period_s;
        cdpr_traj_sample_t ds;
        cdpr_traj_eval(&sc->traj, t, &ds);
        cdpr_statics_result_t res;
        const cdpr_status_t st = cdpr_statics_ik(&s->model, &ds.motion, &o, &res);
        if (st != CDPR_OK) {
            char what[512];
            snprintf(what, sizeof what,
                     "desired pose at t = %g s (%g, %g, %g m, %g, %g, %g rad) is not "
                     "statically reachable (no equilibrium with every cable "
                     "pulling): %s",
                     t, ds.pose[0], ds.pose[1], ds.pose[2], ds.pose[3], ds.pose[4], ds.pose[5],
                     cdpr_status_str(st));
            cdpr_scenario_error(sc, traj_key(sc), what, err);
            return 2;
        }
    }
    return 0;
}

static void csv_header(cdpr_csv_t *c, int nc)
{
    static const char *const head[] = {
        "t_s",  "x_m",  "y_m",        "z_m",        "alpha_rad",  "beta_rad",   "gamma_rad",
        "xd_m", "yd_m", "zd_m",       "alphad_rad", "betad_rad",  "gammad_rad", "ex_m",
        "ey_m", "ez_m", "ealpha_rad", "ebeta_rad",  "egamma_rad", "epos_m",     "erot_rad"};
    for (size_t i = 0; i < sizeof head / sizeof head[0]; ++i) {
        cdpr_csv_name(c, head[i]);
    }
    static const char *const per[] = {"T_cabin%d_N", "T_winch%d_N", "L%d_m",
                                      "Lff%d_m",     "u%d_m_per_s", "n%d"};
    for (size_t k = 0; k < sizeof per / sizeof per[0]; ++k) {
        for (int j = 0; j < nc; ++j) {
            char name[32];
            snprintf(name, sizeof name, per[k], j + 1);
            cdpr_csv_name(c, name);
        }
    }
    cdpr_csv_end_row(c);
}

/* Per-sample quantities shared by the CSV row and the summary. */
typedef struct {
    double pose[6];
    double err[6]; /* actual - desired; angles wrapped */
    double epos_m;
    double erot_rad;
} sample_t;

static void errors(const cdpr_tracker_meas_t *meas, const cdpr_traj_sample_t *des, sample_t *smp)
{
    const cdpr_cabin_motion_t m = meas->cabin;
    smp->pose[0] = m.p_m.x;
    smp->pose[1] = m.p_m.y;
    smp->pose[2] = m.p_m.z;
    cdpr_quat_to_euler(m.q, &smp->pose[3], &smp->pose[4], &smp->pose[5]);
    for (int i = 0; i < 6; ++i) {
        const double e = smp->pose[i] - des->pose[i];
        smp->err[i] = (i < 3) ? e : wrap_pi(e);
    }
    smp->epos_m =
        sqrt(smp->err[0] * smp->err[0] + smp->err[1] * smp->err[1] + smp->err[2] * smp->err[2]);
    const cdpr_quat_t qi = {m.q.w, -m.q.x, -m.q.y, -m.q.z};
    smp->erot_rad = cdpr_v3_norm(cdpr_quat_to_rotvec(cdpr_quat_mul(des->motion.q, qi)));
}

static void csv_row(cdpr_sim_rec_t *rec, const cdpr_sim_row_t *row, const sample_t *smp)
{
    cdpr_csv_t *c = &rec->csv;
    const int nc = rec->n_cables;
    cdpr_csv_num(c, row->t_s);
    for (int i = 0; i < 6; ++i) {
        cdpr_csv_num(c, smp->pose[i]);
    }
    for (int i = 0; i < 6; ++i) {
        cdpr_csv_num(c, row->des->pose[i]);
    }
    for (int i = 0; i < 6; ++i) {
        cdpr_csv_num(c, smp->err[i]);
    }
    cdpr_csv_num(c, smp->epos_m);
    cdpr_csv_num(c, smp->erot_rad);
    for (int j = 0; j < nc; ++j) {
        cdpr_csv_num(c, row->tension_cabin_N[j]);
    }
    for (int j = 0; j < nc; ++j) {
        cdpr_csv_num(c, row->tension_winch_N[j]);
    }
    for (int j = 0; j < nc; ++j) {
        cdpr_csv_num(c, row->meas->length_m[j]);
    }
    for (int j = 0; j < nc; ++j) {
        cdpr_csv_num(c, row->l_ff_m[j]);
    }
    for (int j = 0; j < nc; ++j) {
        cdpr_csv_num(c, row->payout_m_per_s[j]);
    }
    for (int j = 0; j < nc; ++j) {
        cdpr_csv_num(c, (double)row->segments[j]);
    }
    cdpr_csv_end_row(c);
}

int cdpr_sim_rec_open(cdpr_sim_rec_t *rec, const cdpr_scenario_t *sc, const char *out_dir,
                      int n_cables, double duration_s, cdpr_sim_summary_t *sum,
                      cdpr_scenario_error_t *err)
{
    memset(rec, 0, sizeof *rec);
    rec->n_cables = n_cables;
    rec->every = cdpr_scenario_output_every(sc);
    rec->duration_s = duration_s;
    rec->sum = sum;
    sum->min_tension_N = (double)INFINITY;
    sum->nodes_min = CDPR_MAX_SEGMENTS;
    sum->nodes_max = 0;
    if (out_dir == NULL) {
        return 0;
    }
    if (mkdir_p(out_dir) != 0) {
        snprintf(err->msg, sizeof err->msg, "%s: cannot create directory: %s", out_dir,
                 strerror(errno));
        return 3;
    }
    char path[1100];
    snprintf(path, sizeof path, "%s/timeseries.csv", out_dir);
    if (cdpr_csv_open(&rec->csv, path) != 0) {
        snprintf(err->msg, sizeof err->msg, "%s: cannot write: %s", path, strerror(errno));
        return 3;
    }
    rec->csv_open = 1;
    csv_header(&rec->csv, n_cables);
    return 0;
}

void cdpr_sim_rec_period(cdpr_sim_rec_t *rec, long k, int last, const cdpr_sim_row_t *row)
{
    cdpr_sim_summary_t *sum = rec->sum;
    const int nc = rec->n_cables;
    sample_t smp;
    errors(row->meas, row->des, &smp);
    if (k == 0) {
        sum->initial_error_m = smp.epos_m;
    }
    rec->sum2_pos += smp.epos_m * smp.epos_m;
    rec->sum2_rot += smp.erot_rad * smp.erot_rad;
    rec->n++;
    if (row->t_s >= 0.5 * rec->duration_s) {
        rec->sum2_pos_late += smp.epos_m * smp.epos_m;
        rec->n_late++;
    }
    sum->max_error_m = fmax(sum->max_error_m, smp.epos_m);
    sum->max_error_rad = fmax(sum->max_error_rad, smp.erot_rad);
    sum->final_error_m = smp.epos_m;
    sum->final_error_rad = smp.erot_rad;
    for (int j = 0; j < nc; ++j) {
        const double a = row->tension_cabin_N[j];
        const double b = row->tension_winch_N[j];
        sum->max_tension_N = fmax(sum->max_tension_N, fmax(a, b));
        sum->min_tension_N = fmin(sum->min_tension_N, fmin(a, b));
        sum->nodes_min = (row->segments[j] < sum->nodes_min) ? row->segments[j] : sum->nodes_min;
        sum->nodes_max = (row->segments[j] > sum->nodes_max) ? row->segments[j] : sum->nodes_max;
    }
    sum->periods = k;
    sum->sim_time_s = row->t_s;
    if (rec->csv_open != 0 && (k % rec->every == 0 || last != 0)) {
        csv_row(rec, row, &smp);
    }
}

int cdpr_sim_rec_close(cdpr_sim_rec_t *rec)
{
    cdpr_sim_summary_t *sum = rec->sum;
    sum->rms_error_m = (rec->n > 0) ? sqrt(rec->sum2_pos / (double)rec->n) : 0.0;
    sum->rms_error_rad = (rec->n > 0) ? sqrt(rec->sum2_rot / (double)rec->n) : 0.0;
    sum->rms_error_second_half_m =
        (rec->n_late > 0) ? sqrt(rec->sum2_pos_late / (double)rec->n_late) : 0.0;
    if (!isfinite(sum->min_tension_N)) {
        sum->min_tension_N = 0.0;
    }
    int rc = 0;
    if (rec->csv_open != 0) {
        rc = cdpr_csv_close(&rec->csv);
        rec->csv_open = 0;
    }
    return rc;
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

/* Plant (IK lengths -> robot -> catenary placement -> settle), the trajectory's feasibility,
 * and the controller. Returns 0 or 2. */
static int initialise(sim_t *s, const cdpr_scenario_t *sc, double duration, cdpr_sim_summary_t *sum,
                      cdpr_scenario_error_t *err)
{
    const cdpr_status_t ps = cdpr_host_plant_init(&s->plant, sc, &sum->settle_wall_time_s, err);
    sum->settle_steps = s->plant.settle.steps;
    if (ps != CDPR_OK) {
        return 2;
    }
    /* The trajectory before the controller: its error names the time and pose. */
    const int rc_traj = check_reachable(s, sc, duration, err);
    if (rc_traj != 0) {
        return rc_traj;
    }
    /* The controller, with its own model built from the same values. */
    cdpr_diag_t d;
    const cdpr_status_t st = cdpr_tracker_init(&s->tracker, &s->plant.params, &sc->traj, &sc->gains,
                                               sc->period_s, 0.0, &d);
    if (st != CDPR_OK) {
        char what[512];
        snprintf(what, sizeof what, "controller: field '%s': %s", d.field, cdpr_status_str(st));
        cdpr_scenario_error(sc, (strcmp(d.field, "trajectory") == 0) ? traj_key(sc) : "controller",
                            what, err);
        return 2;
    }
    return 0;
}

static void note(cdpr_sim_summary_t *sum, const char *what)
{
    if (sum->message[0] == '\0') {
        snprintf(sum->message, sizeof sum->message, "%s", what);
    }
}

/* The control loop. Returns 0 (reached the end) or 1 (integrator error). */
static int loop(sim_t *s, const cdpr_scenario_t *sc, const cdpr_sim_opts_t *o, double duration,
                cdpr_sim_summary_t *sum, double wall0)
{
    cdpr_plant_t *p = &s->plant;
    const cdpr_robot_t *r = &p->robot;
    const int nc = r->p.n_cables;
    const double dt = sc->period_s;
    const long n_periods = (long)floor(duration / dt + 0.5);
    double next_progress = wall0 + o->progress_after_s;
    int shown = 0;
    double l_ff[CDPR_MAX_CABLES] = {0.0};
    int rc = 0;
    for (long k = 0;; ++k) {
        const double t = (double)k * dt;
        cdpr_traj_sample_t des;
        cdpr_traj_eval(&sc->traj, t, &des);
        cdpr_tracker_meas_t meas;
        cdpr_plant_measure(p, &meas);
        const int last = (k >= n_periods) ? 1 : 0;
        cdpr_tracker_cmd_t cmd;
        if (last == 0) {
            if (cdpr_tracker_step(&s->tracker, &meas, &cmd) != CDPR_OK) {
                note(sum, "non-finite measurement");
                rc = 1;
                break;
            }
            memcpy(l_ff, cmd.l_ff_m, sizeof l_ff);
        }
        /* The row of t_k: state, tensions and the payout rates of the period that ended at t_k
         * (what the real-time node publishes for state k), L_ff(t_k). */
        cdpr_robot_out_t out;
        cdpr_robot_outputs(r, t, p->y, &out);
        int segments[CDPR_MAX_CABLES] = {0};
        for (int j = 0; j < nc; ++j) {
            segments[j] = r->cable[j].n;
        }
        const cdpr_sim_row_t row = {t,
                                    &des,
                                    &meas,
                                    out.tension_cabin_N,
                                    out.tension_winch_N,
                                    l_ff,
                                    r->in.payout_m_per_s,
                                    segments};
        cdpr_sim_rec_period(&s->rec, k, last, &row);
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
        const cdpr_status_t as = cdpr_plant_advance(p, &flags);
        if (as < 0) {
            snprintf(sum->message, sizeof sum->message, "integrator failed at t = %.6g s: %s", t,
                     cdpr_status_str(as));
            rc = 1;
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
    for (int j = 0; j < nc; ++j) {
        sum->node_insertions += p->nodes.insertions[j];
        sum->node_removals += p->nodes.removals[j];
        sum->capacity_hits += p->nodes.capacity_hits[j];
    }
    sum->ik_failures = s->tracker.ik_failures;
    sum->substep_limit_hits = p->stats.substep_limit_hits;
    sum->min_length_periods = p->stats.min_length_periods;
    sum->steps_accepted = p->rk.stats.steps_accepted;
    sum->steps_rejected = p->rk.stats.steps_rejected;
    sum->rhs_evals = p->rk.stats.rhs_evals;
    return rc;
}

int cdpr_sim_run(const cdpr_scenario_t *sc, const cdpr_sim_opts_t *o, cdpr_sim_summary_t *sum,
                 cdpr_scenario_error_t *err)
{
    memset(sum, 0, sizeof *sum);
    sum->status = CDPR_SIM_FAILED;
    if (cdpr_scenario_check(sc, err) != 0) {
        return 2;
    }
    const double duration = (o->duration_s > 0.0) ? o->duration_s : sc->duration_s;
    const double wall0 = cdpr_clock_now_s();
    sim_t *s = calloc(1, sizeof *s);
    if (s == NULL) {
        snprintf(err->msg, sizeof err->msg, "out of memory");
        return 3;
    }
    int rc = initialise(s, sc, duration, sum, err);
    if (rc == 0) {
        rc = cdpr_sim_rec_open(&s->rec, sc, o->out_dir, s->plant.robot.p.n_cables, duration, sum,
                               err);
    }
    if (rc == 0) {
        rc = loop(s, sc, o, duration, sum, wall0);
        sum->wall_time_s = cdpr_clock_now_s() - wall0;
        const int csv_rc = cdpr_sim_rec_close(&s->rec);
        if (rc != 0) {
            sum->status = CDPR_SIM_FAILED;
        } else if (sum->substep_limit_hits + sum->ik_failures + sum->capacity_hits +
                       sum->min_length_periods >
                   0) {
            sum->status = CDPR_SIM_WARNINGS;
            if (sum->substep_limit_hits > 0) {
                note(sum, "substep limit hit (tolerance not met in some periods)");
            } else if (sum->ik_failures > 0) {
                note(sum, "feed-forward IK failed in some periods (last good value held)");
            } else if (sum->min_length_periods > 0) {
                note(sum, "a winch was held at its minimum length");
            }
        } else {
            sum->status = CDPR_SIM_OK;
        }
        if (csv_rc != 0) {
            snprintf(err->msg, sizeof err->msg, "%s/timeseries.csv: write error", o->out_dir);
            rc = 3;
        }
        if (o->out_dir != NULL && rc != 3) {
            char path[1100];
            snprintf(path, sizeof path, "%s/summary.json", o->out_dir);
            if (cdpr_sim_write_summary(path, sc, sum) != 0) {
                snprintf(err->msg, sizeof err->msg, "%s: cannot write: %s", path, strerror(errno));
                rc = 3;
            }
        }
    }
    if (s->rec.csv_open != 0) {
        (void)cdpr_csv_close(&s->rec.csv);
    }
    free(s);
    return rc;
}

/* JSON string body with the characters JSON requires escaped. */
static void json_string(FILE *f, const char *s)
{
    fputc('"', f);
    for (; *s != '\0'; ++s) {
        const unsigned char ch = (unsigned char)*s;
        if (ch == '"' || ch == '\\') {
            fprintf(f, "\\%c", ch);
        } else if (ch < 0x20) {
            fprintf(f, "\\u%04x", ch);
        } else {
            fputc(ch, f);
        }
    }
    fputc('"', f);
}

int cdpr_sim_write_summary(const char *path, const cdpr_scenario_t *sc,
                           const cdpr_sim_summary_t *sum)
{
    FILE *f = fopen(path, "w");
    if (f == NULL) {
        return -1;
    }
    fprintf(f, "{\n  \"scenario\": ");
    json_string(f, sc->path);
    fprintf(f, ",\n  \"robot\": ");
    json_string(f, cdpr_preset_name(sc->robot.preset));
    fprintf(f, ",\n  \"trajectory\": ");
    json_string(f, cdpr_traj_type_name(sc->traj.type));
    fprintf(f, ",\n  \"status\": ");
    json_string(f, cdpr_sim_status_name(sum->status));
    fprintf(f, ",\n  \"message\": ");
    json_string(f, sum->message);
    const struct {
        const char *k;
        double v;
    } nums[] = {
        {"rms_error_m", sum->rms_error_m},
        {"max_error_m", sum->max_error_m},
        {"final_error_m", sum->final_error_m},
        {"initial_error_m", sum->initial_error_m},
        {"rms_error_second_half_m", sum->rms_error_second_half_m},
        {"rms_error_rad", sum->rms_error_rad},
        {"max_error_rad", sum->max_error_rad},
        {"final_error_rad", sum->final_error_rad},
        {"max_tension_N", sum->max_tension_N},
        {"min_tension_N", sum->min_tension_N},
        {"max_payout_m_per_s", sum->max_payout_m_per_s},
        {"sim_time_s", sum->sim_time_s},
        {"wall_time_s", sum->wall_time_s},
        {"settle_wall_time_s", sum->settle_wall_time_s},
        {"control_period_s", sc->period_s},
    };
    for (size_t i = 0; i < sizeof nums / sizeof nums[0]; ++i) {
        fprintf(f, ",\n  \"%s\": %.17g", nums[i].k, nums[i].v);
    }
    const struct {
        const char *k;
        long v;
    } ints[] = {
        {"node_insertions", (long)sum->node_insertions},
        {"node_removals", (long)sum->node_removals},
        {"capacity_hits", (long)sum->capacity_hits},
        {"substep_limit_hits", (long)sum->substep_limit_hits},
        {"ik_failures", (long)sum->ik_failures},
        {"min_length_periods", (long)sum->min_length_periods},
        {"nodes_min", (long)sum->nodes_min},
        {"nodes_max", (long)sum->nodes_max},
        {"periods", sum->periods},
        {"steps_accepted", (long)sum->steps_accepted},
        {"steps_rejected", (long)sum->steps_rejected},
        {"rhs_evals", (long)sum->rhs_evals},
        {"settle_steps", sum->settle_steps},
        {"segments", (long)sc->robot.segments},
    };
    for (size_t i = 0; i < sizeof ints / sizeof ints[0]; ++i) {
        fprintf(f, ",\n  \"%s\": %ld", ints[i].k, ints[i].v);
    }
    fprintf(f, "\n}\n");
    return (fclose(f) == 0) ? 0 : -1;
}

/* ---------------------------------------------------------------- reading summary.json */

typedef struct {
    char *status;
    double rms_error_m, max_error_m, final_error_m, initial_error_m, rms_error_second_half_m;
    double rms_error_rad, max_error_rad, final_error_rad;
    double max_tension_N, min_tension_N, max_payout_m_per_s, sim_time_s, wall_time_s;
    double node_insertions, node_removals, capacity_hits, substep_limit_hits, ik_failures;
    double min_length_periods, nodes_min, nodes_max, periods, steps_accepted, steps_rejected;
    double rhs_evals, settle_steps;
} raw_summary_t;

#define SUM_NUM(key) CYAML_FIELD_FLOAT(#key, CYAML_FLAG_STRICT, raw_summary_t, key)

static const cyaml_schema_field_t summary_fields[] = {
    CYAML_FIELD_STRING_PTR("status", CYAML_FLAG_DEFAULT, raw_summary_t, status, 0, 63),
    SUM_NUM(rms_error_m),
    SUM_NUM(max_error_m),
    SUM_NUM(final_error_m),
    SUM_NUM(initial_error_m),
    SUM_NUM(rms_error_second_half_m),
    SUM_NUM(rms_error_rad),
    SUM_NUM(max_error_rad),
    SUM_NUM(final_error_rad),
    SUM_NUM(max_tension_N),
    SUM_NUM(min_tension_N),
    SUM_NUM(max_payout_m_per_s),
    SUM_NUM(sim_time_s),
    SUM_NUM(wall_time_s),
    SUM_NUM(node_insertions),
    SUM_NUM(node_removals),
    SUM_NUM(capacity_hits),
    SUM_NUM(substep_limit_hits),
    SUM_NUM(ik_failures),
    SUM_NUM(min_length_periods),
    SUM_NUM(nodes_min),
    SUM_NUM(nodes_max),
    SUM_NUM(periods),
    SUM_NUM(steps_accepted),
    SUM_NUM(steps_rejected),
    SUM_NUM(rhs_evals),
    SUM_NUM(settle_steps),
    CYAML_FIELD_END,
};
static const cyaml_schema_value_t summary_schema = {
    CYAML_VALUE_MAPPING(CYAML_FLAG_POINTER, raw_summary_t, summary_fields),
};

typedef struct {
    char text[1024];
    size_t len;
} summary_log_t;

static void summary_log(cyaml_log_t level, void *ctx, const char *fmt, va_list args)
{
    summary_log_t *b = ctx;
    if (level >= CYAML_LOG_ERROR && b->len == 0) {
        const int n = vsnprintf(b->text, sizeof b->text, fmt, args);
        b->len = (n > 0) ? (size_t)n : 0;
        /* first line only */
        char *nl = strchr(b->text, '\n');
        if (nl != NULL) {
            *nl = '\0';
        }
    }
}

int cdpr_sim_read_summary(const char *path, cdpr_sim_summary_t *sum, cdpr_scenario_error_t *err)
{
    summary_log_t lg;
    lg.len = 0;
    lg.text[0] = '\0';
    const cyaml_config_t cfg = {
        .log_fn = summary_log,
        .log_ctx = &lg,
        .mem_fn = cyaml_mem,
        .log_level = CYAML_LOG_ERROR,
        .flags = CYAML_CFG_IGNORE_UNKNOWN_KEYS,
    };
    raw_summary_t *r = NULL;
    const cyaml_err_t e = cyaml_load_file(path, &cfg, &summary_schema, (cyaml_data_t **)&r, NULL);
    if (e != CYAML_OK || r == NULL) {
        snprintf(err->msg, sizeof err->msg, "%s: %s", path,
                 (lg.text[0] != '\0') ? lg.text : cyaml_strerror(e));
        return -1;
    }
    memset(sum, 0, sizeof *sum);
    sum->status =
        (strcmp(r->status, "ok") == 0)
            ? CDPR_SIM_OK
            : ((strcmp(r->status, "warnings") == 0) ? CDPR_SIM_WARNINGS : CDPR_SIM_FAILED);
    sum->rms_error_m = r->rms_error_m;
    sum->max_error_m = r->max_error_m;
    sum->final_error_m = r->final_error_m;
    sum->initial_error_m = r->initial_error_m;
    sum->rms_error_second_half_m = r->rms_error_second_half_m;
    sum->rms_error_rad = r->rms_error_rad;
    sum->max_error_rad = r->max_error_rad;
    sum->final_error_rad = r->final_error_rad;
    sum->max_tension_N = r->max_tension_N;
    sum->min_tension_N = r->min_tension_N;
    sum->max_payout_m_per_s = r->max_payout_m_per_s;
    sum->sim_time_s = r->sim_time_s;
    sum->wall_time_s = r->wall_time_s;
    sum->node_insertions = (unsigned long)r->node_insertions;
    sum->node_removals = (unsigned long)r->node_removals;
    sum->capacity_hits = (unsigned long)r->capacity_hits;
    sum->substep_limit_hits = (unsigned long)r->substep_limit_hits;
    sum->ik_failures = (unsigned long)r->ik_failures;
    sum->min_length_periods = (unsigned long)r->min_length_periods;
    sum->nodes_min = (int)r->nodes_min;
    sum->nodes_max = (int)r->nodes_max;
    sum->periods = (long)r->periods;
    sum->steps_accepted = (unsigned long)r->steps_accepted;
    sum->steps_rejected = (unsigned long)r->steps_rejected;
    sum->rhs_evals = (unsigned long)r->rhs_evals;
    sum->settle_steps = (long)r->settle_steps;
    (void)cyaml_free(&cfg, &summary_schema, r, 0);
    return 0;
}

/* ---------------------------------------------------------------- figures */

int cdpr_sim_plot(const char *prog, const char *script, const char *dir, const char *kind,
                  const char *title)
{
    struct stat sb;
    if (stat(script, &sb) != 0) {
        fprintf(stderr, "%s: warning: plot script %s: %s; no figures\n", prog, script,
                strerror(errno));
        return -1;
    }
    fflush(NULL);
    const pid_t pid = fork();
    if (pid < 0) {
        fprintf(stderr, "%s: warning: fork: %s; no figures\n", prog, strerror(errno));
        return -1;
    }
    if (pid == 0) {
        char *const args[] = {"gnuplot",     "-c", (char *)script, (char *)dir, (char *)kind,
                              (char *)title, NULL};
        execvp("gnuplot", args);
        fprintf(stderr, "%s: warning: cannot run gnuplot: %s; no figures\n", prog, strerror(errno));
        _exit(127);
    }
    int status = 0;
    while (waitpid(pid, &status, 0) < 0) {
        if (errno != EINTR) {
            return -1;
        }
    }
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
        if (!WIFEXITED(status) || WEXITSTATUS(status) != 127) {
            fprintf(stderr, "%s: warning: gnuplot failed (%s); figures may be missing\n", prog,
                    script);
        }
        return -1;
    }
    return 0;
}
