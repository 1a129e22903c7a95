/* SPDX-License-Identifier: BSD-3-Clause */
/// @file scenario.c
/// Scenario files through libcyaml: a schema of "raw" structs (optional keys are pointers, so
/// absence is visible), resolved onto a preset, then checked key by key.
#include "cdpr/host/scenario.h"

#include <cyaml/cyaml.h>
#include <limits.h>
#include <math.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cdpr/config.h"
#include "cdpr/host/yaml.h"
#include "rig_raw.h"

/* Defaults of the learning keys (docs/scenarios.md; used only with learning_gain > 0). */
#define CDPR_SCENARIO_LEARNING_CUTOFF_HZ 1.0
#define CDPR_SCENARIO_LEARNING_LIMIT_M   0.5
#define CDPR_SCENARIO_INTEGRAL_LIMIT_M   0.05

/* ---------------------------------------------------------------- raw (file) structs */

typedef struct {
    double *pose;
    double *offset;
} raw_initial_t;

typedef enum { DIR_CCW = 0, DIR_CW = 1 } raw_direction_t;

typedef struct {
    double centre_m[3];
    double radius_m;
    double speed_m_per_s;
    double start_angle_deg;
    raw_direction_t *direction;
    double *ramp_s;
    double *attitude_rad;
} raw_circle_t;

typedef struct {
    double from[6];
    double to[6];
    double duration_s;
    double *pause_s;
    bool *back_and_forth;
} raw_line_t;

typedef struct {
    double from[6];
    double to[6];
    double duration_s;
    double *pause_s;
    double *cycles; /* whole number, see segments */
} raw_cyclic_t;

typedef struct {
    double pose[6];
} raw_hold_t;

typedef struct {
    cdpr_traj_type_t type;
    raw_circle_t *circle;
    raw_line_t *line;
    raw_hold_t *hold;
    raw_cyclic_t *cyclic;
} raw_traj_t;

typedef struct {
    double *ea_scale; /* controller.model: the controller's model error (issue 22 item 4) */
    double *cabin_mass_scale;
    double *rope_mass_scale;
} raw_model_t;

typedef struct {
    double *period_s; /* not a controller key any more: reported as moved to run.period_s */
    double kp;
    double *kd_s;
    double k_length_per_s;
    double *filter_s;
    double *inertial_ff;
    double *damping_N_s_per_m;
    double *damping_rot_N_m_s;
    double *transfer_s;         /* issue 14: planned transfer, wind feed-forward */
    double *transfer_from_rest; /* 0 or 1 */
    double *wind_ff;
    double *tension_gain_m_per_s_per_N; /* issue 14 item 2: winch tension feedback */
    double *tension_filter_s;
    double *learning_gain; /* issue 14 item 3: learning over laps */
    double *learning_lead_s;
    double *learning_cutoff_hz;
    double *learning_limit_m;
    double *learning_settle_laps; /* whole number, see segments */
    double *integral_per_s;       /* issue 22 item 3: integral action */
    double *integral_limit_m;
    double *weight_estimate_s; /* issue 22 item 3: the cabin's weight from the tensions */
    double *tension_washout_s; /* issue 22 item 2: washout on the tension error */
    raw_model_t *model;
    char *precompensation; /* issue 22 item 1: a correction file (correction.h) */
} raw_controller_t;

typedef struct raw_integrator {
    double *rtol;
    double *atol_position_m;
    double *atol_velocity_m_per_s;
    double *atol_quaternion;
    double *atol_rate_rad_per_s;
    double *h_max_s;
    double *max_trials;   /* whole number, see segments */
    double *max_attempts; /* whole number */
    double *substeps;     /* whole number */
    cdpr_plant_integrator_t *method;
    struct raw_integrator *rkf45;    /* integrator.rkf45: settings when the method is rkf45 */
    struct raw_integrator *ros34pw2; /* integrator.ros34pw2: when it is ros34pw2 */
} raw_integrator_t;

typedef struct {
    double duration_s;
    double period_s;
    double *output_rate_hz;
} raw_run_t;

typedef struct {
    double speed_m_per_s;
    double towards_deg;
    cdpr_wind_profile_t *profile;
    double *start_s;
    double *rise_s;
    double *gust_m_per_s;
} raw_wind_t;

typedef struct {
    char *description;
    cdpr_raw_rig_t *robot; /* robot: one schema with robot files (rig_raw.h) */
    raw_initial_t *initial;
    raw_traj_t trajectory;
    raw_controller_t controller;
    raw_integrator_t *integrator;
    raw_run_t run;
    raw_wind_t *wind;
} raw_t;

/* ---------------------------------------------------------------- schema */

#define OPT                         CYAML_FLAG_OPTIONAL
#define REQ                         CYAML_FLAG_DEFAULT
#define OPT_NUM                     (CYAML_FLAG_OPTIONAL | CYAML_FLAG_STRICT)
#define REQ_NUM                     CYAML_FLAG_STRICT
#define OPT_SEQ                     (CYAML_FLAG_OPTIONAL | CYAML_FLAG_POINTER)
#define OPT_NUMP(key, type, member) CYAML_FIELD_FLOAT_PTR(key, OPT_NUM, type, member)
#define OPT_VEC(key, type, member, n)                                                              \
    CYAML_FIELD_SEQUENCE_FIXED(key, OPT_SEQ, type, member, &num, n)
#define REQ_VEC(key, type, member, n) CYAML_FIELD_SEQUENCE_FIXED(key, REQ, type, member, &num, n)

/* Sequence entries: strict floats (overflow such as 1e999 is an error, not Inf). */
static const cyaml_schema_value_t num = {CYAML_VALUE_FLOAT(CYAML_FLAG_STRICT, double)};

static const cyaml_strval_t traj_names[] = {
    {"hold", CDPR_TRAJ_HOLD},
    {"circle", CDPR_TRAJ_CIRCLE},
    {"line", CDPR_TRAJ_LINE},
    {"cyclic", CDPR_TRAJ_CYCLIC},
};
static const cyaml_strval_t direction_names[] = {
    {"ccw", DIR_CCW},
    {"cw", DIR_CW},
};

/* A preset's polar layout (cdpr_raw_polar_t; the height is the towers' exit height or the
 * attachments' z in body axes). */
static const cyaml_schema_field_t towers_fields[] = {
    OPT_NUMP("radius_m", cdpr_raw_polar_t, radius_m),
    OPT_NUMP("exit_height_m", cdpr_raw_polar_t, height_m),
    OPT_VEC("azimuths_deg", cdpr_raw_polar_t, azimuths_deg, 6),
    CYAML_FIELD_END,
};
static const cyaml_schema_field_t attach_fields[] = {
    OPT_NUMP("radius_m", cdpr_raw_polar_t, radius_m),
    OPT_NUMP("z_m", cdpr_raw_polar_t, height_m),
    OPT_VEC("azimuths_deg", cdpr_raw_polar_t, azimuths_deg, 6),
    CYAML_FIELD_END,
};
/* robot: the robot-file schema, plus a robot file, or a preset as the base of the other keys
 * with its polar layout. */
static const cyaml_schema_field_t robot_fields[] = {
    CYAML_FIELD_STRING_PTR("file", OPT, cdpr_raw_rig_t, file, 1, 4095),
    CYAML_FIELD_ENUM_PTR("preset", OPT | CYAML_FLAG_STRICT, cdpr_raw_rig_t, preset,
                         cdpr_preset_names, CDPR_PRESET_NAME_COUNT),
    CYAML_FIELD_MAPPING_PTR("towers", OPT, cdpr_raw_rig_t, towers, towers_fields),
    CYAML_FIELD_MAPPING_PTR("attachments", OPT, cdpr_raw_rig_t, attachments, attach_fields),
    CDPR_RIG_FIELDS,
    CYAML_FIELD_END,
};
static const cyaml_schema_field_t initial_fields[] = {
    OPT_VEC("pose", raw_initial_t, pose, 6),
    OPT_VEC("offset", raw_initial_t, offset, 6),
    CYAML_FIELD_END,
};
static const cyaml_schema_field_t circle_fields[] = {
    REQ_VEC("centre_m", raw_circle_t, centre_m, 3),
    CYAML_FIELD_FLOAT("radius_m", REQ_NUM, raw_circle_t, radius_m),
    CYAML_FIELD_FLOAT("speed_m_per_s", REQ_NUM, raw_circle_t, speed_m_per_s),
    CYAML_FIELD_FLOAT("start_angle_deg", REQ_NUM, raw_circle_t, start_angle_deg),
    CYAML_FIELD_ENUM_PTR("direction", OPT | CYAML_FLAG_STRICT, raw_circle_t, direction,
                         direction_names, CYAML_ARRAY_LEN(direction_names)),
    OPT_NUMP("ramp_s", raw_circle_t, ramp_s),
    OPT_VEC("attitude_rad", raw_circle_t, attitude_rad, 3),
    CYAML_FIELD_END,
};
static const cyaml_schema_field_t line_fields[] = {
    REQ_VEC("from", raw_line_t, from, 6),
    REQ_VEC("to", raw_line_t, to, 6),
    CYAML_FIELD_FLOAT("duration_s", REQ_NUM, raw_line_t, duration_s),
    OPT_NUMP("pause_s", raw_line_t, pause_s),
    CYAML_FIELD_BOOL_PTR("back_and_forth", OPT, raw_line_t, back_and_forth),
    CYAML_FIELD_END,
};
static const cyaml_schema_field_t cyclic_fields[] = {
    REQ_VEC("from", raw_cyclic_t, from, 6),
    REQ_VEC("to", raw_cyclic_t, to, 6),
    CYAML_FIELD_FLOAT("duration_s", REQ_NUM, raw_cyclic_t, duration_s),
    OPT_NUMP("pause_s", raw_cyclic_t, pause_s),
    OPT_NUMP("cycles", raw_cyclic_t, cycles),
    CYAML_FIELD_END,
};
static const cyaml_schema_field_t hold_fields[] = {
    REQ_VEC("pose", raw_hold_t, pose, 6),
    CYAML_FIELD_END,
};
static const cyaml_schema_field_t traj_fields[] = {
    CYAML_FIELD_ENUM("type", CYAML_FLAG_STRICT, raw_traj_t, type, traj_names,
                     CYAML_ARRAY_LEN(traj_names)),
    CYAML_FIELD_MAPPING_PTR("circle", OPT, raw_traj_t, circle, circle_fields),
    CYAML_FIELD_MAPPING_PTR("line", OPT, raw_traj_t, line, line_fields),
    CYAML_FIELD_MAPPING_PTR("hold", OPT, raw_traj_t, hold, hold_fields),
    CYAML_FIELD_MAPPING_PTR("cyclic", OPT, raw_traj_t, cyclic, cyclic_fields),
    CYAML_FIELD_END,
};
static const cyaml_schema_field_t model_fields[] = {
    OPT_NUMP("ea_scale", raw_model_t, ea_scale),
    OPT_NUMP("cabin_mass_scale", raw_model_t, cabin_mass_scale),
    OPT_NUMP("rope_mass_scale", raw_model_t, rope_mass_scale),
    CYAML_FIELD_END,
};
static const cyaml_schema_field_t controller_fields[] = {
    OPT_NUMP("period_s", raw_controller_t, period_s),
    CYAML_FIELD_FLOAT("kp", REQ_NUM, raw_controller_t, kp),
    OPT_NUMP("kd_s", raw_controller_t, kd_s),
    CYAML_FIELD_FLOAT("k_length_per_s", REQ_NUM, raw_controller_t, k_length_per_s),
    OPT_NUMP("filter_s", raw_controller_t, filter_s),
    OPT_NUMP("inertial_ff", raw_controller_t, inertial_ff),
    OPT_NUMP("damping_N_s_per_m", raw_controller_t, damping_N_s_per_m),
    OPT_NUMP("damping_rot_N_m_s", raw_controller_t, damping_rot_N_m_s),
    OPT_NUMP("transfer_s", raw_controller_t, transfer_s),
    OPT_NUMP("transfer_from_rest", raw_controller_t, transfer_from_rest),
    OPT_NUMP("wind_ff", raw_controller_t, wind_ff),
    OPT_NUMP("tension_gain_m_per_s_per_N", raw_controller_t, tension_gain_m_per_s_per_N),
    OPT_NUMP("tension_filter_s", raw_controller_t, tension_filter_s),
    OPT_NUMP("tension_washout_s", raw_controller_t, tension_washout_s),
    OPT_NUMP("learning_gain", raw_controller_t, learning_gain),
    OPT_NUMP("learning_lead_s", raw_controller_t, learning_lead_s),
    OPT_NUMP("learning_cutoff_hz", raw_controller_t, learning_cutoff_hz),
    OPT_NUMP("learning_limit_m", raw_controller_t, learning_limit_m),
    OPT_NUMP("learning_settle_laps", raw_controller_t, learning_settle_laps),
    OPT_NUMP("integral_per_s", raw_controller_t, integral_per_s),
    OPT_NUMP("integral_limit_m", raw_controller_t, integral_limit_m),
    OPT_NUMP("weight_estimate_s", raw_controller_t, weight_estimate_s),
    CYAML_FIELD_MAPPING_PTR("model", OPT, raw_controller_t, model, model_fields),
    CYAML_FIELD_STRING_PTR("precompensation", OPT, raw_controller_t, precompensation, 1, 4095),
    CYAML_FIELD_END,
};
static const cyaml_strval_t method_names[] = {
    {"rkf45", CDPR_PLANT_RKF45},
    {"ros34pw2", CDPR_PLANT_ROS34PW2},
    {"ros34pw2-fixed", CDPR_PLANT_ROS34PW2_FIXED},
};
/* The integrator section: the method, one subsection per method, then the settings. A
 * subsection (integrator.rkf45, integrator.ros34pw2) takes the same settings without method
 * and subsections: its schema is this array's tail from INTEGRATOR_SETTINGS on. */
#define INTEGRATOR_SETTINGS 3
static const cyaml_schema_field_t integrator_fields[] = {
    CYAML_FIELD_ENUM_PTR("method", OPT | CYAML_FLAG_STRICT, raw_integrator_t, method, method_names,
                         CYAML_ARRAY_LEN(method_names)),
    CYAML_FIELD_MAPPING_PTR("rkf45", OPT, raw_integrator_t, rkf45,
                            &integrator_fields[INTEGRATOR_SETTINGS]),
    CYAML_FIELD_MAPPING_PTR("ros34pw2", OPT, raw_integrator_t, ros34pw2,
                            &integrator_fields[INTEGRATOR_SETTINGS]),
    OPT_NUMP("rtol", raw_integrator_t, rtol), /* [INTEGRATOR_SETTINGS] */
    OPT_NUMP("atol_position_m", raw_integrator_t, atol_position_m),
    OPT_NUMP("atol_velocity_m_per_s", raw_integrator_t, atol_velocity_m_per_s),
    OPT_NUMP("atol_quaternion", raw_integrator_t, atol_quaternion),
    OPT_NUMP("atol_rate_rad_per_s", raw_integrator_t, atol_rate_rad_per_s),
    OPT_NUMP("h_max_s", raw_integrator_t, h_max_s),
    OPT_NUMP("max_trials", raw_integrator_t, max_trials),
    OPT_NUMP("max_attempts", raw_integrator_t, max_attempts),
    OPT_NUMP("substeps", raw_integrator_t, substeps),
    CYAML_FIELD_END,
};
static const cyaml_schema_field_t run_fields[] = {
    CYAML_FIELD_FLOAT("duration_s", REQ_NUM, raw_run_t, duration_s),
    CYAML_FIELD_FLOAT("period_s", REQ_NUM, raw_run_t, period_s),
    OPT_NUMP("output_rate_hz", raw_run_t, output_rate_hz),
    CYAML_FIELD_END,
};
static const cyaml_strval_t wind_profile_names[] = {
    {"steady", CDPR_WIND_STEADY},
    {"ramp", CDPR_WIND_RAMP},
    {"gust", CDPR_WIND_GUST},
};
static const cyaml_schema_field_t wind_fields[] = {
    CYAML_FIELD_FLOAT("speed_m_per_s", REQ_NUM, raw_wind_t, speed_m_per_s),
    CYAML_FIELD_FLOAT("towards_deg", REQ_NUM, raw_wind_t, towards_deg),
    CYAML_FIELD_ENUM_PTR("profile", OPT | CYAML_FLAG_STRICT, raw_wind_t, profile,
                         wind_profile_names, CYAML_ARRAY_LEN(wind_profile_names)),
    OPT_NUMP("start_s", raw_wind_t, start_s),
    OPT_NUMP("rise_s", raw_wind_t, rise_s),
    OPT_NUMP("gust_m_per_s", raw_wind_t, gust_m_per_s),
    CYAML_FIELD_END,
};
static const cyaml_schema_field_t top_fields[] = {
    CYAML_FIELD_STRING_PTR("description", OPT, raw_t, description, 0, 255),
    CYAML_FIELD_MAPPING_PTR("robot", REQ, raw_t, robot, robot_fields),
    CYAML_FIELD_MAPPING_PTR("initial", OPT, raw_t, initial, initial_fields),
    CYAML_FIELD_MAPPING("trajectory", REQ, raw_t, trajectory, traj_fields),
    CYAML_FIELD_MAPPING("controller", REQ, raw_t, controller, controller_fields),
    CYAML_FIELD_MAPPING_PTR("integrator", OPT, raw_t, integrator, integrator_fields),
    CYAML_FIELD_MAPPING("run", REQ, raw_t, run, run_fields),
    CYAML_FIELD_MAPPING_PTR("wind", OPT, raw_t, wind, wind_fields),
    CYAML_FIELD_END,
};
static const cyaml_schema_value_t top_schema = {
    CYAML_VALUE_MAPPING(CYAML_FLAG_POINTER, raw_t, top_fields),
};
/* ---------------------------------------------------------------- errors */

const char *cdpr_traj_type_name(cdpr_traj_type_t type)
{
    return cdpr_yaml_enum_name(traj_names, CYAML_ARRAY_LEN(traj_names), type, "hold");
}

const char *cdpr_wind_profile_name(cdpr_wind_profile_t profile)
{
    return cdpr_yaml_enum_name(wind_profile_names, CYAML_ARRAY_LEN(wind_profile_names), profile,
                               "steady");
}

static void format_error(cdpr_scenario_error_t *err, const char *path, int line, const char *key,
                         const char *what)
{
    if (path == NULL || path[0] == '\0') {
        snprintf(err->msg, sizeof err->msg, "scenario: %s: %s", key, what);
    } else if (line > 0) {
        snprintf(err->msg, sizeof err->msg, "%s:%d: %s: %s", path, line, key, what);
    } else {
        snprintf(err->msg, sizeof err->msg, "%s: %s: %s", path, key, what);
    }
}

void cdpr_scenario_error(const cdpr_scenario_t *sc, const char *key, const char *what,
                         cdpr_scenario_error_t *err)
{
    if (err == NULL) {
        return;
    }
    const char *path = (sc != NULL) ? sc->path : "";
    const int line = (path[0] != '\0') ? cdpr_yaml_key_line(path, key) : 0;
    format_error(err, path, line, key, what);
}

int cdpr_yaml_key_line(const char *path, const char *key)
{
    return cdpr_yaml_path_line(path, key);
}

/* ---------------------------------------------------------------- defaults and resolve */

static void defaults_common(cdpr_scenario_t *sc)
{
    sc->period_s = 0.01;
    sc->gains.kp = 1.0;
    sc->gains.kd_s = 0.0;
    sc->gains.k_length_per_s = 5.0;
    sc->gains.filter_s = 1.0;
    sc->gains.inertial_ff = 1.0;
    sc->gains.learning_cutoff_hz = CDPR_SCENARIO_LEARNING_CUTOFF_HZ; /* used only when on */
    sc->gains.learning_limit_m = CDPR_SCENARIO_LEARNING_LIMIT_M;
    sc->gains.learning_settle_laps = 1;
    sc->gains.integral_limit_m = CDPR_SCENARIO_INTEGRAL_LIMIT_M; /* used only when on */
    sc->controller_model = cdpr_rig_scale_unit();
    sc->integrator.rtol = 1e-6;
    sc->integrator.atol_position_m = 1e-6;
    sc->integrator.atol_velocity_m_per_s = 1e-5;
    sc->integrator.atol_quaternion = 1e-8;
    sc->integrator.atol_rate_rad_per_s = 1e-6;
    sc->integrator.h_max_s = 0.01;
    sc->integrator.max_trials = 2000; /* what every shipped scenario sets */
    sc->integrator.max_attempts = 1;
    sc->integrator.substeps = 0;
    sc->integrator.method = CDPR_PLANT_RKF45;
    for (int m = 0; m < CDPR_SCENARIO_METHODS; ++m) {
        sc->integrator_for[m] = sc->integrator;
        sc->integrator_for[m].method = (cdpr_plant_integrator_t)m;
    }
    sc->output_rate_hz = 0.0; /* 0: one row per control period */
}

void cdpr_scenario_default(cdpr_scenario_t *sc, cdpr_preset_t preset)
{
    memset(sc, 0, sizeof *sc);
    cdpr_preset_config_t c;
    (void)cdpr_preset_get(preset, &c);
    cdpr_rig_from_preset(&c, &sc->rig);
    sc->robot_source = CDPR_ROBOT_FROM_PRESET;
    sc->preset = c.preset;
    sc->traj.type = CDPR_TRAJ_HOLD;
    memcpy(sc->traj.hold_pose, sc->rig.nominal_pose, sizeof sc->traj.hold_pose);
    sc->traj.direction = 1.0;
    defaults_common(sc);
    sc->duration_s = 1.0;
}

static void take(double *dst, const double *src, int n)
{
    if (src != NULL) {
        memcpy(dst, src, sizeof(double) * (size_t)n);
    }
}

/* initial and trajectory sections. */
static void resolve_motion(const raw_t *r, cdpr_scenario_t *sc)
{
    if (r->initial != NULL) {
        sc->has_initial_pose = (r->initial->pose != NULL) ? 1 : 0;
        take(sc->initial_pose, r->initial->pose, 6);
        take(sc->initial_offset, r->initial->offset, 6);
    }
    cdpr_traj_t *t = &sc->traj;
    t->type = r->trajectory.type;
    t->direction = 1.0;
    if (r->trajectory.circle != NULL) {
        const raw_circle_t *ci = r->trajectory.circle;
        take(t->centre_m, ci->centre_m, 3);
        t->radius_m = ci->radius_m;
        t->speed_m_per_s = ci->speed_m_per_s;
        t->start_angle_rad = ci->start_angle_deg * CDPR_PI / 180.0;
        if (ci->direction != NULL && *ci->direction == DIR_CW) {
            t->direction = -1.0;
        }
        take(&t->ramp_s, ci->ramp_s, 1);
        take(t->attitude_rad, ci->attitude_rad, 3);
    }
    if (r->trajectory.line != NULL) {
        const raw_line_t *li = r->trajectory.line;
        take(t->from, li->from, 6);
        take(t->to, li->to, 6);
        t->duration_s = li->duration_s;
        take(&t->pause_s, li->pause_s, 1);
        t->back_and_forth = (li->back_and_forth != NULL && *li->back_and_forth) ? 1 : 0;
    }
    if (r->trajectory.hold != NULL) {
        take(t->hold_pose, r->trajectory.hold->pose, 6);
    }
    if (r->trajectory.cyclic != NULL) {
        const raw_cyclic_t *cy = r->trajectory.cyclic;
        take(t->from, cy->from, 6);
        take(t->to, cy->to, 6);
        t->duration_s = cy->duration_s;
        take(&t->pause_s, cy->pause_s, 1);
        t->cycles = (cy->cycles != NULL) ? (long)*cy->cycles : 0; /* check_whole_numbers */
    }
}

/* The integrator keys given in `in` (the section or one method's subsection). */
static void take_integrator(const raw_integrator_t *in, cdpr_scenario_integrator_t *out)
{
    take(&out->rtol, in->rtol, 1);
    take(&out->atol_position_m, in->atol_position_m, 1);
    take(&out->atol_velocity_m_per_s, in->atol_velocity_m_per_s, 1);
    take(&out->atol_quaternion, in->atol_quaternion, 1);
    take(&out->atol_rate_rad_per_s, in->atol_rate_rad_per_s, 1);
    take(&out->h_max_s, in->h_max_s, 1);
    if (in->max_trials != NULL) {
        out->max_trials = (int)*in->max_trials; /* see check_whole_numbers */
    }
    if (in->max_attempts != NULL) {
        out->max_attempts = (int)*in->max_attempts;
    }
    if (in->substeps != NULL) {
        out->substeps = (int)*in->substeps;
    }
}

/* controller, integrator and run sections, and the description. */
static void resolve_run(const raw_t *r, cdpr_scenario_t *sc)
{
    sc->gains.kp = r->controller.kp;
    take(&sc->gains.kd_s, r->controller.kd_s, 1);
    sc->gains.k_length_per_s = r->controller.k_length_per_s;
    take(&sc->gains.filter_s, r->controller.filter_s, 1);
    take(&sc->gains.inertial_ff, r->controller.inertial_ff, 1);
    take(&sc->gains.damping_N_s_per_m, r->controller.damping_N_s_per_m, 1);
    take(&sc->gains.damping_rot_N_m_s, r->controller.damping_rot_N_m_s, 1);
    take(&sc->gains.transfer_s, r->controller.transfer_s, 1);                 /* default 0: none */
    take(&sc->gains.transfer_from_rest, r->controller.transfer_from_rest, 1); /* 0 or 1 */
    take(&sc->gains.wind_ff, r->controller.wind_ff, 1);                       /* default 0: none */
    take(&sc->gains.tension_gain_m_per_s_per_N, r->controller.tension_gain_m_per_s_per_N, 1);
    take(&sc->gains.tension_filter_s, r->controller.tension_filter_s, 1);   /* default 0: off */
    take(&sc->gains.tension_washout_s, r->controller.tension_washout_s, 1); /* default 0: none */
    take(&sc->gains.learning_gain, r->controller.learning_gain, 1);         /* default 0: off */
    take(&sc->gains.learning_lead_s, r->controller.learning_lead_s, 1);
    take(&sc->gains.learning_cutoff_hz, r->controller.learning_cutoff_hz, 1);
    take(&sc->gains.learning_limit_m, r->controller.learning_limit_m, 1);
    if (r->controller.learning_settle_laps != NULL) {
        sc->gains.learning_settle_laps = (long)*r->controller.learning_settle_laps; /* whole */
    }
    take(&sc->gains.integral_per_s, r->controller.integral_per_s, 1); /* default 0: off */
    take(&sc->gains.integral_limit_m, r->controller.integral_limit_m, 1);
    take(&sc->gains.weight_estimate_s, r->controller.weight_estimate_s, 1); /* default 0: off */
    if (r->controller.model != NULL) {
        const raw_model_t *md = r->controller.model;
        take(&sc->controller_model.ea, md->ea_scale, 1);
        take(&sc->controller_model.cabin_mass, md->cabin_mass_scale, 1);
        take(&sc->controller_model.rope_mass, md->rope_mass_scale, 1);
    }
    if (r->integrator != NULL) {
        const raw_integrator_t *in = r->integrator;
        take_integrator(in, &sc->integrator);
        if (in->method != NULL) {
            sc->integrator.method = *in->method;
        }
        const raw_integrator_t *sub[CDPR_SCENARIO_METHODS] = {in->rkf45, in->ros34pw2,
                                                              in->ros34pw2};
        for (int m = 0; m < CDPR_SCENARIO_METHODS; ++m) {
            sc->integrator_for[m] = sc->integrator;
            sc->integrator_for[m].method = (cdpr_plant_integrator_t)m;
            if (sub[m] != NULL) {
                take_integrator(sub[m], &sc->integrator_for[m]);
            }
        }
        sc->integrator = sc->integrator_for[sc->integrator.method];
    }
    sc->duration_s = r->run.duration_s;
    sc->period_s = r->run.period_s;
    take(&sc->output_rate_hz, r->run.output_rate_hz, 1);
    if (r->description != NULL) {
        snprintf(sc->description, sizeof sc->description, "%s", r->description);
    }
}

/* The wind section; the rig's wind becomes the profile's value at t = 0 (the settled start). */
static void resolve_wind(const raw_t *r, cdpr_scenario_t *sc)
{
    const raw_wind_t *w = r->wind;
    if (w == NULL) {
        return;
    }
    cdpr_scenario_wind_t *o = &sc->wind;
    o->given = 1;
    o->speed_m_per_s = w->speed_m_per_s;
    o->towards_deg = w->towards_deg;
    o->profile = (w->profile != NULL) ? *w->profile : CDPR_WIND_STEADY;
    o->start_s = 0.0;
    o->rise_s = 1.0;
    o->gust_m_per_s = 0.0;
    take(&o->start_s, w->start_s, 1);
    take(&o->rise_s, w->rise_s, 1);
    take(&o->gust_m_per_s, w->gust_m_per_s, 1);
    cdpr_scenario_wind_at(sc, 0.0, sc->rig.wind_m_per_s);
}

/* controller.precompensation: the file's path, relative to the scenario's folder unless
 * absolute (as robot.file). */
static cdpr_status_t resolve_precompensation(const raw_t *r, cdpr_scenario_t *sc,
                                             cdpr_scenario_error_t *err)
{
    sc->precompensation[0] = '\0';
    if (r->controller.precompensation == NULL) {
        return CDPR_OK;
    }
    const char *f = r->controller.precompensation;
    const char *slash = strrchr(sc->path, '/');
    const int n = (f[0] == '/' || slash == NULL)
                      ? snprintf(sc->precompensation, sizeof sc->precompensation, "%s", f)
                      : snprintf(sc->precompensation, sizeof sc->precompensation, "%.*s/%s",
                                 (int)(slash - sc->path), sc->path, f);
    if (n < 0 || (size_t)n >= sizeof sc->precompensation) {
        char what[160];
        snprintf(what, sizeof what,
                 "path too long (%d characters with the scenario's folder; at most %zu)", n,
                 sizeof sc->precompensation - 1U);
        cdpr_scenario_error(sc, "controller.precompensation", what, err);
        return CDPR_E_INVALID_ARG;
    }
    return CDPR_OK;
}

static void resolve(const raw_t *r, cdpr_scenario_t *sc)
{
    resolve_motion(r, sc);
    resolve_run(r, sc);
    resolve_wind(r, sc);
}

/* cos and sin of an angle in degrees; exact at whole multiples of 90 degrees. */
static void cos_sin_deg(double deg, double *c, double *s)
{
    static const double cq[4] = {1.0, 0.0, -1.0, 0.0};
    const double q = deg / 90.0;
    const double k = nearbyint(q);
    if (fabs(q - k) < 1e-12 && fabs(k) < 1e6) {
        const long i = (((long)k % 4L) + 4L) % 4L;
        *c = cq[i];
        *s = cq[(i + 3L) % 4L];
    } else {
        *c = cos(deg * CDPR_PI / 180.0);
        *s = sin(deg * CDPR_PI / 180.0);
    }
}

void cdpr_scenario_wind_at(const cdpr_scenario_t *sc, double t, double v[3])
{
    if (sc->wind.given == 0) {
        memcpy(v, sc->rig.wind_m_per_s, sizeof(double) * 3U);
    } else {
        cdpr_scenario_wind_eval(&sc->wind, t, v);
    }
}

void cdpr_scenario_wind_eval(const cdpr_scenario_wind_t *w, double t, double v[3])
{
    if (w->given == 0) {
        v[0] = 0.0;
        v[1] = 0.0;
        v[2] = 0.0;
        return;
    }
    double speed = w->speed_m_per_s;
    /* rise_s > 0 once checked; before the check (the rig's value at t = 0), a bad one gives
     * the steady speed, so that the message names wind.rise_s rather than a NaN wind. */
    const double x = (w->rise_s > 0.0) ? (t - w->start_s) / w->rise_s : 2.0;
    if (w->profile == CDPR_WIND_RAMP) {
        speed *= (x <= 0.0) ? 0.0 : ((x >= 1.0) ? 1.0 : x);
    } else if (w->profile == CDPR_WIND_GUST && x > 0.0 && x < 1.0) {
        speed += w->gust_m_per_s * 0.5 * (1.0 - cos(2.0 * CDPR_PI * x));
    } else {
        /* steady, or outside the gust */
    }
    double c = 1.0;
    double s = 0.0;
    cos_sin_deg(w->towards_deg, &c, &s);
    v[0] = speed * c;
    v[1] = speed * s;
    v[2] = 0.0;
}

/* Every x[i] finite and in [lo, hi] (or (lo, hi] when lo_open), named `key` in errors. */
static cdpr_status_t in_range(const cdpr_scenario_t *sc, const char *key, const double *x, int n,
                              double lo, double hi, int lo_open, cdpr_scenario_error_t *err);

/* A preset's rig with its polar layout (robot.towers, robot.attachments) as the file gives it:
 * the layout's values range-checked here, as they do not survive into the rig. */
static cdpr_status_t preset_base(const cdpr_raw_rig_t *rr, const cdpr_scenario_t *sc,
                                 cdpr_rig_t *base, cdpr_scenario_error_t *err)
{
    cdpr_preset_config_t c;
    (void)cdpr_preset_get((cdpr_preset_t)*rr->preset, &c);
    cdpr_status_t st = CDPR_OK;
    if (rr->towers != NULL) {
        take(&c.exit_radius_m, rr->towers->radius_m, 1);
        take(&c.exit_height_m, rr->towers->height_m, 1);
        take(c.exit_azimuth_deg, rr->towers->azimuths_deg, 6);
    }
    if (rr->attachments != NULL) {
        take(&c.attach_radius_m, rr->attachments->radius_m, 1);
        take(&c.attach_z_m, rr->attachments->height_m, 1);
        take(c.attach_azimuth_deg, rr->attachments->azimuths_deg, 6);
    }
    const struct {
        const char *key;
        const double *x;
        double lo, hi;
        int n;
        int lo_open;
    } layout[] = {
        {"robot.towers.radius_m", &c.exit_radius_m, 0.0, 1e4, 1, 1},
        {"robot.towers.exit_height_m", &c.exit_height_m, -1e4, 1e4, 1, 0},
        {"robot.towers.azimuths_deg", c.exit_azimuth_deg, -360.0, 360.0, 6, 0},
        {"robot.attachments.radius_m", &c.attach_radius_m, 0.0, 1e3, 1, 0},
        {"robot.attachments.z_m", &c.attach_z_m, -1e3, 1e3, 1, 0},
        {"robot.attachments.azimuths_deg", c.attach_azimuth_deg, -360.0, 360.0, 6, 0},
    };
    for (size_t i = 0; i < sizeof layout / sizeof layout[0] && st == CDPR_OK; ++i) {
        st = in_range(sc, layout[i].key, layout[i].x, layout[i].n, layout[i].lo, layout[i].hi,
                      layout[i].lo_open, err);
    }
    if (st == CDPR_OK) {
        cdpr_rig_from_preset(&c, base);
    }
    return st;
}

/* A robot file's path: relative to the scenario's folder unless absolute. */
static cdpr_status_t robot_file_path(const cdpr_raw_rig_t *rr, const cdpr_scenario_t *sc,
                                     char *file, size_t cap, cdpr_scenario_error_t *err)
{
    /* Every key that a robot file would leave unread (description: is a note, allowed). */
    const void *other[] = {rr->preset,
                           rr->towers,
                           rr->attachments,
                           rr->gravity_m_per_s2,
                           rr->air_density_kg_per_m3,
                           rr->wind_m_per_s,
                           rr->nominal_pose,
                           rr->segments,
                           rr->rope,
                           rr->winch,
                           rr->cabin,
                           rr->cables};
    for (size_t i = 0; i < sizeof other / sizeof other[0]; ++i) {
        if (other[i] != NULL) {
            cdpr_scenario_error(sc, "robot.file",
                                "a robot file takes no other robot keys here: change the "
                                "robot file, or embed the robot instead",
                                err);
            return CDPR_E_PARSE;
        }
    }
    const char *slash = strrchr(sc->path, '/');
    int n;
    if (rr->file[0] == '/' || slash == NULL) {
        n = snprintf(file, cap, "%s", rr->file);
    } else {
        n = snprintf(file, cap, "%.*s/%s", (int)(slash - sc->path), sc->path, rr->file);
    }
    if (n < 0 || (size_t)n >= cap) {
        char what[256];
        snprintf(what, sizeof what,
                 "path too long (%d characters with the scenario's folder; a robot-file "
                 "path has at most %zu)",
                 n, cap - 1U);
        cdpr_scenario_error(sc, "robot.file", what, err);
        return CDPR_E_INVALID_ARG;
    }
    return CDPR_OK;
}

/* robot: a robot file (path relative to the scenario's folder), a preset with overrides (the
 * robot-file keys over the preset's values) or an embedded robot. The one robot record of a
 * scenario is sc->rig. */
static cdpr_status_t resolve_rig(const cdpr_raw_rig_t *rr, cdpr_scenario_t *sc,
                                 cdpr_scenario_error_t *err)
{
    cdpr_rig_error_t re;
    cdpr_status_t st;
    if (rr->file != NULL) {
        char file[sizeof sc->rig.name];
        st = robot_file_path(rr, sc, file, sizeof file, err);
        if (st != CDPR_OK) {
            return st;
        }
        sc->robot_source = CDPR_ROBOT_FROM_FILE;
        st = cdpr_rig_load(file, &sc->rig, &re);
        if (st == CDPR_E_IO) {
            char what[1024];
            snprintf(what, sizeof what, "%.900s (relative to the scenario's folder)", re.msg);
            cdpr_scenario_error(sc, "robot.file", what, err);
            return st;
        }
    } else if (rr->preset != NULL) {
        if (rr->cables != NULL) {
            cdpr_scenario_error(sc, "robot.cables",
                                "a preset's cables come from its layout (robot.towers, "
                                "robot.attachments): drop preset: to list the cables",
                                err);
            return CDPR_E_PARSE;
        }
        cdpr_rig_t base;
        st = preset_base(rr, sc, &base, err);
        if (st != CDPR_OK) {
            return st;
        }
        sc->robot_source = CDPR_ROBOT_FROM_PRESET;
        sc->preset = (cdpr_preset_t)*rr->preset;
        st = cdpr_rig_resolve(rr, &base, sc->path, "robot.", &sc->rig, &re);
    } else {
        if (rr->towers != NULL || rr->attachments != NULL) {
            cdpr_scenario_error(sc, (rr->towers != NULL) ? "robot.towers" : "robot.attachments",
                                "a polar layout needs preset: (an embedded robot lists its "
                                "cables: with exit_m and attach_m)",
                                err);
            return CDPR_E_PARSE;
        }
        if (rr->cables == NULL && rr->cabin == NULL) {
            cdpr_scenario_error(sc, "robot",
                                "needs preset: (a compiled preset and overrides), file: (a robot "
                                "file) or an embedded robot (cables:, cabin:, ...; "
                                "docs/robots.md)",
                                err);
            return CDPR_E_PARSE;
        }
        sc->robot_source = CDPR_ROBOT_EMBEDDED;
        st = cdpr_rig_resolve(rr, NULL, sc->path, "robot.", &sc->rig, &re);
    }
    if (st != CDPR_OK) {
        snprintf(err->msg, sizeof err->msg, "%s", re.msg);
    }
    return st;
}

/* Which trajectory blocks a file gave: exactly the one matching `type`. */
static cdpr_status_t check_traj_blocks(const raw_t *r, cdpr_scenario_t *sc,
                                       cdpr_scenario_error_t *err)
{
    const void *blocks[4] = {r->trajectory.hold, r->trajectory.circle, r->trajectory.line,
                             r->trajectory.cyclic};
    const cdpr_traj_type_t types[4] = {CDPR_TRAJ_HOLD, CDPR_TRAJ_CIRCLE, CDPR_TRAJ_LINE,
                                       CDPR_TRAJ_CYCLIC};
    for (int i = 0; i < 4; ++i) {
        char key[64];
        snprintf(key, sizeof key, "trajectory.%s", cdpr_traj_type_name(types[i]));
        if (types[i] == r->trajectory.type && blocks[i] == NULL) {
            char what[512];
            snprintf(what, sizeof what, "type %s needs a '%s:' block in trajectory",
                     cdpr_traj_type_name(types[i]), cdpr_traj_type_name(types[i]));
            cdpr_scenario_error(sc, "trajectory.type", what, err);
            return CDPR_E_PARSE;
        }
        if (types[i] != r->trajectory.type && blocks[i] != NULL) {
            char what[512];
            snprintf(what, sizeof what, "given, but trajectory.type is %s",
                     cdpr_traj_type_name(r->trajectory.type));
            cdpr_scenario_error(sc, key, what, err);
            return CDPR_E_PARSE;
        }
    }
    return CDPR_OK;
}

/* Counts given in the file: finite whole numbers in range (before they become ints). */
static cdpr_status_t whole(const cdpr_scenario_t *sc, const char *key, const double *v, double lo,
                           double hi, cdpr_scenario_error_t *err)
{
    if (v == NULL) {
        return CDPR_OK;
    }
    if (!isfinite(*v) || floor(*v) < *v || *v < lo || *v > hi) {
        char what[512];
        snprintf(what, sizeof what, "%g is not a whole number in [%g, %g]", *v, lo, hi);
        cdpr_scenario_error(sc, key, what, err);
        return isfinite(*v) ? CDPR_E_OUT_OF_RANGE : CDPR_E_NOT_FINITE;
    }
    return CDPR_OK;
}

static cdpr_status_t check_whole_numbers(const raw_t *r, const cdpr_scenario_t *sc,
                                         cdpr_scenario_error_t *err)
{
    cdpr_status_t st = CDPR_OK;
    if (r->integrator != NULL) {
        const raw_integrator_t *sec[3] = {r->integrator, r->integrator->rkf45,
                                          r->integrator->ros34pw2};
        const char *name[3] = {"integrator", "integrator.rkf45", "integrator.ros34pw2"};
        for (int i = 0; i < 3 && st == CDPR_OK; ++i) {
            if (sec[i] == NULL) {
                continue;
            }
            char key[64];
            snprintf(key, sizeof key, "%s.max_trials", name[i]);
            st = whole(sc, key, sec[i]->max_trials, 1.0, (double)CDPR_SCENARIO_MAX_TRIALS, err);
            if (st == CDPR_OK) {
                snprintf(key, sizeof key, "%s.max_attempts", name[i]);
                st =
                    whole(sc, key, sec[i]->max_attempts, 1.0, (double)CDPR_PLANT_MAX_ATTEMPTS, err);
            }
            if (st == CDPR_OK) {
                snprintf(key, sizeof key, "%s.substeps", name[i]);
                st = whole(sc, key, sec[i]->substeps, 1.0, (double)CDPR_PLANT_MAX_SUBSTEPS, err);
            }
        }
    }
    if (st == CDPR_OK && r->trajectory.cyclic != NULL) {
        st = whole(sc, "trajectory.cyclic.cycles", r->trajectory.cyclic->cycles, 0.0, 1e9, err);
    }
    if (st == CDPR_OK) {
        st = whole(sc, "controller.learning_settle_laps", r->controller.learning_settle_laps, 0.0,
                   1e6, err);
    }
    if (st == CDPR_OK) {
        st = whole(sc, "controller.transfer_from_rest", r->controller.transfer_from_rest, 0.0, 1.0,
                   err);
    }
    if (st != CDPR_OK) {
        return st;
    }
    if (r->run.output_rate_hz != NULL && isfinite(*r->run.output_rate_hz) &&
        !(*r->run.output_rate_hz > 0.0)) {
        char what[256];
        snprintf(what, sizeof what,
                 "%g Hz: a rate must be > 0 (omit the key for one row per control period)",
                 *r->run.output_rate_hz);
        cdpr_scenario_error(sc, "run.output_rate_hz", what, err);
        return CDPR_E_OUT_OF_RANGE;
    }
    if (r->controller.period_s != NULL) {
        cdpr_scenario_error(sc, "controller.period_s",
                            "the control period is run.period_s (one period for the plant, the "
                            "controller and the outputs): move it there",
                            err);
        return CDPR_E_PARSE;
    }
    return CDPR_OK;
}

static cdpr_status_t check_integrator_sections(const raw_t *r, const cdpr_scenario_t *sc,
                                               cdpr_scenario_error_t *err);
static cdpr_status_t check_all(const cdpr_scenario_t *sc, int rig_checked,
                               cdpr_scenario_error_t *err);
static uint64_t fingerprint(const cdpr_scenario_t *sc);

/* The wind keys a profile reads, and no others: a gust size on a ramp is a mistake, not a
 * no-op. */
static cdpr_status_t check_wind_keys(const raw_wind_t *w, const cdpr_scenario_t *sc,
                                     cdpr_scenario_error_t *err)
{
    if (w == NULL) {
        return CDPR_OK;
    }
    const cdpr_wind_profile_t p = (w->profile != NULL) ? *w->profile : CDPR_WIND_STEADY;
    const char *key = NULL;
    if (p == CDPR_WIND_STEADY && (w->start_s != NULL || w->rise_s != NULL)) {
        key = (w->start_s != NULL) ? "wind.start_s" : "wind.rise_s";
    } else if (p != CDPR_WIND_GUST && w->gust_m_per_s != NULL) {
        key = "wind.gust_m_per_s";
    } else if (p != CDPR_WIND_STEADY && w->rise_s == NULL) {
        cdpr_scenario_error(sc, "wind.rise_s",
                            "required for a ramp (its rise time) or a gust (its duration)", err);
        return CDPR_E_PARSE;
    } else if (p == CDPR_WIND_GUST && w->gust_m_per_s == NULL) {
        cdpr_scenario_error(sc, "wind.gust_m_per_s", "required for a gust (its peak)", err);
        return CDPR_E_PARSE;
    } else {
        return CDPR_OK;
    }
    char what[256];
    snprintf(what, sizeof what,
             "not a key of wind.profile %s (steady: speed_m_per_s, "
             "towards_deg; ramp: also start_s, rise_s; gust: also gust_m_per_s)",
             cdpr_wind_profile_name(p));
    cdpr_scenario_error(sc, key, what, err);
    return CDPR_E_PARSE;
}

cdpr_status_t cdpr_scenario_load(const char *path, cdpr_scenario_t *sc, cdpr_scenario_error_t *err)
{
    memset(sc, 0, sizeof *sc);
    if (strlen(path) >= sizeof sc->path) {
        snprintf(err->msg, sizeof err->msg,
                 "%.200s...: path too long (%zu characters; a scenario path has at most %zu)", path,
                 strlen(path), sizeof sc->path - 1U);
        return CDPR_E_INVALID_ARG;
    }
    snprintf(sc->path, sizeof sc->path, "%s", path);
    /* Size, type and syntax before anything parses the file (the key lookup below does). */
    const cdpr_status_t fs = cdpr_yaml_check_file(path, err->msg, sizeof err->msg);
    if (fs == CDPR_E_IO) {
        char why[256];
        (void)cdpr_yaml_check_file(path, why, sizeof why);
        snprintf(err->msg, sizeof err->msg, "%s: cannot open scenario file: %s", path, why);
    }
    if (fs != CDPR_OK) {
        return fs;
    }
    void *data = NULL;
    const cyaml_schema_value_t *schema = &top_schema;
    cdpr_status_t st = cdpr_yaml_load_reported(path, path, schema, "scenario file", &data, err->msg,
                                               sizeof err->msg);
    if (st != CDPR_OK) {
        return st;
    }
    const raw_t *raw = data;
    st = check_traj_blocks(raw, sc, err);
    if (st == CDPR_OK) {
        st = check_whole_numbers(raw, sc, err);
    }
    if (st == CDPR_OK) {
        st = check_integrator_sections(raw, sc, err);
    }
    if (st == CDPR_OK) {
        st = check_wind_keys(raw->wind, sc, err);
    }
    if (st == CDPR_OK) {
        st = resolve_rig(raw->robot, sc, err);
    }
    if (st == CDPR_OK) {
        defaults_common(sc);
        resolve(raw, sc);
        st = resolve_precompensation(raw, sc, err);
    }
    if (st == CDPR_OK) {
        st = check_all(sc, (sc->robot_source == CDPR_ROBOT_FROM_FILE) ? 1 : 0, err);
    }
    if (st == CDPR_OK) {
        sc->checked_stamp = fingerprint(sc);
    }
    cdpr_yaml_free(schema, data);
    return st;
}

/* ---------------------------------------------------------------- checks */

typedef struct {
    const cdpr_scenario_t *sc;
    cdpr_scenario_error_t *err;
    cdpr_status_t failed; /* CDPR_OK until the first failure */
} vctx_t;

/* Every x[i] finite and in [lo, hi] (or (lo, hi] when lo_open): cdpr_yaml_range. */
static void range(vctx_t *v, const char *key, const double *x, int n, double lo, double hi,
                  int lo_open)
{
    if (v->failed != CDPR_OK) {
        return;
    }
    char k[128];
    char what[512];
    const cdpr_status_t st =
        cdpr_yaml_range(key, x, n, lo, hi, lo_open, k, sizeof k, what, sizeof what);
    if (st != CDPR_OK) {
        cdpr_scenario_error(v->sc, k, what, v->err);
        v->failed = st;
    }
}

static cdpr_status_t in_range(const cdpr_scenario_t *sc, const char *key, const double *x, int n,
                              double lo, double hi, int lo_open, cdpr_scenario_error_t *err)
{
    vctx_t v = {sc, err, CDPR_OK};
    range(&v, key, x, n, lo, hi, lo_open);
    return v.failed;
}

static void irange(vctx_t *v, const char *key, long x, long lo, long hi)
{
    if (v->failed == CDPR_OK && (x < lo || x > hi)) {
        char what[512];
        snprintf(what, sizeof what, "%ld is outside [%ld, %ld]", x, lo, hi);
        cdpr_scenario_error(v->sc, key, what, v->err);
        v->failed = CDPR_E_OUT_OF_RANGE;
    }
}

/* A pose: positions within 10 km, angles within +-2 pi. */
static void pose_range(vctx_t *v, const char *key, const double *pose)
{
    char k[128];
    snprintf(k, sizeof k, "%s", key);
    for (int i = 0; i < 6 && v->failed == CDPR_OK; ++i) {
        const double lim = (i < 3) ? 1e4 : 2.0 * CDPR_PI;
        if (!isfinite(pose[i])) {
            char what[512];
            snprintf(what, sizeof what, "element %d is not a finite number (%g)", i, pose[i]);
            cdpr_scenario_error(v->sc, k, what, v->err);
            v->failed = CDPR_E_NOT_FINITE;
        } else if (fabs(pose[i]) > lim) {
            char what[512];
            snprintf(what, sizeof what, "element %d = %g is outside [-%g, %g]", i, pose[i], lim,
                     lim);
            cdpr_scenario_error(v->sc, k, what, v->err);
            v->failed = CDPR_E_OUT_OF_RANGE;
        }
    }
}

/* initial and trajectory sections. */
static void check_motion(vctx_t *vp)
{
    vctx_t v = *vp;
    const cdpr_scenario_t *sc = v.sc;
    if (sc->has_initial_pose != 0) {
        pose_range(&v, "initial.pose", sc->initial_pose);
    }
    pose_range(&v, "initial.offset", sc->initial_offset);
    const cdpr_traj_t *t = &sc->traj;
    switch (t->type) {
    case CDPR_TRAJ_CIRCLE:
        range(&v, "trajectory.circle.centre_m", t->centre_m, 3, -1e4, 1e4, 0);
        range(&v, "trajectory.circle.radius_m", &t->radius_m, 1, 0.0, 1e4, 1);
        range(&v, "trajectory.circle.speed_m_per_s", &t->speed_m_per_s, 1, 0.0, 1e3, 0);
        {
            const double deg = t->start_angle_rad * 180.0 / CDPR_PI;
            range(&v, "trajectory.circle.start_angle_deg", &deg, 1, -360.0, 360.0, 0);
        }
        range(&v, "trajectory.circle.ramp_s", &t->ramp_s, 1, 0.0, 1e6, 0);
        range(&v, "trajectory.circle.attitude_rad", t->attitude_rad, 3, -2.0 * CDPR_PI,
              2.0 * CDPR_PI, 0);
        break;
    case CDPR_TRAJ_LINE:
        pose_range(&v, "trajectory.line.from", t->from);
        pose_range(&v, "trajectory.line.to", t->to);
        range(&v, "trajectory.line.duration_s", &t->duration_s, 1, 0.0, 1e6, 1);
        range(&v, "trajectory.line.pause_s", &t->pause_s, 1, 0.0, 1e6, 0);
        break;
    case CDPR_TRAJ_CYCLIC:
        pose_range(&v, "trajectory.cyclic.from", t->from);
        pose_range(&v, "trajectory.cyclic.to", t->to);
        range(&v, "trajectory.cyclic.duration_s", &t->duration_s, 1, 0.0, 1e6, 1);
        range(&v, "trajectory.cyclic.pause_s", &t->pause_s, 1, 0.0, 1e6, 0);
        break;
    default:
        pose_range(&v, "trajectory.hold.pose", t->hold_pose);
        break;
    }
    *vp = v;
}

/* The integrator's real-valued settings and their upper bounds (lower: > 0). */
#define N_INTEGRATOR_REALS 6
static const char *const integrator_real_names[N_INTEGRATOR_REALS] = {
    "rtol",   "atol_position_m", "atol_velocity_m_per_s", "atol_quaternion", "atol_rate_rad_per_s",
    "h_max_s"};
static const double integrator_real_max[N_INTEGRATOR_REALS] = {0.1, 1.0, 1.0, 1.0, 1.0, 10.0};

/* One integrator setting, keys named under `prefix`; a NULL value is not given (not
 * checked). */
static void check_integrator_reals(vctx_t *v, const char *prefix,
                                   const double *const x[N_INTEGRATOR_REALS])
{
    char key[64];
    for (int i = 0; i < N_INTEGRATOR_REALS; ++i) {
        if (x[i] != NULL) {
            snprintf(key, sizeof key, "%s.%s", prefix, integrator_real_names[i]);
            range(v, key, x[i], 1, 0.0, integrator_real_max[i], 1);
        }
    }
}

/* The settings in use (after overrides), named as the section's. */
static void check_integrator(vctx_t *v, const cdpr_scenario_integrator_t *in)
{
    const double *const x[N_INTEGRATOR_REALS] = {&in->rtol,
                                                 &in->atol_position_m,
                                                 &in->atol_velocity_m_per_s,
                                                 &in->atol_quaternion,
                                                 &in->atol_rate_rad_per_s,
                                                 &in->h_max_s};
    check_integrator_reals(v, "integrator", x);
    irange(v, "integrator.max_trials", in->max_trials, 1, CDPR_SCENARIO_MAX_TRIALS);
    irange(v, "integrator.max_attempts", in->max_attempts, 1, CDPR_PLANT_MAX_ATTEMPTS);
}

/* Every value the file gives in the integrator section and its method subsections, named by
 * where it stands (a method's settings mix the section's and its own, so they are checked
 * here, before they mix; the whole-number counts: check_whole_numbers). */
static cdpr_status_t check_integrator_sections(const raw_t *r, const cdpr_scenario_t *sc,
                                               cdpr_scenario_error_t *err)
{
    if (r->integrator == NULL) {
        return CDPR_OK;
    }
    vctx_t v = {sc, err, CDPR_OK};
    const raw_integrator_t *sec[3] = {r->integrator, r->integrator->rkf45, r->integrator->ros34pw2};
    const char *name[3] = {"integrator", "integrator.rkf45", "integrator.ros34pw2"};
    for (int i = 0; i < 3; ++i) {
        if (sec[i] != NULL) {
            const double *const x[N_INTEGRATOR_REALS] = {sec[i]->rtol,
                                                         sec[i]->atol_position_m,
                                                         sec[i]->atol_velocity_m_per_s,
                                                         sec[i]->atol_quaternion,
                                                         sec[i]->atol_rate_rad_per_s,
                                                         sec[i]->h_max_s};
            check_integrator_reals(&v, name[i], x);
        }
    }
    return v.failed;
}

/* Learning over laps (tracker.h step 8): ranges, a bound when on, and a periodic trajectory
 * (on a line or a hold the tracker would learn nothing: refused rather than ignored). */
static void check_learning(vctx_t *vp)
{
    vctx_t v = *vp;
    const cdpr_scenario_t *sc = v.sc;
    const cdpr_tracker_gains_t *g = &sc->gains;
    range(&v, "controller.learning_gain", &g->learning_gain, 1, 0.0, 2.0, 0);
    range(&v, "controller.learning_lead_s", &g->learning_lead_s, 1, 0.0, 100.0, 0);
    range(&v, "controller.learning_cutoff_hz", &g->learning_cutoff_hz, 1, 0.0, 1e3, 0);
    range(&v, "controller.learning_limit_m", &g->learning_limit_m, 1, 0.0, 100.0, 0);
    if (v.failed == CDPR_OK && g->learning_gain > 0.0) {
        const char *why = NULL;
        if (!(cdpr_traj_lap_s(&sc->traj) > 0.0)) {
            why = "learning over laps needs a periodic trajectory (circle at a speed > 0, or "
                  "cyclic); this one has no laps: omit the key or set it to 0";
        } else if (!(g->learning_limit_m > 0.0)) {
            why = "must be > 0 with learning_gain > 0 (the bound of the learned correction)";
        }
        if (why != NULL) {
            const int gain = (cdpr_traj_lap_s(&sc->traj) > 0.0) ? 0 : 1;
            cdpr_scenario_error(
                sc, (gain != 0) ? "controller.learning_gain" : "controller.learning_limit_m", why,
                v.err);
            v.failed = CDPR_E_OUT_OF_RANGE;
        }
    }
    *vp = v;
}

/* controller, integrator and run sections (ranges). */
static void check_run(vctx_t *vp)
{
    vctx_t v = *vp;
    const cdpr_scenario_t *sc = v.sc;
    range(&v, "controller.kp", &sc->gains.kp, 1, 0.0, 1e3, 0);
    range(&v, "controller.kd_s", &sc->gains.kd_s, 1, 0.0, 1e3, 0);
    range(&v, "controller.k_length_per_s", &sc->gains.k_length_per_s, 1, 0.0, 1e4, 0);
    range(&v, "controller.filter_s", &sc->gains.filter_s, 1, 0.0, 1e3, 0);
    range(&v, "controller.inertial_ff", &sc->gains.inertial_ff, 1, 0.0, 1.0, 0);
    range(&v, "controller.damping_N_s_per_m", &sc->gains.damping_N_s_per_m, 1, 0.0, 1e6, 0);
    range(&v, "controller.damping_rot_N_m_s", &sc->gains.damping_rot_N_m_s, 1, 0.0, 1e6, 0);
    range(&v, "controller.transfer_s", &sc->gains.transfer_s, 1, 0.0, 1e6, 0);
    range(&v, "controller.wind_ff", &sc->gains.wind_ff, 1, 0.0, 1.0, 0);
    range(&v, "controller.tension_gain_m_per_s_per_N", &sc->gains.tension_gain_m_per_s_per_N, 1,
          0.0, 1.0, 0);
    range(&v, "controller.tension_filter_s", &sc->gains.tension_filter_s, 1, 0.0, 1e3, 0);
    range(&v, "controller.tension_washout_s", &sc->gains.tension_washout_s, 1, 0.0, 1e4, 0);
    check_learning(&v);
    range(&v, "controller.integral_per_s", &sc->gains.integral_per_s, 1, 0.0, 1e3, 0);
    range(&v, "controller.integral_limit_m", &sc->gains.integral_limit_m, 1, 0.0, 10.0, 1);
    range(&v, "controller.weight_estimate_s", &sc->gains.weight_estimate_s, 1, 0.0, 1e4, 0);
    const cdpr_rig_scale_t *md = &sc->controller_model;
    range(&v, "controller.model.ea_scale", &md->ea, 1, CDPR_RIG_SCALE_MIN, CDPR_RIG_SCALE_MAX, 0);
    range(&v, "controller.model.cabin_mass_scale", &md->cabin_mass, 1, CDPR_RIG_SCALE_MIN,
          CDPR_RIG_SCALE_MAX, 0);
    range(&v, "controller.model.rope_mass_scale", &md->rope_mass, 1, CDPR_RIG_SCALE_MIN,
          CDPR_RIG_SCALE_MAX, 0);
    check_integrator(&v, &sc->integrator);
    range(&v, "run.duration_s", &sc->duration_s, 1, 0.0, 1e6, 1);
    range(&v, "run.period_s", &sc->period_s, 1, 0.0, 10.0, 1);
    range(&v, "run.output_rate_hz", &sc->output_rate_hz, 1, 0.0, 1e6, 0);
    if (sc->wind.given != 0) {
        const cdpr_scenario_wind_t *w = &sc->wind;
        range(&v, "wind.speed_m_per_s", &w->speed_m_per_s, 1, 0.0, 100.0, 0);
        range(&v, "wind.towards_deg", &w->towards_deg, 1, -360.0, 360.0, 0);
        range(&v, "wind.start_s", &w->start_s, 1, 0.0, 1e6, 0);
        range(&v, "wind.rise_s", &w->rise_s, 1, 0.0, 1e6, 1);
        range(&v, "wind.gust_m_per_s", &w->gust_m_per_s, 1, 0.0, 100.0 - w->speed_m_per_s, 0);
    }
    *vp = v;
}

/* A robot file or an embedded robot: the rig's own checks, keys named in its file. */
static void check_rig(vctx_t *v)
{
    const cdpr_scenario_t *sc = v->sc;
    if (v->failed != CDPR_OK) {
        return;
    }
    const int from_file = (sc->robot_source == CDPR_ROBOT_FROM_FILE) ? 1 : 0;
    cdpr_rig_error_t re;
    const cdpr_status_t st = cdpr_rig_check(&sc->rig, (from_file != 0) ? sc->rig.name : sc->path,
                                            (from_file != 0) ? "" : "robot.", &re);
    if (st != CDPR_OK) {
        if (v->err != NULL) {
            snprintf(v->err->msg, sizeof v->err->msg, "%s", re.msg);
        }
        v->failed = st;
    }
}

/* FNV-1a (64 bit) over the scenario's bytes up to the stamp: equal values, equal bytes (a
 * loaded scenario starts zeroed, padding included; a scenario whose padding differs only
 * fails to match, and is checked again). */
static uint64_t fingerprint(const cdpr_scenario_t *sc)
{
    const unsigned char *b = (const unsigned char *)sc;
    uint64_t h = 14695981039346656037ULL;
    for (size_t i = 0; i < offsetof(cdpr_scenario_t, checked_stamp); ++i) {
        h = (h ^ b[i]) * 1099511628211ULL;
    }
    return (h != 0U) ? h : 1U;
}

int cdpr_scenario_is_checked(const cdpr_scenario_t *sc)
{
    return (sc->checked_stamp != 0U && sc->checked_stamp == fingerprint(sc)) ? 1 : 0;
}

/* cdpr_scenario_check; rig_checked 1: the robot record was just checked (a robot file by
 * cdpr_rig_load, or an unchanged checked scenario), the rest is checked. */
static cdpr_status_t check_all(const cdpr_scenario_t *sc, int rig_checked,
                               cdpr_scenario_error_t *err)
{
    vctx_t v = {sc, err, CDPR_OK};
    if (rig_checked == 0) {
        check_rig(&v);
    }
    check_motion(&v);
    check_run(&v);
    if (v.failed == CDPR_OK) {
        /* Whole control periods, and whole periods per output row. */
        const double periods = sc->duration_s / sc->period_s;
        if (!(periods <= (double)CDPR_SCENARIO_MAX_PERIODS)) {
            char what[512];
            snprintf(what, sizeof what,
                     "%g s gives %g control periods over run.duration_s = %g s: more than the "
                     "%g a run may have",
                     sc->period_s, periods, sc->duration_s, (double)CDPR_SCENARIO_MAX_PERIODS);
            cdpr_scenario_error(sc, "run.period_s", what, err);
            v.failed = CDPR_E_OUT_OF_RANGE;
        } else if (fabs(periods - floor(periods + 0.5)) > 1e-6 * periods || periods < 0.5) {
            char what[512];
            snprintf(what, sizeof what, "%g s is not a whole number of control periods (%g s)",
                     sc->duration_s, sc->period_s);
            cdpr_scenario_error(sc, "run.duration_s", what, err);
            v.failed = CDPR_E_OUT_OF_RANGE;
        } else if (sc->output_rate_hz > 0.0) {
            const double every = 1.0 / (sc->output_rate_hz * sc->period_s);
            if (every < 0.5 || !(every <= (double)CDPR_SCENARIO_MAX_PERIODS) ||
                fabs(every - floor(every + 0.5)) > 1e-6 * every) {
                char what[512];
                snprintf(what, sizeof what,
                         "%g Hz is not the control rate (%g Hz) divided by a whole "
                         "number",
                         sc->output_rate_hz, 1.0 / sc->period_s);
                cdpr_scenario_error(sc, "run.output_rate_hz", what, err);
                v.failed = CDPR_E_OUT_OF_RANGE;
            }
        }
    }
    return v.failed;
}

cdpr_status_t cdpr_scenario_check(const cdpr_scenario_t *sc, cdpr_scenario_error_t *err)
{
    return check_all(sc, 0, err);
}

const char *cdpr_scenario_trajectory_key(const cdpr_scenario_t *sc)
{
    static const char *const keys[] = {"trajectory.hold", "trajectory.circle", "trajectory.line",
                                       "trajectory.cyclic"};
    return keys[(sc->traj.type <= CDPR_TRAJ_CYCLIC) ? sc->traj.type : CDPR_TRAJ_HOLD];
}

const char *cdpr_scenario_robot_name(const cdpr_scenario_t *sc)
{
    return sc->rig.name;
}

int cdpr_scenario_segments(const cdpr_scenario_t *sc)
{
    return sc->rig.cable[0].segments;
}

cdpr_status_t cdpr_scenario_build_robot(const cdpr_scenario_t *sc, const double *length_m,
                                        cdpr_robot_params_t *p, cdpr_winch_params_t *w,
                                        cdpr_diag_t *diag)
{
    return cdpr_rig_build(&sc->rig, length_m, p, w, diag);
}

void cdpr_scenario_initial_pose(const cdpr_scenario_t *sc, double pose[6])
{
    if (sc->has_initial_pose != 0) {
        memcpy(pose, sc->initial_pose, sizeof(double) * 6);
    } else {
        cdpr_traj_sample_t s;
        cdpr_traj_eval(&sc->traj, 0.0, &s);
        memcpy(pose, s.pose, sizeof(double) * 6);
    }
    for (int i = 0; i < 6; ++i) {
        pose[i] += sc->initial_offset[i];
    }
}

long cdpr_scenario_count(double n)
{
    /* NaN and negative counts are 0; beyond the limit saturate (no overflowing cast). */
    if (!(n > 0.0)) {
        return 0;
    }
    const double r = floor(n + 0.5);
    return (r < (double)CDPR_SCENARIO_MAX_PERIODS) ? (long)r : CDPR_SCENARIO_MAX_PERIODS;
}

long cdpr_scenario_periods(const cdpr_scenario_t *sc)
{
    return cdpr_scenario_count(sc->duration_s / sc->period_s);
}

long cdpr_scenario_output_every(const cdpr_scenario_t *sc)
{
    if (!(sc->output_rate_hz > 0.0)) {
        return 1;
    }
    const long every = cdpr_scenario_count(1.0 / (sc->output_rate_hz * sc->period_s));
    return (every >= 1) ? every : 1;
}

/* ---------------------------------------------------------------- command-line overrides */

void cdpr_scenario_overrides_none(cdpr_scenario_overrides_t *ov)
{
    ov->rate_hz = (double)NAN;
    ov->duration_s = (double)NAN;
    ov->max_trials = (double)NAN;
    ov->max_attempts = (double)NAN;
    ov->method = -1;
}

static int given(double v)
{
    return isnan(v) ? 0 : 1;
}

static int differs(double a, double b)
{
    return (a < b || a > b) ? 1 : 0;
}

/* A count option: a whole number that fits an int (its range is the scenario check's). */
static cdpr_status_t whole_option(const char *opt, double v, int *out, cdpr_scenario_error_t *err)
{
    if (!isfinite(v) || floor(v) < v || fabs(v) > (double)INT_MAX) {
        snprintf(err->msg, sizeof err->msg, "%s %g: not a whole number", opt, v);
        return isfinite(v) ? CDPR_E_OUT_OF_RANGE : CDPR_E_NOT_FINITE;
    }
    *out = (int)v;
    return CDPR_OK;
}

cdpr_status_t cdpr_scenario_override(cdpr_scenario_t *sc, const cdpr_scenario_overrides_t *ov,
                                     const char *prog, FILE *notes, cdpr_scenario_error_t *err)
{
    const int rig_checked = cdpr_scenario_is_checked(sc);
    const char *of = (sc->path[0] != '\0') ? sc->path : "the scenario";
    char opts[256] = "";
    int trials = sc->integrator.max_trials;
    int attempts = sc->integrator.max_attempts;
    cdpr_status_t ws = (given(ov->max_trials) != 0)
                           ? whole_option("--max-trials", ov->max_trials, &trials, err)
                           : CDPR_OK;
    if (ws == CDPR_OK && given(ov->max_attempts) != 0) {
        ws = whole_option("--max-attempts", ov->max_attempts, &attempts, err);
    }
    if (ws != CDPR_OK) {
        return ws;
    }
    if (given(ov->rate_hz) != 0) {
        const double period = 1.0 / ov->rate_hz;
        if (notes != NULL && differs(period, sc->period_s) != 0) {
            fprintf(notes, "%s: --rate %g Hz overrides run.period_s = %g s (%g Hz) of %s\n", prog,
                    ov->rate_hz, sc->period_s, 1.0 / sc->period_s, of);
        }
        sc->period_s = period;
        snprintf(opts, sizeof opts, "--rate %g Hz", ov->rate_hz);
        /* Outputs faster than the new control rate: every period (a row per period is all
         * there is), said by its own name. */
        if (isfinite(ov->rate_hz) && ov->rate_hz > 0.0 && sc->output_rate_hz > ov->rate_hz) {
            if (notes != NULL) {
                fprintf(notes,
                        "%s: --rate %g Hz: run.output_rate_hz = %g Hz of %s is above it: a row "
                        "every period (%g Hz)\n",
                        prog, ov->rate_hz, sc->output_rate_hz, of, ov->rate_hz);
            }
            sc->output_rate_hz = ov->rate_hz;
        }
    }
    if (given(ov->duration_s) != 0) {
        if (notes != NULL && differs(ov->duration_s, sc->duration_s) != 0) {
            fprintf(notes, "%s: --duration %g s overrides run.duration_s = %g s of %s\n", prog,
                    ov->duration_s, sc->duration_s, of);
        }
        sc->duration_s = ov->duration_s;
        const size_t n = strlen(opts);
        snprintf(opts + n, sizeof opts - n, "%s--duration %g s", (n > 0) ? ", " : "",
                 ov->duration_s);
    }
    if (ov->method >= 0) {
        const cdpr_plant_integrator_t m = (cdpr_plant_integrator_t)ov->method;
        if (m != sc->integrator.method && ov->method < CDPR_SCENARIO_METHODS) {
            /* The method's own settings (integrator.rkf45 / integrator.ros34pw2 of the file);
             * --max-trials / --max-attempts below still apply on top. */
            const cdpr_scenario_integrator_t *in = &sc->integrator_for[m];
            if (notes != NULL) {
                fprintf(notes,
                        "%s: --integrator %s overrides integrator.method = %s of %s (its "
                        "settings: rtol %g, atol %g m, %g m/s, %g, %g rad/s, h_max %g s, "
                        "max_trials %d, max_attempts %d)\n",
                        prog, cdpr_plant_integrator_name(m),
                        cdpr_plant_integrator_name(sc->integrator.method), of, in->rtol,
                        in->atol_position_m, in->atol_velocity_m_per_s, in->atol_quaternion,
                        in->atol_rate_rad_per_s, in->h_max_s, in->max_trials, in->max_attempts);
            }
            sc->integrator = *in;
        }
        sc->integrator.method = m;
        const size_t n = strlen(opts);
        snprintf(opts + n, sizeof opts - n, "%s--integrator %s", (n > 0) ? ", " : "",
                 cdpr_plant_integrator_name(m));
    }
    const struct {
        const char *opt;
        const char *key;
        int *field;
        int value;
        int is_given;
    } counts[2] = {
        {"--max-trials", "integrator.max_trials", &sc->integrator.max_trials, trials,
         given(ov->max_trials)},
        {"--max-attempts", "integrator.max_attempts", &sc->integrator.max_attempts, attempts,
         given(ov->max_attempts)},
    };
    for (int i = 0; i < 2; ++i) {
        if (counts[i].is_given == 0) {
            continue;
        }
        if (notes != NULL && counts[i].value != *counts[i].field) {
            fprintf(notes, "%s: %s %d overrides %s = %d of %s\n", prog, counts[i].opt,
                    counts[i].value, counts[i].key, *counts[i].field, of);
        }
        *counts[i].field = counts[i].value;
        const size_t n = strlen(opts);
        snprintf(opts + n, sizeof opts - n, "%s%s %d", (n > 0) ? ", " : "", counts[i].opt,
                 counts[i].value);
    }
    cdpr_scenario_error_t ce;
    /* The overrides change run and integrator settings only: a robot checked before stays so. */
    const cdpr_status_t st = check_all(sc, rig_checked, &ce);
    sc->checked_stamp = (st == CDPR_OK) ? fingerprint(sc) : 0U;
    if (st != CDPR_OK) {
        if (opts[0] != '\0') {
            snprintf(err->msg, sizeof err->msg, "%.255s: %.1780s", opts, ce.msg);
        } else {
            *err = ce;
        }
    }
    return st;
}
