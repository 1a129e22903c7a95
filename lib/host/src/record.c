/* SPDX-License-Identifier: BSD-3-Clause */
/// @file record.c
/// Recorder of a tracking run: CSV rows and summary statistics (record.h).
#include "cdpr/host/record.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "cdpr/config.h"
#include "cdpr/host/fs.h"

static double wrap_pi(double a)
{
    while (a > CDPR_PI) {
        a -= 2.0 * CDPR_PI;
    }
    while (a <= -CDPR_PI) {
        a += 2.0 * CDPR_PI;
    }
    return a;
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

static void csv_row(cdpr_record_t *rec, const cdpr_record_row_t *row, const sample_t *smp)
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

/* The provenance as comment lines before the header (the keys of summary.json). */
static void csv_provenance(cdpr_csv_t *c, const cdpr_scenario_t *sc,
                           const cdpr_summary_provenance_t *pv)
{
    cdpr_csv_comment(c, "version", pv->version);
    cdpr_csv_comment(c, "git_describe", pv->git_describe);
    cdpr_csv_comment(c, "build_type", pv->build_type);
    cdpr_csv_comment(c, "scenario", sc->path);
    cdpr_csv_comment(c, "scenario_sha256", pv->scenario_sha256);
    cdpr_csv_comment(c, "integrator", pv->integrator);
}

cdpr_status_t cdpr_record_open(cdpr_record_t *rec, const cdpr_scenario_t *sc,
                               const cdpr_plant_params_t *pp, const char *out_dir, int n_cables,
                               cdpr_summary_t *sum, cdpr_scenario_error_t *err)
{
    memset(rec, 0, sizeof *rec);
    rec->prev_k = -1;
    rec->traj = sc->traj;
    rec->lap = -1;
    rec->last_row_k = -1;
    cdpr_summary_provenance_init(
        &sum->prov, sc->path, (sc->robot_source == CDPR_ROBOT_FROM_FILE) ? sc->rig.name : NULL, pp);
    rec->n_cables = n_cables;
    rec->every = cdpr_scenario_output_every(sc);
    rec->duration_s = sc->duration_s;
    rec->transfer_s = sc->gains.transfer_s;
    rec->sum = sum;
    sum->n_cables = n_cables;
    sum->first_slack_demand_t_s = (double)NAN;
    sum->first_slack_demand_N = (double)NAN;
    sum->min_tension_N = (double)INFINITY;
    for (int j = 0; j < CDPR_MAX_CABLES; ++j) {
        sum->cable_max_tension_N[j] = -(double)INFINITY;
        sum->cable_min_tension_N[j] = (double)INFINITY;
    }
    /* Known only if state 0 is recorded (a tracker over LCM may miss it): else null. */
    sum->initial_error_m = (double)NAN;
    sum->nodes_min = CDPR_MAX_SEGMENTS;
    sum->nodes_max = 0;
    for (int j = 0; j < n_cables && j < CDPR_MAX_CABLES; ++j) {
        rec->du_limit[j] = sc->rig.cable[j].winch.a_max_m_per_s2 * sc->period_s;
        rec->u_limit[j] = sc->rig.cable[j].winch.u_max_m_per_s;
    }
    if (out_dir == NULL) {
        return CDPR_OK;
    }
    if (cdpr_fs_mkdir_p(out_dir) != CDPR_OK) {
        snprintf(err->msg, sizeof err->msg, "%s: cannot create directory: %s", out_dir,
                 strerror(errno));
        return CDPR_E_IO;
    }
    char *path = rec->csv_path;
    if (cdpr_fs_path(path, sizeof rec->csv_path, out_dir, "timeseries.csv") != CDPR_OK) {
        snprintf(err->msg, sizeof err->msg, "%s/timeseries.csv: path too long", out_dir);
        return CDPR_E_IO;
    }
    if (cdpr_csv_open(&rec->csv, path) != CDPR_OK) {
        snprintf(err->msg, sizeof err->msg, "%s: cannot write: %s", path, strerror(errno));
        return CDPR_E_IO;
    }
    rec->csv_open = 1;
    csv_provenance(&rec->csv, sc, &sum->prov);
    csv_header(&rec->csv, n_cables);
    return CDPR_OK;
}

/* The lap statistics: a lap is stored when the first period of the next lap arrives (so the
 * last, unfinished lap is not); time going back (a plant restart seen by a tracker) starts
 * the laps again without storing the interrupted one. */
static void lap_period(cdpr_record_t *rec, double t_s, const sample_t *smp)
{
    const long lap = cdpr_traj_lap(&rec->traj, t_s);
    if (lap != rec->lap) {
        cdpr_summary_t *sum = rec->sum;
        if (rec->lap >= 0 && lap > rec->lap && rec->lap_n > 0 &&
            sum->n_laps < CDPR_SUMMARY_MAX_LAPS) {
            const double n = (double)rec->lap_n;
            sum->lap_rms_m[sum->n_laps] = sqrt(rec->lap_sum2_pos / n);
            sum->lap_rms_rad[sum->n_laps] = sqrt(rec->lap_sum2_rot / n);
            sum->lap_max_m[sum->n_laps] = rec->lap_max;
            sum->n_laps++;
        }
        rec->lap = lap;
        rec->lap_sum2_pos = 0.0;
        rec->lap_sum2_rot = 0.0;
        rec->lap_max = 0.0;
        rec->lap_n = 0;
    }
    if (lap >= 0) {
        rec->lap_sum2_pos += smp->epos_m * smp->epos_m;
        rec->lap_sum2_rot += smp->erot_rad * smp->erot_rad;
        rec->lap_max = fmax(rec->lap_max, smp->epos_m);
        rec->lap_n++;
    }
}

cdpr_status_t cdpr_record_period(cdpr_record_t *rec, long k, int last, const cdpr_record_row_t *row)
{
    cdpr_summary_t *sum = rec->sum;
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
    if (row->t_s >= rec->transfer_s) {
        rec->sum2_pos_after += smp.epos_m * smp.epos_m;
        rec->n_after++;
    }
    lap_period(rec, row->t_s, &smp);
    sum->max_error_m = fmax(sum->max_error_m, smp.epos_m);
    sum->max_error_rad = fmax(sum->max_error_rad, smp.erot_rad);
    sum->final_error_m = smp.epos_m;
    sum->final_error_rad = smp.erot_rad;
    for (int j = 0; j < nc; ++j) {
        const double a = row->tension_cabin_N[j];
        const double b = row->tension_winch_N[j];
        sum->max_tension_N = fmax(sum->max_tension_N, fmax(a, b));
        sum->min_tension_N = fmin(sum->min_tension_N, fmin(a, b));
        sum->cable_max_tension_N[j] = fmax(sum->cable_max_tension_N[j], fmax(a, b));
        sum->cable_min_tension_N[j] = fmin(sum->cable_min_tension_N[j], fmin(a, b));
        sum->nodes_min = (row->segments[j] < sum->nodes_min) ? row->segments[j] : sum->nodes_min;
        sum->nodes_max = (row->segments[j] > sum->nodes_max) ? row->segments[j] : sum->nodes_max;
    }
    /* Node events from the segment counts (a period seen again, e.g. a resent state, adds
     * nothing new). */
    if (rec->prev_k < 0 || k > rec->prev_k) {
        for (int j = 0; j < nc && rec->prev_k >= 0; ++j) {
            const int d = row->segments[j] - rec->prev_segments[j];
            if (d > 0) {
                rec->seg_insertions += (unsigned long)d;
            } else if (d < 0) {
                rec->seg_removals += (unsigned long)-d;
            }
        }
        if (rec->prev_k >= 0) {
            rec->missed += k - rec->prev_k - 1;
        }
        for (int j = 0; j < nc; ++j) {
            /* The winch limited the rate (cdpr_winch_update): a change of a_max T from the
             * period before, or the speed limit (to 1e-9 relative: the clamp's arithmetic). */
            const double u = row->payout_m_per_s[j];
            const int next = (rec->prev_k >= 0 && k == rec->prev_k + 1) ? 1 : 0;
            if ((next != 0 && fabs(u - rec->prev_payout[j]) >= rec->du_limit[j] * (1.0 - 1e-9)) ||
                fabs(u) >= rec->u_limit[j] * (1.0 - 1e-9)) {
                sum->rate_limited_periods[j]++;
            }
            rec->prev_payout[j] = u;
            rec->prev_segments[j] = row->segments[j];
            /* A slack period: either end of cable j without tension. */
            if (!(row->tension_cabin_N[j] > 0.0) || !(row->tension_winch_N[j] > 0.0)) {
                sum->slack_periods[j]++;
            }
        }
        rec->prev_k = k;
    }
    sum->periods = k;
    sum->sim_time_s = row->t_s;
    if (rec->csv_open == 0) {
        return CDPR_OK;
    }
    /* A row when t_k reaches the next output instant (not k % every: a period may be unseen). */
    if (k > rec->last_row_k && (k >= rec->next_row_k || last != 0)) {
        csv_row(rec, row, &smp);
        rec->last_row_k = k;
        rec->next_row_k = (k / rec->every + 1) * rec->every;
    }
    return (rec->csv.failed != 0) ? CDPR_E_IO : CDPR_OK;
}

void cdpr_record_tracker_counts(const cdpr_tracker_t *tr, cdpr_summary_t *sum)
{
    for (int j = 0; j < tr->model.p.n_cables && j < CDPR_MAX_CABLES; ++j) {
        sum->slack_demand_periods[j] = tr->slack_demand_periods[j];
    }
    sum->first_slack_demand_cable = tr->first_slack_cable + 1;
    sum->learning_updates = tr->learning_updates;
    sum->learning_saturations = tr->learning_saturations;
    sum->first_slack_demand_t_s = (tr->first_slack_cable >= 0) ? tr->first_slack_t_s : (double)NAN;
    sum->first_slack_demand_N =
        (tr->first_slack_cable >= 0) ? tr->first_slack_tension_N : (double)NAN;
}

void cdpr_record_node_events(const cdpr_record_t *rec, unsigned long *insertions,
                             unsigned long *removals, long *missed)
{
    *insertions = rec->seg_insertions;
    *removals = rec->seg_removals;
    if (missed != NULL) {
        *missed = rec->missed;
    }
}

cdpr_status_t cdpr_record_close(cdpr_record_t *rec)
{
    cdpr_summary_t *sum = rec->sum;
    sum->rms_error_m = (rec->n > 0) ? sqrt(rec->sum2_pos / (double)rec->n) : 0.0;
    sum->rms_error_rad = (rec->n > 0) ? sqrt(rec->sum2_rot / (double)rec->n) : 0.0;
    sum->rms_error_second_half_m =
        (rec->n_late > 0) ? sqrt(rec->sum2_pos_late / (double)rec->n_late) : 0.0;
    sum->rms_error_after_transfer_m =
        (rec->n_after > 0) ? sqrt(rec->sum2_pos_after / (double)rec->n_after) : 0.0;
    if (!isfinite(sum->min_tension_N)) {
        sum->min_tension_N = 0.0;
    }
    for (int j = 0; j < CDPR_MAX_CABLES; ++j) { /* no period recorded: 0, as the totals */
        sum->cable_max_tension_N[j] =
            isfinite(sum->cable_max_tension_N[j]) ? sum->cable_max_tension_N[j] : 0.0;
        sum->cable_min_tension_N[j] =
            isfinite(sum->cable_min_tension_N[j]) ? sum->cable_min_tension_N[j] : 0.0;
    }
    if (rec->csv_open != 0) {
        (void)cdpr_csv_close(&rec->csv);
        rec->csv_open = 0;
    }
    return (rec->csv.failed != 0) ? CDPR_E_IO : CDPR_OK;
}

int cdpr_record_errno(const cdpr_record_t *rec)
{
    return (rec->csv.failed != 0) ? rec->csv.error : 0;
}

void cdpr_record_io_error(const cdpr_record_t *rec, cdpr_scenario_error_t *err)
{
    const int e = cdpr_record_errno(rec);
    snprintf(err->msg, sizeof err->msg, "%s: write failed: %s",
             (rec->csv_path[0] != '\0') ? rec->csv_path : "timeseries.csv",
             (e != 0) ? strerror(e) : "unknown error");
}
