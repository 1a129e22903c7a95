/* SPDX-License-Identifier: BSD-3-Clause */
/// @file test_presets.c
/// Robot presets against the facts docs/robots.md derived independently (its own statics):
/// set A along the paper's circle and line (lengths, tensions, length rates), set B at the
/// zenith and at 40° zenith angle (tensions, payout range), and the builder's validation.
#include <math.h>
#include <string.h>

#include "cdpr/host/presets.h"
#include "cdpr/statics.h"
#include "cdpr/control/trajectory.h"
#include "test_real.h"
#include "paper_circle.h"
#include "unity.h"

void setUp(void) {}
void tearDown(void) {}

static const double PI = 3.14159265358979323846;
static cdpr_robot_t robot;

static void init_preset(cdpr_preset_t preset)
{
    cdpr_preset_config_t c;
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_preset_get(preset, &c));
    cdpr_robot_params_t p;
    cdpr_winch_params_t w;
    cdpr_diag_t d;
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_preset_build(&c, NULL, &p, &w, &d));
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_robot_init(&robot, &p, &d));
}

static void ik_at(const double pose[6], cdpr_statics_result_t *res)
{
    cdpr_statics_opts_t o;
    cdpr_statics_opts_default(&o);
    const cdpr_cabin_motion_t m = cdpr_cabin_motion_at_pose(pose);
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_statics_ik(&robot, &m, &o, res));
}

static void test_set_a_geometry(void)
{
    init_preset(CDPR_PRESET_PAPER_50M);
    for (int j = 0; j < 6; ++j) {
        /* A_j = (25 cos θ_j, 25 sin θ_j, 30), θ_j = 60° (j-1); |b_j| = 2 m at z = -0.5 m. */
        const double th = PI / 3.0 * j;
        const cdpr_vec3_t a = robot.p.cables[j].exit_point_m;
        TEST_ASSERT_DOUBLE_WITHIN(1e-12, 25.0 * cos(th), a.x);
        TEST_ASSERT_DOUBLE_WITHIN(1e-12, 25.0 * sin(th), a.y);
        TEST_ASSERT_EQUAL_DOUBLE(30.0, a.z);
        const cdpr_vec3_t b = robot.p.cables[j].attach_body_m;
        TEST_ASSERT_DOUBLE_WITHIN(1e-12, 2.0, sqrt(b.x * b.x + b.y * b.y));
        TEST_ASSERT_EQUAL_DOUBLE(-0.5, b.z);
        TEST_ASSERT_EQUAL_INT(20, robot.p.cables[j].n_segments);
    }
    TEST_ASSERT_EQUAL_DOUBLE(40.0, robot.p.cabin.mass_kg);
}

static void test_set_a_along_the_circle_matches_parameters_md(void)
{
    init_preset(CDPR_PRESET_PAPER_50M);
    const cdpr_traj_t tr = test_paper_circle();
    const double lap = 2.0 * PI * 2.0 / 2.0;
    double l0[6];
    double tmin = 1e9;
    double tmax = 0.0;
    double lrel_min = 1.0;
    double lrel_max = 1.0;
    double rate_max = 0.0;
    double l_prev[6];
    const int n = 360;
    for (int k = 0; k <= n; ++k) {
        cdpr_traj_sample_t s;
        cdpr_traj_eval(&tr, lap * k / n, &s);
        cdpr_statics_result_t res;
        ik_at(s.pose, &res);
        for (int j = 0; j < 6; ++j) {
            const double L = res.cable[j].length_m;
            if (k == 0) {
                l0[j] = L;
            } else {
                rate_max = fmax(rate_max, fabs(L - l_prev[j]) / (lap / n));
            }
            l_prev[j] = L;
            tmin = fmin(tmin, res.cable[j].tension_cabin_N);
            tmax = fmax(tmax, res.cable[j].tension_cabin_N);
            lrel_min = fmin(lrel_min, L / l0[j]);
            lrel_max = fmax(lrel_max, L / l0[j]);
        }
    }
    /* docs/robots.md [D]: L0 ~ 31.6 m at the start; cabin-end tensions ~29-208 N; lengths
     * -8 %/+11 %; up to 2.7 m/s of length rate. Its figures are rounded to the digits given,
     * so the tolerances are half a unit of the last digit plus the 1° sampling here (a chord
     * of the 1 Hz-ish tension curve, < 1 %). */
    for (int j = 0; j < 6; ++j) {
        TEST_ASSERT_DOUBLE_WITHIN(0.05, 31.6, l0[j]);
    }
    TEST_ASSERT_DOUBLE_WITHIN(1.0, 29.0, tmin);
    TEST_ASSERT_DOUBLE_WITHIN(2.0, 208.0, tmax);
    TEST_ASSERT_DOUBLE_WITHIN(0.006, 0.92, lrel_min);
    TEST_ASSERT_DOUBLE_WITHIN(0.006, 1.11, lrel_max);
    TEST_ASSERT_DOUBLE_WITHIN(0.06, 2.7, rate_max);
}

static void test_set_a_along_the_line_matches_parameters_md(void)
{
    init_preset(CDPR_PRESET_PAPER_50M);
    const double from[6] = {2.00, 1.00, 16.0, 0.0889, -0.1756, 3.108 - PI};
    const double to[6] = {2.50, 1.50, 16.2, 0.135, -0.263, 3.121 - PI};
    double tmin = 1e9;
    double tmax = 0.0;
    double lmin = 1e9;
    double lmax = 0.0;
    double rate_max = 0.0;
    double l_prev[6];
    const int n = 100;
    for (int k = 0; k <= n; ++k) {
        double pose[6];
        for (int i = 0; i < 6; ++i) {
            pose[i] = from[i] + (to[i] - from[i]) * k / n;
        }
        cdpr_statics_result_t res;
        ik_at(pose, &res);
        for (int j = 0; j < 6; ++j) {
            const double L = res.cable[j].length_m;
            if (k > 0) {
                rate_max = fmax(rate_max, fabs(L - l_prev[j]) / (10.0 / n));
            }
            l_prev[j] = L;
            tmin = fmin(tmin, res.cable[j].tension_cabin_N);
            tmax = fmax(tmax, res.cable[j].tension_cabin_N);
            lmin = fmin(lmin, L);
            lmax = fmax(lmax, L);
        }
    }
    /* docs/robots.md [D]: 73-214 N, 24.9-29.9 m, <= 0.08 m/s (rounded as given). */
    TEST_ASSERT_DOUBLE_WITHIN(1.0, 73.0, tmin);
    TEST_ASSERT_DOUBLE_WITHIN(1.0, 214.0, tmax);
    TEST_ASSERT_DOUBLE_WITHIN(0.05, 24.9, lmin);
    TEST_ASSERT_DOUBLE_WITHIN(0.05, 29.9, lmax);
    TEST_ASSERT_TRUE(rate_max <= 0.085);
}

static void test_set_b_full_scale(void)
{
    init_preset(CDPR_PRESET_FAST);
    TEST_ASSERT_EQUAL_DOUBLE(30000.0, robot.p.cabin.mass_kg);
    TEST_ASSERT_EQUAL_DOUBLE(0.046, robot.p.cables[0].cable.d0_m);
    /* Zenith: on the 160 m focal sphere centred at (0, 0, 300) m, z = 140 m. */
    const double zenith[6] = {0.0, 0.0, 140.0, 0.0, 0.0, 0.0};
    cdpr_statics_result_t res;
    ik_at(zenith, &res);
    for (int j = 0; j < 6; ++j) {
        TEST_ASSERT_TRUE(res.cable[j].tension_cabin_N >= 80e3);
        TEST_ASSERT_TRUE(res.cable[j].tension_winch_N <= 300e3);
        TEST_ASSERT_DOUBLE_WITHIN(1.0, 321.7, res.cable[j].length_m); /* symmetric */
    }
    /* 40° zenith angle toward tower 1, tilted (14/40) x 40° = 14° toward the sphere centre
     * (docs/robots.md orientation law; β < 0 turns the cabin axis toward -x): the extreme of
     * the workspace where docs/robots.md [D] gives payout 211-410 m and tensions 80-300 kN. */
    const double z40 = 40.0 * PI / 180.0;
    const double edge[6] = {160.0 * sin(z40),   0.0, 300.0 - 160.0 * cos(z40), 0.0,
                            -14.0 * PI / 180.0, 0.0};
    ik_at(edge, &res);
    double tmin = 1e12;
    double tmax = 0.0;
    double lmin = 1e9;
    double lmax = 0.0;
    for (int j = 0; j < 6; ++j) {
        tmin = fmin(tmin, res.cable[j].tension_cabin_N);
        tmax = fmax(tmax, res.cable[j].tension_winch_N);
        lmin = fmin(lmin, res.cable[j].length_m);
        lmax = fmax(lmax, res.cable[j].length_m);
    }
    /* Rounded to the metre in docs/robots.md: +-1 m. Tensions inside the stated range. */
    TEST_ASSERT_DOUBLE_WITHIN(1.0, 211.0, lmin);
    TEST_ASSERT_DOUBLE_WITHIN(1.0, 410.0, lmax);
    TEST_ASSERT_TRUE(tmin >= 80e3);
    TEST_ASSERT_TRUE(tmax <= 300e3);
}

static void test_builder_validates_and_reports_the_field(void)
{
    cdpr_preset_config_t c;
    TEST_ASSERT_EQUAL_INT(CDPR_E_INVALID_ARG, cdpr_preset_get((cdpr_preset_t)7, &c));
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_preset_get(CDPR_PRESET_PAPER_50M, &c));
    cdpr_robot_params_t p;
    cdpr_winch_params_t w;
    cdpr_diag_t d;
    c.cable.ea_N = NAN_R;
    TEST_ASSERT_EQUAL_INT(CDPR_E_NOT_FINITE, cdpr_preset_build(&c, NULL, &p, &w, &d));
    TEST_ASSERT_EQUAL_STRING("ea_N", d.field);
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_preset_get(CDPR_PRESET_PAPER_50M, &c));
    c.winch.u_max_m_per_s = -1.0;
    TEST_ASSERT_TRUE(cdpr_preset_build(&c, NULL, &p, &w, &d) < 0);
    TEST_ASSERT_EQUAL_STRING("u_max_m_per_s", d.field);
    TEST_ASSERT_EQUAL_STRING("paper-50m", cdpr_preset_name(CDPR_PRESET_PAPER_50M));
    TEST_ASSERT_EQUAL_STRING("fast", cdpr_preset_name(CDPR_PRESET_FAST));
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_set_a_geometry);
    RUN_TEST(test_set_a_along_the_circle_matches_parameters_md);
    RUN_TEST(test_set_a_along_the_line_matches_parameters_md);
    RUN_TEST(test_set_b_full_scale);
    RUN_TEST(test_builder_validates_and_reports_the_field);
    return UNITY_END() ? 1 : 0;
}
