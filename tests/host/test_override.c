/* SPDX-License-Identifier: BSD-3-Clause */
/// @file test_override.c
/// Command-line overrides of a scenario's run settings (cdpr_scenario_override): a value that
/// differs from the file prints one note, an equal one prints nothing, a value the scenario's
/// own check refuses is refused naming the option.
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "cdpr/host/scenario.h"
#include "unity.h"

#ifndef CDPR_SOURCE_DIR
#define CDPR_SOURCE_DIR "."
#endif

#define CIRCLE CDPR_SOURCE_DIR "/scenarios/paper-circle.yaml"

void setUp(void) {}
void tearDown(void) {}

static cdpr_scenario_t g_sc;
static char g_notes[4096];

/* Load paper-circle (run.period_s 0.01, run.duration_s 12.6, integrator.max_trials 2000,
 * max_attempts 1), apply `ov`; the notes into g_notes. */
static cdpr_status_t apply(const cdpr_scenario_overrides_t *ov, cdpr_scenario_error_t *err)
{
    TEST_ASSERT_EQUAL_INT_MESSAGE(CDPR_OK, cdpr_scenario_load(CIRCLE, &g_sc, err), err->msg);
    FILE *f = tmpfile();
    TEST_ASSERT_NOT_NULL(f);
    err->msg[0] = '\0';
    const cdpr_status_t st = cdpr_scenario_override(&g_sc, ov, "prog", f, err);
    rewind(f);
    const size_t n = fread(g_notes, 1, sizeof g_notes - 1, f);
    g_notes[n] = '\0';
    fclose(f);
    return st;
}

static void test_differing_values_print_one_note_each(void)
{
    cdpr_scenario_overrides_t ov;
    cdpr_scenario_overrides_none(&ov);
    ov.rate_hz = 1000.0;
    ov.max_trials = 50.0;
    ov.duration_s = 2.5;
    ov.max_attempts = 3.0;
    cdpr_scenario_error_t err;
    TEST_ASSERT_EQUAL_INT_MESSAGE(CDPR_OK, apply(&ov, &err), err.msg);
    TEST_ASSERT_EQUAL_STRING(
        "prog: --rate 1000 Hz overrides run.period_s = 0.01 s (100 Hz) of " CIRCLE "\n"
        "prog: --duration 2.5 s overrides run.duration_s = 12.6 s of " CIRCLE "\n"
        "prog: --max-trials 50 overrides integrator.max_trials = 2000 of " CIRCLE "\n"
        "prog: --max-attempts 3 overrides integrator.max_attempts = 1 of " CIRCLE "\n",
        g_notes);
    TEST_ASSERT_EQUAL_DOUBLE(0.001, g_sc.period_s);
    TEST_ASSERT_EQUAL_DOUBLE(2.5, g_sc.duration_s);
    TEST_ASSERT_EQUAL_INT(50, g_sc.integrator.max_trials);
    TEST_ASSERT_EQUAL_INT(3, g_sc.integrator.max_attempts);
    TEST_ASSERT_EQUAL_INT(2500, cdpr_scenario_periods(&g_sc));
}

/* --integrator names the method; a --rate below run.output_rate_hz gives a row every period,
 * said by the key's own name (not refused for a rate the user never set). */
static void test_integrator_and_a_rate_below_the_output_rate(void)
{
    cdpr_scenario_overrides_t ov;
    cdpr_scenario_overrides_none(&ov);
    ov.method = (int)CDPR_PLANT_ROS34PW2;
    ov.rate_hz = 20.0;
    ov.duration_s = 12.6;
    cdpr_scenario_error_t err;
    TEST_ASSERT_EQUAL_INT_MESSAGE(CDPR_OK, apply(&ov, &err), err.msg);
    TEST_ASSERT_EQUAL_STRING(
        "prog: --rate 20 Hz overrides run.period_s = 0.01 s (100 Hz) of " CIRCLE "\n"
        "prog: --rate 20 Hz: run.output_rate_hz = 100 Hz of " CIRCLE
        " is above it: a row every period (20 Hz)\n"
        "prog: --integrator ros34pw2 overrides integrator.method = rkf45 of " CIRCLE
        " (its settings: rtol 0.001, atol 0.0001 m, 0.01 m/s, 1e-06, 0.0001 rad/s, h_max 0.01 s, "
        "max_trials 4, max_attempts 1)\n",
        g_notes);
    /* The method's own settings: the file's integrator.ros34pw2 subsection. */
    TEST_ASSERT_EQUAL_INT(CDPR_PLANT_ROS34PW2, g_sc.integrator.method);
    TEST_ASSERT_EQUAL_DOUBLE(1.0e-3, g_sc.integrator.rtol);
    TEST_ASSERT_EQUAL_DOUBLE(1.0e-2, g_sc.integrator.atol_velocity_m_per_s);
    TEST_ASSERT_EQUAL_INT(4, g_sc.integrator.max_trials);
    TEST_ASSERT_EQUAL_DOUBLE(20.0, g_sc.output_rate_hz);
    TEST_ASSERT_EQUAL_INT(1, cdpr_scenario_output_every(&g_sc));
}

/* --max-trials applies on top of the settings --integrator brings, and names their value. */
static void test_max_trials_on_top_of_the_method_settings(void)
{
    cdpr_scenario_overrides_t ov;
    cdpr_scenario_overrides_none(&ov);
    ov.method = (int)CDPR_PLANT_ROS34PW2;
    ov.max_trials = 6.0;
    cdpr_scenario_error_t err;
    TEST_ASSERT_EQUAL_INT_MESSAGE(CDPR_OK, apply(&ov, &err), err.msg);
    TEST_ASSERT_NOT_NULL_MESSAGE(
        strstr(g_notes, "prog: --max-trials 6 overrides integrator.max_trials = 4 of " CIRCLE),
        g_notes);
    TEST_ASSERT_EQUAL_INT(6, g_sc.integrator.max_trials);
    TEST_ASSERT_EQUAL_DOUBLE(1.0e-3, g_sc.integrator.rtol);
    /* Back to the file's method: its settings again. */
    cdpr_scenario_overrides_none(&ov);
    ov.method = (int)CDPR_PLANT_RKF45;
    TEST_ASSERT_EQUAL_INT_MESSAGE(CDPR_OK, cdpr_scenario_override(&g_sc, &ov, "prog", NULL, &err),
                                  err.msg);
    TEST_ASSERT_EQUAL_DOUBLE(1.0e-6, g_sc.integrator.rtol);
    TEST_ASSERT_EQUAL_INT(2000, g_sc.integrator.max_trials);
}

static void test_equal_values_print_nothing(void)
{
    cdpr_scenario_overrides_t ov;
    cdpr_scenario_overrides_none(&ov);
    cdpr_scenario_error_t err;
    TEST_ASSERT_EQUAL_INT(CDPR_OK, apply(&ov, &err)); /* nothing given */
    TEST_ASSERT_EQUAL_STRING("", g_notes);
    ov.rate_hz = 100.0;
    ov.duration_s = 12.6;
    ov.max_trials = 2000.0;
    ov.max_attempts = 1.0;
    TEST_ASSERT_EQUAL_INT_MESSAGE(CDPR_OK, apply(&ov, &err), err.msg);
    TEST_ASSERT_EQUAL_STRING("", g_notes);
    TEST_ASSERT_EQUAL_DOUBLE(0.01, g_sc.period_s);
}

/* Refused with `st`, the message naming `opt` and `key`. */
static void refused(const cdpr_scenario_overrides_t *ov, cdpr_status_t st, const char *opt,
                    const char *key)
{
    cdpr_scenario_error_t err;
    TEST_ASSERT_EQUAL_INT_MESSAGE(st, apply(ov, &err), err.msg);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err.msg, opt), err.msg);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err.msg, key), err.msg);
}

static void test_out_of_range_overrides_are_refused_naming_the_option(void)
{
    cdpr_scenario_overrides_t ov;
    cdpr_scenario_overrides_none(&ov);
    ov.rate_hz = 0.05; /* period 20 s: outside (0, 10] */
    refused(&ov, CDPR_E_OUT_OF_RANGE, "--rate 0.05 Hz", "run.period_s");
    cdpr_scenario_overrides_none(&ov);
    ov.rate_hz = 0.0; /* period +inf */
    refused(&ov, CDPR_E_NOT_FINITE, "--rate 0 Hz", "run.period_s");
    cdpr_scenario_overrides_none(&ov);
    ov.duration_s = 1.005; /* not a whole number of 0.01 s periods */
    refused(&ov, CDPR_E_OUT_OF_RANGE, "--duration 1.005 s", "run.duration_s");
    cdpr_scenario_overrides_none(&ov);
    ov.duration_s = -1.0;
    refused(&ov, CDPR_E_OUT_OF_RANGE, "--duration -1 s", "run.duration_s");
    cdpr_scenario_overrides_none(&ov);
    ov.max_trials = 0.0;
    refused(&ov, CDPR_E_OUT_OF_RANGE, "--max-trials 0", "integrator.max_trials");
    cdpr_scenario_overrides_none(&ov);
    ov.max_trials = 3.5;
    refused(&ov, CDPR_E_OUT_OF_RANGE, "--max-trials 3.5", "whole");
    cdpr_scenario_overrides_none(&ov);
    ov.max_attempts = 17.0; /* CDPR_PLANT_MAX_ATTEMPTS is 16 */
    refused(&ov, CDPR_E_OUT_OF_RANGE, "--max-attempts 17", "integrator.max_attempts");
    cdpr_scenario_overrides_none(&ov);
    ov.rate_hz = 150.0; /* run.output_rate_hz 100 does not divide 150 Hz */
    refused(&ov, CDPR_E_OUT_OF_RANGE, "--rate 150 Hz", "run.output_rate_hz");
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_differing_values_print_one_note_each);
    RUN_TEST(test_integrator_and_a_rate_below_the_output_rate);
    RUN_TEST(test_max_trials_on_top_of_the_method_settings);
    RUN_TEST(test_equal_values_print_nothing);
    RUN_TEST(test_out_of_range_overrides_are_refused_naming_the_option);
    return UNITY_END() ? 1 : 0;
}
