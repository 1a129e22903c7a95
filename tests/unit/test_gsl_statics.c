/* SPDX-License-Identifier: BSD-3-Clause */
/// @file test_gsl_statics.c
/// The core's sag-aware IK (nested Newton, analytic Jacobian) against an independent
/// formulation solved by GSL (all 18 unknowns at once, Powell hybrid, numerical Jacobian),
/// without and with an external wrench on the cabin; and the IK's verdict "infeasible" against
/// an independent search for equilibria (GSL continuation in the pose, checked by the core's
/// forward statics): every equilibrium the search finds where the IK says infeasible has a
/// cable hanging in a loop (longer than CDPR_STATICS_MAX_LENGTH_PER_CHORD chords).
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_errno.h>
#include <gsl/gsl_multiroots.h>

#include "cdpr/catenary.h"
#include "cdpr/gsl/statics.h"
#include "cdpr/robot.h"
#include "cdpr/statics.h"
#include "unity.h"

void setUp(void) {}
void tearDown(void) {}

static cdpr_robot_t robot;

static void build(double ea, double rho, double mass)
{
    static const double az_deg[6] = {25.0, 35.0, 145.0, 155.0, 265.0, 275.0};
    const double pi = 3.14159265358979323846;
    cdpr_robot_params_t p;
    cdpr_robot_params_default(&p);
    p.n_cables = 6;
    p.cabin.mass_kg = mass;
    for (int j = 0; j < 6; ++j) {
        const double th = (double)j * pi / 3.0;
        const double az = az_deg[j] * pi / 180.0;
        p.cables[j].exit_point_m = cdpr_v3(25.0 * cos(th), 25.0 * sin(th), 30.0);
        p.cables[j].attach_body_m = cdpr_v3(2.0 * cos(az), 2.0 * sin(az), -0.5);
        p.cables[j].cable.ea_N = ea;
        p.cables[j].cable.rho_kg_per_m = rho;
        p.cables[j].n_segments = 8;
        p.cables[j].length_m = 30.0;
    }
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_robot_init(&robot, &p, NULL));
}

static void compare_at(double x, double y, double z, double a, double b, double g)
{
    cdpr_cabin_motion_t pose;
    memset(&pose, 0, sizeof pose);
    pose.p_m = cdpr_v3(x, y, z);
    pose.q = cdpr_quat_from_euler(a, b, g);
    cdpr_statics_opts_t o;
    cdpr_statics_opts_default(&o);
    cdpr_statics_result_t ours;
    cdpr_statics_result_t ref;
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_statics_ik(&robot, &pose, &o, &ours));
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_gsl_statics_ik(&robot, &pose, 500, &ref));
    for (int j = 0; j < 6; ++j) {
        /* Both solve to wrench residuals < 1e-7 N and spans < 1e-10 m; the conditioning of
         * the 6x6 system (cable geometry) amplifies that to ~1e-9 relative in H: 1e-7. */
        const double H = ref.cable[j].H_N;
        TEST_ASSERT_DOUBLE_WITHIN(1e-7 * H, H, ours.cable[j].H_N);
        TEST_ASSERT_DOUBLE_WITHIN(1e-7 * (H + fabs(ref.cable[j].v_cabin_N)), ref.cable[j].v_cabin_N,
                                  ours.cable[j].v_cabin_N);
        TEST_ASSERT_DOUBLE_WITHIN(1e-9 * ref.cable[j].length_m, ref.cable[j].length_m,
                                  ours.cable[j].length_m);
    }
}

static void test_50m_model_poses_agree_with_gsl(void)
{
    build(2.0e6, 0.14, 40.0);
    compare_at(0.0, 0.0, 9.135, 0.0, 0.0, 0.0);            /* circle start */
    compare_at(0.0, 0.001, 9.135 - 1.470, 0.0, 0.0, 0.0);  /* circle initial offset */
    compare_at(2.0, 1.0, 16.0, 0.0889, -0.1756, -0.03359); /* line start (gamma - pi) */
    compare_at(2.5, 1.5, 16.2, 0.135, -0.263, -0.02059);   /* line end */
    compare_at(-2.0, 1.0, 14.0, 0.0, 0.05, -0.1);
}

static void test_heavy_soft_cables_agree_with_gsl(void)
{
    /* Sag and stretch both large: 10x heavier, 100x softer cables, light cabin. */
    build(2.0e4, 1.4, 20.0);
    compare_at(0.0, 0.0, 9.135, 0.0, 0.0, 0.0);
    /* (GSL's hybrid solver started from the massless solution does not converge off-centre
     * with these heavy cables; the core's solver does. Poses where both converge:) */
    compare_at(2.0, 1.0, 16.0, 0.0889, -0.1756, -0.03359);
}

/* The same comparison under an external wrench (cdpr_statics_ik_wrench against
 * cdpr_gsl_statics_ik_wrench, whose start is its own massless solution of the loaded
 * problem). Both solve to the tolerances above; the loads here change the H_j by tens of per
 * cent, not the conditioning: the same bounds. */
static void compare_loaded_at(const double pose6[6], cdpr_vec3_t f, cdpr_vec3_t tau)
{
    cdpr_cabin_motion_t pose;
    memset(&pose, 0, sizeof pose);
    pose.p_m = cdpr_v3(pose6[0], pose6[1], pose6[2]);
    pose.q = cdpr_quat_from_euler(pose6[3], pose6[4], pose6[5]);
    cdpr_statics_opts_t o;
    cdpr_statics_opts_default(&o);
    cdpr_statics_result_t ours;
    cdpr_statics_result_t ref;
    cdpr_statics_result_t unloaded;
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_statics_ik_wrench(&robot, &pose, f, tau, &o, &ours));
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_gsl_statics_ik_wrench(&robot, &pose, f, tau, 500, &ref));
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_statics_ik(&robot, &pose, &o, &unloaded));
    double moved = 0.0;
    for (int j = 0; j < 6; ++j) {
        const double H = ref.cable[j].H_N;
        TEST_ASSERT_DOUBLE_WITHIN(1e-7 * H, H, ours.cable[j].H_N);
        TEST_ASSERT_DOUBLE_WITHIN(1e-7 * (H + fabs(ref.cable[j].v_cabin_N)), ref.cable[j].v_cabin_N,
                                  ours.cable[j].v_cabin_N);
        TEST_ASSERT_DOUBLE_WITHIN(1e-9 * ref.cable[j].length_m, ref.cable[j].length_m,
                                  ours.cable[j].length_m);
        moved =
            fmax(moved, fabs(ours.cable[j].H_N - unloaded.cable[j].H_N) / unloaded.cable[j].H_N);
    }
    /* The load matters: far above the agreement bound. */
    TEST_ASSERT_TRUE(moved > 1e-2);
}

static void test_external_wrench_agrees_with_gsl(void)
{
    build(2.0e6, 0.14, 40.0);
    /* The circle's start with its centripetal load m v^2 / r = 80 N toward the centre
     * (0, -2, 9.135) as the tracker feeds it (d'Alembert: f_ext = -m a points outward). */
    const double start[6] = {0.0, 0.0, 9.135, 0.0, 0.0, 0.0};
    compare_loaded_at(start, cdpr_v3(0.0, 80.0, 0.0), cdpr_v3(0.0, 0.0, 0.0));
    const double line[6] = {2.0, 1.0, 16.0, 0.0889, -0.1756, -0.03359};
    compare_loaded_at(line, cdpr_v3(-30.0, 20.0, 15.0), cdpr_v3(5.0, -3.0, 8.0));
    const double off[6] = {-2.0, 1.0, 14.0, 0.0, 0.05, -0.1};
    compare_loaded_at(off, cdpr_v3(25.0, 10.0, -40.0), cdpr_v3(-6.0, 4.0, -10.0));
    /* An offset centre of mass: both take moments about it (statics.h). */
    static const double az_deg[6] = {25.0, 35.0, 145.0, 155.0, 265.0, 275.0};
    const double pi = 3.14159265358979323846;
    cdpr_robot_params_t p;
    cdpr_robot_params_default(&p);
    p.n_cables = 6;
    p.cabin.mass_kg = 40.0;
    p.cabin.com_body_m = cdpr_v3(0.1, -0.05, 0.15);
    for (int j = 0; j < 6; ++j) {
        const double th = (double)j * pi / 3.0;
        const double az = az_deg[j] * pi / 180.0;
        p.cables[j].exit_point_m = cdpr_v3(25.0 * cos(th), 25.0 * sin(th), 30.0);
        p.cables[j].attach_body_m = cdpr_v3(2.0 * cos(az), 2.0 * sin(az), -0.5);
        p.cables[j].n_segments = 8;
        p.cables[j].length_m = 30.0;
    }
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_robot_init(&robot, &p, NULL));
    const double tilted[6] = {1.0, -0.5, 12.0, 0.03, -0.02, 0.1};
    compare_loaded_at(tilted, cdpr_v3(40.0, -20.0, -10.0), cdpr_v3(-4.0, 6.0, 2.0));
}

/* ---- Equilibria by continuation (independent of the core's IK) ---------------------------
 * Unknowns (H_j, V_j, L_j) of the six cables, the 18 equations of cdpr_gsl_statics (wrench and
 * span closures, written here again), solved by GSL's hybrid method along the straight path
 * of poses pose(s) = centre + s (target - centre), each solve started from the previous root;
 * the step grows by 1.5 after a solve and halves after a failure (down to 1e-7). */
static double cont_target[6];
static double cont_s;

static cdpr_cabin_motion_t cont_pose(double s)
{
    cdpr_cabin_motion_t m;
    memset(&m, 0, sizeof m);
    m.p_m = cdpr_v3(s * cont_target[0], s * cont_target[1], 13.0 + s * (cont_target[2] - 13.0));
    m.q = cdpr_quat_from_euler(s * cont_target[3], s * cont_target[4], s * cont_target[5]);
    return m;
}

/* Chord of cable j at a pose [m]. */
static double chord_at(const cdpr_cabin_motion_t *m, int j, cdpr_vec3_t *P, cdpr_vec3_t *arm)
{
    cdpr_mat3_t R;
    cdpr_quat_to_mat3(m->q, &R);
    const cdpr_vec3_t b = robot.p.cables[j].attach_body_m;
    *P = cdpr_v3_add(m->p_m, cdpr_m3_mul_v3(&R, b));
    *arm = cdpr_m3_mul_v3(&R, cdpr_v3_sub(b, robot.p.cabin.com_body_m));
    return cdpr_v3_norm(cdpr_v3_sub(robot.p.cables[j].exit_point_m, *P));
}

static int cont_equations(const gsl_vector *x, void *params, gsl_vector *f)
{
    (void)params;
    const cdpr_cabin_motion_t m = cont_pose(cont_s);
    const double weight = robot.p.cabin.mass_kg * robot.p.g_m_per_s2;
    cdpr_vec3_t force = cdpr_v3(0.0, 0.0, -weight);
    cdpr_vec3_t moment = cdpr_v3(0.0, 0.0, 0.0);
    for (int j = 0; j < 6; ++j) {
        const double H = gsl_vector_get(x, 3u * (size_t)j);
        const double V = gsl_vector_get(x, 3u * (size_t)j + 1u);
        const double L = gsl_vector_get(x, 3u * (size_t)j + 2u);
        if (!(H > 0.0) || !(L > 0.0)) {
            return GSL_EDOM;
        }
        cdpr_vec3_t P;
        cdpr_vec3_t arm;
        (void)chord_at(&m, j, &P, &arm);
        const cdpr_vec3_t d = cdpr_v3_sub(robot.p.cables[j].exit_point_m, P);
        const double l = sqrt(d.x * d.x + d.y * d.y);
        const cdpr_vec3_t F = cdpr_v3(H * d.x / l, H * d.y / l, V);
        force = cdpr_v3_add(force, F);
        moment = cdpr_v3_add(moment, cdpr_v3_cross(arm, F));
        const cdpr_catenary_cable_t c = {robot.p.cables[j].cable.rho_kg_per_m * robot.p.g_m_per_s2,
                                         robot.p.cables[j].cable.ea_N};
        double ls = 0.0;
        double hs = 0.0;
        if (cdpr_catenary_spans(&c, H, V, L, &ls, &hs) != CDPR_OK) {
            return GSL_EDOM;
        }
        gsl_vector_set(f, 6u + 2u * (size_t)j, (ls - l) / 30.0);
        gsl_vector_set(f, 7u + 2u * (size_t)j, (hs - d.z) / 30.0);
    }
    const double r[6] = {force.x, force.y, force.z, moment.x, moment.y, moment.z};
    for (size_t i = 0; i < 6; ++i) {
        gsl_vector_set(f, i, r[i] / weight);
    }
    return GSL_SUCCESS;
}

/* March from s = 0 (the core's IK at the centre, a checked equilibrium) to s = 1. Returns 1
 * with x at the target's root if the march arrives, else 0. */
static int cont_march(gsl_vector *x)
{
    gsl_multiroot_function fn = {cont_equations, 18, NULL};
    gsl_multiroot_fsolver *sv = gsl_multiroot_fsolver_alloc(gsl_multiroot_fsolver_hybrids, 18);
    TEST_ASSERT_NOT_NULL(sv);
    double s = 0.0;
    double ds = 0.05;
    while (s < 1.0 && ds > 1e-7) {
        cont_s = (s + ds > 1.0) ? 1.0 : s + ds;
        int conv = 0;
        if (gsl_multiroot_fsolver_set(sv, &fn, x) == GSL_SUCCESS) {
            for (int it = 0; it < 200 && conv == 0; ++it) {
                const int rc = gsl_multiroot_fsolver_iterate(sv);
                conv = (gsl_multiroot_test_residual(sv->f, 1e-13) == GSL_SUCCESS) ? 1 : 0;
                if (rc != GSL_SUCCESS && conv == 0) {
                    break;
                }
            }
        }
        if (conv != 0) {
            gsl_vector_memcpy(x, sv->x);
            s = cont_s;
            ds *= 1.5;
        } else {
            ds *= 0.5;
        }
    }
    gsl_multiroot_fsolver_free(sv);
    return (s >= 1.0) ? 1 : 0;
}

static void test_a_loop_is_reported_with_its_cable(void)
{
    /* At (3, -2, 12) m tilted (0.05, -0.05, 0.2) rad the catenaries balance the weight only with
     * a cable hanging in a loop. GSL finds that equilibrium; the core's forward statics accepts
     * its lengths (the model has it); the IK reports the pose as infeasible and names the first
     * cable GSL finds over 1.5 chords, with its length per chord. */
    build(2.0e6, 0.14, 40.0);
    const cdpr_cabin_motion_t m = {cdpr_v3(3.0, -2.0, 12.0), cdpr_quat_from_euler(0.05, -0.05, 0.2),
                                   cdpr_v3(0.0, 0.0, 0.0), cdpr_v3(0.0, 0.0, 0.0)};
    cdpr_statics_opts_t o;
    cdpr_statics_opts_default(&o);
    cdpr_statics_result_t ref;
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_gsl_statics_ik(&robot, &m, 500, &ref));
    int first = -1;
    double ratio = 0.0;
    double L[6];
    for (int j = 0; j < 6; ++j) {
        cdpr_vec3_t P;
        cdpr_vec3_t arm;
        const double q = ref.cable[j].length_m / chord_at(&m, j, &P, &arm);
        L[j] = ref.cable[j].length_m;
        if (q > 1.5 && first < 0) {
            first = j;
            ratio = q;
        }
    }
    TEST_ASSERT_TRUE(ratio > 2.0); /* 85 m on a 30 m chord */
    cdpr_statics_result_t fw;
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_statics_forward(&robot, L, &m, &o, &fw));
    TEST_ASSERT_TRUE(cdpr_v3_norm(cdpr_v3_sub(fw.pose.p_m, m.p_m)) < 1e-6);
    cdpr_statics_result_t res;
    cdpr_statics_verdict_t why;
    const cdpr_vec3_t zero = cdpr_v3(0.0, 0.0, 0.0);
    TEST_ASSERT_EQUAL_INT(CDPR_E_INFEASIBLE,
                          cdpr_statics_ik_dist(&robot, &m, zero, zero, NULL, &o, &res, &why));
    TEST_ASSERT_EQUAL_INT(CDPR_STATICS_WHY_LOOP, why.why);
    TEST_ASSERT_EQUAL_INT(first, why.cable);
    TEST_ASSERT_DOUBLE_WITHIN(1e-6 * ratio, ratio, why.value);
}

static void test_infeasible_verdicts_agree_with_forward_statics(void)
{
    /* 200 random poses of the 50 m model's workspace (x, y within 6 m, z 6-20 m, angles within
     * 0.15 rad; statics.h). Where the IK solves, the forward statics at its lengths returns the
     * pose and no cable is a loop. Where it says infeasible, the continuation either stops
     * before the pose (a fold: the equilibria end there) or arrives at an equilibrium, which the
     * forward statics confirms and which has a loop. Before the loop limit moved into the IK,
     * 3 of these poses (140, 164, 181 of this seed) were called infeasible while the
     * continuation arrived at equilibria (8.1, 11.6 and 2.7 chords). Counts of this seed:
     * 75 solved (the same 75 before), 54 folds, 71 loops; before, the IK returned 69 of those
     * loops as solutions (up to 11.6 chords) and called the other two infeasible. */
    build(2.0e6, 0.14, 40.0);
    gsl_set_error_handler_off();
    cdpr_statics_opts_t o;
    cdpr_statics_opts_default(&o);
    srand(7);
    int solved = 0;
    int fold = 0;
    int loop = 0;
    for (int k = 0; k < 200; ++k) {
        cont_target[0] = 12.0 * ((double)rand() / RAND_MAX - 0.5);
        cont_target[1] = 12.0 * ((double)rand() / RAND_MAX - 0.5);
        cont_target[2] = 6.0 + 14.0 * ((double)rand() / RAND_MAX);
        for (int i = 3; i < 6; ++i) {
            cont_target[i] = 0.3 * ((double)rand() / RAND_MAX - 0.5);
        }
        const cdpr_cabin_motion_t m = cont_pose(1.0);
        cdpr_statics_result_t res;
        const cdpr_status_t st = cdpr_statics_ik(&robot, &m, &o, &res);
        TEST_ASSERT_TRUE(st == CDPR_OK || st == CDPR_E_INFEASIBLE);
        if (st == CDPR_OK) {
            double L[6];
            for (int j = 0; j < 6; ++j) {
                cdpr_vec3_t P;
                cdpr_vec3_t arm;
                L[j] = res.cable[j].length_m;
                TEST_ASSERT_TRUE(L[j] <= 1.5 * chord_at(&m, j, &P, &arm));
            }
            cdpr_cabin_motion_t guess = m;
            guess.p_m = cdpr_v3(m.p_m.x + 0.01, m.p_m.y, m.p_m.z - 0.02);
            cdpr_statics_result_t fw;
            TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_statics_forward(&robot, L, &guess, &o, &fw));
            TEST_ASSERT_TRUE(cdpr_v3_norm(cdpr_v3_sub(fw.pose.p_m, m.p_m)) < 1e-8);
            ++solved;
            continue;
        }
        /* Infeasible: search from the centre's equilibrium. */
        const cdpr_cabin_motion_t c0 = cont_pose(0.0);
        cdpr_statics_result_t r0;
        TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_statics_ik(&robot, &c0, &o, &r0));
        gsl_vector *x = gsl_vector_alloc(18);
        for (int j = 0; j < 6; ++j) {
            gsl_vector_set(x, 3u * (size_t)j, r0.cable[j].H_N);
            gsl_vector_set(x, 3u * (size_t)j + 1u, r0.cable[j].v_cabin_N);
            gsl_vector_set(x, 3u * (size_t)j + 2u, r0.cable[j].length_m);
        }
        if (cont_march(x) == 0) {
            ++fold;
        } else {
            double L[6];
            double worst = 0.0;
            for (int j = 0; j < 6; ++j) {
                cdpr_vec3_t P;
                cdpr_vec3_t arm;
                L[j] = gsl_vector_get(x, 3u * (size_t)j + 2u);
                worst = fmax(worst, L[j] / chord_at(&m, j, &P, &arm));
            }
            cdpr_statics_result_t fw;
            TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_statics_forward(&robot, L, &m, &o, &fw));
            TEST_ASSERT_TRUE(worst > 1.5); /* the verdict: an equilibrium, but with a loop */
            ++loop;
        }
        gsl_vector_free(x);
    }
    /* The sample has all three kinds. */
    TEST_ASSERT_TRUE(solved >= 70);
    TEST_ASSERT_TRUE(fold >= 40);
    TEST_ASSERT_TRUE(loop >= 60);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_50m_model_poses_agree_with_gsl);
    RUN_TEST(test_heavy_soft_cables_agree_with_gsl);
    RUN_TEST(test_external_wrench_agrees_with_gsl);
    RUN_TEST(test_a_loop_is_reported_with_its_cable);
    RUN_TEST(test_infeasible_verdicts_agree_with_forward_statics);
    return UNITY_END() ? 1 : 0;
}
