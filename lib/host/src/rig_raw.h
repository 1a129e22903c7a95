/* SPDX-License-Identifier: BSD-3-Clause */
/// @file rig_raw.h
/// The libcyaml schema of robot descriptions (rig.h): one schema for robot files (rig.c) and a
/// scenario's `robot:` section (scenario.c), which adds `file:`, `preset:` (a base the other
/// keys override) and the preset's polar layout (`towers:`, `attachments:`). Internal to
/// lib/host.
#ifndef CDPR_HOST_RIG_RAW_H
#define CDPR_HOST_RIG_RAW_H

#include <cyaml/cyaml.h>

#include "cdpr/cable.h"
#include "cdpr/host/rig.h"

/// Rope keys as read (optional keys are pointers, so absence is visible).
typedef struct {
    double *d0_m;
    double *rho_kg_per_m;
    double *ea_N;
    double *damping_Ns;
    double *damping_ratio;
    double *damping_ref_hz;
    cdpr_slack_law_t *slack_law;
    double *cd;
    double *cm;
} cdpr_raw_rope_t;

/// Winch keys as read.
typedef struct {
    double *u_max_m_per_s;
    double *a_max_m_per_s2;
    double *kp_per_s;
    double *min_length_m;
} cdpr_raw_winch_t;

/// Tension distribution keys as read (the statics of a redundant robot, statics.h).
typedef struct {
    double *min_N;
    double *max_N;
    double *ref_N;
} cdpr_raw_tensions_t;

/// One entry of `cables:`.
typedef struct {
    double *exit_m;
    double *attach_m;
    cdpr_raw_rope_t *rope;
    cdpr_raw_winch_t *winch;
    double *segments; /* a number, checked to be whole */
} cdpr_raw_rig_cable_t;

/// `cabin:`.
typedef struct {
    double *mass_kg;
    double **inertia_kg_m2; /* three rows of three */
    double *com_m;
} cdpr_raw_cabin_t;

/// `towers:` or `attachments:` of a preset's polar layout (scenario only): radius, height
/// (exit_height_m / z_m) and the six azimuths.
typedef struct {
    double *radius_m;
    double *height_m;
    double *azimuths_deg;
} cdpr_raw_polar_t;

/// A robot description as read: a robot file's top level, or a scenario's `robot:` section
/// (which may hold `file:`, or `preset:` as the base of the other keys).
typedef struct {
    char *file;                    /* scenario only */
    int *preset;                   /* scenario only: a cdpr_preset_t (presets.h) */
    cdpr_raw_polar_t *towers;      /* scenario only, with preset */
    cdpr_raw_polar_t *attachments; /* scenario only, with preset */
    char *description;
    double *gravity_m_per_s2;
    double *air_density_kg_per_m3;
    double *wind_m_per_s;
    double *nominal_pose;
    double *segments;
    cdpr_raw_rope_t *rope;
    cdpr_raw_winch_t *winch;
    cdpr_raw_cabin_t *cabin;
    cdpr_raw_tensions_t *tension_distribution;
    cdpr_raw_rig_cable_t *cables;
    unsigned cables_count;
} cdpr_raw_rig_t;

/// The keys of a description, in a robot file and in a scenario's robot section alike: the
/// entries of a cyaml_schema_field_t array over cdpr_raw_rig_t (rig.c defines the tables).
/// The presets' names as scenario files write them (presets.c; the `preset:` key's enum).
#define CDPR_PRESET_NAME_COUNT 2
extern const cyaml_strval_t cdpr_preset_names[CDPR_PRESET_NAME_COUNT];

extern const cyaml_schema_value_t cdpr_rig_num_schema;
extern const cyaml_schema_field_t cdpr_rig_rope_fields[];
extern const cyaml_schema_field_t cdpr_rig_winch_fields[];
extern const cyaml_schema_field_t cdpr_rig_cabin_fields[];
extern const cyaml_schema_field_t cdpr_rig_tension_fields[];
extern const cyaml_schema_value_t cdpr_rig_cable_entry;

/// Largest `cables:` list read (the count is then checked against CDPR_MAX_CABLES).
#define CDPR_RIG_MAX_LISTED 64

// clang-format off
#define CDPR_RIG_FIELDS                                                                            \
    CYAML_FIELD_STRING_PTR("description", CYAML_FLAG_OPTIONAL, cdpr_raw_rig_t, description, 0,     \
                           255),                                                                   \
    CDPR_RIG_NUM("gravity_m_per_s2", gravity_m_per_s2),                                            \
    CDPR_RIG_NUM("air_density_kg_per_m3", air_density_kg_per_m3),                                  \
    CDPR_RIG_VEC("wind_m_per_s", wind_m_per_s, 3),                                                 \
    CDPR_RIG_VEC("nominal_pose", nominal_pose, 6),                                                 \
    CDPR_RIG_NUM("segments", segments),                                                            \
    CYAML_FIELD_MAPPING_PTR("rope", CYAML_FLAG_OPTIONAL, cdpr_raw_rig_t, rope,                     \
                            cdpr_rig_rope_fields),                                                 \
    CYAML_FIELD_MAPPING_PTR("winch", CYAML_FLAG_OPTIONAL, cdpr_raw_rig_t, winch,                   \
                            cdpr_rig_winch_fields),                                                \
    CYAML_FIELD_MAPPING_PTR("cabin", CYAML_FLAG_OPTIONAL, cdpr_raw_rig_t, cabin,                   \
                            cdpr_rig_cabin_fields),                                                \
    CYAML_FIELD_MAPPING_PTR("tension_distribution", CYAML_FLAG_OPTIONAL, cdpr_raw_rig_t,           \
                            tension_distribution, cdpr_rig_tension_fields),                        \
    CYAML_FIELD_SEQUENCE("cables", CYAML_FLAG_OPTIONAL | CYAML_FLAG_POINTER, cdpr_raw_rig_t,       \
                         cables, &cdpr_rig_cable_entry, 0, CDPR_RIG_MAX_LISTED)
#define CDPR_RIG_NUM(key, member)                                                                  \
    CYAML_FIELD_FLOAT_PTR(key, CYAML_FLAG_OPTIONAL | CYAML_FLAG_STRICT, cdpr_raw_rig_t, member)
#define CDPR_RIG_VEC(key, member, n)                                                               \
    CYAML_FIELD_SEQUENCE_FIXED(key, CYAML_FLAG_OPTIONAL | CYAML_FLAG_POINTER, cdpr_raw_rig_t,      \
                               member, &cdpr_rig_num_schema, n)
// clang-format on

/// Resolve a raw description onto `rig` (whole numbers and the damping form checked; ranges
/// are cdpr_rig_check's). `base` NULL: a complete description (cables:, cabin.mass_kg and
/// cabin.inertia_kg_m2 required; the documented defaults for the optional keys). `base` given
/// (a preset's rig): every key is optional and overrides the base's value (rope:, winch: and
/// segments: apply to every cable, air_density_kg_per_m3 to every rope); cables: is not read.
/// `path`/`prefix` name keys in errors (rig.h). Does not look at the scenario-only members.
/// Returns CDPR_OK or CDPR_E_PARSE / CDPR_E_OUT_OF_RANGE / CDPR_E_NOT_FINITE / CDPR_E_CAPACITY
/// with err filled.
cdpr_status_t cdpr_rig_resolve(const cdpr_raw_rig_t *raw, const cdpr_rig_t *base, const char *path,
                               const char *prefix, cdpr_rig_t *rig, cdpr_rig_error_t *err);

#endif /* CDPR_HOST_RIG_RAW_H */
