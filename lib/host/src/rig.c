/* SPDX-License-Identifier: BSD-3-Clause */
/// @file rig.c
/// Robot descriptions (rig.h): robot files through libcyaml, the core build
/// and the checks (docs/robots.md "Robot files").
#include "cdpr/host/rig.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cdpr/cabin.h"
#include "cdpr/host/yaml.h"
#include "rig_raw.h"

/* ---------------------------------------------------------------- schema */

#define OPT                         CYAML_FLAG_OPTIONAL
#define OPT_NUM                     (CYAML_FLAG_OPTIONAL | CYAML_FLAG_STRICT)
#define OPT_SEQ                     (CYAML_FLAG_OPTIONAL | CYAML_FLAG_POINTER)
#define OPT_NUMP(key, type, member) CYAML_FIELD_FLOAT_PTR(key, OPT_NUM, type, member)
#define OPT_VEC(key, type, member, n)                                                              \
    CYAML_FIELD_SEQUENCE_FIXED(key, OPT_SEQ, type, member, &cdpr_rig_num_schema, n)

/* Strict floats: overflow such as 1e999 is an error, not Inf; "4O.0" is not a number. */
const cyaml_schema_value_t cdpr_rig_num_schema = {CYAML_VALUE_FLOAT(CYAML_FLAG_STRICT, double)};
static const cyaml_schema_value_t row = {
    CYAML_VALUE_SEQUENCE_FIXED(CYAML_FLAG_POINTER, double, &cdpr_rig_num_schema, 3),
};

static const cyaml_strval_t slack_law_names[] = {
    {"passive", CDPR_SLACK_PASSIVE},
    {"moordyn", CDPR_SLACK_MOORDYN},
};
const cyaml_schema_field_t cdpr_rig_rope_fields[] = {
    OPT_NUMP("d0_m", cdpr_raw_rope_t, d0_m),
    OPT_NUMP("rho_kg_per_m", cdpr_raw_rope_t, rho_kg_per_m),
    OPT_NUMP("ea_N", cdpr_raw_rope_t, ea_N),
    OPT_NUMP("damping_Ns", cdpr_raw_rope_t, damping_Ns),
    OPT_NUMP("damping_ratio", cdpr_raw_rope_t, damping_ratio),
    OPT_NUMP("damping_ref_hz", cdpr_raw_rope_t, damping_ref_hz),
    CYAML_FIELD_ENUM_PTR("slack_law", OPT | CYAML_FLAG_STRICT, cdpr_raw_rope_t, slack_law,
                         slack_law_names, CYAML_ARRAY_LEN(slack_law_names)),
    OPT_NUMP("cd", cdpr_raw_rope_t, cd),
    OPT_NUMP("cm", cdpr_raw_rope_t, cm),
    CYAML_FIELD_END,
};
const cyaml_schema_field_t cdpr_rig_winch_fields[] = {
    OPT_NUMP("u_max_m_per_s", cdpr_raw_winch_t, u_max_m_per_s),
    OPT_NUMP("a_max_m_per_s2", cdpr_raw_winch_t, a_max_m_per_s2),
    OPT_NUMP("kp_per_s", cdpr_raw_winch_t, kp_per_s),
    OPT_NUMP("min_length_m", cdpr_raw_winch_t, min_length_m),
    CYAML_FIELD_END,
};
const cyaml_schema_field_t cdpr_rig_tension_fields[] = {
    OPT_NUMP("min_N", cdpr_raw_tensions_t, min_N),
    OPT_NUMP("max_N", cdpr_raw_tensions_t, max_N),
    OPT_NUMP("ref_N", cdpr_raw_tensions_t, ref_N),
    CYAML_FIELD_END,
};
static const cyaml_schema_field_t cable_fields[] = {
    OPT_VEC("exit_m", cdpr_raw_rig_cable_t, exit_m, 3),
    OPT_VEC("attach_m", cdpr_raw_rig_cable_t, attach_m, 3),
    CYAML_FIELD_MAPPING_PTR("rope", OPT, cdpr_raw_rig_cable_t, rope, cdpr_rig_rope_fields),
    CYAML_FIELD_MAPPING_PTR("winch", OPT, cdpr_raw_rig_cable_t, winch, cdpr_rig_winch_fields),
    OPT_NUMP("segments", cdpr_raw_rig_cable_t, segments),
    CYAML_FIELD_END,
};
const cyaml_schema_value_t cdpr_rig_cable_entry = {
    CYAML_VALUE_MAPPING(CYAML_FLAG_DEFAULT, cdpr_raw_rig_cable_t, cable_fields),
};
const cyaml_schema_field_t cdpr_rig_cabin_fields[] = {
    OPT_NUMP("mass_kg", cdpr_raw_cabin_t, mass_kg),
    CYAML_FIELD_SEQUENCE_FIXED("inertia_kg_m2", OPT_SEQ, cdpr_raw_cabin_t, inertia_kg_m2, &row, 3),
    OPT_VEC("com_m", cdpr_raw_cabin_t, com_m, 3),
    CYAML_FIELD_END,
};

static const cyaml_schema_field_t file_fields[] = {
    CDPR_RIG_FIELDS,
    CYAML_FIELD_END,
};
static const cyaml_schema_value_t file_schema = {
    CYAML_VALUE_MAPPING(CYAML_FLAG_POINTER, cdpr_raw_rig_t, file_fields),
};

/* ---------------------------------------------------------------- errors */

/* "FILE:LINE: PREFIXKEY: what". A per-cable key that the file does not hold but whose
 * robot-level default it does ("cables[2].rope.ea_N" from "rope.ea_N") is named by the
 * default, with the cable. */
static cdpr_status_t rig_error(const char *path, const char *prefix, const char *key,
                               const char *what, cdpr_status_t st, cdpr_rig_error_t *err)
{
    if (err == NULL) {
        return st;
    }
    const char *p = (path != NULL) ? path : "";
    char full[256];
    snprintf(full, sizeof full, "%s%s", prefix, key);
    int line = cdpr_yaml_path_line(p, full);
    const char *dot = strchr(key, '.');
    int cable = -1;
    if (line == 0 && dot != NULL && strncmp(key, "cables[", 7) == 0) {
        char *end = NULL;
        const long c = strtol(key + 7, &end, 10);
        cable = (end != key + 7 && *end == ']' && c >= 0 && c < 1000) ? (int)c : -1;
    }
    if (cable >= 0) {
        char alt[256];
        snprintf(alt, sizeof alt, "%s%s", prefix, dot + 1);
        const int alt_line = cdpr_yaml_path_line(p, alt);
        if (alt_line > 0) {
            snprintf(full, sizeof full, "%.200s (cable %d)", alt, cable + 1);
            line = alt_line;
        }
    }
    if (line == 0) {
        /* A missing key: the line of the mapping that lacks it. */
        char parent[256];
        snprintf(parent, sizeof parent, "%s%s", prefix, key);
        char *cut = strrchr(parent, '.');
        if (cut != NULL) {
            *cut = '\0';
            line = cdpr_yaml_path_line(p, parent);
        }
    }
    cdpr_yaml_format_error(err->msg, sizeof err->msg, p, line, full, what);
    return st;
}

/* ---------------------------------------------------------------- presets and the build */

/* The same steps, in the same order, as cdpr_preset_build (presets.c): bit-identical. */
cdpr_status_t cdpr_rig_build(const cdpr_rig_t *rig, const double *length_m, cdpr_robot_params_t *p,
                             cdpr_winch_params_t *w, cdpr_diag_t *diag)
{
    if (rig == NULL || p == NULL) {
        return cdpr_diag_set(diag, CDPR_E_INVALID_ARG, "config", -1);
    }
    if (rig->n_cables < 1 || rig->n_cables > CDPR_MAX_CABLES) {
        return cdpr_diag_set(diag, CDPR_E_CAPACITY, "n_cables", rig->n_cables);
    }
    cdpr_robot_params_t rp;
    memset(&rp, 0, sizeof rp); /* padding too: equal rigs give equal bytes */
    cdpr_robot_params_default(&rp);
    rp.n_cables = rig->n_cables;
    rp.g_m_per_s2 = rig->gravity_m_per_s2;
    rp.mode = CDPR_CABIN_DYNAMIC;
    rp.has_tension_dist = rig->has_tension_distribution;
    rp.tension_min_N = rig->tension_min_N;
    rp.tension_max_N = rig->tension_max_N;
    rp.tension_ref_N = rig->tension_ref_N;
    rp.cabin.mass_kg = rig->cabin_mass_kg;
    rp.cabin.com_body_m = cdpr_v3(rig->cabin_com_m[0], rig->cabin_com_m[1], rig->cabin_com_m[2]);
    for (int i = 0; i < 3; ++i) {
        for (int k = 0; k < 3; ++k) {
            rp.cabin.inertia_com_kg_m2.m[i][k] = rig->cabin_inertia_kg_m2[i][k];
        }
    }
    const cdpr_cabin_motion_t nominal = cdpr_cabin_motion_at_pose(rig->nominal_pose);
    cdpr_mat3_t R;
    cdpr_quat_to_mat3(nominal.q, &R);
    for (int j = 0; j < rig->n_cables; ++j) {
        const cdpr_rig_cable_t *rc = &rig->cable[j];
        cdpr_robot_cable_params_t *c = &rp.cables[j];
        c->cable = rc->rope;
        c->exit_point_m = cdpr_v3(rc->exit_m[0], rc->exit_m[1], rc->exit_m[2]);
        c->attach_body_m = cdpr_v3(rc->attach_m[0], rc->attach_m[1], rc->attach_m[2]);
        c->n_segments = rc->segments;
        if (length_m != NULL) {
            c->length_m = length_m[j];
        } else {
            const cdpr_vec3_t a = cdpr_v3_add(nominal.p_m, cdpr_m3_mul_v3(&R, c->attach_body_m));
            c->length_m = cdpr_v3_norm(cdpr_v3_sub(c->exit_point_m, a));
        }
    }
    /* Validate with the core's own rules (scratch object: nothing is kept). */
    static const cdpr_robot_t zero;
    cdpr_robot_t scratch = zero;
    const cdpr_status_t st = cdpr_robot_init(&scratch, &rp, diag);
    if (st != CDPR_OK) {
        return st;
    }
    if (w != NULL) {
        for (int j = 0; j < rig->n_cables; ++j) {
            cdpr_winch_t wt;
            const cdpr_status_t ws = cdpr_winch_init(&wt, &rig->cable[j].winch, diag);
            if (ws != CDPR_OK) {
                return cdpr_diag_set(diag, ws, (diag != NULL) ? diag->field : "winch", j);
            }
        }
        for (int j = 0; j < CDPR_MAX_CABLES; ++j) {
            w[j] = rig->cable[(j < rig->n_cables) ? j : 0].winch;
        }
    }
    *p = rp;
    return cdpr_diag_set(diag, CDPR_OK, "", -1);
}

/* ---------------------------------------------------------------- resolve */

typedef struct {
    const char *path;
    const char *prefix;
    cdpr_rig_error_t *err;
    cdpr_status_t failed; /* CDPR_OK until the first failure */
} rctx_t;

static void fail(rctx_t *v, const char *key, const char *what, cdpr_status_t st)
{
    if (v->failed == CDPR_OK) {
        v->failed = rig_error(v->path, v->prefix, key, what, st, v->err);
    }
}

/* A count: a finite whole number in [lo, hi]. */
static int whole(rctx_t *v, const char *key, double x, int lo, int hi)
{
    if (!isfinite(x) || floor(x) < x || x < (double)lo || x > (double)hi) {
        char what[256];
        snprintf(what, sizeof what, "%g is not a whole number in [%d, %d]", x, lo, hi);
        fail(v, key, what, isfinite(x) ? CDPR_E_OUT_OF_RANGE : CDPR_E_NOT_FINITE);
        return lo;
    }
    return (int)x;
}

static void take(double *dst, const double *src, int n)
{
    if (src != NULL) {
        memcpy(dst, src, sizeof(double) * (size_t)n);
    }
}

/* A rope mapping over `r` (given values only); `where` is its key ("rope", "cables[1].rope").
 * Sets *damping when the mapping gives a damping form. */
static void apply_rope(rctx_t *v, const cdpr_raw_rope_t *raw, const char *where,
                       cdpr_cable_params_t *r, int *has_d0, int *has_rho, int *has_ea,
                       int *has_damping)
{
    if (raw == NULL) {
        return;
    }
    if (raw->damping_Ns != NULL && raw->damping_ratio != NULL) {
        char key[96];
        snprintf(key, sizeof key, "%s.damping_ratio", where);
        fail(v, key, "give damping_Ns or damping_ratio (+ damping_ref_hz), not both", CDPR_E_PARSE);
        return;
    }
    *has_d0 |= (raw->d0_m != NULL) ? 1 : 0;
    *has_rho |= (raw->rho_kg_per_m != NULL) ? 1 : 0;
    *has_ea |= (raw->ea_N != NULL) ? 1 : 0;
    take(&r->d0_m, raw->d0_m, 1);
    take(&r->rho_kg_per_m, raw->rho_kg_per_m, 1);
    take(&r->ea_N, raw->ea_N, 1);
    if (raw->damping_Ns != NULL) {
        r->damping_Ns = *raw->damping_Ns;
        r->damping_ratio = 0.0;
        *has_damping = 1;
    }
    if (raw->damping_ratio != NULL) {
        r->damping_ratio = *raw->damping_ratio;
        r->damping_Ns = 0.0;
        *has_damping = 1;
    }
    take(&r->damping_ref_hz, raw->damping_ref_hz, 1);
    if (raw->slack_law != NULL) {
        r->slack_law = *raw->slack_law;
    }
    take(&r->cd, raw->cd, 1);
    take(&r->cm, raw->cm, 1);
}

static void apply_winch(const cdpr_raw_winch_t *raw, cdpr_winch_params_t *w, int has[4])
{
    if (raw == NULL) {
        return;
    }
    const double *src[4] = {raw->u_max_m_per_s, raw->a_max_m_per_s2, raw->kp_per_s,
                            raw->min_length_m};
    double *dst[4] = {&w->u_max_m_per_s, &w->a_max_m_per_s2, &w->kp_per_s, &w->min_length_m};
    for (int i = 0; i < 4; ++i) {
        if (src[i] != NULL) {
            *dst[i] = *src[i];
            has[i] = 1;
        }
    }
}

static void missing(rctx_t *v, int j, const char *section, const char *key)
{
    char k[128];
    char what[256];
    snprintf(k, sizeof k, "cables[%d].%s.%s", j, section, key);
    snprintf(what, sizeof what,
             "missing required key (give %s.%s for every cable or "
             "cables[%d].%s.%s)",
             section, key, j, section, key);
    fail(v, k, what, CDPR_E_PARSE);
}

/* Cable j: the robot-level defaults, then its own keys. */
static void resolve_cable(rctx_t *v, const cdpr_raw_rig_t *raw, int j, double air,
                          cdpr_rig_cable_t *c)
{
    const cdpr_raw_rig_cable_t *rc = &raw->cables[j];
    char key[96];
    if (rc->exit_m == NULL || rc->attach_m == NULL) {
        snprintf(key, sizeof key, "cables[%d].%s", j, (rc->exit_m == NULL) ? "exit_m" : "attach_m");
        fail(v, key, "missing required key", CDPR_E_PARSE);
        return;
    }
    take(c->exit_m, rc->exit_m, 3);
    take(c->attach_m, rc->attach_m, 3);
    /* Rope: defaults of the optional keys (docs/robots.md), then rope:, then the cable's. */
    cdpr_cable_params_t *r = &c->rope;
    memset(r, 0, sizeof *r);
    r->slack_law = CDPR_SLACK_PASSIVE;
    r->damping_ref_hz = 5.0;
    r->cd = 1.2;
    r->cm = 0.03;
    r->rho_air_kg_per_m3 = air;
    int has_d0 = 0;
    int has_rho = 0;
    int has_ea = 0;
    int has_damping = 0;
    apply_rope(v, raw->rope, "rope", r, &has_d0, &has_rho, &has_ea, &has_damping);
    snprintf(key, sizeof key, "cables[%d].rope", j);
    apply_rope(v, rc->rope, key, r, &has_d0, &has_rho, &has_ea, &has_damping);
    if (v->failed != CDPR_OK) {
        return;
    }
    if (has_d0 == 0 || has_rho == 0 || has_ea == 0 || has_damping == 0) {
        missing(v, j, "rope",
                (has_d0 == 0)
                    ? "d0_m"
                    : ((has_rho == 0) ? "rho_kg_per_m" : ((has_ea == 0) ? "ea_N" : "damping_Ns")));
        return;
    }
    /* Winch: every limit given at either level. */
    static const char *const winch_keys[4] = {"u_max_m_per_s", "a_max_m_per_s2", "kp_per_s",
                                              "min_length_m"};
    int has[4] = {0, 0, 0, 0};
    apply_winch(raw->winch, &c->winch, has);
    apply_winch(rc->winch, &c->winch, has);
    for (int i = 0; i < 4; ++i) {
        if (has[i] == 0) {
            missing(v, j, "winch", winch_keys[i]);
            return;
        }
    }
    const double *seg = (rc->segments != NULL) ? rc->segments : raw->segments;
    if (seg == NULL) {
        snprintf(key, sizeof key, "cables[%d].segments", j);
        fail(v, key, "missing required key (give segments for every cable or per cable)",
             CDPR_E_PARSE);
        return;
    }
    snprintf(key, sizeof key, (rc->segments != NULL) ? "cables[%d].segments" : "segments", j);
    c->segments = whole(v, key, *seg, 1, CDPR_MAX_SEGMENTS);
}

/* A complete description (no base): required keys, the documented defaults of the others. */
static void resolve_full(rctx_t *v, const cdpr_raw_rig_t *raw, cdpr_rig_t *rig)
{
    if (raw->cables == NULL || raw->cables_count == 0) {
        fail(v, "cables", "missing required key (one entry per cable)", CDPR_E_PARSE);
        return;
    }
    if (raw->cables_count > (unsigned)CDPR_MAX_CABLES) {
        char what[256];
        snprintf(what, sizeof what,
                 "%u cables: this build supports 1 to %d (CDPR_MAX_CABLES, lib/core config.h)",
                 raw->cables_count, CDPR_MAX_CABLES);
        fail(v, "cables", what, CDPR_E_CAPACITY);
        return;
    }
    if (raw->cabin == NULL || raw->cabin->mass_kg == NULL || raw->cabin->inertia_kg_m2 == NULL) {
        fail(v,
             (raw->cabin == NULL)
                 ? "cabin"
                 : ((raw->cabin->mass_kg == NULL) ? "cabin.mass_kg" : "cabin.inertia_kg_m2"),
             "missing required key", CDPR_E_PARSE);
        return;
    }
    rig->n_cables = (int)raw->cables_count;
    rig->gravity_m_per_s2 = 9.80665;
    double air = 1.225;
    take(&air, raw->air_density_kg_per_m3, 1);
    for (int j = 0; j < rig->n_cables && v->failed == CDPR_OK; ++j) {
        resolve_cable(v, raw, j, air, &rig->cable[j]);
    }
    if (raw->nominal_pose == NULL) {
        /* Under the exit points' centroid, at half their mean height. */
        for (int j = 0; j < rig->n_cables; ++j) {
            for (int i = 0; i < 3; ++i) {
                rig->nominal_pose[i] += rig->cable[j].exit_m[i] / (double)rig->n_cables;
            }
        }
        rig->nominal_pose[2] *= 0.5;
    }
}

/* Overrides of a base (a preset's rig): robot-level keys only, each applied to every cable. */
static void resolve_over(rctx_t *v, const cdpr_raw_rig_t *raw, cdpr_rig_t *rig)
{
    int unused[4] = {0, 0, 0, 0};
    for (int j = 0; j < rig->n_cables && v->failed == CDPR_OK; ++j) {
        cdpr_rig_cable_t *c = &rig->cable[j];
        take(&c->rope.rho_air_kg_per_m3, raw->air_density_kg_per_m3, 1);
        apply_rope(v, raw->rope, "rope", &c->rope, &unused[0], &unused[1], &unused[2], &unused[3]);
        apply_winch(raw->winch, &c->winch, unused);
        if (raw->segments != NULL) {
            c->segments = whole(v, "segments", *raw->segments, 1, CDPR_MAX_SEGMENTS);
        }
    }
}

cdpr_status_t cdpr_rig_resolve(const cdpr_raw_rig_t *raw, const cdpr_rig_t *base, const char *path,
                               const char *prefix, cdpr_rig_t *rig, cdpr_rig_error_t *err)
{
    rctx_t v = {path, prefix, err, CDPR_OK};
    if (base != NULL) {
        *rig = *base;
        resolve_over(&v, raw, rig);
    } else {
        memset(rig, 0, sizeof *rig);
        snprintf(rig->name, sizeof rig->name, "%s",
                 (path != NULL && path[0] != '\0' && prefix[0] == '\0') ? path : "embedded");
        resolve_full(&v, raw, rig);
    }
    if (v.failed != CDPR_OK) {
        return v.failed;
    }
    /* Robot-level values, over the defaults or the base. */
    take(&rig->gravity_m_per_s2, raw->gravity_m_per_s2, 1);
    take(rig->wind_m_per_s, raw->wind_m_per_s, 3);
    take(rig->nominal_pose, raw->nominal_pose, 6);
    if (raw->cabin != NULL) {
        take(&rig->cabin_mass_kg, raw->cabin->mass_kg, 1);
        if (raw->cabin->inertia_kg_m2 != NULL) {
            for (int i = 0; i < 3; ++i) {
                take(rig->cabin_inertia_kg_m2[i], raw->cabin->inertia_kg_m2[i], 3);
            }
        }
        take(rig->cabin_com_m, raw->cabin->com_m, 3);
    }
    const cdpr_raw_tensions_t *td = raw->tension_distribution;
    if (td != NULL) {
        if (td->min_N == NULL || td->max_N == NULL) {
            fail(&v,
                 (td->min_N == NULL) ? "tension_distribution.min_N" : "tension_distribution.max_N",
                 "missing required key", CDPR_E_PARSE);
            return v.failed;
        }
        rig->has_tension_distribution = 1;
        rig->tension_min_N = *td->min_N;
        rig->tension_max_N = *td->max_N;
        rig->tension_ref_N =
            (td->ref_N != NULL) ? *td->ref_N : 0.5 * (rig->tension_min_N + rig->tension_max_N);
    }
    return CDPR_OK;
}

/* ---------------------------------------------------------------- checks */

/* Every x[i] finite and in [lo, hi] (or (lo, hi] when lo_open): cdpr_yaml_range. */
static void range(rctx_t *v, const char *key, const double *x, int n, double lo, double hi,
                  int lo_open)
{
    char k[128];
    char what[256];
    const cdpr_status_t st =
        cdpr_yaml_range(key, x, n, lo, hi, lo_open, k, sizeof k, what, sizeof what);
    if (st != CDPR_OK) {
        fail(v, k, what, st);
    }
}

void cdpr_rig_principal_moments(const double m[3][3], double eig[3])
{
    const double p1 = m[0][1] * m[0][1] + m[0][2] * m[0][2] + m[1][2] * m[1][2];
    double e[3];
    if (!(p1 > 0.0)) {
        e[0] = m[0][0];
        e[1] = m[1][1];
        e[2] = m[2][2];
    } else {
        /* Trigonometric solution of the characteristic cubic (Smith 1961). */
        const double q = (m[0][0] + m[1][1] + m[2][2]) / 3.0;
        const double d0 = m[0][0] - q;
        const double d1 = m[1][1] - q;
        const double d2 = m[2][2] - q;
        const double p = sqrt((d0 * d0 + d1 * d1 + d2 * d2 + 2.0 * p1) / 6.0);
        const double b00 = d0 / p;
        const double b11 = d1 / p;
        const double b22 = d2 / p;
        const double b01 = m[0][1] / p;
        const double b02 = m[0][2] / p;
        const double b12 = m[1][2] / p;
        const double det = b00 * (b11 * b22 - b12 * b12) - b01 * (b01 * b22 - b12 * b02) +
                           b02 * (b01 * b12 - b11 * b02);
        double r = 0.5 * det;
        r = (r < -1.0) ? -1.0 : ((r > 1.0) ? 1.0 : r);
        const double phi = acos(r) / 3.0;
        e[0] = q + 2.0 * p * cos(phi);
        e[2] = q + 2.0 * p * cos(phi + 2.0 * CDPR_PI / 3.0);
        e[1] = 3.0 * q - e[0] - e[2];
    }
    /* Ascending. */
    for (int i = 0; i < 2; ++i) {
        for (int k = i + 1; k < 3; ++k) {
            if (e[k] < e[i]) {
                const double t = e[i];
                e[i] = e[k];
                e[k] = t;
            }
        }
    }
    memcpy(eig, e, sizeof e);
}

cdpr_status_t cdpr_rig_inertia_plausible(const double I[3][3], char *what, size_t cap)
{
    const double scale = fabs(I[0][0]) + fabs(I[1][1]) + fabs(I[2][2]);
    const double m1 = I[0][0];
    const double m2 = I[0][0] * I[1][1] - I[0][1] * I[0][1];
    const double m3 = I[0][0] * (I[1][1] * I[2][2] - I[1][2] * I[1][2]) -
                      I[0][1] * (I[0][1] * I[2][2] - I[1][2] * I[0][2]) +
                      I[0][2] * (I[0][1] * I[1][2] - I[1][1] * I[0][2]);
    double e[3];
    cdpr_rig_principal_moments(I, e);
    if (!(m1 > 0.0) || !(m2 > 0.0) || !(m3 > 0.0) || !(e[0] > 0.0)) {
        snprintf(what, cap,
                 "not positive definite (principal moments %g, %g, %g kg m^2): every moment of "
                 "a rigid body is > 0",
                 e[0], e[1], e[2]);
        return CDPR_E_NOT_POSITIVE;
    }
    if (e[0] + e[1] < e[2] - 1e-9 * scale) {
        snprintf(what, cap,
                 "principal moments %g, %g, %g kg m^2 break the triangle inequality "
                 "(%g + %g < %g): no rigid body has them",
                 e[0], e[1], e[2], e[0], e[1], e[2]);
        return CDPR_E_OUT_OF_RANGE;
    }
    return CDPR_OK;
}

/* Symmetric, positive definite, physical (triangle inequalities of the principal moments). */
static void check_inertia(rctx_t *v, const double I[3][3])
{
    for (int i = 0; i < 3; ++i) {
        char k[64];
        snprintf(k, sizeof k, "cabin.inertia_kg_m2[%d]", i);
        range(v, k, I[i], 3, -1e12, 1e12, 0);
    }
    if (v->failed != CDPR_OK) {
        return;
    }
    const double scale = fabs(I[0][0]) + fabs(I[1][1]) + fabs(I[2][2]);
    char what[256];
    for (int i = 0; i < 3; ++i) {
        for (int k = i + 1; k < 3; ++k) {
            if (fabs(I[i][k] - I[k][i]) > 1e-9 * scale) {
                char key[64];
                snprintf(key, sizeof key, "cabin.inertia_kg_m2[%d][%d]", k, i);
                snprintf(what, sizeof what, "not symmetric: [%d][%d] = %g but [%d][%d] = %g", k, i,
                         I[k][i], i, k, I[i][k]);
                fail(v, key, what, CDPR_E_OUT_OF_RANGE);
                return;
            }
        }
    }
    const cdpr_status_t st = cdpr_rig_inertia_plausible(I, what, sizeof what);
    if (st != CDPR_OK) {
        fail(v, "cabin.inertia_kg_m2", what, st);
    }
}

static void check_pose(rctx_t *v, const char *key, const double *pose)
{
    for (int i = 0; i < 6 && v->failed == CDPR_OK; ++i) {
        char k[64];
        snprintf(k, sizeof k, "%s[%d]", key, i);
        const double lim = (i < 3) ? 1e4 : 2.0 * CDPR_PI;
        range(v, k, &pose[i], 1, -lim, lim, 0);
    }
}

static void check_cable(rctx_t *v, int j, const cdpr_rig_cable_t *c)
{
    char k[96];
#define KEY(name) (snprintf(k, sizeof k, "cables[%d].%s", j, name), k)
    range(v, KEY("exit_m"), c->exit_m, 3, -1e4, 1e4, 0);
    range(v, KEY("attach_m"), c->attach_m, 3, -1e3, 1e3, 0);
    const cdpr_cable_params_t *r = &c->rope;
    range(v, KEY("rope.d0_m"), &r->d0_m, 1, 0.0, 1.0, 1);
    range(v, KEY("rope.rho_kg_per_m"), &r->rho_kg_per_m, 1, 0.0, 1e4, 1);
    range(v, KEY("rope.ea_N"), &r->ea_N, 1, 0.0, 1e13, 1);
    range(v, KEY("rope.damping_Ns"), &r->damping_Ns, 1, 0.0, 1e12, 0);
    range(v, KEY("rope.damping_ratio"), &r->damping_ratio, 1, 0.0, 1.0, 0);
    range(v, KEY("rope.damping_ref_hz"), &r->damping_ref_hz, 1, 0.0, 1e4, 1);
    range(v, KEY("rope.cd"), &r->cd, 1, 0.0, 10.0, 0);
    range(v, KEY("rope.cm"), &r->cm, 1, 0.0, 10.0, 0);
    range(v, KEY("winch.u_max_m_per_s"), &c->winch.u_max_m_per_s, 1, 0.0, 1e3, 1);
    range(v, KEY("winch.a_max_m_per_s2"), &c->winch.a_max_m_per_s2, 1, 0.0, 1e4, 1);
    range(v, KEY("winch.kp_per_s"), &c->winch.kp_per_s, 1, 0.0, 1e4, 1);
    range(v, KEY("winch.min_length_m"), &c->winch.min_length_m, 1, 0.0, 1e5, 1);
    if (v->failed == CDPR_OK && (c->segments < 1 || c->segments > CDPR_MAX_SEGMENTS)) {
        char what[128];
        snprintf(what, sizeof what, "%d is outside [1, %d]", c->segments, CDPR_MAX_SEGMENTS);
        fail(v, KEY("segments"), what, CDPR_E_OUT_OF_RANGE);
    }
#undef KEY
}

cdpr_status_t cdpr_rig_check(const cdpr_rig_t *rig, const char *path, const char *prefix,
                             cdpr_rig_error_t *err)
{
    rctx_t v = {(path != NULL) ? path : "", (prefix != NULL) ? prefix : "", err, CDPR_OK};
    if (rig->n_cables < 1 || rig->n_cables > CDPR_MAX_CABLES) {
        char what[128];
        snprintf(what, sizeof what, "%d cables: this build supports 1 to %d (CDPR_MAX_CABLES)",
                 rig->n_cables, CDPR_MAX_CABLES);
        fail(&v, "cables", what, CDPR_E_CAPACITY);
        return v.failed;
    }
    range(&v, "gravity_m_per_s2", &rig->gravity_m_per_s2, 1, 0.0, 100.0, 1);
    range(&v, "wind_m_per_s", rig->wind_m_per_s, 3, -100.0, 100.0, 0);
    range(&v, "air_density_kg_per_m3", &rig->cable[0].rope.rho_air_kg_per_m3, 1, 0.0, 100.0, 0);
    check_pose(&v, "nominal_pose", rig->nominal_pose);
    range(&v, "cabin.mass_kg", &rig->cabin_mass_kg, 1, 0.0, 1e9, 1);
    range(&v, "cabin.com_m", rig->cabin_com_m, 3, -1e3, 1e3, 0);
    if (rig->has_tension_distribution != 0) {
        range(&v, "tension_distribution.min_N", &rig->tension_min_N, 1, 0.0, 1e9, 0);
        range(&v, "tension_distribution.max_N", &rig->tension_max_N, 1, 0.0, 1e9, 1);
        if (v.failed == CDPR_OK && !(rig->tension_max_N > rig->tension_min_N)) {
            char what[160];
            snprintf(what, sizeof what, "%g N is not above min_N = %g N", rig->tension_max_N,
                     rig->tension_min_N);
            fail(&v, "tension_distribution.max_N", what, CDPR_E_OUT_OF_RANGE);
        }
        range(&v, "tension_distribution.ref_N", &rig->tension_ref_N, 1, rig->tension_min_N,
              rig->tension_max_N, 0);
    }
    if (v.failed == CDPR_OK) {
        check_inertia(&v, rig->cabin_inertia_kg_m2);
    }
    for (int j = 0; j < rig->n_cables && v.failed == CDPR_OK; ++j) {
        check_cable(&v, j, &rig->cable[j]);
    }
    if (v.failed != CDPR_OK) {
        return v.failed;
    }
    cdpr_robot_params_t p;
    cdpr_diag_t d;
    memset(&d, 0, sizeof d);
    cdpr_winch_params_t w[CDPR_MAX_CABLES];
    const cdpr_status_t st = cdpr_rig_build(rig, NULL, &p, w, &d);
    if (st != CDPR_OK) {
        char key[64];
        char what[512];
        if (d.index >= 0 && d.index < rig->n_cables) {
            snprintf(key, sizeof key, "cables[%d]", d.index);
            snprintf(what, sizeof what, "rejected by the model: field '%s' (cable %d): %s%s",
                     d.field, d.index + 1, cdpr_status_str(st),
                     (strcmp(d.field, "length_m") == 0)
                         ? " (the attachment at the nominal pose is on the exit point)"
                         : "");
        } else {
            snprintf(key, sizeof key, "cabin");
            snprintf(what, sizeof what, "rejected by the model: field '%s': %s", d.field,
                     cdpr_status_str(st));
        }
        fail(&v, key, what, st);
    }
    return v.failed;
}

/* ---------------------------------------------------------------- files */

cdpr_status_t cdpr_rig_load(const char *path, cdpr_rig_t *rig, cdpr_rig_error_t *err)
{
    if (strlen(path) >= sizeof rig->name) {
        snprintf(err->msg, sizeof err->msg,
                 "%.200s...: path too long (%zu characters; a robot-file path has at most %zu)",
                 path, strlen(path), sizeof rig->name - 1U);
        return CDPR_E_INVALID_ARG;
    }
    /* The file the path names, links and ".." resolved: only a .yaml/.yml file is read (a
     * scenario's robot.file cannot make the loader read, or echo, any other file), and the
     * resolved path is the rig's name, so the summary says which file ran. */
    char *resolved = realpath(path, NULL);
    if (resolved == NULL) {
        snprintf(err->msg, sizeof err->msg, "%s: cannot open robot file: %s", path,
                 strerror(errno));
        return CDPR_E_IO;
    }
    char real[sizeof rig->name];
    const size_t len = strlen(resolved);
    (void)snprintf(real, sizeof real, "%s", resolved);
    const int yaml_ext = ((len > 5U && strcmp(resolved + len - 5U, ".yaml") == 0) ||
                          (len > 4U && strcmp(resolved + len - 4U, ".yml") == 0))
                             ? 1
                             : 0;
    free(resolved);
    if (yaml_ext == 0 || len >= sizeof rig->name) {
        snprintf(err->msg, sizeof err->msg,
                 "%s: cannot open robot file: %s (the path resolves to %.200s%s)", path,
                 (yaml_ext == 0) ? "not a robot file, whose name ends in .yaml or .yml"
                                 : "path too long once resolved",
                 real, (len > 200U) ? "..." : "");
        return CDPR_E_IO;
    }
    void *data = NULL;
    cdpr_status_t st = cdpr_yaml_load_reported(real, path, &file_schema, "robot file", &data,
                                               err->msg, sizeof err->msg);
    if (st != CDPR_OK) {
        return st;
    }
    st = cdpr_rig_resolve(data, NULL, path, "", rig, err);
    if (st == CDPR_OK) {
        st = cdpr_rig_check(rig, path, "", err);
    }
    if (st == CDPR_OK) {
        (void)snprintf(rig->name, sizeof rig->name, "%s", real);
    }
    cdpr_yaml_free(&file_schema, data);
    return st;
}

cdpr_rig_scale_t cdpr_rig_scale_unit(void)
{
    const cdpr_rig_scale_t s = {1.0, 1.0, 1.0};
    return s;
}

int cdpr_rig_scale_is_unit(const cdpr_rig_scale_t *s)
{
    /* Exact comparisons on purpose: "unchanged" means the factors as written, 1. */
    const int ea = (s->ea >= 1.0 && s->ea <= 1.0) ? 1 : 0;
    const int cabin = (s->cabin_mass >= 1.0 && s->cabin_mass <= 1.0) ? 1 : 0;
    const int rope = (s->rope_mass >= 1.0 && s->rope_mass <= 1.0) ? 1 : 0;
    return ea & cabin & rope;
}

void cdpr_rig_scale(cdpr_rig_t *rig, const cdpr_rig_scale_t *s)
{
    for (int j = 0; j < rig->n_cables; ++j) {
        rig->cable[j].rope.ea_N *= s->ea;
        rig->cable[j].rope.rho_kg_per_m *= s->rope_mass;
    }
    rig->cabin_mass_kg *= s->cabin_mass;
    for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 3; ++c) {
            rig->cabin_inertia_kg_m2[r][c] *= s->cabin_mass;
        }
    }
}
