/* SPDX-License-Identifier: BSD-3-Clause */
/// @file test_rig.c
/// Robot files (rig.h, docs/robots.md "Robot files"): the shipped robots/paper-50m.yaml and
/// robots/fast.yaml build the core parameters byte for byte as the compiled presets do; a
/// scenario naming a robot file or embedding a robot resolves to the same plant as the
/// preset; per-cable values (ropes, segments) reach the core; cable counts 1..CDPR_MAX_CABLES
/// load and the six-cable features refuse the others; every bad value is reported with
/// file, line and key (inertia: symmetric, positive definite, triangle inequalities).
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "cdpr/host/plant.h"
#include "cdpr/host/rig.h"
#include "cdpr/host/scenario.h"
#include "text_files.h"
#include "unity.h"

void setUp(void) {}
void tearDown(void) {}

/* The core parameters with every padding byte zero: each scalar copied into a zeroed object
 * (struct assignment would copy padding, which no build defines), so memcmp compares the
 * values' bytes, all of them. */
static void canon_cable(const cdpr_cable_params_t *in, cdpr_cable_params_t *out)
{
    out->d0_m = in->d0_m;
    out->rho_kg_per_m = in->rho_kg_per_m;
    out->ea_N = in->ea_N;
    out->damping_Ns = in->damping_Ns;
    out->damping_ratio = in->damping_ratio;
    out->damping_ref_hz = in->damping_ref_hz;
    out->cd = in->cd;
    out->cm = in->cm;
    out->rho_air_kg_per_m3 = in->rho_air_kg_per_m3;
    out->slack_law = in->slack_law;
}

static void canon(const cdpr_robot_params_t *in, cdpr_robot_params_t *out)
{
    TEST_ASSERT_EQUAL_size_t_MESSAGE(10 * 8, sizeof in->cables[0].cable,
                                     "cdpr_cable_params_t changed: update canon_cable");
    TEST_ASSERT_EQUAL_size_t_MESSAGE(4 + 4 + CDPR_MAX_CABLES * 144 + 8 + 24 + 72 + 8 + 4 + 4 + 24,
                                     sizeof *in, "cdpr_robot_params_t changed: update canon");
    memset(out, 0, sizeof *out);
    out->n_cables = in->n_cables;
    for (int j = 0; j < CDPR_MAX_CABLES; ++j) {
        canon_cable(&in->cables[j].cable, &out->cables[j].cable);
        out->cables[j].exit_point_m = in->cables[j].exit_point_m;
        out->cables[j].attach_body_m = in->cables[j].attach_body_m;
        out->cables[j].n_segments = in->cables[j].n_segments;
        out->cables[j].length_m = in->cables[j].length_m;
    }
    out->cabin.mass_kg = in->cabin.mass_kg;
    out->cabin.com_body_m = in->cabin.com_body_m;
    out->cabin.inertia_com_kg_m2 = in->cabin.inertia_com_kg_m2;
    out->g_m_per_s2 = in->g_m_per_s2;
    out->mode = in->mode;
    out->has_tension_dist = in->has_tension_dist;
    out->tension_min_N = in->tension_min_N;
    out->tension_max_N = in->tension_max_N;
    out->tension_ref_N = in->tension_ref_N;
}

static void assert_same_params(const cdpr_robot_params_t *a, const cdpr_robot_params_t *b,
                               const char *what)
{
    static cdpr_robot_params_t ca;
    static cdpr_robot_params_t cb;
    canon(a, &ca);
    canon(b, &cb);
    TEST_ASSERT_EQUAL_MEMORY_MESSAGE(&ca, &cb, sizeof ca, what);
}

/* Byte-for-byte equality of the preset's build and the robot file's build (values; the
 * winch parameters have no padding). */
static void check_file_equals_preset(const char *file, cdpr_preset_t preset)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/%s", CDPR_SOURCE_DIR, file);
    static cdpr_rig_t rig;
    cdpr_rig_error_t err;
    const cdpr_status_t st = cdpr_rig_load(path, &rig, &err);
    TEST_ASSERT_EQUAL_INT_MESSAGE(CDPR_OK, st, err.msg);
    TEST_ASSERT_EQUAL_INT(6, rig.n_cables);

    cdpr_preset_config_t cfg;
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_preset_get(preset, &cfg));
    static cdpr_robot_params_t p_preset;
    static cdpr_robot_params_t p_file;
    cdpr_winch_params_t w_preset;
    cdpr_winch_params_t w_file[CDPR_MAX_CABLES];
    memset(&p_preset, 0, sizeof p_preset);
    memset(&p_file, 0, sizeof p_file);
    memset(&w_preset, 0, sizeof w_preset);
    memset(w_file, 0, sizeof w_file);
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_preset_build(&cfg, NULL, &p_preset, &w_preset, NULL));
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_rig_build(&rig, NULL, &p_file, w_file, NULL));
    assert_same_params(&p_preset, &p_file, file);
    for (int j = 0; j < CDPR_MAX_CABLES; ++j) {
        TEST_ASSERT_EQUAL_MEMORY_MESSAGE(&w_preset, &w_file[j], sizeof w_preset, file);
    }
    /* With given lengths too (the plant's second build, after the IK). */
    const double lengths[6] = {31.0, 31.5, 32.0, 32.5, 33.0, 33.5};
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_preset_build(&cfg, lengths, &p_preset, NULL, NULL));
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_rig_build(&rig, lengths, &p_file, NULL, NULL));
    assert_same_params(&p_preset, &p_file, file);
    /* (cdpr_preset_build is cdpr_rig_build of cdpr_rig_from_preset: the comparison above,
     * with the robot file read independently, is what checks the conversion.) */
    /* Everything the file holds besides the core parameters: wind and the nominal pose. */
    TEST_ASSERT_EQUAL_MEMORY(cfg.wind_m_per_s, rig.wind_m_per_s, sizeof rig.wind_m_per_s);
    TEST_ASSERT_EQUAL_MEMORY(cfg.nominal_pose, rig.nominal_pose, sizeof rig.nominal_pose);
}

static void test_shipped_robot_files_equal_the_presets_bit_for_bit(void)
{
    check_file_equals_preset("robots/paper-50m.yaml", CDPR_PRESET_PAPER_50M);
    check_file_equals_preset("robots/fast.yaml", CDPR_PRESET_FAST);
}

/* A scenario with robot: {file: ...} and one with the preset give the same plant parameters. */
static void test_scenario_with_robot_file_equals_preset(void)
{
    make_tmp();
    char src[1024];
    snprintf(src, sizeof src, "%s/scenarios/paper-circle.yaml", CDPR_SOURCE_DIR);
    static cdpr_scenario_t a;
    static cdpr_scenario_t b;
    cdpr_scenario_error_t err;
    TEST_ASSERT_EQUAL_INT_MESSAGE(CDPR_OK, cdpr_scenario_load(src, &a, &err), err.msg);

    /* The same scenario text with its robot section replaced by a file reference. */
    FILE *f = fopen(src, "r");
    TEST_ASSERT_NOT_NULL(f);
    static char text[16384];
    const size_t n = fread(text, 1, sizeof text - 1, f);
    text[n] = '\0';
    fclose(f);
    char *robot = strstr(text, "robot:\n");
    char *initial = strstr(text, "initial:\n");
    TEST_ASSERT_NOT_NULL(robot);
    TEST_ASSERT_NOT_NULL(initial);
    static char out[16384];
    char file_ref[1200];
    snprintf(file_ref, sizeof file_ref, "robot:\n  file: %s/robots/paper-50m.yaml\n",
             CDPR_SOURCE_DIR);
    snprintf(out, sizeof out, "%.*s%s%s", (int)(robot - text), text, file_ref, initial);
    char path[1024];
    snprintf(path, sizeof path, "%s/file-robot.yaml", tmp_dir);
    write_text(path, out);
    TEST_ASSERT_EQUAL_INT_MESSAGE(CDPR_OK, cdpr_scenario_load(path, &b, &err), err.msg);
    TEST_ASSERT_EQUAL_INT(CDPR_ROBOT_FROM_FILE, b.robot_source);
    TEST_ASSERT_EQUAL_INT(20, cdpr_scenario_segments(&b));

    static cdpr_plant_params_t pa;
    static cdpr_plant_params_t pb;
    memset(&pa, 0, sizeof pa);
    memset(&pb, 0, sizeof pb);
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_host_plant_params(&a, &pa, &err));
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_host_plant_params(&b, &pb, &err));
    assert_same_params(&pa.robot, &pb.robot, "plant robot");
    TEST_ASSERT_EQUAL_MEMORY(&pa.winch, &pb.winch, sizeof pa.winch);
    TEST_ASSERT_EQUAL_MEMORY(&pa.wind_m_per_s, &pb.wind_m_per_s, sizeof pa.wind_m_per_s);
}

/* The example rig (irregular towers, per-cable rope) and its scenario (relative file path). */
static void test_example_rig_and_its_scenario(void)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/scenarios/example-rig-circle.yaml", CDPR_SOURCE_DIR);
    static cdpr_scenario_t sc;
    cdpr_scenario_error_t err;
    TEST_ASSERT_EQUAL_INT_MESSAGE(CDPR_OK, cdpr_scenario_load(path, &sc, &err), err.msg);
    TEST_ASSERT_EQUAL_INT(CDPR_ROBOT_FROM_FILE, sc.robot_source);
    TEST_ASSERT_NOT_NULL(strstr(cdpr_scenario_robot_name(&sc), "robots/example-rig.yaml"));
    static cdpr_robot_params_t p;
    cdpr_winch_params_t w[CDPR_MAX_CABLES];
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_scenario_build_robot(&sc, NULL, &p, w, NULL));
    TEST_ASSERT_EQUAL_INT(6, p.n_cables);
    TEST_ASSERT_EQUAL_DOUBLE(-13.5, p.cables[2].exit_point_m.x);
    TEST_ASSERT_EQUAL_DOUBLE(32.5, p.cables[2].exit_point_m.z);
    TEST_ASSERT_EQUAL_DOUBLE(-0.45, p.cables[1].attach_body_m.z);
    /* Cable 4's own rope and segments; the others the defaults. */
    TEST_ASSERT_EQUAL_DOUBLE(3.5e6, p.cables[3].cable.ea_N);
    TEST_ASSERT_EQUAL_DOUBLE(0.002, p.cables[3].cable.damping_ratio);
    TEST_ASSERT_EQUAL_DOUBLE(0.0, p.cables[3].cable.damping_Ns);
    TEST_ASSERT_EQUAL_INT(24, p.cables[3].n_segments);
    TEST_ASSERT_EQUAL_DOUBLE(2.0e6, p.cables[0].cable.ea_N);
    TEST_ASSERT_EQUAL_DOUBLE(170.0, p.cables[0].cable.damping_Ns);
    TEST_ASSERT_EQUAL_INT(20, p.cables[5].n_segments);
    TEST_ASSERT_EQUAL_DOUBLE(1.2, p.cables[4].cable.rho_air_kg_per_m3);
    /* Full inertia and CoM. */
    TEST_ASSERT_EQUAL_DOUBLE(-1.2, p.cabin.inertia_com_kg_m2.m[2][0]);
    TEST_ASSERT_EQUAL_DOUBLE(0.9, p.cabin.inertia_com_kg_m2.m[1][2]);
    TEST_ASSERT_EQUAL_DOUBLE(0.05, p.cabin.com_body_m.z);
    /* Per-cable winch limits: cable 2 has its own, the others the defaults. */
    TEST_ASSERT_EQUAL_DOUBLE(4.0, w[0].u_max_m_per_s);
    TEST_ASSERT_EQUAL_DOUBLE(4.5, w[1].u_max_m_per_s);
    TEST_ASSERT_EQUAL_DOUBLE(4.0, w[1].a_max_m_per_s2);
    TEST_ASSERT_EQUAL_DOUBLE(5.0, w[2].a_max_m_per_s2);
    /* The plant starts (IK, catenaries, settling) on it. */
    static cdpr_plant_t plant;
    TEST_ASSERT_EQUAL_INT_MESSAGE(CDPR_OK, cdpr_host_plant_init(&plant, &sc, NULL, &err), err.msg);
}

static const char EMBEDDED[] =
    "robot:\n"
    "  gravity_m_per_s2: 9.81\n"
    "  cabin:\n"
    "    mass_kg: 40.0\n"
    "    inertia_kg_m2:\n"
    "      - [45.0, 0.0, 0.0]\n"
    "      - [0.0, 45.0, 0.0]\n"
    "      - [0.0, 0.0, 90.0]\n"
    "  rope: {d0_m: 0.006, rho_kg_per_m: 0.14, ea_N: 2.0e6, "
    "damping_Ns: 170.0}\n"
    "  winch: {u_max_m_per_s: 4.0, a_max_m_per_s2: 5.0, kp_per_s: 5.0, "
    "min_length_m: 0.5}\n"
    "  segments: 10\n"
    "  cables:\n"
    "    - {exit_m: [25.0, 0.0, 30.0], attach_m: [1.8, 0.8, -0.5]}\n"
    "    - {exit_m: [12.5, 21.6, 30.0], attach_m: [1.6, 1.1, -0.5]}\n"
    "    - exit_m: [-12.5, 21.6, 30.0]\n"
    "      attach_m: [-1.6, 1.1, -0.5]\n"
    "      rope:\n"
    "        ea_N: 2.5e6\n"
    "    - {exit_m: [-25.0, 0.0, 30.0], attach_m: [-1.8, 0.8, -0.5]}\n"
    "    - {exit_m: [-12.5, -21.6, 30.0], attach_m: [-0.2, -2.0, -0.5]}\n"
    "    - {exit_m: [12.5, -21.6, 30.0], attach_m: [0.2, -2.0, -0.5]}\n"
    "trajectory:\n"
    "  type: hold\n"
    "  hold:\n"
    "    pose: [0.0, 0.0, 9.0, 0.0, 0.0, 0.0]\n"
    "controller:\n"
    "  kp: 0.0\n"
    "  k_length_per_s: 5.0\n"
    "run:\n"
    "  duration_s: 0.1\n"
    "  period_s: 0.01\n";

static void test_embedded_robot(void)
{
    make_tmp();
    char path[1024];
    snprintf(path, sizeof path, "%s/embedded.yaml", tmp_dir);
    write_text(path, EMBEDDED);
    static cdpr_scenario_t sc;
    cdpr_scenario_error_t err;
    TEST_ASSERT_EQUAL_INT_MESSAGE(CDPR_OK, cdpr_scenario_load(path, &sc, &err), err.msg);
    TEST_ASSERT_EQUAL_INT(CDPR_ROBOT_EMBEDDED, sc.robot_source);
    TEST_ASSERT_EQUAL_STRING("embedded", cdpr_scenario_robot_name(&sc));
    TEST_ASSERT_EQUAL_DOUBLE(2.5e6, sc.rig.cable[2].rope.ea_N);
    TEST_ASSERT_EQUAL_DOUBLE(2.0e6, sc.rig.cable[3].rope.ea_N);
    TEST_ASSERT_EQUAL_DOUBLE(9.81, sc.rig.gravity_m_per_s2);
    TEST_ASSERT_EQUAL_INT(10, sc.rig.cable[5].segments);
    /* Defaults of the optional keys (docs/robots.md). */
    TEST_ASSERT_EQUAL_DOUBLE(1.225, sc.rig.cable[0].rope.rho_air_kg_per_m3);
    TEST_ASSERT_EQUAL_DOUBLE(1.2, sc.rig.cable[0].rope.cd);
    TEST_ASSERT_EQUAL_DOUBLE(0.03, sc.rig.cable[0].rope.cm);
    TEST_ASSERT_EQUAL_DOUBLE(5.0, sc.rig.cable[0].rope.damping_ref_hz);
    TEST_ASSERT_EQUAL_INT(CDPR_SLACK_PASSIVE, sc.rig.cable[0].rope.slack_law);
    TEST_ASSERT_EQUAL_DOUBLE(15.0, sc.rig.nominal_pose[2]); /* half the exits' mean height */
    static cdpr_plant_t plant;
    TEST_ASSERT_EQUAL_INT_MESSAGE(CDPR_OK, cdpr_host_plant_init(&plant, &sc, NULL, &err), err.msg);
}

/* A redundant robot (eight cables: the embedded six and two more): it loads; the plant's
 * start needs its tension distribution (tension_distribution:), with which it settles; bad
 * bounds are refused naming the key; a six-cable robot whose start breaks its bounds is
 * refused by the plant's IK. */
static void test_redundant_robot_keys(void)
{
#if CDPR_MAX_CABLES >= 8
    make_tmp();
    static char text[8192];
    static char t2[8192];
    replace(EMBEDDED, "  cables:\n",
            "  cables:\n    - {exit_m: [0.0, 25.0, 30.0], attach_m: [0.0, 1.5, 0.5]}\n"
            "    - {exit_m: [0.0, -25.0, 30.0], attach_m: [0.0, -1.5, 0.5]}\n",
            t2, sizeof t2);
    char path[1024];
    snprintf(path, sizeof path, "%s/eight.yaml", tmp_dir);
    write_text(path, t2);
    static cdpr_scenario_t sc;
    static cdpr_plant_params_t pp;
    static cdpr_plant_t plant;
    cdpr_scenario_error_t err;
    TEST_ASSERT_EQUAL_INT_MESSAGE(CDPR_OK, cdpr_scenario_load(path, &sc, &err), err.msg);
    TEST_ASSERT_EQUAL_INT(8, sc.rig.n_cables);
    TEST_ASSERT_EQUAL_INT(0, sc.rig.has_tension_distribution);
    TEST_ASSERT_EQUAL_INT(CDPR_E_PARSE, cdpr_host_plant_params(&sc, &pp, &err));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err.msg, "8 cables: a redundant robot's initial pose "
                                                 "needs its tension distribution"),
                                 err.msg);
    replace(t2, "  segments: 10\n",
            "  segments: 10\n  tension_distribution: {min_N: 25.0, max_N: 500.0}\n", text,
            sizeof text);
    write_text(path, text);
    TEST_ASSERT_EQUAL_INT_MESSAGE(CDPR_OK, cdpr_scenario_load(path, &sc, &err), err.msg);
    TEST_ASSERT_EQUAL_INT(1, sc.rig.has_tension_distribution);
    TEST_ASSERT_EQUAL_DOUBLE(262.5, sc.rig.tension_ref_N); /* mid-range by default */
    TEST_ASSERT_EQUAL_INT_MESSAGE(CDPR_OK, cdpr_host_plant_init(&plant, &sc, NULL, &err), err.msg);
    for (int j = 0; j < 8; ++j) {
        TEST_ASSERT_TRUE(plant.initial.cable[j].tension_cabin_N >= 25.0 - 1e-6);
    }
    static const struct {
        const char *keys;
        cdpr_status_t st;
        const char *named;
    } bad[4] = {
        {"{min_N: 300.0, max_N: 100.0}", CDPR_E_OUT_OF_RANGE, "robot.tension_distribution.max_N"},
        {"{min_N: 25.0}", CDPR_E_PARSE, "robot.tension_distribution.max_N"},
        {"{min_N: 25.0, max_N: 500.0, ref_N: 600.0}", CDPR_E_OUT_OF_RANGE,
         "robot.tension_distribution.ref_N"},
        {"{min_N: -1.0, max_N: 500.0}", CDPR_E_OUT_OF_RANGE, "robot.tension_distribution.min_N"}};
    for (int i = 0; i < 4; ++i) {
        char line[256];
        snprintf(line, sizeof line, "  segments: 10\n  tension_distribution: %s\n", bad[i].keys);
        replace(t2, "  segments: 10\n", line, text, sizeof text);
        write_text(path, text);
        TEST_ASSERT_EQUAL_INT_MESSAGE(bad[i].st, cdpr_scenario_load(path, &sc, &err), bad[i].keys);
        TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err.msg, bad[i].named), err.msg);
    }
    /* Six cables whose start needs more than 50 N somewhere: refused by the start's IK. */
    replace(EMBEDDED, "  segments: 10\n",
            "  segments: 10\n  tension_distribution: {min_N: 1.0, max_N: 50.0}\n", text,
            sizeof text);
    write_text(path, text);
    TEST_ASSERT_EQUAL_INT_MESSAGE(CDPR_OK, cdpr_scenario_load(path, &sc, &err), err.msg);
    TEST_ASSERT_EQUAL_INT(CDPR_E_INFEASIBLE, cdpr_host_plant_init(&plant, &sc, NULL, &err));
#else
    TEST_IGNORE_MESSAGE("built with CDPR_MAX_CABLES < 8");
#endif
}

/* Fewer cables than six: the robot loads and builds; the plant (sag-aware IK) refuses. */
static void test_other_cable_counts(void)
{
    make_tmp();
    static char text[8192];
    static char t2[8192];
    /* Drop the last two cables. */
    replace(EMBEDDED, "    - {exit_m: [-12.5, -21.6, 30.0], attach_m: [-0.2, -2.0, -0.5]}\n", "",
            t2, sizeof t2);
    replace(t2, "    - {exit_m: [12.5, -21.6, 30.0], attach_m: [0.2, -2.0, -0.5]}\n", "", text,
            sizeof text);
    char path[1024];
    snprintf(path, sizeof path, "%s/four.yaml", tmp_dir);
    write_text(path, text);
    static cdpr_scenario_t sc;
    cdpr_scenario_error_t err;
    TEST_ASSERT_EQUAL_INT_MESSAGE(CDPR_OK, cdpr_scenario_load(path, &sc, &err), err.msg);
    TEST_ASSERT_EQUAL_INT(4, sc.rig.n_cables);
    static cdpr_robot_params_t p;
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_scenario_build_robot(&sc, NULL, &p, NULL, NULL));
    TEST_ASSERT_EQUAL_INT(4, p.n_cables);
    static cdpr_plant_params_t pp;
    TEST_ASSERT_EQUAL_INT(CDPR_E_CAPACITY, cdpr_host_plant_params(&sc, &pp, &err));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err.msg, "4 cables"), err.msg);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err.msg, "needs at least 6"), err.msg);
    /* The tracker too. */
    cdpr_tracker_t *tr = malloc(sizeof *tr);
    TEST_ASSERT_NOT_NULL(tr);
    cdpr_diag_t d;
    TEST_ASSERT_EQUAL_INT(CDPR_E_CAPACITY,
                          cdpr_tracker_init(tr, &p, &sc.traj, &sc.gains, 0.01, 0.0, &d));
    TEST_ASSERT_EQUAL_INT(4, d.index);
    free(tr);
    /* More than CDPR_MAX_CABLES: six plus as many more as the capacity, plus one. */
    char extra[2048] = "  cables:\n";
    for (int j = 6; j <= CDPR_MAX_CABLES; ++j) {
        strcat(extra, "    - {exit_m: [0.0, 25.0, 30.0], attach_m: [0.0, 2.0, -0.5]}\n");
    }
    replace(EMBEDDED, "  cables:\n", extra, text, sizeof text);
    write_text(path, text);
    TEST_ASSERT_EQUAL_INT(CDPR_E_CAPACITY, cdpr_scenario_load(path, &sc, &err));
    char want[64];
    snprintf(want, sizeof want, "robot.cables: %d cables", CDPR_MAX_CABLES + 1);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err.msg, want), err.msg);
}

typedef struct {
    const char *name;
    const char *from; /* text of robots/example-rig.yaml to replace */
    const char *to;
    const char *key;    /* key the message must name */
    const char *marker; /* text on the line the message must name (in the edited file) */
    cdpr_status_t status;
} bad_case_t;

static const bad_case_t BAD[] = {
    {"unknown key in a cable", "      damping_ref_hz: 5.0\n", "      damping_ref_hzz: 5.0\n",
     "cables[3].rope.damping_ref_hzz", "damping_ref_hzz", CDPR_E_PARSE},
    {"NaN exit", "[-13.5, 20.0, 32.5]", "[-13.5, nan, 32.5]", "cables[2].exit_m[1]", "[-13.5, nan",
     CDPR_E_NOT_FINITE},
    {"negative EA per cable", "ea_N: 3.5e6", "ea_N: -3.5e6", "cables[3].rope.ea_N", "ea_N: -3.5e6",
     CDPR_E_OUT_OF_RANGE},
    {"bad default rope", "  ea_N: 2.0e6\n", "  ea_N: 0.0\n", "rope.ea_N (cable 1)", "  ea_N: 0.0",
     CDPR_E_OUT_OF_RANGE},
    {"not symmetric", "    - [0.6, 47.0, 0.9]\n", "    - [0.7, 47.0, 0.9]\n",
     "cabin.inertia_kg_m2[1][0]", "[0.7, 47.0", CDPR_E_OUT_OF_RANGE},
    {"not positive definite", "    - [50.0, 0.6, -1.2]\n", "    - [-50.0, 0.6, -1.2]\n",
     "cabin.inertia_kg_m2", "inertia_kg_m2:", CDPR_E_NOT_POSITIVE},
    {"triangle inequality", "    - [-1.2, 0.9, 93.0]\n", "    - [-1.2, 0.9, 130.0]\n",
     "cabin.inertia_kg_m2", "inertia_kg_m2:", CDPR_E_OUT_OF_RANGE},
    {"both damping forms", "      damping_ratio: 0.002",
     "      damping_Ns: 1.0\n      damping_ratio: 0.002", "cables[3].rope.damping_ratio",
     "damping_ratio: 0.002", CDPR_E_PARSE},
    {"missing attachment", "    attach_m: [-0.15, -2.00, -0.50]\n", "", "cables[4].attach_m",
     "- exit_m: [-12.0, -23.0", CDPR_E_PARSE},
    {"fractional segments", "    segments: 24\n", "    segments: 24.5\n", "cables[3].segments",
     "segments: 24.5", CDPR_E_OUT_OF_RANGE},
    {"attachment on its exit point", "    attach_m: [1.60, 1.20, -0.45]\n",
     "    attach_m: [11.0, 22.5, 19.0]\n", "cables[1]", "- exit_m: [11.0, 22.5",
     CDPR_E_NOT_POSITIVE},
    {"a bad winch limit of one cable", "    segments: 24\n",
     "    segments: 24\n    winch: {kp_per_s: 0.0}\n", "cables[3].winch.kp_per_s",
     "winch: {kp_per_s", CDPR_E_OUT_OF_RANGE},
    {"missing winch limit", "  kp_per_s: 5.0\n", "", "cables[0].winch.kp_per_s", "", CDPR_E_PARSE},
    {"wrong row length", "    - [0.6, 47.0, 0.9]\n", "    - [0.6, 47.0]\n",
     "cabin.inertia_kg_m2[1]", "[0.6, 47.0]", CDPR_E_PARSE},
};

static void test_bad_robot_files_name_file_key_and_line(void)
{
    make_tmp();
    char src[1024];
    snprintf(src, sizeof src, "%s/robots/example-rig.yaml", CDPR_SOURCE_DIR);
    FILE *f = fopen(src, "r");
    TEST_ASSERT_NOT_NULL(f);
    static char good[16384];
    const size_t n = fread(good, 1, sizeof good - 1, f);
    good[n] = '\0';
    fclose(f);
    for (size_t i = 0; i < sizeof BAD / sizeof BAD[0]; ++i) {
        const bad_case_t *c = &BAD[i];
        static char text[16384];
        replace(good, c->from, c->to, text, sizeof text);
        char path[1024];
        snprintf(path, sizeof path, "%s/bad-%zu.yaml", tmp_dir, i);
        write_text(path, text);
        static cdpr_rig_t rig;
        cdpr_rig_error_t err;
        const cdpr_status_t st = cdpr_rig_load(path, &rig, &err);
        char expect[1600];
        const int line = (c->marker[0] != '\0') ? line_of(text, c->marker) : 0;
        if (line > 0) {
            snprintf(expect, sizeof expect, "%s:%d: %s: ", path, line, c->key);
        } else {
            snprintf(expect, sizeof expect, "%s: %s: ", path, c->key);
        }
        char msg[4000];
        snprintf(msg, sizeof msg, "%s: got \"%s\", want prefix \"%s\"", c->name, err.msg, expect);
        TEST_ASSERT_EQUAL_INT_MESSAGE(c->status, st, msg);
        TEST_ASSERT_TRUE_MESSAGE(strncmp(err.msg, expect, strlen(expect)) == 0, msg);
    }
}

/* Scenario-level errors: embedded keys named robot.*, a missing robot file, file + keys. */
static void test_scenario_robot_errors(void)
{
    make_tmp();
    static char text[8192];
    char path[1024];
    snprintf(path, sizeof path, "%s/scn-bad.yaml", tmp_dir);
    static cdpr_scenario_t sc;
    cdpr_scenario_error_t err;

    replace(EMBEDDED, "        ea_N: 2.5e6\n", "        ea_N: inf\n", text, sizeof text);
    write_text(path, text);
    TEST_ASSERT_EQUAL_INT(CDPR_E_NOT_FINITE, cdpr_scenario_load(path, &sc, &err));
    char expect[2400];
    snprintf(expect, sizeof expect, "%s:%d: robot.cables[2].rope.ea_N: ", path,
             line_of(text, "ea_N: inf"));
    TEST_ASSERT_TRUE_MESSAGE(strncmp(err.msg, expect, strlen(expect)) == 0, err.msg);

    replace(EMBEDDED, "  segments: 10\n", "  segmnts: 10\n", text, sizeof text);
    write_text(path, text);
    TEST_ASSERT_EQUAL_INT(CDPR_E_PARSE, cdpr_scenario_load(path, &sc, &err));
    snprintf(expect, sizeof expect, "%s:%d: robot.segmnts: unknown key", path,
             line_of(text, "segmnts"));
    TEST_ASSERT_TRUE_MESSAGE(strncmp(err.msg, expect, strlen(expect)) == 0, err.msg);

    write_text(path, "robot:\n  file: no-such-robot.yaml\ntrajectory:\n  type: hold\n  hold:\n"
                     "    pose: [0, 0, 9, 0, 0, 0]\ncontroller:\n  kp: 0.0\n  k_length_per_s: 5.0\n"
                     "run:\n  duration_s: 0.1\n  period_s: 0.01\n");
    TEST_ASSERT_EQUAL_INT(CDPR_E_IO, cdpr_scenario_load(path, &sc, &err));
    snprintf(expect, sizeof expect, "%s:2: robot.file: %s/no-such-robot.yaml: cannot open", path,
             tmp_dir);
    TEST_ASSERT_TRUE_MESSAGE(strncmp(err.msg, expect, strlen(expect)) == 0, err.msg);

    write_text(path, "robot:\n  file: x.yaml\n  segments: 4\ntrajectory:\n  type: hold\n  hold:\n"
                     "    pose: [0, 0, 9, 0, 0, 0]\ncontroller:\n  kp: 0.0\n  k_length_per_s: 5.0\n"
                     "run:\n  duration_s: 0.1\n  period_s: 0.01\n");
    TEST_ASSERT_EQUAL_INT(CDPR_E_PARSE, cdpr_scenario_load(path, &sc, &err));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err.msg, "robot.file: a robot file takes no other"),
                                 err.msg);

    write_text(path, "robot:\n  gravity_m_per_s2: 9.8\ntrajectory:\n  type: hold\n  hold:\n"
                     "    pose: [0, 0, 9, 0, 0, 0]\ncontroller:\n  kp: 0.0\n  k_length_per_s: 5.0\n"
                     "run:\n  duration_s: 0.1\n  period_s: 0.01\n");
    TEST_ASSERT_EQUAL_INT(CDPR_E_PARSE, cdpr_scenario_load(path, &sc, &err));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err.msg, "robot: needs preset:"), err.msg);
}

/* A robot file is the .yaml/.yml file its path resolves to (links and ".." followed): the
 * summary names that file, and no scenario can make the loader read (and echo in an error)
 * anything else. */
static void test_robot_file_resolved_and_contained(void)
{
    make_tmp();
    char path[1024];
    static cdpr_scenario_t sc;
    cdpr_scenario_error_t err;
    snprintf(path, sizeof path, "%s/scenarios/example-rig-circle.yaml", CDPR_SOURCE_DIR);
    TEST_ASSERT_EQUAL_INT_MESSAGE(CDPR_OK, cdpr_scenario_load(path, &sc, &err), err.msg);
    char want[1024];
    snprintf(want, sizeof want, "%s/robots/example-rig.yaml", CDPR_SOURCE_DIR);
    char *real = realpath(want, NULL);
    TEST_ASSERT_NOT_NULL(real);
    TEST_ASSERT_EQUAL_STRING(real, cdpr_scenario_robot_name(&sc));
    free(real);

    char other[1024];
    snprintf(other, sizeof other, "%s/secret.txt", tmp_dir);
    write_text(other, "TOPSECRET: 1\n");
    char link[1024];
    snprintf(link, sizeof link, "%s/sneaky.yaml", tmp_dir);
    (void)unlink(link);
    TEST_ASSERT_EQUAL_INT(0, symlink("secret.txt", link));
    char dotdot[600];
    snprintf(dotdot, sizeof dotdot, "../%s/secret.txt", strrchr(tmp_dir, '/') + 1);
    const char *const files[] = {"secret.txt", "sneaky.yaml", dotdot};
    snprintf(path, sizeof path, "%s/scn-contained.yaml", tmp_dir);
    for (size_t i = 0; i < sizeof files / sizeof files[0]; ++i) {
        static char text[1024];
        snprintf(text, sizeof text,
                 "robot:\n  file: %s\ntrajectory:\n  type: hold\n  hold:\n"
                 "    pose: [0, 0, 9, 0, 0, 0]\ncontroller:\n  kp: 0.0\n  k_length_per_s: 5.0\n"
                 "run:\n  duration_s: 0.1\n  period_s: 0.01\n",
                 files[i]);
        write_text(path, text);
        const cdpr_status_t st = cdpr_scenario_load(path, &sc, &err);
        TEST_ASSERT_EQUAL_INT_MESSAGE(CDPR_E_IO, st, err.msg);
        TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err.msg, "robot.file: "), err.msg);
        TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err.msg, "not a robot file"), err.msg);
        TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err.msg, "secret.txt)"), err.msg);
        TEST_ASSERT_NULL_MESSAGE(strstr(err.msg, "TOPSECRET"), err.msg);
    }
}

static void test_principal_moments(void)
{
    /* diag(1, 2, 3) rotated by 90 deg about z: the moments are unchanged. */
    const double m[3][3] = {{2.0, 0.0, 0.0}, {0.0, 1.0, 0.0}, {0.0, 0.0, 3.0}};
    double e[3];
    cdpr_rig_principal_moments(m, e);
    TEST_ASSERT_EQUAL_DOUBLE(1.0, e[0]);
    TEST_ASSERT_EQUAL_DOUBLE(3.0, e[2]);
    /* [[2,1,0],[1,2,0],[0,0,5]]: 1, 3, 5. */
    const double n[3][3] = {{2.0, 1.0, 0.0}, {1.0, 2.0, 0.0}, {0.0, 0.0, 5.0}};
    cdpr_rig_principal_moments(n, e);
    TEST_ASSERT_DOUBLE_WITHIN(1e-12, 1.0, e[0]);
    TEST_ASSERT_DOUBLE_WITHIN(1e-12, 3.0, e[1]);
    TEST_ASSERT_DOUBLE_WITHIN(1e-12, 5.0, e[2]);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_shipped_robot_files_equal_the_presets_bit_for_bit);
    RUN_TEST(test_scenario_with_robot_file_equals_preset);
    RUN_TEST(test_example_rig_and_its_scenario);
    RUN_TEST(test_embedded_robot);
    RUN_TEST(test_other_cable_counts);
    RUN_TEST(test_redundant_robot_keys);
    RUN_TEST(test_bad_robot_files_name_file_key_and_line);
    RUN_TEST(test_robot_file_resolved_and_contained);
    RUN_TEST(test_scenario_robot_errors);
    RUN_TEST(test_principal_moments);
    return UNITY_END();
}
