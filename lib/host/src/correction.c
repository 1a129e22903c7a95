/* SPDX-License-Identifier: BSD-3-Clause */
/// @file correction.c
/// Length pre-compensation files (correction.h): hashes, YAML write and read, the checks.
#include "cdpr/host/correction.h"

#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "cdpr/statics.h"
#include "cdpr/host/plant.h"
#include "cdpr/host/rig.h"
#include "cdpr/host/yaml.h"

/* ---------------------------------------------------------------- hashes */

/* Canonical text: "name=v1,v2,...;" with every number as %.9g (see correction.h). */
static void put(cdpr_sha256_t *h, const char *name, const double *v, int n)
{
    char buf[64];
    cdpr_sha256_update(h, name, strlen(name));
    cdpr_sha256_update(h, "=", 1U);
    for (int i = 0; i < n; ++i) {
        const int k = snprintf(buf, sizeof buf, "%s%.9g", (i > 0) ? "," : "", v[i]);
        cdpr_sha256_update(h, buf, (size_t)k);
    }
    cdpr_sha256_update(h, ";", 1U);
}

static void put1(cdpr_sha256_t *h, const char *name, double v)
{
    put(h, name, &v, 1);
}

static void finish(cdpr_sha256_t *h, char hex[CDPR_SHA256_HEX + 1])
{
    unsigned char d[CDPR_SHA256_BYTES];
    cdpr_sha256_final(h, d);
    cdpr_sha256_hex(d, hex);
}

static void hash_trajectory(const cdpr_traj_t *t, char hex[CDPR_SHA256_HEX + 1])
{
    cdpr_sha256_t h;
    cdpr_sha256_init(&h);
    put1(&h, "type", (double)t->type);
    put(&h, "hold_pose", t->hold_pose, 6);
    put(&h, "centre_m", t->centre_m, 3);
    put1(&h, "radius_m", t->radius_m);
    put1(&h, "speed_m_per_s", t->speed_m_per_s);
    put1(&h, "start_angle_rad", t->start_angle_rad);
    put1(&h, "direction", t->direction);
    put1(&h, "ramp_s", t->ramp_s);
    put(&h, "attitude_rad", t->attitude_rad, 3);
    put(&h, "from", t->from, 6);
    put(&h, "to", t->to, 6);
    put1(&h, "duration_s", t->duration_s);
    put1(&h, "pause_s", t->pause_s);
    put1(&h, "back_and_forth", (double)t->back_and_forth);
    put1(&h, "cycles", (double)t->cycles);
    finish(&h, hex);
}

static void hash_robot(const cdpr_scenario_t *sc, char hex[CDPR_SHA256_HEX + 1])
{
    cdpr_rig_t rig = sc->rig;
    cdpr_rig_scale(&rig, &sc->controller_model); /* what the controller knows */
    cdpr_sha256_t h;
    cdpr_sha256_init(&h);
    put1(&h, "n_cables", (double)rig.n_cables);
    for (int j = 0; j < rig.n_cables; ++j) {
        const cdpr_rig_cable_t *c = &rig.cable[j];
        const cdpr_cable_params_t *r = &c->rope;
        const cdpr_winch_params_t *w = &c->winch;
        const double v[] = {c->exit_m[0],
                            c->exit_m[1],
                            c->exit_m[2],
                            c->attach_m[0],
                            c->attach_m[1],
                            c->attach_m[2],
                            r->d0_m,
                            r->rho_kg_per_m,
                            r->ea_N,
                            r->damping_Ns,
                            r->damping_ratio,
                            r->damping_ref_hz,
                            r->cd,
                            r->cm,
                            r->rho_air_kg_per_m3,
                            (double)r->slack_law,
                            w->u_max_m_per_s,
                            w->a_max_m_per_s2,
                            w->kp_per_s,
                            w->min_length_m};
        put(&h, "cable", v, (int)(sizeof v / sizeof v[0]));
    }
    put1(&h, "cabin_mass_kg", rig.cabin_mass_kg);
    put(&h, "cabin_inertia_kg_m2", &rig.cabin_inertia_kg_m2[0][0], 9);
    put(&h, "cabin_com_m", rig.cabin_com_m, 3);
    put1(&h, "gravity_m_per_s2", rig.gravity_m_per_s2);
    put(&h, "wind_m_per_s", rig.wind_m_per_s, 3);
    const double td[] = {(double)rig.has_tension_distribution, rig.tension_min_N, rig.tension_max_N,
                         rig.tension_ref_N};
    put(&h, "tension_distribution", td, 4);
    finish(&h, hex);
}

/* Every gain below, but wind_m_per_s (the steady wind is the robot's: hash_robot) and the
 * correction itself. A gain added to cdpr_tracker_gains_t breaks this build until it is hashed
 * here (and counted in the check). Gains added after the file format's first release join the
 * hash only when set (> 0), so a correction made before they existed stays valid for a
 * controller that does not use them. */
typedef char cdpr_every_gain_hashed[(sizeof(cdpr_tracker_gains_t) ==
                                     (20U * sizeof(cdpr_real_t)) + sizeof(cdpr_vec3_t) +
                                         sizeof(long) + sizeof(const cdpr_tracker_correction_t *))
                                        ? 1
                                        : -1];

static void hash_controller(const cdpr_tracker_gains_t *g, char hex[CDPR_SHA256_HEX + 1])
{
    const double v[] = {g->kp,
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
                        g->learning_gain,
                        g->learning_lead_s,
                        g->learning_cutoff_hz,
                        g->learning_limit_m,
                        (double)g->learning_settle_laps,
                        g->transfer_from_rest,
                        g->integral_per_s,
                        g->integral_limit_m,
                        g->weight_estimate_s};
    cdpr_sha256_t h;
    cdpr_sha256_init(&h);
    put(&h, "gains", v, (int)(sizeof v / sizeof v[0]));
    if (g->tension_washout_s > 0.0) {
        put1(&h, "tension_washout_s", g->tension_washout_s);
    }
    finish(&h, hex);
}

void cdpr_correction_hashes(const cdpr_scenario_t *sc, char traj[CDPR_SHA256_HEX + 1],
                            char robot[CDPR_SHA256_HEX + 1], char controller[CDPR_SHA256_HEX + 1])
{
    hash_trajectory(&sc->traj, traj);
    hash_robot(sc, robot);
    hash_controller(&sc->gains, controller);
}

/* A report that knows nothing: NaN figures, no model runs, made for the plant as written. */
static void report_unknown(cdpr_correction_report_t *r)
{
    r->iterations = 0;
    r->rms_before_m = (double)NAN;
    r->rms_after_m = (double)NAN;
    r->max_after_m = (double)NAN;
    r->max_after_rad = (double)NAN;
    r->min_tension_N = (double)NAN;
    r->robust_mass = 0.0;
    r->robust_ea = 0.0;
    r->varied_rms_after_m = (double)NAN;
    r->varied_max_after_m = (double)NAN;
    r->varied_max_after_rad = (double)NAN;
    r->varied_min_tension_N = (double)NAN;
}

cdpr_status_t cdpr_correction_init(cdpr_host_correction_t *hc, const cdpr_scenario_t *sc,
                                   int n_coef, double start_s, double spacing_s)
{
    if (n_coef < 1 || n_coef > CDPR_CORRECTION_MAX_COEF || !(spacing_s > 0.0) ||
        !isfinite(spacing_s) || !isfinite(start_s)) {
        return CDPR_E_OUT_OF_RANGE;
    }
    (void)memset(hc, 0, sizeof *hc);
    cdpr_correction_hashes(sc, hc->trajectory_sha256, hc->robot_sha256, hc->controller_sha256);
    hc->c.n_cables = sc->rig.n_cables;
    hc->c.n_coef = n_coef;
    hc->c.start_s = start_s;
    hc->c.spacing_s = spacing_s;
    hc->c.period_s = sc->period_s;
    hc->c.coef_m = hc->coef_m;
    report_unknown(&hc->report);
    hc->floor_N = CDPR_CORRECTION_FLOOR_N;
    return CDPR_OK;
}

/* ---------------------------------------------------------------- write */

/* The error's text, when the caller wants it. */
#define SET_ERR(err, ...)                                                                          \
    do {                                                                                           \
        if ((err) != NULL) {                                                                       \
            (void)snprintf((err)->msg, sizeof(err)->msg, __VA_ARGS__);                             \
        }                                                                                          \
    } while (0)

static void write_body(FILE *f, const cdpr_host_correction_t *hc, const char *note)
{
    const cdpr_correction_report_t *r = &hc->report;
    fprintf(f, "# SPDX-License-Identifier: BSD-3-Clause\n");
    fprintf(f, "# Length pre-compensation c_j(t) for the controller's step 4c (cdpr-precomp;\n");
    fprintf(f, "# docs/scenarios.md \"Pre-compensation\"): cubic B-spline coefficients [m]\n");
    fprintf(f, "# per cable. Tied to its scenario by the hashes below: regenerate, do not edit.\n");
    if (note != NULL && note[0] != '\0') {
        fprintf(f, "# %s\n", note);
    }
    fprintf(f, "format: %s\n", CDPR_CORRECTION_FORMAT);
    fprintf(f, "trajectory_sha256: \"%s\"\n", hc->trajectory_sha256);
    fprintf(f, "robot_sha256: \"%s\"\n", hc->robot_sha256);
    fprintf(f, "controller_sha256: \"%s\"\n", hc->controller_sha256);
    fprintf(f, "period_s: %.17g\n", (double)hc->c.period_s);
    fprintf(f, "start_s: %.17g\n", (double)hc->c.start_s);
    fprintf(f, "spacing_s: %.17g\n", (double)hc->c.spacing_s);
    fprintf(f, "floor_N: %.17g\n", hc->floor_N);
    fprintf(f, "report:                # how it was made (unknown values left out)\n");
    fprintf(f, "  iterations: %d\n", r->iterations);
    /* the varied plants' entries only for a robust correction */
    const double robust = (r->robust_mass > 0.0 || r->robust_ea > 0.0) ? 1.0 : (double)NAN;
    const double rv[] = {r->rms_before_m,
                         r->rms_after_m,
                         r->max_after_m,
                         r->max_after_rad,
                         r->min_tension_N,
                         robust * r->robust_mass,
                         robust * r->robust_ea,
                         robust * r->varied_rms_after_m,
                         robust * r->varied_max_after_m,
                         robust * r->varied_max_after_rad,
                         robust * r->varied_min_tension_N};
    static const char *const rn[] = {
        "rms_before_m",       "rms_after_m",          "max_after_m",         "max_after_rad",
        "min_tension_N",      "robust_mass",          "robust_ea",           "varied_rms_after_m",
        "varied_max_after_m", "varied_max_after_rad", "varied_min_tension_N"};
    for (size_t i = 0; i < sizeof rv / sizeof rv[0]; ++i) {
        if (isfinite(rv[i])) {
            fprintf(f, "  %s: %.6g\n", rn[i], rv[i]);
        }
    }
    fprintf(f, "cables:\n");
    for (int j = 0; j < hc->c.n_cables; ++j) {
        fprintf(f, "  - coef_m: [");
        for (int i = 0; i < hc->c.n_coef; ++i) {
            fprintf(f, "%s%.17g", (i == 0) ? "" : ((i % 6 == 0) ? ",\n      " : ", "),
                    (double)hc->coef_m[(long)j * hc->c.n_coef + i]);
        }
        fprintf(f, "]\n");
    }
}

cdpr_status_t cdpr_correction_write(const char *path, const cdpr_host_correction_t *hc,
                                    const char *note, cdpr_scenario_error_t *err)
{
    char tmp[1100];
    const int n = snprintf(tmp, sizeof tmp, "%s.tmp", path);
    if (n < 0 || (size_t)n >= sizeof tmp) {
        SET_ERR(err, "%s: path too long", path);
        return CDPR_E_IO;
    }
    FILE *f = fopen(tmp, "w");
    if (f == NULL) {
        SET_ERR(err, "%s: cannot write: %s", tmp, strerror(errno));
        return CDPR_E_IO;
    }
    write_body(f, hc, note);
    int e = (ferror(f) != 0 || fflush(f) != 0) ? errno : 0;
    if (e == 0 && fsync(fileno(f)) != 0) {
        e = errno;
    }
    if (fclose(f) != 0 && e == 0) {
        e = errno;
    }
    if (e == 0 && rename(tmp, path) != 0) {
        e = errno;
    }
    if (e != 0) {
        (void)unlink(tmp);
        SET_ERR(err, "%s: write failed: %s (the old file, if any, is unchanged)", path,
                strerror(e));
        return CDPR_E_IO;
    }
    return CDPR_OK;
}

/* ---------------------------------------------------------------- read */

typedef struct {
    double *coef_m;
    unsigned coef_m_count;
} raw_cable_t;

typedef struct {
    double *iterations;
    double *rms_before_m;
    double *rms_after_m;
    double *max_after_m;
    double *max_after_rad;
    double *min_tension_N;
    double *robust_mass;
    double *robust_ea;
    double *varied_rms_after_m;
    double *varied_max_after_m;
    double *varied_max_after_rad;
    double *varied_min_tension_N;
} raw_report_t;

typedef struct {
    char *format;
    char *trajectory_sha256;
    char *robot_sha256;
    char *controller_sha256;
    double period_s;
    double start_s;
    double spacing_s;
    double floor_N;
    raw_report_t *report;
    raw_cable_t *cables;
    unsigned cables_count;
} raw_corr_t;

/* Strict numbers: "4O.0" is not a number, overflow is an error (cdpr_yaml_load). The report's
 * values may be NaN (.nan: unknown). */
static const cyaml_schema_value_t num = {CYAML_VALUE_FLOAT(CYAML_FLAG_STRICT, double)};
#define OPT_NUMP(key, member)                                                                      \
    CYAML_FIELD_FLOAT_PTR(key, CYAML_FLAG_OPTIONAL | CYAML_FLAG_STRICT, raw_report_t, member)
static const cyaml_schema_field_t report_fields[] = {
    OPT_NUMP("iterations", iterations),
    OPT_NUMP("rms_before_m", rms_before_m),
    OPT_NUMP("rms_after_m", rms_after_m),
    OPT_NUMP("max_after_m", max_after_m),
    OPT_NUMP("max_after_rad", max_after_rad),
    OPT_NUMP("min_tension_N", min_tension_N),
    OPT_NUMP("robust_mass", robust_mass),
    OPT_NUMP("robust_ea", robust_ea),
    OPT_NUMP("varied_rms_after_m", varied_rms_after_m),
    OPT_NUMP("varied_max_after_m", varied_max_after_m),
    OPT_NUMP("varied_max_after_rad", varied_max_after_rad),
    OPT_NUMP("varied_min_tension_N", varied_min_tension_N),
    CYAML_FIELD_END,
};
static const cyaml_schema_field_t cable_fields[] = {
    CYAML_FIELD_SEQUENCE("coef_m", CYAML_FLAG_POINTER, raw_cable_t, coef_m, &num, 1,
                         CDPR_CORRECTION_MAX_COEF),
    CYAML_FIELD_END,
};
static const cyaml_schema_value_t cable_schema = {
    CYAML_VALUE_MAPPING(CYAML_FLAG_DEFAULT, raw_cable_t, cable_fields),
};
static const cyaml_schema_field_t corr_fields[] = {
    CYAML_FIELD_STRING_PTR("format", CYAML_FLAG_DEFAULT, raw_corr_t, format, 1, 64),
    CYAML_FIELD_STRING_PTR("trajectory_sha256", CYAML_FLAG_DEFAULT, raw_corr_t, trajectory_sha256,
                           CDPR_SHA256_HEX, CDPR_SHA256_HEX),
    CYAML_FIELD_STRING_PTR("robot_sha256", CYAML_FLAG_DEFAULT, raw_corr_t, robot_sha256,
                           CDPR_SHA256_HEX, CDPR_SHA256_HEX),
    CYAML_FIELD_STRING_PTR("controller_sha256", CYAML_FLAG_DEFAULT, raw_corr_t, controller_sha256,
                           CDPR_SHA256_HEX, CDPR_SHA256_HEX),
    CYAML_FIELD_FLOAT("period_s", CYAML_FLAG_STRICT, raw_corr_t, period_s),
    CYAML_FIELD_FLOAT("start_s", CYAML_FLAG_STRICT, raw_corr_t, start_s),
    CYAML_FIELD_FLOAT("spacing_s", CYAML_FLAG_STRICT, raw_corr_t, spacing_s),
    CYAML_FIELD_FLOAT("floor_N", CYAML_FLAG_STRICT, raw_corr_t, floor_N),
    CYAML_FIELD_MAPPING_PTR("report", CYAML_FLAG_OPTIONAL, raw_corr_t, report, report_fields),
    CYAML_FIELD_SEQUENCE("cables", CYAML_FLAG_POINTER, raw_corr_t, cables, &cable_schema, 1,
                         CDPR_MAX_CABLES),
    CYAML_FIELD_END,
};
static const cyaml_schema_value_t corr_schema = {
    CYAML_VALUE_MAPPING(CYAML_FLAG_POINTER, raw_corr_t, corr_fields),
};

/* "FILE:LINE: KEY: what" */
static void key_err(cdpr_scenario_error_t *err, const char *path, const char *key, const char *what)
{
    if (err != NULL) {
        cdpr_yaml_format_error(err->msg, sizeof err->msg, path, cdpr_yaml_path_line(path, key), key,
                               what);
    }
}

static double opt(const double *v)
{
    return (v != NULL) ? *v : (double)NAN;
}

static cdpr_status_t take_raw(const raw_corr_t *r, const char *path, cdpr_host_correction_t *hc,
                              cdpr_scenario_error_t *err)
{
    if (strcmp(r->format, CDPR_CORRECTION_FORMAT) != 0) {
        key_err(err, path, "format",
                "not '" CDPR_CORRECTION_FORMAT "' (not a correction file "
                "of this version)");
        return CDPR_E_PARSE;
    }
    const double v[4] = {r->period_s, r->spacing_s, r->start_s, r->floor_N};
    static const char *const names[4] = {"period_s", "spacing_s", "start_s", "floor_N"};
    for (int i = 0; i < 4; ++i) {
        if (!isfinite(v[i]) || (i < 2 && !(v[i] > 0.0)) || (i == 3 && v[i] < 0.0)) {
            key_err(err, path, names[i],
                    "must be a finite number (> 0 for a period or spacing, >= 0 for a floor)");
            return CDPR_E_OUT_OF_RANGE;
        }
    }
    const unsigned n_coef = r->cables[0].coef_m_count;
    (void)memset(hc, 0, sizeof *hc);
    for (unsigned j = 0; j < r->cables_count; ++j) {
        char key[64];
        snprintf(key, sizeof key, "cables[%u].coef_m", j);
        if (r->cables[j].coef_m_count != n_coef) {
            char what[128];
            snprintf(what, sizeof what, "%u coefficients, cable 1 has %u: every cable has as many",
                     r->cables[j].coef_m_count, n_coef);
            key_err(err, path, key, what);
            return CDPR_E_OUT_OF_RANGE;
        }
        for (unsigned i = 0; i < n_coef; ++i) {
            const double a = r->cables[j].coef_m[i];
            if (!isfinite(a) || fabs(a) > 10.0) {
                char what[128];
                snprintf(what, sizeof what, "coefficient %u is %g: must be finite, |a| <= 10 m",
                         i + 1U, a);
                key_err(err, path, key, what);
                return CDPR_E_OUT_OF_RANGE;
            }
            hc->coef_m[(size_t)j * n_coef + i] = (cdpr_real_t)a;
        }
    }
    hc->c.n_cables = (int)r->cables_count;
    hc->c.n_coef = (int)n_coef;
    hc->c.start_s = (cdpr_real_t)r->start_s;
    hc->c.spacing_s = (cdpr_real_t)r->spacing_s;
    hc->c.period_s = (cdpr_real_t)r->period_s;
    hc->c.coef_m = hc->coef_m;
    hc->floor_N = r->floor_N;
    snprintf(hc->trajectory_sha256, sizeof hc->trajectory_sha256, "%s", r->trajectory_sha256);
    snprintf(hc->robot_sha256, sizeof hc->robot_sha256, "%s", r->robot_sha256);
    snprintf(hc->controller_sha256, sizeof hc->controller_sha256, "%s", r->controller_sha256);
    const raw_report_t *rp = r->report;
    report_unknown(&hc->report);
    if (rp != NULL) {
        const double it = opt(rp->iterations);
        hc->report.iterations = (isfinite(it) && it >= 0.0 && it < 1e6) ? (int)it : 0;
        hc->report.rms_before_m = opt(rp->rms_before_m);
        hc->report.rms_after_m = opt(rp->rms_after_m);
        hc->report.max_after_m = opt(rp->max_after_m);
        hc->report.max_after_rad = opt(rp->max_after_rad);
        hc->report.min_tension_N = opt(rp->min_tension_N);
        /* absent: the correction was made for the plant as written (as every file before the
         * keys existed) */
        hc->report.robust_mass = (rp->robust_mass != NULL) ? *rp->robust_mass : 0.0;
        hc->report.robust_ea = (rp->robust_ea != NULL) ? *rp->robust_ea : 0.0;
        hc->report.varied_rms_after_m = opt(rp->varied_rms_after_m);
        hc->report.varied_max_after_m = opt(rp->varied_max_after_m);
        hc->report.varied_max_after_rad = opt(rp->varied_max_after_rad);
        hc->report.varied_min_tension_N = opt(rp->varied_min_tension_N);
    }
    return CDPR_OK;
}

cdpr_status_t cdpr_correction_read(const char *path, cdpr_host_correction_t *hc,
                                   cdpr_scenario_error_t *err)
{
    void *data = NULL;
    char msg[sizeof err->msg];
    const cdpr_status_t st = cdpr_yaml_load_reported(path, path, &corr_schema, "correction file",
                                                     &data, msg, sizeof msg);
    if (st != CDPR_OK) {
        SET_ERR(err, "%s", msg);
        return st;
    }
    const cdpr_status_t ts = take_raw((const raw_corr_t *)data, path, hc, err);
    cdpr_yaml_free(&corr_schema, data);
    return ts;
}

/* ---------------------------------------------------------------- check */

/* The slack demand (correction.h): at every knot of the support within the run. */
static cdpr_status_t check_slack(const cdpr_scenario_t *sc, const cdpr_host_correction_t *hc,
                                 const char *path, cdpr_scenario_error_t *err)
{
    cdpr_robot_params_t *model = malloc(sizeof *model);
    cdpr_tracker_t *tr = malloc(sizeof *tr);
    cdpr_status_t st = (model == NULL || tr == NULL) ? CDPR_E_CAPACITY : CDPR_OK;
    if (st == CDPR_OK) {
        st = cdpr_host_controller_params(sc, model, err);
    }
    cdpr_diag_t d;
    if (st == CDPR_OK) {
        cdpr_tracker_gains_t g = sc->gains;
        g.correction = NULL;
        st = cdpr_tracker_init(tr, model, &sc->traj, &g, sc->period_s, 0.0, &d);
        if (st != CDPR_OK) {
            SET_ERR(err, "%s: the controller's model: %s (%s)", path, cdpr_status_str(st), d.field);
        }
    }
    const cdpr_tracker_correction_t *c = &hc->c;
    const long n_knots = (long)c->n_coef + 4L;
    for (long i = 0; st == CDPR_OK && i < n_knots; ++i) {
        const double t = (double)c->start_s + (double)i * (double)c->spacing_s;
        if (t < 0.0 || t > sc->duration_s) {
            continue;
        }
        cdpr_traj_sample_t s;
        cdpr_traj_eval(&sc->traj, t, &s);
        cdpr_statics_result_t ik;
        cdpr_statics_result_t fw;
        const cdpr_vec3_t zero = cdpr_v3(0.0, 0.0, 0.0);
        st = cdpr_statics_ik_dist(&tr->model, &s.motion, zero, zero, NULL, &tr->ik_opts, &ik, NULL);
        cdpr_real_t len[CDPR_MAX_CABLES];
        for (int j = 0; st == CDPR_OK && j < c->n_cables; ++j) {
            len[j] = ik.cable[j].length_m + cdpr_tracker_correction_at(c, j, (cdpr_real_t)t);
        }
        if (st == CDPR_OK) {
            st = cdpr_statics_forward(&tr->model, len, &s.motion, &tr->ik_opts, &fw);
        }
        if (st != CDPR_OK) {
            SET_ERR(err,
                    "%s: the corrected lengths at t = %.6g s have no static equilibrium on the "
                    "controller's model (%s): a correction for another run, or one that pulls "
                    "the cabin out of the workspace",
                    path, t, cdpr_status_str(st));
            st = CDPR_E_INFEASIBLE;
            break;
        }
        for (int j = 0; j < c->n_cables; ++j) {
            const double lo = fmin(fw.cable[j].tension_cabin_N, fw.cable[j].tension_winch_N);
            if (!(lo >= hc->floor_N) || !(lo > 0.0)) {
                SET_ERR(err,
                        "%s: the correction demands a slack cable: cable %d at t = %.6g s "
                        "(c = %.4g m; cable-end tension %.4g N held statically, below the "
                        "file's floor_N %.4g N)",
                        path, j + 1, t, (double)(len[j] - ik.cable[j].length_m), lo, hc->floor_N);
                st = CDPR_E_INFEASIBLE;
                break;
            }
        }
    }
    free(model);
    free(tr);
    return st;
}

cdpr_status_t cdpr_correction_check(const cdpr_scenario_t *sc, const cdpr_host_correction_t *hc,
                                    const char *path, cdpr_scenario_error_t *err)
{
    char traj[CDPR_SHA256_HEX + 1];
    char robot[CDPR_SHA256_HEX + 1];
    char ctrl[CDPR_SHA256_HEX + 1];
    cdpr_correction_hashes(sc, traj, robot, ctrl);
    const char *const mine[3] = {hc->trajectory_sha256, hc->robot_sha256, hc->controller_sha256};
    const char *const theirs[3] = {traj, robot, ctrl};
    static const char *const what[3] = {"trajectory", "robot (the controller's model)",
                                        "controller gains"};
    for (int i = 0; i < 3; ++i) {
        if (strcmp(mine[i], theirs[i]) != 0) {
            SET_ERR(err,
                    "%s: made for another %s (its hash %.12s..., the scenario's %.12s...): "
                    "regenerate it with cdpr-precomp",
                    path, what[i], mine[i], theirs[i]);
            return CDPR_E_OUT_OF_RANGE;
        }
    }
    if (!(fabs((double)hc->c.period_s - sc->period_s) <= 1e-9 * sc->period_s)) {
        SET_ERR(err, "%s: made for a control period of %g s, the scenario's is %g s", path,
                (double)hc->c.period_s, sc->period_s);
        return CDPR_E_OUT_OF_RANGE;
    }
    if (hc->c.n_cables != sc->rig.n_cables) {
        SET_ERR(err, "%s: %d cables, the robot has %d", path, hc->c.n_cables, sc->rig.n_cables);
        return CDPR_E_OUT_OF_RANGE;
    }
    return check_slack(sc, hc, path, err);
}

cdpr_status_t cdpr_correction_for_scenario(const cdpr_scenario_t *sc, cdpr_host_correction_t *hc,
                                           const cdpr_tracker_correction_t **out,
                                           cdpr_scenario_error_t *err)
{
    *out = NULL;
    if (sc->precompensation[0] == '\0') {
        return CDPR_OK;
    }
    cdpr_scenario_error_t e;
    cdpr_status_t st = cdpr_correction_read(sc->precompensation, hc, &e);
    if (st == CDPR_OK) {
        st = cdpr_correction_check(sc, hc, sc->precompensation, &e);
    }
    if (st != CDPR_OK) {
        cdpr_scenario_error(sc, "controller.precompensation", e.msg, err);
        return st;
    }
    *out = &hc->c;
    return CDPR_OK;
}
