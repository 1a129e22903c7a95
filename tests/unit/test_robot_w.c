/* SPDX-License-Identifier: BSD-3-Clause */
/// @file test_robot_w.c
/// The robot's W-matrix (robot_w.h): the block-tridiagonal solve against W applied by central
/// finite differences of cdpr_robot_rhs (an independent Jacobian), on cables whose dropped
/// terms vanish (no drag, nodes at rest, cabin held), and the failure paths.
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "cdpr/robot.h"
#include "cdpr/robot_w.h"
#include "test_real.h"
#include "unity.h"

void setUp(void) {}
void tearDown(void) {}

static cdpr_robot_t robot;
static cdpr_robot_w_t wm;
static cdpr_real_t y[CDPR_ROBOT_STATE_MAX];
static cdpr_real_t b[CDPR_ROBOT_STATE_MAX];
static cdpr_real_t x[CDPR_ROBOT_STATE_MAX];
static cdpr_real_t yp[CDPR_ROBOT_STATE_MAX];
static cdpr_real_t fp[CDPR_ROBOT_STATE_MAX];
static cdpr_real_t fm[CDPR_ROBOT_STATE_MAX];

/* Two cables from a held cabin (prescribed, motion_fn NULL): a taut one with a sagged,
 * stretched shape and a slack one, so every branch of the tension law appears. */
static void build(cdpr_slack_law_t law, double damping)
{
    cdpr_robot_params_t p;
    cdpr_robot_params_default(&p);
    p.mode = CDPR_CABIN_PRESCRIBED;
    p.n_cables = 2;
    for (int j = 0; j < 2; ++j) {
        cdpr_robot_cable_params_t *c = &p.cables[j];
        c->cable.cd = CDPR_R(0.0);
        c->cable.damping_Ns = (cdpr_real_t)damping;
        c->cable.slack_law = law;
        c->attach_body_m = cdpr_v3(CDPR_R(0.0), CDPR_R(0.0), CDPR_R(0.0));
        c->n_segments = 12;
    }
    p.cables[0].exit_point_m = cdpr_v3(CDPR_R(20.0), CDPR_R(3.0), CDPR_R(10.0));
    p.cables[0].length_m = CDPR_R(21.0); /* every segment taut after the bend below */
    p.cables[1].exit_point_m = cdpr_v3(CDPR_R(-10.0), CDPR_R(-5.0), CDPR_R(4.0));
    p.cables[1].length_m = CDPR_R(14.0);
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_robot_init(&robot, &p, NULL));
    cdpr_cabin_motion_t m;
    memset(&m, 0, sizeof m);
    m.q.w = CDPR_R(1.0);
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_robot_place_straight(&robot, &m, y));
    /* Bend the cables: node i of cable j moves by a smooth offset normal to the chord, so the
     * taut segments are stretched by different amounts and point in different directions. */
    for (int j = 0; j < 2; ++j) {
        const int nf = robot.cable[j].n - 1;
        cdpr_real_t *pos = y + robot.offset[j] + 1;
        for (int i = 1; i <= nf; ++i) {
            const double s = (double)i / (double)(nf + 1);
            pos[3 * (i - 1) + 2] -= (cdpr_real_t)(0.8 * sin(3.14159265358979 * s));
            pos[3 * (i - 1) + 1] += (cdpr_real_t)(0.3 * sin(2.0 * 3.14159265358979 * s));
        }
    }
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_robot_w_init(&wm, &robot));
}

/* A direction on the free-node rows only (cabin and payout rows zero). */
static void node_direction(cdpr_real_t *v, unsigned seed)
{
    memset(v, 0, sizeof(cdpr_real_t) * (size_t)robot.dim);
    unsigned s = seed;
    for (int j = 0; j < robot.p.n_cables; ++j) {
        const int nf = robot.cable[j].n - 1;
        for (int i = 1; i < 1 + 6 * nf; ++i) {
            s = s * 1664525u + 1013904223u;
            v[robot.offset[j] + i] = (cdpr_real_t)(((double)(s >> 8) / 16777216.0) - 0.5);
        }
    }
}

/* W v = v - g J v with J v by central differences of the RHS (step e). */
static void apply_w(const cdpr_real_t *v, double g, double e, cdpr_real_t *out)
{
    for (int i = 0; i < robot.dim; ++i) {
        yp[i] = y[i] + (cdpr_real_t)e * v[i];
    }
    (void)cdpr_robot_rhs(0.0, yp, fp, &robot);
    for (int i = 0; i < robot.dim; ++i) {
        yp[i] = y[i] - (cdpr_real_t)e * v[i];
    }
    (void)cdpr_robot_rhs(0.0, yp, fm, &robot);
    for (int i = 0; i < robot.dim; ++i) {
        const double jv = ((double)fp[i] - (double)fm[i]) / (2.0 * e);
        out[i] = (cdpr_real_t)((double)v[i] - g * jv);
    }
}

/* Largest |(W x)_i - b_i| / max(|b|, |x|) over the free-node rows (W x is a difference of
 * terms of the size of x). */
static double residual(double g, int only_cable)
{
    static cdpr_real_t wx[CDPR_ROBOT_STATE_MAX];
    /* Central differences with e = 1e-5 (perturbations 1e-5..1e-2 m: no segment changes
     * branch): truncation O(e^2) and rounding 1e-16 |f| / e, both below 1e-7 relative to x
     * (measured 1e-10..3e-8; e = 1e-4 and 1e-6 give 1e-7 and 3e-7, e = 1e-8 1e-5: rounding). */
    apply_w(x, g, 1e-5, wx);
    double r = 0.0;
    double bmax = 0.0;
    for (int j = 0; j < robot.p.n_cables; ++j) {
        const int nf = robot.cable[j].n - 1;
        if (only_cable >= 0 && j != only_cable) {
            continue;
        }
        for (int i = 1; i < 1 + 6 * nf; ++i) {
            const int k = robot.offset[j] + i;
            r = fmax(r, fabs((double)wx[k] - (double)b[k]));
            bmax = fmax(bmax, fmax(fabs((double)b[k]), fabs((double)x[k])));
        }
    }
    return r / bmax;
}

static void check_solve(cdpr_slack_law_t law, double damping)
{
    SKIP_IN_FLOAT("finite differences of the RHS need double");
    build(law, damping);
    const double gs[3] = {1e-5, 4.4e-4, 4e-3};
    for (int k = 0; k < 3; ++k) {
        TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_robot_w_factor(&wm, 0.0, y, (cdpr_real_t)gs[k]));
        node_direction(b, 7u + (unsigned)k);
        TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_robot_w_solve(&wm, b, x));
        const double r = residual(gs[k], -1);
        char msg[80];
        (void)snprintf(msg, sizeof msg, "g %.1e residual %.3e", gs[k], r);
        TEST_ASSERT_TRUE_MESSAGE(r < 1e-6, msg);
        /* Identity rows: cabin and payout. */
        TEST_ASSERT_EQUAL_MEMORY(b, x, sizeof(cdpr_real_t) * CDPR_CABIN_STATE_DIM);
        for (int j = 0; j < robot.p.n_cables; ++j) {
            TEST_ASSERT_EQUAL_MEMORY(&b[robot.offset[j]], &x[robot.offset[j]], sizeof x[0]);
        }
    }
}

static void test_solve_inverts_w_passive(void)
{
    check_solve(CDPR_SLACK_PASSIVE, 0.0);
}

static void test_solve_inverts_w_moordyn(void)
{
    check_solve(CDPR_SLACK_MOORDYN, 170.0);
}

/* The passive law's damper enters B on the taut cable (cable 0; on the slack cable 1 at rest
 * the law sits on its kink T = max(0, c eps'), where central differences average the two
 * sides, so it is left out). At rest the dropped direction term c (I - t tT) dv / (l lu) is 0. */
static void test_solve_inverts_w_with_axial_damping(void)
{
    SKIP_IN_FLOAT("finite differences of the RHS need double");
    build(CDPR_SLACK_PASSIVE, 170.0);
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_robot_w_factor(&wm, 0.0, y, CDPR_R(1e-3)));
    node_direction(b, 3u);
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_robot_w_solve(&wm, b, x));
    const double r = residual(1e-3, 0);
    char msg[48];
    (void)snprintf(msg, sizeof msg, "residual %.3e", r);
    TEST_ASSERT_TRUE_MESSAGE(r < 1e-6, msg);
}

/* Dynamic mode: a symmetric four-cable robot (combined CoM at the body origin) with the cabin
 * implicit. At rest the dropped cabin terms (gyroscopic, attitude dependence of v_0 and of
 * q_dot, the CoM offset) vanish; what remains dropped is the change of the torque's R^T with
 * the attitude, of relative size T lu / (EA |a|) (~1e-3 here), so the body-rate rows are checked
 * to 1e-2 and every other row (node, position, quaternion and velocity rows) to 1e-6. */
static void test_solve_inverts_w_dynamic_cabin(void)
{
    SKIP_IN_FLOAT("finite differences of the RHS need double");
    cdpr_robot_params_t p;
    cdpr_robot_params_default(&p);
    p.mode = CDPR_CABIN_DYNAMIC;
    p.n_cables = 4;
    const double ex[4][3] = {{10, 10, 12}, {-10, 10, 12}, {-10, -10, 12}, {10, -10, 12}};
    const double at[4][3] = {
        {0.5, 0.5, 0.0}, {-0.5, 0.5, 0.0}, {-0.5, -0.5, 0.0}, {0.5, -0.5, 0.0}};
    for (int j = 0; j < 4; ++j) {
        cdpr_robot_cable_params_t *c = &p.cables[j];
        c->cable.cd = CDPR_R(0.0);
        c->cable.damping_Ns = CDPR_R(170.0);
        c->exit_point_m =
            cdpr_v3((cdpr_real_t)ex[j][0], (cdpr_real_t)ex[j][1], (cdpr_real_t)ex[j][2]);
        c->attach_body_m =
            cdpr_v3((cdpr_real_t)at[j][0], (cdpr_real_t)at[j][1], (cdpr_real_t)at[j][2]);
        c->n_segments = 10;
        c->length_m = CDPR_R(16.0); /* taut: chords of 17.6 m */
    }
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_robot_init(&robot, &p, NULL));
    cdpr_cabin_motion_t m;
    memset(&m, 0, sizeof m);
    m.q = cdpr_quat_from_euler(CDPR_R(0.1), CDPR_R(-0.05), CDPR_R(0.2));
    m.p_m = cdpr_v3(CDPR_R(0.3), CDPR_R(-0.2), CDPR_R(0.5));
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_robot_place_straight(&robot, &m, y));
    for (int j = 0; j < 4; ++j) {
        const int nf = robot.cable[j].n - 1;
        cdpr_real_t *pos = y + robot.offset[j] + 1;
        for (int i = 1; i <= nf; ++i) {
            pos[3 * (i - 1) + 2] -= (cdpr_real_t)(0.2 * sin(3.14159265358979 * i / (nf + 1.0)));
        }
    }
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_robot_w_init(&wm, &robot));
    const double g = 1e-3;
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_robot_w_factor(&wm, 0.0, y, (cdpr_real_t)g));
    node_direction(b, 11u);
    unsigned s = 5u;
    for (int i = 0; i < CDPR_CABIN_STATE_DIM; ++i) {
        s = s * 1664525u + 1013904223u;
        b[i] = (cdpr_real_t)(((double)(s >> 8) / 16777216.0) - 0.5);
    }
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_robot_w_solve(&wm, b, x));
    static cdpr_real_t wx[CDPR_ROBOT_STATE_MAX];
    apply_w(x, g, 1e-5, wx);
    double xmax = 0.0;
    for (int i = 0; i < robot.dim; ++i) {
        xmax = fmax(xmax, fmax(fabs((double)x[i]), fabs((double)b[i])));
    }
    for (int i = 0; i < robot.dim; ++i) {
        const int is_rate = (i >= CDPR_CABIN_W && i < CDPR_CABIN_W + 3);
        int is_lu = 0;
        for (int j = 0; j < 4; ++j) {
            is_lu |= (i == robot.offset[j]);
        }
        if (is_lu != 0) {
            continue; /* payout rows: identity, and x_lu = b_lu = 0 */
        }
        const double r = fabs((double)wx[i] - (double)b[i]) / xmax;
        char msg[64];
        (void)snprintf(msg, sizeof msg, "row %d residual %.3e", i, r);
        TEST_ASSERT_TRUE_MESSAGE(r < ((is_rate != 0) ? 1e-2 : 1e-6), msg);
    }
}

static void test_failures(void)
{
    build(CDPR_SLACK_PASSIVE, 170.0);
    TEST_ASSERT_EQUAL_INT(CDPR_E_INVALID_ARG, cdpr_robot_w_init(NULL, &robot));
    TEST_ASSERT_EQUAL_INT(CDPR_E_SINGULAR, cdpr_robot_w_solve(&wm, b, x)); /* not factored */
    TEST_ASSERT_EQUAL_INT(CDPR_E_SINGULAR, cdpr_robot_w_factor(&wm, 0.0, y, NAN_R));
    TEST_ASSERT_EQUAL_INT(CDPR_E_SINGULAR, cdpr_robot_w_factor(&wm, 0.0, y, CDPR_R(-1.0)));
    y[robot.offset[0] + 4] = NAN_R;
    TEST_ASSERT_EQUAL_INT(CDPR_E_SINGULAR, cdpr_robot_w_factor(&wm, 0.0, y, CDPR_R(1e-3)));
    TEST_ASSERT_EQUAL_INT(CDPR_E_SINGULAR, cdpr_robot_w_solve(&wm, b, x));
    TEST_ASSERT_EQUAL_INT(CDPR_E_INVALID_ARG, cdpr_robot_w_factor(NULL, 0.0, y, CDPR_R(1e-3)));
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_solve_inverts_w_passive);
    RUN_TEST(test_solve_inverts_w_moordyn);
    RUN_TEST(test_solve_inverts_w_with_axial_damping);
    RUN_TEST(test_solve_inverts_w_dynamic_cabin);
    RUN_TEST(test_failures);
    return UNITY_END() ? 1 : 0;
}
