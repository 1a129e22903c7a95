/* SPDX-License-Identifier: BSD-3-Clause */
/// @file main.c
/// cdpr-bench: cost of the core's right-hand side and of one RKF45 step, against GSL's rkf45
/// on the identical RHS, state and step (docs/performance.md).
///
/// Prints three tables and the machine:
///   (a) ns per segment per cdpr_robot_rhs evaluation, 1 and 6 cables x {8, 16, 32, 64}
///       segments, on the 50 m model (docs/robots.md set A) with taut cables and small random
///       node velocities (every branch of the segment model is taken);
///   (b) one fixed-h RKF45 step: cdpr_rkf45_trial vs gsl_odeiv2_step_apply (both 6 RHS calls);
///   (c) adaptive stepping as users call it: cdpr_rkf45_step vs gsl_odeiv2_evolve_apply, per
///       accepted step, with the RHS calls per step each one made;
///   (d) the implicit ROS34PW2 trial (robot_w.h): factorisation, solve and the whole trial
///       (1 factorisation, 4 solves, 4 RHS), in us and in RHS evaluations;
///   (e) one period of the fixed-cost mode;
///   (f) the sag-aware inverse kinematics per call: six cables (cdpr_statics_ik, and GSL's
///       18-unknown solve for comparison) and eight cables with the tension distribution
///       (cdpr_statics_ik_dist), over 20 poses, with the iterations each took.
/// Times are the best of N runs, each repeating the operation for at least T seconds
/// (CLOCK_MONOTONIC). Our timed loops make no heap allocation; GSL's objects are allocated
/// before timing (cdpr_gsl_stepper_init).
///
/// Host only: links cdpr_gsl, hence GSL (GPL-3).
#ifndef _GNU_SOURCE
#define _POSIX_C_SOURCE 200809L /* clock_gettime under -std=c99 */
#endif

#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_odeiv2.h>
#include <gsl/gsl_version.h>

#include "app_cli.h"
#include "app_status.h"
#include "cdpr/config.h"
#include "cdpr/gsl/ref.h"
#include "cdpr/host/clock.h"
#include "cdpr/rkf45.h"
#include "cdpr/robot.h"
#include "cdpr/robot_w.h"
#include "cdpr/ros34pw2.h"
#include "cdpr/gsl/statics.h"
#include "cdpr/statics.h"

#define DEG_TO_RAD (CDPR_PI / 180.0)

typedef struct {
    double min_time_s; /* each run repeats the operation for at least this long [s] */
    int runs;          /* best of this many runs */
} options_t;

static cdpr_robot_t robot;
static double y0s[CDPR_ROBOT_STATE_MAX];  /* the benchmark state */
static double ys[CDPR_ROBOT_STATE_MAX];   /* working copy */
static double yout[CDPR_ROBOT_STATE_MAX]; /* trial output */
static double dydt[CDPR_ROBOT_STATE_MAX];
static double work[CDPR_RKF45_WORK_PER_DIM * CDPR_ROBOT_STATE_MAX];
static volatile double sink; /* keeps results observable */

/* ------------------------------------------------------------------------------------------ */
/* The benchmark robot                                                                         */

/* Fixed-seed 64-bit LCG (Knuth's MMIX constants): repeatable "random" velocities. */
static unsigned long long lcg_state = 0x2545F4914F6CDD1DULL;

static double lcg_uniform(void) /* in [-1, 1) */
{
    lcg_state = lcg_state * 6364136223846793005ULL + 1442695040888963407ULL;
    return (double)(lcg_state >> 11) * (2.0 / 9007199254740992.0) - 1.0;
}

/* docs/robots.md set A: exit points (25 cos th, 25 sin th, 30) m, th_j = (j-1) 60 deg; cabin at
 * (0, 0, 9.135) m, level; attachments radius 2 m, z = -0.5 m, azimuths 25, 35, 145, 155, 265,
 * 275 deg; default cable (6 mm, 0.14 kg/m, EA 2e6 N, c 170 N s). Unstretched length = straight
 * distance / 1.002: every segment is stretched 0.2 % (taut, the tension branch is taken).
 * Cables 1..n_cables of the six. Node velocities uniform in +-5 cm/s, cabin velocity +-1 cm/s
 * and body rates +-0.01 rad/s, so the damping and drag terms are non-trivial. Returns 0 on
 * success. */
static int make_robot(int n_cables, int n_segments)
{
    static const double attach_az_deg[6] = {25.0, 35.0, 145.0, 155.0, 265.0, 275.0};
    cdpr_robot_params_t p;
    cdpr_robot_params_default(&p);
    p.n_cables = n_cables;
    p.mode = CDPR_CABIN_DYNAMIC;
    const cdpr_vec3_t cabin = cdpr_v3(0.0, 0.0, 9.135);
    for (int j = 0; j < n_cables; ++j) {
        cdpr_robot_cable_params_t *c = &p.cables[j];
        const double th = 60.0 * (double)j * DEG_TO_RAD;
        const double az = attach_az_deg[j] * DEG_TO_RAD;
        c->exit_point_m = cdpr_v3(25.0 * cos(th), 25.0 * sin(th), 30.0);
        c->attach_body_m = cdpr_v3(2.0 * cos(az), 2.0 * sin(az), -0.5);
        const cdpr_vec3_t a = cdpr_v3_add(cabin, c->attach_body_m); /* q = identity */
        c->length_m = cdpr_v3_norm(cdpr_v3_sub(c->exit_point_m, a)) / 1.002;
        c->n_segments = n_segments;
    }
    cdpr_diag_t diag;
    cdpr_status_t st = cdpr_robot_init(&robot, &p, &diag);
    if (st != CDPR_OK) {
        fprintf(stderr, "cdpr-bench: robot init failed: %s (%s, %d)\n", cdpr_status_str(st),
                diag.field, diag.index);
        return -1;
    }
    cdpr_cabin_motion_t m;
    m.p_m = cabin;
    m.q.w = 1.0;
    m.q.x = 0.0;
    m.q.y = 0.0;
    m.q.z = 0.0;
    m.v_m_per_s = cdpr_v3(0.01 * lcg_uniform(), 0.01 * lcg_uniform(), 0.01 * lcg_uniform());
    m.w_rad_per_s = cdpr_v3(0.01 * lcg_uniform(), 0.01 * lcg_uniform(), 0.01 * lcg_uniform());
    st = cdpr_robot_place_straight(&robot, &m, y0s);
    if (st != CDPR_OK) {
        fprintf(stderr, "cdpr-bench: placement failed: %s\n", cdpr_status_str(st));
        return -1;
    }
    for (int j = 0; j < n_cables; ++j) {
        const int nf = robot.cable[j].n - 1;
        double *vel = y0s + robot.offset[j] + 1 + 3 * nf;
        for (int i = 0; i < 3 * nf; ++i) {
            vel[i] = 0.05 * lcg_uniform();
        }
    }
    return 0;
}

/* ------------------------------------------------------------------------------------------ */
/* Timing                                                                                      */

/* One timed operation: `reps` repetitions; returns the units of work done (for per-unit
 * times, e.g. accepted steps), or `reps` when each repetition is one unit. */
typedef double (*bench_fn)(void *ctx, long reps);

typedef struct {
    double ns_per_unit; /* best run */
    long reps;          /* repetitions per run */
} timing_t;

static timing_t measure(bench_fn fn, void *ctx, const options_t *o)
{
    /* Calibrate: grow reps until one run lasts min_time (the growth also warms caches). */
    long reps = 1;
    for (;;) {
        const double t0 = cdpr_clock_now_s();
        (void)fn(ctx, reps);
        const double dt = cdpr_clock_now_s() - t0;
        if (dt >= o->min_time_s) {
            break;
        }
        const double grow = (dt > 0.0) ? 1.2 * o->min_time_s / dt : 10.0;
        const double next = (double)reps * ((grow < 10.0) ? ((grow > 1.5) ? grow : 1.5) : 10.0);
        reps = (long)next + 1;
    }
    timing_t r;
    r.reps = reps;
    r.ns_per_unit = (double)INFINITY;
    for (int k = 0; k < o->runs; ++k) {
        const double t0 = cdpr_clock_now_s();
        const double units = fn(ctx, reps);
        const double ns = 1e9 * (cdpr_clock_now_s() - t0) / units;
        if (ns < r.ns_per_unit) {
            r.ns_per_unit = ns;
        }
    }
    return r;
}

/* (a) one RHS evaluation. */
static double bench_rhs(void *ctx, long reps)
{
    (void)ctx;
    double acc = 0.0;
    for (long k = 0; k < reps; ++k) {
        (void)cdpr_robot_rhs(0.0, y0s, dydt, &robot);
        acc += dydt[robot.dim - 1];
    }
    sink = acc;
    return (double)reps;
}

/* (b) fixed-h single steps. Both loops restore the working state first (GSL steps in place),
 * so both carry the same copy of dim doubles. */
typedef struct {
    cdpr_rkf45_t ours;
    cdpr_gsl_stepper_t gsl;
    double h_s;
    int dim;
} step_ctx_t;

static void restore(int dim)
{
    memcpy(ys, y0s, (size_t)dim * sizeof(double));
}

static double bench_ours_trial(void *ctx, long reps)
{
    step_ctx_t *c = (step_ctx_t *)ctx;
    double err = 0.0;
    double acc = 0.0;
    for (long k = 0; k < reps; ++k) {
        restore(c->dim);
        (void)cdpr_rkf45_trial(&c->ours, cdpr_robot_rhs, &robot, 0.0, ys, c->h_s, yout, &err);
        acc += err;
    }
    sink = acc + yout[c->dim - 1];
    return (double)reps;
}

static double bench_gsl_apply(void *ctx, long reps)
{
    step_ctx_t *c = (step_ctx_t *)ctx;
    for (long k = 0; k < reps; ++k) {
        restore(c->dim);
        (void)cdpr_gsl_stepper_apply(&c->gsl, 0.0, c->h_s, ys);
    }
    sink = ys[c->dim - 1] + c->gsl.yerr[c->dim - 1];
    return (double)reps;
}

/* (c) adaptive stepping: each repetition restarts from the benchmark state and takes
 * SEQ_STEPS accepted steps; the unit is one accepted step (rejected trials included). */
#define SEQ_STEPS 50
#define SEQ_H0_S  1e-4

typedef struct {
    cdpr_rkf45_t ours;
    cdpr_rkf45_params_t ours_params;
    cdpr_gsl_stepper_t gsl;
    int dim;
    unsigned long rhs_ours; /* RHS calls in the last run */
    unsigned long rhs_gsl;
    double t_reached_ours_s; /* simulated time covered by one sequence */
    double t_reached_gsl_s;
} seq_ctx_t;

static double bench_ours_steps(void *ctx, long reps)
{
    seq_ctx_t *c = (seq_ctx_t *)ctx;
    unsigned long evals = 0;
    double t = 0.0;
    for (long k = 0; k < reps; ++k) {
        restore(c->dim);
        /* Restart the step-size history and counters (O(1): atol_vec is NULL). */
        (void)cdpr_rkf45_init(&c->ours, &c->ours_params, work, (int)(sizeof work / sizeof work[0]),
                              CDPR_ROBOT_STATE_MAX, c->dim, NULL);
        t = 0.0;
        for (int i = 0; i < SEQ_STEPS; ++i) {
            (void)cdpr_rkf45_step(&c->ours, cdpr_robot_rhs, &robot, &t, ys, 1.0);
        }
        evals += c->ours.stats.rhs_evals;
    }
    c->rhs_ours = evals;
    c->t_reached_ours_s = t;
    sink = ys[c->dim - 1];
    return (double)reps * SEQ_STEPS;
}

static double bench_gsl_evolve(void *ctx, long reps)
{
    seq_ctx_t *c = (seq_ctx_t *)ctx;
    const unsigned long e0 = c->gsl.adapter.rhs_evals;
    double t = 0.0;
    for (long k = 0; k < reps; ++k) {
        restore(c->dim);
        cdpr_gsl_stepper_reset(&c->gsl); /* y jumped back: drop GSL's cached dydt */
        t = 0.0;
        double h = SEQ_H0_S;
        for (int i = 0; i < SEQ_STEPS; ++i) {
            (void)cdpr_gsl_stepper_evolve(&c->gsl, &t, 1.0, &h, ys);
        }
    }
    c->rhs_gsl = c->gsl.adapter.rhs_evals - e0;
    c->t_reached_gsl_s = t;
    sink = ys[c->dim - 1];
    return (double)reps * SEQ_STEPS;
}

/* ------------------------------------------------------------------------------------------ */
/* Tables                                                                                      */

static int total_segments(void)
{
    int s = 0;
    for (int j = 0; j < robot.p.n_cables; ++j) {
        s += robot.cable[j].n;
    }
    return s;
}

static int table_rhs(const options_t *o)
{
    static const int cables[2] = {1, 6};
    static const int segs[4] = {8, 16, 32, 64};
    printf("(a) cdpr_robot_rhs, one evaluation (50 m model, taut cables, random node "
           "velocities)\n");
    printf("    %6s %10s %6s %8s %12s %14s\n", "cables", "segs/cable", "segs", "dim", "ns/eval",
           "ns/segment");
    for (int a = 0; a < 2; ++a) {
        for (int b = 0; b < 4; ++b) {
            if (make_robot(cables[a], segs[b]) != 0) {
                return -1;
            }
            const timing_t t = measure(bench_rhs, NULL, o);
            const int ns = total_segments();
            printf("    %6d %10d %6d %8d %12.1f %14.2f\n", cables[a], segs[b], ns, robot.dim,
                   t.ns_per_unit, t.ns_per_unit / (double)ns);
        }
    }
    printf("\n");
    return 0;
}

static int table_step(const options_t *o)
{
    static const int segs[3] = {16, 32, 64};
    printf("(b) one RKF45 step, same RHS, state and h = 1e-4 s (each: 6 RHS evaluations)\n");
    printf("    %6s %10s %8s %14s %18s %10s\n", "cables", "segs/cable", "dim", "ours trial us",
           "GSL step_apply us", "ours/GSL");
    for (int b = 0; b < 3; ++b) {
        if (make_robot(6, segs[b]) != 0) {
            return -1;
        }
        step_ctx_t c;
        c.h_s = 1e-4;
        c.dim = robot.dim;
        cdpr_rkf45_params_t p;
        cdpr_rkf45_params_default(&p);
        cdpr_diag_t diag;
        if (cdpr_rkf45_init(&c.ours, &p, work, (int)(sizeof work / sizeof work[0]),
                            CDPR_ROBOT_STATE_MAX, robot.dim, &diag) != CDPR_OK ||
            cdpr_gsl_stepper_init(&c.gsl, cdpr_robot_rhs, &robot, (size_t)robot.dim, p.step.rtol,
                                  p.step.atol) != CDPR_OK) {
            fprintf(stderr, "cdpr-bench: integrator init failed\n");
            return -1;
        }
        const timing_t to = measure(bench_ours_trial, &c, o);
        const timing_t tg = measure(bench_gsl_apply, &c, o);
        printf("    %6d %10d %8d %14.2f %18.2f %10.3f\n", 6, segs[b], robot.dim,
               1e-3 * to.ns_per_unit, 1e-3 * tg.ns_per_unit, to.ns_per_unit / tg.ns_per_unit);
        cdpr_gsl_stepper_free(&c.gsl);
    }
    printf("\n");
    return 0;
}

static int table_adaptive(const options_t *o)
{
    static const int segs[3] = {16, 32, 64};
    printf("(c) adaptive stepping as users call it, rtol 1e-6, atol 1e-8, %d accepted steps from\n"
           "    h0 = 1e-4 s: cdpr_rkf45_step vs gsl_odeiv2_evolve_apply (rejected trials "
           "included)\n",
           SEQ_STEPS);
    printf("    %6s %10s %12s %9s %12s %9s %10s %12s\n", "cables", "segs/cable", "ours us/step",
           "RHS/step", "GSL us/step", "RHS/step", "ours/GSL", "trial/evolve");
    for (int b = 0; b < 3; ++b) {
        if (make_robot(6, segs[b]) != 0) {
            return -1;
        }
        seq_ctx_t c;
        c.dim = robot.dim;
        cdpr_rkf45_params_default(&c.ours_params);
        c.ours_params.step.h_init_s = SEQ_H0_S;
        cdpr_diag_t diag;
        if (cdpr_rkf45_init(&c.ours, &c.ours_params, work, (int)(sizeof work / sizeof work[0]),
                            CDPR_ROBOT_STATE_MAX, robot.dim, &diag) != CDPR_OK ||
            cdpr_gsl_stepper_init(&c.gsl, cdpr_robot_rhs, &robot, (size_t)robot.dim,
                                  c.ours_params.step.rtol, c.ours_params.step.atol) != CDPR_OK) {
            fprintf(stderr, "cdpr-bench: integrator init failed\n");
            return -1;
        }
        const timing_t to = measure(bench_ours_steps, &c, o);
        const timing_t tg = measure(bench_gsl_evolve, &c, o);
        /* A fixed-h trial on the same state, for the trial-vs-evolve column. */
        step_ctx_t s;
        s.h_s = 1e-4;
        s.dim = robot.dim;
        s.ours = c.ours;
        const timing_t tt = measure(bench_ours_trial, &s, o);
        const double steps_o = (double)to.reps * SEQ_STEPS;
        const double steps_g = (double)tg.reps * SEQ_STEPS;
        printf("    %6d %10d %12.2f %9.2f %12.2f %9.2f %10.3f %12.3f\n", 6, segs[b],
               1e-3 * to.ns_per_unit, (double)c.rhs_ours / steps_o, 1e-3 * tg.ns_per_unit,
               (double)c.rhs_gsl / steps_g, to.ns_per_unit / tg.ns_per_unit,
               tt.ns_per_unit / tg.ns_per_unit);
        printf("    %6s %10s   (%d steps cover %.2f ms ours, %.2f ms GSL)\n", "", "", SEQ_STEPS,
               1e3 * c.t_reached_ours_s, 1e3 * c.t_reached_gsl_s);
        cdpr_gsl_stepper_free(&c.gsl);
    }
    printf("\n");
    return 0;
}

/* ------------------------------------------------------------------------------------------ */
/* Machine                                                                                     */

/* (d) the implicit trial and its parts. */
typedef struct {
    cdpr_ros_t ros;
    cdpr_robot_w_t w;
    cdpr_ros_problem_t pb;
    double h_s;
} ros_ctx_t;

static double bench_w_factor(void *ctx, long reps)
{
    ros_ctx_t *c = (ros_ctx_t *)ctx;
    for (long k = 0; k < reps; ++k) {
        (void)cdpr_robot_w_factor(&c->w, 0.0, y0s, 0.435866521508459 * c->h_s);
    }
    sink = c->w.dinv[0][0][0];
    return (double)reps;
}

static double bench_w_solve(void *ctx, long reps)
{
    ros_ctx_t *c = (ros_ctx_t *)ctx;
    double acc = 0.0;
    for (long k = 0; k < reps; ++k) {
        (void)cdpr_robot_w_solve(&c->w, dydt, yout);
        acc += yout[robot.dim - 1];
    }
    sink = acc;
    return (double)reps;
}

static double bench_ros_trial(void *ctx, long reps)
{
    ros_ctx_t *c = (ros_ctx_t *)ctx;
    double err = 0.0;
    double acc = 0.0;
    for (long k = 0; k < reps; ++k) {
        restore(robot.dim);
        (void)cdpr_ros_trial(&c->ros, &c->pb, 0.0, ys, c->h_s, yout, &err);
        acc += err;
    }
    sink = acc + yout[robot.dim - 1];
    return (double)reps;
}

/* The 6-cable benchmark robot with `segs` segments per cable, a ROS34PW2 solver on its W and
 * W factored for the 1 ms step at the benchmark state: 0, or -1 after saying why. */
static int ros_setup(ros_ctx_t *c, int segs)
{
    if (make_robot(6, segs) != 0) {
        return -1;
    }
    cdpr_ros_params_t p;
    cdpr_ros_params_default(&p);
    cdpr_diag_t diag;
    if (cdpr_ros_init(&c->ros, &p, work, (int)(sizeof work / sizeof work[0]), CDPR_ROBOT_STATE_MAX,
                      robot.dim, &diag) != CDPR_OK ||
        cdpr_robot_w_init(&c->w, &robot) != CDPR_OK ||
        cdpr_robot_w_factor(&c->w, 0.0, y0s, 0.435866521508459e-3) != CDPR_OK) {
        fprintf(stderr, "cdpr-bench: implicit integrator init failed\n");
        return -1;
    }
    c->pb.f = cdpr_robot_rhs;
    c->pb.f_ctx = &robot;
    c->pb.factor = cdpr_robot_w_factor;
    c->pb.solve = cdpr_robot_w_solve;
    c->pb.lin_ctx = &c->w;
    c->h_s = 1e-3;
    return 0;
}

static int table_ros(const options_t *o)
{
    static const int segs[3] = {16, 32, 64};
    static ros_ctx_t c;
    printf("(d) one ROS34PW2 trial (ros34pw2.h + robot_w.h), h = 1 ms, same RHS and state;\n"
           "    RHS-eq = time / one cdpr_robot_rhs evaluation\n");
    printf("    %6s %10s %8s %9s %11s %8s %10s %8s %10s %8s\n", "cables", "segs/cable", "dim",
           "RHS us", "factor us", "RHS-eq", "solve us", "RHS-eq", "trial us", "RHS-eq");
    for (int b = 0; b < 3; ++b) {
        if (ros_setup(&c, segs[b]) != 0) {
            return -1;
        }
        (void)cdpr_robot_rhs(0.0, y0s, dydt, &robot);
        const timing_t tr = measure(bench_rhs, NULL, o);
        const timing_t tf = measure(bench_w_factor, &c, o);
        const timing_t ts = measure(bench_w_solve, &c, o);
        const timing_t tt = measure(bench_ros_trial, &c, o);
        printf("    %6d %10d %8d %9.2f %11.2f %8.2f %10.2f %8.2f %10.2f %8.2f\n", 6, segs[b],
               robot.dim, 1e-3 * tr.ns_per_unit, 1e-3 * tf.ns_per_unit,
               tf.ns_per_unit / tr.ns_per_unit, 1e-3 * ts.ns_per_unit,
               ts.ns_per_unit / tr.ns_per_unit, 1e-3 * tt.ns_per_unit,
               tt.ns_per_unit / tr.ns_per_unit);
    }
    printf("\n");
    return 0;
}

/* (e) one period of the fixed-cost mode: cdpr_ros_fixed over 1 ms in n substeps. */
typedef struct {
    ros_ctx_t *c;
    int n;
} fixed_ctx_t;

static double bench_ros_fixed(void *ctx, long reps)
{
    const fixed_ctx_t *f = (const fixed_ctx_t *)ctx;
    double err = 0.0;
    double acc = 0.0;
    for (long k = 0; k < reps; ++k) {
        restore(robot.dim);
        double t = 0.0;
        (void)cdpr_ros_fixed(&f->c->ros, &f->c->pb, &t, ys, 1e-3, f->n, &err);
        acc += err;
    }
    sink = acc + ys[robot.dim - 1];
    return (double)reps;
}

static int table_fixed(const options_t *o)
{
    /* n: what the plant derives for the paper circle's rope at 1 kHz (docs/model.md). */
    static const int segs[3] = {16, 32, 64};
    static const int subs[3] = {2, 3, 6};
    static ros_ctx_t c;
    printf("(e) one period of the fixed-cost mode (cdpr_ros_fixed, 1 ms in n substeps: n\n"
           "    factorisations, 4n solves, 4n RHS), same state; RHS-eq as in (d)\n");
    printf("    %6s %10s %8s %3s %11s %8s\n", "cables", "segs/cable", "dim", "n", "period us",
           "RHS-eq");
    for (int b = 0; b < 3; ++b) {
        if (ros_setup(&c, segs[b]) != 0) {
            return -1;
        }
        fixed_ctx_t f = {&c, subs[b]};
        const timing_t tr = measure(bench_rhs, NULL, o);
        const timing_t tp = measure(bench_ros_fixed, &f, o);
        printf("    %6d %10d %8d %3d %11.2f %8.2f\n", 6, segs[b], robot.dim, subs[b],
               1e-3 * tp.ns_per_unit, tp.ns_per_unit / tr.ns_per_unit);
    }
    printf("\n");
    return 0;
}

/* (f): the IK over a set of poses. */
enum { IK_POSES = 20 };
typedef struct {
    cdpr_cabin_motion_t pose[IK_POSES];
    cdpr_statics_dist_t dist;
    int use_dist; /* 0: cdpr_statics_ik, 1: cdpr_statics_ik_dist, 2: GSL */
    long iterations;
    int worst;
} ik_ctx_t;

static double bench_ik(void *ctx, long reps)
{
    ik_ctx_t *c = (ik_ctx_t *)ctx;
    cdpr_statics_opts_t o;
    cdpr_statics_opts_default(&o);
    const cdpr_vec3_t zero = cdpr_v3(0.0, 0.0, 0.0);
    double acc = 0.0;
    c->iterations = 0;
    c->worst = 0;
    for (long r = 0; r < reps; ++r) {
        for (int k = 0; k < IK_POSES; ++k) {
            cdpr_statics_result_t res;
            cdpr_status_t st;
            if (c->use_dist == 1) {
                st =
                    cdpr_statics_ik_dist(&robot, &c->pose[k], zero, zero, &c->dist, &o, &res, NULL);
            } else if (c->use_dist == 2) {
                st = cdpr_gsl_statics_ik(&robot, &c->pose[k], 500, &res);
            } else {
                st = cdpr_statics_ik(&robot, &c->pose[k], &o, &res);
            }
            if (st != CDPR_OK) {
                return -1.0;
            }
            acc += res.cable[0].length_m;
            c->iterations += res.iterations;
            c->worst = (res.iterations > c->worst) ? res.iterations : c->worst;
        }
    }
    sink = acc;
    return (double)(reps * IK_POSES);
}

/* Robot for (f): the 50 m model (6 cables), or the eight-cable layout of
 * tests/unit/test_gsl_statics_dist.c (four towers, two cables each). */
static int ik_robot(int n_cables)
{
    static const double attach_az_deg[6] = {25.0, 35.0, 145.0, 155.0, 265.0, 275.0};
    cdpr_robot_params_t p;
    cdpr_robot_params_default(&p);
    p.n_cables = n_cables;
    for (int j = 0; j < n_cables; ++j) {
        cdpr_robot_cable_params_t *c = &p.cables[j];
        if (n_cables == 6) {
            const double th = 60.0 * (double)j * DEG_TO_RAD;
            const double az = attach_az_deg[j] * DEG_TO_RAD;
            c->exit_point_m = cdpr_v3(25.0 * cos(th), 25.0 * sin(th), 30.0);
            c->attach_body_m = cdpr_v3(2.0 * cos(az), 2.0 * sin(az), -0.5);
        } else {
            const int tower = j / 2; /* two cables per tower */
            const double side = (j % 2 != 0) ? 1.0 : -1.0;
            const double th = (double)tower * CDPR_PI / 2.0 + CDPR_PI / 4.0 + 0.2 * side;
            const double az = (double)tower * CDPR_PI / 2.0 + CDPR_PI / 4.0 - 0.5 * side;
            c->exit_point_m = cdpr_v3(25.0 * cos(th), 25.0 * sin(th), 30.0);
            c->attach_body_m = cdpr_v3(1.5 * cos(az), 1.5 * sin(az), 0.5 * side);
        }
        c->length_m = 30.0;
        c->n_segments = 8;
    }
    cdpr_diag_t diag;
    const cdpr_status_t st = cdpr_robot_init(&robot, &p, &diag);
    if (st != CDPR_OK) {
        fprintf(stderr, "cdpr-bench: robot init failed: %s (%s, %d)\n", cdpr_status_str(st),
                diag.field, diag.index);
        return -1;
    }
    return 0;
}

static int table_ik(const options_t *o)
{
    printf("(f) sag-aware inverse kinematics per call, 20 poses of the central workspace (x, y\n"
           "    within 2 m, z 10-16 m, tilts within 0.05 rad), 50 m model's rope and cabin\n");
    printf("    %-48s %10s %8s %6s\n", "case", "us/call", "iter", "max");
    static ik_ctx_t c;
    for (int k = 0; k < IK_POSES; ++k) {
        const double x = 2.0 * lcg_uniform();
        const double yy = 2.0 * lcg_uniform();
        const double z = 13.0 + 3.0 * lcg_uniform();
        c.pose[k].p_m = cdpr_v3(x, yy, z);
        c.pose[k].q =
            cdpr_quat_from_euler(0.05 * lcg_uniform(), 0.05 * lcg_uniform(), 0.05 * lcg_uniform());
        c.pose[k].v_m_per_s = cdpr_v3(0.0, 0.0, 0.0);
        c.pose[k].w_rad_per_s = c.pose[k].v_m_per_s;
    }
    cdpr_statics_dist_init(&c.dist, 25.0, 500.0);
    static const struct {
        int cables;
        int mode;
        const char *name;
    } cases[3] = {{6, 0, "6 cables, cdpr_statics_ik (Newton)"},
                  {6, 2, "6 cables, GSL hybrid on 18 unknowns (allocates)"},
                  {8, 1, "8 cables, cdpr_statics_ik_dist 25-500 N (SQP)"}};
    for (int i = 0; i < 3; ++i) {
        if (cases[i].cables > CDPR_MAX_CABLES) {
            printf("    %-48s (a build with CDPR_MAX_CABLES >= %d)\n", cases[i].name,
                   cases[i].cables);
            continue;
        }
        if (ik_robot(cases[i].cables) != 0) {
            return -1;
        }
        c.use_dist = cases[i].mode;
        if (bench_ik(&c, 1) < 0.0) {
            fprintf(stderr, "cdpr-bench: (f) %s: a pose did not solve\n", cases[i].name);
            return -1;
        }
        const timing_t t = measure(bench_ik, &c, o);
        (void)bench_ik(&c, 1);
        printf("    %-48s %10.1f %8.2f %6d\n", cases[i].name, 1e-3 * t.ns_per_unit,
               (double)c.iterations / IK_POSES, c.worst);
    }
    printf("\n");
    return 0;
}

static void print_machine(const options_t *o)
{
    char model[256] = "unknown";
    char mhz[64] = "?";
    int cpus = 0;
    FILE *f = fopen("/proc/cpuinfo", "r");
    if (f != NULL) {
        char line[512];
        while (fgets(line, (int)sizeof line, f) != NULL) {
            const char *colon = strchr(line, ':');
            if (colon == NULL) {
                continue;
            }
            const char *val = colon + 1;
            while (*val == ' ' || *val == '\t') {
                ++val;
            }
            const size_t len = strcspn(val, "\n");
            if (strncmp(line, "model name", 10) == 0) {
                ++cpus;
                if (cpus == 1 && len < sizeof model) {
                    memcpy(model, val, len);
                    model[len] = '\0';
                }
            } else if (strncmp(line, "cpu MHz", 7) == 0 && mhz[0] == '?' && len < sizeof mhz) {
                memcpy(mhz, val, len);
                mhz[len] = '\0';
            }
        }
        fclose(f);
    }
    printf("machine : %s, %d logical CPUs, %s MHz (from /proc/cpuinfo)\n", model, cpus, mhz);
#if defined(__clang__)
    printf("compiler: clang %s\n", __VERSION__);
#elif defined(__GNUC__)
    printf("compiler: gcc %s\n", __VERSION__);
#else
    printf("compiler: %s\n", __VERSION__);
#endif
    /* The exact -O level is not visible to the preprocessor; these macros are. */
    printf("build   : %s%s%s%s%s%s\n",
#ifdef __OPTIMIZE__
           "optimised (__OPTIMIZE__)",
#else
           "NOT optimised (-O0: use the release preset)",
#endif
#ifdef NDEBUG
           ", NDEBUG",
#else
           ", assertions on",
#endif
#ifdef __FAST_MATH__
           ", -ffast-math",
#else
           ", IEEE math (no -ffast-math)",
#endif
#if defined(__SANITIZE_ADDRESS__)
           ", AddressSanitizer",
#else
           "",
#endif
#if defined(__AVX2__)
           ", AVX2",
#elif defined(__AVX__)
           ", AVX",
#elif defined(__SSE2__)
           ", SSE2 (baseline x86-64, no -march)",
#else
           "",
#endif
#if defined(__FMA__)
           ", FMA available");
#else
           "");
#endif
    printf("GSL     : %s; cdpr_real_t = double; CDPR_MAX_SEGMENTS %d, CDPR_MAX_CABLES %d\n",
           GSL_VERSION, CDPR_MAX_SEGMENTS, CDPR_MAX_CABLES);
    printf("timing  : CLOCK_MONOTONIC, best of %d runs, each >= %.2f s\n\n", o->runs,
           o->min_time_s);
}

static void usage(FILE *f)
{
    fprintf(f, "usage: cdpr-bench [--quick] [--help] [--version]\n"
               "Time the cdpr core's RHS and RKF45 step against GSL's rkf45 on the same RHS.\n\n"
               "  --quick   short runs (0.02 s, best of 2): a smoke test, numbers are noisy\n"
               "  --help    this text\n"
               "  --version version and git description\n\n"
               "Default: best of 5 runs of >= 0.2 s per case (about a minute). Build with the\n"
               "release preset; see docs/performance.md.\n"
               "exit codes: 0 done, 2 bad command line or a case the core refused (no files)\n");
}

int main(int argc, char **argv)
{
    options_t o;
    o.min_time_s = 0.2;
    o.runs = 5;
    static const struct option long_opts[] = {{"quick", no_argument, NULL, 'q'},
                                              CDPR_APP_STD_OPTIONS_END};
    opterr = 0;
    for (;;) {
        const int c = getopt_long(argc, argv, CDPR_APP_OPTSTRING "q", long_opts, NULL);
        if (c == -1) {
            break;
        }
        switch (c) {
        case 'q':
            o.min_time_s = 0.02;
            o.runs = 2;
            break;
        default:
            return cdpr_app_exit_code(
                cdpr_app_other_option("cdpr-bench", c, argv, long_opts, usage));
        }
    }
    if (optind < argc) {
        return cdpr_app_exit_code(
            cdpr_app_usage_error("cdpr-bench", "unexpected argument '%s'", argv[optind]));
    }

    printf("cdpr-bench: the cdpr core's RHS and RKF45 step vs GSL rkf45 on the same RHS\n");
    print_machine(&o);
    if (table_rhs(&o) != 0 || table_step(&o) != 0 || table_adaptive(&o) != 0 ||
        table_ros(&o) != 0 || table_fixed(&o) != 0 || table_ik(&o) != 0) {
        /* A benchmark robot or integrator the core refused (the message says which). */
        return cdpr_app_exit_code(CDPR_E_INVALID_ARG);
    }
    printf("Allocation: the timed loops of our side call only cdpr_core, which references no\n"
           "allocator (core_symbols test); GSL's objects are allocated before timing.\n");
    return cdpr_app_exit_code(CDPR_OK);
}
