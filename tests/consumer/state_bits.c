/* SPDX-License-Identifier: BSD-3-Clause */
/// @file state_bits.c
/// Consumer test program (tests/consumer/run.sh): builds a plant from fixed parameters,
/// steps it a fixed number of periods and prints the state vector's bits, one hexadecimal
/// word per component, so that two builds of the library can be compared byte for byte.
///
/// The same source is built inside the project (tests/consumer/CMakeLists.txt: host, Cortex-M7
/// and Cortex-M4 trees) and by the out-of-tree consumers: find_package (tests/consumer/package),
/// pkg-config, and the Cortex-M7 firmware consumers (tests/consumer/firmware) through the
/// installed package and through add_subdirectory(<cdpr>/lib/core <binary-dir>).
///
/// Only literal parameters and the library's own arithmetic: the program computes nothing
/// itself, so its output depends on how the library was built, not on the consumer's flags.
/// With CDPR_CONSUMER_HOST the robot comes from lib/host's preset (cdpr/host/presets.h)
/// instead of the literal table. With CDPR_CONSUMER_CONTROL the winch commands come from the
/// example controller (lib/control: cdpr/control/tracker.h) holding the home pose with winch
/// tension feedback, closed on the plant each period, and its last commands are printed too.
/// Exit status 0 when every period succeeded.
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "cdpr/plant.h"
#include "cdpr/status.h"
#include "cdpr/version.h"
#ifdef CDPR_CONSUMER_HOST
#include "cdpr/host/presets.h"
#endif
#ifdef CDPR_CONSUMER_CONTROL
#include "cdpr/control/tracker.h"
#endif

#define N_CABLES   6
#define N_SEGMENTS 8
#define N_PERIODS  20

static cdpr_plant_t plant;
static cdpr_plant_params_t pp;
#ifdef CDPR_CONSUMER_CONTROL
static cdpr_tracker_t tracker;
static cdpr_tracker_cmd_t cmd;
#endif

#ifndef CDPR_CONSUMER_HOST
/* The paper's 50 m robot, as the firmware example writes it. */
#include "../../apps/firmware-example/paper_robot.h"
#endif
static const cdpr_real_t HOME[6] = {CDPR_R(0.0), CDPR_R(0.0), CDPR_R(9.135),
                                    CDPR_R(0.0), CDPR_R(0.0), CDPR_R(0.0)};
#ifndef CDPR_CONSUMER_CONTROL
static const cdpr_real_t RATE_M_PER_S[N_CABLES] = {CDPR_R(0.02), CDPR_R(0.0), CDPR_R(-0.02),
                                                   CDPR_R(0.02), CDPR_R(0.0), CDPR_R(-0.02)};
#endif

/* "<label> <hex of the bits>\n", most significant nibble first (any endianness). */
static void put_bits(const char *label, int index, cdpr_real_t x)
{
    char hex[2u * sizeof(uint64_t) + 1u];
    uint64_t bits = 0u;
    size_t nibbles = 2u * sizeof x;
    if (sizeof x == sizeof(uint64_t)) {
        memcpy(&bits, &x, sizeof x);
    } else {
        uint32_t b32 = 0u;
        memcpy(&b32, &x, sizeof b32);
        bits = b32;
    }
    for (size_t i = 0u; i < nibbles; ++i) {
        hex[nibbles - 1u - i] = "0123456789abcdef"[bits & 0xfu];
        bits >>= 4u;
    }
    hex[nibbles] = '\0';
    printf("%s[%d] %s\n", label, index, hex);
}

static int build_params(void)
{
    cdpr_plant_params_default(&pp);
#ifdef CDPR_CONSUMER_HOST
    cdpr_preset_config_t cfg;
    cdpr_diag_t d;
    if (cdpr_preset_get(CDPR_PRESET_PAPER_50M, &cfg) != CDPR_OK) {
        return -1;
    }
    cfg.segments = N_SEGMENTS;
    const cdpr_status_t st = cdpr_preset_build(&cfg, NULL, &pp.robot, &pp.winch[0], &d);
    for (int j = 1; j < CDPR_MAX_CABLES; ++j) {
        pp.winch[j] = pp.winch[0];
    }
    if (st != CDPR_OK) {
        printf("preset: %s at %s[%d]\n", cdpr_status_str(st), d.field, d.index);
        return -1;
    }
    printf("preset %s\n", cdpr_preset_name(cfg.preset));
#else
    pp.robot.n_cables = N_CABLES;
    for (int j = 0; j < N_CABLES; ++j) {
        cdpr_robot_cable_params_t *c = &pp.robot.cables[j];
        c->exit_point_m = cdpr_v3(EXIT_M[j][0], EXIT_M[j][1], EXIT_M[j][2]);
        c->attach_body_m = cdpr_v3(ATTACH_M[j][0], ATTACH_M[j][1], ATTACH_M[j][2]);
        c->n_segments = N_SEGMENTS;
        c->length_m = CDPR_R(31.541); /* validation start only: the IK sets the length */
    }
#endif
    pp.initial = cdpr_cabin_motion_at_pose(HOME);
    pp.start = CDPR_PLANT_START_CATENARY; /* no settling: quick under QEMU too */
    pp.period_s = CDPR_R(0.005);
    return 0;
}

int main(void)
{
    cdpr_diag_t d;
    if (build_params() != 0) {
        return 1;
    }
    cdpr_status_t st = cdpr_plant_init(&plant, &pp, &d);
    if (st != CDPR_OK) {
        printf("plant init: %s at %s[%d]\n", cdpr_status_str(st), d.field, d.index);
        return 1;
    }
#ifdef CDPR_CONSUMER_CONTROL
    cdpr_traj_t traj;
    memset(&traj, 0, sizeof traj);
    traj.type = CDPR_TRAJ_HOLD;
    for (int i = 0; i < 6; ++i) {
        traj.hold_pose[i] = HOME[i];
    }
    cdpr_tracker_gains_t g;
    memset(&g, 0, sizeof g);
    g.k_length_per_s = CDPR_R(5.0);
    g.filter_s = CDPR_R(0.1);
    g.inertial_ff = CDPR_R(1.0);
    g.tension_gain_m_per_s_per_N = CDPR_R(1e-3);
    g.tension_filter_s = CDPR_R(0.05);
    st = cdpr_tracker_init(&tracker, &pp.robot, &traj, &g, pp.period_s, CDPR_R(0.0), &d);
    if (st != CDPR_OK) {
        printf("tracker init: %s at %s[%d]\n", cdpr_status_str(st), d.field, d.index);
        return 1;
    }
#endif
    for (int k = 0; k < N_PERIODS; ++k) {
        int flags = 0;
#ifdef CDPR_CONSUMER_CONTROL
        cdpr_plant_meas_t m;
        cdpr_plant_measure(&plant, &m);
        st = cdpr_tracker_step(&tracker, &m, &cmd);
        if (st != CDPR_OK) {
            printf("period %d: tracker %s\n", k, cdpr_status_str(st));
            return 1;
        }
        st = cdpr_plant_step(&plant, CDPR_WINCH_RATE, cmd.rate_m_per_s, &flags);
#else
        st = cdpr_plant_step(&plant, CDPR_WINCH_RATE, RATE_M_PER_S, &flags);
#endif
        if (st < 0) {
            printf("period %d: %s\n", k, cdpr_status_str(st));
            return 1;
        }
    }
    cdpr_robot_out_t out;
    cdpr_plant_outputs(&plant, &out);
    const int dim = cdpr_robot_state_dim(&plant.robot);
    printf("cdpr %s: %d periods, state dimension %d, real of %d bytes\n", CDPR_VERSION_STRING,
           N_PERIODS, dim, (int)sizeof(cdpr_real_t));
    put_bits("t", 0, cdpr_plant_time(&plant));
    for (int i = 0; i < dim; ++i) {
        put_bits("y", i, plant.y[i]);
    }
    for (int j = 0; j < N_CABLES; ++j) {
        put_bits("tension_winch", j, out.tension_winch_N[j]);
    }
#ifdef CDPR_CONSUMER_CONTROL
    for (int j = 0; j < N_CABLES; ++j) {
        put_bits("rate_cmd", j, cmd.rate_m_per_s[j]);
    }
#endif
    return 0;
}
