/* SPDX-License-Identifier: BSD-3-Clause */
/// @file main.c
/// Minimal bare-metal integration of the cdpr core: what a winch-controller firmware links and
/// calls. Built only by the cortex-m7 and cortex-m4 presets; ctest runs it under QEMU.
///
/// - The model (the paper's 50 m robot, docs/robots.md: six cables of 16 segments between exit
/// points
///   on a 25 m circle at 30 m and a 40 kg cabin) comes from a compiled-in configuration. The
///   start is the static equilibrium at the home pose: sag-aware inverse kinematics gives the
///   unstretched lengths, and the cables start on their catenaries, at rest.
/// - Every object is a static of known size (docs/firmware.md): nothing is allocated.
/// - A periodic interrupt (SysTick, 1 kHz) only counts ticks; the main loop runs one control
///   period per tick outside the interrupt: one cdpr_plant_step (winch updates, a bounded
///   advance of exactly dt, quaternion renormalisation, node events; rolled back on failure),
///   then the outputs for telemetry.
///
/// Under QEMU with `-icount shift=0` the virtual clock advances 1 ns per executed instruction,
/// so SysTick's counter measures instructions; the program calibrates that against a loop of
/// known length and prints the instructions per control period (docs/firmware.md). The exit
/// status is 0 when the run ends taut, finite and without integrator errors.
///
/// -DFW_EIGHT (cdpr-firmware-example-eight): the eight-cable robot of robots/eight-50m.yaml at its
/// nominal pose (13 m), started by the sag-aware IK with its tension distribution, in the fixed
/// mode; the core compiled into it at 8 cables x 16 segments (the presets' is 6 x 64).
///
/// -DFW_CONTROL (cdpr-firmware-example-control): the example controller of lib/control closes
/// the loop on the target in the same period: measure the plant, one cdpr_tracker_step (the
/// sag-aware IK feed-forward of the paper's circle plus pose feedback), command the winches,
/// advance the plant. It prints the controller's instructions per period next to the whole
/// period's, and fails when a feed-forward IK failed or the cabin strayed 1 cm from the circle.
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "cdpr/plant.h"
#include "cdpr/status.h"
#ifdef FW_CONTROL
#include "cdpr/control/tracker.h"
#endif

/* ---- Compiled-in configuration -------------------------------------------------------- */

#ifdef FW_EIGHT
#define N_CABLES 8
#else
#define N_CABLES 6
#endif
#ifndef N_SEGMENTS
#define N_SEGMENTS 16 /* -DN_SEGMENTS=32: the variants of CMakeLists.txt */
#endif
#define N_PERIODS 200 /* 0.2 s of simulated time */
#if defined(FW_RKF45)
/* -DFW_RKF45: the explicit RKF45 (rkf45.h) with step control, at most MAX_TRIALS trials per
 * period: a bound, not a constant; the work varies 2-3x between periods (docs/firmware.md). */
#define MAX_TRIALS 40 /* work bound per period: 6 x 40 RHS evaluations */
#elif defined(FW_ROS34PW2)
/* -DFW_ROS34PW2: the adaptive implicit integrator (ros34pw2.h), at most 3 trials of 1
 * factorisation, 4 solves and 4 RHS evaluations per period, node tolerances as in
 * docs/model.md §7. */
#define MAX_TRIALS 3
#else
/* Default: the fixed-cost mode (plant.h "Fixed-cost stepping"), exactly n ROS34PW2 substeps
 * per period, n derived from the model at init: n factorisations, 4 n solves and 4 n RHS
 * evaluations in every period, the mean and the worst case alike. */
#define FW_FIXED
#define MAX_TRIALS 1 /* not used by the fixed mode (it has no trials) */
#endif
#define SYSTICK_HZ     1000
#define CPU_CLOCK_HZ   25000000u /* QEMU's MPS2 boards clock SysTick at 25 MHz */
#define SYSTICK_RELOAD (CPU_CLOCK_HZ / SYSTICK_HZ)

#if CDPR_MAX_CABLES < N_CABLES || CDPR_MAX_SEGMENTS < N_SEGMENTS
#error "the example needs CDPR_MAX_CABLES >= N_CABLES and CDPR_MAX_SEGMENTS >= N_SEGMENTS"
#endif

static const cdpr_real_t DT_S = CDPR_R(0.001); /* control period [s] */

#ifdef FW_EIGHT
/* The eight-cable robot (EXIT_M, ATTACH_M, TENSION_*); its nominal pose 13 m up, level. */
#include "eight_robot.h"
static const cdpr_real_t CHORD_M = CDPR_R(29.0); /* initial guess only: the IK sets L */
static const cdpr_real_t CABIN_Z_M = CDPR_R(13.0);
#else
/* The paper's robot (EXIT_M, ATTACH_M); the cabin's home pose: 9.135 m above the ground, level. */
#include "paper_robot.h"
static const cdpr_real_t CHORD_M = CDPR_R(31.541); /* initial guess only: the IK sets L */
static const cdpr_real_t CABIN_Z_M = CDPR_R(9.135);
#endif
/* Winch commands: a slow payout on two opposite cables, haul-in on two others [m/s]. */
#ifndef FW_CONTROL
/* The open-loop winch commands of the plain build [m/s]. */
#ifdef FW_EIGHT
static const cdpr_real_t RATE_CMD_M_PER_S[N_CABLES] = {CDPR_R(0.02),  CDPR_R(0.0),  CDPR_R(-0.02),
                                                       CDPR_R(0.0),   CDPR_R(0.02), CDPR_R(0.0),
                                                       CDPR_R(-0.02), CDPR_R(0.0)};
#else
static const cdpr_real_t RATE_CMD_M_PER_S[N_CABLES] = {CDPR_R(0.02), CDPR_R(0.0), CDPR_R(-0.02),
                                                       CDPR_R(0.02), CDPR_R(0.0), CDPR_R(-0.02)};
#endif
#endif

/* Integrator tolerances [relative; m, m/s, rad/s]. float resolves the strain of these stiff
 * cables (EA = 2 MN) only to ~1e-7, i.e. 0.24 N of tension noise per segment; asking for less
 * than 1e-4 makes the step controller chase that noise (docs/firmware.md). The statics solver
 * defaults are set for double, so the float build states its own. */
#ifdef CDPR_REAL_IS_FLOAT
#define RTOL            CDPR_R(1e-4)
#define ATOL            CDPR_R(1e-4)
#define STATICS_FORCE_N CDPR_R(1e-2)
#define STATICS_SPAN_M  CDPR_R(1e-4)
#else
#define RTOL            CDPR_R(1e-6)
#define ATOL            CDPR_R(1e-6)
#define STATICS_FORCE_N CDPR_R(1e-7)
#define STATICS_SPAN_M  CDPR_R(1e-10)
#endif

/* ---- The model: one static, caller-owned plant (size in docs/firmware.md) ------------ */

static cdpr_plant_t plant;
static cdpr_plant_params_t params;
static cdpr_robot_out_t out;

#ifdef FW_CONTROL
/* ---- The controller (lib/control): one static tracker, its measurement and command ---- */

static cdpr_tracker_t tracker;
static cdpr_tracker_meas_t meas;
static cdpr_tracker_cmd_t cmd;
static uint64_t ctrl_clocks_sum;
static uint64_t ctrl_clocks_max;
static cdpr_real_t err_max_m; /* largest |p - p_d| */

/* The paper circle's path (centre (0, -2, 9.135) m, radius 2 m, from the home pose, counter-
 * clockwise) driven slowly, 0.2 m/s after a 2 s speed ramp (the paper's 2 m/s step from rest
 * asks the winches for more than this example's default winch limits give); the controller of
 * scenarios/paper-circle-laps.yaml without its transfer and learning: no pose feedback, length
 * loop 5 1/s, full d'Alembert feed-forward, winch tension feedback 1e-3 m/s/N through 50 ms. */
static int init_controller(void)
{
    cdpr_traj_t traj;
    (void)memset(&traj, 0, sizeof traj);
    traj.type = CDPR_TRAJ_CIRCLE;
    traj.centre_m[1] = CDPR_R(-2.0);
    traj.centre_m[2] = CABIN_Z_M;
    traj.radius_m = CDPR_R(2.0);
    traj.speed_m_per_s = CDPR_R(0.2);
    traj.start_angle_rad = CDPR_R(1.5707963267948966);
    traj.direction = CDPR_R(1.0);
    traj.ramp_s = CDPR_R(2.0);
    cdpr_tracker_gains_t g;
    (void)memset(&g, 0, sizeof g);
    g.k_length_per_s = CDPR_R(5.0);
    g.filter_s = CDPR_R(0.1);
    g.inertial_ff = CDPR_R(1.0);
    g.tension_gain_m_per_s_per_N = CDPR_R(1e-3);
    g.tension_filter_s = CDPR_R(0.05);
    cdpr_diag_t d;
    const cdpr_status_t st =
        cdpr_tracker_init(&tracker, &params.robot, &traj, &g, DT_S, CDPR_R(0.0), &d);
    if (st != CDPR_OK) {
        printf("tracker init: %s at %s[%d]\n", cdpr_status_str(st), d.field, d.index);
        return -1;
    }
    tracker.ik_opts.force_tol_N = STATICS_FORCE_N;
    tracker.ik_opts.span_tol_m = STATICS_SPAN_M;
    return 0;
}
#endif

/* ---- SysTick: the periodic call and the instruction counter --------------------------- */

#define SYST_CSR (*(volatile uint32_t *)0xE000E010u)
#define SYST_RVR (*(volatile uint32_t *)0xE000E014u)
#define SYST_CVR (*(volatile uint32_t *)0xE000E018u)

static volatile uint32_t ticks;

void SysTick_Handler(void); /* overrides the weak one of tests/target/startup.c */
void SysTick_Handler(void)
{
    ticks++;
}

/* SysTick clock periods since start: tick count and down-counter read consistently. */
static uint64_t now_clocks(void)
{
    uint32_t before;
    uint32_t value;
    uint32_t after;
    do {
        before = ticks;
        value = SYST_CVR;
        after = ticks;
    } while (before != after || value == 0u);
    return (uint64_t)before * SYSTICK_RELOAD + (SYSTICK_RELOAD - 1u - value);
}

/* 2 instructions per iteration (subs, bne): a loop of known length for the calibration. */
static void spin(uint32_t n)
{
    __asm__ volatile("1: subs %0, %0, #1\n\tbne 1b" : "+r"(n) : : "cc");
}

/* ---- Initialisation from the compiled-in configuration -------------------------------- */

static int init_model(void)
{
    cdpr_plant_params_default(&params);
    cdpr_robot_params_t *r = &params.robot;
    r->n_cables = N_CABLES;
    for (int j = 0; j < N_CABLES; ++j) {
        cdpr_robot_cable_params_t *c = &r->cables[j];
        c->exit_point_m = cdpr_v3(EXIT_M[j][0], EXIT_M[j][1], EXIT_M[j][2]);
        c->attach_body_m = cdpr_v3(ATTACH_M[j][0], ATTACH_M[j][1], ATTACH_M[j][2]);
        c->n_segments = N_SEGMENTS;
        c->length_m = CHORD_M;
    }
#ifdef FW_EIGHT
    /* A redundant robot: its start (the IK) resolves the redundancy by this distribution. */
    r->has_tension_dist = 1;
    r->tension_min_N = TENSION_MIN_N;
    r->tension_max_N = TENSION_MAX_N;
    r->tension_ref_N = TENSION_REF_N;
#endif
    /* Home pose at rest: the plant's IK gives the unstretched lengths that hold it and the
     * cables start on their catenaries (no settling on the target: CATENARY start). */
    const cdpr_real_t home[6] = {CDPR_R(0.0), CDPR_R(0.0), CABIN_Z_M,
                                 CDPR_R(0.0), CDPR_R(0.0), CDPR_R(0.0)};
    params.initial = cdpr_cabin_motion_at_pose(home);
    params.start = CDPR_PLANT_START_CATENARY;
    params.ik.force_tol_N = STATICS_FORCE_N;
    params.ik.span_tol_m = STATICS_SPAN_M;
    params.rkf45.step.rtol = RTOL;
    params.atol.position_m = ATOL;
    params.atol.velocity_m_per_s = ATOL;
    params.atol.quaternion = ATOL;
    params.atol.rate_rad_per_s = ATOL;
#ifndef FW_RKF45
#ifdef FW_FIXED
    params.integrator = CDPR_PLANT_ROS34PW2_FIXED;
#else
    params.integrator = CDPR_PLANT_ROS34PW2;
#endif
    params.ros.step.rtol = CDPR_R(1e-3);
    params.ros.step.h_init_s = DT_S;
    params.atol.position_m = CDPR_R(1e-4);
    params.atol.velocity_m_per_s = CDPR_R(1e-2);
    params.atol.quaternion = CDPR_R(1e-6);
    params.atol.rate_rad_per_s = CDPR_R(1e-4);
#endif
    params.period_s = DT_S;
    params.max_trials = MAX_TRIALS;
    params.max_attempts = 1; /* the real-time work bound: MAX_TRIALS trials per period */
    cdpr_diag_t d;
    const cdpr_status_t st = cdpr_plant_init(&plant, &params, &d);
    if (st != CDPR_OK) {
        printf("plant init: %s at %s[%d]\n", cdpr_status_str(st), d.field, d.index);
        return -1;
    }
    return 0;
}

/* ---- One control period: what the periodic task of a winch controller calls ---------- */

static uint64_t now_clocks(void);

static cdpr_status_t control_period(void)
{
#ifdef FW_CONTROL
    /* Measure, then the controller's commands for this period (its own clock reading). */
    cdpr_plant_measure_out(&plant, &meas, &out);
    const uint64_t c0 = now_clocks();
    const cdpr_status_t cst = cdpr_tracker_step(&tracker, &meas, &cmd);
    const uint64_t c1 = now_clocks();
    if (cst < 0) {
        return cst;
    }
    ctrl_clocks_sum += c1 - c0;
    ctrl_clocks_max = (c1 - c0 > ctrl_clocks_max) ? c1 - c0 : ctrl_clocks_max;
    const cdpr_real_t e = cdpr_v3_norm(cdpr_v3_sub(meas.cabin.p_m, cmd.desired.motion.p_m));
    err_max_m = (e > err_max_m) ? e : err_max_m;
    const cdpr_real_t *rates = cmd.rate_m_per_s;
#else
    const cdpr_real_t *rates = RATE_CMD_M_PER_S;
#endif
    /* Winch commands -> limits -> exactly dt with at most MAX_TRIALS trials -> node events.
     * On an error the plant is exactly as before the call (the next period tries again). */
    int flags = 0;
    const cdpr_status_t st = cdpr_plant_step(&plant, CDPR_WINCH_RATE, rates, &flags);
    if (st < 0) {
        return st;
    }
#ifndef FW_CONTROL
    /* Cabin force and end tensions for telemetry / the controller. */
    cdpr_plant_outputs(&plant, &out);
#endif
    return st;
}

#ifndef FW_RKF45
/* The parts of an implicit period, measured once on the final state: one RHS evaluation, one
 * factorisation of W (gamma h for the 1 ms step) and one solve. A trial is 4 RHS + 4 solves
 * (+ 1 factorisation when W is renewed) + the stage arithmetic: the floor of any 4-stage
 * W-method on this model (docs/performance.md). */
#define FW_DIM_MAX (CDPR_CABIN_STATE_DIM + N_CABLES * (1 + 6 * (N_SEGMENTS + 3)))
static cdpr_real_t scratch_f[FW_DIM_MAX];
static cdpr_real_t scratch_x[FW_DIM_MAX];

static void print_part_costs(uint64_t per_calib)
{
    cdpr_robot_t *robot = &plant.robot;
    if (robot->dim > FW_DIM_MAX || per_calib == 0u) {
        return;
    }
    const cdpr_real_t gamma_h = CDPR_R(0.435866521508459) * DT_S;
    const cdpr_real_t t_s = (cdpr_real_t)plant.k * DT_S;
    const uint64_t c0 = now_clocks();
    const cdpr_status_t s1 = cdpr_robot_rhs(t_s, plant.y, scratch_f, robot);
    const uint64_t c1 = now_clocks();
    const cdpr_status_t s2 = cdpr_robot_w_factor(&plant.w, t_s, plant.y, gamma_h);
    const uint64_t c2 = now_clocks();
    const cdpr_status_t s3 = cdpr_robot_w_solve(&plant.w, scratch_f, scratch_x);
    const uint64_t c3 = now_clocks();
    if (s1 < 0 || s2 < 0 || s3 < 0) {
        printf("parts: %s / %s / %s\n", cdpr_status_str(s1), cdpr_status_str(s2),
               cdpr_status_str(s3));
        return;
    }
    printf("parts, instructions: rhs %lu, factorisation %lu, solve %lu\n",
           (unsigned long)((c1 - c0) * 200000u / per_calib),
           (unsigned long)((c2 - c1) * 200000u / per_calib),
           (unsigned long)((c3 - c2) * 200000u / per_calib));
}
#endif

int main(void)
{
    if (init_model() != 0) {
        return 1;
    }
#ifdef FW_CONTROL
    if (init_controller() != 0) {
        return 1;
    }
#endif
    SYST_RVR = SYSTICK_RELOAD - 1u;
    SYST_CVR = 0u;
    SYST_CSR = 0x7u; /* processor clock, interrupt, enable */

    /* Calibration: clocks for a loop of 2 x 100000 instructions. */
    const uint64_t c0 = now_clocks();
    spin(100000u);
    const uint64_t c1 = now_clocks();
    const uint64_t per_calib = c1 - c0;

    uint64_t clocks_max = 0u;
    uint64_t clocks_sum = 0u;
    uint32_t overruns = 0u;
    uint32_t warnings = 0u;
    uint32_t last = ticks;
    for (int k = 0; k < N_PERIODS; ++k) {
        while (ticks == last) {
            __asm__ volatile("wfi");
        }
        overruns += (ticks - last > 1u) ? 1u : 0u;
        last = ticks;
        const uint64_t s0 = now_clocks();
        const cdpr_status_t st = control_period();
        const uint64_t s1 = now_clocks();
        if (st < 0) {
            printf("period %d: %s\n", k, cdpr_status_str(st));
            return 1;
        }
        warnings += (st > 0) ? 1u : 0u;
        clocks_sum += s1 - s0;
        clocks_max = (s1 - s0 > clocks_max) ? s1 - s0 : clocks_max;
    }
#ifndef FW_RKF45
    print_part_costs(per_calib);
#endif
    SYST_CSR = 0u;

    /* Integers only: newlib-nano's printf has no floating point unless asked for. */
    int ok = 1;
    const cdpr_robot_t *robot = &plant.robot;
    for (int i = 0; i < robot->dim; ++i) {
        ok = (isfinite(plant.y[i]) != 0) ? ok : 0;
    }
    cdpr_plant_work_t work;
    cdpr_plant_work(&plant, &work);
    printf("cdpr firmware example: %d cables x %d segments, %s, %d periods of 1 ms\n", N_CABLES,
           N_SEGMENTS, (sizeof(cdpr_real_t) == 4u) ? "float" : "double", N_PERIODS);
    printf("cabin z: %ld mm, state dim %d, rhs evals %lu, substep-limit periods %lu\n",
           (long)lroundf((float)(plant.y[CDPR_CABIN_P + 2] * CDPR_R(1000.0))), robot->dim,
           work.rhs_evals, (unsigned long)warnings);
    printf("per period, max: rhs evals %lu, factorisations %lu, solves %lu\n",
           plant.stats.max_rhs_evals, plant.stats.max_factorisations, plant.stats.max_solves);
    if (params.integrator == CDPR_PLANT_ROS34PW2_FIXED) {
        /* every period did exactly this work; the error estimate is a health figure */
        printf("fixed mode: %d substeps per period, error norm max x1000 %ld, above 1 in %lu "
               "periods\n",
               plant.substeps, (long)lroundf((float)(plant.stats.max_err_norm * CDPR_R(1000.0))),
               plant.stats.err_above_one_periods);
        ok = (plant.stats.max_rhs_evals * (unsigned long)N_PERIODS == work.rhs_evals) ? ok : 0;
    }
    for (int j = 0; j < N_CABLES; ++j) {
        const long tc = (long)lroundf((float)out.tension_cabin_N[j]);
        const long tw = (long)lroundf((float)out.tension_winch_N[j]);
        printf("cable %d: tension cabin %ld N, winch %ld N, payout %ld mm/s\n", j, tc, tw,
               (long)lroundf((float)(plant.winch[j].u_m_per_s * CDPR_R(1000.0))));
        ok = (out.tension_cabin_N[j] > CDPR_R(0.0)) ? ok : 0; /* taut, as configured */
    }
    /* With -icount shift=0: 1 instruction = 1 ns of virtual time; the calibration loop is
     * 200000 instructions, so instructions = clocks x 200000 / per_calib. */
    if (per_calib > 0u) {
        printf("instructions per control period (valid under -icount shift=0): "
               "mean %lu, max %lu (calibration %lu clocks / 200000 instructions)\n",
               (unsigned long)(clocks_sum * 200000u / per_calib / N_PERIODS),
               (unsigned long)(clocks_max * 200000u / per_calib), (unsigned long)per_calib);
    }
#ifdef FW_CONTROL
    /* The controller's share of the period (inside the total above), its IK failures (held
     * feed-forward) and the tracking error over the first 0.2 s of the speed ramp: a sanity
     * bound of 1 cm (a host run of the same loop: 2.6 mm at 0.2 s, 14 mm at most over the 2 s
     * ramp), not a performance claim. */
    printf("controller: feed-forward IK failures %lu, max tracking error %ld um\n",
           tracker.ik_failures, (long)lroundf((float)(err_max_m * CDPR_R(1e6))));
    ok = (tracker.ik_failures == 0u && err_max_m < CDPR_R(0.01)) ? ok : 0;
    if (per_calib > 0u) {
        printf("controller instructions per period (cdpr_tracker_step): mean %lu, max %lu\n",
               (unsigned long)(ctrl_clocks_sum * 200000u / per_calib / N_PERIODS),
               (unsigned long)(ctrl_clocks_max * 200000u / per_calib));
    }
#endif
    printf("overruns of the 1 ms tick: %lu\n", (unsigned long)overruns);
    printf("%s\n", (ok != 0) ? "OK" : "FAILED");
    return (ok != 0) ? 0 : 1;
}
