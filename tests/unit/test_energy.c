/* SPDX-License-Identifier: BSD-3-Clause */
/// @file test_energy.c
/// Conservation laws: with no damping and no drag the lumped-mass model is conservative, so
/// kinetic + gravitational + elastic energy (computed here independently of the core's RHS)
/// stays constant; with damping or drag on it never increases.
///
/// Float build: rtol 1e-9 is far below what float can honour (u_f = 6e-8 per step on states of
/// tens of metres), so the float runs ask for RTOL_TIGHT = 1e-6 and RTOL_MODERATE = 1e-5. The
/// drift then follows the integrator's local error, as in double: measured 6.3e-5 (swinging
/// cable) and 5.5e-5 (cabin) of the energy scale on the host float build.
#include <math.h>
#include <string.h>

#include "cdpr/robot.h"
#include "cdpr/rkf45.h"
#include "test_real.h"
#include "unity.h"

void setUp(void) {}
void tearDown(void) {}

static cdpr_robot_t robot;
static cdpr_real_t y[CDPR_ROBOT_STATE_MAX];
static cdpr_real_t atol_v[CDPR_ROBOT_STATE_MAX];
static cdpr_real_t work[CDPR_RKF45_WORK_PER_DIM * CDPR_ROBOT_STATE_MAX];

/* Position of node i of cable j (0 = cabin attachment, n = exit point). */
static void node_pos(int j, int i, const cdpr_real_t *s, double r[3])
{
    const cdpr_cable_t *c = &robot.cable[j];
    const int n = c->n;
    if (i == n) {
        r[0] = robot.p.cables[j].exit_point_m.x;
        r[1] = robot.p.cables[j].exit_point_m.y;
        r[2] = robot.p.cables[j].exit_point_m.z;
        return;
    }
    if (i == 0) {
        cdpr_cabin_motion_t m;
        cdpr_cabin_get_motion(s, &m);
        cdpr_vec3_t a;
        cdpr_vec3_t v;
        cdpr_robot_attachment(&robot, j, &m, &a, &v);
        r[0] = a.x;
        r[1] = a.y;
        r[2] = a.z;
        return;
    }
    const cdpr_real_t *p = s + robot.offset[j] + 1 + 3 * (i - 1);
    r[0] = p[0];
    r[1] = p[1];
    r[2] = p[2];
}

/* Total mechanical energy, written from the physics (docs/model.md §2, §3), not from the RHS:
 * free nodes: 1/2 m v^2 + m g z; segments: 1/2 EA lu eps^2 when eps > 0 (the slack law
 * T = EA eps for eps > 0 has this potential); cabin (with node-0 masses, dynamic mode):
 * 1/2 M |v_c|^2 + 1/2 w.I w + M g z_c. */
static double energy_part(const cdpr_real_t *s, int kinetic_only)
{
    const double g = robot.p.g_m_per_s2;
    double e = 0.0;
    for (int j = 0; j < robot.p.n_cables; ++j) {
        const cdpr_cable_t *c = &robot.cable[j];
        const int n = c->n;
        const double rho = c->p.rho_kg_per_m;
        const double ea = c->p.ea_N;
        const cdpr_real_t *vel = s + robot.offset[j] + 1 + 3 * (n - 1);
        for (int k = 0; k < n; ++k) {
            const double lu = (k == n - 1) ? s[robot.offset[j]] : c->lu_m[k];
            double a[3];
            double b[3];
            node_pos(j, k, s, a);
            node_pos(j, k + 1, s, b);
            const double l = sqrt((b[0] - a[0]) * (b[0] - a[0]) + (b[1] - a[1]) * (b[1] - a[1]) +
                                  (b[2] - a[2]) * (b[2] - a[2]));
            const double eps = l / lu - 1.0;
            if (eps > 0.0 && kinetic_only == 0) {
                e += 0.5 * ea * lu * eps * eps;
            }
            if (k >= 1) {
                const double lprev = c->lu_m[k - 1];
                const double m = 0.5 * rho * (lprev + lu);
                const cdpr_real_t *v = vel + 3 * (k - 1);
                e += 0.5 * m * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
                e += (kinetic_only == 0) ? m * g * a[2] : 0.0;
            }
        }
    }
    if (robot.p.mode == CDPR_CABIN_DYNAMIC) {
        cdpr_cabin_motion_t m;
        cdpr_cabin_get_motion(s, &m);
        cdpr_mat3_t R;
        cdpr_quat_to_mat3(cdpr_quat_normalize(m.q), &R);
        const cdpr_vec3_t rc = cdpr_m3_mul_v3(&R, robot.cabin.com_body_m);
        const cdpr_vec3_t ww = cdpr_m3_mul_v3(&R, m.w_rad_per_s);
        const cdpr_vec3_t vc = cdpr_v3_add(m.v_m_per_s, cdpr_v3_cross(ww, rc));
        const cdpr_vec3_t Iw = cdpr_m3_mul_v3(&robot.cabin.inertia_kg_m2, m.w_rad_per_s);
        const double M = robot.cabin.mass_kg;
        e += 0.5 * M * cdpr_v3_dot(vc, vc) + 0.5 * cdpr_v3_dot(m.w_rad_per_s, Iw);
        e += (kinetic_only == 0) ? M * g * (m.p_m.z + rc.z) : 0.0;
    }
    return e;
}

static double energy(const cdpr_real_t *s)
{
    return energy_part(s, 0);
}

static double kinetic(const cdpr_real_t *s)
{
    return energy_part(s, 1);
}

/* Integrate to t_end recording the largest |E - E0|, the largest rise of E between two
 * accepted steps, and the largest kinetic energy (the scale of the energy exchange). */
static void run(double t_end, double rtol, double *drift, double *rise, double *scale)
{
    const int dim = robot.dim;
    cdpr_robot_fill_atol(&robot, rtol, rtol, rtol, rtol, atol_v);
    cdpr_rkf45_params_t sp;
    cdpr_rkf45_params_default(&sp);
    sp.step.rtol = rtol;
    sp.step.atol_vec = atol_v;
    cdpr_rkf45_t s;
    TEST_ASSERT_EQUAL_INT(CDPR_OK,
                          cdpr_rkf45_init(&s, &sp, work, (int)(sizeof work / sizeof work[0]),
                                          CDPR_ROBOT_STATE_MAX, dim, NULL));
    const double e0 = energy(y);
    double eprev = e0;
    double kmax = kinetic(y);
    *drift = 0.0;
    *rise = 0.0;
    cdpr_real_t t = 0.0;
    while (t < t_end) {
        TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_rkf45_step(&s, cdpr_robot_rhs, &robot, &t, y, t_end));
        cdpr_robot_normalize(&robot, y);
        const double e = energy(y);
        *drift = fmax(*drift, fabs(e - e0));
        *rise = fmax(*rise, e - eprev);
        kmax = fmax(kmax, kinetic(y));
        eprev = e;
    }
    *scale = kmax;
}

/* Integrator tolerances (float: see the file comment). */
#define RTOL_TIGHT    TOL(1e-9, 1e-6)
#define RTOL_MODERATE TOL(1e-7, 1e-5)
/* Energy drift bound, relative to the scale: 6x the measured drift (double 1.7e-7, float
 * 6.3e-5), still >= 1000x tighter than a wrong force term (damping alone removes > 50 %). */
#define DRIFT_REL TOL(1e-6, 4e-4)

static void build_single(double cd, double damping)
{
    cdpr_robot_params_t p;
    cdpr_robot_params_default(&p);
    p.mode = CDPR_CABIN_PRESCRIBED; /* end A held at the origin */
    p.cables[0].cable.ea_N = 1.0e4;
    p.cables[0].cable.damping_Ns = damping;
    p.cables[0].cable.cd = cd;
    p.cables[0].exit_point_m = cdpr_v3(40.0, 0.0, 5.0);
    p.cables[0].n_segments = 12;
    p.cables[0].length_m = 50.0;
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_robot_init(&robot, &p, NULL));
    cdpr_cabin_motion_t m;
    memset(&m, 0, sizeof m);
    m.q.w = 1.0;
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_robot_place_straight(&robot, &m, y));
    /* A sideways kick so the swing is three-dimensional. */
    const int nf = robot.cable[0].n - 1;
    y[robot.offset[0] + 1 + 3 * nf + 3 * (nf / 2) + 1] = 2.0;
}

static void test_swinging_cable_conserves_energy(void)
{
    build_single(0.0, 0.0);
    double drift;
    double rise;
    double scale;
    run(10.0, RTOL_TIGHT, &drift, &rise, &scale);
    /* The fall converts ~500 J of potential energy into motion (scale = peak kinetic energy).
     * RKF45 at rtol 1e-9 is not symplectic; its energy drift is the accumulated local error:
     * measured 1.7e-7 of the scale here (7.7e-8 for the cabin case below). The bound 1e-6
     * leaves a 6x margin and is 1e5x tighter than the energy a missing, mis-signed or
     * mis-massed force term produces over 10 s (damping alone removes > 50 %). */
    TEST_ASSERT_TRUE(scale > 100.0);
    TEST_ASSERT_DOUBLE_WITHIN(DRIFT_REL * scale, 0.0, drift);
}

static void test_energy_never_rises_with_damping_or_drag(void)
{
    double drift;
    double rise;
    double scale;
    /* With damping the tension jumps when a slack segment turns taut with a stretching rate
     * (T = c eps_dot at eps = 0+): a discontinuous RHS, so a moderate tolerance. */
    build_single(0.0, 170.0); /* strain-rate damping only */
    run(5.0, RTOL_MODERATE, &drift, &rise, &scale);
    TEST_ASSERT_TRUE(drift > 1e-3 * scale); /* damping does remove energy */
    TEST_ASSERT_TRUE(rise < 1e-5 * scale);  /* ... and never adds any (to integration error) */
    build_single(1.2, 0.0);                 /* aerodynamic drag only, still air */
    run(5.0, RTOL_TIGHT, &drift, &rise, &scale);
    TEST_ASSERT_TRUE(drift > 1e-4 * scale);
    /* float: the energy evaluated from float states is itself uncertain by ~u_f times the
     * potential energy (of the order of the scale), hence 1e-5 there. */
    TEST_ASSERT_TRUE(rise < TOL(1e-7, 1e-5) * scale);
}

/* Three cables holding a cabin with an offset centre of mass, released from slightly slack
 * straight cables: the cabin-cable coupling (forces, torques, node-0 masses) must be
 * consistent for the total energy to be conserved. */
static void test_cabin_on_three_cables_conserves_energy(void)
{
    cdpr_robot_params_t p;
    cdpr_robot_params_default(&p);
    p.mode = CDPR_CABIN_DYNAMIC;
    p.n_cables = 3;
    p.cabin.com_body_m = cdpr_v3(0.1, -0.05, -0.3);
    p.cabin.inertia_com_kg_m2.m[0][1] = 2.0;
    p.cabin.inertia_com_kg_m2.m[1][0] = 2.0;
    for (int j = 0; j < 3; ++j) {
        const double th = 2.0 * 3.14159265358979323846 * j / 3.0;
        cdpr_robot_cable_params_t *c = &p.cables[j];
        c->cable.ea_N = 2.0e4;
        c->cable.damping_Ns = 0.0;
        c->cable.cd = 0.0;
        c->exit_point_m = cdpr_v3(10.0 * cos(th), 10.0 * sin(th), 10.0);
        c->attach_body_m = cdpr_v3(1.0 * cos(th + 0.3), 1.0 * sin(th + 0.3), 0.2);
        c->n_segments = 6;
        c->length_m = 13.0;
    }
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_robot_init(&robot, &p, NULL));
    cdpr_cabin_motion_t m;
    memset(&m, 0, sizeof m);
    m.q = cdpr_quat_from_euler(0.05, -0.03, 0.2);
    m.p_m = cdpr_v3(0.3, 0.2, 0.0);
    m.w_rad_per_s = cdpr_v3(0.1, 0.0, 0.2);
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_robot_place_straight(&robot, &m, y));
    double drift;
    double rise;
    double scale;
    run(10.0, RTOL_TIGHT, &drift, &rise, &scale);
    TEST_ASSERT_TRUE(scale > 100.0);
    TEST_ASSERT_DOUBLE_WITHIN(DRIFT_REL * scale, 0.0, drift);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_swinging_cable_conserves_energy);
    RUN_TEST(test_energy_never_rises_with_damping_or_drag);
    RUN_TEST(test_cabin_on_three_cables_conserves_energy);
    return UNITY_END() ? 1 : 0;
}
