/* SPDX-License-Identifier: BSD-3-Clause */
/// @file paper_plant.h
/// Plant parameters of the paper's 50 m model (docs/robots.md set A) written out for the core
/// tests, independently of lib/host's preset: exit points on a 25 m circle at 30 m,
/// attachments on a 2 m circle 0.5 m below the cabin origin, 40 kg cabin, 6 mm rope, `segments`
/// per cable, home pose (0, 0, 9.135 m) level, 10 ms period, 400 trials; in float the
/// integrator tolerances float can honour.
#ifndef CDPR_TEST_PAPER_PLANT_H
#define CDPR_TEST_PAPER_PLANT_H

#include <math.h>

#include "cdpr/plant.h"

static const double TEST_EXIT_AZ_DEG[6] = {0.0, 60.0, 120.0, 180.0, 240.0, 300.0};
static const double TEST_ATTACH_AZ_DEG[6] = {25.0, 35.0, 145.0, 155.0, 265.0, 275.0};
static const double TEST_HOME_Z_M = 9.135;

static inline void test_paper_plant_params(cdpr_plant_params_t *pp, int segments)
{
    cdpr_plant_params_default(pp);
    cdpr_robot_params_t *r = &pp->robot;
    r->n_cables = 6;
    r->cabin.mass_kg = CDPR_R(40.0);
    r->cabin.inertia_com_kg_m2.m[0][0] = CDPR_R(45.0);
    r->cabin.inertia_com_kg_m2.m[1][1] = CDPR_R(45.0);
    r->cabin.inertia_com_kg_m2.m[2][2] = CDPR_R(90.0);
    for (int j = 0; j < 6; ++j) {
        cdpr_robot_cable_params_t *c = &r->cables[j];
        const double th = TEST_EXIT_AZ_DEG[j] * CDPR_PI / 180.0;
        const double ph = TEST_ATTACH_AZ_DEG[j] * CDPR_PI / 180.0;
        c->exit_point_m =
            cdpr_v3((cdpr_real_t)(25.0 * cos(th)), (cdpr_real_t)(25.0 * sin(th)), CDPR_R(30.0));
        c->attach_body_m =
            cdpr_v3((cdpr_real_t)(2.0 * cos(ph)), (cdpr_real_t)(2.0 * sin(ph)), CDPR_R(-0.5));
        c->n_segments = segments;
        c->length_m = CDPR_R(31.5); /* replaced by the IK */
        c->cable.d0_m = CDPR_R(0.006);
        c->cable.rho_kg_per_m = CDPR_R(0.14);
        c->cable.ea_N = CDPR_R(2.0e6);
        c->cable.damping_Ns = CDPR_R(170.0);
        c->cable.cd = CDPR_R(1.2);
        c->cable.cm = CDPR_R(0.03);
        c->cable.rho_air_kg_per_m3 = CDPR_R(1.225);
    }
    const cdpr_real_t pose[6] = {CDPR_R(0.0), CDPR_R(0.0), (cdpr_real_t)TEST_HOME_Z_M,
                                 CDPR_R(0.0), CDPR_R(0.0), CDPR_R(0.0)};
    pp->initial = cdpr_cabin_motion_at_pose(pose);
#ifdef CDPR_REAL_IS_FLOAT
    /* float resolves the strain of EA = 2 MN ropes to ~1e-7 (0.24 N per segment): ask the
     * integrator for what float can honour (docs/firmware.md). */
    pp->rkf45.step.rtol = CDPR_R(1e-4);
    pp->atol.position_m = CDPR_R(1e-4);
    pp->atol.velocity_m_per_s = CDPR_R(1e-4);
    pp->atol.quaternion = CDPR_R(1e-4);
    pp->atol.rate_rad_per_s = CDPR_R(1e-4);
#endif
    pp->rkf45.step.h_max_s = CDPR_R(0.01);
    pp->period_s = CDPR_R(0.01);
    pp->max_trials = 400;
}

/* The implicit plant's real-time settings of the tests and docs (docs/model.md §7): loose node
 * tolerances (the stiff axial modes are damped, not resolved), 1 kHz, at most 3 trials;
 * `vtol` is the node-velocity tolerance [m/s] (1e-2 in the docs). Also what the fixed mode's
 * error norm is weighed with. */
static inline void test_paper_rt_params(cdpr_plant_params_t *pp, cdpr_plant_integrator_t m,
                                        double vtol)
{
    pp->integrator = m;
    pp->ros.step.rtol = CDPR_R(1e-3);
    pp->ros.step.h_max_s = CDPR_R(0.01);
    pp->ros.step.h_init_s = CDPR_R(1e-3);
    pp->atol.position_m = CDPR_R(1e-4);
    pp->atol.velocity_m_per_s = (cdpr_real_t)vtol;
    pp->atol.quaternion = CDPR_R(1e-6);
    pp->atol.rate_rad_per_s = CDPR_R(1e-4);
    pp->period_s = CDPR_R(0.001);
    pp->max_trials = 3;
}

/* Payout rates of period k at 1 kHz (the implicit plant tests): every cable pays out / hauls in
 * with its own phase, so the cabin translates and turns and the tensions swing (peak rates 0.4
 * m/s). */
static inline void test_paper_rates_at(int k, cdpr_real_t *u)
{
    const double t = 0.001 * k;
    for (int j = 0; j < 6; ++j) {
        u[j] = (cdpr_real_t)(0.4 * sin(2.0 * CDPR_PI * (0.7 + 0.1 * j) * t + 1.1 * j) *
                             (1.0 - exp(-4.0 * t)));
    }
}

static inline double test_cabin_angle(const cdpr_cabin_motion_t *a, const cdpr_cabin_motion_t *b)
{
    /* rotation angle [rad] of a^-1 b: 2 asin |vec(conj(a) b)| */
    const double w = (double)a->q.w, x = -(double)a->q.x, y = -(double)a->q.y, z = -(double)a->q.z;
    const double bw = (double)b->q.w, bx = (double)b->q.x, by = (double)b->q.y, bz = (double)b->q.z;
    const double vx = w * bx + x * bw + y * bz - z * by;
    const double vy = w * by - x * bz + y * bw + z * bx;
    const double vz = w * bz + x * by - y * bx + z * bw;
    return 2.0 * asin(fmin(1.0, sqrt(vx * vx + vy * vy + vz * vz)));
}

#endif /* CDPR_TEST_PAPER_PLANT_H */
