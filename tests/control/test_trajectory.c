/* SPDX-License-Identifier: BSD-3-Clause */
/// @file test_trajectory.c
/// Trajectories against their definitions: the circle's geometry, speed and direction, its
/// speed ramp, the line's end points and rates, every derivative against a central finite
/// difference of the pose (the body angular velocity against one of the quaternion), and the
/// accelerations (pose, body origin, body-axes angular) against central finite differences of
/// the velocities. Core and lib/control only: also run on the Cortex-M7 and, in float, the M4;
/// the float tolerances (TOL, test_real.h) are argued where they differ: float's u_f = 6e-8
/// relative on poses of ~10 m and times of ~10 s, and central differences over h = 1e-2 s in
/// float (1e-4 s in double) so that rounding (u_f |x| / h) stays below the truncation error.
#include <math.h>
#include <string.h>

#include "cdpr/control/trajectory.h"
#include "paper_circle.h"
#include "test_real.h"
#include "unity.h"

void setUp(void) {}
void tearDown(void) {}

static const double PI = 3.14159265358979323846;

static cdpr_traj_t paper_circle(void)
{
    return test_paper_circle();
}

/* An input as the build's real type holds it (exact comparisons of copied inputs). */
#define AS_REAL(x) ((double)(cdpr_real_t)(x))

/* Six pose values into a trajectory's cdpr_real_t array. */
static void set6(cdpr_real_t dst[6], const double src[6])
{
    for (int i = 0; i < 6; ++i) {
        dst[i] = (cdpr_real_t)src[i];
    }
}

/* Central-difference step [s] and the tolerance of a derivative checked with it. Double:
 * h = 1e-4 s, truncation h^2/6 times the third derivative (<= 10 here) < 2e-8, rounding
 * 1e-16 x 20 / h = 2e-11: 1e-7. Float: h = 1e-2 s (at 1e-4 s, float's rounding
 * 6e-8 x 20 m / 1e-4 s = 1e-2 would swamp it), truncation 1e-4 / 6 x 10 = 1.7e-4, rounding
 * 6e-8 x 20 / 1e-2 = 1.2e-4: 3e-4 (1e-4 of the rates and accelerations of O(1) checked). */
#define FD_H   TOL(1e-4, 1e-2)
#define FD_TOL TOL(1e-7, 3e-4)

/* Central difference of every pose coordinate vs the analytic rate. The error of a central
 * difference is h^2/6 |f'''|; with h = 1e-4 s and |f'''| <= v^3/r^2 = 2 m/s^3 on the circle
 * that is 3e-9, rounding adds ~1e-15/h = 1e-11: tolerance 1e-7. */
static void check_rates(const cdpr_traj_t *tr, double t)
{
    const double h = FD_H;
    cdpr_traj_sample_t a;
    cdpr_traj_sample_t b;
    cdpr_traj_sample_t s;
    cdpr_traj_eval(tr, t - h, &a);
    cdpr_traj_eval(tr, t + h, &b);
    cdpr_traj_eval(tr, t, &s);
    for (int i = 0; i < 6; ++i) {
        TEST_ASSERT_DOUBLE_WITHIN(FD_TOL, (b.pose[i] - a.pose[i]) / (2.0 * h), s.rate[i]);
    }
    /* Body rate: ω = 2 Im(q^-1 q') with q' by central difference (same error order). */
    const cdpr_quat_t qi = {s.motion.q.w, -s.motion.q.x, -s.motion.q.y, -s.motion.q.z};
    const cdpr_quat_t qd = {(cdpr_real_t)((b.motion.q.w - a.motion.q.w) / (2.0 * h)),
                            (cdpr_real_t)((b.motion.q.x - a.motion.q.x) / (2.0 * h)),
                            (cdpr_real_t)((b.motion.q.y - a.motion.q.y) / (2.0 * h)),
                            (cdpr_real_t)((b.motion.q.z - a.motion.q.z) / (2.0 * h))};
    const cdpr_quat_t w = cdpr_quat_mul(qi, qd);
    TEST_ASSERT_DOUBLE_WITHIN(FD_TOL, 2.0 * w.x, s.motion.w_rad_per_s.x);
    TEST_ASSERT_DOUBLE_WITHIN(FD_TOL, 2.0 * w.y, s.motion.w_rad_per_s.y);
    TEST_ASSERT_DOUBLE_WITHIN(FD_TOL, 2.0 * w.z, s.motion.w_rad_per_s.z);
    TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-15, 1e-6), s.rate[0], s.motion.v_m_per_s.x);
}

static void test_circle_geometry_speed_and_direction(void)
{
    const cdpr_traj_t tr = paper_circle();
    cdpr_traj_sample_t s;
    cdpr_traj_eval(&tr, 0.0, &s);
    /* Start point (0, 0, 9.135) [paper §4]. */
    /* float: cos(pi/2) of a float pi/2 is 4e-8, times r = 2 m */
    TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-15, 2e-7), 0.0, s.pose[0]);
    TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-15, 2e-7), 0.0, s.pose[1]);
    TEST_ASSERT_EQUAL_DOUBLE(AS_REAL(9.135), s.pose[2]);
    for (int k = 0; k < 50; ++k) {
        const double t = 0.173 * k;
        cdpr_traj_eval(&tr, t, &s);
        const double dx = s.pose[0] - tr.centre_m[0];
        const double dy = s.pose[1] - tr.centre_m[1];
        /* float: a few u_f of the 2 m radius and of the 2 m/s speed (sin, cos of the float
         * angle are each within an ulp): 2e-6; their product 4 within 1e-5 */
        TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-14, 2e-6), 2.0, sqrt(dx * dx + dy * dy));
        TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-14, 2e-6), 2.0, hypot(s.rate[0], s.rate[1]));
        /* Counter-clockwise seen from above: (p - c) x v along +z, = r v. */
        TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-13, 1e-5), 4.0, dx * s.rate[1] - dy * s.rate[0]);
        for (int i = 3; i < 6; ++i) {
            TEST_ASSERT_EQUAL_DOUBLE(0.0, s.pose[i]);
        }
        check_rates(&tr, t + 0.05);
    }
    /* One lap takes 2 pi r / v. float: the time 2 pi rounded (2.4e-7 s) and the angle 2 pi +
     * pi/2 rounded (4.8e-7 rad) move the point by ~1.5e-6 m on r = 2 m: 5e-6. */
    cdpr_traj_eval(&tr, (cdpr_real_t)(2.0 * PI), &s);
    TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-13, 5e-6), 0.0, s.pose[0]);
    TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-13, 5e-6), 0.0, s.pose[1]);
    cdpr_traj_eval(&tr, -1.0, &s); /* before the start: held at the start point */
    TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-15, 2e-7), 0.0, s.pose[0]);
    TEST_ASSERT_EQUAL_DOUBLE(0.0, s.rate[0]);
}

static void test_circle_ramp_and_clockwise(void)
{
    cdpr_traj_t tr = paper_circle();
    tr.ramp_s = CDPR_R(2.0);
    tr.direction = CDPR_R(-1.0);
    tr.attitude_rad[2] = CDPR_R(0.3);
    for (int k = 0; k <= 40; ++k) {
        const double t = 0.1 * k;
        cdpr_traj_sample_t s;
        cdpr_traj_eval(&tr, t, &s);
        /* Speed v t / T during the ramp, then v. */
        const double v = (t < 2.0) ? 2.0 * t / 2.0 : 2.0;
        TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-14, 2e-6), v, hypot(s.rate[0], s.rate[1]));
        if (t > 0.0) {
            const double dx = s.pose[0] - tr.centre_m[0];
            const double dy = s.pose[1] - tr.centre_m[1];
            TEST_ASSERT_TRUE(dx * s.rate[1] - dy * s.rate[0] < 0.0); /* clockwise */
        }
        TEST_ASSERT_EQUAL_DOUBLE(AS_REAL(0.3), s.pose[5]);
        if (t > 0.0) {
            check_rates(&tr, t + 0.05);
        }
    }
}

static void test_line_end_points_rates_and_return(void)
{
    cdpr_traj_t tr;
    memset(&tr, 0, sizeof tr);
    tr.type = CDPR_TRAJ_LINE;
    const double from[6] = {2.00, 1.00, 16.0, 0.0889, -0.1756, 3.108 - PI};
    const double to[6] = {2.50, 1.50, 16.2, 0.135, -0.263, 3.121 - PI};
    set6(tr.from, from);
    set6(tr.to, to);
    tr.duration_s = CDPR_R(10.0);
    cdpr_traj_sample_t s;
    cdpr_traj_eval(&tr, 0.0, &s);
    for (int i = 0; i < 6; ++i) {
        TEST_ASSERT_EQUAL_DOUBLE(AS_REAL(from[i]), s.pose[i]);
    }
    /* float: the inputs' rounding (u_f x 16 m = 1e-6 m, over 10 s 1e-7 m/s) and a few
     * roundings of the interpolation: 2e-6 m, 3e-7 m/s */
    cdpr_traj_eval(&tr, 5.0, &s);
    for (int i = 0; i < 6; ++i) {
        TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-15, 2e-6), 0.5 * (from[i] + to[i]), s.pose[i]);
        TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-16, 3e-7), (to[i] - from[i]) / 10.0, s.rate[i]);
    }
    for (int k = 1; k < 10; ++k) {
        check_rates(&tr, 0.97 * k);
    }
    cdpr_traj_eval(&tr, 12.0, &s);
    for (int i = 0; i < 6; ++i) {
        TEST_ASSERT_EQUAL_DOUBLE(AS_REAL(to[i]), s.pose[i]);
        TEST_ASSERT_EQUAL_DOUBLE(0.0, s.rate[i]);
    }
    TEST_ASSERT_EQUAL_DOUBLE(10.0, cdpr_traj_end_time(&tr));
    /* Back and forth with a pause: at `to` during the pause, back at `from` at the end. */
    tr.back_and_forth = 1;
    tr.pause_s = CDPR_R(2.0);
    cdpr_traj_eval(&tr, 11.0, &s);
    TEST_ASSERT_EQUAL_DOUBLE(AS_REAL(to[2]), s.pose[2]);
    cdpr_traj_eval(&tr, 17.0, &s);
    TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-14, 2e-6), 0.5 * (from[2] + to[2]), s.pose[2]);
    TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-16, 3e-7), -(to[2] - from[2]) / 10.0, s.rate[2]);
    check_rates(&tr, 17.0);
    cdpr_traj_eval(&tr, 30.0, &s);
    TEST_ASSERT_EQUAL_DOUBLE(AS_REAL(from[2]), s.pose[2]);
    TEST_ASSERT_EQUAL_DOUBLE(22.0, cdpr_traj_end_time(&tr));
}

static void test_hold(void)
{
    cdpr_traj_t tr;
    memset(&tr, 0, sizeof tr);
    tr.type = CDPR_TRAJ_HOLD;
    const double pose[6] = {0.5, -0.5, 10.0, 0.1, -0.2, 0.3};
    set6(tr.hold_pose, pose);
    cdpr_traj_sample_t s;
    cdpr_traj_eval(&tr, 3.0, &s);
    for (int i = 0; i < 6; ++i) {
        TEST_ASSERT_EQUAL_DOUBLE(AS_REAL(pose[i]), s.pose[i]);
        TEST_ASSERT_EQUAL_DOUBLE(0.0, s.rate[i]);
    }
}

/* Accelerations against central differences of the analytic velocities, away from kinks.
 * Error h^2/6 |d^3v/dt^3|: on the circle v th'^3 = 2 m/s^4 (with the ramp's extra terms below
 * 5 m/s^4), for the angular rates of the test line below ~10 rad/s^4; with h = 1e-4 s that is
 * < 2e-8, rounding adds ~1e-16 / h = 1e-12: tolerance 1e-7. */
static void check_accels(const cdpr_traj_t *tr, double t)
{
    const double h = FD_H; /* FD_TOL above; kinks are at least 0.05 s away */
    cdpr_traj_sample_t a;
    cdpr_traj_sample_t b;
    cdpr_traj_sample_t s;
    cdpr_traj_eval(tr, t - h, &a);
    cdpr_traj_eval(tr, t + h, &b);
    cdpr_traj_eval(tr, t, &s);
    for (int i = 0; i < 6; ++i) {
        TEST_ASSERT_DOUBLE_WITHIN(FD_TOL, (b.rate[i] - a.rate[i]) / (2.0 * h), s.accel[i]);
    }
    /* Body origin: derivative of the world velocity. */
    TEST_ASSERT_DOUBLE_WITHIN(FD_TOL, (b.motion.v_m_per_s.x - a.motion.v_m_per_s.x) / (2.0 * h),
                              s.a_m_per_s2.x);
    TEST_ASSERT_DOUBLE_WITHIN(FD_TOL, (b.motion.v_m_per_s.y - a.motion.v_m_per_s.y) / (2.0 * h),
                              s.a_m_per_s2.y);
    TEST_ASSERT_DOUBLE_WITHIN(FD_TOL, (b.motion.v_m_per_s.z - a.motion.v_m_per_s.z) / (2.0 * h),
                              s.a_m_per_s2.z);
    /* Angular: derivative of the body-axes ω (itself checked against the quaternion in
     * check_rates). */
    TEST_ASSERT_DOUBLE_WITHIN(FD_TOL, (b.motion.w_rad_per_s.x - a.motion.w_rad_per_s.x) / (2.0 * h),
                              s.dw_rad_per_s2.x);
    TEST_ASSERT_DOUBLE_WITHIN(FD_TOL, (b.motion.w_rad_per_s.y - a.motion.w_rad_per_s.y) / (2.0 * h),
                              s.dw_rad_per_s2.y);
    TEST_ASSERT_DOUBLE_WITHIN(FD_TOL, (b.motion.w_rad_per_s.z - a.motion.w_rad_per_s.z) / (2.0 * h),
                              s.dw_rad_per_s2.z);
}

static void test_circle_accelerations(void)
{
    /* The paper's circle at constant speed: centripetal v^2 / r = 2 m/s^2 toward the centre,
     * no tangential part, no angular acceleration. */
    cdpr_traj_t tr = paper_circle();
    for (int k = 0; k < 30; ++k) {
        const double t = 0.05 + 0.21 * k;
        cdpr_traj_sample_t s;
        cdpr_traj_eval(&tr, t, &s);
        /* (c - p) / r is the unit vector toward the centre. */
        const double ux = (tr.centre_m[0] - s.pose[0]) / 2.0;
        const double uy = (tr.centre_m[1] - s.pose[1]) / 2.0;
        /* float: the pose's 2e-6 m (above) over r = 2 m, times 2 m/s^2 */
        TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-13, 4e-6), 2.0 * ux, s.a_m_per_s2.x);
        TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-13, 4e-6), 2.0 * uy, s.a_m_per_s2.y);
        TEST_ASSERT_EQUAL_DOUBLE(0.0, s.a_m_per_s2.z);
        TEST_ASSERT_EQUAL_DOUBLE(0.0, cdpr_v3_norm(s.dw_rad_per_s2));
        check_accels(&tr, t);
    }
    /* With a 2 s ramp, clockwise, yawed: tangential v / T = 1 m/s^2 during the ramp on top
     * of the growing centripetal part (v t / T)^2 / r, then centripetal only. */
    tr.ramp_s = CDPR_R(2.0);
    tr.direction = CDPR_R(-1.0);
    tr.attitude_rad[2] = CDPR_R(0.3);
    for (int k = 0; k < 30; ++k) {
        const double t = 0.05 + 0.13 * k;
        if (fabs(t - 2.0) < 1e-3) {
            continue; /* the kink at the end of the ramp */
        }
        cdpr_traj_sample_t s;
        cdpr_traj_eval(&tr, t, &s);
        const double v = (t < 2.0) ? t : 2.0;
        const double at = (t < 2.0) ? 1.0 : 0.0;
        const double an = v * v / 2.0;
        TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-12, 4e-6), sqrt(at * at + an * an),
                                  hypot(s.a_m_per_s2.x, s.a_m_per_s2.y));
        check_accels(&tr, t);
    }
    /* Before the start: at rest, no acceleration. */
    cdpr_traj_sample_t s;
    cdpr_traj_eval(&tr, -0.5, &s);
    TEST_ASSERT_EQUAL_DOUBLE(0.0, cdpr_v3_norm(s.a_m_per_s2));
}

static void test_line_and_hold_accelerations(void)
{
    /* Every pose coordinate linear in time: no linear acceleration; the body-axes angular
     * acceleration is not zero, because the map from Euler-angle rates to ω changes with the
     * angles. Large angle changes make that term visible (|dω/dt| ~ 0.1-1 rad/s^2). */
    cdpr_traj_t tr;
    memset(&tr, 0, sizeof tr);
    tr.type = CDPR_TRAJ_LINE;
    const double from[6] = {2.00, 1.00, 16.0, 0.0, 0.0, 0.0};
    const double to[6] = {2.50, 1.50, 16.2, 1.0, -0.8, 2.0};
    set6(tr.from, from);
    set6(tr.to, to);
    tr.duration_s = CDPR_R(2.0);
    double largest = 0.0;
    for (int k = 1; k < 20; ++k) {
        const double t = 0.1 * k;
        cdpr_traj_sample_t s;
        cdpr_traj_eval(&tr, t, &s);
        for (int i = 0; i < 6; ++i) {
            TEST_ASSERT_EQUAL_DOUBLE(0.0, s.accel[i]);
        }
        largest = fmax(largest, cdpr_v3_norm(s.dw_rad_per_s2));
        check_accels(&tr, t);
    }
    TEST_ASSERT_TRUE(largest > 0.1);
    /* Holding: everything zero. */
    memset(&tr, 0, sizeof tr);
    tr.type = CDPR_TRAJ_HOLD;
    tr.hold_pose[2] = CDPR_R(9.0);
    tr.hold_pose[4] = CDPR_R(0.2);
    cdpr_traj_sample_t s;
    cdpr_traj_eval(&tr, 1.0, &s);
    TEST_ASSERT_EQUAL_DOUBLE(0.0, cdpr_v3_norm(s.a_m_per_s2));
    TEST_ASSERT_EQUAL_DOUBLE(0.0, cdpr_v3_norm(s.dw_rad_per_s2));
}

/* The cyclic deploy/retrieve type against its closed form: each leg is the cycloid
 * s(u) = u - sin(2 pi u) / (2 pi); continuous position, velocity and acceleration at every
 * leg and cycle boundary; periodic; held at `from` after the last cycle. */
static cdpr_traj_t cyclic_traj(void)
{
    cdpr_traj_t tr;
    memset(&tr, 0, sizeof tr);
    tr.type = CDPR_TRAJ_CYCLIC;
    const double from[6] = {0.0, 0.0, 4.0, 0.0, 0.0, 0.0};
    const double to[6] = {1.0, -2.0, 15.0, 0.1, 0.0, -0.2};
    set6(tr.from, from);
    set6(tr.to, to);
    tr.duration_s = CDPR_R(8.0);
    tr.pause_s = CDPR_R(2.0);
    tr.cycles = 3;
    return tr;
}

static void test_cyclic_closed_form_continuity_and_period(void)
{
    const cdpr_traj_t tr = cyclic_traj();
    const double P = 20.0; /* 2 (8 + 2) */
    TEST_ASSERT_EQUAL_DOUBLE(P, cdpr_traj_cycle_s(&tr));
    TEST_ASSERT_EQUAL_DOUBLE(3.0 * P, cdpr_traj_end_time(&tr));
    cdpr_traj_sample_t a;
    cdpr_traj_sample_t b;
    /* Closed form at a quarter of the way out (u = 1/4: s = 1/4 - 1/(2 pi), s' = 1/T,
     * s'' = 2 pi / T^2) and of the way back (t = 10 + 2, u = 1/4, reversed). Tolerance:
     * a few ulps of the arithmetic (1e-12 of values O(10); float: 5e-6 of the 15 m pose and of
     * rates and accelerations O(1), sin of a float 2 pi u within an ulp). */
    cdpr_traj_eval(&tr, 2.0, &a);
    cdpr_traj_eval(&tr, 12.0, &b);
    const double s = 0.25 - 1.0 / (2.0 * PI);
    for (int i = 0; i < 6; ++i) {
        const double d = tr.to[i] - tr.from[i];
        TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-12, 5e-6), tr.from[i] + s * d, a.pose[i]);
        TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-12, 5e-6), d / 8.0, a.rate[i]);
        TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-12, 5e-6), 2.0 * PI * d / 64.0, a.accel[i]);
        TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-12, 5e-6), tr.to[i] - s * d, b.pose[i]);
        TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-12, 5e-6), -d / 8.0, b.rate[i]);
        TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-12, 5e-6), -2.0 * PI * d / 64.0, b.accel[i]);
    }
    /* Continuity across every boundary (leg ends, pauses, cycle ends): the jump over +-dt
     * is bounded by the largest derivative times 2 dt (|d| <= 11 m: v <= 2.75 m/s,
     * a <= 1.08 m/s^2, jerk <= 0.85 m/s^3); double: dt = 1e-7 s, tolerance 1e-6; float: a time
     * of 60 s resolves only 3.8e-6 s, so dt = 1e-4 s, tolerance 1e-3 (above 2.75 x 2e-4).
     * Either is far below a real jump (a leg's peak rate is 2.75 m/s, its peak acceleration
     * 1.08 m/s^2). */
    const double edges[] = {0.0, 8.0, 10.0, 18.0, 20.0, 28.0, 40.0, 58.0, 60.0};
    const double dt = TOL(1e-7, 1e-4);
    for (size_t e = 0; e < sizeof edges / sizeof edges[0]; ++e) {
        cdpr_traj_eval(&tr, (cdpr_real_t)(edges[e] - dt), &a);
        cdpr_traj_eval(&tr, (cdpr_real_t)(edges[e] + dt), &b);
        for (int i = 0; i < 6; ++i) {
            TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-6, 1e-3), a.pose[i], b.pose[i]);
            TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-6, 1e-3), a.rate[i], b.rate[i]);
            TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-6, 1e-3), a.accel[i], b.accel[i]);
        }
    }
    /* Periodic: t and t + P agree (within the rounding of fmod at t ~ 40 s; float: times up to
     * 60 s round to 3.8e-6 s, times the 2.75 m/s peak rate: 5e-5) in every cycle. */
    for (double t = 0.05; t < 2.0 * P; t += 0.37) {
        cdpr_traj_eval(&tr, (cdpr_real_t)t, &a);
        cdpr_traj_eval(&tr, (cdpr_real_t)(t + P), &b);
        for (int i = 0; i < 6; ++i) {
            TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-9, 5e-5), a.pose[i], b.pose[i]);
            TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-9, 5e-5), a.rate[i], b.rate[i]);
            TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-9, 5e-5), a.accel[i], b.accel[i]);
        }
    }
    /* After the last cycle, and before the start: at `from`, at rest. */
    const double outside[2] = {-1.0, 3.0 * P + 5.0};
    for (int k = 0; k < 2; ++k) {
        cdpr_traj_eval(&tr, outside[k], &a);
        for (int i = 0; i < 6; ++i) {
            TEST_ASSERT_EQUAL_DOUBLE(tr.from[i], a.pose[i]);
            TEST_ASSERT_EQUAL_DOUBLE(0.0, a.rate[i]);
            TEST_ASSERT_EQUAL_DOUBLE(0.0, a.accel[i]);
        }
    }
    /* cycles = 0 repeats for ever. */
    cdpr_traj_t forever = tr;
    forever.cycles = 0;
    TEST_ASSERT_TRUE(isinf(cdpr_traj_end_time(&forever)));
    /* float: 20 002 s is held to 2e-3 s, where the pose moves at 1.4 m/s: 5e-3 m */
    cdpr_traj_eval(&forever, (cdpr_real_t)(2.0 + 1000.0 * P), &a);
    TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-9, 5e-3), tr.from[2] + s * 11.0, a.pose[2]);
    /* The rates are the derivatives of the pose (central differences, as for the others). */
    for (double t = 0.3; t < P; t += 1.1) {
        check_rates(&tr, t);
    }
}

/* Laps against the closed form: the paper circle (r 2 m, 2 m/s, no ramp) turns once per
 * 2 pi r / v = 6.283 s; with a 1 s ramp the path is v (t - 0.5) after the ramp, so lap 1
 * starts half a second later; cyclic: one lap per cycle P = 20 s, -1 after the last; not
 * periodic: -1. */
static void test_laps(void)
{
    cdpr_traj_t tr = paper_circle();
    const double lap_s = 2.0 * PI * tr.radius_m / tr.speed_m_per_s;
    /* How close to a lap boundary a time is taken: 1e-9 s in double; float resolves 6.3 s to
     * 4.8e-7 s and the lap's phase to a few of those: 1e-5 s. */
    const double eps = TOL(1e-9, 1e-5);
    TEST_ASSERT_EQUAL_INT(-1, (int)cdpr_traj_lap(&tr, CDPR_R(-0.1)));
    TEST_ASSERT_EQUAL_INT(0, (int)cdpr_traj_lap(&tr, CDPR_R(0.0)));
    TEST_ASSERT_EQUAL_INT(0, (int)cdpr_traj_lap(&tr, (cdpr_real_t)(lap_s - eps)));
    TEST_ASSERT_EQUAL_INT(1, (int)cdpr_traj_lap(&tr, (cdpr_real_t)(lap_s + eps)));
    TEST_ASSERT_EQUAL_INT(9, (int)cdpr_traj_lap(&tr, (cdpr_real_t)(9.5 * lap_s)));
    tr.ramp_s = CDPR_R(1.0);
    TEST_ASSERT_EQUAL_INT(0, (int)cdpr_traj_lap(&tr, (cdpr_real_t)(lap_s + 0.5 - eps)));
    TEST_ASSERT_EQUAL_INT(1, (int)cdpr_traj_lap(&tr, (cdpr_real_t)(lap_s + 0.5 + eps)));
    TEST_ASSERT_EQUAL_INT(0, (int)cdpr_traj_lap(&tr, CDPR_R(0.5))); /* inside the ramp */
    tr.speed_m_per_s = CDPR_R(0.0);
    TEST_ASSERT_EQUAL_INT(-1, (int)cdpr_traj_lap(&tr, 3.0));
    const cdpr_traj_t cy = cyclic_traj();
    TEST_ASSERT_EQUAL_INT(0, (int)cdpr_traj_lap(&cy, 19.999));
    TEST_ASSERT_EQUAL_INT(1, (int)cdpr_traj_lap(&cy, 20.001));
    TEST_ASSERT_EQUAL_INT(2, (int)cdpr_traj_lap(&cy, 59.999));
    TEST_ASSERT_EQUAL_INT(-1, (int)cdpr_traj_lap(&cy, 60.001));
    cdpr_traj_t line;
    memset(&line, 0, sizeof line);
    line.type = CDPR_TRAJ_LINE;
    line.duration_s = CDPR_R(10.0);
    TEST_ASSERT_EQUAL_INT(-1, (int)cdpr_traj_lap(&line, 5.0));
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_circle_geometry_speed_and_direction);
    RUN_TEST(test_circle_ramp_and_clockwise);
    RUN_TEST(test_line_end_points_rates_and_return);
    RUN_TEST(test_hold);
    RUN_TEST(test_circle_accelerations);
    RUN_TEST(test_line_and_hold_accelerations);
    RUN_TEST(test_cyclic_closed_form_continuity_and_period);
    RUN_TEST(test_laps);
    return UNITY_END() ? 1 : 0;
}
