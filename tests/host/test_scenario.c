/* SPDX-License-Identifier: BSD-3-Clause */
/// @file test_scenario.c
/// Scenario files: a file using every key resolves to exactly the values written in it;
/// omitted keys take the preset's values (docs/robots.md, typed in here independently);
/// the committed scenarios load with the paper's numbers; and every kind of bad file (missing
/// key, wrong type, unknown key, NaN/Inf, out of range, wrong length, inconsistent sections,
/// unreachable pose, broken YAML) is rejected with a message naming the file, the key and
/// the line, and makes cdpr-sim exit with status 2.
#include <fcntl.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "cdpr/host/plant.h"
#include "cdpr/host/scenario.h"
#include "cdpr/host/sim.h"
#include "cdpr/host/yaml.h"
#include "text_files.h"
#include "unity.h"

void setUp(void) {}
void tearDown(void) {}

static const double PI = 3.14159265358979323846;

/* Every key of the format, each value different from the preset's. */
static const char GOOD_LINE[] = "description: \"test: every key\"\n"
                                "robot:\n"
                                "  preset: paper-50m\n"
                                "  segments: 12\n"
                                "  gravity_m_per_s2: 9.81\n"
                                "  air_density_kg_per_m3: 1.2\n"
                                "  wind_m_per_s: [1.0, -0.5, 0.0]\n"
                                "  towers:\n"
                                "    radius_m: 26.0\n"
                                "    exit_height_m: 31.0\n"
                                "    azimuths_deg: [1, 61, 121, 181, 241, 301]\n"
                                "  attachments:\n"
                                "    radius_m: 2.1\n"
                                "    z_m: -0.4\n"
                                "    azimuths_deg: [24, 36, 144, 156, 264, 276]\n"
                                "  cabin:\n"
                                "    mass_kg: 41.0\n"
                                "    inertia_kg_m2: [[50.0, 0.5, -0.25], [0.5, 46.0, 0.125], "
                                "[-0.25, 0.125, 91.0]]\n"
                                "    com_m: [0.01, -0.02, 0.03]\n"
                                "  rope:\n"
                                "    d0_m: 0.007\n"
                                "    rho_kg_per_m: 0.15\n"
                                "    ea_N: 2.5e6\n"
                                "    damping_Ns: 160.0\n"
                                "    cd: 1.1\n"
                                "    cm: 0.04\n"
                                "  winch:\n"
                                "    u_max_m_per_s: 3.5\n"
                                "    a_max_m_per_s2: 4.5\n"
                                "    kp_per_s: 4.0\n"
                                "    min_length_m: 0.75\n"
                                "initial:\n"
                                "  pose: [0.1, 0.2, 10.0, 0.01, -0.02, 0.03]\n"
                                "  offset: [0.0, 0.001, -0.01, 0.0, 0.0, 0.002]\n"
                                "trajectory:\n"
                                "  type: line\n"
                                "  line:\n"
                                "    from: [0.1, 0.2, 10.0, 0.01, -0.02, 0.03]\n"
                                "    to: [0.5, -0.3, 11.0, 0.02, 0.01, -0.04]\n"
                                "    duration_s: 10.0\n"
                                "    pause_s: 1.5\n"
                                "    back_and_forth: true\n"
                                "controller:\n"
                                "  kp: 0.5\n"
                                "  kd_s: 0.05\n"
                                "  k_length_per_s: 4.0\n"
                                "  filter_s: 0.25\n"
                                "  inertial_ff: 0.5\n"
                                "  damping_N_s_per_m: 30.0\n"
                                "  damping_rot_N_m_s: 20.0\n"
                                "  model:\n"
                                "    ea_scale: 0.9\n"
                                "    cabin_mass_scale: 1.1\n"
                                "    rope_mass_scale: 1.05\n"
                                "integrator:\n"
                                "  rtol: 1.0e-7\n"
                                "  atol_position_m: 2.0e-6\n"
                                "  atol_velocity_m_per_s: 3.0e-5\n"
                                "  atol_quaternion: 4.0e-8\n"
                                "  atol_rate_rad_per_s: 5.0e-6\n"
                                "  h_max_s: 0.005\n"
                                "  max_trials: 300\n"
                                "  max_attempts: 2\n"
                                "run:\n"
                                "  duration_s: 12.0\n"
                                "  period_s: 0.02\n"
                                "  output_rate_hz: 25\n";

/* The smallest valid file: required keys only. */
static const char MINIMAL[] = "robot:\n"
                              "  preset: paper-50m\n"
                              "trajectory:\n"
                              "  type: circle\n"
                              "  circle:\n"
                              "    centre_m: [0.0, -2.0, 9.135]\n"
                              "    radius_m: 2.0\n"
                              "    speed_m_per_s: 2.0\n"
                              "    start_angle_deg: 90\n"
                              "controller:\n"
                              "  kp: 0.0\n"
                              "  k_length_per_s: 5.0\n"
                              "run:\n"
                              "  duration_s: 1.0\n"
                              "  period_s: 0.01\n";

/* Run cdpr-sim with `args`; stdout+stderr into out; returns the exit status. */
static int run_sim(const char *args, char *out, size_t cap)
{
#ifdef CDPR_SIM_EXE
    char cmd[2048];
    snprintf(cmd, sizeof cmd, "'%s' %s 2>&1", CDPR_SIM_EXE, args);
    FILE *p = popen(cmd, "r");
    TEST_ASSERT_NOT_NULL(p);
    const size_t n = fread(out, 1, cap - 1, p);
    out[n] = '\0';
    const int st = pclose(p);
    TEST_ASSERT_TRUE(WIFEXITED(st));
    return WEXITSTATUS(st);
#else
    (void)args;
    snprintf(out, cap, "cdpr-sim not built");
    return -1;
#endif
}

static void test_every_key_resolves_to_the_value_written(void)
{
    make_tmp();
    char path[600];
    snprintf(path, sizeof path, "%s/good_line.yaml", tmp_dir);
    write_text(path, GOOD_LINE);
    cdpr_scenario_t sc;
    cdpr_scenario_error_t err;
    TEST_ASSERT_EQUAL_INT_MESSAGE(CDPR_OK, cdpr_scenario_load(path, &sc, &err), err.msg);
    /* Exact: decimal literals parse to the nearest double, as the C literals below do. */
    TEST_ASSERT_EQUAL_STRING("test: every key", sc.description);
    TEST_ASSERT_EQUAL_INT(CDPR_ROBOT_FROM_PRESET, sc.robot_source);
    TEST_ASSERT_EQUAL_INT(CDPR_PRESET_PAPER_50M, sc.preset);
    TEST_ASSERT_EQUAL_STRING("paper-50m", sc.rig.name);
    const cdpr_rig_t *g = &sc.rig;
    TEST_ASSERT_EQUAL_INT(6, g->n_cables);
    TEST_ASSERT_EQUAL_DOUBLE(9.81, g->gravity_m_per_s2);
    TEST_ASSERT_EQUAL_DOUBLE(1.0, g->wind_m_per_s[0]);
    TEST_ASSERT_EQUAL_DOUBLE(-0.5, g->wind_m_per_s[1]);
    /* The polar layout, evaluated here from its definition (docs/robots.md): exit points at
     * radius 26 m, height 31 m, azimuths 1 + 60 j deg; attachments at 2.1 m, z -0.4 m. */
    const double exit_deg[6] = {1, 61, 121, 181, 241, 301};
    const double att_deg[6] = {24, 36, 144, 156, 264, 276};
    for (int j = 0; j < 6; ++j) {
        const cdpr_rig_cable_t *k = &g->cable[j];
        TEST_ASSERT_DOUBLE_WITHIN(1e-12, 26.0 * cos(exit_deg[j] * PI / 180.0), k->exit_m[0]);
        TEST_ASSERT_DOUBLE_WITHIN(1e-12, 26.0 * sin(exit_deg[j] * PI / 180.0), k->exit_m[1]);
        TEST_ASSERT_EQUAL_DOUBLE(31.0, k->exit_m[2]);
        TEST_ASSERT_DOUBLE_WITHIN(1e-12, 2.1 * cos(att_deg[j] * PI / 180.0), k->attach_m[0]);
        TEST_ASSERT_DOUBLE_WITHIN(1e-12, 2.1 * sin(att_deg[j] * PI / 180.0), k->attach_m[1]);
        TEST_ASSERT_EQUAL_DOUBLE(-0.4, k->attach_m[2]);
        /* Robot-level rope, winch, segments and air density: every cable. */
        TEST_ASSERT_EQUAL_INT(12, k->segments);
        TEST_ASSERT_EQUAL_DOUBLE(0.007, k->rope.d0_m);
        TEST_ASSERT_EQUAL_DOUBLE(0.15, k->rope.rho_kg_per_m);
        TEST_ASSERT_EQUAL_DOUBLE(2.5e6, k->rope.ea_N);
        TEST_ASSERT_EQUAL_DOUBLE(160.0, k->rope.damping_Ns);
        TEST_ASSERT_EQUAL_DOUBLE(1.1, k->rope.cd);
        TEST_ASSERT_EQUAL_DOUBLE(0.04, k->rope.cm);
        TEST_ASSERT_EQUAL_DOUBLE(1.2, k->rope.rho_air_kg_per_m3);
        TEST_ASSERT_EQUAL_DOUBLE(3.5, k->winch.u_max_m_per_s);
        TEST_ASSERT_EQUAL_DOUBLE(4.5, k->winch.a_max_m_per_s2);
        TEST_ASSERT_EQUAL_DOUBLE(4.0, k->winch.kp_per_s);
        TEST_ASSERT_EQUAL_DOUBLE(0.75, k->winch.min_length_m);
    }
    TEST_ASSERT_EQUAL_DOUBLE(41.0, g->cabin_mass_kg);
    TEST_ASSERT_EQUAL_DOUBLE(46.0, g->cabin_inertia_kg_m2[1][1]);
    TEST_ASSERT_EQUAL_DOUBLE(0.125, g->cabin_inertia_kg_m2[2][1]);
    TEST_ASSERT_EQUAL_DOUBLE(-0.25, g->cabin_inertia_kg_m2[0][2]);
    TEST_ASSERT_EQUAL_DOUBLE(-0.02, g->cabin_com_m[1]);
    TEST_ASSERT_EQUAL_INT(1, sc.has_initial_pose);
    TEST_ASSERT_EQUAL_DOUBLE(10.0, sc.initial_pose[2]);
    TEST_ASSERT_EQUAL_DOUBLE(0.002, sc.initial_offset[5]);
    TEST_ASSERT_EQUAL_INT(CDPR_TRAJ_LINE, sc.traj.type);
    TEST_ASSERT_EQUAL_DOUBLE(-0.04, sc.traj.to[5]);
    TEST_ASSERT_EQUAL_DOUBLE(10.0, sc.traj.duration_s);
    TEST_ASSERT_EQUAL_DOUBLE(1.5, sc.traj.pause_s);
    TEST_ASSERT_EQUAL_INT(1, sc.traj.back_and_forth);
    TEST_ASSERT_EQUAL_DOUBLE(0.02, sc.period_s);
    TEST_ASSERT_EQUAL_INT(2, sc.integrator.max_attempts);
    TEST_ASSERT_EQUAL_DOUBLE(0.5, sc.gains.kp);
    TEST_ASSERT_EQUAL_DOUBLE(0.05, sc.gains.kd_s);
    TEST_ASSERT_EQUAL_DOUBLE(4.0, sc.gains.k_length_per_s);
    TEST_ASSERT_EQUAL_DOUBLE(0.25, sc.gains.filter_s);
    TEST_ASSERT_EQUAL_DOUBLE(0.5, sc.gains.inertial_ff);
    TEST_ASSERT_EQUAL_DOUBLE(30.0, sc.gains.damping_N_s_per_m);
    TEST_ASSERT_EQUAL_DOUBLE(20.0, sc.gains.damping_rot_N_m_s);
    TEST_ASSERT_EQUAL_DOUBLE(0.9, sc.controller_model.ea);
    TEST_ASSERT_EQUAL_DOUBLE(1.1, sc.controller_model.cabin_mass);
    TEST_ASSERT_EQUAL_DOUBLE(1.05, sc.controller_model.rope_mass);
    /* The controller's model carries the factors, the plant's robot does not. */
    static cdpr_robot_params_t model;
    TEST_ASSERT_EQUAL_INT_MESSAGE(CDPR_OK, cdpr_host_controller_params(&sc, &model, &err), err.msg);
    TEST_ASSERT_EQUAL_DOUBLE(41.0, g->cabin_mass_kg);
    TEST_ASSERT_EQUAL_DOUBLE(41.0 * 1.1, model.cabin.mass_kg);
    TEST_ASSERT_EQUAL_DOUBLE(91.0 * 1.1, model.cabin.inertia_com_kg_m2.m[2][2]);
    TEST_ASSERT_EQUAL_DOUBLE(2.5e6, g->cable[3].rope.ea_N);
    TEST_ASSERT_EQUAL_DOUBLE(2.5e6 * 0.9, model.cables[3].cable.ea_N);
    TEST_ASSERT_EQUAL_DOUBLE(0.15 * 1.05, model.cables[5].cable.rho_kg_per_m);
    TEST_ASSERT_EQUAL_DOUBLE(1.0e-7, sc.integrator.rtol);
    TEST_ASSERT_EQUAL_DOUBLE(2.0e-6, sc.integrator.atol_position_m);
    TEST_ASSERT_EQUAL_DOUBLE(3.0e-5, sc.integrator.atol_velocity_m_per_s);
    TEST_ASSERT_EQUAL_DOUBLE(4.0e-8, sc.integrator.atol_quaternion);
    TEST_ASSERT_EQUAL_DOUBLE(5.0e-6, sc.integrator.atol_rate_rad_per_s);
    TEST_ASSERT_EQUAL_DOUBLE(0.005, sc.integrator.h_max_s);
    TEST_ASSERT_EQUAL_INT(300, sc.integrator.max_trials);
    TEST_ASSERT_EQUAL_DOUBLE(12.0, sc.duration_s);
    TEST_ASSERT_EQUAL_DOUBLE(25.0, sc.output_rate_hz);
    TEST_ASSERT_EQUAL_INT(600, (int)cdpr_scenario_periods(&sc));    /* 12 s / 0.02 s */
    TEST_ASSERT_EQUAL_INT(2, (int)cdpr_scenario_output_every(&sc)); /* 50 Hz / 25 Hz */
    double pose[6];
    cdpr_scenario_initial_pose(&sc, pose);
    TEST_ASSERT_DOUBLE_WITHIN(1e-15, 0.201, pose[1]); /* pose + offset, one rounding */
}

static void test_omitted_keys_take_the_preset(void)
{
    make_tmp();
    char path[600];
    snprintf(path, sizeof path, "%s/minimal.yaml", tmp_dir);
    write_text(path, MINIMAL);
    cdpr_scenario_t sc;
    cdpr_scenario_error_t err;
    TEST_ASSERT_EQUAL_INT_MESSAGE(CDPR_OK, cdpr_scenario_load(path, &sc, &err), err.msg);
    /* docs/robots.md set A, typed in from the table. */
    const cdpr_rig_t *g = &sc.rig;
    const double att[6] = {25.0, 35.0, 145.0, 155.0, 265.0, 275.0};
    for (int j = 0; j < 6; ++j) {
        const cdpr_rig_cable_t *k = &g->cable[j];
        TEST_ASSERT_DOUBLE_WITHIN(1e-12, 25.0 * cos(60.0 * j * PI / 180.0), k->exit_m[0]);
        TEST_ASSERT_DOUBLE_WITHIN(1e-12, 25.0 * sin(60.0 * j * PI / 180.0), k->exit_m[1]);
        TEST_ASSERT_EQUAL_DOUBLE(30.0, k->exit_m[2]);
        TEST_ASSERT_DOUBLE_WITHIN(1e-12, 2.0 * cos(att[j] * PI / 180.0), k->attach_m[0]);
        TEST_ASSERT_DOUBLE_WITHIN(1e-12, 2.0 * sin(att[j] * PI / 180.0), k->attach_m[1]);
        TEST_ASSERT_EQUAL_DOUBLE(-0.5, k->attach_m[2]);
        TEST_ASSERT_EQUAL_DOUBLE(0.006, k->rope.d0_m);
        TEST_ASSERT_EQUAL_DOUBLE(0.14, k->rope.rho_kg_per_m);
        TEST_ASSERT_EQUAL_DOUBLE(2.0e6, k->rope.ea_N);
        TEST_ASSERT_EQUAL_DOUBLE(170.0, k->rope.damping_Ns);
        TEST_ASSERT_EQUAL_DOUBLE(1.2, k->rope.cd);
        TEST_ASSERT_EQUAL_DOUBLE(0.03, k->rope.cm);
        TEST_ASSERT_EQUAL_DOUBLE(1.225, k->rope.rho_air_kg_per_m3);
        TEST_ASSERT_EQUAL_DOUBLE(4.0, k->winch.u_max_m_per_s);
        TEST_ASSERT_EQUAL_DOUBLE(5.0, k->winch.a_max_m_per_s2);
        TEST_ASSERT_EQUAL_INT(20, k->segments);
    }
    TEST_ASSERT_EQUAL_DOUBLE(40.0, g->cabin_mass_kg);
    TEST_ASSERT_EQUAL_DOUBLE(45.0, g->cabin_inertia_kg_m2[0][0]);
    TEST_ASSERT_EQUAL_DOUBLE(90.0, g->cabin_inertia_kg_m2[2][2]);
    TEST_ASSERT_EQUAL_DOUBLE(0.0, g->cabin_inertia_kg_m2[0][1]);
    TEST_ASSERT_EQUAL_DOUBLE(9.80665, g->gravity_m_per_s2);
    /* Documented defaults of the optional sections (docs/scenarios.md). */
    TEST_ASSERT_EQUAL_INT(0, sc.has_initial_pose);
    TEST_ASSERT_EQUAL_DOUBLE(1.0, sc.traj.direction); /* ccw */
    TEST_ASSERT_EQUAL_DOUBLE(0.0, sc.traj.ramp_s);
    TEST_ASSERT_EQUAL_DOUBLE(0.0, sc.gains.kd_s);
    TEST_ASSERT_EQUAL_DOUBLE(1.0, sc.gains.filter_s);
    TEST_ASSERT_EQUAL_DOUBLE(1.0, sc.gains.inertial_ff);
    TEST_ASSERT_EQUAL_DOUBLE(0.0, sc.gains.damping_N_s_per_m);
    TEST_ASSERT_EQUAL_DOUBLE(0.0, sc.gains.damping_rot_N_m_s);
    TEST_ASSERT_EQUAL_INT(1, cdpr_rig_scale_is_unit(&sc.controller_model));
    TEST_ASSERT_EQUAL_DOUBLE(0.0, sc.gains.integral_per_s);
    TEST_ASSERT_EQUAL_DOUBLE(0.05, sc.gains.integral_limit_m);
    TEST_ASSERT_EQUAL_DOUBLE(0.0, sc.gains.weight_estimate_s);
    TEST_ASSERT_EQUAL_DOUBLE(0.0, sc.gains.tension_washout_s);
    TEST_ASSERT_EQUAL_DOUBLE(1e-6, sc.integrator.rtol);
    TEST_ASSERT_EQUAL_INT(2000, sc.integrator.max_trials);
    TEST_ASSERT_EQUAL_INT(1, (int)cdpr_scenario_output_every(&sc));
    /* Initial pose: the circle's start, (0, -2 + 2, 9.135). */
    double pose[6];
    cdpr_scenario_initial_pose(&sc, pose);
    TEST_ASSERT_DOUBLE_WITHIN(1e-15, 0.0, pose[0]);
    TEST_ASSERT_DOUBLE_WITHIN(1e-15, 0.0, pose[1]);
    TEST_ASSERT_EQUAL_DOUBLE(9.135, pose[2]);
}

static void test_committed_scenarios_hold_the_papers_numbers(void)
{
    cdpr_scenario_t sc;
    cdpr_scenario_error_t err;
    TEST_ASSERT_EQUAL_INT_MESSAGE(
        CDPR_OK, cdpr_scenario_load(CDPR_SOURCE_DIR "/scenarios/paper-circle.yaml", &sc, &err),
        err.msg);
    /* Paper §4 and docs/robots.md: centre (0, -2, 9.135), r 2 m, 2 m/s, ccw, start (0, 0,
     * 9.135), offset (0, 1, -1470) mm. */
    TEST_ASSERT_EQUAL_INT(CDPR_TRAJ_CIRCLE, sc.traj.type);
    TEST_ASSERT_EQUAL_DOUBLE(-2.0, sc.traj.centre_m[1]);
    TEST_ASSERT_EQUAL_DOUBLE(9.135, sc.traj.centre_m[2]);
    TEST_ASSERT_EQUAL_DOUBLE(2.0, sc.traj.radius_m);
    TEST_ASSERT_EQUAL_DOUBLE(2.0, sc.traj.speed_m_per_s);
    TEST_ASSERT_EQUAL_DOUBLE(1.0, sc.traj.direction);
    TEST_ASSERT_DOUBLE_WITHIN(1e-15, PI / 2.0, sc.traj.start_angle_rad);
    TEST_ASSERT_EQUAL_DOUBLE(0.001, sc.initial_offset[1]);
    TEST_ASSERT_EQUAL_DOUBLE(-1.470, sc.initial_offset[2]);
    TEST_ASSERT_EQUAL_DOUBLE(2.0e6, sc.rig.cable[5].rope.ea_N);

    TEST_ASSERT_EQUAL_INT_MESSAGE(
        CDPR_OK, cdpr_scenario_load(CDPR_SOURCE_DIR "/scenarios/paper-line.yaml", &sc, &err),
        err.msg);
    /* Paper §4 poses, γ mapped to γ - π (docs/robots.md). Written to 14 decimals in the file. */
    const double from[6] = {2.00, 1.00, 16.0, 0.0889, -0.1756, 3.108 - PI};
    const double to[6] = {2.50, 1.50, 16.2, 0.135, -0.263, 3.121 - PI};
    for (int i = 0; i < 6; ++i) {
        TEST_ASSERT_DOUBLE_WITHIN(1e-13, from[i], sc.traj.from[i]);
        TEST_ASSERT_DOUBLE_WITHIN(1e-13, to[i], sc.traj.to[i]);
    }
    TEST_ASSERT_EQUAL_DOUBLE(10.0, sc.traj.duration_s);
    TEST_ASSERT_EQUAL_INT(0, sc.has_initial_pose);

    TEST_ASSERT_EQUAL_INT_MESSAGE(
        CDPR_OK, cdpr_scenario_load(CDPR_SOURCE_DIR "/scenarios/deploy-retrieve.yaml", &sc, &err),
        err.msg);
    TEST_ASSERT_EQUAL_INT(1, sc.traj.back_and_forth);
}

typedef struct {
    const char *label;
    const char *from; /* text of GOOD_LINE to replace */
    const char *to;   /* replacement */
    const char *key;  /* key path the message must name */
    const char *line; /* marker whose line the message must give ("" = no line check) */
    int at_run;       /* 1: the file loads; the run refuses it (feasibility) */
} bad_case_t;

static const bad_case_t BAD[] = {
    {"missing key", "    duration_s: 10.0\n", "", "trajectory.line.duration_s", "  line:", 0},
    {"wrong type", "mass_kg: 41.0", "mass_kg: heavy", "robot.cabin.mass_kg", "mass_kg:", 0},
    {"unknown key", "    cd: 1.1\n", "    cdd: 1.1\n", "robot.rope.cdd", "cdd:", 0},
    {"NaN", "ea_N: 2.5e6", "ea_N: nan", "robot.rope.ea_N", "ea_N:", 0},
    {"YAML NaN", "ea_N: 2.5e6", "ea_N: .nan", "robot.rope.ea_N", "ea_N:", 0},
    {"Inf", "rtol: 1.0e-7", "rtol: inf", "integrator.rtol", "rtol:", 0},
    {"overflow", "rtol: 1.0e-7", "rtol: 1e999", "integrator.rtol", "rtol:", 0},
    {"NaN in a list", "[0.1, 0.2, 10.0, 0.01, -0.02, 0.03]\n  offset",
     "[0.1, nan, 10.0, 0.01, -0.02, 0.03]\n  offset", "initial.pose", "  pose:", 0},
    {"out of range", "segments: 12", "segments: 0", "robot.segments", "segments:", 0},
    {"negative", "ea_N: 2.5e6", "ea_N: -2.5e6", "robot.rope.ea_N", "ea_N:", 0},
    {"not an integer", "max_trials: 300", "max_trials: 3.5", "integrator.max_trials",
     "max_trials:", 0},
    {"bad name", "type: line", "type: spiral", "trajectory.type", "type:", 0},
    {"short list", "[-0.25, 0.125, 91.0]]", "[-0.25, 0.125]]", "robot.cabin.inertia_kg_m2",
     "inertia_kg_m2:", 0},
    {"scalar for a section", "controller:\n  kp: 0.5\n", "controller: 3\ncontroller2:\n  kp: 0.5\n",
     "controller", "controller:", 0},
    {"period in the controller", "controller:\n  kp: 0.5\n",
     "controller:\n  period_s: 0.02\n  kp: 0.5\n", "controller.period_s", "  period_s:", 0},
    {"max_attempts out of range", "max_attempts: 2", "max_attempts: 17", "integrator.max_attempts",
     "max_attempts:", 0},
    {"two trajectory blocks", "controller:\n",
     "  hold:\n    pose: [0, 0, 9, 0, 0, 0]\ncontroller:\n", "trajectory.hold", "  hold:", 0},
    {"period vs duration", "duration_s: 12.0", "duration_s: 12.01", "run.duration_s",
     "  duration_s: 12.0", 0},
    {"output rate", "output_rate_hz: 25", "output_rate_hz: 30", "run.output_rate_hz",
     "output_rate_hz:", 0},
    /* Validation at load (issue 10). */
    {"period count overflow (M1)", "period_s: 0.02", "period_s: 1e-20", "run.period_s",
     "period_s:", 0},
    {"output rate 0 (L5)", "output_rate_hz: 25", "output_rate_hz: 0", "run.output_rate_hz",
     "output_rate_hz:", 0},
    {"inertia triangle (L5)", "[[50.0, 0.5, -0.25], [0.5, 46.0, 0.125], [-0.25, 0.125, 91.0]]",
     "[[1.0, 0, 0], [0, 1.0, 0], [0, 0, 10.0]]", "robot.cabin.inertia_kg_m2", "inertia_kg_m2:", 0},
    {"undamped cables (L8)", "damping_Ns: 160.0", "damping_Ns: 0.0", "robot.rope", "  rope:", 1},
    /* One schema (issue 21): the preset form's former keys are refused, naming the key. */
    {"the former cable: of a preset", "  rope:\n", "  cable:\n", "robot.cable", "  cable:", 0},
    {"a polar layout out of range", "    radius_m: 26.0\n", "    radius_m: -26.0\n",
     "robot.towers.radius_m", "radius_m: -26.0", 0},
    {"a polar layout without a preset", "  preset: paper-50m\n", "", "robot.towers",
     "  towers:", 0},
    {"a robot file with a preset", "  preset: paper-50m\n", "  preset: paper-50m\n  file: x.yaml\n",
     "robot.file", "  file:", 0},
    {"a preset's robot lists no cables", "  winch:\n",
     "  cables:\n    - exit_m: [0, 0, 1]\n      attach_m: [0, 0, 0]\n  winch:\n", "robot.cables",
     "  cables:", 0},
    {"cables beyond 1000 m (L5)", "    radius_m: 26.0\n    exit_height_m: 31.0\n",
     "    radius_m: 2000.0\n    exit_height_m: 1500.0\n", "trajectory.line", "  line:", 1},
    {"unreachable start", "pose: [0.1, 0.2, 10.0", "pose: [0.1, 0.2, 35.0", "initial.pose",
     "  pose:", 1},
    {"unreachable trajectory", "to: [0.5, -0.3, 11.0", "to: [40.0, -0.3, 11.0", "trajectory.line",
     "  line:", 1},
    {"transfer from rest not 0 or 1", "  filter_s: 0.25\n",
     "  filter_s: 0.25\n  transfer_from_rest: 0.5\n", "controller.transfer_from_rest",
     "  transfer_from_rest:", 0},
    /* A method's own settings (integrator.ros34pw2) are checked like the section's. */
    {"method setting out of range", "  max_attempts: 2\n",
     "  max_attempts: 2\n  ros34pw2:\n    rtol: 0.5\n", "integrator.ros34pw2.rtol", "    rtol: 0.5",
     0},
    {"method setting not whole", "  max_attempts: 2\n",
     "  max_attempts: 2\n  rkf45:\n    max_trials: 2.5\n", "integrator.rkf45.max_trials",
     "    max_trials: 2.5", 0},
    {"the method in use: its own setting", "  max_attempts: 2\n",
     "  max_attempts: 2\n  method: ros34pw2\n  ros34pw2:\n    rtol: 0.5\n",
     "integrator.ros34pw2.rtol", "    rtol: 0.5", 0},
    {"the section's setting under the method in use", "  rtol: 1.0e-7\n",
     "  method: ros34pw2\n  ros34pw2:\n    rtol: 1.0e-3\n  rtol: 0.5\n", "integrator.rtol",
     "  rtol: 0.5", 0},
    /* Strict numbers (issue 26): the whole value is a decimal number; libcyaml alone read a
     * prefix ("4O.0" as 4, "2_500_000" as 2, "41 kg" as 41) and hex. */
    {"trailing text (letter O)", "mass_kg: 41.0", "mass_kg: 4O.0", "robot.cabin.mass_kg",
     "mass_kg:", 0},
    {"digit separators", "ea_N: 2.5e6", "ea_N: 2_500_000", "robot.rope.ea_N", "ea_N:", 0},
    {"a unit", "mass_kg: 41.0", "mass_kg: 41 kg", "robot.cabin.mass_kg", "mass_kg:", 0},
    {"a unit suffix", "period_s: 0.02", "period_s: 0.02s", "run.period_s", "period_s:", 0},
    {"hex", "segments: 12", "segments: 0x0C", "robot.segments", "segments:", 0},
    {"hex float in a list", "[0.1, 0.2, 10.0, 0.01, -0.02, 0.03]\n  offset",
     "[0.1, 0x1p-3, 10.0, 0.01, -0.02, 0.03]\n  offset", "initial.pose[1]", "  pose:", 0},
    {"a second document", "controller:\n", "controller:\n  kp: 0.5\n---\ncontroller:\n",
     "a second YAML document", "---", 0},
    {"nesting deeper than the limit", "  kp: 0.5\n",
     "  kp: [[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[1]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]\n",
     "nested deeper than 32 levels", "", 0},
    {"integral bound zero", "  damping_rot_N_m_s: 20.0\n",
     "  damping_rot_N_m_s: 20.0\n  integral_limit_m: 0\n", "controller.integral_limit_m",
     "integral_limit_m:", 0},
    {"integral gain negative", "  damping_rot_N_m_s: 20.0\n",
     "  damping_rot_N_m_s: 20.0\n  integral_per_s: -0.1\n", "controller.integral_per_s",
     "integral_per_s:", 0},
    {"weight estimate negative", "  damping_rot_N_m_s: 20.0\n",
     "  damping_rot_N_m_s: 20.0\n  weight_estimate_s: -1\n", "controller.weight_estimate_s",
     "weight_estimate_s:", 0},
    {"tension washout negative", "  damping_rot_N_m_s: 20.0\n",
     "  damping_rot_N_m_s: 20.0\n  tension_washout_s: -0.5\n", "controller.tension_washout_s",
     "tension_washout_s:", 0},
    {"model factor out of range", "ea_scale: 0.9", "ea_scale: 0.4", "controller.model.ea_scale",
     "ea_scale:", 0},
    {"model key unknown", "cabin_mass_scale: 1.1", "cabin_mass: 1.1", "controller.model.cabin_mass",
     "cabin_mass:", 0},
    {"method key unknown", "  max_attempts: 2\n", "  max_attempts: 2\n  ros34pw2:\n    method: x\n",
     "integrator.ros34pw2.method", "    method: x", 0},
};

/* Rope damping as a ratio at a frequency: converted once to c = zeta EA / (pi f) (Kelvin-Voigt:
 * zeta(omega) = c omega / (2 EA)), replacing the preset's c; the axial law by name; a ratio
 * and a c together are refused naming the key. */
static void test_damping_ratio_and_slack_law(void)
{
    make_tmp();
    static char text[sizeof GOOD_LINE + 512];
    char path[700];
    replace(GOOD_LINE, "    damping_Ns: 160.0\n",
            "    damping_ratio: 0.01\n    damping_ref_hz: 4.0\n    slack_law: moordyn\n", text,
            sizeof text);
    snprintf(path, sizeof path, "%s/damping_ratio.yaml", tmp_dir);
    write_text(path, text);
    cdpr_scenario_t sc;
    cdpr_scenario_error_t err;
    TEST_ASSERT_EQUAL_INT_MESSAGE(CDPR_OK, cdpr_scenario_load(path, &sc, &err), err.msg);
    TEST_ASSERT_EQUAL_DOUBLE(0.01, sc.rig.cable[0].rope.damping_ratio);
    TEST_ASSERT_EQUAL_DOUBLE(0.0, sc.rig.cable[0].rope.damping_Ns);
    TEST_ASSERT_EQUAL_INT(CDPR_SLACK_MOORDYN, sc.rig.cable[0].rope.slack_law);
    cdpr_robot_params_t rp;
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_scenario_build_robot(&sc, NULL, &rp, NULL, NULL));
    static cdpr_robot_t robot;
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_robot_init(&robot, &rp, NULL));
    /* EA 2.5e6 N: c = 0.01 * 2.5e6 / (pi * 4) = 1989.4368 N s. */
    TEST_ASSERT_DOUBLE_WITHIN(1e-9, 0.01 * 2.5e6 / (3.14159265358979323846 * 4.0),
                              robot.cable[0].p.damping_Ns);
    replace(GOOD_LINE, "    damping_Ns: 160.0\n",
            "    damping_Ns: 160.0\n    damping_ratio: 0.01\n", text, sizeof text);
    snprintf(path, sizeof path, "%s/damping_both.yaml", tmp_dir);
    write_text(path, text);
    TEST_ASSERT_EQUAL_INT(CDPR_E_PARSE, cdpr_scenario_load(path, &sc, &err));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err.msg, "robot.rope.damping_ratio: give damping_Ns or "
                                                 "damping_ratio"),
                                 err.msg);
    replace(GOOD_LINE, "    damping_Ns: 160.0\n", "    damping_Ns: 160.0\n    slack_law: clip\n",
            text, sizeof text);
    snprintf(path, sizeof path, "%s/slack_law.yaml", tmp_dir);
    write_text(path, text);
    TEST_ASSERT_TRUE(cdpr_scenario_load(path, &sc, &err) < 0);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err.msg, "slack_law"), err.msg);
}

/* integrator.rkf45 / integrator.ros34pw2: each method gets the section's keys and then its
 * own; the one in use is that of `method`. */
static void test_settings_per_method(void)
{
    make_tmp();
    static char text[sizeof GOOD_LINE + 512];
    replace(GOOD_LINE, "  max_attempts: 2\n",
            "  max_attempts: 2\n  method: ros34pw2\n  ros34pw2:\n    rtol: 1.0e-3\n"
            "    max_trials: 4\n  rkf45:\n    atol_velocity_m_per_s: 7.0e-5\n",
            text, sizeof text);
    char path[700];
    snprintf(path, sizeof path, "%s/per_method.yaml", tmp_dir);
    write_text(path, text);
    cdpr_scenario_t sc;
    cdpr_scenario_error_t err;
    TEST_ASSERT_EQUAL_INT_MESSAGE(CDPR_OK, cdpr_scenario_load(path, &sc, &err), err.msg);
    const cdpr_scenario_integrator_t *ros = &sc.integrator_for[CDPR_PLANT_ROS34PW2];
    const cdpr_scenario_integrator_t *rk = &sc.integrator_for[CDPR_PLANT_RKF45];
    TEST_ASSERT_EQUAL_INT(CDPR_PLANT_ROS34PW2, sc.integrator.method);
    TEST_ASSERT_EQUAL_DOUBLE(1.0e-3, sc.integrator.rtol); /* its own */
    TEST_ASSERT_EQUAL_INT(4, sc.integrator.max_trials);
    TEST_ASSERT_EQUAL_DOUBLE(2.0e-6, sc.integrator.atol_position_m); /* the section's */
    TEST_ASSERT_EQUAL_INT(2, sc.integrator.max_attempts);
    TEST_ASSERT_EQUAL_DOUBLE(3.0e-5, sc.integrator.atol_velocity_m_per_s);
    TEST_ASSERT_EQUAL_MEMORY(&sc.integrator, ros, sizeof *ros);
    TEST_ASSERT_EQUAL_INT(CDPR_PLANT_RKF45, rk->method);
    TEST_ASSERT_EQUAL_DOUBLE(1.0e-7, rk->rtol);
    TEST_ASSERT_EQUAL_INT(300, rk->max_trials);
    TEST_ASSERT_EQUAL_DOUBLE(7.0e-5, rk->atol_velocity_m_per_s);
    /* Without subsections both methods get the section's keys. */
    snprintf(path, sizeof path, "%s/per_method_none.yaml", tmp_dir);
    write_text(path, GOOD_LINE);
    TEST_ASSERT_EQUAL_INT_MESSAGE(CDPR_OK, cdpr_scenario_load(path, &sc, &err), err.msg);
    TEST_ASSERT_EQUAL_INT(CDPR_PLANT_RKF45, sc.integrator.method);
    for (int m = 0; m < 2; ++m) {
        TEST_ASSERT_EQUAL_INT(m, sc.integrator_for[m].method);
        TEST_ASSERT_EQUAL_DOUBLE(1.0e-7, sc.integrator_for[m].rtol);
        TEST_ASSERT_EQUAL_INT(300, sc.integrator_for[m].max_trials);
    }
}

static void test_bad_files_name_file_key_and_line(void)
{
    make_tmp();
    for (size_t k = 0; k < sizeof BAD / sizeof BAD[0]; ++k) {
        const bad_case_t *b = &BAD[k];
        static char text[sizeof GOOD_LINE + 512];
        replace(GOOD_LINE, b->from, b->to, text, sizeof text);
        char path[700];
        snprintf(path, sizeof path, "%s/bad_%02u.yaml", tmp_dir, (unsigned)k);
        write_text(path, text);
        cdpr_scenario_t sc;
        cdpr_scenario_error_t err;
        err.msg[0] = '\0';
        cdpr_status_t rc = cdpr_scenario_load(path, &sc, &err);
        if (b->at_run != 0) {
            TEST_ASSERT_EQUAL_INT_MESSAGE(CDPR_OK, rc, b->label);
            cdpr_sim_opts_t o;
            cdpr_sim_opts_default(&o);
            cdpr_summary_t sum;
            rc = cdpr_sim_run(&sc, &o, &sum, &err);
        }
        /* A bad value or file, never an I/O error (the app's exit code 2 is checked below). */
        TEST_ASSERT_TRUE_MESSAGE(rc < 0 && rc != CDPR_E_IO, b->label);
        char what[2300];
        snprintf(what, sizeof what, "%s: %s", b->label, err.msg);
        TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err.msg, path), what);
        TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err.msg, b->key), what);
        if (b->line[0] != '\0') {
            char at[760];
            snprintf(at, sizeof at, "%s:%d: ", path, line_of(text, b->line));
            TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err.msg, at), what);
        }
#ifdef CDPR_SIM_EXE
        /* The app: exit status 2 and the same file and key on stderr. */
        char args[1600];
        char out[4096];
        /* --unchecked-gains: no note about GOOD_LINE's unchecked feedback (the design check
         * refuses it: test_design_check_refuses_good_line); these cases are about the file. */
        snprintf(args, sizeof args, "'%s' --out '%s/bad_out' --no-plot --quiet --unchecked-gains",
                 path, tmp_dir);
        TEST_ASSERT_EQUAL_INT_MESSAGE(2, run_sim(args, out, sizeof out), what);
        TEST_ASSERT_NOT_NULL_MESSAGE(strstr(out, path), out);
        TEST_ASSERT_NOT_NULL_MESSAGE(strstr(out, b->key), out);
#endif
    }
}

static void test_unreadable_files(void)
{
    make_tmp();
    cdpr_scenario_t sc;
    cdpr_scenario_error_t err;
    char path[600];
    snprintf(path, sizeof path, "%s/does-not-exist.yaml", tmp_dir);
    TEST_ASSERT_EQUAL_INT(CDPR_E_IO, cdpr_scenario_load(path, &sc, &err));
    TEST_ASSERT_NOT_NULL(strstr(err.msg, path));
    snprintf(path, sizeof path, "%s/empty.yaml", tmp_dir);
    write_text(path, "");
    TEST_ASSERT_EQUAL_INT(CDPR_E_PARSE, cdpr_scenario_load(path, &sc, &err));
    TEST_ASSERT_NOT_NULL(strstr(err.msg, "empty"));
    snprintf(path, sizeof path, "%s/broken.yaml", tmp_dir);
    write_text(path, "robot: [1, 2\n");
    TEST_ASSERT_EQUAL_INT(CDPR_E_PARSE, cdpr_scenario_load(path, &sc, &err));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err.msg, path), err.msg);
    /* A syntax error is found by libyaml's pass before the schema: line and column of the
     * construct that opened it. */
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err.msg, "broken.yaml:1:8: unclosed list '['"), err.msg);
}

static void test_command_line(void)
{
#ifndef CDPR_SIM_EXE
    TEST_IGNORE_MESSAGE("cdpr-sim not built (CDPR_BUILD_APPS=OFF)");
#else
    make_tmp();
    char out[8192];
    TEST_ASSERT_EQUAL_INT(0, run_sim("--help", out, sizeof out));
    TEST_ASSERT_NOT_NULL(strstr(out, "usage: cdpr-sim SCENARIO --out DIR"));
    TEST_ASSERT_EQUAL_INT(2, run_sim("", out, sizeof out));
    TEST_ASSERT_NOT_NULL(strstr(out, "missing SCENARIO"));
    TEST_ASSERT_EQUAL_INT(2,
                          run_sim(CDPR_SOURCE_DIR "/scenarios/paper-line.yaml", out, sizeof out));
    TEST_ASSERT_NOT_NULL(strstr(out, "--out DIR is required"));
    TEST_ASSERT_EQUAL_INT(2, run_sim(CDPR_SOURCE_DIR "/scenarios/paper-line.yaml --out x "
                                                     "--duration -1",
                                     out, sizeof out));
    TEST_ASSERT_NOT_NULL(strstr(out, "--duration"));
    /* An unreadable scenario is CDPR_E_IO: exit 3 by the apps' table (app_status.h). */
    TEST_ASSERT_EQUAL_INT(3, run_sim("nope.yaml --out x", out, sizeof out));
    TEST_ASSERT_NOT_NULL(strstr(out, "nope.yaml: cannot open"));
    TEST_ASSERT_EQUAL_INT(2, run_sim("--bogus", out, sizeof out));
#endif
}

/* The design check at load when asked (--check-design, lib/design): GOOD_LINE's feedback (kp
 * 0.5, kd_s 0.05, wrench damping 30 / 20, filter 0.25 s) makes the linearised closed loop grow,
 * so cdpr-sim --check-design refuses it with exit 2, the file, the keys and the growth named,
 * before running anything; without the option (or with --unchecked-gains given last) it runs,
 * and without --quiet one note says the check was skipped. */
static void test_design_check_refuses_good_line(void)
{
#ifndef CDPR_SIM_EXE
    TEST_IGNORE_MESSAGE("cdpr-sim not built (CDPR_BUILD_APPS=OFF)");
#else
    make_tmp();
    char path[700];
    snprintf(path, sizeof path, "%s/good_line.yaml", tmp_dir);
    static char text[sizeof GOOD_LINE + 64];
    replace(GOOD_LINE, "  duration_s: 12.0\n", "  duration_s: 0.04\n", text, sizeof text);
    write_text(path, text);
    char args[1600];
    char out[4096];
    char summary[800];
    snprintf(summary, sizeof summary, "%s/good_out/summary.json", tmp_dir);
    (void)remove(summary); /* a previous run's */
    snprintf(args, sizeof args, "'%s' --out '%s/good_out' --no-plot --quiet --check-design", path,
             tmp_dir);
    TEST_ASSERT_EQUAL_INT_MESSAGE(2, run_sim(args, out, sizeof out), out);
    char want[1800];
    snprintf(want, sizeof want,
             "cdpr-design: %s: controller (kp 0.5, kd_s 0.05, damping_N_s_per_m 30, "
             "damping_rot_N_m_s 20, filter_s 0.25): the linearised closed loop grows at ",
             path);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(out, want), out);
    TEST_ASSERT_NULL_MESSAGE(fopen(summary, "r"), "refused, yet something ran");
    snprintf(args, sizeof args,
             "'%s' --out '%s/good_out' --no-plot --quiet --check-design --unchecked-gains", path,
             tmp_dir);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, run_sim(args, out, sizeof out), out);
    TEST_ASSERT_NULL_MESSAGE(strstr(out, "grows"), out);
    snprintf(args, sizeof args, "'%s' --out '%s/good_out' --no-plot", path, tmp_dir);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, run_sim(args, out, sizeof out), out);
    snprintf(want, sizeof want,
             "cdpr-sim: note: %s: the controller's feedback/learning is not checked before this "
             "run; --check-design checks it first, or cdpr-design %s --verdict\n",
             path, path);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(out, want), out);
#endif
}

/* The cyclic trajectory's keys resolve; the saturating period count never overflows. */
static void test_cyclic_and_counts(void)
{
    make_tmp();
    static char text[sizeof GOOD_LINE + 512];
    replace(GOOD_LINE, "  type: line\n  line:\n", "  type: cyclic\n  cyclic:\n    cycles: 3\n",
            text, sizeof text);
    static char text2[sizeof GOOD_LINE + 512];
    replace(text, "    back_and_forth: true\n", "", text2, sizeof text2);
    char path[700];
    snprintf(path, sizeof path, "%s/cyclic.yaml", tmp_dir);
    write_text(path, text2);
    cdpr_scenario_t sc;
    cdpr_scenario_error_t err;
    err.msg[0] = '\0';
    TEST_ASSERT_EQUAL_INT_MESSAGE(CDPR_OK, cdpr_scenario_load(path, &sc, &err), err.msg);
    TEST_ASSERT_EQUAL_INT(CDPR_TRAJ_CYCLIC, sc.traj.type);
    TEST_ASSERT_EQUAL_STRING("cyclic", cdpr_traj_type_name(sc.traj.type));
    TEST_ASSERT_EQUAL_DOUBLE(10.0, sc.traj.duration_s);
    TEST_ASSERT_EQUAL_DOUBLE(1.5, sc.traj.pause_s);
    TEST_ASSERT_EQUAL_INT(3, (int)sc.traj.cycles);
    TEST_ASSERT_EQUAL_DOUBLE(11.0, sc.traj.to[2]);
    TEST_ASSERT_EQUAL_DOUBLE(3.0 * 23.0, cdpr_traj_end_time(&sc.traj));
    /* cycles must be a whole number. */
    static char text3[sizeof GOOD_LINE + 512];
    replace(text2, "cycles: 3", "cycles: 2.5", text3, sizeof text3);
    write_text(path, text3);
    TEST_ASSERT_EQUAL_INT(CDPR_E_OUT_OF_RANGE, cdpr_scenario_load(path, &sc, &err));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err.msg, "trajectory.cyclic.cycles: 2.5 is not a whole"),
                                 err.msg);
    /* Counts: rounded, 0 for NaN and negatives, saturated at the limit (no overflowing cast). */
    TEST_ASSERT_EQUAL_INT(2, (int)cdpr_scenario_count(2.4));
    TEST_ASSERT_EQUAL_INT(3, (int)cdpr_scenario_count(2.5));
    TEST_ASSERT_EQUAL_INT(0, (int)cdpr_scenario_count((double)NAN));
    TEST_ASSERT_EQUAL_INT(0, (int)cdpr_scenario_count(-5.0));
    TEST_ASSERT_TRUE(cdpr_scenario_count(5e19) == CDPR_SCENARIO_MAX_PERIODS);
    TEST_ASSERT_TRUE(cdpr_scenario_count((double)INFINITY) == CDPR_SCENARIO_MAX_PERIODS);
    /* A scenario changed in code to a period the file check refuses still counts safely. */
    write_text(path, text2);
    TEST_ASSERT_EQUAL_INT_MESSAGE(CDPR_OK, cdpr_scenario_load(path, &sc, &err), err.msg);
    sc.period_s = 1e-20;
    TEST_ASSERT_TRUE(cdpr_scenario_periods(&sc) == CDPR_SCENARIO_MAX_PERIODS);
    TEST_ASSERT_NOT_EQUAL(CDPR_OK, cdpr_scenario_check(&sc, &err));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err.msg, "run.period_s: 1e-20 s gives"), err.msg);
}

/* a and b the same double, bit for bit (an exact zero is +0 here). */
static int same(double a, double b)
{
    return memcmp(&a, &b, sizeof a) == 0;
}

/* Load MINIMAL plus `wind` into sc; returns the load's status. */
static cdpr_status_t load_with_wind(const char *wind, cdpr_scenario_t *sc,
                                    cdpr_scenario_error_t *err)
{
    static char text[sizeof MINIMAL + 512];
    snprintf(text, sizeof text, "%s%s", MINIMAL, wind);
    char path[700];
    snprintf(path, sizeof path, "%s/wind.yaml", tmp_dir);
    write_text(path, text);
    err->msg[0] = '\0';
    return cdpr_scenario_load(path, sc, err);
}

/* The wind section (issue 23): each profile against its closed form, written here from
 * docs/scenarios.md; exact zeros at whole quarter turns; the rig's wind at t = 0; keys that
 * a profile does not read, missing ones and ranges refused with the key named. */
static void test_wind_section(void)
{
    make_tmp();
    cdpr_scenario_t sc;
    cdpr_scenario_error_t err;
    double v[3];
    /* No section: the robot's steady wind at every time. */
    TEST_ASSERT_EQUAL_INT_MESSAGE(CDPR_OK, load_with_wind("", &sc, &err), err.msg);
    TEST_ASSERT_EQUAL_INT(0, sc.wind.given);
    sc.rig.wind_m_per_s[1] = 3.0;
    cdpr_scenario_wind_at(&sc, 123.0, v);
    TEST_ASSERT_TRUE(same(v[0], 0.0) && same(v[1], 3.0) && same(v[2], 0.0));
    /* Steady, towards +y (90 deg and -270 deg): exactly (0, 8, 0); the rig holds it. */
    const char *const quarter[] = {"90", "-270"};
    for (int i = 0; i < 2; ++i) {
        char w[256];
        snprintf(w, sizeof w, "wind:\n  speed_m_per_s: 8.0\n  towards_deg: %s\n", quarter[i]);
        TEST_ASSERT_EQUAL_INT_MESSAGE(CDPR_OK, load_with_wind(w, &sc, &err), err.msg);
        TEST_ASSERT_EQUAL_INT(CDPR_WIND_STEADY, sc.wind.profile);
        cdpr_scenario_wind_at(&sc, 5.0, v);
        TEST_ASSERT_TRUE(same(v[0], 0.0) && same(v[1], 8.0) && same(v[2], 0.0));
        TEST_ASSERT_TRUE(same(sc.rig.wind_m_per_s[0], 0.0) && same(sc.rig.wind_m_per_s[1], 8.0));
    }
    /* Ramp: 0 until 2 s, linear to 8 m/s at 12 s, towards 30 deg. */
    TEST_ASSERT_EQUAL_INT_MESSAGE(
        CDPR_OK,
        load_with_wind("wind:\n  speed_m_per_s: 8.0\n  towards_deg: 30\n"
                       "  profile: ramp\n  start_s: 2.0\n  rise_s: 10.0\n",
                       &sc, &err),
        err.msg);
    TEST_ASSERT_EQUAL_STRING("ramp", cdpr_wind_profile_name(sc.wind.profile));
    const double c30 = cos(PI / 6.0);
    const double s30 = 0.5;
    const double ramp_t[] = {0.0, 2.0, 4.5, 7.0, 12.0, 20.0};
    const double ramp_v[] = {0.0, 0.0, 2.0, 4.0, 8.0, 8.0};
    for (int i = 0; i < 6; ++i) {
        cdpr_scenario_wind_at(&sc, ramp_t[i], v);
        TEST_ASSERT_DOUBLE_WITHIN(1e-14, ramp_v[i] * c30, v[0]);
        TEST_ASSERT_DOUBLE_WITHIN(1e-14, ramp_v[i] * s30, v[1]);
        TEST_ASSERT_TRUE(same(v[2], 0.0));
    }
    TEST_ASSERT_TRUE(same(sc.rig.wind_m_per_s[0], 0.0) && same(sc.rig.wind_m_per_s[1], 0.0));
    /* Gust: 5 m/s towards -x, plus 3 m/s (1 - cos) over [1, 5] s: peak 8 at 3 s, 6.5 at 2 s. */
    TEST_ASSERT_EQUAL_INT_MESSAGE(
        CDPR_OK,
        load_with_wind("wind:\n  speed_m_per_s: 5.0\n  towards_deg: 180\n  profile: gust\n"
                       "  start_s: 1.0\n  rise_s: 4.0\n  gust_m_per_s: 3.0\n",
                       &sc, &err),
        err.msg);
    const double gust_t[] = {0.0, 1.0, 2.0, 3.0, 4.0, 5.0, 9.0};
    const double gust_v[] = {5.0, 5.0, 6.5, 8.0, 6.5, 5.0, 5.0};
    for (int i = 0; i < 7; ++i) {
        cdpr_scenario_wind_at(&sc, gust_t[i], v);
        TEST_ASSERT_DOUBLE_WITHIN(1e-14, -gust_v[i], v[0]);
        TEST_ASSERT_TRUE(same(v[1], 0.0));
    }
    /* Refused: each names its key. */
    static const struct {
        const char *text;
        const char *key;
        cdpr_status_t st;
    } bad[] = {
        {"wind:\n  speed_m_per_s: 8\n  towards_deg: 0\n  rise_s: 2\n", "wind.rise_s", CDPR_E_PARSE},
        {"wind:\n  speed_m_per_s: 8\n  towards_deg: 0\n  profile: ramp\n", "wind.rise_s",
         CDPR_E_PARSE},
        {"wind:\n  speed_m_per_s: 8\n  towards_deg: 0\n  profile: ramp\n  rise_s: 1\n"
         "  gust_m_per_s: 1\n",
         "wind.gust_m_per_s", CDPR_E_PARSE},
        {"wind:\n  speed_m_per_s: 8\n  towards_deg: 0\n  profile: gust\n  rise_s: 1\n",
         "wind.gust_m_per_s", CDPR_E_PARSE},
        {"wind:\n  speed_m_per_s: 8\n  towards_deg: 0\n  profile: gale\n", "wind.profile",
         CDPR_E_PARSE},
        {"wind:\n  speed_m_per_s: 8\n", "wind.towards_deg", CDPR_E_PARSE},
        {"wind:\n  speed_m_per_s: -1\n  towards_deg: 0\n", "wind.speed_m_per_s",
         CDPR_E_OUT_OF_RANGE},
        {"wind:\n  speed_m_per_s: 8\n  towards_deg: 400\n", "wind.towards_deg",
         CDPR_E_OUT_OF_RANGE},
        {"wind:\n  speed_m_per_s: 8\n  towards_deg: 0\n  profile: ramp\n  rise_s: 0\n",
         "wind.rise_s", CDPR_E_OUT_OF_RANGE},
        {"wind:\n  speed_m_per_s: 80\n  towards_deg: 0\n  profile: gust\n  rise_s: 1\n"
         "  gust_m_per_s: 30\n",
         "wind.gust_m_per_s", CDPR_E_OUT_OF_RANGE},
        {"wind:\n  speed_m_per_s: nan\n  towards_deg: 0\n", "wind.speed_m_per_s",
         CDPR_E_NOT_FINITE},
    };
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; ++k) {
        const cdpr_status_t st = load_with_wind(bad[k].text, &sc, &err);
        TEST_ASSERT_EQUAL_INT_MESSAGE(bad[k].st, st, bad[k].text);
        TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err.msg, bad[k].key), err.msg);
    }
}

/* Files refused before any parse (issue 10, L6 and L9): a directory, a file over 1 MiB. */
static void test_file_checks_before_parsing(void)
{
    make_tmp();
    cdpr_scenario_t sc;
    cdpr_scenario_error_t err;
    char path[700];
    snprintf(path, sizeof path, "%s/a-dir.yaml", tmp_dir);
    (void)mkdir(path, 0755);
    TEST_ASSERT_EQUAL_INT(CDPR_E_PARSE, cdpr_scenario_load(path, &sc, &err));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err.msg, "a-dir.yaml: is a directory"), err.msg);
    snprintf(path, sizeof path, "%s/big.yaml", tmp_dir);
    FILE *f = fopen(path, "wb");
    TEST_ASSERT_NOT_NULL(f);
    fputs(MINIMAL, f);
    fputs("description: \"", f);
    for (long i = 0; i < CDPR_YAML_MAX_FILE_BYTES; ++i) {
        fputc('A', f);
    }
    fputs("\"\n", f);
    fclose(f);
    TEST_ASSERT_EQUAL_INT(CDPR_E_PARSE, cdpr_scenario_load(path, &sc, &err));
    TEST_ASSERT_NOT_NULL_MESSAGE(
        strstr(err.msg, "bytes: larger than the limit of YAML input files (1048576 bytes, 1 MiB)"),
        err.msg);
    TEST_ASSERT_TRUE(strlen(err.msg) < 200 + strlen(path));

    /* Deep nesting within the size limit: refused at the limit's depth, at once (libyaml's
     * scanner costs depth per token: before the bound, 400 kB of '[' took 282 s of CPU). */
    snprintf(path, sizeof path, "%s/deep.yaml", tmp_dir);
    f = fopen(path, "wb");
    TEST_ASSERT_NOT_NULL(f);
    fputs("description: ", f);
    for (long i = 0; i < CDPR_YAML_MAX_FILE_BYTES - 100; ++i) {
        fputc('[', f);
    }
    fputc('\n', f);
    fclose(f);
    TEST_ASSERT_EQUAL_INT(CDPR_E_PARSE, cdpr_scenario_load(path, &sc, &err));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err.msg, "deep.yaml:1:"), err.msg);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err.msg, "nested deeper than 32 levels"), err.msg);

    /* A FIFO as the scenario, and as the robot file it names: refused without blocking,
     * whether or not a writer holds it open (an open(2) without O_NONBLOCK waited forever). */
    snprintf(path, sizeof path, "%s/fifo.yaml", tmp_dir);
    (void)unlink(path);
    TEST_ASSERT_EQUAL_INT(0, mkfifo(path, 0600));
    TEST_ASSERT_EQUAL_INT(CDPR_E_PARSE, cdpr_scenario_load(path, &sc, &err));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err.msg, "fifo.yaml: not a regular file"), err.msg);
    const int writer_rd = open(path, O_RDONLY | O_NONBLOCK); /* lets a writer open */
    const int writer = open(path, O_WRONLY | O_NONBLOCK);
    TEST_ASSERT_TRUE(writer_rd >= 0 && writer >= 0);
    TEST_ASSERT_EQUAL_INT(CDPR_E_PARSE, cdpr_scenario_load(path, &sc, &err));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err.msg, "fifo.yaml: not a regular file"), err.msg);
    char scn[700];
    snprintf(scn, sizeof scn, "%s/robot-fifo.yaml", tmp_dir);
    write_text(scn, "robot:\n  file: fifo.yaml\ntrajectory:\n  type: hold\n  hold:\n"
                    "    pose: [0, 0, 9, 0, 0, 0]\ncontroller:\n  kp: 0.0\n"
                    "  k_length_per_s: 5.0\nrun:\n  duration_s: 0.1\n  period_s: 0.01\n");
    TEST_ASSERT_TRUE(cdpr_scenario_load(scn, &sc, &err) < 0);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err.msg, "fifo.yaml: not a regular file"), err.msg);
    (void)close(writer);
    (void)close(writer_rd);
    (void)unlink(path);
}

/* Paths longer than the loaders hold: "path too long", never a cut path (before: the first 511
 * characters were loaded, silently, another file or none). */
static void test_long_paths_are_refused_not_cut(void)
{
    make_tmp();
    char good[700];
    snprintf(good, sizeof good, "%s/minimal.yaml", tmp_dir);
    write_text(good, MINIMAL);
    /* tmp_dir/././.../minimal.yaml: the same file, by a path of over 600 characters. */
    static char path[2048];
    int n = snprintf(path, sizeof path, "%s/", tmp_dir);
    while (n < 620) {
        n += snprintf(path + n, sizeof path - (size_t)n, "./");
    }
    snprintf(path + n, sizeof path - (size_t)n, "minimal.yaml");
    static cdpr_scenario_t sc;
    cdpr_scenario_error_t err;
    TEST_ASSERT_EQUAL_INT(CDPR_E_INVALID_ARG, cdpr_scenario_load(path, &sc, &err));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err.msg, "path too long ("), err.msg);
    /* A robot file named by a long relative path. */
    static char text[4096];
    static char rel[1024];
    int m = 0;
    while (m < 600) {
        m += snprintf(rel + m, sizeof rel - (size_t)m, "./");
    }
    snprintf(rel + m, sizeof rel - (size_t)m, "robot.yaml");
    snprintf(text, sizeof text,
             "robot:\n  file: %s\ntrajectory:\n  type: hold\n  hold:\n"
             "    pose: [0, 0, 9, 0, 0, 0]\ncontroller:\n  kp: 0.0\n"
             "  k_length_per_s: 5.0\nrun:\n  duration_s: 0.1\n  period_s: 0.01\n",
             rel);
    snprintf(good, sizeof good, "%s/long-robot-path.yaml", tmp_dir);
    write_text(good, text);
    TEST_ASSERT_EQUAL_INT(CDPR_E_INVALID_ARG, cdpr_scenario_load(good, &sc, &err));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err.msg, ":2: robot.file: path too long ("), err.msg);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_every_key_resolves_to_the_value_written);
    RUN_TEST(test_omitted_keys_take_the_preset);
    RUN_TEST(test_committed_scenarios_hold_the_papers_numbers);
    RUN_TEST(test_damping_ratio_and_slack_law);
    RUN_TEST(test_settings_per_method);
    RUN_TEST(test_bad_files_name_file_key_and_line);
    RUN_TEST(test_unreadable_files);
    RUN_TEST(test_command_line);
    RUN_TEST(test_design_check_refuses_good_line);
    RUN_TEST(test_cyclic_and_counts);
    RUN_TEST(test_wind_section);
    RUN_TEST(test_file_checks_before_parsing);
    RUN_TEST(test_long_paths_are_refused_not_cut);
    return UNITY_END() ? 1 : 0;
}
