/* SPDX-License-Identifier: BSD-3-Clause */
/// @file presets.h
/// Robot configurations of the project's parameter sets (docs/robots.md): the paper's
/// reconstructed "50 m model" (set A) and a FAST-like full-scale robot (set B).
///
/// A configuration is a preset's values in its polar layout; the robot record of the host is
/// cdpr_rig_t (rig.h), which cdpr_rig_from_preset makes of it (a scenario with `robot:
/// {preset: ...}` starts from that rig and overrides it with the robot-file keys, scenario.h).
/// cdpr_preset_build turns it into the core's cdpr_robot_params_t and cdpr_winch_params_t. Each
/// value's source is in docs/robots.md with its tag: [P] published, [A] assumed, [D] derived.
///
/// Geometry (docs/model.md §1): exit point A_j = (a cos θ_j, a sin θ_j, H); attachment
/// b_j = (r_b cos φ_j, r_b sin φ_j, z_b) in body axes, relative to the body origin (the
/// cabin's centre of mass unless com_m is set).
///
/// Host library (double core only); no allocation, no I/O.
#ifndef CDPR_HOST_PRESETS_H
#define CDPR_HOST_PRESETS_H

#include "cdpr/cabin.h"
#include "cdpr/cable.h"
#include "cdpr/robot.h"
#include "cdpr/status.h"
#include "cdpr/winch.h"
#include "cdpr/host/rig.h"

/// The six-cable robots of docs/robots.md.
#define CDPR_ROBOT_CABLES 6

/// Preset parameter sets.
typedef enum {
    CDPR_PRESET_PAPER_50M = 0, ///< set A: the paper's 50 m scaled model (reconstructed)
    CDPR_PRESET_FAST = 1       ///< set B: FAST-like full scale
} cdpr_preset_t;

/// Every value of a robot configuration (inputs; all SI).
typedef struct {
    cdpr_preset_t preset;                         ///< where the defaults came from
    double exit_radius_m;                         ///< tower circle radius a [m]
    double exit_height_m;                         ///< pulley exit height H [m]
    double exit_azimuth_deg[CDPR_ROBOT_CABLES];   ///< θ_j [deg]
    double attach_radius_m;                       ///< attachment radius r_b [m]
    double attach_z_m;                            ///< attachment height z_b, body axes [m]
    double attach_azimuth_deg[CDPR_ROBOT_CABLES]; ///< φ_j [deg]
    double cabin_mass_kg;                         ///< cabin mass [kg]
    double cabin_inertia_kg_m2[3];                ///< Ixx, Iyy, Izz about the CoM [kg m^2]
    double cabin_products_kg_m2[3];               ///< Ixy, Ixz, Iyz about the CoM [kg m^2]
    double cabin_com_m[3];                        ///< CoM in body axes [m]
    cdpr_cable_params_t cable;                    ///< the same cable for all six
    double gravity_m_per_s2;                      ///< g [m/s^2]
    double wind_m_per_s[3];                       ///< uniform wind J [m/s]
    int segments;                                 ///< initial segments per cable
    cdpr_winch_params_t winch;                    ///< limits of every winch
    double nominal_pose[6];                       ///< a feasible pose (x,y,z [m], α,β,γ [rad])
} cdpr_preset_config_t;

/// Name of a preset as written in scenario files ("paper-50m", "fast"); never NULL.
const char *cdpr_preset_name(cdpr_preset_t preset);

/// Fill `cfg` with a preset's values (docs/robots.md). Returns CDPR_E_INVALID_ARG for an
/// unknown preset (cfg untouched).
cdpr_status_t cdpr_preset_get(cdpr_preset_t preset, cdpr_preset_config_t *cfg);

/// Exit point A_j and body attachment b_j of cable j (0-based) [m].
void cdpr_preset_geometry(const cdpr_preset_config_t *cfg, int j, cdpr_vec3_t *exit_m,
                          cdpr_vec3_t *attach_body_m);

/// Build the core parameters: dynamic cabin, six cables of `cfg->segments` segments and
/// unstretched lengths `length_m[j]` (NULL: the straight distance from the attachment to the
/// exit point at the nominal pose — a placeholder for models used only for statics). The
/// result is validated with cdpr_robot_init's rules on a scratch robot, so a bad value is
/// reported here with `diag` naming the core field (index = cable). Winch limits go to `w`
/// (may be NULL) and are validated too.
cdpr_status_t cdpr_preset_build(const cdpr_preset_config_t *cfg, const double *length_m,
                                cdpr_robot_params_t *p, cdpr_winch_params_t *w, cdpr_diag_t *diag);

/// The rig of a preset configuration (presets.h): exit points and attachments from its polar
/// layout (cdpr_preset_geometry), the same rope and winch for every cable. Name: the preset's.
void cdpr_rig_from_preset(const cdpr_preset_config_t *cfg, cdpr_rig_t *rig);

#endif /* CDPR_HOST_PRESETS_H */
