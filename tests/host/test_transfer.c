/* SPDX-License-Identifier: BSD-3-Clause */
/// @file test_transfer.c
/// Issue 14, increment 1: the planned transfer (trajectory.h, cdpr_transfer_t) against its
/// closed form -- the septic blend's values and derivatives at 0 and 1 and against finite
/// differences, the reference equal to the measured start at t0 and to the trajectory from
/// t0 + T on, its velocity, acceleration, body rate and angular acceleration the derivatives
/// of its pose -- the cables' wind load (cdpr_tracker_wind_wrench) against a hand
/// computation, the feed-forward's slack demands on a case whose windward cable must push, and
/// the recorder's plant slack periods on rows with known slack ends.
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <sys/stat.h>
#include <string.h>

#include "cdpr/host/record.h"
#include "cdpr/host/scenario.h"
#include "cdpr/control/tracker.h"
#include "cdpr/control/trajectory.h"
#include "paper_circle.h"
#include "paper_model.h"
#include "unity.h"

void setUp(void) {}
void tearDown(void) {}

static cdpr_robot_t model;
static cdpr_tracker_t tracker;

static void model_params(cdpr_robot_params_t *p)
{
    test_paper_model_params(p, &model);
}

static void test_blend_closed_form(void)
{
    double s, d1, d2;
    cdpr_transfer_blend(0.0, &s, &d1, &d2);
    TEST_ASSERT_EQUAL_DOUBLE(0.0, s);
    TEST_ASSERT_EQUAL_DOUBLE(0.0, d1);
    TEST_ASSERT_EQUAL_DOUBLE(0.0, d2);
    cdpr_transfer_blend(1.0, &s, &d1, &d2);
    TEST_ASSERT_DOUBLE_WITHIN(1e-12, 1.0, s);
    TEST_ASSERT_DOUBLE_WITHIN(1e-11, 0.0, d1);
    TEST_ASSERT_DOUBLE_WITHIN(1e-10, 0.0, d2);
    cdpr_transfer_blend(0.5, &s, &d1, &d2);
    TEST_ASSERT_DOUBLE_WITHIN(1e-15, 0.5, s);
    TEST_ASSERT_DOUBLE_WITHIN(1e-12, 2.1875, d1); /* 35/16 */
    TEST_ASSERT_DOUBLE_WITHIN(1e-12, 0.0, d2);
    const double h = 1e-5;
    for (double x = 0.05; x < 1.0; x += 0.1) {
        double sp, dp, ddp, sm, dm, ddm;
        cdpr_transfer_blend(x, &s, &d1, &d2);
        cdpr_transfer_blend(x + h, &sp, &dp, &ddp);
        cdpr_transfer_blend(x - h, &sm, &dm, &ddm);
        TEST_ASSERT_DOUBLE_WITHIN(1e-8, (sp - sm) / (2.0 * h), d1);
        TEST_ASSERT_DOUBLE_WITHIN(1e-7, (dp - dm) / (2.0 * h), d2);
        cdpr_transfer_blend(1.0 - x, &sp, &dp, &ddp);
        TEST_ASSERT_DOUBLE_WITHIN(1e-14, 1.0, s + sp); /* symmetric about (1/2, 1/2) */
    }
    cdpr_transfer_blend(-1.0, &s, &d1, &d2); /* clamped */
    TEST_ASSERT_EQUAL_DOUBLE(0.0, s);
    cdpr_transfer_blend(2.0, &s, &d1, &d2);
    TEST_ASSERT_DOUBLE_WITHIN(1e-12, 1.0, s);
}

/* The paper line (attitude moving) and a measured start off it by a position and a
 * rotation. */
static void line_and_start(cdpr_traj_t *tr, cdpr_cabin_motion_t *m0)
{
    const double from[6] = {2.0, 1.0, 16.0, 0.0889, -0.1756, -0.0336};
    const double to[6] = {2.5, 1.5, 16.2, 0.135, -0.263, -0.0206};
    *tr = test_line(from, to, 10.0);
    cdpr_traj_sample_t d;
    cdpr_traj_eval(tr, 0.5, &d);
    memset(m0, 0, sizeof *m0);
    m0->p_m = cdpr_v3_add(d.motion.p_m, cdpr_v3(0.3, -0.2, -0.5));
    const cdpr_quat_t r = {cos(0.06), 0.5 * sin(0.06), -0.3 * sin(0.06), 0.8 * sin(0.06)};
    m0->q = cdpr_quat_normalize(cdpr_quat_mul(r, d.motion.q));
    m0->v_m_per_s = cdpr_v3(1.0, 2.0, 3.0); /* used from rest only */
}

static double rot_between(cdpr_quat_t a, cdpr_quat_t b)
{
    const cdpr_quat_t bi = {b.w, -b.x, -b.y, -b.z};
    return cdpr_v3_norm(cdpr_quat_to_rotvec(cdpr_quat_mul(a, bi)));
}

/* From t_end on the transfer is exactly the trajectory; just before it, continuous with it
 * (position, velocity, acceleration, rates). */
static void joins_trajectory(const cdpr_transfer_t *x, const cdpr_traj_t *tr, double t_end)
{
    cdpr_traj_sample_t r;
    cdpr_traj_sample_t d;
    for (double t = t_end; t < t_end + 2.0; t += 0.37) {
        cdpr_transfer_eval(x, tr, t, &r);
        cdpr_traj_eval(tr, t, &d);
        TEST_ASSERT_EQUAL_MEMORY(&d, &r, sizeof d);
    }
    cdpr_transfer_eval(x, tr, t_end - 1e-6, &r);
    cdpr_traj_eval(tr, t_end - 1e-6, &d);
    TEST_ASSERT_DOUBLE_WITHIN(1e-12, 0.0, cdpr_v3_norm(cdpr_v3_sub(r.motion.p_m, d.motion.p_m)));
    TEST_ASSERT_DOUBLE_WITHIN(1e-12, 0.0, rot_between(r.motion.q, d.motion.q));
    TEST_ASSERT_DOUBLE_WITHIN(1e-10, 0.0,
                              cdpr_v3_norm(cdpr_v3_sub(r.motion.v_m_per_s, d.motion.v_m_per_s)));
    TEST_ASSERT_DOUBLE_WITHIN(1e-8, 0.0, cdpr_v3_norm(cdpr_v3_sub(r.a_m_per_s2, d.a_m_per_s2)));
    TEST_ASSERT_DOUBLE_WITHIN(
        1e-10, 0.0, cdpr_v3_norm(cdpr_v3_sub(r.motion.w_rad_per_s, d.motion.w_rad_per_s)));
    TEST_ASSERT_DOUBLE_WITHIN(1e-8, 0.0,
                              cdpr_v3_norm(cdpr_v3_sub(r.dw_rad_per_s2, d.dw_rad_per_s2)));
}

static void test_transfer_ends(void)
{
    cdpr_traj_t tr;
    cdpr_cabin_motion_t m0;
    line_and_start(&tr, &m0);
    const double t0 = 0.5;
    const double T = 3.0;
    cdpr_transfer_t x;
    cdpr_transfer_init(&x, &tr, t0, T, &m0, 0);
    cdpr_traj_sample_t r;
    cdpr_traj_sample_t d;
    /* At t0: the measured pose, with the trajectory's velocity and acceleration. */
    cdpr_transfer_eval(&x, &tr, t0, &r);
    cdpr_traj_eval(&tr, t0, &d);
    TEST_ASSERT_DOUBLE_WITHIN(1e-14, 0.0, cdpr_v3_norm(cdpr_v3_sub(r.motion.p_m, m0.p_m)));
    TEST_ASSERT_DOUBLE_WITHIN(1e-12, 0.0, rot_between(r.motion.q, m0.q));
    TEST_ASSERT_DOUBLE_WITHIN(1e-14, 0.0,
                              cdpr_v3_norm(cdpr_v3_sub(r.motion.v_m_per_s, d.motion.v_m_per_s)));
    TEST_ASSERT_DOUBLE_WITHIN(1e-14, 0.0, cdpr_v3_norm(cdpr_v3_sub(r.a_m_per_s2, d.a_m_per_s2)));
    /* ṡ = 0: the body rate is the trajectory's (R_r = E R_traj, ω_r,world = E ω_traj,world). */
    TEST_ASSERT_DOUBLE_WITHIN(
        1e-12, 0.0, cdpr_v3_norm(cdpr_v3_sub(r.motion.w_rad_per_s, d.motion.w_rad_per_s)));
    joins_trajectory(&x, &tr, t0 + T);
    /* T = 0: no transfer at all. */
    cdpr_transfer_init(&x, &tr, t0, 0.0, &m0, 0);
    cdpr_transfer_eval(&x, &tr, t0, &r);
    cdpr_traj_eval(&tr, t0, &d);
    TEST_ASSERT_EQUAL_MEMORY(&d, &r, sizeof d);
}

/* World angular velocity from central differences of q: rotvec(q(t+h) q(t-h)^-1) / 2h. */
static cdpr_vec3_t w_world_fd(const cdpr_transfer_t *x, const cdpr_traj_t *tr, double t, double h)
{
    cdpr_traj_sample_t a;
    cdpr_traj_sample_t b;
    cdpr_transfer_eval(x, tr, t + h, &a);
    cdpr_transfer_eval(x, tr, t - h, &b);
    const cdpr_quat_t bi = {b.motion.q.w, -b.motion.q.x, -b.motion.q.y, -b.motion.q.z};
    return cdpr_v3_scale(cdpr_quat_to_rotvec(cdpr_quat_mul(a.motion.q, bi)), 0.5 / h);
}

static void check_derivatives(int from_rest);

/* Velocities and accelerations against central differences of the reference itself, both
 * kinds of transfer (from rest: the clock w(t) and the velocity term enter every one). */
static void test_transfer_derivatives(void)
{
    for (int from_rest = 0; from_rest <= 1; ++from_rest) {
        check_derivatives(from_rest);
    }
}

static void check_derivatives(int from_rest)
{
    cdpr_traj_t tr;
    cdpr_cabin_motion_t m0;
    line_and_start(&tr, &m0);
    cdpr_transfer_t x;
    cdpr_transfer_init(&x, &tr, 0.5, 3.0, &m0, from_rest);
    const double h = 1e-4;
    for (double t = 0.6; t < 3.5; t += 0.29) {
        cdpr_traj_sample_t r, rp, rm;
        cdpr_transfer_eval(&x, &tr, t, &r);
        cdpr_transfer_eval(&x, &tr, t + h, &rp);
        cdpr_transfer_eval(&x, &tr, t - h, &rm);
        const cdpr_vec3_t v_fd = cdpr_v3_scale(cdpr_v3_sub(rp.motion.p_m, rm.motion.p_m), 0.5 / h);
        const cdpr_vec3_t a_fd =
            cdpr_v3_scale(cdpr_v3_sub(rp.motion.v_m_per_s, rm.motion.v_m_per_s), 0.5 / h);
        TEST_ASSERT_DOUBLE_WITHIN(1e-7, 0.0, cdpr_v3_norm(cdpr_v3_sub(v_fd, r.motion.v_m_per_s)));
        TEST_ASSERT_DOUBLE_WITHIN(1e-7, 0.0, cdpr_v3_norm(cdpr_v3_sub(a_fd, r.a_m_per_s2)));
        cdpr_mat3_t R;
        cdpr_quat_to_mat3(r.motion.q, &R);
        const cdpr_vec3_t w_w = cdpr_m3_mul_v3(&R, r.motion.w_rad_per_s);
        TEST_ASSERT_DOUBLE_WITHIN(1e-8, 0.0,
                                  cdpr_v3_norm(cdpr_v3_sub(w_world_fd(&x, &tr, t, h), w_w)));
        const cdpr_vec3_t dw_fd =
            cdpr_v3_scale(cdpr_v3_sub(rp.motion.w_rad_per_s, rm.motion.w_rad_per_s), 0.5 / h);
        TEST_ASSERT_DOUBLE_WITHIN(1e-7, 0.0, cdpr_v3_norm(cdpr_v3_sub(dw_fd, r.dw_rad_per_s2)));
        /* pose[] agrees with motion. */
        TEST_ASSERT_DOUBLE_WITHIN(1e-15, r.motion.p_m.x, r.pose[0]);
        TEST_ASSERT_DOUBLE_WITHIN(
            1e-12, 0.0,
            rot_between(cdpr_quat_from_euler(r.pose[3], r.pose[4], r.pose[5]), r.motion.q));
    }
}

/* From rest: at t0 the measured position and velocity, the trajectory's clock at rest (the
 * angular velocity is the attitude blend's alone, zero at t0); from t0 + T exactly the
 * trajectory, and continuous with it just before; the clock runs at most 1.88 times as
 * fast: d(τ s)/dτ = 175 τ^4 - 504 τ^5 + 490 τ^6 - 160 τ^7 is largest at the root τ = 5/8 of
 * 8 τ^2 - 13 τ + 5 (its derivative is 140 τ^3 (τ - 1)(8 τ^2 - 13 τ + 5)), sampled here. */
static void test_transfer_from_rest_ends(void)
{
    cdpr_traj_t tr;
    cdpr_cabin_motion_t m0;
    line_and_start(&tr, &m0);
    const double t0 = 0.5;
    const double T = 3.0;
    cdpr_transfer_t x;
    cdpr_transfer_init(&x, &tr, t0, T, &m0, 1);
    cdpr_traj_sample_t r;
    cdpr_transfer_eval(&x, &tr, t0, &r);
    TEST_ASSERT_DOUBLE_WITHIN(1e-14, 0.0, cdpr_v3_norm(cdpr_v3_sub(r.motion.p_m, m0.p_m)));
    TEST_ASSERT_DOUBLE_WITHIN(1e-12, 0.0, rot_between(r.motion.q, m0.q));
    TEST_ASSERT_DOUBLE_WITHIN(1e-14, 0.0,
                              cdpr_v3_norm(cdpr_v3_sub(r.motion.v_m_per_s, m0.v_m_per_s)));
    TEST_ASSERT_DOUBLE_WITHIN(1e-14, 0.0, cdpr_v3_norm(r.motion.w_rad_per_s));
    const double v0[3] = {m0.v_m_per_s.x, m0.v_m_per_s.y, m0.v_m_per_s.z};
    for (int i = 0; i < 6; ++i) { /* the Euler rates: the trajectory's clock stands still */
        TEST_ASSERT_DOUBLE_WITHIN(1e-14, (i < 3) ? v0[i] : 0.0, r.rate[i]);
    }
    joins_trajectory(&x, &tr, t0 + T);
    /* The clock's speed w' = d(τ s)/dτ: 0 at τ = 0, 1 at τ = 1, largest at τ = 5/8. */
    double wmax = 0.0;
    for (int k = 0; k <= 1000; ++k) {
        double s;
        double d1;
        double d2;
        const double tau = k / 1000.0;
        cdpr_transfer_blend(tau, &s, &d1, &d2);
        wmax = fmax(wmax, s + tau * d1);
    }
    const double u = 0.625;
    const double u4 = u * u * u * u;
    const double wpeak = u4 * (175.0 + u * (-504.0 + u * (490.0 - 160.0 * u)));
    TEST_ASSERT_DOUBLE_WITHIN(1e-12, wpeak, wmax);
    TEST_ASSERT_DOUBLE_WITHIN(1e-4, 1.8835, wpeak);
}

/* The wind load written out per component (docs/model.md §2 drag at rest, half at the cabin). */
static void test_wind_wrench_hand(void)
{
    cdpr_robot_params_t p;
    model_params(&p);
    const double pose[6] = {0.5, -1.0, 9.0, 0.05, -0.02, 0.3};
    cdpr_cabin_motion_t m;
    memset(&m, 0, sizeof m);
    m.p_m = cdpr_v3(pose[0], pose[1], pose[2]);
    m.q = cdpr_quat_from_euler(pose[3], pose[4], pose[5]);
    const double J[3] = {8.0, -3.0, 0.5};
    cdpr_vec3_t f;
    cdpr_vec3_t tau;
    cdpr_tracker_wind_wrench(&model, &m, cdpr_v3(J[0], J[1], J[2]), &f, &tau);
    cdpr_mat3_t R;
    cdpr_quat_to_mat3(m.q, &R);
    double F[3] = {0.0, 0.0, 0.0};
    double M[3] = {0.0, 0.0, 0.0};
    for (int j = 0; j < 6; ++j) {
        const cdpr_robot_cable_params_t *c = &model.p.cables[j];
        const double b[3] = {c->attach_body_m.x, c->attach_body_m.y, c->attach_body_m.z};
        double rb[3];
        for (int i = 0; i < 3; ++i) {
            rb[i] = R.m[i][0] * b[0] + R.m[i][1] * b[1] + R.m[i][2] * b[2];
        }
        const double A[3] = {c->exit_point_m.x, c->exit_point_m.y, c->exit_point_m.z};
        const double P[3] = {pose[0] + rb[0], pose[1] + rb[1], pose[2] + rb[2]};
        const double d[3] = {A[0] - P[0], A[1] - P[1], A[2] - P[2]};
        const double l = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        const double t[3] = {d[0] / l, d[1] / l, d[2] / l};
        const double jt = J[0] * t[0] + J[1] * t[1] + J[2] * t[2];
        const double jn[3] = {J[0] - jt * t[0], J[1] - jt * t[1], J[2] - jt * t[2]};
        const double njn = sqrt(jn[0] * jn[0] + jn[1] * jn[1] + jn[2] * jn[2]);
        /* 1/2 rho_a d0 Cd = 0.5 * 1.225 * 0.006 * 1.2 for this rope; Cm = 0.03. */
        TEST_ASSERT_DOUBLE_WITHIN(1e-15, 0.5 * 1.225 * 0.006 * 1.2,
                                  0.5 * c->cable.rho_air_kg_per_m3 * c->cable.d0_m * c->cable.cd);
        const double k = 0.5 * 1.225 * 0.006 * 1.2 * l;
        double D[3];
        for (int i = 0; i < 3; ++i) {
            D[i] = 0.5 * k * (njn * jn[i] + 0.03 * fabs(jt) * jt * t[i]); /* cabin's half */
            F[i] += D[i];
        }
        M[0] += rb[1] * D[2] - rb[2] * D[1]; /* CoM at the body origin */
        M[1] += rb[2] * D[0] - rb[0] * D[2];
        M[2] += rb[0] * D[1] - rb[1] * D[0];
    }
    TEST_ASSERT_DOUBLE_WITHIN(1e-12, F[0], f.x);
    TEST_ASSERT_DOUBLE_WITHIN(1e-12, F[1], f.y);
    TEST_ASSERT_DOUBLE_WITHIN(1e-12, F[2], f.z);
    TEST_ASSERT_DOUBLE_WITHIN(1e-12, M[0], tau.x);
    TEST_ASSERT_DOUBLE_WITHIN(1e-12, M[1], tau.y);
    TEST_ASSERT_DOUBLE_WITHIN(1e-12, M[2], tau.z);
    TEST_ASSERT_TRUE(f.x > 1.0 && f.y < -0.1); /* mostly along the wind */
    /* Quadratic in the wind, zero without it. */
    cdpr_vec3_t f2;
    cdpr_tracker_wind_wrench(&model, &m, cdpr_v3(2.0 * J[0], 2.0 * J[1], 2.0 * J[2]), &f2, &tau);
    TEST_ASSERT_DOUBLE_WITHIN(1e-12, 4.0 * f.x, f2.x);
    cdpr_tracker_wind_wrench(&model, &m, cdpr_v3(0.0, 0.0, 0.0), &f2, &tau);
    TEST_ASSERT_EQUAL_DOUBLE(0.0, cdpr_v3_norm(f2) + cdpr_v3_norm(tau));
}

/* A hold at the circle's start under a 60 m/s wind along +x in the feed-forward: the load
 * (about 5x the weight sideways) needs cable 1 (exit point at +x, azimuth 0) to push; cable 4
 * (at 180 deg, leeward) pulls harder. */
static void test_slack_demand_counted(void)
{
    cdpr_robot_params_t p;
    model_params(&p);
    cdpr_traj_t tr;
    memset(&tr, 0, sizeof tr);
    tr.type = CDPR_TRAJ_HOLD;
    tr.hold_pose[2] = 9.135;
    cdpr_tracker_gains_t g = {0.0, 0.0,  5.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, {60.0, 0.0, 0.0},
                              0.0, 0.0,  0.0, 0.0, 0.0, 0.0, 0,   0.0, 0.0, 0.0,
                              0.0, NULL, 0.0};
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_tracker_init(&tracker, &p, &tr, &g, 0.01, 0.0, NULL));
    TEST_ASSERT_EQUAL_INT(-1, tracker.first_slack_cable);
    tracker.g.wind_ff = 1.0; /* the wind load from the first step on */
    for (int k = 0; k < 5; ++k) {
        cdpr_tracker_meas_t meas;
        memset(&meas, 0, sizeof meas);
        meas.t_s = 0.01 * k;
        cdpr_traj_sample_t d;
        cdpr_traj_eval(&tr, meas.t_s, &d);
        meas.cabin = d.motion;
        memcpy(meas.length_m, tracker.l_ff_m, sizeof meas.length_m);
        cdpr_tracker_cmd_t cmd;
        TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_tracker_step(&tracker, &meas, &cmd));
        TEST_ASSERT_NOT_EQUAL_INT(CDPR_OK, cmd.ik_status);
        TEST_ASSERT_TRUE((cmd.slack_demand & 1U) != 0U);
        TEST_ASSERT_TRUE((cmd.slack_demand & 8U) == 0U);
        TEST_ASSERT_TRUE(cmd.demand_tension_N[0] <= 0.0);
        TEST_ASSERT_TRUE(cmd.demand_tension_N[3] > 0.0);
        /* The straight tensions balance weight and wind (independent residual). */
        cdpr_vec3_t fw;
        cdpr_vec3_t tw;
        cdpr_tracker_wind_wrench(&model, &d.motion, g.wind_m_per_s, &fw, &tw);
        cdpr_vec3_t sum = cdpr_v3(0.0, 0.0, -model.p.cabin.mass_kg * model.p.g_m_per_s2);
        sum = cdpr_v3_add(sum, fw);
        for (int j = 0; j < 6; ++j) {
            cdpr_vec3_t u;
            cdpr_vec3_t gj;
            cdpr_tracker_jacobian(&model, j, &d.motion, &u, &gj);
            sum = cdpr_v3_add(sum, cdpr_v3_scale(u, cmd.demand_tension_N[j]));
        }
        TEST_ASSERT_DOUBLE_WITHIN(1e-9, 0.0, cdpr_v3_norm(sum));
    }
    TEST_ASSERT_EQUAL_UINT32(5u, (unsigned)tracker.slack_demand_periods[0]);
    TEST_ASSERT_EQUAL_UINT32(0u, (unsigned)tracker.slack_demand_periods[3]);
    TEST_ASSERT_EQUAL_INT(0, tracker.first_slack_cable);
    TEST_ASSERT_DOUBLE_WITHIN(1e-12, 0.01, tracker.first_slack_t_s); /* the step at t = 0 */
    TEST_ASSERT_TRUE(tracker.first_slack_tension_N <= 0.0);
    cdpr_summary_t sum;
    memset(&sum, 0, sizeof sum);
    cdpr_record_tracker_counts(&tracker, &sum);
    TEST_ASSERT_EQUAL_UINT32(5u, (unsigned)sum.slack_demand_periods[0]);
    TEST_ASSERT_EQUAL_INT(1, sum.first_slack_demand_cable);
}

/* The recorder counts a period as slack for cable j when either end has no tension, once per
 * period (a resent period adds nothing). */
static void test_plant_slack_periods(void)
{
    cdpr_scenario_t sc;
    cdpr_scenario_error_t err;
    TEST_ASSERT_EQUAL_INT(
        CDPR_OK, cdpr_scenario_load(CDPR_SOURCE_DIR "/scenarios/paper-line.yaml", &sc, &err));
    static cdpr_record_t rec;
    cdpr_summary_t sum;
    memset(&sum, 0, sizeof sum);
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_record_open(&rec, &sc, NULL, NULL, 6, &sum, &err));
    cdpr_traj_sample_t d;
    cdpr_traj_eval(&sc.traj, 0.0, &d);
    cdpr_tracker_meas_t meas;
    memset(&meas, 0, sizeof meas);
    meas.cabin = d.motion;
    const double lff[6] = {30.0, 30.0, 30.0, 30.0, 30.0, 30.0};
    const double u[6] = {0.0};
    const int seg[6] = {20, 20, 20, 20, 20, 20};
    const long ks[6] = {0, 1, 2, 3, 3, 4}; /* period 3 seen twice */
    for (int i = 0; i < 6; ++i) {
        double tc[6] = {50.0, 50.0, 50.0, 50.0, 50.0, 50.0};
        double tw[6] = {60.0, 60.0, 60.0, 60.0, 60.0, 60.0};
        if (ks[i] == 1 || ks[i] == 2) {
            tw[1] = 0.0; /* cable 2 slack at the winch */
        }
        if (ks[i] == 3) {
            tc[4] = 0.0; /* cable 5 slack at the cabin, and at both ends in period 4 below */
        }
        if (ks[i] == 4) {
            tc[4] = 0.0;
            tw[4] = 0.0;
        }
        const cdpr_record_row_t row = {0.01 * (double)ks[i], &d, &meas, tc, tw, lff, u, seg};
        TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_record_period(&rec, ks[i], i == 5, &row));
    }
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_record_close(&rec));
    const unsigned long want[6] = {0, 2, 0, 0, 2, 0};
    for (int j = 0; j < 6; ++j) {
        TEST_ASSERT_EQUAL_UINT32((unsigned)want[j], (unsigned)sum.slack_periods[j]);
    }
    TEST_ASSERT_EQUAL_INT(6, sum.n_cables);
    TEST_ASSERT_EQUAL_INT(0, sum.first_slack_demand_cable);
}

/* Per-lap statistics of the recorder on a cyclic trajectory (P = 1 s) with fabricated rows
 * at 10 Hz: the error is 0.1 m in lap 0, then 0.3 m and 0.4 m alternately in lap 1, 0.2 m in
 * lap 2 (unfinished: not stored). RMS of lap 1 = sqrt((0.09 + 0.16) / 2) = 0.35355 m; largest
 * 0.4 m. laps.csv holds the same. A time that goes back (a restarted plant) starts again. */
static void test_lap_statistics(void)
{
    cdpr_scenario_t sc;
    cdpr_scenario_error_t err;
    TEST_ASSERT_EQUAL_INT(
        CDPR_OK, cdpr_scenario_load(CDPR_SOURCE_DIR "/scenarios/paper-line.yaml", &sc, &err));
    memset(&sc.traj, 0, sizeof sc.traj);
    sc.traj.type = CDPR_TRAJ_CYCLIC;
    sc.traj.duration_s = 0.5;
    sc.traj.pause_s = 0.0;
    static cdpr_record_t rec;
    static cdpr_summary_t sum;
    memset(&sum, 0, sizeof sum);
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_record_open(&rec, &sc, NULL, NULL, 6, &sum, &err));
    cdpr_traj_sample_t d;
    memset(&d, 0, sizeof d);
    d.motion.q.w = 1.0;
    cdpr_tracker_meas_t meas;
    memset(&meas, 0, sizeof meas);
    meas.cabin.q.w = 1.0;
    const double tc[6] = {50, 50, 50, 50, 50, 50}, lff[6] = {30, 30, 30, 30, 30, 30};
    const double u[6] = {0.0};
    const int seg[6] = {20, 20, 20, 20, 20, 20};
    for (long k = 0; k <= 25; ++k) {
        const double t = 0.1 * (double)k;
        double e = 0.1;
        if (k >= 10 && k < 20) {
            e = (k % 2 == 0) ? 0.3 : 0.4;
        } else if (k >= 20) {
            e = 0.2;
        }
        meas.cabin.p_m = cdpr_v3(e, 0.0, 0.0);
        const cdpr_record_row_t row = {t, &d, &meas, tc, tc, lff, u, seg};
        TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_record_period(&rec, k, k == 25, &row));
    }
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_record_close(&rec));
    TEST_ASSERT_EQUAL_INT(2, sum.n_laps);
    TEST_ASSERT_DOUBLE_WITHIN(1e-12, 0.1, sum.lap_rms_m[0]);
    TEST_ASSERT_DOUBLE_WITHIN(1e-12, sqrt((0.09 + 0.16) / 2.0), sum.lap_rms_m[1]);
    TEST_ASSERT_DOUBLE_WITHIN(1e-12, 0.4, sum.lap_max_m[1]);
    TEST_ASSERT_DOUBLE_WITHIN(1e-12, 0.0, sum.lap_rms_rad[1]);
    (void)mkdir(CDPR_TEST_TMP, 0775);
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_summary_write_laps(CDPR_TEST_TMP "/laps.csv", &sum));
    FILE *f = fopen(CDPR_TEST_TMP "/laps.csv", "r");
    TEST_ASSERT_NOT_NULL(f);
    char line[256];
    TEST_ASSERT_NOT_NULL(fgets(line, sizeof line, f));
    TEST_ASSERT_EQUAL_STRING("lap,rms_m,max_m,rms_rad\n", line);
    TEST_ASSERT_NOT_NULL(fgets(line, sizeof line, f));
    TEST_ASSERT_NOT_NULL(fgets(line, sizeof line, f));
    TEST_ASSERT_EQUAL_INT('2', line[0]);
    TEST_ASSERT_DOUBLE_WITHIN(1e-12, 0.4, strtod(strchr(strchr(line, ',') + 1, ',') + 1, NULL));
    TEST_ASSERT_NULL(fgets(line, sizeof line, f));
    fclose(f);
    /* Time going back: lap 0 again, the interrupted lap is not stored. */
    memset(&sum, 0, sizeof sum);
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_record_open(&rec, &sc, NULL, NULL, 6, &sum, &err));
    const double ts[5] = {0.0, 0.5, 0.9, 0.1, 1.2}; /* 0.9 -> 0.1: a restart */
    for (int i = 0; i < 5; ++i) {
        meas.cabin.p_m = cdpr_v3(0.1, 0.0, 0.0);
        const cdpr_record_row_t row = {ts[i], &d, &meas, tc, tc, lff, u, seg};
        TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_record_period(&rec, i, i == 4, &row));
    }
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_record_close(&rec));
    TEST_ASSERT_EQUAL_INT(1, sum.n_laps); /* only the lap 0 after the restart, at t = 1.2 */
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_blend_closed_form);
    RUN_TEST(test_transfer_ends);
    RUN_TEST(test_transfer_derivatives);
    RUN_TEST(test_transfer_from_rest_ends);
    RUN_TEST(test_wind_wrench_hand);
    RUN_TEST(test_slack_demand_counted);
    RUN_TEST(test_plant_slack_periods);
    RUN_TEST(test_lap_statistics);
    return UNITY_END();
}
