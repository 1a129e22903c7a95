/* SPDX-License-Identifier: BSD-3-Clause */
/// @file quickstart.c
/// The smallest complete use of the core: build the plant of the paper's 50 m six-cable robot
/// in code, step it for one second of 10 ms control periods while two winches pay out, print
/// the cabin height and the winch-end tensions. Only lib/core's public API (cdpr/plant.h).
///
/// The region between the [readme] markers is README.md's "Using the core" block, byte for
/// byte (ctest readme_example checks it); ctest example_quickstart runs the program.
/// Exit status: 0 when every period succeeded and every tension is positive and finite.
/* [readme] */
#include <math.h>
#include <stdio.h>

#include "cdpr/plant.h"

static cdpr_plant_t plant; /* caller-owned, about 300 kB: make it static, not a local */

int main(void)
{
    cdpr_plant_params_t pp;
    cdpr_plant_params_default(&pp); /* every field has a default; set the robot */

    const double deg = CDPR_PI / 180.0;
    const double attach_deg[6] = {25.0, 35.0, 145.0, 155.0, 265.0, 275.0};
    pp.robot.n_cables = 6;
    for (int j = 0; j < 6; ++j) {
        cdpr_robot_cable_params_t *c = &pp.robot.cables[j];
        c->exit_point_m = cdpr_v3(25.0 * cos(60.0 * j * deg), 25.0 * sin(60.0 * j * deg), 30.0);
        c->attach_body_m = cdpr_v3(2.0 * cos(attach_deg[j] * deg), 2.0 * sin(attach_deg[j] * deg),
                                   -0.5); /* body axes, from the cabin origin */
        c->n_segments = 16;
        c->length_m = 31.5; /* a start for validation only: the plant's IK sets the length */
        c->cable.d0_m = 0.006;
        c->cable.rho_kg_per_m = 0.14;
        c->cable.ea_N = 2e6;
        c->cable.damping_Ns = 170.0;
        c->cable.cd = 1.2;
        c->cable.cm = 0.03;
        c->cable.rho_air_kg_per_m3 = 1.225;
    }
    pp.robot.cabin.mass_kg = 40.0;
    pp.robot.cabin.inertia_com_kg_m2 = (cdpr_mat3_t){{{45, 0, 0}, {0, 45, 0}, {0, 0, 90}}};
    pp.initial.p_m = cdpr_v3(0.0, 0.0, 9.135); /* level (q = 1), at rest */
    pp.period_s = 0.01;

    /* IK of the initial pose, nodes on the catenaries, settled to rest. Not real-time. */
    cdpr_diag_t d;
    cdpr_status_t st = cdpr_plant_init(&plant, &pp, &d);
    if (st != CDPR_OK) {
        printf("plant init: %s at %s[%d]\n", cdpr_status_str(st), d.field, d.index);
        return 1;
    }

    /* 100 periods of exactly 10 ms: cables 0 and 3 pay out at 0.05 m/s, the others hold. */
    const cdpr_real_t rate_m_per_s[6] = {0.05, 0.0, 0.0, 0.05, 0.0, 0.0};
    int ok = 1;
    for (int k = 0; k < 100; ++k) {
        int flags = 0;
        st = cdpr_plant_step(&plant, CDPR_WINCH_RATE, rate_m_per_s, &flags);
        if (st < 0) { /* the plant is as before the call; a controller could retry */
            printf("period %d: %s\n", k, cdpr_status_str(st));
            ok = 0;
            break;
        }
    }

    cdpr_plant_meas_t m;
    cdpr_robot_out_t out;
    cdpr_plant_measure(&plant, &m);
    cdpr_plant_outputs(&plant, &out);
    printf("t = %.2f s, cabin z = %.4f m\n", m.t_s, m.cabin.p_m.z);
    for (int j = 0; j < 6; ++j) {
        printf("cable %d: winch-end tension %.2f N\n", j, out.tension_winch_N[j]);
        ok = (isfinite(out.tension_winch_N[j]) && out.tension_winch_N[j] > 0.0) ? ok : 0;
    }
    return ok ? 0 : 1;
}
/* [/readme] */
