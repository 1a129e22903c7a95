/* SPDX-License-Identifier: BSD-3-Clause */
/// @file test_fixed_mode.c
/// The fixed-cost mode from a scenario (integrator.method ros34pw2-fixed, integrator.substeps;
/// docs/scenarios.md): the paper circle at 1 kHz with 16, 32 and 64 segments per cable runs
/// with the same work in every period (the most RHS calls of a period times the periods equals
/// the total, and both are 4 n per period), the summary says so; a substep count below the
/// derived one, 0, or not whole is refused naming integrator.substeps and the count needed;
/// on the four shipped cases (paper circle and line, deploy-retrieve, the example rig), one
/// second at 1 kHz under the scenario's controller, the fixed mode is at least as close to an
/// RKF45 rtol 1e-10 reference as the adaptive real-time setting (cabin position, attitude,
/// 10 ms mean winch tension).
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>

#include "cdpr/host/plant.h"
#include "cdpr/host/scenario.h"
#include "cdpr/host/sim.h"
#include "unity.h"

void setUp(void) {}
void tearDown(void) {}

#define CIRCLE CDPR_SOURCE_DIR "/scenarios/paper-circle.yaml"

static cdpr_scenario_t g_sc;

/* The paper circle with `segments` per cable at 1 kHz in the fixed mode, for `duration` s. */
static void load_circle(int segments, double duration)
{
    cdpr_scenario_error_t err;
    TEST_ASSERT_EQUAL_INT_MESSAGE(CDPR_OK, cdpr_scenario_load(CIRCLE, &g_sc, &err), err.msg);
    for (int j = 0; j < g_sc.rig.n_cables; ++j) {
        g_sc.rig.cable[j].segments = segments;
    }
    cdpr_scenario_overrides_t ov;
    cdpr_scenario_overrides_none(&ov);
    ov.rate_hz = 1000.0;
    ov.duration_s = duration;
    ov.method = (int)CDPR_PLANT_ROS34PW2_FIXED;
    TEST_ASSERT_EQUAL_INT_MESSAGE(CDPR_OK, cdpr_scenario_override(&g_sc, &ov, "test", NULL, &err),
                                  err.msg);
}

static void test_circle_same_work_every_period(void)
{
    const int segs[3] = {16, 32, 64};
    mkdir(CDPR_TEST_TMP, 0775);
    for (int i = 0; i < 3; ++i) {
        /* 0.3 s: past the start of the circle, where the cables first go slack at 64. */
        load_circle(segs[i], 0.3);
        cdpr_sim_opts_t o;
        cdpr_sim_opts_default(&o);
        o.out_dir = CDPR_TEST_TMP;
        static cdpr_summary_t sum;
        cdpr_scenario_error_t err;
        TEST_ASSERT_EQUAL_INT_MESSAGE(CDPR_OK, cdpr_sim_run(&g_sc, &o, &sum, &err), err.msg);
        char msg[200];
        (void)snprintf(msg, sizeof msg,
                       "6 x %d: %d substeps, %lu RHS in %ld periods, most %lu; error norm max "
                       "%.3g, above 1 in %lu periods",
                       segs[i], sum.substeps, sum.rhs_evals, sum.periods, sum.max_rhs_per_period,
                       sum.max_err_norm, sum.err_above_one_periods);
        TEST_MESSAGE(msg);
        TEST_ASSERT_EQUAL_INT_MESSAGE(CDPR_SUMMARY_OK, sum.status, sum.message);
        TEST_ASSERT_EQUAL_INT_MESSAGE(300, sum.periods, msg);
        TEST_ASSERT_TRUE_MESSAGE(sum.substeps >= 1, msg);
        TEST_ASSERT_EQUAL_UINT_MESSAGE(4UL * (unsigned long)sum.substeps, sum.max_rhs_per_period,
                                       msg);
        TEST_ASSERT_EQUAL_UINT_MESSAGE(sum.max_rhs_per_period * (unsigned long)sum.periods,
                                       sum.rhs_evals, msg);
        TEST_ASSERT_EQUAL_UINT_MESSAGE((unsigned long)sum.substeps * (unsigned long)sum.periods,
                                       sum.steps_accepted, msg);
        TEST_ASSERT_EQUAL_UINT(0UL, sum.steps_rejected);
        /* The summary file says the same. */
        static cdpr_summary_t back;
        TEST_ASSERT_EQUAL_INT(CDPR_OK,
                              cdpr_summary_read(CDPR_TEST_TMP "/summary.json", &back, &err));
        TEST_ASSERT_EQUAL_INT(sum.substeps, back.substeps);
        TEST_ASSERT_EQUAL_UINT(sum.max_rhs_per_period, back.max_rhs_per_period);
        TEST_ASSERT_EQUAL_DOUBLE(sum.max_err_norm, back.max_err_norm);
        TEST_ASSERT_EQUAL_UINT(sum.err_above_one_periods, back.err_above_one_periods);
    }
}

/* ------------------------------------------ accuracy on the four shipped cases (issue 20) */

/* Largest deviations of a plant from the reference over a run. */
typedef struct {
    double pos_m;
    double att_rad;
    double tension_N;                /* 10 ms moving mean of every winch-end tension */
    double sum[CDPR_MAX_CABLES];     /* the run's 10-period window sums */
    double sum_ref[CDPR_MAX_CABLES]; /* ... of the reference */
    double win[10][CDPR_MAX_CABLES];
    double win_ref[10][CDPR_MAX_CABLES];
} dev_t10;

/* Rotation angle of a^-1 b [rad]. */
static double angle_between(const cdpr_quat_t *a, const cdpr_quat_t *b)
{
    const double d = fabs((double)a->w * (double)b->w + (double)a->x * (double)b->x +
                          (double)a->y * (double)b->y + (double)a->z * (double)b->z);
    return 2.0 * acos(fmin(1.0, d));
}

static void deviation(dev_t10 *d, long k, int nc, const cdpr_plant_meas_t *r,
                      const cdpr_plant_meas_t *m)
{
    const double dx = (double)(m->cabin.p_m.x - r->cabin.p_m.x);
    const double dy = (double)(m->cabin.p_m.y - r->cabin.p_m.y);
    const double dz = (double)(m->cabin.p_m.z - r->cabin.p_m.z);
    d->pos_m = fmax(d->pos_m, sqrt(dx * dx + dy * dy + dz * dz));
    d->att_rad = fmax(d->att_rad, angle_between(&r->cabin.q, &m->cabin.q));
    const long slot = k % 10;
    for (int j = 0; j < nc; ++j) {
        d->sum[j] += (double)m->tension_winch_N[j] - d->win[slot][j];
        d->sum_ref[j] += (double)r->tension_winch_N[j] - d->win_ref[slot][j];
        d->win[slot][j] = (double)m->tension_winch_N[j];
        d->win_ref[slot][j] = (double)r->tension_winch_N[j];
        if (k >= 9) {
            d->tension_N = fmax(d->tension_N, fabs(d->sum[j] - d->sum_ref[j]) / 10.0);
        }
    }
}

/* The plant parameters of `name` at 1 kHz with integrator `method` (-1: the file's, RKF45). */
static void case_params(const char *name, int method, cdpr_plant_params_t *pp)
{
    char path[600];
    (void)snprintf(path, sizeof path, "%s/scenarios/%s.yaml", CDPR_SOURCE_DIR, name);
    cdpr_scenario_error_t err;
    TEST_ASSERT_EQUAL_INT_MESSAGE(CDPR_OK, cdpr_scenario_load(path, &g_sc, &err), err.msg);
    cdpr_scenario_overrides_t ov;
    cdpr_scenario_overrides_none(&ov);
    ov.rate_hz = 1000.0;
    ov.duration_s = 1.0;
    ov.method = method;
    TEST_ASSERT_EQUAL_INT_MESSAGE(CDPR_OK, cdpr_scenario_override(&g_sc, &ov, "test", NULL, &err),
                                  err.msg);
    TEST_ASSERT_EQUAL_INT_MESSAGE(CDPR_OK, cdpr_host_plant_params(&g_sc, pp, &err), err.msg);
}

static cdpr_plant_t g_ref;
static cdpr_plant_t g_fix;
static cdpr_plant_t g_ada;
static cdpr_tracker_t g_ctl;

static void init_or_fail(cdpr_plant_t *p, const cdpr_plant_params_t *pp)
{
    cdpr_diag_t d;
    const cdpr_status_t st = cdpr_plant_init(p, pp, &d);
    TEST_ASSERT_EQUAL_INT_MESSAGE(CDPR_OK, st, (d.field != NULL) ? d.field : cdpr_status_str(st));
}

/* One second of `name` at 1 kHz: the scenario's controller closes the loop on an RKF45
 * reference at rtol 1e-10; the fixed mode and the adaptive real-time setting (below) get the
 * same commands from the same settled start. The fixed mode must be
 * at least as close to the reference as the adaptive one in cabin position, attitude and 10 ms
 * mean winch tension. */
static void accuracy_case(const char *name)
{
    cdpr_plant_params_t pp;
    case_params(name, (int)CDPR_PLANT_ROS34PW2_FIXED, &pp);
    init_or_fail(&g_fix, &pp);
    /* The adaptive real-time setting (the ros34pw2 sections of the paper scenarios, and
     * docs/performance.md "Which integrator to ship"), for every case: files without such a
     * section would otherwise give ROS34PW2 their RKF45 tolerances and 2000 trials, no
     * real-time setting at all. */
    case_params(name, (int)CDPR_PLANT_ROS34PW2, &pp);
    pp.ros.step.rtol = 1e-3;
    pp.atol.position_m = 1e-4;
    pp.atol.velocity_m_per_s = 1e-2;
    pp.atol.quaternion = 1e-6;
    pp.atol.rate_rad_per_s = 1e-4;
    pp.max_trials = 4;
    init_or_fail(&g_ada, &pp);
    case_params(name, (int)CDPR_PLANT_RKF45, &pp);
    pp.rkf45.step.rtol = 1e-10;
    pp.atol.position_m = 1e-10;
    pp.atol.velocity_m_per_s = 1e-9;
    pp.atol.quaternion = 1e-12;
    pp.atol.rate_rad_per_s = 1e-10;
    pp.max_trials = 1000000;
    init_or_fail(&g_ref, &pp);
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_tracker_init(&g_ctl, &g_ref.params, &g_sc.traj, &g_sc.gains,
                                                     g_sc.period_s, 0.0, NULL));
    /* The same settled start (the settling does not depend on the scheme). */
    TEST_ASSERT_EQUAL_MEMORY(g_ref.y, g_fix.y, sizeof(double) * (size_t)g_ref.robot.dim);
    TEST_ASSERT_EQUAL_MEMORY(g_ref.y, g_ada.y, sizeof(double) * (size_t)g_ref.robot.dim);
    static dev_t10 df;
    static dev_t10 da;
    memset(&df, 0, sizeof df);
    memset(&da, 0, sizeof da);
    const int nc = g_ref.params.n_cables;
    const long periods = lround(g_sc.duration_s / g_sc.period_s);
    for (long k = 0; k < periods; ++k) {
        cdpr_plant_meas_t r, f, a;
        cdpr_plant_measure(&g_ref, &r);
        cdpr_plant_measure(&g_fix, &f);
        cdpr_plant_measure(&g_ada, &a);
        deviation(&df, k, nc, &r, &f);
        deviation(&da, k, nc, &r, &a);
        cdpr_tracker_cmd_t c;
        TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_tracker_step(&g_ctl, &r, &c));
        int fl = 0;
        TEST_ASSERT_TRUE(cdpr_plant_step(&g_ref, CDPR_WINCH_RATE, c.rate_m_per_s, &fl) >= 0);
        TEST_ASSERT_TRUE(cdpr_plant_step(&g_fix, CDPR_WINCH_RATE, c.rate_m_per_s, &fl) >= 0);
        TEST_ASSERT_TRUE(cdpr_plant_step(&g_ada, CDPR_WINCH_RATE, c.rate_m_per_s, &fl) >= 0);
    }
    char msg[400];
    (void)snprintf(msg, sizeof msg,
                   "%s, 1 s at 1 kHz: fixed (%d substeps) %.3e m, %.3e rad, %.4f N; adaptive "
                   "%.3e m, %.3e rad, %.4f N (cabin position, attitude, 10 ms mean winch "
                   "tension; node events %lu/%lu)",
                   name, g_fix.substeps, df.pos_m, df.att_rad, df.tension_N, da.pos_m, da.att_rad,
                   da.tension_N, g_ref.nodes.insertions[0] + g_ref.nodes.insertions[1],
                   g_ref.nodes.removals[0] + g_ref.nodes.removals[1]);
    TEST_MESSAGE(msg);
    TEST_ASSERT_EQUAL_UINT_MESSAGE(0u, g_fix.stats.step_failures, msg);
    TEST_ASSERT_TRUE_MESSAGE(df.pos_m <= da.pos_m, msg);
    TEST_ASSERT_TRUE_MESSAGE(df.att_rad <= da.att_rad, msg);
    TEST_ASSERT_TRUE_MESSAGE(df.tension_N <= da.tension_N, msg);
}

static void test_fixed_at_least_as_close_as_adaptive_on_the_four_cases(void)
{
    static const char *const cases[4] = {"paper-circle", "paper-line", "deploy-retrieve",
                                         "example-rig-circle"};
    for (int i = 0; i < 4; ++i) {
        accuracy_case(cases[i]);
    }
}

/* integrator.substeps below the derived count: refused at init with the key and the count. */
static void test_too_few_substeps_refused_with_the_count_needed(void)
{
    load_circle(32, 0.1);
    static cdpr_plant_t plant;
    cdpr_scenario_error_t err;
    TEST_ASSERT_EQUAL_INT_MESSAGE(CDPR_OK, cdpr_host_plant_model(&plant, &g_sc, &err), err.msg);
    int need = 0;
    cdpr_plant_params_t pp;
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_host_plant_params(&g_sc, &pp, &err));
    TEST_ASSERT_EQUAL_INT(
        CDPR_OK, cdpr_plant_fixed_substeps(&plant.robot, pp.winch, pp.period_s, &need, NULL));
    TEST_ASSERT_TRUE(need >= 2);
    g_sc.integrator.substeps = need - 1;
    TEST_ASSERT_EQUAL_INT(CDPR_E_OUT_OF_RANGE, cdpr_host_plant_init(&plant, &g_sc, NULL, &err));
    char want[96];
    (void)snprintf(want, sizeof want, "needs: at least %d at period 0.001 s", need);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err.msg, "integrator.substeps: "), err.msg);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err.msg, want), err.msg);
    /* A period the fixed mode cannot hold at all: 0.1 s at 64 segments. */
    load_circle(64, 0.2);
    g_sc.period_s = 0.1;
    TEST_ASSERT_EQUAL_INT(CDPR_E_OUT_OF_RANGE, cdpr_host_plant_init(&plant, &g_sc, NULL, &err));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err.msg, "integrator.substeps: the fixed mode cannot"),
                                 err.msg);
}

/* In the file: 0, a fraction and a count above 64 are refused by the loader. */
static void test_substeps_key_strict(void)
{
    static const char *const bad[3] = {"0", "2.5", "65"};
    mkdir(CDPR_TEST_TMP, 0775);
    for (int i = 0; i < 3; ++i) {
        char path[600];
        (void)snprintf(path, sizeof path, "%s/fixed-%d.yaml", CDPR_TEST_TMP, i);
        FILE *f = fopen(path, "w");
        TEST_ASSERT_NOT_NULL(f);
        fprintf(f,
                "robot: {preset: paper-50m, segments: 8}\n"
                "trajectory: {type: hold, hold: {pose: [0, 0, 9.135, 0, 0, 0]}}\n"
                "controller: {kp: 0.0, k_length_per_s: 5.0}\n"
                "integrator: {method: ros34pw2-fixed, substeps: %s}\n"
                "run: {duration_s: 0.1, period_s: 0.001}\n",
                bad[i]);
        fclose(f);
        cdpr_scenario_error_t err;
        TEST_ASSERT_EQUAL_INT_MESSAGE(CDPR_E_OUT_OF_RANGE, cdpr_scenario_load(path, &g_sc, &err),
                                      err.msg);
        TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err.msg, ":4: integrator.substeps: "), err.msg);
        TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err.msg, "not a whole number in [1, 64]"), err.msg);
    }
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_circle_same_work_every_period);
    RUN_TEST(test_too_few_substeps_refused_with_the_count_needed);
    RUN_TEST(test_substeps_key_strict);
    RUN_TEST(test_fixed_at_least_as_close_as_adaptive_on_the_four_cases);
    return UNITY_END() ? 1 : 0;
}
