/* SPDX-License-Identifier: BSD-3-Clause */
/// @file test_plant_fixed.c
/// The plant's fixed-cost mode (CDPR_PLANT_ROS34PW2_FIXED, plant.h "Fixed-cost stepping"):
/// - the work of every period is the same (4 n RHS, n factorisations, 4 n solves), through node
///   insertions and removals, at 8, 16 and 32 segments per cable;
/// - against an independent reference (RKF45 at rtol 1e-10 of the same plant and commands) it
///   is at least as close as the adaptive real-time setting (ROS34PW2, at most 3 trials, the
///   settings of test_plant_ros.c), on the cabin pose and the 10 ms mean winch tension;
/// - the derived n is the smallest with h ω_max <= CDPR_PLANT_FIXED_H_OMEGA, ω_max computed
///   here from the rope and winch data; fewer substeps, a period that hauls a half-segment in,
///   and substeps outside [0, 64] are refused with the field named and the derived n given;
/// - a period whose substep is not finite is refused, the plant bit-identical, counted.
#include <math.h>
#include <string.h>

#include "cdpr/plant.h"
#include "paper_plant.h"
#include "test_real.h"
#include "unity.h"

void setUp(void) {}
void tearDown(void) {}

static cdpr_plant_t fixed;
static cdpr_plant_t adaptive;
static cdpr_plant_t ref;

static void init_plant(cdpr_plant_t *p, const cdpr_plant_params_t *pp)
{
    cdpr_diag_t d;
    const cdpr_status_t st = cdpr_plant_init(p, pp, &d);
    TEST_ASSERT_EQUAL_INT_MESSAGE(CDPR_OK, st, d.field);
}

/* The adaptive real-time setting of test_plant_ros.c and the docs (3 trials, loose node
 * tolerances), and the fixed mode with the same tolerances (they only weigh its error norm). */
static void rt_params(cdpr_plant_params_t *pp, int segments, cdpr_plant_integrator_t m)
{
    test_paper_plant_params(pp, segments);
    test_paper_rt_params(pp, m, 1e-2);
}

/* ω_max of plant.h computed here from the parameters: the rope's wave speed, the nominal
 * segment length of each cable (unstretched length / segments) and the shortest pulley-side
 * segment a period can leave. */
static double omega_max(const cdpr_plant_t *p)
{
    double om = 0.0;
    for (int j = 0; j < p->params.n_cables; ++j) {
        const cdpr_robot_cable_params_t *c = &p->params.cables[j];
        const double delta = (double)c->length_m / (double)c->n_segments;
        const double b =
            0.5 * delta - (double)p->pp.winch[j].u_max_m_per_s * (double)p->pp.period_s;
        om = fmax(om, 2.0 * sqrt((double)c->cable.ea_N / (double)c->cable.rho_kg_per_m) /
                          sqrt(delta * b));
    }
    return om;
}

/* Every period of a run with node events costs exactly the same; n as derived. */
static void test_fixed_work_identical_every_period(void)
{
    const int segs[3] = {8, 16, 32};
    for (int s = 0; s < 3; ++s) {
        cdpr_plant_params_t pp;
        rt_params(&pp, segs[s], CDPR_PLANT_ROS34PW2_FIXED);
        pp.period_s = CDPR_R(0.002);
        init_plant(&fixed, &pp);
        const int n = fixed.substeps;
        const double hw = (double)pp.period_s * omega_max(&fixed);
        char msg[160];
        (void)snprintf(msg, sizeof msg, "%d segments: n = %d, period x omega_max = %.3f", segs[s],
                       n, hw);
        TEST_MESSAGE(msg);
        TEST_ASSERT_TRUE_MESSAGE(hw / n <= CDPR_PLANT_FIXED_H_OMEGA * (1.0 + 1e-6), msg);
        TEST_ASSERT_TRUE_MESSAGE(n == 1 || hw / (n - 1) > CDPR_PLANT_FIXED_H_OMEGA, msg);
        /* Strong payout on cable 0 and haul-in on cable 3: nodes come and go. */
        const cdpr_real_t rates[6] = {CDPR_R(3.0),  CDPR_R(0.0), CDPR_R(0.0),
                                      CDPR_R(-2.0), CDPR_R(0.0), CDPR_R(0.0)};
        for (int k = 0;
             k < 3000 && (fixed.nodes.insertions[0] < 2u || fixed.nodes.removals[3] < 2u); ++k) {
            int flags = 0;
            const cdpr_status_t st = cdpr_plant_step(&fixed, CDPR_WINCH_RATE, rates, &flags);
            TEST_ASSERT_TRUE_MESSAGE(st >= 0, cdpr_status_str(st));
            TEST_ASSERT_EQUAL_UINT_MESSAGE(4u * (unsigned)n, fixed.stats.last_rhs_evals, msg);
            TEST_ASSERT_EQUAL_UINT_MESSAGE((unsigned)n, fixed.stats.last_factorisations, msg);
            TEST_ASSERT_EQUAL_UINT_MESSAGE(4u * (unsigned)n, fixed.stats.last_solves, msg);
        }
        TEST_ASSERT_TRUE_MESSAGE(fixed.nodes.insertions[0] >= 2u, "no insertions on cable 0");
        TEST_ASSERT_TRUE_MESSAGE(fixed.nodes.removals[3] >= 2u, "no removals on cable 3");
        TEST_ASSERT_EQUAL_UINT(4u * (unsigned)n, fixed.stats.max_rhs_evals);
        TEST_ASSERT_EQUAL_UINT(0u, fixed.stats.step_failures);
    }
}

/* Largest deviations of one run from the reference. */
typedef struct {
    double pos_m;
    double att_rad;
    double tension_mean_N; /* 10 ms moving mean of the winch-end tension */
    double hist[6][10];
    double hist_ref[6][10];
} deviation_t;

static void deviate(deviation_t *d, int k, const cdpr_plant_t *p)
{
    cdpr_plant_meas_t a, b;
    cdpr_plant_measure(&ref, &a);
    cdpr_plant_measure(p, &b);
    d->pos_m = fmax(d->pos_m, (double)cdpr_v3_norm(cdpr_v3_sub(a.cabin.p_m, b.cabin.p_m)));
    d->att_rad = fmax(d->att_rad, test_cabin_angle(&a.cabin, &b.cabin));
    for (int j = 0; j < 6; ++j) {
        d->hist_ref[j][k % 10] = (double)a.tension_winch_N[j];
        d->hist[j][k % 10] = (double)b.tension_winch_N[j];
        if (k >= 9) {
            double sa = 0.0, sb = 0.0;
            for (int m = 0; m < 10; ++m) {
                sa += d->hist_ref[j][m];
                sb += d->hist[j][m];
            }
            d->tension_mean_N = fmax(d->tension_mean_N, fabs(sa - sb) / 10.0);
        }
    }
}

/* 1.5 s of the payout profiles of test_plant_ros.c at 1 kHz, 16 segments: both real-time
 * settings against the tight reference, every period. */
static void test_fixed_at_least_as_close_as_adaptive(void)
{
    SKIP_IN_FLOAT("the rtol 1e-10 reference needs double");
    cdpr_plant_params_t pp;
    test_paper_plant_params(&pp, 16);
    pp.integrator = CDPR_PLANT_RKF45;
    pp.rkf45.step.rtol = CDPR_R(1e-10);
    pp.atol.position_m = CDPR_R(1e-10);
    pp.atol.velocity_m_per_s = CDPR_R(1e-9);
    pp.atol.quaternion = CDPR_R(1e-12);
    pp.atol.rate_rad_per_s = CDPR_R(1e-10);
    pp.period_s = CDPR_R(0.001);
    pp.max_trials = 100000;
    init_plant(&ref, &pp);
    rt_params(&pp, 16, CDPR_PLANT_ROS34PW2_FIXED);
    init_plant(&fixed, &pp);
    rt_params(&pp, 16, CDPR_PLANT_ROS34PW2);
    init_plant(&adaptive, &pp);
    static deviation_t df, da;
    memset(&df, 0, sizeof df);
    memset(&da, 0, sizeof da);
    for (int k = 0; k < 1500; ++k) {
        cdpr_real_t u[6];
        test_paper_rates_at(k, u);
        int f = 0;
        TEST_ASSERT_TRUE(cdpr_plant_step(&ref, CDPR_WINCH_RATE, u, &f) >= 0);
        TEST_ASSERT_TRUE(cdpr_plant_step(&fixed, CDPR_WINCH_RATE, u, &f) >= 0);
        TEST_ASSERT_TRUE(cdpr_plant_step(&adaptive, CDPR_WINCH_RATE, u, &f) >= 0);
        deviate(&df, k, &fixed);
        deviate(&da, k, &adaptive);
    }
    char msg[300];
    (void)snprintf(msg, sizeof msg,
                   "fixed (n = %d): %.3e m, %.3e rad, %.3f N; adaptive: %.3e m, %.3e rad, %.3f N "
                   "(cabin position, attitude, 10 ms mean winch tension); fixed error norm max "
                   "%.3g, above 1 in %lu periods",
                   fixed.substeps, df.pos_m, df.att_rad, df.tension_mean_N, da.pos_m, da.att_rad,
                   da.tension_mean_N, (double)fixed.stats.max_err_norm,
                   fixed.stats.err_above_one_periods);
    TEST_MESSAGE(msg);
    TEST_ASSERT_TRUE_MESSAGE(df.pos_m <= da.pos_m, msg);
    TEST_ASSERT_TRUE_MESSAGE(df.att_rad <= da.att_rad, msg);
    TEST_ASSERT_TRUE_MESSAGE(df.tension_mean_N <= da.tension_mean_N, msg);
    TEST_ASSERT_EQUAL_UINT(0u, fixed.stats.step_failures);
}

/* Refusals at init: the field named and the derived n given; nothing settled. */
static void test_fixed_refuses_too_few_substeps_and_long_periods(void)
{
    cdpr_plant_params_t pp;
    rt_params(&pp, 16, CDPR_PLANT_ROS34PW2_FIXED);
    init_plant(&fixed, &pp);
    const int need = fixed.substeps;
    TEST_ASSERT_TRUE(need >= 2);
    cdpr_diag_t d;
    pp.substeps = need - 1;
    fixed.settle.steps = -1;
    TEST_ASSERT_EQUAL_INT(CDPR_E_OUT_OF_RANGE, cdpr_plant_init(&fixed, &pp, &d));
    TEST_ASSERT_EQUAL_STRING("substeps", d.field);
    TEST_ASSERT_EQUAL_INT(need, d.index);
    TEST_ASSERT_EQUAL_INT(0, fixed.ready);
    TEST_ASSERT_EQUAL_INT(-1L, fixed.settle.steps); /* refused before the settling */
    pp.substeps = need + 3;                         /* more is allowed */
    init_plant(&fixed, &pp);
    TEST_ASSERT_EQUAL_INT(need + 3, fixed.substeps);
    pp.substeps = -1;
    TEST_ASSERT_EQUAL_INT(CDPR_E_OUT_OF_RANGE, cdpr_plant_init(&fixed, &pp, &d));
    TEST_ASSERT_EQUAL_STRING("substeps", d.field);
    pp.substeps = CDPR_PLANT_MAX_SUBSTEPS + 1;
    TEST_ASSERT_EQUAL_INT(CDPR_E_OUT_OF_RANGE, cdpr_plant_init(&fixed, &pp, &d));
    TEST_ASSERT_EQUAL_STRING("substeps", d.field);
    /* 0.5 s at 4 m/s hauls in 2 m, more than half a ~2 m segment: no substep count holds. */
    pp.substeps = 0;
    pp.period_s = CDPR_R(0.5);
    TEST_ASSERT_EQUAL_INT(CDPR_E_OUT_OF_RANGE, cdpr_plant_init(&fixed, &pp, &d));
    TEST_ASSERT_EQUAL_STRING("substeps", d.field);
    TEST_ASSERT_EQUAL_INT(-1, d.index); /* no count holds: no count to name */
    /* 100 ms at 32 segments would need more than 64 substeps. */
    rt_params(&pp, 32, CDPR_PLANT_ROS34PW2_FIXED);
    pp.period_s = CDPR_R(0.1);
    TEST_ASSERT_EQUAL_INT(CDPR_E_OUT_OF_RANGE, cdpr_plant_init(&fixed, &pp, &d));
    TEST_ASSERT_EQUAL_STRING("substeps", d.field);
    /* The other schemes ignore substeps. */
    rt_params(&pp, 16, CDPR_PLANT_ROS34PW2);
    pp.substeps = 1;
    init_plant(&adaptive, &pp);
    TEST_ASSERT_EQUAL_INT(0, adaptive.substeps);
}

/* A substep that is not finite: the period is refused, the plant bit-identical, counted. */
static void test_fixed_nonfinite_period_refused_state_kept(void)
{
    cdpr_plant_params_t pp;
    rt_params(&pp, 8, CDPR_PLANT_ROS34PW2_FIXED);
    init_plant(&fixed, &pp);
    const cdpr_real_t u[6] = {CDPR_R(0.1), CDPR_R(0.0), CDPR_R(0.0),
                              CDPR_R(0.0), CDPR_R(0.0), CDPR_R(0.0)};
    int flags = 0;
    TEST_ASSERT_TRUE(cdpr_plant_step(&fixed, CDPR_WINCH_RATE, u, &flags) >= 0);
    static cdpr_real_t y0[CDPR_ROBOT_STATE_MAX];
    memcpy(y0, fixed.y, sizeof y0);
    const long k0 = fixed.k;
    const cdpr_real_t e0 = fixed.stats.last_err_norm;
    fixed.robot.in.wind_m_per_s.x = (cdpr_real_t)NAN_R; /* the drag turns NaN */
    TEST_ASSERT_EQUAL_INT(CDPR_E_STATE_NOT_FINITE,
                          cdpr_plant_step(&fixed, CDPR_WINCH_RATE, u, &flags));
    TEST_ASSERT_EQUAL_INT(CDPR_PLANT_STEP_FAILED, flags);
    TEST_ASSERT_EQUAL_MEMORY(y0, fixed.y, sizeof y0);
    TEST_ASSERT_EQUAL_INT(k0, fixed.k);
    TEST_ASSERT_EQUAL_UINT(1u, fixed.stats.step_failures);
    TEST_ASSERT_EQUAL_INT(CDPR_E_STATE_NOT_FINITE, fixed.stats.last_failure);
    TEST_ASSERT_EQUAL_UINT(1u, fixed.ros.stats.nonfinite_rejected);
    TEST_ASSERT_EQUAL_MEMORY(&e0, &fixed.stats.last_err_norm, sizeof e0); /* never published */
    /* The input restored, the plant goes on from the kept state. */
    fixed.robot.in.wind_m_per_s.x = CDPR_R(0.0);
    TEST_ASSERT_TRUE(cdpr_plant_step(&fixed, CDPR_WINCH_RATE, u, &flags) >= 0);
    TEST_ASSERT_EQUAL_INT(k0 + 1, fixed.k);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_fixed_work_identical_every_period);
    RUN_TEST(test_fixed_at_least_as_close_as_adaptive);
    RUN_TEST(test_fixed_refuses_too_few_substeps_and_long_periods);
    RUN_TEST(test_fixed_nonfinite_period_refused_state_kept);
    return UNITY_END() ? 1 : 0;
}
