/* SPDX-License-Identifier: BSD-3-Clause */
/// @file rig.h
/// Robot descriptions ("rigs") of any geometry: per cable the exit point, the body attachment,
/// the rope, the winch limits and the segment count; the cabin's mass, full inertia matrix and
/// centre of mass; gravity, air density and wind. Read from robot files (YAML through
/// libcyaml; docs/robots.md "Robot files" lists every key) or from a compiled preset
/// (presets.h, whose polar layout is one special case: cdpr_rig_from_preset), and turned into the
/// core's cdpr_robot_params_t and cdpr_winch_params_t.
///
/// A scenario's `robot:` section names a preset (`preset:` + overrides, presets.h), a robot
/// file (`file:`, relative to the scenario file) or embeds a description (`cables:`,
/// `cabin:`, ...); scenario.h resolves all three to a cdpr_rig_t.
///
/// The number of cables is 1..CDPR_MAX_CABLES. The plant's start (the sag-aware IK of the
/// initial pose) and the tracker need at least CDPR_RIG_IK_CABLES (6), and a redundant robot
/// (more than six) its tension distribution (`tension_distribution:`, copied into the core's
/// cdpr_robot_params_t by cdpr_rig_build).
///
/// Host library; loading allocates (libcyaml) and frees everything before returning.
#ifndef CDPR_HOST_RIG_H
#define CDPR_HOST_RIG_H

#include <stddef.h>

#include "cdpr/cable.h"
#include "cdpr/config.h"
#include "cdpr/robot.h"
#include "cdpr/status.h"
#include "cdpr/winch.h"

/// Cable count of a robot whose sag-aware IK has no choice to make (cdpr_statics_ik); the
/// plant's start and the tracker need at least this many.
#define CDPR_RIG_IK_CABLES 6

/// One cable of a rig (inputs; all SI).
typedef struct {
    double exit_m[3];          ///< pulley exit point A_j, world [m]
    double attach_m[3];        ///< attachment b_j, body axes, from the body origin [m]
    cdpr_cable_params_t rope;  ///< rope (rho_air_kg_per_m3: the rig's air density)
    cdpr_winch_params_t winch; ///< winch limits
    int segments;              ///< initial segments, 1..CDPR_MAX_SEGMENTS
} cdpr_rig_cable_t;

/// A robot description (plain data, no pointers).
typedef struct {
    char name[512];                          ///< preset name, robot file path or "embedded"
    int n_cables;                            ///< 1..CDPR_MAX_CABLES
    cdpr_rig_cable_t cable[CDPR_MAX_CABLES]; ///< per cable
    double cabin_mass_kg;                    ///< cabin mass [kg]
    double cabin_inertia_kg_m2[3][3];        ///< inertia about the CoM, body axes [kg m^2]
    double cabin_com_m[3];                   ///< CoM in body axes, from the body origin [m]
    double gravity_m_per_s2;                 ///< g [m/s^2]
    double wind_m_per_s[3];                  ///< uniform wind J [m/s]
    double nominal_pose[6];       ///< a pose inside the workspace (x,y,z [m], α,β,γ [rad])
    int has_tension_distribution; ///< 1: the keys below were given (tension_distribution:)
    double tension_min_N;         ///< every cable's lowest tension at least this [N]
    double tension_max_N;         ///< every cable's highest tension at most this [N]
    double tension_ref_N;         ///< the tensions the distribution aims at (default mid-range) [N]
} cdpr_rig_t;

/// Error text of a failed load or check: "FILE:LINE: KEY: what" (as cdpr_scenario_error_t).
typedef struct {
    char msg[2048];
} cdpr_rig_error_t;

/// Build the core parameters, exactly as cdpr_preset_build does for a preset (byte for byte
/// for cdpr_rig_from_preset's rigs): dynamic cabin, cable j with its rope, segments and
/// unstretched length `length_m[j]` (NULL: the straight distance at the nominal pose, a
/// placeholder for statics-only models), validated with cdpr_robot_init's rules. `w` (may be
/// NULL; CDPR_MAX_CABLES entries) receives every cable's winch limits (entries past n_cables:
/// cable 0's), validated by cdpr_winch_init's rules. Errors: diag names the core field
/// (index = cable).
cdpr_status_t cdpr_rig_build(const cdpr_rig_t *rig, const double *length_m, cdpr_robot_params_t *p,
                             cdpr_winch_params_t *w, cdpr_diag_t *diag);

/// Load and check a robot file (docs/robots.md "Robot files"). Returns CDPR_OK, or with `err`
/// naming file, line and key: CDPR_E_IO (cannot open), CDPR_E_PARSE (malformed YAML, unknown
/// or missing key, wrong type, both damping forms, a count that is not whole), or the error
/// of a value (cdpr_rig_check).
cdpr_status_t cdpr_rig_load(const char *path, cdpr_rig_t *rig, cdpr_rig_error_t *err);

/// Check every value of a rig: finite, in range (docs/robots.md), an inertia matrix that is
/// symmetric, positive definite and physical (principal moments obey the triangle
/// inequalities), and accepted by the core (cdpr_rig_build). `path` (file the values came
/// from; "" or NULL if none) and `prefix` (key path of the rig inside that file, e.g.
/// "robot."; "" for a robot file) name the key in errors. Returns CDPR_OK, CDPR_E_CAPACITY
/// (cable count), CDPR_E_NOT_FINITE, CDPR_E_OUT_OF_RANGE, CDPR_E_NOT_POSITIVE (inertia not
/// positive definite) or the core's status.
cdpr_status_t cdpr_rig_check(const cdpr_rig_t *rig, const char *path, const char *prefix,
                             cdpr_rig_error_t *err);

/// Physical plausibility of a symmetric inertia matrix [kg m^2]: positive definite (its leading
/// minors and principal moments > 0: CDPR_E_NOT_POSITIVE) and principal moments e1 <= e2 <= e3
/// with e3 <= e1 + e2 (within 1e-9 of the trace; the triangle inequality every rigid body
/// obeys, equality for a flat plate: CDPR_E_OUT_OF_RANGE). On failure `what` says why
/// (moments named). O(1). Returns CDPR_OK otherwise.
cdpr_status_t cdpr_rig_inertia_plausible(const double I[3][3], char *what, size_t cap);

/// Principal moments of a symmetric 3x3 matrix, ascending (closed form). O(1).
void cdpr_rig_principal_moments(const double m[3][3], double eig[3]);

/// Factors on a rig's mass and stiffness (inputs): the model error between a controller's
/// model and the robot (a scenario's controller.model), or the plant variations of the
/// design check's robustness set. 1 = unchanged.
typedef struct {
    double ea;         ///< every rope's axial stiffness EA [-]
    double cabin_mass; ///< the cabin's mass and inertia (a heavier cabin of the same shape) [-]
    double rope_mass;  ///< every rope's mass per length [-]
} cdpr_rig_scale_t;

/// Lowest and highest factor a rig scale may hold (cdpr_rig_scale_check).
#define CDPR_RIG_SCALE_MIN 0.5
#define CDPR_RIG_SCALE_MAX 2.0

/// No change: every factor 1.
cdpr_rig_scale_t cdpr_rig_scale_unit(void);

/// 1 when every factor of `s` is exactly 1.
int cdpr_rig_scale_is_unit(const cdpr_rig_scale_t *s);

/// Multiply the rig's every rope EA by s->ea and mass per length by s->rope_mass, the cabin's
/// mass and inertia matrix by s->cabin_mass. A rope's damping keeps its form: a damping ratio
/// stays the ratio (its c follows EA), a strain-rate damping c stays c. Factors 1 leave the
/// values bit for bit. O(cables); cannot fail (the factors are checked where they are read).
void cdpr_rig_scale(cdpr_rig_t *rig, const cdpr_rig_scale_t *s);

#endif /* CDPR_HOST_RIG_H */
