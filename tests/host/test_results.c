/* SPDX-License-Identifier: BSD-3-Clause */
/// @file test_results.c
/// The result writers: timeseries.csv (provenance comments, header and row format, record.h)
/// from a hand-made period, the statistics of the summary, summary.json written and read back
/// (provenance, unknown values as null both ways, files without the provenance keys), node
/// events from the segment counts, rows at the output instants when periods are skipped, every
/// status name written and read back, and write or read errors reported as statuses (CDPR_E_IO
/// with the errno kept, CDPR_E_PARSE) that leave only whole rows in the file. Expectations are
/// written out here, never regenerated from the code.
#include <errno.h>
#include <math.h>
#include <fcntl.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include "cdpr/version.h"
#include "cdpr/host/record.h"
#include "cdpr/host/summary.h"
#include "unity.h"

#ifndef CDPR_TEST_TMP
#define CDPR_TEST_TMP "/tmp/test_results"
#endif
#ifndef CDPR_TEST_BUILD_TYPE
#define CDPR_TEST_BUILD_TYPE ""
#endif

void setUp(void) {}
void tearDown(void) {}

static char g_text[8192];

static const char *slurp(const char *path)
{
    FILE *f = fopen(path, "rb");
    TEST_ASSERT_NOT_NULL_MESSAGE(f, path);
    const size_t n = fread(g_text, 1, sizeof g_text - 1, f);
    g_text[n] = '\0';
    fclose(f);
    return g_text;
}

static void write_text(const char *path, const char *text)
{
    FILE *f = fopen(path, "wb");
    TEST_ASSERT_NOT_NULL_MESSAGE(f, path);
    fputs(text, f);
    TEST_ASSERT_EQUAL_INT(0, fclose(f));
}

static void scenario(cdpr_scenario_t *sc)
{
    cdpr_scenario_default(sc, CDPR_PRESET_PAPER_50M);
    snprintf(sc->path, sizeof sc->path, "scenarios/made-up.yaml");
    sc->duration_s = 1.0;
    sc->period_s = 0.01;
    sc->output_rate_hz = 0.0; /* a row every period */
}

static void test_csv_header_and_row(void)
{
    mkdir(CDPR_TEST_TMP, 0775);
    const char *dir = CDPR_TEST_TMP "/csv";
    cdpr_scenario_t sc;
    scenario(&sc);
    cdpr_summary_t sum;
    memset(&sum, 0, sizeof sum);
    cdpr_record_t rec;
    cdpr_scenario_error_t err;
    TEST_ASSERT_EQUAL_INT_MESSAGE(CDPR_OK, cdpr_record_open(&rec, &sc, NULL, dir, 2, &sum, &err),
                                  err.msg);
    /* Measured at (1, 2, 3) m, level; desired 0.5 m further along x, level. */
    cdpr_traj_sample_t des;
    memset(&des, 0, sizeof des);
    des.pose[0] = 1.5;
    des.pose[1] = 2.0;
    des.pose[2] = 3.0;
    des.motion.q.w = 1.0;
    cdpr_tracker_meas_t meas;
    memset(&meas, 0, sizeof meas);
    meas.t_s = 0.5;
    meas.cabin.p_m = cdpr_v3(1.0, 2.0, 3.0);
    meas.cabin.q.w = 1.0;
    meas.length_m[0] = 10.25;
    meas.length_m[1] = 20.5;
    const double t_cabin[2] = {100.0, 200.0};
    const double t_winch[2] = {110.0, 210.0};
    const double l_ff[2] = {10.0, 20.0};
    const double payout[2] = {0.125, -0.25};
    const int segments[2] = {20, 21};
    const cdpr_record_row_t row = {0.5, &des, &meas, t_cabin, t_winch, l_ff, payout, segments};
    cdpr_record_period(&rec, 0, 1, &row);
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_record_close(&rec));
    /* The provenance first, as comments: made-up.yaml does not exist (no hash), no plant
     * parameters were given (no integrator): null. */
    char expected[2048];
    snprintf(expected, sizeof expected,
             "# version: %s\n# git_describe: %s\n# build_type: %s\n"
             "# scenario: scenarios/made-up.yaml\n# scenario_sha256: null\n# integrator: null\n"
             "%s",
             CDPR_VERSION_STRING, CDPR_GIT_DESCRIBE,
             (CDPR_TEST_BUILD_TYPE[0] != '\0') ? CDPR_TEST_BUILD_TYPE : "null",
             "t_s,x_m,y_m,z_m,alpha_rad,beta_rad,gamma_rad,xd_m,yd_m,zd_m,alphad_rad,betad_rad,"
             "gammad_rad,ex_m,ey_m,ez_m,ealpha_rad,ebeta_rad,egamma_rad,epos_m,erot_rad,"
             "T_cabin1_N,T_cabin2_N,T_winch1_N,T_winch2_N,L1_m,L2_m,Lff1_m,Lff2_m,"
             "u1_m_per_s,u2_m_per_s,n1,n2\n"
             /* beta of the identity is asin(-0) = -0 in cdpr_quat_to_euler; %.17g keeps the sign,
              * so the error -0 - 0 prints "-0" too. */
             "0.5,1,2,3,0,-0,0,1.5,2,3,0,0,0,-0.5,0,0,0,-0,0,0.5,0,"
             "100,200,110,210,10.25,20.5,10,20,0.125,-0.25,20,21\n");
    TEST_ASSERT_EQUAL_STRING(expected, slurp(CDPR_TEST_TMP "/csv/timeseries.csv"));
    /* The statistics of that one period. */
    TEST_ASSERT_EQUAL_DOUBLE(0.5, sum.rms_error_m);
    TEST_ASSERT_EQUAL_DOUBLE(0.5, sum.initial_error_m);
    TEST_ASSERT_EQUAL_DOUBLE(0.5, sum.final_error_m);
    TEST_ASSERT_EQUAL_DOUBLE(0.5, sum.rms_error_second_half_m); /* t = 0.5 >= 1 s / 2 */
    TEST_ASSERT_EQUAL_DOUBLE(100.0, sum.min_tension_N);
    TEST_ASSERT_EQUAL_DOUBLE(210.0, sum.max_tension_N);
    TEST_ASSERT_EQUAL_INT(20, sum.nodes_min);
    TEST_ASSERT_EQUAL_INT(21, sum.nodes_max);
    /* Per cable, either end: cable 1 had 100 (cabin) and 110 (winch), cable 2 200 and 210. */
    TEST_ASSERT_EQUAL_DOUBLE(100.0, sum.cable_min_tension_N[0]);
    TEST_ASSERT_EQUAL_DOUBLE(110.0, sum.cable_max_tension_N[0]);
    TEST_ASSERT_EQUAL_DOUBLE(200.0, sum.cable_min_tension_N[1]);
    TEST_ASSERT_EQUAL_DOUBLE(210.0, sum.cable_max_tension_N[1]);
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_summary_write(CDPR_TEST_TMP "/csv/s.json", &sc, &sum));
    const char *text = slurp(CDPR_TEST_TMP "/csv/s.json");
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(text, "\"cable_max_tension_N\": [110, 210],\n"), text);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(text, "\"cable_min_tension_N\": [100, 200],\n"), text);
}

static void fill(cdpr_summary_t *s)
{
    memset(s, 0, sizeof *s);
    s->rms_error_m = 0.1;
    s->max_error_m = 1.0 / 3.0;
    s->final_error_m = 2e-7;
    s->initial_error_m = 1.47;
    s->rms_error_second_half_m = 0.05;
    s->rms_error_rad = 1e-3;
    s->max_error_rad = 3.14159;
    s->final_error_rad = 0.0;
    s->max_tension_N = 1234.5;
    s->min_tension_N = 12.25;
    s->max_payout_m_per_s = 0.75;
    s->sim_time_s = 12.6;
    s->wall_time_s = 3.5;
    s->node_insertions = 11;
    s->node_removals = 12;
    s->capacity_hits = 13;
    s->substep_limit_hits = 14;
    s->ik_failures = 15;
    s->min_length_periods = 16;
    s->nodes_min = 17;
    s->nodes_max = 18;
    s->periods = 1260;
    s->steps_accepted = 19;
    s->steps_rejected = 20;
    s->rhs_evals = 21;
    s->settle_steps = 22;
    s->status = CDPR_SUMMARY_WARNINGS;
    snprintf(s->message, sizeof s->message, "a \"quoted\" note");
}

static void test_summary_written_then_read_back_equal(void)
{
    mkdir(CDPR_TEST_TMP, 0775);
    const char *path = CDPR_TEST_TMP "/summary.json";
    cdpr_scenario_t sc;
    scenario(&sc);
    cdpr_summary_t a;
    fill(&a);
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_summary_write(path, &sc, &a));
    const char *text = slurp(path);
    TEST_ASSERT_NOT_NULL(strstr(text, "\"scenario\": \"scenarios/made-up.yaml\",\n"));
    TEST_ASSERT_NOT_NULL(strstr(text, "\"status\": \"warnings\",\n"));
    TEST_ASSERT_NOT_NULL(strstr(text, "\"message\": \"a \\\"quoted\\\" note\",\n"));
    TEST_ASSERT_NOT_NULL(strstr(text, "\"rms_error_m\": 0.10000000000000001,\n"));
    TEST_ASSERT_NOT_NULL(strstr(text, "\"control_period_s\": 0.01,\n"));
    TEST_ASSERT_NOT_NULL(strstr(text, "\"periods\": 1260,\n"));
    cdpr_summary_t b;
    cdpr_scenario_error_t err;
    TEST_ASSERT_EQUAL_INT_MESSAGE(CDPR_OK, cdpr_summary_read(path, &b, &err), err.msg);
    TEST_ASSERT_EQUAL(CDPR_SUMMARY_WARNINGS, b.status);
    const double *da[] = {&a.rms_error_m,
                          &a.max_error_m,
                          &a.final_error_m,
                          &a.initial_error_m,
                          &a.rms_error_second_half_m,
                          &a.rms_error_rad,
                          &a.max_error_rad,
                          &a.final_error_rad,
                          &a.max_tension_N,
                          &a.min_tension_N,
                          &a.max_payout_m_per_s,
                          &a.sim_time_s,
                          &a.wall_time_s};
    const double *db[] = {&b.rms_error_m,
                          &b.max_error_m,
                          &b.final_error_m,
                          &b.initial_error_m,
                          &b.rms_error_second_half_m,
                          &b.rms_error_rad,
                          &b.max_error_rad,
                          &b.final_error_rad,
                          &b.max_tension_N,
                          &b.min_tension_N,
                          &b.max_payout_m_per_s,
                          &b.sim_time_s,
                          &b.wall_time_s};
    for (size_t i = 0; i < sizeof da / sizeof da[0]; ++i) {
        TEST_ASSERT_EQUAL_MEMORY(da[i], db[i], sizeof(double)); /* bit for bit */
    }
    TEST_ASSERT_EQUAL_UINT32(11, b.node_insertions);
    TEST_ASSERT_EQUAL_UINT32(12, b.node_removals);
    TEST_ASSERT_EQUAL_UINT32(13, b.capacity_hits);
    TEST_ASSERT_EQUAL_UINT32(14, b.substep_limit_hits);
    TEST_ASSERT_EQUAL_UINT32(15, b.ik_failures);
    TEST_ASSERT_EQUAL_UINT32(16, b.min_length_periods);
    TEST_ASSERT_EQUAL_INT(17, b.nodes_min);
    TEST_ASSERT_EQUAL_INT(18, b.nodes_max);
    TEST_ASSERT_EQUAL_INT(1260, b.periods);
    TEST_ASSERT_EQUAL_UINT32(19, b.steps_accepted);
    TEST_ASSERT_EQUAL_UINT32(20, b.steps_rejected);
    TEST_ASSERT_EQUAL_UINT32(21, b.rhs_evals);
    TEST_ASSERT_EQUAL_INT(22, b.settle_steps);
}

static void test_provenance_of_an_existing_scenario_file(void)
{
    /* A scenario "file" holding the bytes "abc": FIPS 180-4's first example, so its hash is
     * known independently. The integrator is the plant parameters'. */
    mkdir(CDPR_TEST_TMP, 0775);
    write_text(CDPR_TEST_TMP "/abc.yaml", "abc");
    cdpr_scenario_t sc;
    scenario(&sc);
    snprintf(sc.path, sizeof sc.path, "%s", CDPR_TEST_TMP "/abc.yaml");
    /* Its robot a robot file of the bytes "abcd" (the hash Python's hashlib and sha256sum give:
     * 88d4266f...589). */
    write_text(CDPR_TEST_TMP "/abcd.yaml", "abcd");
    sc.robot_source = CDPR_ROBOT_FROM_FILE;
    snprintf(sc.rig.name, sizeof sc.rig.name, "%s", CDPR_TEST_TMP "/abcd.yaml");
    cdpr_plant_params_t pp;
    cdpr_plant_params_default(&pp);
    pp.integrator = CDPR_PLANT_RKF45;
    cdpr_summary_t sum;
    memset(&sum, 0, sizeof sum);
    cdpr_record_t rec;
    cdpr_scenario_error_t err;
    TEST_ASSERT_EQUAL_INT_MESSAGE(
        CDPR_OK, cdpr_record_open(&rec, &sc, &pp, CDPR_TEST_TMP "/prov", 2, &sum, &err), err.msg);
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_record_close(&rec));
    const char *abc = "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad";
    const char *abcd = "88d4266fd4e6338d13b845fcf289579d209c897823b9217da3e161936f031589";
    TEST_ASSERT_EQUAL_STRING(abc, sum.prov.scenario_sha256);
    TEST_ASSERT_EQUAL_STRING(abcd, sum.prov.robot_sha256);
    TEST_ASSERT_EQUAL_STRING("rkf45", sum.prov.integrator);
    TEST_ASSERT_EQUAL_STRING(CDPR_VERSION_STRING, sum.prov.version);
    TEST_ASSERT_EQUAL_STRING(CDPR_GIT_DESCRIBE, sum.prov.git_describe);
    TEST_ASSERT_EQUAL_STRING(CDPR_TEST_BUILD_TYPE, sum.prov.build_type);
    const char *csv = slurp(CDPR_TEST_TMP "/prov/timeseries.csv");
    TEST_ASSERT_NOT_NULL_MESSAGE(
        strstr(csv, "\n# scenario_sha256: "
                    "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad\n"
                    "# integrator: rkf45\nt_s,"),
        csv);
    TEST_ASSERT_EQUAL_STRING("rkf45", cdpr_plant_integrator_name(CDPR_PLANT_RKF45));

    /* summary.json carries the same, and reads back. */
    const char *path = CDPR_TEST_TMP "/prov/summary.json";
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_summary_write(path, &sc, &sum));
    const char *text = slurp(path);
    char line[256];
    snprintf(line, sizeof line, "{\n  \"version\": \"%s\",\n  \"git_describe\": \"%s\",\n",
             CDPR_VERSION_STRING, CDPR_GIT_DESCRIBE);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(text, line), text);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(text,
                                        "\"scenario_sha256\": "
                                        "\"ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb41"
                                        "0ff61f20015ad\",\n"),
                                 text);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(text, "\"integrator\": \"rkf45\",\n"), text);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(text,
                                        "\"robot_sha256\": "
                                        "\"88d4266fd4e6338d13b845fcf289579d209c897823b9217da3e1"
                                        "61936f031589\",\n"),
                                 text);
    cdpr_summary_t back;
    TEST_ASSERT_EQUAL_INT_MESSAGE(CDPR_OK, cdpr_summary_read(path, &back, &err), err.msg);
    TEST_ASSERT_EQUAL_STRING(abc, back.prov.scenario_sha256);
    TEST_ASSERT_EQUAL_STRING(abcd, back.prov.robot_sha256);
    TEST_ASSERT_EQUAL_STRING("rkf45", back.prov.integrator);
    TEST_ASSERT_EQUAL_STRING(CDPR_VERSION_STRING, back.prov.version);
    TEST_ASSERT_EQUAL_STRING(CDPR_GIT_DESCRIBE, back.prov.git_describe);
    TEST_ASSERT_EQUAL_STRING(CDPR_TEST_BUILD_TYPE, back.prov.build_type);
}

static void test_unknown_values_are_null_both_ways(void)
{
    /* What a controller over LCM cannot know: the plant's integrator counts and settling. */
    mkdir(CDPR_TEST_TMP, 0775);
    const char *path = CDPR_TEST_TMP "/nulls.json";
    cdpr_scenario_t sc;
    scenario(&sc);
    cdpr_summary_t a;
    fill(&a);
    cdpr_summary_plant_unknown(&a);
    a.max_tension_N = (double)INFINITY; /* JSON has no infinity either */
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_summary_write(path, &sc, &a));
    const char *text = slurp(path);
    static const char *const nulls[] = {"\"version\": null,\n",
                                        "\"git_describe\": null,\n",
                                        "\"build_type\": null,\n",
                                        "\"scenario_sha256\": null,\n",
                                        "\"robot_sha256\": null,\n",
                                        "\"integrator\": null,\n",
                                        "\"capacity_hits\": null,\n",
                                        "\"substep_limit_hits\": null,\n",
                                        "\"min_length_periods\": null,\n",
                                        "\"steps_accepted\": null,\n",
                                        "\"steps_rejected\": null,\n",
                                        "\"rhs_evals\": null,\n",
                                        "\"max_rhs_per_period\": null,\n",
                                        "\"max_err_norm\": null,\n",
                                        "\"err_above_one_periods\": null,\n",
                                        "\"settle_steps\": null,\n",
                                        "\"settle_wall_time_s\": null,\n",
                                        "\"max_tension_N\": null,\n"};
    for (size_t i = 0; i < sizeof nulls / sizeof nulls[0]; ++i) {
        TEST_ASSERT_NOT_NULL_MESSAGE(strstr(text, nulls[i]), nulls[i]);
    }
    /* The known values next to them stay numbers. */
    TEST_ASSERT_NOT_NULL(strstr(text, "\"node_insertions\": 11,\n"));
    TEST_ASSERT_NOT_NULL(strstr(text, "\"ik_failures\": 15,\n"));
    TEST_ASSERT_NOT_NULL(strstr(text, "\"periods\": 1260,\n"));
    cdpr_summary_t b;
    cdpr_scenario_error_t err;
    TEST_ASSERT_EQUAL_INT_MESSAGE(CDPR_OK, cdpr_summary_read(path, &b, &err), err.msg);
    TEST_ASSERT_TRUE(b.capacity_hits == CDPR_SUMMARY_UNKNOWN);
    TEST_ASSERT_TRUE(b.substep_limit_hits == CDPR_SUMMARY_UNKNOWN);
    TEST_ASSERT_TRUE(b.min_length_periods == CDPR_SUMMARY_UNKNOWN);
    TEST_ASSERT_TRUE(b.steps_accepted == CDPR_SUMMARY_UNKNOWN);
    TEST_ASSERT_TRUE(b.steps_rejected == CDPR_SUMMARY_UNKNOWN);
    TEST_ASSERT_TRUE(b.rhs_evals == CDPR_SUMMARY_UNKNOWN);
    TEST_ASSERT_TRUE(b.max_rhs_per_period == CDPR_SUMMARY_UNKNOWN);
    TEST_ASSERT_TRUE(isnan(b.max_err_norm));
    TEST_ASSERT_TRUE(b.err_above_one_periods == CDPR_SUMMARY_UNKNOWN);
    TEST_ASSERT_TRUE(b.settle_steps < 0);
    TEST_ASSERT_TRUE(isnan(b.settle_wall_time_s));
    TEST_ASSERT_TRUE(isnan(b.max_tension_N));
    TEST_ASSERT_EQUAL_STRING("", b.prov.version);
    TEST_ASSERT_EQUAL_STRING("", b.prov.scenario_sha256);
    TEST_ASSERT_EQUAL_STRING("", b.prov.integrator);
    TEST_ASSERT_EQUAL_UINT32(11, b.node_insertions);
    TEST_ASSERT_EQUAL_UINT32(15, b.ik_failures);
    TEST_ASSERT_EQUAL_DOUBLE(0.1, b.rms_error_m);
    /* Written again from what was read (the reader skips the message): the same file. */
    snprintf(b.message, sizeof b.message, "%s", a.message);
    char first[8192];
    snprintf(first, sizeof first, "%s", text);
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_summary_write(path, &sc, &b));
    TEST_ASSERT_EQUAL_STRING(first, slurp(path));
    /* The printed block says unknown instead of printing the sentinels. */
    FILE *f = fopen(CDPR_TEST_TMP "/nulls.txt", "w");
    TEST_ASSERT_NOT_NULL(f);
    cdpr_summary_print(f, "over LCM", &b);
    TEST_ASSERT_EQUAL_INT(0, fclose(f));
    const char *printed = slurp(CDPR_TEST_TMP "/nulls.txt");
    TEST_ASSERT_NULL_MESSAGE(strstr(printed, "18446744073709551615"), printed);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(printed, "the plant's integrator ran elsewhere"), printed);
}

static void test_summary_without_provenance_keys_reads(void)
{
    /* A summary written before the provenance keys existed (tests/regression/paper-line.json). */
    char path[600];
    snprintf(path, sizeof path, "%s/tests/regression/paper-line.json", CDPR_SOURCE_DIR);
    cdpr_summary_t s;
    cdpr_scenario_error_t err;
    TEST_ASSERT_EQUAL_INT_MESSAGE(CDPR_OK, cdpr_summary_read(path, &s, &err), err.msg);
    TEST_ASSERT_EQUAL_STRING("", s.prov.version);
    TEST_ASSERT_EQUAL_STRING("", s.prov.scenario_sha256);
    TEST_ASSERT_EQUAL_INT(400, s.periods);
    TEST_ASSERT_TRUE(s.rhs_evals > 0 && s.rhs_evals != CDPR_SUMMARY_UNKNOWN);
    TEST_ASSERT_TRUE(isfinite(s.settle_wall_time_s));
}

/* One period of cable segment counts and payout rates into the recorder (no CSV). */
static void period(cdpr_record_t *rec, long k, int s1, int s2, double u1, double u2)
{
    cdpr_traj_sample_t des;
    memset(&des, 0, sizeof des);
    des.motion.q.w = 1.0;
    cdpr_tracker_meas_t meas;
    memset(&meas, 0, sizeof meas);
    meas.cabin.q.w = 1.0;
    const double zero[2] = {0.0, 0.0};
    const double u[2] = {u1, u2};
    const int segments[2] = {s1, s2};
    const cdpr_record_row_t row = {0.01 * (double)k, &des, &meas, zero, zero, zero, u, segments};
    cdpr_record_period(rec, k, 0, &row);
}

static void test_node_events_from_segment_counts(void)
{
    cdpr_scenario_t sc;
    scenario(&sc);
    cdpr_summary_t sum;
    memset(&sum, 0, sizeof sum);
    cdpr_record_t rec;
    cdpr_scenario_error_t err;
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_record_open(&rec, &sc, NULL, NULL, 2, &sum, &err));
    /* Cable 1: 20 -> 21 -> 21 -> 22 | gap of 2 periods | 20: 2 insertions, 2 removals (the
     * gap's net change). Cable 2: 18 throughout, then 19 and back to 18: 1 + 1. State 3 seen
     * again (a resent state) adds nothing. */
    period(&rec, 0, 20, 18, 0.0, 0.0);
    period(&rec, 1, 21, 18, 0.0, 0.0);
    period(&rec, 2, 21, 19, 0.0, 0.0);
    period(&rec, 3, 22, 18, 0.0, 0.0);
    period(&rec, 3, 22, 18, 0.0, 0.0);
    period(&rec, 6, 20, 18, 0.0, 0.0);
    unsigned long ins = 0;
    unsigned long rem = 0;
    long missed = 0;
    cdpr_record_node_events(&rec, &ins, &rem, &missed);
    TEST_ASSERT_EQUAL_UINT32(3, ins);
    TEST_ASSERT_EQUAL_UINT32(3, rem);
    TEST_ASSERT_EQUAL_INT32(2, missed);
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_record_close(&rec));
    TEST_ASSERT_EQUAL_INT(18, sum.nodes_min);
    TEST_ASSERT_EQUAL_INT(22, sum.nodes_max);
}

/* Rate-limited periods from the applied payout rates against each winch's limits (the
 * paper's: a_max 5 m/s^2, so 0.05 m/s per 10 ms period; u_max 4 m/s): cable 1 changes by
 * exactly 0.05 (counted), 0.04 (not), 0.05 (counted), then after a gap of one unrecorded
 * period by 0.16 (not counted: no period before it), then to u_max (counted, once, though it
 * also changes by more than 0.05); cable 2 by 0.05 less 1e-7 (not) and -0.05 (counted). */
static void test_rate_limited_periods(void)
{
    cdpr_scenario_t sc;
    scenario(&sc);
    TEST_ASSERT_EQUAL_DOUBLE(5.0, sc.rig.cable[0].winch.a_max_m_per_s2);
    TEST_ASSERT_EQUAL_DOUBLE(4.0, sc.rig.cable[1].winch.u_max_m_per_s);
    cdpr_summary_t sum;
    memset(&sum, 0, sizeof sum);
    cdpr_record_t rec;
    cdpr_scenario_error_t err;
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_record_open(&rec, &sc, NULL, NULL, 2, &sum, &err));
    period(&rec, 0, 20, 20, 0.0, 0.0);
    period(&rec, 1, 20, 20, 0.05, 0.05 - 1e-7);
    period(&rec, 2, 20, 20, 0.09, 0.05 - 1e-7 - 0.05);
    period(&rec, 3, 20, 20, 0.14, 0.0);
    period(&rec, 5, 20, 20, 0.30, 0.0);
    period(&rec, 6, 20, 20, 4.0, 0.0);
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_record_close(&rec));
    TEST_ASSERT_EQUAL_UINT32(3, sum.rate_limited_periods[0]);
    TEST_ASSERT_EQUAL_UINT32(1, sum.rate_limited_periods[1]);
}

/* A file-size limit of `bytes` for this process (EFBIG past it, SIGXFSZ ignored): a write
 * error on a regular file, without a full disk. Returns the old limit. */
static struct rlimit limit_file_size(rlim_t bytes, void (**prev)(int))
{
    struct rlimit old;
    TEST_ASSERT_EQUAL_INT(0, getrlimit(RLIMIT_FSIZE, &old));
    struct rlimit lim = old;
    lim.rlim_cur = bytes;
    *prev = signal(SIGXFSZ, SIG_IGN);
    TEST_ASSERT_EQUAL_INT(0, setrlimit(RLIMIT_FSIZE, &lim));
    return old;
}

static void restore_file_size(const struct rlimit *old, void (*prev)(int))
{
    TEST_ASSERT_EQUAL_INT(0, setrlimit(RLIMIT_FSIZE, old));
    (void)signal(SIGXFSZ, prev);
}

static void test_write_errors_are_io(void)
{
    cdpr_scenario_t sc;
    scenario(&sc);
    cdpr_summary_t s;
    fill(&s);
    /* Outputs go to regular files only: a device is refused at the open, before any write. */
    TEST_ASSERT_EQUAL_INT(CDPR_E_IO, cdpr_summary_write("/dev/full", &sc, &s));
    TEST_ASSERT_EQUAL_INT(CDPR_E_IO,
                          cdpr_summary_write("/nonexistent-cdpr-dir/summary.json", &sc, &s));
    cdpr_csv_t c;
    TEST_ASSERT_EQUAL_INT(CDPR_E_IO, cdpr_csv_open(&c, "/dev/full"));
    TEST_ASSERT_EQUAL_INT(EINVAL, c.error);
    /* The CSV writer on a regular file that cannot grow: the error shows at the close. */
    mkdir(CDPR_TEST_TMP, 0775);
    void (*prev)(int);
    const struct rlimit old = limit_file_size(100, &prev);
    const cdpr_status_t open_st = cdpr_csv_open(&c, CDPR_TEST_TMP "/no-room.csv");
    for (int i = 0; i < 10000; ++i) {
        cdpr_csv_num(&c, 0.1 * (double)i);
    }
    cdpr_csv_end_row(&c);
    const cdpr_status_t close_st = cdpr_csv_close(&c);
    restore_file_size(&old, prev);
    TEST_ASSERT_EQUAL_INT(CDPR_OK, open_st);
    TEST_ASSERT_EQUAL_INT(CDPR_E_IO, close_st);
    /* The recorder in a directory that cannot be created (below a file). */
    cdpr_record_t rec;
    cdpr_scenario_error_t err;
    memset(&s, 0, sizeof s);
    TEST_ASSERT_EQUAL_INT(CDPR_E_IO,
                          cdpr_record_open(&rec, &sc, NULL, "/dev/null/out", 6, &s, &err));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err.msg, "/dev/null/out"), err.msg);
}

/* A FIFO where an output goes: refused at once (a blocking open would wait forever for a
 * reader), and nothing is written to it. */
static void test_outputs_refuse_a_fifo_without_blocking(void)
{
    mkdir(CDPR_TEST_TMP, 0775);
    const char *path = CDPR_TEST_TMP "/fifo.json";
    (void)unlink(path);
    TEST_ASSERT_EQUAL_INT(0, mkfifo(path, 0600));
    cdpr_scenario_t sc;
    scenario(&sc);
    cdpr_summary_t s;
    fill(&s);
    TEST_ASSERT_EQUAL_INT(CDPR_E_IO, cdpr_summary_write(path, &sc, &s));
    cdpr_csv_t c;
    TEST_ASSERT_EQUAL_INT(CDPR_E_IO, cdpr_csv_open(&c, path));
    /* With a reader on the FIFO the open succeeds at once, and the file check refuses it. */
    const int rd = open(path, O_RDONLY | O_NONBLOCK);
    TEST_ASSERT_TRUE(rd >= 0);
    TEST_ASSERT_EQUAL_INT(CDPR_E_IO, cdpr_csv_open(&c, path));
    TEST_ASSERT_EQUAL_INT(EINVAL, c.error);
    TEST_ASSERT_EQUAL_INT(CDPR_E_IO, cdpr_summary_write(path, &sc, &s));
    char b[16];
    TEST_ASSERT_TRUE(read(rd, b, sizeof b) <= 0); /* nothing written */
    (void)close(rd);
    (void)unlink(path);
}

/* Every line of `text` ends with '\n' and has `fields` comma-separated fields; returns lines. */
static int whole_rows(const char *text, int fields)
{
    int lines = 0;
    int commas = 0;
    for (const char *p = text; *p != '\0'; ++p) {
        if (*p == ',') {
            commas++;
        } else if (*p == '\n') {
            TEST_ASSERT_EQUAL_INT_MESSAGE(fields - 1, commas, "a torn row");
            commas = 0;
            lines++;
        }
    }
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, commas, "the file ends inside a row");
    TEST_ASSERT_TRUE(text[0] == '\0' || text[strlen(text) - 1] == '\n');
    return lines;
}

static void test_csv_cut_mid_row_leaves_whole_rows(void)
{
    /* A file-size limit of 3000 bytes (EFBIG past it, SIGXFSZ ignored) falls inside a row of
     * 40 fields of 20 bytes: the writer must cut the file back to the last whole row. With
     * stdio, the file ended at byte 3000, inside row 4. */
    mkdir(CDPR_TEST_TMP, 0775);
    const char *path = CDPR_TEST_TMP "/limited.csv";
    void (*prev)(int);
    const struct rlimit old = limit_file_size(3000, &prev);
    cdpr_csv_t c;
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_csv_open(&c, path));
    for (int r = 0; r < 100; ++r) {
        for (int i = 0; i < 40; ++i) {
            cdpr_csv_num(&c, 1.0 / 3.0 + (double)(r * 40 + i)); /* 17-20 digits */
        }
        cdpr_csv_end_row(&c);
    }
    const cdpr_status_t st = cdpr_csv_close(&c);
    restore_file_size(&old, prev);
    TEST_ASSERT_EQUAL_INT(CDPR_E_IO, st);
    const char *text = slurp(path);
    const int rows = whole_rows(text, 40);
    TEST_ASSERT_TRUE_MESSAGE(rows >= 1 && strlen(text) <= 3000, text);
}

static void test_write_error_keeps_errno(void)
{
    /* A regular file that cannot grow: every write fails with EFBIG. */
    mkdir(CDPR_TEST_TMP, 0775);
    void (*prev)(int);
    const struct rlimit old = limit_file_size(0, &prev);
    cdpr_csv_t c;
    const cdpr_status_t open_st = cdpr_csv_open(&c, CDPR_TEST_TMP "/no-room-2.csv");
    cdpr_csv_num(&c, 1.0);
    cdpr_csv_end_row(&c);
    const cdpr_status_t flush_st = cdpr_csv_flush(&c);
    const int flush_errno = c.error;
    const cdpr_status_t close_st = cdpr_csv_close(&c);
    restore_file_size(&old, prev);
    TEST_ASSERT_EQUAL_INT(CDPR_OK, open_st);
    TEST_ASSERT_EQUAL_INT(CDPR_E_IO, flush_st);
    TEST_ASSERT_EQUAL_INT(EFBIG, flush_errno);
    TEST_ASSERT_EQUAL_INT(CDPR_E_IO, close_st);
    TEST_ASSERT_EQUAL_INT(EFBIG, c.error);
}

static void test_status_names_round_trip(void)
{
    mkdir(CDPR_TEST_TMP, 0775);
    const char *path = CDPR_TEST_TMP "/status.json";
    const struct {
        cdpr_summary_status_t st;
        const char *name;
    } all[] = {{CDPR_SUMMARY_OK, "ok"},
               {CDPR_SUMMARY_WARNINGS, "warnings"},
               {CDPR_SUMMARY_FAILED, "failed"},
               {CDPR_SUMMARY_INTERRUPTED, "interrupted"},
               {CDPR_SUMMARY_IO_ERROR, "io_error"}};
    cdpr_scenario_t sc;
    scenario(&sc);
    for (size_t i = 0; i < sizeof all / sizeof all[0]; ++i) {
        cdpr_summary_t s;
        fill(&s);
        s.status = all[i].st;
        TEST_ASSERT_EQUAL_STRING(all[i].name, cdpr_summary_status_name(all[i].st));
        TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_summary_write(path, &sc, &s));
        char line[64];
        snprintf(line, sizeof line, "\"status\": \"%s\",", all[i].name);
        TEST_ASSERT_NOT_NULL_MESSAGE(strstr(slurp(path), line), line);
        cdpr_summary_t b;
        cdpr_scenario_error_t err;
        TEST_ASSERT_EQUAL_INT_MESSAGE(CDPR_OK, cdpr_summary_read(path, &b, &err), err.msg);
        TEST_ASSERT_EQUAL_INT_MESSAGE(all[i].st, b.status, all[i].name);
    }
}

static void test_rows_at_output_instants_when_periods_are_skipped(void)
{
    /* 20 Hz rows at 100 Hz: an instant every 5 periods. A recorder that sees periods
     * 0..21 except 5, 10, 15, 20 (a tracker that skipped those states) writes a row at the
     * first period at or after each instant: 0, 6, 11, 16, 21. k % 5 wrote only 0. */
    mkdir(CDPR_TEST_TMP, 0775);
    cdpr_scenario_t sc;
    scenario(&sc);
    sc.output_rate_hz = 20.0;
    cdpr_summary_t sum;
    memset(&sum, 0, sizeof sum);
    cdpr_record_t rec;
    cdpr_scenario_error_t err;
    TEST_ASSERT_EQUAL_INT(CDPR_OK,
                          cdpr_record_open(&rec, &sc, NULL, CDPR_TEST_TMP "/skip", 2, &sum, &err));
    for (long k = 0; k <= 21; ++k) {
        if (k == 0 || k % 5 != 0) {
            period(&rec, k, 20, 20, 0.0, 0.0);
        }
    }
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_record_close(&rec));
    const char *text = slurp(CDPR_TEST_TMP "/skip/timeseries.csv");
    const long expected[] = {0, 6, 11, 16, 21};
    const char *p = strstr(text, "\nt_s,");
    TEST_ASSERT_NOT_NULL(p);
    int rows = 0;
    for (p = strchr(p + 1, '\n'); p != NULL && p[1] != '\0'; p = strchr(p + 1, '\n')) {
        TEST_ASSERT_TRUE_MESSAGE(rows < 5, p);
        /* The row's t_s is the one period() recorded: 0.01 k. */
        TEST_ASSERT_EQUAL_DOUBLE(0.01 * (double)expected[rows], strtod(p + 1, NULL));
        rows++;
    }
    TEST_ASSERT_EQUAL_INT(5, rows);
}

static void test_read_errors(void)
{
    mkdir(CDPR_TEST_TMP, 0775);
    cdpr_summary_t s;
    cdpr_scenario_error_t err;
    TEST_ASSERT_EQUAL_INT(CDPR_E_IO, cdpr_summary_read(CDPR_TEST_TMP "/missing.json", &s, &err));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err.msg, "missing.json"), err.msg);
    write_text(CDPR_TEST_TMP "/partial.json", "{\"status\": \"ok\"}\n");
    TEST_ASSERT_EQUAL_INT(CDPR_E_PARSE, cdpr_summary_read(CDPR_TEST_TMP "/partial.json", &s, &err));
    write_text(CDPR_TEST_TMP "/empty.json", "");
    TEST_ASSERT_EQUAL_INT(CDPR_E_PARSE, cdpr_summary_read(CDPR_TEST_TMP "/empty.json", &s, &err));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err.msg, "empty"), err.msg);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_csv_header_and_row);
    RUN_TEST(test_summary_written_then_read_back_equal);
    RUN_TEST(test_provenance_of_an_existing_scenario_file);
    RUN_TEST(test_unknown_values_are_null_both_ways);
    RUN_TEST(test_summary_without_provenance_keys_reads);
    RUN_TEST(test_node_events_from_segment_counts);
    RUN_TEST(test_rate_limited_periods);
    RUN_TEST(test_write_errors_are_io);
    RUN_TEST(test_outputs_refuse_a_fifo_without_blocking);
    RUN_TEST(test_read_errors);
    RUN_TEST(test_csv_cut_mid_row_leaves_whole_rows);
    RUN_TEST(test_write_error_keeps_errno);
    RUN_TEST(test_status_names_round_trip);
    RUN_TEST(test_rows_at_output_instants_when_periods_are_skipped);
    return UNITY_END() ? 1 : 0;
}
