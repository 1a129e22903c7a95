/* SPDX-License-Identifier: BSD-3-Clause */
/// @file summary.c
/// summary.json writer and reader, and the end-of-run block (summary.h).
#include "cdpr/host/summary.h"

#include <errno.h>
#include <math.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "cdpr/version.h"
#include "cdpr/host/csv.h"
#include "cdpr/host/fs.h"
#include "cdpr/host/yaml.h"

/* CMAKE_BUILD_TYPE of this library (lib/host/CMakeLists.txt). */
#ifndef CDPR_HOST_BUILD_TYPE
#define CDPR_HOST_BUILD_TYPE ""
#endif

/* 1 unless the count is CDPR_SUMMARY_UNKNOWN. */
#define KNOWN(count) (((count) != CDPR_SUMMARY_UNKNOWN) ? 1 : 0)

/* The status names summary.json writes ("failed" is also what an unknown name reads as). */
static const cyaml_strval_t status_names[] = {
    {"ok", CDPR_SUMMARY_OK},
    {"warnings", CDPR_SUMMARY_WARNINGS},
    {"interrupted", CDPR_SUMMARY_INTERRUPTED},
    {"io_error", CDPR_SUMMARY_IO_ERROR},
    {"failed", CDPR_SUMMARY_FAILED},
};

const char *cdpr_summary_status_name(cdpr_summary_status_t st)
{
    return cdpr_yaml_enum_name(status_names, CYAML_ARRAY_LEN(status_names), st, "failed");
}

/* ---------------------------------------------------------------- writing summary.json */

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

/* A string value, or null when it is "" (unknown). */
static void json_string_or_null(FILE *f, const char *s)
{
    if (s[0] == '\0') {
        fputs("null", f);
    } else {
        json_string(f, s);
    }
}

void cdpr_summary_provenance_init(cdpr_summary_provenance_t *prov, const char *scenario_path,
                                  const char *robot_path, const cdpr_plant_params_t *pp)
{
    memset(prov, 0, sizeof *prov);
    snprintf(prov->version, sizeof prov->version, "%s", CDPR_VERSION_STRING);
    snprintf(prov->git_describe, sizeof prov->git_describe, "%s", CDPR_GIT_DESCRIBE);
    snprintf(prov->build_type, sizeof prov->build_type, "%s", CDPR_HOST_BUILD_TYPE);
    if (scenario_path != NULL && scenario_path[0] != '\0') {
        (void)cdpr_sha256_file(scenario_path, prov->scenario_sha256);
    }
    if (robot_path != NULL && robot_path[0] != '\0') {
        (void)cdpr_sha256_file(robot_path, prov->robot_sha256);
    }
    if (pp != NULL) {
        const char *name = cdpr_plant_integrator_name(pp->integrator);
        if (name != NULL) {
            snprintf(prov->integrator, sizeof prov->integrator, "%s", name);
        } else {
            snprintf(prov->integrator, sizeof prov->integrator, "integrator-%d",
                     (int)pp->integrator);
        }
    }
}

/* Close a written summary. Every fprintf/fputc into it left its failure in the stream's error
 * flag; a full device shows at the flush: check the flag, the flush and the close, keep the
 * first errno. A regular file that could not be written whole is emptied (the reader then says
 * "empty file"), never left as torn JSON; the directory entry is left alone (the path may be a
 * device or a link). CDPR_OK or CDPR_E_IO with errno set. */
static cdpr_status_t close_summary(FILE *f)
{
    int e = 0;
    if (fflush(f) != 0 || ferror(f) != 0) {
        e = (errno != 0) ? errno : EIO;
        struct stat sb;
        if (fstat(fileno(f), &sb) == 0 && S_ISREG(sb.st_mode)) {
            (void)ftruncate(fileno(f), 0);
        }
    }
    if (fclose(f) != 0 && e == 0) {
        e = (errno != 0) ? errno : EIO;
    }
    if (e != 0) {
        errno = e;
        return CDPR_E_IO;
    }
    return CDPR_OK;
}

/* A per-cable count list ("key": [c1, ...]), or null when the cable count is unknown. */
void cdpr_summary_plant_unknown(cdpr_summary_t *sum)
{
    sum->capacity_hits = CDPR_SUMMARY_UNKNOWN;
    sum->substep_limit_hits = CDPR_SUMMARY_UNKNOWN;
    sum->min_length_periods = CDPR_SUMMARY_UNKNOWN;
    sum->steps_accepted = CDPR_SUMMARY_UNKNOWN;
    sum->steps_rejected = CDPR_SUMMARY_UNKNOWN;
    sum->rhs_evals = CDPR_SUMMARY_UNKNOWN;
    sum->max_rhs_per_period = CDPR_SUMMARY_UNKNOWN;
    sum->max_err_norm = (double)NAN;
    sum->err_above_one_periods = CDPR_SUMMARY_UNKNOWN;
    sum->settle_steps = -1;
    sum->settle_wall_time_s = (double)NAN;
}

cdpr_status_t cdpr_summary_write_laps(const char *path, const cdpr_summary_t *sum)
{
    cdpr_csv_t csv;
    if (sum->n_laps <= 0) {
        return CDPR_OK;
    }
    if (cdpr_csv_open(&csv, path) != CDPR_OK) {
        return CDPR_E_IO;
    }
    static const char *const head[] = {"lap", "rms_m", "max_m", "rms_rad"};
    for (size_t i = 0; i < sizeof head / sizeof head[0]; ++i) {
        cdpr_csv_name(&csv, head[i]);
    }
    cdpr_csv_end_row(&csv);
    for (int i = 0; i < sum->n_laps && i < CDPR_SUMMARY_MAX_LAPS; ++i) {
        cdpr_csv_num(&csv, (double)(i + 1));
        cdpr_csv_num(&csv, sum->lap_rms_m[i]);
        cdpr_csv_num(&csv, sum->lap_max_m[i]);
        cdpr_csv_num(&csv, sum->lap_rms_rad[i]);
        cdpr_csv_end_row(&csv);
    }
    if (cdpr_csv_close(&csv) != CDPR_OK) {
        errno = (csv.error != 0) ? csv.error : EIO;
        return CDPR_E_IO;
    }
    return CDPR_OK;
}

/* A list of n reals (%.17g; [] for none). */
static void write_reals(FILE *f, const char *key, int n, const double *v)
{
    fprintf(f, ",\n  \"%s\": [", key);
    for (int i = 0; i < n && i < CDPR_SUMMARY_MAX_LAPS; ++i) {
        fprintf(f, "%s%.17g", (i == 0) ? "" : ", ", v[i]);
    }
    fputc(']', f);
}

/* A per-cable list of reals (%.17g; null when the cable count is unknown). */
static void write_cable_reals(FILE *f, const char *key, int n, const double *v)
{
    if (n <= 0 || n > CDPR_MAX_CABLES) {
        fprintf(f, ",\n  \"%s\": null", key);
    } else {
        write_reals(f, key, n, v);
    }
}

static void write_counts(FILE *f, const char *key, int n, const unsigned long *c)
{
    fprintf(f, ",\n  \"%s\": ", key);
    if (n <= 0 || n > CDPR_MAX_CABLES) {
        fputs("null", f);
        return;
    }
    for (int j = 0; j < n; ++j) {
        fprintf(f, "%s%lu", (j == 0) ? "[" : ", ", c[j]);
    }
    fputc(']', f);
}

/* ---- the resolved parameters ("parameters": what the run used, every default applied) */

typedef struct {
    const char *k;
    double v;
} kv_t;

/* "key": value (%.17g, null if not finite), with the separator before all but the first. */
static void json_num(FILE *f, int *first, const char *key, double v)
{
    fprintf(f, "%s\"%s\": ", (*first != 0) ? "" : ", ", key);
    *first = 0;
    if (isfinite(v)) {
        fprintf(f, "%.17g", v);
    } else {
        fputs("null", f);
    }
}

static void json_nums(FILE *f, int *first, const kv_t *kv, size_t n)
{
    for (size_t i = 0; i < n; ++i) {
        json_num(f, first, kv[i].k, kv[i].v);
    }
}

static void json_vec(FILE *f, int *first, const char *key, const double *v, int n)
{
    fprintf(f, "%s\"%s\": [", (*first != 0) ? "" : ", ", key);
    *first = 0;
    for (int i = 0; i < n; ++i) {
        fprintf(f, "%s%.17g", (i == 0) ? "" : ", ", v[i]);
    }
    fputc(']', f);
}

/* The robot record (sc->rig) as the run built it. */
static void write_robot_parameters(FILE *f, const cdpr_rig_t *rig)
{
    int first = 1;
    fprintf(f, ",\n    \"robot\": {\"n_cables\": %d", rig->n_cables);
    first = 0;
    json_num(f, &first, "gravity_m_per_s2", rig->gravity_m_per_s2);
    json_num(f, &first, "air_density_kg_per_m3", (double)rig->cable[0].rope.rho_air_kg_per_m3);
    json_vec(f, &first, "wind_m_per_s", rig->wind_m_per_s, 3);
    json_vec(f, &first, "nominal_pose", rig->nominal_pose, 6);
    fprintf(f, ",\n      \"cabin\": {");
    first = 1;
    json_num(f, &first, "mass_kg", rig->cabin_mass_kg);
    fprintf(f, ", \"inertia_kg_m2\": [");
    for (int i = 0; i < 3; ++i) {
        const double *row = rig->cabin_inertia_kg_m2[i];
        fprintf(f, "%s[%.17g, %.17g, %.17g]", (i == 0) ? "" : ", ", row[0], row[1], row[2]);
    }
    fputc(']', f);
    json_vec(f, &first, "com_m", rig->cabin_com_m, 3);
    fprintf(f, "},\n      \"cables\": [");
    for (int j = 0; j < rig->n_cables && j < CDPR_MAX_CABLES; ++j) {
        const cdpr_rig_cable_t *c = &rig->cable[j];
        const cdpr_cable_params_t *r = &c->rope;
        const cdpr_winch_params_t *w = &c->winch;
        fprintf(f, "%s\n        {", (j == 0) ? "" : ",");
        first = 1;
        json_vec(f, &first, "exit_m", c->exit_m, 3);
        json_vec(f, &first, "attach_m", c->attach_m, 3);
        fprintf(f, ", \"segments\": %d, \"rope\": {", c->segments);
        first = 1;
        const kv_t rope[] = {
            {"d0_m", (double)r->d0_m},
            {"rho_kg_per_m", (double)r->rho_kg_per_m},
            {"ea_N", (double)r->ea_N},
            {"damping_Ns", (double)r->damping_Ns},
            {"damping_ratio", (double)r->damping_ratio},
            {"damping_ref_hz", (double)r->damping_ref_hz},
            {"cd", (double)r->cd},
            {"cm", (double)r->cm},
        };
        json_nums(f, &first, rope, sizeof rope / sizeof rope[0]);
        fprintf(f, "}, \"winch\": {");
        first = 1;
        const kv_t winch[] = {
            {"u_max_m_per_s", (double)w->u_max_m_per_s},
            {"a_max_m_per_s2", (double)w->a_max_m_per_s2},
            {"kp_per_s", (double)w->kp_per_s},
            {"min_length_m", (double)w->min_length_m},
        };
        json_nums(f, &first, winch, sizeof winch / sizeof winch[0]);
        fprintf(f, "}}");
    }
    fprintf(f, "]}");
}

/* "parameters": the resolved values of the run (robot, wind section, controller, integrator,
 * run settings), so that a results table can say what each case ran. */
static void write_parameters(FILE *f, const cdpr_scenario_t *sc)
{
    fprintf(f, ",\n  \"parameters\": {\"segments_initial\": %d", cdpr_scenario_segments(sc));
    write_robot_parameters(f, &sc->rig);
    int first = 1;
    const cdpr_scenario_wind_t *w = &sc->wind;
    if (w->given == 0) {
        fprintf(f, ",\n    \"wind\": null");
    } else {
        fprintf(f, ",\n    \"wind\": {\"profile\": ");
        json_string(f, cdpr_wind_profile_name(w->profile));
        first = 0;
        const kv_t wind[] = {
            {"speed_m_per_s", w->speed_m_per_s},
            {"towards_deg", w->towards_deg},
            {"start_s", w->start_s},
            {"rise_s", w->rise_s},
            {"gust_m_per_s", w->gust_m_per_s},
        };
        json_nums(f, &first, wind, sizeof wind / sizeof wind[0]);
        fputc('}', f);
    }
    const cdpr_tracker_gains_t *g = &sc->gains;
    fprintf(f, ",\n    \"controller\": {");
    first = 1;
    const kv_t gains[] = {
        {"kp", (double)g->kp},
        {"kd_s", (double)g->kd_s},
        {"k_length_per_s", (double)g->k_length_per_s},
        {"filter_s", (double)g->filter_s},
        {"inertial_ff", (double)g->inertial_ff},
        {"damping_N_s_per_m", (double)g->damping_N_s_per_m},
        {"damping_rot_N_m_s", (double)g->damping_rot_N_m_s},
        {"transfer_s", (double)g->transfer_s},
        {"transfer_from_rest", (double)g->transfer_from_rest},
        {"wind_ff", (double)g->wind_ff},
        {"tension_gain_m_per_s_per_N", (double)g->tension_gain_m_per_s_per_N},
        {"tension_filter_s", (double)g->tension_filter_s},
        {"learning_gain", (double)g->learning_gain},
        {"learning_lead_s", (double)g->learning_lead_s},
        {"learning_cutoff_hz", (double)g->learning_cutoff_hz},
        {"learning_limit_m", (double)g->learning_limit_m},
        {"learning_settle_laps", (double)g->learning_settle_laps},
    };
    json_nums(f, &first, gains, sizeof gains / sizeof gains[0]);
    const cdpr_scenario_integrator_t *in = &sc->integrator;
    fprintf(f, "},\n    \"integrator\": {\"method\": ");
    json_string(f, cdpr_plant_integrator_name(in->method));
    first = 0;
    const kv_t integ[] = {
        {"rtol", in->rtol},
        {"atol_position_m", in->atol_position_m},
        {"atol_velocity_m_per_s", in->atol_velocity_m_per_s},
        {"atol_quaternion", in->atol_quaternion},
        {"atol_rate_rad_per_s", in->atol_rate_rad_per_s},
        {"h_max_s", in->h_max_s},
        {"max_trials", (double)in->max_trials},
        {"max_attempts", (double)in->max_attempts},
        {"substeps", (double)in->substeps},
    };
    json_nums(f, &first, integ, sizeof integ / sizeof integ[0]);
    fprintf(f, "},\n    \"run\": {");
    first = 1;
    const kv_t run[] = {
        {"duration_s", sc->duration_s},
        {"period_s", sc->period_s},
        {"output_rate_hz", sc->output_rate_hz},
    };
    json_nums(f, &first, run, sizeof run / sizeof run[0]);
    fprintf(f, "}}");
}

/* The real-time plant's figures, "rt_*" keys (null when not known). */
static void write_rt(FILE *f, const cdpr_summary_rt_t *rt)
{
    const struct {
        const char *k;
        double v;
        int whole;
    } v[] = {
        {"rt_seq", (double)rt->seq, 1},
        {"rt_periods", (double)rt->periods, 1},
        {"rt_deadline_misses", (double)rt->deadline_misses, 1},
        {"rt_startup_misses", (double)rt->startup_misses, 1},
        {"rt_misses_late_wakeup", (double)rt->misses_late_wakeup, 1},
        {"rt_misses_preempted", (double)rt->misses_preempted, 1},
        {"rt_misses_long_compute", (double)rt->misses_long_compute, 1},
        {"rt_misses_in_row_max", (double)rt->misses_in_row_max, 1},
        {"rt_overrun_stop", (double)rt->overrun_stop, 1},
        {"rt_compute_us_p99", rt->compute_us_p99, 0},
        {"rt_compute_us_max", rt->compute_us_max, 0},
        {"rt_cpu_us_p99", rt->cpu_us_p99, 0},
        {"rt_cpu_us_max", rt->cpu_us_max, 0},
        {"rt_wake_late_us_max", rt->wake_late_us_max, 0},
    };
    for (size_t i = 0; i < sizeof v / sizeof v[0]; ++i) {
        if (rt->known == 0 || !isfinite(v[i].v)) {
            fprintf(f, ",\n  \"%s\": null", v[i].k);
        } else if (v[i].whole != 0) {
            fprintf(f, ",\n  \"%s\": %.0f", v[i].k, v[i].v);
        } else {
            fprintf(f, ",\n  \"%s\": %.17g", v[i].k, v[i].v);
        }
    }
}

cdpr_status_t cdpr_summary_write(const char *path, const cdpr_scenario_t *sc,
                                 const cdpr_summary_t *sum)
{
    FILE *f = cdpr_fs_fopen(path, "w", NULL, 0);
    if (f == NULL) {
        return CDPR_E_IO;
    }
    errno = 0;
    const cdpr_summary_provenance_t *pv = &sum->prov;
    fprintf(f, "{\n  \"version\": ");
    json_string_or_null(f, pv->version);
    fprintf(f, ",\n  \"git_describe\": ");
    json_string_or_null(f, pv->git_describe);
    fprintf(f, ",\n  \"build_type\": ");
    json_string_or_null(f, pv->build_type);
    fprintf(f, ",\n  \"scenario\": ");
    json_string(f, sc->path);
    fprintf(f, ",\n  \"scenario_sha256\": ");
    json_string_or_null(f, pv->scenario_sha256);
    fprintf(f, ",\n  \"robot\": ");
    json_string(f, cdpr_scenario_robot_name(sc));
    fprintf(f, ",\n  \"robot_sha256\": ");
    json_string_or_null(f, pv->robot_sha256);
    fprintf(f, ",\n  \"trajectory\": ");
    json_string(f, cdpr_traj_type_name(sc->traj.type));
    fprintf(f, ",\n  \"integrator\": ");
    json_string_or_null(f, pv->integrator);
    fprintf(f, ",\n  \"status\": ");
    json_string(f, cdpr_summary_status_name(sum->status));
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
        {"rms_error_after_transfer_m", sum->rms_error_after_transfer_m},
        {"first_slack_demand_t_s", sum->first_slack_demand_t_s},
        {"first_slack_demand_N", sum->first_slack_demand_N},
        {"max_err_norm", sum->max_err_norm},
    };
    for (size_t i = 0; i < sizeof nums / sizeof nums[0]; ++i) {
        /* JSON has no NaN or infinity: a non-finite value is not known. */
        if (isfinite(nums[i].v)) {
            fprintf(f, ",\n  \"%s\": %.17g", nums[i].k, nums[i].v);
        } else {
            fprintf(f, ",\n  \"%s\": null", nums[i].k);
        }
    }
    const struct {
        const char *k;
        long v;
        int known;
    } ints[] = {
        {"node_insertions", (long)sum->node_insertions, KNOWN(sum->node_insertions)},
        {"node_removals", (long)sum->node_removals, KNOWN(sum->node_removals)},
        {"capacity_hits", (long)sum->capacity_hits, KNOWN(sum->capacity_hits)},
        {"substep_limit_hits", (long)sum->substep_limit_hits, KNOWN(sum->substep_limit_hits)},
        {"ik_failures", (long)sum->ik_failures, KNOWN(sum->ik_failures)},
        {"min_length_periods", (long)sum->min_length_periods, KNOWN(sum->min_length_periods)},
        {"nodes_min", (long)sum->nodes_min, 1},
        {"nodes_max", (long)sum->nodes_max, 1},
        {"periods", sum->periods, 1},
        {"steps_accepted", (long)sum->steps_accepted, KNOWN(sum->steps_accepted)},
        {"steps_rejected", (long)sum->steps_rejected, KNOWN(sum->steps_rejected)},
        {"rhs_evals", (long)sum->rhs_evals, KNOWN(sum->rhs_evals)},
        {"max_rhs_per_period", (long)sum->max_rhs_per_period, KNOWN(sum->max_rhs_per_period)},
        {"substeps", (long)sum->substeps, (sum->substeps > 0) ? 1 : 0},
        {"err_above_one_periods", (long)sum->err_above_one_periods,
         KNOWN(sum->err_above_one_periods)},
        {"settle_steps", sum->settle_steps, (sum->settle_steps >= 0) ? 1 : 0},
        {"segments", (long)cdpr_scenario_segments(sc), 1},
        {"first_slack_demand_cable", (long)sum->first_slack_demand_cable,
         (sum->first_slack_demand_cable > 0) ? 1 : 0},
        {"learning_updates", (long)sum->learning_updates, KNOWN(sum->learning_updates)},
        {"learning_saturations", (long)sum->learning_saturations, KNOWN(sum->learning_saturations)},
    };
    for (size_t i = 0; i < sizeof ints / sizeof ints[0]; ++i) {
        if (ints[i].known != 0) {
            fprintf(f, ",\n  \"%s\": %ld", ints[i].k, ints[i].v);
        } else {
            fprintf(f, ",\n  \"%s\": null", ints[i].k);
        }
    }
    write_rt(f, &sum->rt);
    write_counts(f, "rate_limited_periods", sum->n_cables, sum->rate_limited_periods);
    write_counts(f, "slack_periods", sum->n_cables, sum->slack_periods);
    write_counts(f, "slack_demand_periods", sum->n_cables, sum->slack_demand_periods);
    write_cable_reals(f, "cable_max_tension_N", sum->n_cables, sum->cable_max_tension_N);
    write_cable_reals(f, "cable_min_tension_N", sum->n_cables, sum->cable_min_tension_N);
    write_reals(f, "lap_rms_m", sum->n_laps, sum->lap_rms_m);
    write_reals(f, "lap_max_m", sum->n_laps, sum->lap_max_m);
    write_reals(f, "lap_rms_rad", sum->n_laps, sum->lap_rms_rad);
    write_parameters(f, sc);
    fprintf(f, "\n}\n");
    return close_summary(f);
}

/* ---------------------------------------------------------------- reading summary.json */

/* Every number may be null (a pointer left NULL); the provenance strings may also be missing
 * (files written before they existed). */
typedef struct {
    char *status;
    char *version, *git_describe, *build_type, *scenario_sha256, *robot_sha256, *integrator;
    double *rms_error_m, *max_error_m, *final_error_m, *initial_error_m, *rms_error_second_half_m;
    double *rms_error_rad, *max_error_rad, *final_error_rad;
    double *max_tension_N, *min_tension_N, *max_payout_m_per_s, *sim_time_s, *wall_time_s;
    double *settle_wall_time_s, *rms_error_after_transfer_m, *first_slack_demand_t_s;
    double *first_slack_demand_N, *first_slack_demand_cable;
    double *node_insertions, *node_removals, *capacity_hits, *substep_limit_hits, *ik_failures;
    double *min_length_periods, *nodes_min, *nodes_max, *periods, *steps_accepted;
    double *steps_rejected, *rhs_evals, *settle_steps, *learning_updates, *learning_saturations;
    double *max_rhs_per_period, *substeps, *max_err_norm, *err_above_one_periods;
    double *rt_seq, *rt_periods, *rt_deadline_misses, *rt_startup_misses, *rt_misses_late_wakeup;
    double *rt_misses_preempted, *rt_misses_long_compute, *rt_misses_in_row_max;
    double *rt_overrun_stop, *rt_compute_us_p99, *rt_compute_us_max, *rt_cpu_us_p99;
    double *rt_cpu_us_max, *rt_wake_late_us_max;
} raw_summary_t;

#define SUM_NUM(key)                                                                               \
    CYAML_FIELD_FLOAT_PTR(#key, CYAML_FLAG_STRICT | CYAML_FLAG_POINTER_NULL_STR, raw_summary_t, key)
#define SUM_OPT_NUM(key)                                                                           \
    CYAML_FIELD_FLOAT_PTR(#key,                                                                    \
                          CYAML_FLAG_STRICT | CYAML_FLAG_OPTIONAL | CYAML_FLAG_POINTER_NULL_STR,   \
                          raw_summary_t, key)
#define SUM_OPT_STR(key)                                                                           \
    CYAML_FIELD_STRING_PTR(#key, CYAML_FLAG_OPTIONAL | CYAML_FLAG_POINTER_NULL_STR, raw_summary_t, \
                           key, 0, 255)

static const cyaml_schema_field_t summary_fields[] = {
    CYAML_FIELD_STRING_PTR("status", CYAML_FLAG_DEFAULT, raw_summary_t, status, 0, 63),
    SUM_OPT_STR(version),
    SUM_OPT_STR(git_describe),
    SUM_OPT_STR(build_type),
    SUM_OPT_STR(scenario_sha256),
    SUM_OPT_STR(robot_sha256),
    SUM_OPT_STR(integrator),
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
    SUM_OPT_NUM(settle_wall_time_s),
    SUM_OPT_NUM(rms_error_after_transfer_m),
    SUM_OPT_NUM(first_slack_demand_t_s),
    SUM_OPT_NUM(first_slack_demand_N),
    SUM_OPT_NUM(first_slack_demand_cable),
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
    SUM_OPT_NUM(learning_updates),
    SUM_OPT_NUM(learning_saturations),
    SUM_OPT_NUM(max_rhs_per_period),
    SUM_OPT_NUM(substeps),
    SUM_OPT_NUM(max_err_norm),
    SUM_OPT_NUM(err_above_one_periods),
    SUM_OPT_NUM(rt_seq),
    SUM_OPT_NUM(rt_periods),
    SUM_OPT_NUM(rt_deadline_misses),
    SUM_OPT_NUM(rt_startup_misses),
    SUM_OPT_NUM(rt_misses_late_wakeup),
    SUM_OPT_NUM(rt_misses_preempted),
    SUM_OPT_NUM(rt_misses_long_compute),
    SUM_OPT_NUM(rt_misses_in_row_max),
    SUM_OPT_NUM(rt_overrun_stop),
    SUM_OPT_NUM(rt_compute_us_p99),
    SUM_OPT_NUM(rt_compute_us_max),
    SUM_OPT_NUM(rt_cpu_us_p99),
    SUM_OPT_NUM(rt_cpu_us_max),
    SUM_OPT_NUM(rt_wake_late_us_max),
    CYAML_FIELD_END,
};
static const cyaml_schema_value_t summary_schema = {
    CYAML_VALUE_MAPPING(CYAML_FLAG_POINTER, raw_summary_t, summary_fields),
};

/* A number, NaN for null. */
static double real_or_nan(const double *v)
{
    return (v != NULL) ? *v : (double)NAN;
}

/* A count, CDPR_SUMMARY_UNKNOWN for null (or a value no count can have). */
static unsigned long count_or_unknown(const double *v)
{
    return (v != NULL && *v >= 0.0 && *v < (double)CDPR_SUMMARY_UNKNOWN) ? (unsigned long)*v
                                                                         : CDPR_SUMMARY_UNKNOWN;
}

static void string_or_empty(char *dst, size_t cap, const char *v)
{
    snprintf(dst, cap, "%s", (v != NULL) ? v : "");
}

/* The real-time block: known when its state seq is (a file of a batch run, or written before
 * the block existed, has none). */
static void rt_from_raw(const raw_summary_t *r, cdpr_summary_rt_t *rt)
{
    memset(rt, 0, sizeof *rt);
    if (r->rt_seq == NULL || !(*r->rt_seq >= 0.0)) {
        return;
    }
    rt->known = 1;
    rt->seq = (long)*r->rt_seq;
    rt->periods = (r->rt_periods != NULL) ? (long)*r->rt_periods : -1;
    rt->deadline_misses = count_or_unknown(r->rt_deadline_misses);
    rt->startup_misses = count_or_unknown(r->rt_startup_misses);
    rt->misses_late_wakeup = count_or_unknown(r->rt_misses_late_wakeup);
    rt->misses_preempted = count_or_unknown(r->rt_misses_preempted);
    rt->misses_long_compute = count_or_unknown(r->rt_misses_long_compute);
    rt->misses_in_row_max = count_or_unknown(r->rt_misses_in_row_max);
    rt->overrun_stop = (r->rt_overrun_stop != NULL && *r->rt_overrun_stop > 0.0) ? 1 : 0;
    rt->compute_us_p99 = real_or_nan(r->rt_compute_us_p99);
    rt->compute_us_max = real_or_nan(r->rt_compute_us_max);
    rt->cpu_us_p99 = real_or_nan(r->rt_cpu_us_p99);
    rt->cpu_us_max = real_or_nan(r->rt_cpu_us_max);
    rt->wake_late_us_max = real_or_nan(r->rt_wake_late_us_max);
}

static void from_raw(const raw_summary_t *r, cdpr_summary_t *sum)
{
    memset(sum, 0, sizeof *sum);
    sum->status = (cdpr_summary_status_t)cdpr_yaml_enum_value(
        status_names, CYAML_ARRAY_LEN(status_names), r->status, CDPR_SUMMARY_FAILED);
    cdpr_summary_provenance_t *pv = &sum->prov;
    string_or_empty(pv->version, sizeof pv->version, r->version);
    string_or_empty(pv->git_describe, sizeof pv->git_describe, r->git_describe);
    string_or_empty(pv->build_type, sizeof pv->build_type, r->build_type);
    string_or_empty(pv->scenario_sha256, sizeof pv->scenario_sha256, r->scenario_sha256);
    string_or_empty(pv->robot_sha256, sizeof pv->robot_sha256, r->robot_sha256);
    string_or_empty(pv->integrator, sizeof pv->integrator, r->integrator);
    sum->rms_error_m = real_or_nan(r->rms_error_m);
    sum->max_error_m = real_or_nan(r->max_error_m);
    sum->final_error_m = real_or_nan(r->final_error_m);
    sum->initial_error_m = real_or_nan(r->initial_error_m);
    sum->rms_error_second_half_m = real_or_nan(r->rms_error_second_half_m);
    sum->rms_error_rad = real_or_nan(r->rms_error_rad);
    sum->max_error_rad = real_or_nan(r->max_error_rad);
    sum->final_error_rad = real_or_nan(r->final_error_rad);
    sum->max_tension_N = real_or_nan(r->max_tension_N);
    sum->min_tension_N = real_or_nan(r->min_tension_N);
    sum->max_payout_m_per_s = real_or_nan(r->max_payout_m_per_s);
    sum->sim_time_s = real_or_nan(r->sim_time_s);
    sum->wall_time_s = real_or_nan(r->wall_time_s);
    sum->settle_wall_time_s = real_or_nan(r->settle_wall_time_s);
    sum->rms_error_after_transfer_m = real_or_nan(r->rms_error_after_transfer_m);
    sum->first_slack_demand_t_s = real_or_nan(r->first_slack_demand_t_s);
    sum->first_slack_demand_N = real_or_nan(r->first_slack_demand_N);
    sum->first_slack_demand_cable =
        (r->first_slack_demand_cable != NULL) ? (int)*r->first_slack_demand_cable : 0;
    sum->node_insertions = count_or_unknown(r->node_insertions);
    sum->node_removals = count_or_unknown(r->node_removals);
    sum->capacity_hits = count_or_unknown(r->capacity_hits);
    sum->substep_limit_hits = count_or_unknown(r->substep_limit_hits);
    sum->ik_failures = count_or_unknown(r->ik_failures);
    sum->min_length_periods = count_or_unknown(r->min_length_periods);
    sum->learning_updates = count_or_unknown(r->learning_updates);
    sum->learning_saturations = count_or_unknown(r->learning_saturations);
    sum->nodes_min = (r->nodes_min != NULL) ? (int)*r->nodes_min : -1;
    sum->nodes_max = (r->nodes_max != NULL) ? (int)*r->nodes_max : -1;
    sum->periods = (r->periods != NULL) ? (long)*r->periods : -1;
    sum->steps_accepted = count_or_unknown(r->steps_accepted);
    sum->steps_rejected = count_or_unknown(r->steps_rejected);
    sum->rhs_evals = count_or_unknown(r->rhs_evals);
    sum->max_rhs_per_period = count_or_unknown(r->max_rhs_per_period);
    sum->substeps = (r->substeps != NULL && *r->substeps >= 1.0 &&
                     *r->substeps <= (double)CDPR_PLANT_MAX_SUBSTEPS)
                        ? (int)*r->substeps
                        : 0;
    sum->max_err_norm = (r->max_err_norm != NULL) ? *r->max_err_norm : (double)NAN;
    sum->err_above_one_periods = count_or_unknown(r->err_above_one_periods);
    sum->settle_steps = (r->settle_steps != NULL) ? (long)*r->settle_steps : -1;
    rt_from_raw(r, &sum->rt);
}

cdpr_status_t cdpr_summary_read(const char *path, cdpr_summary_t *sum, cdpr_scenario_error_t *err)
{
    cdpr_yaml_log_t lg;
    void *data = NULL;
    const cdpr_status_t st =
        cdpr_yaml_load(path, &summary_schema, CYAML_CFG_IGNORE_UNKNOWN_KEYS, &data, &lg);
    if (st != CDPR_OK) {
        char why[512];
        snprintf(err->msg, sizeof err->msg, "%s: %s", path,
                 (lg.empty != 0) ? "empty file" : cdpr_yaml_first_error(&lg, why, sizeof why));
        return st;
    }
    from_raw(data, sum);
    cdpr_yaml_free(&summary_schema, data);
    return CDPR_OK;
}

/* ---------------------------------------------------------------- the end-of-run block */

/* The per-cable slack counts of the plant (recorded periods) and of the feed-forward. */
static void print_slack(FILE *f, const cdpr_summary_t *s)
{
    if (fabs(s->rms_error_after_transfer_m - s->rms_error_m) > 0.0) {
        fprintf(f, "  after transfer  rms %.4g m (t >= controller.transfer_s)\n",
                s->rms_error_after_transfer_m);
    }
    if (s->n_cables <= 0 || s->n_cables > CDPR_MAX_CABLES) {
        return;
    }
    const unsigned long *lists[3] = {s->slack_periods, s->slack_demand_periods,
                                     s->rate_limited_periods};
    static const char *const names[3] = {"  slack periods  ", "; feed-forward demands",
                                         "  rate-limited    "};
    for (int k = 0; k < 3; ++k) {
        fputs(names[k], f);
        for (int j = 0; j < s->n_cables; ++j) {
            fprintf(f, "%s%lu", (j == 0) ? " " : "/", lists[k][j]);
        }
        fputs((k == 1) ? " (cables 1..n)\n" : "", f);
    }
    fputs(" (periods the winch's acceleration or speed limit set the rate)\n", f);
    if (s->first_slack_demand_cable > 0) {
        fprintf(f, "  first slack demand: cable %d at t = %.4g s (%.4g N on the chords)\n",
                s->first_slack_demand_cable, s->first_slack_demand_t_s, s->first_slack_demand_N);
    }
    if (s->learning_updates != CDPR_SUMMARY_UNKNOWN && s->learning_updates > 0) {
        fprintf(f, "  learning        %lu laps learned, %lu knot values at the limit\n",
                s->learning_updates, s->learning_saturations);
    }
}

/* RMS position error per complete lap (periodic trajectories), at most 12 shown. */
static void print_laps(FILE *f, const cdpr_summary_t *s)
{
    if (s->n_laps <= 0) {
        return;
    }
    fprintf(f, "  per lap (%d)     rms", s->n_laps);
    const int more = (s->n_laps > 12) ? 1 : 0;
    const int shown = (more != 0) ? 12 : s->n_laps;
    for (int i = 0; i < shown; ++i) {
        fprintf(f, " %.3g", s->lap_rms_m[i]);
    }
    fprintf(f, "%s m; last lap %.4g m\n", (more != 0) ? " ..." : "", s->lap_rms_m[s->n_laps - 1]);
}

/* The real-time plant's work per period and its overruns, when known. */
static void print_rt(FILE *f, const cdpr_summary_rt_t *rt)
{
    if (rt->known == 0) {
        return;
    }
    fprintf(f,
            "  real time       plant as of state %ld: work per period p99 %.0f us CPU, %.0f us "
            "wall (max %.0f / %.0f us)\n",
            rt->seq, rt->cpu_us_p99, rt->compute_us_p99, rt->cpu_us_max, rt->compute_us_max);
    fprintf(f,
            "  overruns        %lu deadline misses: %lu in the start-up; then %lu late "
            "wake-ups, %lu preempted, %lu long computations (most in a row %lu)%s\n",
            rt->deadline_misses, rt->startup_misses, rt->misses_late_wakeup, rt->misses_preempted,
            rt->misses_long_compute, rt->misses_in_row_max,
            (rt->overrun_stop != 0) ? "; the overrun policy stopped the plant" : "");
}

void cdpr_summary_print(FILE *f, const char *title, const cdpr_summary_t *s)
{
    fprintf(f, "%s: %s%s%s\n", title, cdpr_summary_status_name(s->status),
            (s->message[0] != '\0') ? " - " : "", s->message);
    char initial[32];
    if (isfinite(s->initial_error_m)) {
        snprintf(initial, sizeof initial, "%.4g m", s->initial_error_m);
    } else {
        snprintf(initial, sizeof initial, "unknown: state 0 not seen");
    }
    fprintf(f,
            "  tracking error  rms %.4g m, max %.4g m, final %.4g m (initial %s); "
            "attitude rms %.1f mrad, max %.1f mrad\n",
            s->rms_error_m, s->max_error_m, s->final_error_m, initial, 1e3 * s->rms_error_rad,
            1e3 * s->max_error_rad);
    fprintf(f, "  tensions        %.4g .. %.4g N;  payout |u| <= %.3g m/s\n", s->min_tension_N,
            s->max_tension_N, s->max_payout_m_per_s);
    if (s->node_insertions != CDPR_SUMMARY_UNKNOWN && s->node_removals != CDPR_SUMMARY_UNKNOWN) {
        fprintf(f, "  node events     %lu insertions, %lu removals (segments %d..%d per cable)\n",
                s->node_insertions, s->node_removals, s->nodes_min, s->nodes_max);
    } else {
        fprintf(f, "  node events     unknown (segments %d..%d per cable)\n", s->nodes_min,
                s->nodes_max);
    }
    if (s->rhs_evals != CDPR_SUMMARY_UNKNOWN && s->rhs_evals > 0 &&
        s->steps_accepted != CDPR_SUMMARY_UNKNOWN && s->steps_rejected != CDPR_SUMMARY_UNKNOWN &&
        s->substep_limit_hits != CDPR_SUMMARY_UNKNOWN) {
        fprintf(f,
                "  integrator      %lu steps, %lu rejected, %lu substep-limit periods, "
                "%lu IK failures\n",
                s->steps_accepted, s->steps_rejected, s->substep_limit_hits, s->ik_failures);
        if (s->substeps > 0 && s->err_above_one_periods != CDPR_SUMMARY_UNKNOWN) {
            fprintf(f,
                    "  fixed cost      %d substeps, %lu RHS in every period (most %lu); error "
                    "norm max %.3g, above 1 in %lu periods\n",
                    s->substeps, 4UL * (unsigned long)s->substeps, s->max_rhs_per_period,
                    s->max_err_norm, s->err_above_one_periods);
        }
    } else {
        fprintf(f, "  controller      %lu IK failures (the plant's integrator ran elsewhere)\n",
                s->ik_failures);
    }
    print_slack(f, s);
    print_laps(f, s);
    print_rt(f, &s->rt);
    if (isfinite(s->settle_wall_time_s)) {
        fprintf(f, "  time            %.3g s simulated in %.3g s wall (settling %.3g s)\n",
                s->sim_time_s, s->wall_time_s, s->settle_wall_time_s);
    } else {
        fprintf(f, "  time            %.3g s simulated in %.3g s wall\n", s->sim_time_s,
                s->wall_time_s);
    }
}
