/* SPDX-License-Identifier: BSD-3-Clause */
/// @file test_winch.c
/// Winch payout/haul-in with node insertion and removal (docs/model.md §2, winch and node
/// events): conservation of the unstretched length at every event, the last-segment window,
/// momentum change per event, node-event counts per metre, capacity, return to the start, and
/// the command limits.
#include <math.h>
#include <string.h>

#include "cdpr/robot.h"
#include "cdpr/rkf45.h"
#include "cdpr/settle.h"
#include "cdpr/winch.h"
#include "test_real.h"
#include "unity.h"

void setUp(void) {}
void tearDown(void) {}

static cdpr_robot_t robot;
static cdpr_real_t y[CDPR_ROBOT_STATE_MAX];
static cdpr_real_t y_start[CDPR_ROBOT_STATE_MAX];
static cdpr_real_t scratch[CDPR_ROBOT_STATE_MAX];
static cdpr_real_t work[CDPR_RKF45_WORK_PER_DIM * CDPR_ROBOT_STATE_MAX];
static cdpr_rkf45_t solver;

static const double L0 = 25.0;
static const int N0 = 10; /* Delta = 2.5 m */

static void build_with(int n, double length, double damping)
{
    cdpr_robot_params_t p;
    cdpr_robot_params_default(&p);
    p.mode = CDPR_CABIN_PRESCRIBED; /* cable end A held at the origin */
    /* Soft (EA = 2 kN: ~2 % strain under its own weight) so paying out at 0.5 m/s keeps
     * the cable taut: payout faster than the cable can sag makes the pulley-side segment
     * slack, which is physics but not what these tests are about. */
    p.cables[0].cable.ea_N = 2.0e3;
    p.cables[0].cable.damping_Ns = damping;
    p.cables[0].exit_point_m = cdpr_v3(20.0, 0.0, 5.0);
    p.cables[0].n_segments = n;
    p.cables[0].length_m = length;
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_robot_init(&robot, &p, NULL));
    cdpr_cabin_motion_t m;
    memset(&m, 0, sizeof m);
    m.q.w = 1.0;
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_robot_place_straight(&robot, &m, y));
    cdpr_rkf45_params_t sp;
    cdpr_rkf45_params_default(&sp);
    /* float: requests float can honour on coordinates of ~20 m (u_f |y| = 1.2e-6). */
    sp.step.rtol = TOL(1e-7, 1e-5);
    sp.step.atol = TOL(1e-8, 1e-5);
    TEST_ASSERT_EQUAL_INT(CDPR_OK,
                          cdpr_rkf45_init(&solver, &sp, work, (int)(sizeof work / sizeof work[0]),
                                          CDPR_ROBOT_STATE_MAX, robot.dim, NULL));
}

/* Build, settle to rest with material damping (same damping ratio as the default rope:
 * 170 N s at EA = 2 MN scales with sqrt(EA)), then continue without it. With damping the
 * tension jumps from 0 to c eps_dot when a slack segment turns taut while stretching; a
 * whipping cable (fast haul-in) does that often and the adaptive integrator pays for every
 * jump with rejected steps. These tests are about node events, so they run the conservative
 * model, whose RHS is continuous (docs/model.md, "Slack"). */
static void settle(void);
static void build(int n, double length)
{
    build_with(n, length, 170.0 * sqrt(2.0e3 / 2.0e6));
    settle();
    memcpy(y_start, y, sizeof(cdpr_real_t) * (size_t)robot.dim);
    build_with(n, length, 0.0);
    memcpy(y, y_start, sizeof(cdpr_real_t) * (size_t)robot.dim);
}

static double total_length(void)
{
    return cdpr_cable_total_length(&robot.cable[0], y + robot.offset[0]);
}

/* Linear momentum of the free nodes (lumped masses as in docs/model.md §2). */
static void momentum(double p[3], double *vmax)
{
    const cdpr_cable_t *c = &robot.cable[0];
    const int nf = c->n - 1;
    const cdpr_real_t *vel = y + robot.offset[0] + 1 + 3 * nf;
    p[0] = p[1] = p[2] = 0.0;
    *vmax = 0.0;
    for (int i = 1; i <= nf; ++i) {
        const double lu_next = (i == nf) ? y[robot.offset[0]] : c->lu_m[i];
        const double m = 0.5 * c->p.rho_kg_per_m * (c->lu_m[i - 1] + lu_next);
        const cdpr_real_t *v = vel + 3 * (i - 1);
        for (int k = 0; k < 3; ++k) {
            p[k] += m * v[k];
        }
        *vmax = fmax(*vmax, sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]));
    }
}

typedef struct {
    double max_len_jump;   /* |L after - L before| over events [m] */
    double max_dp;         /* |momentum change| per event [kg m/s] */
    double max_dp_bound;   /* rho * 2 Delta * vmax at that event */
    int window_violations; /* last segment outside [Delta/2, 2 Delta] after events */
} event_check_t;

/* Run `seconds` at payout rate u (periods of 10 ms, events after each period). */
static void run(double u, double seconds, cdpr_node_stats_t *ns, event_check_t *ec, int *warn_cap)
{
    robot.in.payout_m_per_s[0] = u;
    const int periods = (int)lround(seconds / 0.01);
    cdpr_real_t t = 0.0;
    for (int k = 0; k < periods; ++k) {
        const cdpr_status_t st =
            cdpr_rkf45_advance(&solver, cdpr_robot_rhs, &robot, &t, y, 0.01, 400);
        TEST_ASSERT_EQUAL_INT(CDPR_OK, st);
        const double len_before = total_length();
        double p0[3];
        double vmax;
        momentum(p0, &vmax);
        int changed = 0;
        const cdpr_status_t ev = cdpr_winch_node_events(&robot, t, y, ns, &changed);
        TEST_ASSERT_TRUE(ev == CDPR_OK || ev == CDPR_WARN_CAPACITY);
        if (ev == CDPR_WARN_CAPACITY) {
            ++*warn_cap;
        }
        if (changed != 0) {
            TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_rkf45_set_dim(&solver, robot.dim));
            ec->max_len_jump = fmax(ec->max_len_jump, fabs(total_length() - len_before));
            double p1[3];
            double vmax1;
            momentum(p1, &vmax1);
            const double dp =
                sqrt((p1[0] - p0[0]) * (p1[0] - p0[0]) + (p1[1] - p0[1]) * (p1[1] - p0[1]) +
                     (p1[2] - p0[2]) * (p1[2] - p0[2]));
            const double bound =
                robot.cable[0].p.rho_kg_per_m * 2.0 * robot.cable[0].delta_m * vmax;
            if (dp > ec->max_dp) {
                ec->max_dp = dp;
                ec->max_dp_bound = bound;
            }
            const double last = y[robot.offset[0]];
            const double d = robot.cable[0].delta_m;
            if (robot.cable[0].n < CDPR_MAX_SEGMENTS && (last < 0.5 * d || last > 2.0 * d)) {
                ec->window_violations++;
            }
        }
    }
}

static void settle(void)
{
    cdpr_settle_t cfg;
    cdpr_settle_default(&cfg);
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_settle_robot(&robot, &solver, y, scratch, &cfg));
}

/* Why the float build skips the two settled cases below: the node forces carry rounding of
 * EA x 2 u_f = 2.4e-4 N per segment, ~1.4e-3 m/s^2 on 0.35 kg nodes (7e-3 on the 0.07 kg
 * nodes of the capacity case). Measured on the host's float build: the round trip's start
 * settles under cdpr_settle_default's float tolerance of 1e-2 m/s^2 (at 8e-3), the capacity
 * case's stalls at ~7e-2 m/s^2 (CDPR_E_NO_CONVERGENCE). And the round trip still cannot count
 * events exactly: 20 m is exactly 8 Delta, and the payout integrated in float ends 3e-4 m
 * short of the 8th insertion threshold. */
#define SKIP_SETTLED_IN_FLOAT()                                                                    \
    SKIP_IN_FLOAT("settling to rest needs node forces below float rounding (test_winch.c)")

static void test_payout_and_haul_in_round_trip(void)
{
    SKIP_SETTLED_IN_FLOAT();
    build(N0, L0);
    const int dim0 = robot.dim;
    cdpr_node_stats_t ns;
    memset(&ns, 0, sizeof ns);
    event_check_t ec;
    memset(&ec, 0, sizeof ec);
    int warn = 0;
    /* 20 m out at 0.5 m/s, then 20 m in: Delta = 2.5 m, so 8 insertions then 8 removals. */
    run(0.5, 40.0, &ns, &ec, &warn);
    TEST_ASSERT_DOUBLE_WITHIN(1e-9, L0 + 20.0, total_length()); /* d lu/dt = u, exactly */
    TEST_ASSERT_EQUAL_UINT32(8u, (unsigned)ns.insertions[0]);
    TEST_ASSERT_EQUAL_UINT32(0u, (unsigned)ns.removals[0]);
    TEST_ASSERT_EQUAL_INT(N0 + 8, robot.cable[0].n);
    run(-0.5, 40.0, &ns, &ec, &warn);
    TEST_ASSERT_DOUBLE_WITHIN(1e-9, L0, total_length());
    /* No chattering: exactly one event per Delta paid out or hauled in. */
    TEST_ASSERT_EQUAL_UINT32(8u, (unsigned)ns.insertions[0]);
    TEST_ASSERT_EQUAL_UINT32(8u, (unsigned)ns.removals[0]);
    TEST_ASSERT_EQUAL_INT(0, warn);
    TEST_ASSERT_EQUAL_INT(0, ec.window_violations);
    /* Events move lengths between segments only: the total is unchanged to rounding
     * (a few ulp of 45 m). */
    TEST_ASSERT_TRUE(ec.max_len_jump <= 1e-13);
    /* Momentum change per event: the interpolated/merged node mass (at most rho * 2 Delta)
     * times the node speed near the pulley. */
    TEST_ASSERT_TRUE(ec.max_dp <= ec.max_dp_bound + 1e-15);
    /* Back at the start length: same node count and, once at rest, the same equilibrium.
     * Settle with the material damping back on (a fresh robot of the same layout). */
    TEST_ASSERT_EQUAL_INT(N0, robot.cable[0].n);
    TEST_ASSERT_EQUAL_INT(dim0, robot.dim);
    static cdpr_real_t y_end[CDPR_ROBOT_STATE_MAX];
    memcpy(y_end, y, sizeof(cdpr_real_t) * (size_t)robot.dim);
    build_with(N0, L0, 170.0 * sqrt(2.0e3 / 2.0e6));
    memcpy(y, y_end, sizeof(cdpr_real_t) * (size_t)robot.dim);
    settle();
    for (int i = 0; i < robot.dim; ++i) {
        /* Settled to 1e-6 m/s^2 with transverse stiffness ~ T/Delta ~ 10 N/m on ~0.35 kg
         * nodes: static position error << 1e-6 m; 1e-5 m bounds it. */
        TEST_ASSERT_DOUBLE_WITHIN(1e-5, y_start[i], y[i]);
    }
}

static void test_capacity_reached_keeps_running_with_warning(void)
{
    SKIP_SETTLED_IN_FLOAT();
    build(CDPR_MAX_SEGMENTS - 1, (CDPR_MAX_SEGMENTS - 1) * 0.5); /* Delta = 0.5 m */
    cdpr_node_stats_t ns;
    memset(&ns, 0, sizeof ns);
    event_check_t ec;
    memset(&ec, 0, sizeof ec);
    int warn = 0;
    run(0.5, 6.0, &ns, &ec, &warn); /* 3 m out: one insertion, then capacity */
    TEST_ASSERT_EQUAL_UINT32(1u, (unsigned)ns.insertions[0]);
    TEST_ASSERT_EQUAL_INT(CDPR_MAX_SEGMENTS, robot.cable[0].n);
    TEST_ASSERT_TRUE(warn > 0);
    TEST_ASSERT_EQUAL_UINT32((unsigned)warn, (unsigned)ns.capacity_hits[0]);
    TEST_ASSERT_TRUE(y[robot.offset[0]] > 2.0 * robot.cable[0].delta_m); /* last keeps growing */
    TEST_ASSERT_DOUBLE_WITHIN(1e-9, (CDPR_MAX_SEGMENTS - 1) * 0.5 + 3.0, total_length());
}

static void test_single_segment_cable_grows_from_the_cabin_node(void)
{
    /* n = 1: the inserted node is interpolated from the cabin attachment; hauling back in
     * removes it and returns to one segment. */
    build(1, 21.0);
    cdpr_node_stats_t ns;
    memset(&ns, 0, sizeof ns);
    event_check_t ec;
    memset(&ec, 0, sizeof ec);
    int warn = 0;
    run(0.5, 44.0, &ns, &ec, &warn); /* 21 -> 43 m > 2 Delta = 42 m */
    TEST_ASSERT_EQUAL_UINT32(1u, (unsigned)ns.insertions[0]);
    TEST_ASSERT_EQUAL_INT(2, robot.cable[0].n);
    TEST_ASSERT_DOUBLE_WITHIN(1e-9, 21.0, robot.cable[0].lu_m[0]);
    run(-0.5, 44.0, &ns, &ec, &warn);
    TEST_ASSERT_EQUAL_INT(1, robot.cable[0].n);
    TEST_ASSERT_EQUAL_INT(CDPR_CABIN_STATE_DIM + 1, robot.dim);
    /* d lu/dt = u is integrated exactly, but float rounds lu (<= 43 m: u_f lu = 2.6e-6) once
     * per accepted step: bound (accepted steps) x 2 u_f x 43 m (test_real.h). */
    const double tol_len = TOL(1e-9, (double)solver.stats.steps_accepted * 2.0 * U_REAL * 43.0);
    TEST_ASSERT_DOUBLE_WITHIN(tol_len, 21.0, total_length());
}

static void test_winch_rate_and_acceleration_limits(void)
{
    cdpr_winch_params_t p;
    cdpr_winch_params_default(&p);
    cdpr_winch_t w;
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_winch_init(&w, &p, NULL));
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_winch_command(&w, CDPR_WINCH_RATE, 10.0));
    /* Accelerates at a_max = 5 m/s^2: after k periods of 0.1 s, u = 0.5 k, capped at 4. */
    for (int k = 1; k <= 10; ++k) {
        TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_winch_update(&w, 100.0, 0.1));
        TEST_ASSERT_DOUBLE_WITHIN(1e-12, fmin(0.5 * k, 4.0), w.u_m_per_s);
    }
    /* Bad commands are refused and the last good one kept. */
    TEST_ASSERT_EQUAL_INT(CDPR_E_NOT_FINITE, cdpr_winch_command(&w, CDPR_WINCH_RATE, NAN_R));
    TEST_ASSERT_EQUAL_INT(CDPR_E_OUT_OF_RANGE, cdpr_winch_command(&w, CDPR_WINCH_LENGTH, -1.0));
    TEST_ASSERT_EQUAL_INT(CDPR_E_OUT_OF_RANGE, cdpr_winch_command(&w, (cdpr_winch_mode_t)7, 1.0));
    TEST_ASSERT_EQUAL_INT(CDPR_WINCH_RATE, w.mode);
    TEST_ASSERT_DOUBLE_WITHIN(0.0, 10.0, w.command);
}

static void test_winch_length_mode_and_minimum_length(void)
{
    cdpr_winch_params_t p;
    cdpr_winch_params_default(&p);
    p.min_length_m = 10.0;
    cdpr_winch_t w;
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_winch_init(&w, &p, NULL));
    /* Length mode: L' = kp (L_cmd - L) within the limits converges to the setpoint. */
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_winch_command(&w, CDPR_WINCH_LENGTH, 12.0));
    double L = 20.0;
    for (int k = 0; k < 2000; ++k) {
        (void)cdpr_winch_update(&w, L, 0.005);
        L += w.u_m_per_s * 0.005;
        TEST_ASSERT_TRUE(fabs(w.u_m_per_s) <= p.u_max_m_per_s);
    }
    TEST_ASSERT_DOUBLE_WITHIN(1e-6, 12.0, L);
    /* Hauling in at full speed stops exactly at the minimum and reports it. */
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_winch_command(&w, CDPR_WINCH_RATE, -4.0));
    cdpr_status_t st = CDPR_OK;
    for (int k = 0; k < 400 && st == CDPR_OK; ++k) {
        st = cdpr_winch_update(&w, L, 0.01);
        L += w.u_m_per_s * 0.01;
    }
    TEST_ASSERT_EQUAL_INT(CDPR_WARN_MIN_LENGTH, st);
    /* float: L reaches the core rounded to float (u_f x 10 m = 6e-7) and the stopping rate
     * carries one more rounding: 2e-6. */
    TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-12, 2e-6), 10.0, L);
    TEST_ASSERT_EQUAL_INT(1, w.at_min_length);
    TEST_ASSERT_EQUAL_INT(CDPR_WARN_MIN_LENGTH, cdpr_winch_update(&w, L, 0.01));
    TEST_ASSERT_DOUBLE_WITHIN(1e-12, 0.0, w.u_m_per_s);
    /* Paying out again leaves the minimum. */
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_winch_command(&w, CDPR_WINCH_RATE, 1.0));
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_winch_update(&w, L, 0.01));
    TEST_ASSERT_TRUE(w.u_m_per_s > 0.0);
    /* Invalid limits are named. */
    cdpr_diag_t d;
    p.a_max_m_per_s2 = INF_R;
    TEST_ASSERT_EQUAL_INT(CDPR_E_NOT_FINITE, cdpr_winch_init(&w, &p, &d));
    TEST_ASSERT_EQUAL_STRING("a_max_m_per_s2", d.field);
}

/* One event on a known state, against the rules of winch.h written out here (issue 26: a
 * wrong velocity of the inserted node, or a removal that did not merge the momenta, passed
 * the loose per-event momentum bound above):
 *  - insertion: the new node at the unstretched fraction f = Delta / lu_last of the straight
 *    last segment from the last free node to the pulley, with velocity (1 - f) v_last (the
 *    pulley at rest); every other node unchanged;
 *  - removal: the surviving neighbour takes (m_keep v_keep + m_gone v_gone) / (m_keep +
 *    m_gone), m = half the unstretched lengths on either side times rho; the rest unchanged. */
static void test_event_states_follow_the_rules(void)
{
    build_with(N0, L0, 0.0);
    const cdpr_cable_t *c = &robot.cable[0];
    const int o = robot.offset[0];
    const double delta = (double)c->delta_m;
    const cdpr_vec3_t A = robot.p.cables[0].exit_point_m;
    /* Known velocities: node i moves at (0.1 i, -0.05 i, 0.02 i) m/s. */
    int nf = c->n - 1;
    for (int i = 0; i < nf; ++i) {
        cdpr_real_t *v = y + o + 1 + 3 * nf + 3 * i;
        v[0] = (cdpr_real_t)(0.1 * (i + 1));
        v[1] = (cdpr_real_t)(-0.05 * (i + 1));
        v[2] = (cdpr_real_t)(0.02 * (i + 1));
    }
    /* Insertion: the last segment 2 Delta + 0.4 m long. */
    const double lu_last = 2.0 * delta + 0.4;
    y[o] = (cdpr_real_t)lu_last;
    double pa[3];
    double va[3];
    for (int k = 0; k < 3; ++k) {
        pa[k] = (double)y[o + 1 + 3 * (nf - 1) + k];
        va[k] = (double)y[o + 1 + 3 * nf + 3 * (nf - 1) + k];
    }
    const double pb[3] = {(double)A.x, (double)A.y, (double)A.z};
    cdpr_node_stats_t ns;
    memset(&ns, 0, sizeof ns);
    int changed = 0;
    cdpr_real_t t = 0.0;
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_winch_node_events(&robot, t, y, &ns, &changed));
    TEST_ASSERT_EQUAL_INT(1, changed);
    TEST_ASSERT_EQUAL_INT(nf + 1, c->n - 1);
    const double f = delta / lu_last;
    for (int k = 0; k < 3; ++k) {
        const double p_new = (double)y[o + 1 + 3 * nf + k];
        const double v_new = (double)y[o + 1 + 3 * (nf + 1) + 3 * nf + k];
        TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-12, 1e-5), pa[k] + f * (pb[k] - pa[k]), p_new);
        TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-14, 1e-6), (1.0 - f) * va[k], v_new);
        /* The node before it is unchanged. */
        TEST_ASSERT_DOUBLE_WITHIN(0.0, va[k], (double)y[o + 1 + 3 * (nf + 1) + 3 * (nf - 1) + k]);
    }
    TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-12, 1e-5), lu_last - delta, (double)y[o]);

    /* Removal: the last segment shorter than Delta / 2. */
    nf = c->n - 1;
    y[o] = (cdpr_real_t)(0.3 * delta);
    const double rho = (double)c->p.rho_kg_per_m;
    const double lu_pp = (double)c->lu_m[nf - 2];
    const double lu_prev = (double)c->lu_m[nf - 1];
    const double m_keep = 0.5 * rho * (lu_pp + lu_prev);
    const double m_gone = 0.5 * rho * (lu_prev + 0.3 * delta);
    double v_keep[3];
    double v_gone[3];
    for (int k = 0; k < 3; ++k) {
        v_keep[k] = (double)y[o + 1 + 3 * nf + 3 * (nf - 2) + k];
        v_gone[k] = (double)y[o + 1 + 3 * nf + 3 * (nf - 1) + k];
    }
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_winch_node_events(&robot, t, y, &ns, &changed));
    TEST_ASSERT_EQUAL_INT(1, changed);
    TEST_ASSERT_EQUAL_INT(nf - 1, c->n - 1);
    for (int k = 0; k < 3; ++k) {
        const double want = (m_keep * v_keep[k] + m_gone * v_gone[k]) / (m_keep + m_gone);
        TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-14, 1e-6), want,
                                  (double)y[o + 1 + 3 * (nf - 1) + 3 * (nf - 2) + k]);
    }
    TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-12, 1e-5), lu_prev + 0.3 * delta, (double)y[o]);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_payout_and_haul_in_round_trip);
    RUN_TEST(test_event_states_follow_the_rules);
    RUN_TEST(test_capacity_reached_keeps_running_with_warning);
    RUN_TEST(test_single_segment_cable_grows_from_the_cabin_node);
    RUN_TEST(test_winch_rate_and_acceleration_limits);
    RUN_TEST(test_winch_length_mode_and_minimum_length);
    return UNITY_END() ? 1 : 0;
}
