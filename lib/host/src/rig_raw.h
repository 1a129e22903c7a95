/* SPDX-License-Identifier: BSD-3-Clause */
/// @file rig_raw.h
/// The libcyaml schema of robot descriptions (rig.h), shared by robot files (rig.c) and the
/// scenario's `robot:` section when it names a file or embeds a robot (scenario.c). Internal
/// to lib/host.
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

/// A robot description as read: a robot file's top level, or a scenario's `robot:` section
/// (which may hold `file:` instead).
typedef struct {
    char *file; /* scenario only */
    char *description;
    double *gravity_m_per_s2;
    double *air_density_kg_per_m3;
    double *wind_m_per_s;
    double *nominal_pose;
    double *segments;
    cdpr_raw_rope_t *rope;
    cdpr_raw_winch_t *winch;
    cdpr_raw_cabin_t *cabin;
    cdpr_raw_rig_cable_t *cables;
    unsigned cables_count;
} cdpr_raw_rig_t;

/// Fields of a scenario's `robot:` section when it has no `preset:` (file or embedded robot).
extern const cyaml_schema_field_t cdpr_rig_scenario_fields[];

/// Resolve a raw description onto `rig` (defaults applied, whole numbers and the damping form
/// checked; ranges are cdpr_rig_check's). `path`/`prefix` name keys in errors (rig.h). Does
/// not look at raw->file. Returns CDPR_OK or CDPR_E_PARSE / CDPR_E_OUT_OF_RANGE /
/// CDPR_E_NOT_FINITE / CDPR_E_CAPACITY with err filled.
cdpr_status_t cdpr_rig_resolve(const cdpr_raw_rig_t *raw, const char *path, const char *prefix,
                               cdpr_rig_t *rig, cdpr_rig_error_t *err);

#endif /* CDPR_HOST_RIG_RAW_H */
