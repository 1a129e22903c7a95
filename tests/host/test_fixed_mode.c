/* SPDX-License-Identifier: BSD-3-Clause */
/// @file test_fixed_mode.c
/// The fixed-cost mode from a scenario (integrator.method ros34pw2-fixed, integrator.substeps;
/// docs/scenarios.md): the paper circle at 1 kHz with 16, 32 and 64 segments per cable runs
/// with the same work in every period (the most RHS calls of a period times the periods equals
/// the total, and both are 4 n per period), the summary says so; a substep count below the
/// derived one, 0, or not whole is refused naming integrator.substeps and the count needed.
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
    g_sc.robot.segments = segments;
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
        static cdpr_sim_summary_t sum;
        cdpr_scenario_error_t err;
        TEST_ASSERT_EQUAL_INT_MESSAGE(CDPR_OK, cdpr_sim_run(&g_sc, &o, &sum, &err), err.msg);
        char msg[200];
        (void)snprintf(msg, sizeof msg,
                       "6 x %d: %d substeps, %lu RHS in %ld periods, most %lu; error norm max "
                       "%.3g, above 1 in %lu periods",
                       segs[i], sum.substeps, sum.rhs_evals, sum.periods, sum.max_rhs_per_period,
                       sum.max_err_norm, sum.err_above_one_periods);
        TEST_MESSAGE(msg);
        TEST_ASSERT_EQUAL_INT_MESSAGE(CDPR_SIM_OK, sum.status, sum.message);
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
        static cdpr_sim_summary_t back;
        TEST_ASSERT_EQUAL_INT(CDPR_OK,
                              cdpr_sim_read_summary(CDPR_TEST_TMP "/summary.json", &back, &err));
        TEST_ASSERT_EQUAL_INT(sum.substeps, back.substeps);
        TEST_ASSERT_EQUAL_UINT(sum.max_rhs_per_period, back.max_rhs_per_period);
        TEST_ASSERT_EQUAL_DOUBLE(sum.max_err_norm, back.max_err_norm);
        TEST_ASSERT_EQUAL_UINT(sum.err_above_one_periods, back.err_above_one_periods);
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
    return UNITY_END() ? 1 : 0;
}
