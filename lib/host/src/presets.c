/* SPDX-License-Identifier: BSD-3-Clause */
/// @file presets.c
/// The parameter sets A and B of docs/robots.md, which gives every value's tag and source.
#include "cdpr/host/presets.h"

#include "cdpr/config.h"
#include "cdpr/host/rig.h"
#include "cdpr/host/yaml.h"
#include "rig_raw.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

const cyaml_strval_t cdpr_preset_names[CDPR_PRESET_NAME_COUNT] = {
    {"paper-50m", CDPR_PRESET_PAPER_50M},
    {"fast", CDPR_PRESET_FAST},
};

const char *cdpr_preset_name(cdpr_preset_t preset)
{
    return cdpr_yaml_enum_name(cdpr_preset_names, CDPR_PRESET_NAME_COUNT, preset, "unknown");
}

/* Six towers at (j-1) 60 deg; attachments in twisted pairs at +-5 deg about 30, 150, 270 deg
 * (docs/robots.md: radial attachments leave yaw without static stiffness). */
static void hexagon(cdpr_preset_config_t *c)
{
    static const double attach_deg[CDPR_ROBOT_CABLES] = {25.0, 35.0, 145.0, 155.0, 265.0, 275.0};
    for (int j = 0; j < CDPR_ROBOT_CABLES; ++j) {
        c->exit_azimuth_deg[j] = 60.0 * (double)j;
        c->attach_azimuth_deg[j] = attach_deg[j];
    }
}

cdpr_status_t cdpr_preset_get(cdpr_preset_t preset, cdpr_preset_config_t *cfg)
{
    if (cfg == NULL || (preset != CDPR_PRESET_PAPER_50M && preset != CDPR_PRESET_FAST)) {
        return CDPR_E_INVALID_ARG;
    }
    cdpr_preset_config_t c;
    memset(&c, 0, sizeof c);
    c.preset = preset;
    hexagon(&c);
    c.gravity_m_per_s2 = 9.80665;
    /* Axial law and damping form: the core's defaults (passive slack law; c given in N s,
     * its damping ratio at a frequency is in docs/robots.md). */
    c.cable.slack_law = CDPR_SLACK_PASSIVE;
    c.cable.damping_ratio = 0.0;
    c.cable.damping_ref_hz = 5.0;
    /* Drag: Cd 1.2 and Cm in 0.02-0.05 from the paper, air at sea level. */
    c.cable.cd = 1.2;
    c.cable.cm = 0.03;
    c.cable.rho_air_kg_per_m3 = 1.225;
    if (preset == CDPR_PRESET_PAPER_50M) {
        c.exit_radius_m = 25.0;
        c.exit_height_m = 30.0;
        c.attach_radius_m = 2.0;
        c.attach_z_m = -0.5;
        c.cabin_mass_kg = 40.0;
        c.cabin_inertia_kg_m2[0] = 45.0;
        c.cabin_inertia_kg_m2[1] = 45.0;
        c.cabin_inertia_kg_m2[2] = 90.0;
        c.cable.d0_m = 0.006;
        c.cable.rho_kg_per_m = 0.14;
        c.cable.ea_N = 2.0e6;
        c.cable.damping_Ns = 170.0;
        c.segments = 20;
        c.winch.u_max_m_per_s = 4.0;
        c.winch.a_max_m_per_s2 = 5.0;
        c.winch.kp_per_s = 5.0;
        c.winch.min_length_m = 0.5;
        c.nominal_pose[2] = 9.135; /* the circle's start (paper §4) */
    } else {
        /* Origin at the reflector vertex; the zenith cabin sits at z = 140 m. */
        c.exit_radius_m = 300.0;
        c.exit_height_m = 270.0;
        c.attach_radius_m = 6.5;
        c.attach_z_m = 0.0;
        c.cabin_mass_kg = 30000.0;
        c.cabin_inertia_kg_m2[0] = 3.57e5;
        c.cabin_inertia_kg_m2[1] = 3.57e5;
        c.cabin_inertia_kg_m2[2] = 6.34e5;
        c.cable.d0_m = 0.046;
        c.cable.rho_kg_per_m = 10.0;
        c.cable.ea_N = 1.5e8;
        /* 10 % of critical for one nominal 8 m segment: 0.1 * 2 * 8 * sqrt(EA rho). */
        c.cable.damping_Ns = 6.2e4;
        c.segments = 40;
        c.winch.u_max_m_per_s = 0.5;
        c.winch.a_max_m_per_s2 = 0.2;
        c.winch.kp_per_s = 1.0;
        c.winch.min_length_m = 10.0;
        c.nominal_pose[2] = 140.0;
    }
    *cfg = c;
    return CDPR_OK;
}

void cdpr_preset_geometry(const cdpr_preset_config_t *cfg, int j, cdpr_vec3_t *exit_m,
                          cdpr_vec3_t *attach_body_m)
{
    const double th = cfg->exit_azimuth_deg[j] * CDPR_PI / 180.0;
    const double ph = cfg->attach_azimuth_deg[j] * CDPR_PI / 180.0;
    *exit_m =
        cdpr_v3(cfg->exit_radius_m * cos(th), cfg->exit_radius_m * sin(th), cfg->exit_height_m);
    *attach_body_m =
        cdpr_v3(cfg->attach_radius_m * cos(ph), cfg->attach_radius_m * sin(ph), cfg->attach_z_m);
}

void cdpr_rig_from_preset(const cdpr_preset_config_t *cfg, cdpr_rig_t *rig)
{
    memset(rig, 0, sizeof *rig);
    snprintf(rig->name, sizeof rig->name, "%s", cdpr_preset_name(cfg->preset));
    rig->n_cables = CDPR_ROBOT_CABLES;
    for (int j = 0; j < CDPR_ROBOT_CABLES; ++j) {
        cdpr_rig_cable_t *c = &rig->cable[j];
        cdpr_vec3_t e;
        cdpr_vec3_t b;
        cdpr_preset_geometry(cfg, j, &e, &b);
        c->exit_m[0] = e.x;
        c->exit_m[1] = e.y;
        c->exit_m[2] = e.z;
        c->attach_m[0] = b.x;
        c->attach_m[1] = b.y;
        c->attach_m[2] = b.z;
        c->rope = cfg->cable;
        c->winch = cfg->winch;
        c->segments = cfg->segments;
    }
    rig->cabin_mass_kg = cfg->cabin_mass_kg;
    const double *I = cfg->cabin_inertia_kg_m2;
    const double *P = cfg->cabin_products_kg_m2; /* Ixy, Ixz, Iyz */
    const double m[3][3] = {{I[0], P[0], P[1]}, {P[0], I[1], P[2]}, {P[1], P[2], I[2]}};
    memcpy(rig->cabin_inertia_kg_m2, m, sizeof m);
    memcpy(rig->cabin_com_m, cfg->cabin_com_m, sizeof rig->cabin_com_m);
    rig->gravity_m_per_s2 = cfg->gravity_m_per_s2;
    memcpy(rig->wind_m_per_s, cfg->wind_m_per_s, sizeof rig->wind_m_per_s);
    memcpy(rig->nominal_pose, cfg->nominal_pose, sizeof rig->nominal_pose);
}

cdpr_status_t cdpr_preset_build(const cdpr_preset_config_t *cfg, const double *length_m,
                                cdpr_robot_params_t *p, cdpr_winch_params_t *w, cdpr_diag_t *diag)
{
    if (cfg == NULL || p == NULL) {
        return cdpr_diag_set(diag, CDPR_E_INVALID_ARG, "config", -1);
    }
    /* One builder for every robot form: the preset as a rig (its six cables alike). */
    cdpr_rig_t rig;
    cdpr_winch_params_t winch[CDPR_MAX_CABLES];
    cdpr_rig_from_preset(cfg, &rig);
    const cdpr_status_t st = cdpr_rig_build(&rig, length_m, p, (w != NULL) ? winch : NULL, diag);
    if (st == CDPR_OK && w != NULL) {
        *w = winch[0];
    }
    return st;
}
