/* SPDX-License-Identifier: BSD-3-Clause */
/// @file test_determinism.c
/// The six-cable robot (docs/robots.md set A geometry) stepped through the real-time call:
/// no heap allocation during init and stepping, and two identical runs bit-identical.
#include <math.h>
#include <string.h>

#include "alloc_count.h"
#include "cdpr/robot.h"
#include "cdpr/rkf45.h"
#include "test_real.h"
#include "unity.h"

void setUp(void) {}
void tearDown(void) {}

typedef struct {
    cdpr_robot_t robot;
    cdpr_rkf45_t solver;
    cdpr_real_t y[CDPR_ROBOT_STATE_MAX];
    cdpr_real_t atol[CDPR_ROBOT_STATE_MAX];
    cdpr_real_t work[CDPR_RKF45_WORK_PER_DIM * CDPR_ROBOT_STATE_MAX];
    cdpr_real_t t;
} sim_t;

static sim_t run_a;
static sim_t run_b;

/* 50 m model: exit points on a 25 m circle at 30 m, twisted attachment pairs (25/35 deg ...). */
static void init_sim(sim_t *s)
{
    static const double az_deg[6] = {25.0, 35.0, 145.0, 155.0, 265.0, 275.0};
    const double pi = 3.14159265358979323846;
    cdpr_robot_params_t p;
    cdpr_robot_params_default(&p);
    p.n_cables = 6;
    const cdpr_vec3_t cabin = cdpr_v3(0.0, 0.0, 9.135);
    for (int j = 0; j < 6; ++j) {
        const double th = (double)j * pi / 3.0;
        const double az = az_deg[j] * pi / 180.0;
        cdpr_robot_cable_params_t *c = &p.cables[j];
        c->exit_point_m = cdpr_v3(25.0 * cos(th), 25.0 * sin(th), 30.0);
        c->attach_body_m = cdpr_v3(2.0 * cos(az), 2.0 * sin(az), -0.5);
        const cdpr_vec3_t a = cdpr_v3_add(cabin, c->attach_body_m);
        c->length_m = 0.999 * cdpr_v3_norm(cdpr_v3_sub(c->exit_point_m, a)); /* taut */
        c->n_segments = 16;
    }
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_robot_init(&s->robot, &p, NULL));
    s->robot.in.wind_m_per_s = cdpr_v3(4.0, 1.0, 0.0);
    for (int j = 0; j < 6; ++j) {
        s->robot.in.payout_m_per_s[j] = 0.01 * (double)(j - 3);
    }
    cdpr_cabin_motion_t m;
    memset(&m, 0, sizeof m);
    m.p_m = cabin;
    m.q.w = 1.0;
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_robot_place_straight(&s->robot, &m, s->y));
    cdpr_robot_fill_atol(&s->robot, 1e-6, 1e-5, 1e-8, 1e-6, s->atol);
    cdpr_rkf45_params_t sp;
    cdpr_rkf45_params_default(&sp);
    sp.step.rtol = 1e-6;
    sp.step.atol_vec = s->atol;
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_rkf45_init(&s->solver, &sp, s->work,
                                                   (int)(sizeof s->work / sizeof s->work[0]),
                                                   CDPR_ROBOT_STATE_MAX, s->robot.dim, NULL));
    s->t = 0.0;
}

/* 200 control periods of 1 ms, at most 40 trials each (the real-time call). */
static void step_sim(sim_t *s)
{
    for (int k = 0; k < 200; ++k) {
        const cdpr_status_t st =
            cdpr_rkf45_advance(&s->solver, cdpr_robot_rhs, &s->robot, &s->t, s->y, 1e-3, 40);
        TEST_ASSERT_TRUE(st >= 0);
        cdpr_robot_normalize(&s->robot, s->y);
    }
}

static void test_init_and_stepping_make_no_heap_allocation(void)
{
    if (!cdpr_alloc_counting_available()) {
        TEST_IGNORE_MESSAGE(cdpr_alloc_unavailable_reason());
    }
    cdpr_alloc_reset();
    init_sim(&run_a);
    step_sim(&run_a);
    TEST_ASSERT_EQUAL_UINT32(0u, (unsigned)cdpr_alloc_count());
    TEST_ASSERT_TRUE(run_a.solver.stats.steps_accepted >= 200u);
}

static void test_two_identical_runs_are_bit_identical(void)
{
    init_sim(&run_a);
    step_sim(&run_a);
    init_sim(&run_b);
    step_sim(&run_b);
    const size_t bytes = sizeof(cdpr_real_t) * (size_t)run_a.robot.dim;
    TEST_ASSERT_EQUAL_INT(run_a.robot.dim, run_b.robot.dim);
    TEST_ASSERT_EQUAL_MEMORY(run_a.y, run_b.y, bytes);
    TEST_ASSERT_EQUAL_MEMORY(&run_a.t, &run_b.t, sizeof run_a.t);
    TEST_ASSERT_EQUAL_UINT32((unsigned)run_a.solver.stats.rhs_evals,
                             (unsigned)run_b.solver.stats.rhs_evals);
    /* The run did something: the cabin moved and the payout changed the lengths. */
    TEST_ASSERT_TRUE(fabs(run_a.y[CDPR_CABIN_P + 2] - 9.135) > 1e-4);
    /* d lu/dt = u exactly: cable 0 hauls in at 0.03 m/s for 0.2 s. float: the integration is
     * exact but every accepted step rounds lu (~1.3 m) once, up to u_f lu = 8e-8 each, so the
     * bound is (accepted steps) x 2 u_f lu (test_real.h). */
    const double lu0 = run_a.robot.p.cables[0].length_m / 16.0;
    const double tol_lu =
        TOL(1e-12, (double)run_a.solver.stats.steps_accepted * 2.0 * U_REAL * lu0);
    TEST_ASSERT_DOUBLE_WITHIN(tol_lu, lu0 - 0.03 * 0.2, run_a.y[run_a.robot.offset[0]]);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_init_and_stepping_make_no_heap_allocation);
    RUN_TEST(test_two_identical_runs_are_bit_identical);
    return UNITY_END() ? 1 : 0;
}
