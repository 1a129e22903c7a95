/* SPDX-License-Identifier: BSD-3-Clause */
/// @file test_correction.c
/// Pre-compensation files (cdpr/host/correction.h; issue 22 item 1): the round trip through the
/// file, the refusals at load (another trajectory, robot, controller, period; a slack demand;
/// a file that is not one) and the scenario key, on the paper's line (scenarios/paper-line.yaml).
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "cdpr/host/correction.h"
#include "cdpr/host/scenario.h"
#include "text_files.h"
#include "unity.h"

void setUp(void) {}
void tearDown(void) {}

static cdpr_scenario_t sc;
static cdpr_host_correction_t hc;
static cdpr_host_correction_t back;

static void load_line(void)
{
    cdpr_scenario_error_t err;
    TEST_ASSERT_EQUAL_INT_MESSAGE(
        CDPR_OK, cdpr_scenario_load(CDPR_SOURCE_DIR "/scenarios/paper-line.yaml", &sc, &err),
        err.msg);
}

/* A small correction for the line: n coefficients every 0.3 s, cable j's a_i = amp sin(...). */
static void small_correction(double amp)
{
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_correction_init(&hc, &sc, 40, 0.0, 0.3));
    for (int j = 0; j < 6; ++j) {
        for (int i = 0; i < 40; ++i) {
            hc.coef_m[j * 40 + i] = amp * sin(0.37 * (double)i + (double)j) / 3.0;
        }
    }
    hc.report.iterations = 3;
    hc.report.rms_before_m = 0.018;
    hc.report.rms_after_m = 0.0013;
}

static void test_round_trip(void)
{
    make_tmp();
    load_line();
    small_correction(1e-3);
    char path[600];
    snprintf(path, sizeof path, "%s/rt.yaml", tmp_dir);
    cdpr_scenario_error_t err;
    TEST_ASSERT_EQUAL_INT_MESSAGE(CDPR_OK, cdpr_correction_write(path, &hc, "a test", &err),
                                  err.msg);
    TEST_ASSERT_EQUAL_INT_MESSAGE(CDPR_OK, cdpr_correction_read(path, &back, &err), err.msg);
    TEST_ASSERT_EQUAL_INT(6, back.c.n_cables);
    TEST_ASSERT_EQUAL_INT(40, back.c.n_coef);
    TEST_ASSERT_EQUAL_DOUBLE(0.3, back.c.spacing_s);
    TEST_ASSERT_EQUAL_DOUBLE(sc.period_s, back.c.period_s);
    TEST_ASSERT_TRUE(back.c.coef_m == back.coef_m);
    /* %.17g: every coefficient back bit for bit */
    TEST_ASSERT_EQUAL_INT(0, memcmp(hc.coef_m, back.coef_m, sizeof(cdpr_real_t) * 240U));
    TEST_ASSERT_EQUAL_STRING(hc.trajectory_sha256, back.trajectory_sha256);
    TEST_ASSERT_EQUAL_STRING(hc.robot_sha256, back.robot_sha256);
    TEST_ASSERT_EQUAL_STRING(hc.controller_sha256, back.controller_sha256);
    TEST_ASSERT_EQUAL_INT(3, back.report.iterations);
    TEST_ASSERT_DOUBLE_WITHIN(1e-9, 0.0013, back.report.rms_after_m);
    TEST_ASSERT_TRUE(isnan(back.report.min_tension_N)); /* unknown: left out of the file */
    /* made for the plant as written: no varied plants in the file, read back as none */
    TEST_ASSERT_EQUAL_DOUBLE(0.0, back.report.robust_mass);
    TEST_ASSERT_TRUE(isnan(back.report.varied_rms_after_m));
    /* no PATH.tmp left behind */
    char tmp[620];
    snprintf(tmp, sizeof tmp, "%s.tmp", path);
    TEST_ASSERT_NOT_EQUAL(0, access(tmp, F_OK));
}

/* A robust correction's varied-plant report (cdpr-precomp --robust-mass) survives the file. */
static void test_round_trip_robust_report(void)
{
    make_tmp();
    load_line();
    small_correction(1e-3);
    hc.report.robust_mass = 0.1;
    hc.report.varied_rms_after_m = 0.0028;
    hc.report.varied_max_after_m = 0.006;
    hc.report.varied_max_after_rad = 0.0054;
    hc.report.varied_min_tension_N = 29.2;
    char path[600];
    snprintf(path, sizeof path, "%s/rt-robust.yaml", tmp_dir);
    cdpr_scenario_error_t err;
    TEST_ASSERT_EQUAL_INT_MESSAGE(CDPR_OK, cdpr_correction_write(path, &hc, "a test", &err),
                                  err.msg);
    TEST_ASSERT_EQUAL_INT_MESSAGE(CDPR_OK, cdpr_correction_read(path, &back, &err), err.msg);
    TEST_ASSERT_DOUBLE_WITHIN(1e-12, 0.1, back.report.robust_mass);
    TEST_ASSERT_EQUAL_DOUBLE(0.0, back.report.robust_ea);
    TEST_ASSERT_DOUBLE_WITHIN(1e-9, 0.0028, back.report.varied_rms_after_m);
    TEST_ASSERT_DOUBLE_WITHIN(1e-9, 0.006, back.report.varied_max_after_m);
    TEST_ASSERT_DOUBLE_WITHIN(1e-9, 0.0054, back.report.varied_max_after_rad);
    TEST_ASSERT_DOUBLE_WITHIN(1e-9, 29.2, back.report.varied_min_tension_N);
}

static void expect_refused(const cdpr_scenario_t *s, cdpr_status_t st, const char *says)
{
    cdpr_scenario_error_t err;
    err.msg[0] = '\0';
    TEST_ASSERT_EQUAL_INT_MESSAGE(st, cdpr_correction_check(s, &hc, "c.yaml", &err), err.msg);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err.msg, says), err.msg);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err.msg, "c.yaml"), err.msg);
}

static void test_check_ties_it_to_its_scenario(void)
{
    load_line();
    small_correction(1e-3);
    cdpr_scenario_error_t err;
    TEST_ASSERT_EQUAL_INT_MESSAGE(CDPR_OK, cdpr_correction_check(&sc, &hc, "c.yaml", &err),
                                  err.msg);
    static cdpr_scenario_t other;
    other = sc;
    other.traj.to[0] += 0.1; /* another line */
    expect_refused(&other, CDPR_E_OUT_OF_RANGE, "another trajectory");
    other = sc;
    other.rig.cable[2].rope.ea_N *= 1.1; /* another robot */
    expect_refused(&other, CDPR_E_OUT_OF_RANGE, "another robot");
    other = sc;
    other.gains.k_length_per_s = 4.0; /* another closed loop */
    expect_refused(&other, CDPR_E_OUT_OF_RANGE, "another controller gains");
    other = sc;
    other.period_s = 0.005; /* another period */
    expect_refused(&other, CDPR_E_OUT_OF_RANGE, "control period of 0.01 s");
    /* A plant 10 % stiffer that the controller's model undoes (controller.model) is the same
     * robot to the controller: the correction stays (its hash is of the controller's model,
     * to 9 digits: 2.2e6 / 1.1 is not 2e6 in the last bit). */
    other = sc;
    for (int j = 0; j < other.rig.n_cables; ++j) {
        other.rig.cable[j].rope.ea_N *= 1.1;
    }
    other.controller_model.ea = 1.0 / 1.1;
    TEST_ASSERT_EQUAL_INT_MESSAGE(CDPR_OK, cdpr_correction_check(&other, &hc, "c.yaml", &err),
                                  err.msg);
}

static void test_slack_demand_is_refused(void)
{
    load_line();
    small_correction(1e-3);
    /* Cable 3 paid out 4 m more from t = 4.5 s on (fully from 5.4 s): the controller's model,
     * held there statically, has that cable hanging below the 20 N floor. A catenary keeps
     * its weight's tension: 1.5 m more still leaves 25 N (accepted, below). */
    for (int i = 15; i < 40; ++i) {
        hc.coef_m[2 * 40 + i] = 4.0;
    }
    expect_refused(&sc, CDPR_E_INFEASIBLE, "slack cable: cable 3 at t = 5.");
    for (int i = 15; i < 40; ++i) {
        hc.coef_m[2 * 40 + i] = 1.5;
    }
    cdpr_scenario_error_t e1;
    TEST_ASSERT_EQUAL_INT_MESSAGE(CDPR_OK, cdpr_correction_check(&sc, &hc, "c.yaml", &e1), e1.msg);
    hc.floor_N = 30.0; /* the same correction made for a 30 N floor */
    expect_refused(&sc, CDPR_E_INFEASIBLE, "slack cable: cable 3 at t = 5.1 s");
    /* Hauled in instead (-0.02 m): the others take up the load, accepted. */
    for (int i = 15; i < 40; ++i) {
        hc.coef_m[2 * 40 + i] = -0.02;
    }
    cdpr_scenario_error_t err;
    TEST_ASSERT_EQUAL_INT_MESSAGE(CDPR_OK, cdpr_correction_check(&sc, &hc, "c.yaml", &err),
                                  err.msg);
}

static void read_refused(const char *text, cdpr_status_t st, const char *says)
{
    char path[600];
    snprintf(path, sizeof path, "%s/bad.yaml", tmp_dir);
    write_text(path, text);
    cdpr_scenario_error_t err;
    err.msg[0] = '\0';
    TEST_ASSERT_EQUAL_INT_MESSAGE(st, cdpr_correction_read(path, &back, &err), err.msg);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err.msg, says), err.msg);
}

static void test_files_that_are_not_corrections(void)
{
    make_tmp();
    static const char head[] =
        "format: cdpr-correction-1\n"
        "trajectory_sha256: \"0000000000000000000000000000000000000000000000000000000000000000\"\n"
        "robot_sha256: \"0000000000000000000000000000000000000000000000000000000000000000\"\n"
        "controller_sha256: \"0000000000000000000000000000000000000000000000000000000000000000\"\n"
        "period_s: 0.01\nstart_s: 0\nspacing_s: 0.3\nfloor_N: 20\n";
    char text[2048];
    snprintf(text, sizeof text, "%scables:\n  - coef_m: [0.001, 4O.0, 0]\n", head);
    read_refused(text, CDPR_E_PARSE, "'4O.0' is not a number");
    snprintf(text, sizeof text, "%scables:\n  - coef_m: [0.001, 0, 0]\n  - coef_m: [0, 0]\n", head);
    read_refused(text, CDPR_E_OUT_OF_RANGE, "2 coefficients, cable 1 has 3");
    snprintf(text, sizeof text, "%scables:\n  - coef_m: [0.001, 20.0, 0]\n", head);
    read_refused(text, CDPR_E_OUT_OF_RANGE, "coefficient 2 is 20");
    char other[2048];
    replace(text, "cdpr-correction-1", "cdpr-correction-9", other, sizeof other);
    read_refused(other, CDPR_E_PARSE, "not 'cdpr-correction-1'");
    replace(text, "spacing_s: 0.3\n", "", other, sizeof other);
    read_refused(other, CDPR_E_PARSE, "spacing_s");
    replace(text, "spacing_s: 0.3", "spacing_s: 0", other, sizeof other);
    read_refused(other, CDPR_E_OUT_OF_RANGE, "spacing_s");
}

static void test_scenario_key(void)
{
    make_tmp();
    load_line();
    /* The scenario names the file relative to its folder. */
    FILE *f = fopen(CDPR_SOURCE_DIR "/scenarios/paper-line.yaml", "r");
    TEST_ASSERT_NOT_NULL(f);
    static char text[16384];
    const size_t n = fread(text, 1, sizeof text - 1, f);
    text[n] = '\0';
    fclose(f);
    static char edited[16500];
    replace(text, "\ncontroller:\n", "\ncontroller:\n  precompensation: line-corr.yaml\n", edited,
            sizeof edited);
    char path[600];
    snprintf(path, sizeof path, "%s/line.yaml", tmp_dir);
    write_text(path, edited);
    static cdpr_scenario_t with;
    cdpr_scenario_error_t err;
    TEST_ASSERT_EQUAL_INT_MESSAGE(CDPR_OK, cdpr_scenario_load(path, &with, &err), err.msg);
    char want[600];
    snprintf(want, sizeof want, "%s/line-corr.yaml", tmp_dir);
    TEST_ASSERT_EQUAL_STRING(want, with.precompensation);
    /* No file (yet): refused with the key's line. */
    (void)unlink(want); /* a previous run's */
    const cdpr_tracker_correction_t *c = NULL;
    TEST_ASSERT_EQUAL_INT(CDPR_E_IO, cdpr_correction_for_scenario(&with, &hc, &c, &err));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err.msg, "controller.precompensation"), err.msg);
    TEST_ASSERT_NULL(c);
    /* A correction made for it: read, checked, handed out. */
    small_correction(1e-3);
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_correction_write(want, &hc, NULL, &err));
    TEST_ASSERT_EQUAL_INT_MESSAGE(CDPR_OK, cdpr_correction_for_scenario(&with, &back, &c, &err),
                                  err.msg);
    TEST_ASSERT_TRUE(c == &back.c);
    /* The scenario without the key: none. */
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_correction_for_scenario(&sc, &back, &c, &err));
    TEST_ASSERT_NULL(c);
    /* A correction made for another line is refused under the key. */
    static cdpr_scenario_t moved;
    moved = sc;
    moved.traj.to[2] += 0.2;
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_correction_init(&hc, &moved, 40, 0.0, 0.3));
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_correction_write(want, &hc, NULL, &err));
    TEST_ASSERT_EQUAL_INT(CDPR_E_OUT_OF_RANGE,
                          cdpr_correction_for_scenario(&with, &back, &c, &err));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err.msg, "controller.precompensation"), err.msg);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err.msg, "another trajectory"), err.msg);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_round_trip);
    RUN_TEST(test_round_trip_robust_report);
    RUN_TEST(test_check_ties_it_to_its_scenario);
    RUN_TEST(test_slack_demand_is_refused);
    RUN_TEST(test_files_that_are_not_corrections);
    RUN_TEST(test_scenario_key);
    return UNITY_END();
}
