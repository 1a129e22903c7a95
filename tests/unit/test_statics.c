/// @file test_statics.c
/// Sag-aware statics of the six-cable 50 m model (PARAMETERS.md set A): IK balances the cabin
/// wrench (checked here from the returned forces), each cable's catenary closes on both end
/// points, forward statics inverts IK, infeasible poses are reported, and the lumped-mass
/// robot settled by its own dynamics converges to the statics solution as segments increase.
#include <math.h>
#include <string.h>

#include "cdpr/catenary.h"
#include "cdpr/robot.h"
#include "cdpr/rkf45.h"
#include "cdpr/settle.h"
#include "cdpr/statics.h"
#include "unity.h"

void setUp(void) {}
void tearDown(void) {}

static const double PI = 3.14159265358979323846;

static cdpr_robot_t robot;
static cdpr_real_t y[CDPR_ROBOT_STATE_MAX];
static cdpr_real_t scratch[CDPR_ROBOT_STATE_MAX];
static cdpr_real_t work[CDPR_RKF45_WORK_PER_DIM * CDPR_ROBOT_STATE_MAX];

/* PARAMETERS.md set A; lengths are placeholders until IK provides them. */
static void params_50m(cdpr_robot_params_t *p, int segments, const double *lengths)
{
    static const double az_deg[6] = {25.0, 35.0, 145.0, 155.0, 265.0, 275.0};
    cdpr_robot_params_default(p);
    p->n_cables = 6;
    p->cabin.mass_kg = 40.0;
    for (int j = 0; j < 6; ++j) {
        const double th = (double)j * PI / 3.0;
        const double az = az_deg[j] * PI / 180.0;
        cdpr_robot_cable_params_t *c = &p->cables[j];
        c->exit_point_m = cdpr_v3(25.0 * cos(th), 25.0 * sin(th), 30.0);
        c->attach_body_m = cdpr_v3(2.0 * cos(az), 2.0 * sin(az), -0.5);
        c->n_segments = segments;
        c->length_m = (lengths != NULL) ? lengths[j] : 30.0;
    }
}

static cdpr_cabin_motion_t pose_of(double x, double yy, double z, double a, double b, double g)
{
    cdpr_cabin_motion_t m;
    memset(&m, 0, sizeof m);
    m.p_m = cdpr_v3(x, yy, z);
    m.q = cdpr_quat_from_euler(a, b, g);
    return m;
}

static void ik(const cdpr_cabin_motion_t *pose, cdpr_statics_result_t *res)
{
    cdpr_robot_params_t p;
    params_50m(&p, 8, NULL);
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_robot_init(&robot, &p, NULL));
    cdpr_statics_opts_t o;
    cdpr_statics_opts_default(&o);
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_statics_ik(&robot, pose, &o, res));
}

static void test_ik_balances_the_cabin_and_closes_every_catenary(void)
{
    const cdpr_cabin_motion_t poses[3] = {pose_of(0.0, 0.0, 9.135, 0.0, 0.0, 0.0),
                                          pose_of(0.0, 0.001, 9.135 - 1.470, 0.0, 0.0, 0.0),
                                          pose_of(2.0, 1.0, 16.0, 0.0889, -0.1756, -0.03359)};
    for (int k = 0; k < 3; ++k) {
        cdpr_statics_result_t res;
        ik(&poses[k], &res);
        /* Wrench from the returned forces, recomputed here: sum F - M g z, sum (P - c_w) x F,
         * with the CoM at the body origin (PARAMETERS.md: b_j relative to the CoM). */
        double f[3] = {0.0, 0.0, -40.0 * 9.80665};
        double m[3] = {0.0, 0.0, 0.0};
        for (int j = 0; j < 6; ++j) {
            const cdpr_vec3_t F = res.cable[j].force_on_cabin_N;
            const cdpr_vec3_t a = cdpr_v3_sub(res.cable[j].attach_world_m, poses[k].p_m);
            f[0] += F.x;
            f[1] += F.y;
            f[2] += F.z;
            m[0] += a.y * F.z - a.z * F.y;
            m[1] += a.z * F.x - a.x * F.z;
            m[2] += a.x * F.y - a.y * F.x;
            /* Every cable pulls (H > 0), and the catenary of (H, V, L) spans exactly from
             * the attachment to the exit point. */
            TEST_ASSERT_TRUE(res.cable[j].H_N > 0.0);
            const cdpr_vec3_t d =
                cdpr_v3_sub(robot.p.cables[j].exit_point_m, res.cable[j].attach_world_m);
            const cdpr_catenary_cable_t c = {0.14 * 9.80665, 2.0e6};
            double l;
            double h;
            TEST_ASSERT_EQUAL_INT(CDPR_OK,
                                  cdpr_catenary_spans(&c, res.cable[j].H_N, res.cable[j].v_cabin_N,
                                                      res.cable[j].length_m, &l, &h));
            TEST_ASSERT_DOUBLE_WITHIN(1e-8, sqrt(d.x * d.x + d.y * d.y), l);
            TEST_ASSERT_DOUBLE_WITHIN(1e-8, d.z, h);
            /* The horizontal force points from the attachment toward the tower. */
            TEST_ASSERT_TRUE(F.x * d.x + F.y * d.y > 0.0);
        }
        for (int i = 0; i < 3; ++i) {
            TEST_ASSERT_DOUBLE_WITHIN(1e-6, 0.0, f[i]); /* N, of a 392 N weight */
            TEST_ASSERT_DOUBLE_WITHIN(1e-6, 0.0, m[i]); /* N m */
        }
    }
}

static void test_circle_start_matches_parameter_set_facts(void)
{
    /* PARAMETERS.md (derived): at the circle's start every cable has L0 ~ 31.6 m. */
    cdpr_statics_result_t res;
    const cdpr_cabin_motion_t pose = pose_of(0.0, 0.0, 9.135, 0.0, 0.0, 0.0);
    ik(&pose, &res);
    for (int j = 0; j < 6; ++j) {
        TEST_ASSERT_DOUBLE_WITHIN(0.1, 31.6, res.cable[j].length_m);
        TEST_ASSERT_TRUE(res.cable[j].tension_winch_N > res.cable[j].tension_cabin_N);
    }
    /* The massless model differs, by a few per cent here (sag ~4 % of the chord). */
    cdpr_statics_result_t st;
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_statics_ik_straight(&robot, &pose, &st));
    double maxrel = 0.0;
    for (int j = 0; j < 6; ++j) {
        maxrel = fmax(maxrel, fabs(st.cable[j].tension_cabin_N - res.cable[j].tension_cabin_N) /
                                  res.cable[j].tension_cabin_N);
    }
    TEST_ASSERT_TRUE(maxrel > 1e-3);
    TEST_ASSERT_TRUE(maxrel < 0.3);
}

static void test_forward_statics_inverts_ik(void)
{
    const cdpr_cabin_motion_t pose = pose_of(1.0, -0.5, 12.0, 0.03, -0.02, 0.1);
    cdpr_statics_result_t res;
    ik(&pose, &res);
    double L[6];
    for (int j = 0; j < 6; ++j) {
        L[j] = res.cable[j].length_m;
    }
    cdpr_cabin_motion_t guess = pose_of(1.3, -0.2, 11.5, 0.0, 0.0, 0.0);
    cdpr_statics_opts_t o;
    cdpr_statics_opts_default(&o);
    cdpr_statics_result_t fw;
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_statics_forward(&robot, L, &guess, &o, &fw));
    /* Issue 3 asks mm / mrad; the solvers' tolerances give ~1e-8. */
    TEST_ASSERT_DOUBLE_WITHIN(1e-6, pose.p_m.x, fw.pose.p_m.x);
    TEST_ASSERT_DOUBLE_WITHIN(1e-6, pose.p_m.y, fw.pose.p_m.y);
    TEST_ASSERT_DOUBLE_WITHIN(1e-6, pose.p_m.z, fw.pose.p_m.z);
    double a0;
    double b0;
    double g0;
    double a1;
    double b1;
    double g1;
    cdpr_quat_to_euler(pose.q, &a0, &b0, &g0);
    cdpr_quat_to_euler(fw.pose.q, &a1, &b1, &g1);
    TEST_ASSERT_DOUBLE_WITHIN(1e-6, a0, a1);
    TEST_ASSERT_DOUBLE_WITHIN(1e-6, b0, b1);
    TEST_ASSERT_DOUBLE_WITHIN(1e-6, g0, g1);
}

static void test_infeasible_and_bad_poses_are_reported(void)
{
    cdpr_robot_params_t p;
    params_50m(&p, 8, NULL);
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_robot_init(&robot, &p, NULL));
    cdpr_statics_opts_t o;
    cdpr_statics_opts_default(&o);
    cdpr_statics_result_t res;
    /* Outside the tower circle: some cable would have to push. */
    const cdpr_cabin_motion_t out = pose_of(30.0, 0.0, 10.0, 0.0, 0.0, 0.0);
    TEST_ASSERT_EQUAL_INT(CDPR_E_INFEASIBLE, cdpr_statics_ik(&robot, &out, &o, &res));
    TEST_ASSERT_EQUAL_INT(CDPR_E_INFEASIBLE, cdpr_statics_ik_straight(&robot, &out, &res));
    /* Above the exit points: every cable pulls the cabin down. */
    const cdpr_cabin_motion_t high = pose_of(0.0, 0.0, 35.0, 0.0, 0.0, 0.0);
    TEST_ASSERT_EQUAL_INT(CDPR_E_INFEASIBLE, cdpr_statics_ik(&robot, &high, &o, &res));
    TEST_ASSERT_EQUAL_INT(CDPR_E_INFEASIBLE, cdpr_statics_ik_straight(&robot, &high, &res));
    /* Tilted by 1.2 rad is still feasible (different cables carry the weight). */
    const cdpr_cabin_motion_t tilt = pose_of(0.0, 0.0, 10.0, 1.2, 0.0, 0.0);
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_statics_ik(&robot, &tilt, &o, &res));
    cdpr_cabin_motion_t nan_pose = pose_of(0.0, 0.0, 10.0, 0.0, 0.0, 0.0);
    nan_pose.p_m.z = NAN;
    TEST_ASSERT_EQUAL_INT(CDPR_E_NOT_FINITE, cdpr_statics_ik(&robot, &nan_pose, &o, &res));
    o.max_iter = 0;
    TEST_ASSERT_EQUAL_INT(CDPR_E_INVALID_ARG, cdpr_statics_ik(&robot, &out, &o, &res));
}

/* Lumped-mass robot with the IK lengths, placed on the catenaries and settled by its own
 * dynamics (cabin free): its cabin position and end tensions vs the statics solution. */
static void settle_vs_statics(int segments, const cdpr_statics_result_t *res, double *dpos,
                              double *dten)
{
    double L[6];
    for (int j = 0; j < 6; ++j) {
        L[j] = res->cable[j].length_m;
    }
    cdpr_robot_params_t p;
    params_50m(&p, segments, L);
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_robot_init(&robot, &p, NULL));
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_robot_place_catenary(&robot, res, y));
    cdpr_rkf45_params_t sp;
    cdpr_rkf45_params_default(&sp);
    sp.rtol = 1e-9;
    sp.atol = 1e-10;
    cdpr_rkf45_t s;
    TEST_ASSERT_EQUAL_INT(CDPR_OK,
                          cdpr_rkf45_init(&s, &sp, work, (int)(sizeof work / sizeof work[0]),
                                          CDPR_ROBOT_STATE_MAX, robot.dim, NULL));
    cdpr_settle_t cfg;
    cdpr_settle_default(&cfg);
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_robot_settle(&robot, &s, y, scratch, &cfg));
    const cdpr_vec3_t dp = cdpr_v3_sub(cdpr_v3(y[0], y[1], y[2]), res->pose.p_m);
    *dpos = cdpr_v3_norm(dp);
    cdpr_robot_out_t out;
    cdpr_robot_outputs(&robot, 0.0, y, &out);
    *dten = 0.0;
    for (int j = 0; j < 6; ++j) {
        /* Continuous cabin-end force = segment-0 pull minus node 0's lumped weight (that mass
         * rides on the cabin in the lumped model). */
        const double wn = 0.5 * 0.14 * robot.cable[j].lu_m[0] * 9.80665;
        const cdpr_vec3_t F = out.force_on_cabin_N[j];
        const double T = sqrt(F.x * F.x + F.y * F.y + (F.z - wn) * (F.z - wn));
        *dten = fmax(*dten, fabs(T - res->cable[j].tension_cabin_N));
    }
}

static void test_settled_lumped_robot_converges_to_statics(void)
{
    cdpr_statics_result_t res;
    const cdpr_cabin_motion_t pose = pose_of(0.5, -0.3, 10.0, 0.0, 0.0, 0.0);
    ik(&pose, &res);
    double dp[3];
    double dt[3];
    const int ns[3] = {4, 8, 16};
    for (int k = 0; k < 3; ++k) {
        settle_vs_statics(ns[k], &res, &dp[k], &dt[k]);
    }
    /* The discrete chain's equilibrium differs from the catenary by O(Delta^2). */
    TEST_ASSERT_TRUE(dp[2] < 5e-3);
    TEST_ASSERT_TRUE(dt[2] < 0.05); /* N, of ~30-200 N */
    TEST_ASSERT_TRUE(dp[0] / dp[1] > 3.0);
    TEST_ASSERT_TRUE(dp[1] / dp[2] > 3.0);
    TEST_ASSERT_TRUE(dt[0] / dt[1] > 3.0);
    TEST_ASSERT_TRUE(dt[1] / dt[2] > 3.0);
}

static void test_robot_initialised_at_equilibrium_stays_at_rest(void)
{
    cdpr_statics_result_t res;
    const cdpr_cabin_motion_t pose = pose_of(0.0, 0.0, 9.135, 0.0, 0.0, 0.0);
    ik(&pose, &res);
    double dp;
    double dt;
    settle_vs_statics(8, &res, &dp, &dt);
    static cdpr_real_t y0[CDPR_ROBOT_STATE_MAX];
    memcpy(y0, y, sizeof(cdpr_real_t) * (size_t)robot.dim);
    cdpr_rkf45_params_t sp;
    cdpr_rkf45_params_default(&sp);
    cdpr_rkf45_t s;
    TEST_ASSERT_EQUAL_INT(CDPR_OK,
                          cdpr_rkf45_init(&s, &sp, work, (int)(sizeof work / sizeof work[0]),
                                          CDPR_ROBOT_STATE_MAX, robot.dim, NULL));
    double t = 0.0;
    double drift = 0.0;
    for (int k = 0; k < 1000; ++k) { /* 10 s in 10 ms periods */
        TEST_ASSERT_EQUAL_INT(CDPR_OK,
                              cdpr_rkf45_advance(&s, cdpr_robot_rhs, &robot, &t, y, 0.01, 100));
        cdpr_robot_normalize(&robot, y);
        drift = fmax(drift, cdpr_v3_norm(cdpr_v3_sub(cdpr_v3(y[0], y[1], y[2]),
                                                     cdpr_v3(y0[0], y0[1], y0[2]))));
    }
    /* Settled to 1e-6 m/s^2 residual acceleration; the cabin's softest mode (~0.4 Hz,
     * omega^2 ~ 6 1/s^2) turns that into < 1e-6 m; integration at rtol 1e-6 adds its own
     * error. Bound: 1e-5 m over 10 s. */
    TEST_ASSERT_DOUBLE_WITHIN(1e-5, 0.0, drift);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_ik_balances_the_cabin_and_closes_every_catenary);
    RUN_TEST(test_circle_start_matches_parameter_set_facts);
    RUN_TEST(test_forward_statics_inverts_ik);
    RUN_TEST(test_infeasible_and_bad_poses_are_reported);
    RUN_TEST(test_settled_lumped_robot_converges_to_statics);
    RUN_TEST(test_robot_initialised_at_equilibrium_stays_at_rest);
    return UNITY_END() ? 1 : 0;
}
