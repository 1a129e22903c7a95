/* SPDX-License-Identifier: BSD-3-Clause */
/// @file test_plant_ros.c
/// The plant with the implicit integrator (CDPR_PLANT_ROS34PW2: ros34pw2.h + robot_w.h)
/// against an independent reference, a tight RKF45 run (rtol 1e-10) of the same plant and
/// commands: the paper robot (6 cables) driven by payout-rate profiles at 1 kHz, the cabin
/// within 1 mm and 1 mrad and the winch-end tensions within 1 % of the peak tension; the
/// per-period work counters and bounds; node insertion/removal conserving the paid-out length
/// per event; and the straight release of test_slack.c (slack, snap, damping) against a tight
/// RKF45 reference with the energy never increasing beyond the error estimate.
#include <math.h>
#include <string.h>

#include "alloc_count.h"
#include "cdpr/plant.h"
#include "cdpr/robot_w.h"
#include "cdpr/ros34pw2.h"
#include "paper_plant.h"
#include "test_real.h"
#include "unity.h"

void setUp(void) {}
void tearDown(void) {}

/* The paper's 50 m model (docs/robots.md) as in test_plant.c, 8 segments per cable. */
#define SEGMENTS 8

static cdpr_plant_t plant;

/* Rope damping of both runs: 0 keeps the paper rope's c = 170 N s (zeta 0.13 % at 5 Hz);
 * > 0 gives every cable that damping ratio at 5 Hz instead (cable.h). */
static double g_zeta = 0.0;

static void robot_params(cdpr_plant_params_t *pp)
{
    test_paper_plant_params(pp, SEGMENTS);
    if (g_zeta > 0.0) {
        for (int j = 0; j < pp->robot.n_cables; ++j) {
            cdpr_cable_params_t *c = &pp->robot.cables[j].cable;
            c->damping_Ns = CDPR_R(0.0);
            c->damping_ratio = (cdpr_real_t)g_zeta;
            c->damping_ref_hz = CDPR_R(5.0);
        }
    }
}

static void init_plant(cdpr_plant_t *p, const cdpr_plant_params_t *pp)
{
    cdpr_diag_t d;
    const cdpr_status_t st = cdpr_plant_init(p, pp, &d);
    TEST_ASSERT_EQUAL_INT_MESSAGE(CDPR_OK, st, d.field);
}

static cdpr_plant_t ref;

/* The implicit run's settings: loose node tolerances (the stiff axial modes are damped, not
 * resolved: docs/model.md "Time integration"), a 1 kHz period, at most 3 trials, the plant's
 * default reuse of W (jac_reuse_max 4; measured with 0 / 10 / 100: cabin 0.5 / 1.3 / 75 um,
 * 10 ms mean tension 0.23 / 0.24 / 2.2 % of the peak). */
static double g_vtol = 1e-2; /* velocity atol of ros_params [m/s] */

static void ros_params(cdpr_plant_params_t *pp)
{
    test_paper_rt_params(pp, CDPR_PLANT_ROS34PW2, g_vtol);
}

static void ref_params(cdpr_plant_params_t *pp)
{
    pp->integrator = CDPR_PLANT_RKF45;
    pp->rkf45.step.rtol = CDPR_R(1e-10);
    pp->atol.position_m = CDPR_R(1e-10);
    pp->atol.velocity_m_per_s = CDPR_R(1e-9);
    pp->atol.quaternion = CDPR_R(1e-12);
    pp->atol.rate_rad_per_s = CDPR_R(1e-10);
    pp->period_s = CDPR_R(0.001);
    pp->max_trials = 100000;
}

/* 1.5 s of payout profiles at 1 kHz: implicit vs the tight RKF45 reference, every period;
 * the raw winch-end tension within `raw_pct` of the peak. */
static void follow_tight_reference(double raw_pct)
{
    cdpr_plant_params_t pp;
    robot_params(&pp);
    ref_params(&pp);
    init_plant(&ref, &pp);
    robot_params(&pp);
    ros_params(&pp);
    init_plant(&plant, &pp);
    double dpos = 0.0, datt = 0.0, dten = 0.0, dtenf = 0.0, tpeak = 0.0;
    /* 10 ms moving averages of every winch-end tension (both runs) */
    static double hist_a[6][10], hist_b[6][10];
    memset(hist_a, 0, sizeof hist_a);
    memset(hist_b, 0, sizeof hist_b);
    unsigned long max_fac = 0, max_sol = 0, max_rhs = 0;
    for (int k = 0; k < 1500; ++k) {
        cdpr_real_t u[6];
        test_paper_rates_at(k, u);
        int f1 = 0, f2 = 0;
        TEST_ASSERT_TRUE(cdpr_plant_step(&ref, CDPR_WINCH_RATE, u, &f1) >= 0);
        TEST_ASSERT_TRUE(cdpr_plant_step(&plant, CDPR_WINCH_RATE, u, &f2) >= 0);
        cdpr_plant_meas_t a, b;
        cdpr_plant_measure(&ref, &a);
        cdpr_plant_measure(&plant, &b);
        dpos = fmax(dpos, (double)cdpr_v3_norm(cdpr_v3_sub(a.cabin.p_m, b.cabin.p_m)));
        datt = fmax(datt, test_cabin_angle(&a.cabin, &b.cabin));
        cdpr_robot_out_t oa, ob;
        cdpr_plant_outputs(&ref, &oa);
        cdpr_plant_outputs(&plant, &ob);
        for (int j = 0; j < 6; ++j) {
            tpeak = fmax(tpeak, fabs((double)oa.tension_winch_N[j]));
            dten = fmax(dten, fabs((double)oa.tension_winch_N[j] - (double)ob.tension_winch_N[j]));
            hist_a[j][k % 10] = (double)oa.tension_winch_N[j];
            hist_b[j][k % 10] = (double)ob.tension_winch_N[j];
            if (k >= 9) {
                double sa = 0.0, sb = 0.0;
                for (int m = 0; m < 10; ++m) {
                    sa += hist_a[j][m];
                    sb += hist_b[j][m];
                }
                dtenf = fmax(dtenf, fabs(sa - sb) / 10.0);
            }
        }
        max_fac =
            (plant.stats.last_factorisations > max_fac) ? plant.stats.last_factorisations : max_fac;
        max_sol = (plant.stats.last_solves > max_sol) ? plant.stats.last_solves : max_sol;
        max_rhs = (plant.stats.last_rhs_evals > max_rhs) ? plant.stats.last_rhs_evals : max_rhs;
    }
    char msg[200];
    (void)snprintf(msg, sizeof msg,
                   "dpos %.3e m datt %.3e rad; winch tension of peak %.1f N: %.3f %% raw, %.3f %% "
                   "10 ms mean",
                   dpos, datt, tpeak, 100.0 * dten / tpeak, 100.0 * dtenf / tpeak);
    TEST_MESSAGE(msg);
    TEST_ASSERT_TRUE_MESSAGE(dpos < 1e-3, msg);
    TEST_ASSERT_TRUE_MESSAGE(datt < 1e-3, msg);
    /* The raw tension carries the stiff axial vibration the L-stable step damps instead of
     * resolving (measured 1.6 % of the peak); its 10 ms mean is what the target bounds. */
    TEST_ASSERT_TRUE_MESSAGE(dtenf < 0.01 * tpeak, msg);
    TEST_ASSERT_TRUE_MESSAGE(dten < 0.01 * raw_pct * tpeak, msg);
    /* Work bound of a period: max_trials (3) trials of 1 factorisation, 4 solves, <= 4 RHS. */
    TEST_ASSERT_EQUAL_UINT(max_fac, plant.stats.max_factorisations);
    TEST_ASSERT_EQUAL_UINT(max_sol, plant.stats.max_solves);
    TEST_ASSERT_EQUAL_UINT(max_rhs, plant.stats.max_rhs_evals);
    TEST_ASSERT_TRUE(plant.stats.max_factorisations <= 3u);
    TEST_ASSERT_TRUE(plant.stats.max_solves <= 12u);
    TEST_ASSERT_TRUE(plant.stats.max_rhs_evals <= 12u);
    TEST_ASSERT_EQUAL_UINT(0u, plant.stats.step_failures);
    TEST_ASSERT_EQUAL_UINT(0u, ref.stats.max_factorisations); /* RKF45: no W */
}

static void test_implicit_follows_tight_reference(void)
{
    SKIP_IN_FLOAT("the rtol 1e-10 reference needs double");
    g_vtol = 1e-2;
    follow_tight_reference(3.0);
}

/* With the velocity tolerance at 1e-4 m/s (instead of 1e-2) the raw 1 kHz tension is within
 * 1 % of the peak too (measured 0.77 %, against 1.71 %), for the same work on this case
 * (4.04 RHS per period against 4.01; on the paper circle's snaps it costs more:
 * docs/validation.md §4a). */
static void test_implicit_raw_tension_at_a_tighter_velocity_tolerance(void)
{
    SKIP_IN_FLOAT("the rtol 1e-10 reference needs double");
    g_vtol = 1e-4;
    follow_tight_reference(1.0);
    g_vtol = 1e-2;
}

/* The same comparison across the rope damping users state (docs/model.md: 0.1 % for long
 * bridge stays to 2 % for stranded ropes, at 5 Hz): c = 127 N s and 2546 N s. More damping
 * makes the top axial modes overdamped (stiffer for RKF45, not for the L-stable method). */
static void test_implicit_follows_tight_reference_across_rope_damping(void)
{
    SKIP_IN_FLOAT("the rtol 1e-10 reference needs double");
    const double zetas[2] = {0.001, 0.02};
    for (int i = 0; i < 2; ++i) {
        g_zeta = zetas[i];
        g_vtol = 1e-2;
        follow_tight_reference(3.0);
    }
    g_zeta = 0.0;
}

/* Node events under the implicit scheme: the unstretched length changes by exactly the
 * integral of the applied rate, through insertions and removals (test_plant.c's case). */
static void test_node_events_conserve_length(void)
{
    cdpr_plant_params_t pp;
    robot_params(&pp);
    ros_params(&pp);
    pp.period_s = CDPR_R(0.01);
    pp.max_trials = 20;
#ifdef CDPR_REAL_IS_FLOAT
    pp.ros.step.rtol = CDPR_R(1e-3);
#endif
    init_plant(&plant, &pp);
    cdpr_plant_meas_t m0;
    cdpr_plant_measure(&plant, &m0);
    const cdpr_real_t rates[6] = {CDPR_R(3.0),  CDPR_R(0.0), CDPR_R(0.0),
                                  CDPR_R(-2.0), CDPR_R(0.0), CDPR_R(0.0)};
    double sum_u0 = 0.0;
    double sum_u3 = 0.0;
    for (int k = 0; k < 250; ++k) {
        int flags = 0;
        const cdpr_status_t st = cdpr_plant_step(&plant, CDPR_WINCH_RATE, rates, &flags);
        TEST_ASSERT_TRUE_MESSAGE(st >= 0, cdpr_status_str(st));
        sum_u0 += (double)plant.winch[0].u_m_per_s * (double)pp.period_s;
        sum_u3 += (double)plant.winch[3].u_m_per_s * (double)pp.period_s;
    }
    cdpr_plant_meas_t m1;
    cdpr_plant_measure(&plant, &m1);
    TEST_ASSERT_TRUE_MESSAGE(plant.nodes.insertions[0] >= 1u, "no insertion on cable 0");
    TEST_ASSERT_TRUE_MESSAGE(plant.nodes.removals[3] >= 1u, "no removal on cable 3");
    TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-9, 2e-4), sum_u0, (double)(m1.length_m[0] - m0.length_m[0]));
    TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-9, 2e-4), sum_u3, (double)(m1.length_m[3] - m0.length_m[3]));
    TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-9, 2e-4), 0.0, (double)(m1.length_m[1] - m0.length_m[1]));
    TEST_ASSERT_TRUE(plant.ros.lin.factorisations > 0u);
}

/* Reruns are bit-identical; stepping allocates nothing. */
static void test_reruns_bit_identical_no_allocation(void)
{
    static cdpr_real_t y1[CDPR_ROBOT_STATE_MAX];
    cdpr_plant_params_t pp;
    int dim1 = 0;
    for (int run = 0; run < 2; ++run) {
        robot_params(&pp);
        ros_params(&pp);
        init_plant(&plant, &pp);
        cdpr_alloc_reset();
        for (int k = 0; k < 200; ++k) {
            cdpr_real_t u[6];
            test_paper_rates_at(k, u);
            int flags = 0;
            TEST_ASSERT_TRUE(cdpr_plant_step(&plant, CDPR_WINCH_RATE, u, &flags) >= 0);
        }
        TEST_ASSERT_EQUAL_UINT(0u, cdpr_alloc_count());
        if (run == 0) {
            memcpy(y1, plant.y, sizeof y1);
            dim1 = plant.robot.dim;
        }
    }
    TEST_ASSERT_EQUAL_INT(dim1, plant.robot.dim);
    TEST_ASSERT_EQUAL_MEMORY(y1, plant.y, sizeof(cdpr_real_t) * (size_t)dim1);
}

/* ---------------------------------------------------------------- straight release */

#define REL_SEG 20
static cdpr_robot_t rel;
static cdpr_robot_w_t relw;
static cdpr_real_t ry[CDPR_ROBOT_STATE_MAX];
static cdpr_real_t rwork[CDPR_PLANT_WORK_PER_DIM * CDPR_ROBOT_STATE_MAX];

/* test_slack.c's case: one 100 m cable (EA 1e6 N, 1 kg/m, d 10 mm, c 5000 N s, drag) between
 * fixed ends 80 m apart, released from the chord at rest. */
static void build_release(void)
{
    cdpr_robot_params_t p;
    cdpr_robot_params_default(&p);
    p.mode = CDPR_CABIN_PRESCRIBED;
    p.n_cables = 1;
    cdpr_robot_cable_params_t *c = &p.cables[0];
    c->cable.ea_N = CDPR_R(1e6);
    c->cable.rho_kg_per_m = CDPR_R(1.0);
    c->cable.d0_m = CDPR_R(0.01);
    c->cable.damping_Ns = CDPR_R(5000.0);
    c->cable.cd = CDPR_R(1.2);
    c->cable.cm = CDPR_R(0.03);
    c->cable.rho_air_kg_per_m3 = CDPR_R(1.2);
    c->exit_point_m = cdpr_v3(CDPR_R(80.0), CDPR_R(0.0), CDPR_R(0.0));
    c->attach_body_m = cdpr_v3(CDPR_R(0.0), CDPR_R(0.0), CDPR_R(0.0));
    c->n_segments = REL_SEG;
    c->length_m = CDPR_R(100.0);
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_robot_init(&rel, &p, NULL));
    cdpr_cabin_motion_t m;
    memset(&m, 0, sizeof m);
    m.q.w = CDPR_R(1.0);
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_robot_place_straight(&rel, &m, ry));
}

/* Kinetic + elastic + gravitational energy of the released cable [J]. */
static double release_energy(void)
{
    const cdpr_cable_t *c = &rel.cable[0];
    const int nf = c->n - 1;
    const cdpr_real_t *pos = ry + rel.offset[0] + 1;
    const cdpr_real_t *vel = pos + 3 * nf;
    double e = 0.0;
    for (int i = 1; i <= nf; ++i) {
        const double m =
            0.5 * (double)c->p.rho_kg_per_m * ((double)c->lu_m[i - 1] + (double)c->lu_m[i]);
        const cdpr_real_t *v = vel + 3 * (i - 1);
        e += 0.5 * m * ((double)v[0] * v[0] + (double)v[1] * v[1] + (double)v[2] * v[2]);
        e += m * 9.80665 * (double)pos[3 * (i - 1) + 2];
    }
    for (int k = 0; k <= nf; ++k) {
        const double a[3] = {k == 0 ? 0.0 : (double)pos[3 * (k - 1)],
                             k == 0 ? 0.0 : (double)pos[3 * (k - 1) + 1],
                             k == 0 ? 0.0 : (double)pos[3 * (k - 1) + 2]};
        const double b[3] = {k == nf ? 80.0 : (double)pos[3 * k],
                             k == nf ? 0.0 : (double)pos[3 * k + 1],
                             k == nf ? 0.0 : (double)pos[3 * k + 2]};
        const double l = sqrt((b[0] - a[0]) * (b[0] - a[0]) + (b[1] - a[1]) * (b[1] - a[1]) +
                              (b[2] - a[2]) * (b[2] - a[2]));
        const double lu = (double)c->lu_m[k];
        const double eps = l / lu - 1.0;
        if (eps > 0.0) {
            e += 0.5 * (double)c->p.ea_N * lu * eps * eps;
        }
    }
    return e;
}

/* Mid-node trajectory every 0.1 s over 3 s: implicit (rtol 1e-6, node tolerances 1e-6 m and
 * 1e-4 m/s) vs RKF45 at rtol 1e-10; and the implicit run's energy never rises (damping and
 * drag only remove it) by more than its own error estimate allows. */
static void test_release_against_tight_reference_and_energy(void)
{
    SKIP_IN_FLOAT("the rtol 1e-10 reference needs double");
    static double mid_ref[30][3];
    build_release();
    {
        cdpr_rkf45_t rk;
        cdpr_rkf45_params_t sp;
        cdpr_rkf45_params_default(&sp);
        sp.step.rtol = CDPR_R(1e-10);
        sp.step.atol = CDPR_R(1e-12);
        sp.step.h_max_s = CDPR_R(0.01);
        sp.step.h_min_s = CDPR_R(1e-14);
        TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_rkf45_init(&rk, &sp, rwork,
                                                       (int)(sizeof rwork / sizeof rwork[0]),
                                                       CDPR_ROBOT_STATE_MAX, rel.dim, NULL));
        cdpr_real_t t = 0.0;
        for (int k = 0; k < 30; ++k) {
            while (t < 0.1 * (k + 1)) {
                TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_rkf45_step(&rk, cdpr_robot_rhs, &rel, &t, ry,
                                                               (cdpr_real_t)(0.1 * (k + 1))));
            }
            for (int a = 0; a < 3; ++a) {
                mid_ref[k][a] = (double)ry[rel.offset[0] + 1 + 3 * (REL_SEG / 2 - 1) + a];
            }
        }
    }
    build_release();
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_robot_w_init(&relw, &rel));
    cdpr_ros_t ros;
    cdpr_ros_params_t rp;
    cdpr_ros_params_default(&rp);
    rp.step.rtol = CDPR_R(1e-6);
    static cdpr_real_t atol[CDPR_ROBOT_STATE_MAX];
    cdpr_robot_fill_atol(&rel, CDPR_R(1e-6), CDPR_R(1e-5), CDPR_R(1e-8), CDPR_R(1e-6), atol);
    rp.step.atol_vec = atol;
    rp.step.h_max_s = CDPR_R(0.01);
    TEST_ASSERT_EQUAL_INT(CDPR_OK,
                          cdpr_ros_init(&ros, &rp, rwork, (int)(sizeof rwork / sizeof rwork[0]),
                                        CDPR_ROBOT_STATE_MAX, rel.dim, NULL));
    cdpr_ros_problem_t pb;
    pb.f = cdpr_robot_rhs;
    pb.f_ctx = &rel;
    pb.factor = cdpr_robot_w_factor;
    pb.solve = cdpr_robot_w_solve;
    pb.lin_ctx = &relw;
    cdpr_real_t t = 0.0;
    double dmax = 0.0;
    double e_prev = release_energy();
    double rise_max = 0.0;
    for (int k = 0; k < 30; ++k) {
        while (t < 0.1 * (k + 1)) {
            TEST_ASSERT_EQUAL_INT(CDPR_OK,
                                  cdpr_ros_step(&ros, &pb, &t, ry, (cdpr_real_t)(0.1 * (k + 1))));
            const double e = release_energy();
            rise_max = fmax(rise_max, e - e_prev);
            e_prev = e;
        }
        for (int a = 0; a < 3; ++a) {
            dmax = fmax(dmax, fabs(mid_ref[k][a] -
                                   (double)ry[rel.offset[0] + 1 + 3 * (REL_SEG / 2 - 1) + a]));
        }
    }
    char msg[160];
    (void)snprintf(
        msg, sizeof msg,
        "mid node %.3e m from the RKF45 reference, %lu implicit steps, energy rise max %.3e J",
        dmax, ros.stats.steps_accepted, rise_max);
    TEST_MESSAGE(msg);
    TEST_ASSERT_TRUE_MESSAGE(dmax < 1e-3, msg);
    /* Energy estimate: an accepted step changes each velocity by at most its tolerance
     * (1e-4 + 1e-6 |v|) beyond the exact solution, i.e. the kinetic energy by at most
     * sum m |v| dv ~ 100 kg x 10 m/s x 1e-4 m/s = 0.1 J per step; the elastic and potential
     * terms by EA/lu eps dl and m g dz with dl, dz <= 1e-6 m: below 0.1 J. */
    TEST_ASSERT_TRUE_MESSAGE(rise_max < 0.2, msg);
}

/* cdpr_plant_work reports the scheme's own counters (rkf45.h, ros34pw2.h), whichever the scheme:
 * RKF45 has no factorisations or solves. */
static void test_work_is_the_integrators_counters(void)
{
    static const cdpr_plant_integrator_t schemes[3] = {CDPR_PLANT_RKF45, CDPR_PLANT_ROS34PW2,
                                                       CDPR_PLANT_ROS34PW2_FIXED};
    for (int s = 0; s < 3; ++s) {
        cdpr_plant_params_t pp;
        robot_params(&pp);
        if (schemes[s] != CDPR_PLANT_RKF45) {
            ros_params(&pp);
        }
        pp.integrator = schemes[s];
        init_plant(&plant, &pp);
        for (int k = 0; k < 20; ++k) {
            cdpr_real_t u[6];
            test_paper_rates_at(k, u);
            int flags = 0;
            TEST_ASSERT_TRUE(cdpr_plant_step(&plant, CDPR_WINCH_RATE, u, &flags) >= 0);
        }
        cdpr_plant_work_t w;
        cdpr_plant_work(&plant, &w);
        TEST_ASSERT_EQUAL_INT((int)schemes[s], (int)w.integrator);
        TEST_ASSERT_TRUE(w.rhs_evals > 0u);
        if (schemes[s] == CDPR_PLANT_RKF45) {
            TEST_ASSERT_EQUAL_UINT32(plant.rk.stats.steps_accepted, w.steps_accepted);
            TEST_ASSERT_EQUAL_UINT32(plant.rk.stats.steps_rejected, w.steps_rejected);
            TEST_ASSERT_EQUAL_UINT32(plant.rk.stats.rhs_evals, w.rhs_evals);
            TEST_ASSERT_EQUAL_UINT32(0u, w.factorisations + w.solves);
        } else {
            TEST_ASSERT_EQUAL_UINT32(plant.ros.stats.steps_accepted, w.steps_accepted);
            TEST_ASSERT_EQUAL_UINT32(plant.ros.stats.steps_rejected, w.steps_rejected);
            TEST_ASSERT_EQUAL_UINT32(plant.ros.stats.rhs_evals, w.rhs_evals);
            TEST_ASSERT_EQUAL_UINT32(plant.ros.lin.factorisations, w.factorisations);
            TEST_ASSERT_EQUAL_UINT32(plant.ros.lin.solves, w.solves);
            TEST_ASSERT_TRUE(w.factorisations > 0u && w.solves >= w.factorisations);
        }
    }
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_work_is_the_integrators_counters);
    RUN_TEST(test_implicit_follows_tight_reference);
    RUN_TEST(test_implicit_raw_tension_at_a_tighter_velocity_tolerance);
    RUN_TEST(test_implicit_follows_tight_reference_across_rope_damping);
    RUN_TEST(test_node_events_conserve_length);
    RUN_TEST(test_reruns_bit_identical_no_allocation);
    RUN_TEST(test_release_against_tight_reference_and_energy);
    return UNITY_END() ? 1 : 0;
}
