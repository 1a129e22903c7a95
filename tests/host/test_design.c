/* SPDX-License-Identifier: BSD-3-Clause */
/// @file test_design.c
/// The design analysis (cdpr/design/design.h) on a model with closed forms: six winch lengths
/// that integrate their payout rates (A = 0, B = I) under the length loop u = -k_L x. Then
/// exp([[0, I], [0, 0]] T) = [[I, T I], [0, I]]; the closed loop's eigenvalues are 1 - k_L T
/// (and 0); each channel is the sampled integrator l(z) = k_L T / (z - 1), decoupled, with
/// phase margin 90° - asin(k_L T / 2), no -180° crossing below Nyquist and α -> 1 - k_L T / 2
/// at Nyquist; k_L T > 2 grows at Nyquist at ln(k_L T - 1) / T; the learning's lap-to-lap map
/// is M = Q (1 - γ e^{jωλ} (1 - a) / (z - a)), a = 1 - k_L T (tests/host/test_learning.c's
/// closed form). The same length loops on CDPR_DESIGN_NU_MAX winches (eight in the default build):
/// every channel has the closed-form margins. And the failures: NaN in a matrix, an empty or
/// mis-sized model, no feedback -> no check.
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cdpr/design/design.h"
#include "unity.h"

/* Last: its macro I would clash with the headers' parameter names. */
#include <complex.h>
#undef I

void setUp(void) {}
void tearDown(void) {}

#define N   6
#define NX  CDPR_DESIGN_NU_MAX /* the most winches (and states) of a model here */
#define NZX CDPR_DESIGN_NZ_MAX
static double g_A[NX * NX], g_B[NX * NX], g_Kx[NX * NX], g_Kz[NX * NZX], g_Zx[NZX * NX];
static double g_Zz[NZX * NZX], g_Ku[NX * NX], g_Zu[NZX * NX], g_Cm[CDPR_DESIGN_NM_MAX * NX];
static cdpr_design_report_t g_r;

/* nu winch lengths (nu states), each integrating its payout rate under u = -k_L x. */
static void integrators_n(cdpr_design_model_t *m, double kl, double T, int nu)
{
    memset(m, 0, sizeof *m);
    memset(g_A, 0, sizeof g_A);
    memset(g_B, 0, sizeof g_B);
    memset(g_Kx, 0, sizeof g_Kx);
    memset(g_Kz, 0, sizeof g_Kz);
    memset(g_Zx, 0, sizeof g_Zx);
    memset(g_Zz, 0, sizeof g_Zz);
    memset(g_Ku, 0, sizeof g_Ku);
    memset(g_Zu, 0, sizeof g_Zu);
    memset(g_Cm, 0, sizeof g_Cm);
    for (int i = 0; i < nu; ++i) {
        g_B[i * nu + i] = 1.0;
        g_Kx[i * nu + i] = -kl;
        if (i < 6) {
            g_Cm[i * nu + i] = -1.0; /* the pose rows: e_L = J (δp, δθ) = -x (six winches) */
            m->J[i * 6 + i] = 1.0;
        }
        g_Cm[(12 + i) * nu + i] = 1.0; /* the lengths */
    }
    m->n = nu;
    m->nu = nu;
    m->nz = CDPR_DESIGN_NZ(nu);
    m->nm = 12 + nu;
    m->period_s = T;
    m->A = g_A;
    m->B = g_B;
    m->Kx = g_Kx;
    m->Kz = g_Kz;
    m->Zx = g_Zx;
    m->Zz = g_Zz;
    m->Ku = g_Ku;
    m->Zu = g_Zu;
    m->Cm = g_Cm;
    m->k_length_per_s = kl;
}

static void integrators(cdpr_design_model_t *m, double kl, double T)
{
    integrators_n(m, kl, T, N);
}

static void test_zero_order_hold(void)
{
    cdpr_design_model_t m;
    integrators(&m, 5.0, 0.01);
    double Phi[N * N];
    double Gam[N * 6];
    cdpr_design_error_t err;
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_design_discretise(&m, Phi, Gam, &err));
    for (int i = 0; i < N * N; ++i) {
        TEST_ASSERT_DOUBLE_WITHIN(1e-15, (i % 7 == 0) ? 1.0 : 0.0, Phi[i]);
        TEST_ASSERT_DOUBLE_WITHIN(1e-17, (i % 7 == 0) ? 0.01 : 0.0, Gam[i]);
    }
}

static void test_length_loop_closed_forms(void)
{
    const double kl = 5.0;
    const double T = 0.01;
    cdpr_design_model_t m;
    integrators(&m, kl, T);
    cdpr_design_error_t err;
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_design_analyse(&m, 0, &g_r, &err));
    TEST_ASSERT_DOUBLE_WITHIN(1e-12, 1.0 - kl * T, g_r.max_abs_eig);
    TEST_ASSERT_DOUBLE_WITHIN(1e-9, log(1.0 - kl * T) / T, g_r.growth_per_s);
    TEST_ASSERT_EQUAL_INT(0, g_r.grows);
    TEST_ASSERT_EQUAL_INT(3000, g_r.n_freq); /* no plant modes to refine around */
    TEST_ASSERT_EQUAL_INT(1, g_r.active);
    const double pm = 90.0 - asin(kl * T / 2.0) * 180.0 / 3.14159265358979323846;
    for (int j = 0; j < 6; ++j) {
        TEST_ASSERT_DOUBLE_WITHIN(1e-5, pm, g_r.pm_deg[j]); /* linear interpolation on the grid */
        TEST_ASSERT_TRUE(isinf(g_r.gm_db[j]));
    }
    TEST_ASSERT_DOUBLE_WITHIN(1e-5, pm, g_r.pm_min_deg);
    TEST_ASSERT_DOUBLE_WITHIN(1e-4, 1.0 - kl * T / 2.0, g_r.alpha);
    TEST_ASSERT_TRUE(g_r.alpha_hz > 49.9);
    TEST_ASSERT_EQUAL_INT(0, g_r.learning);
}

/* Every winch of the largest model this build analyses: nu channels, each the closed form. */
static void test_length_loops_of_every_winch(void)
{
    const double kl = 5.0;
    const double T = 0.01;
    cdpr_design_model_t m;
    integrators_n(&m, kl, T, NX);
    cdpr_design_error_t err;
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_design_analyse(&m, 0, &g_r, &err));
    TEST_ASSERT_EQUAL_INT(NX, g_r.n_channels);
    TEST_ASSERT_DOUBLE_WITHIN(1e-12, 1.0 - kl * T, g_r.max_abs_eig);
    const double pm = 90.0 - asin(kl * T / 2.0) * 180.0 / 3.14159265358979323846;
    for (int j = 0; j < NX; ++j) {
        TEST_ASSERT_DOUBLE_WITHIN(1e-5, pm, g_r.pm_deg[j]);
        TEST_ASSERT_TRUE(isinf(g_r.gm_db[j]));
    }
    TEST_ASSERT_DOUBLE_WITHIN(1e-4, 1.0 - kl * T / 2.0, g_r.alpha);
    /* One winch's loop twice as fast: only its channel's margin moves (decoupled loops). */
    g_Kx[(NX - 1) * NX + (NX - 1)] = -2.0 * kl;
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_design_analyse(&m, 0, &g_r, &err));
    const double pm2 = 90.0 - asin(2.0 * kl * T / 2.0) * 180.0 / 3.14159265358979323846;
    TEST_ASSERT_DOUBLE_WITHIN(1e-5, pm, g_r.pm_deg[0]);
    TEST_ASSERT_DOUBLE_WITHIN(1e-5, pm2, g_r.pm_deg[NX - 1]);
    TEST_ASSERT_DOUBLE_WITHIN(1e-5, pm2, g_r.pm_min_deg);
    /* Sizes that do not fit together are refused. */
    m.nz = 30;
    TEST_ASSERT_EQUAL_INT(CDPR_E_INVALID_ARG, cdpr_design_analyse(&m, 0, &g_r, &err));
    TEST_ASSERT_NOT_NULL(strstr(err.msg, "model sizes"));
}

static void test_length_loop_too_fast_grows(void)
{
    const double kl = 250.0; /* k_L T = 2.5: the eigenvalue 1 - 2.5 = -1.5 */
    const double T = 0.01;
    cdpr_design_model_t m;
    integrators(&m, kl, T);
    cdpr_design_error_t err;
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_design_analyse(&m, 0, &g_r, &err));
    TEST_ASSERT_EQUAL_INT(1, g_r.grows);
    TEST_ASSERT_DOUBLE_WITHIN(1e-9, log(1.5) / T, g_r.growth_per_s);
    TEST_ASSERT_DOUBLE_WITHIN(1e-9, 50.0, g_r.growth_hz);
}

static void test_learning_closed_form(void)
{
    const double kl = 5.0;
    const double T = 0.01;
    const double gamma = 0.5;
    const double lead = 0.1;
    const double fc = 1.0;
    cdpr_design_model_t m;
    integrators(&m, kl, T);
    m.lap_s = 1.0;
    m.learn_knots = 100.0;
    m.learning_gain = gamma;
    m.learning_lead_s = lead;
    m.learning_cutoff_hz = fc;
    cdpr_design_error_t err;
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_design_analyse(&m, 1, &g_r, &err));
    TEST_ASSERT_EQUAL_INT(1, g_r.learning);
    TEST_ASSERT_TRUE(g_r.n_harmonics >= 5);
    const double pi = 3.14159265358979323846;
    const double a = 1.0 - kl * T;
    const double aq = exp(-2.0 * pi * fc * 0.01);
    double worst = 0.0;
    for (int h = 1; h <= g_r.n_harmonics; ++h) {
        const double w = 2.0 * pi * (double)h;
        const double complex z = cexp(w * T * (double complex)_Complex_I);
        const double q = (1.0 - aq) * (1.0 - aq) /
                         pow(cabs(1.0 - aq * cexp(-w * 0.01 * (double complex)_Complex_I)), 2.0);
        const double rho = cabs(
            q * (1.0 - gamma * cexp(w * lead * (double complex)_Complex_I) * (1.0 - a) / (z - a)));
        TEST_ASSERT_DOUBLE_WITHIN(1e-12, (double)h, g_r.harmonic_hz[h - 1]);
        TEST_ASSERT_DOUBLE_WITHIN(1e-12, q, g_r.harmonic_q[h - 1]);
        TEST_ASSERT_DOUBLE_WITHIN(1e-10, rho, g_r.rho[h - 1]);
        TEST_ASSERT_DOUBLE_WITHIN(1e-10, rho, g_r.sigma_max[h - 1]); /* M is a multiple of I */
        worst = fmax(worst, rho);
    }
    TEST_ASSERT_DOUBLE_WITHIN(1e-10, worst, g_r.max_rho);
    TEST_ASSERT_DOUBLE_WITHIN(1e-6, 1.0, g_r.g0_diag[0]); /* G(1) = (1 - a) / (1 - a) */
}

static void test_not_finite_refused(void)
{
    cdpr_design_model_t m;
    integrators(&m, 5.0, 0.01);
    cdpr_design_error_t err;
    g_Zz[7] = (double)NAN;
    TEST_ASSERT_EQUAL_INT(CDPR_E_NOT_FINITE, cdpr_design_analyse(&m, 1, &g_r, &err));
    TEST_ASSERT_NOT_NULL(strstr(err.msg, "Zz is not finite"));
    integrators(&m, 5.0, 0.01);
    g_A[3] = (double)INFINITY;
    double Phi[N * N];
    double Gam[N * 6];
    TEST_ASSERT_EQUAL_INT(CDPR_E_NOT_FINITE, cdpr_design_discretise(&m, Phi, Gam, &err));
    TEST_ASSERT_NOT_NULL(strstr(err.msg, "A is not finite"));
    integrators(&m, 5.0, 0.01);
    m.learning_lead_s = (double)NAN;
    TEST_ASSERT_EQUAL_INT(CDPR_E_NOT_FINITE, cdpr_design_analyse(&m, 1, &g_r, &err));
    memset(&m, 0, sizeof m);
    TEST_ASSERT_EQUAL_INT(CDPR_E_INVALID_ARG, cdpr_design_analyse(&m, 1, &g_r, &err));
}

static void test_feed_forward_is_not_checked(void)
{
    cdpr_tracker_gains_t g;
    memset(&g, 0, sizeof g);
    g.k_length_per_s = 5.0;
    g.filter_s = 0.1;
    TEST_ASSERT_EQUAL_INT(0, cdpr_tracker_has_feedback(&g));
    for (int k = 0; k < 6; ++k) {
        cdpr_tracker_gains_t h = g;
        double *key[6] = {&h.kp,
                          &h.kd_s,
                          &h.damping_N_s_per_m,
                          &h.damping_rot_N_m_s,
                          &h.tension_gain_m_per_s_per_N,
                          &h.learning_gain};
        *key[k] = 0.1;
        TEST_ASSERT_EQUAL_INT(1, cdpr_tracker_has_feedback(&h));
    }
    static cdpr_scenario_t sc; /* zeros: an unusable scenario, never looked at */
    sc.gains = g;
    int checked = -1;
    int warn = -1;
    cdpr_design_error_t err;
    TEST_ASSERT_EQUAL_INT(CDPR_OK,
                          cdpr_design_check_scenario(&sc, "x.yaml", &checked, &warn, NULL, &err));
    TEST_ASSERT_EQUAL_INT(0, checked);
    TEST_ASSERT_EQUAL_INT(0, warn);
}

/* A shipped scenario, loaded (TEST_ASSERT on failure). */
static void load(const char *name, cdpr_scenario_t *sc)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/scenarios/%s", CDPR_SOURCE_DIR, name);
    cdpr_scenario_error_t err;
    TEST_ASSERT_EQUAL_INT_MESSAGE(CDPR_OK, cdpr_scenario_load(path, sc, &err), err.msg);
}

/* The robustness set's poses: a line's start, middle and end; a circle's 0, half and all of
 * the run (it never stops); a hold's one pose, counted once. */
static void test_robust_times(void)
{
    static cdpr_scenario_t sc;
    double t[CDPR_DESIGN_ROBUST_POSES];
    load("paper-line.yaml", &sc); /* a 10 s line */
    TEST_ASSERT_EQUAL_INT(3, cdpr_design_robust_times(&sc, t));
    TEST_ASSERT_EQUAL_DOUBLE(0.0, t[0]);
    TEST_ASSERT_EQUAL_DOUBLE(5.0, t[1]);
    TEST_ASSERT_EQUAL_DOUBLE(10.0, t[2]);
    load("paper-circle-laps.yaml", &sc);
    TEST_ASSERT_EQUAL_INT(3, cdpr_design_robust_times(&sc, t));
    TEST_ASSERT_EQUAL_DOUBLE(0.5 * sc.duration_s, t[1]);
    TEST_ASSERT_EQUAL_DOUBLE(sc.duration_s, t[2]);
    sc.traj.type = CDPR_TRAJ_HOLD;
    TEST_ASSERT_EQUAL_INT(1, cdpr_design_robust_times(&sc, t));
    TEST_ASSERT_EQUAL_DOUBLE(0.0, t[0]);
}

/* Sum of the cable forces on the settled cabin, world z [N]: at rest it carries the combined
 * weight (cabin and the ropes' node-0 masses) -- Newton, independent of the variation. */
static double settled_lift(cdpr_design_point_t *pt, double *weight)
{
    const cdpr_robot_t *r = &pt->plant.robot;
    cdpr_robot_out_t out;
    cdpr_robot_outputs(r, 0.0, pt->plant.y, &out);
    *weight = r->cabin.mass_kg * r->p.g_m_per_s2;
    return out.total_force_N.z;
}

/* A case's plant carries the variation, its controller the scenario's model: cabin mass +20 %
 * in the plant (statics: the cables lift 1.2 times the cabin), the controller's model mass
 * unchanged; EA +20 % in the plant's ropes only. */
static void test_robust_variation_reaches_the_plant_only(void)
{
    static cdpr_scenario_t sc;
    load("paper-line.yaml", &sc);
    const cdpr_rig_scale_t heavy = {1.0, 1.2, 1.0};
    cdpr_design_point_t *pt = NULL;
    cdpr_design_error_t err;
    TEST_ASSERT_EQUAL_INT_MESSAGE(CDPR_OK, cdpr_design_point_new(&sc, 10.0, &heavy, &pt, &err),
                                  err.msg);
    TEST_ASSERT_EQUAL_DOUBLE(sc.rig.cabin_mass_kg, pt->tr0.model.p.cabin.mass_kg);
    TEST_ASSERT_EQUAL_DOUBLE(1.2 * sc.rig.cabin_mass_kg, pt->plant.params.cabin.mass_kg);
    TEST_ASSERT_EQUAL_DOUBLE(1.2 * sc.rig.cabin_inertia_kg_m2[2][2],
                             pt->plant.params.cabin.inertia_com_kg_m2.m[2][2]);
    TEST_ASSERT_EQUAL_DOUBLE(sc.rig.cable[0].rope.ea_N, pt->plant.params.cables[0].cable.ea_N);
    double w_heavy = 0.0;
    const double lift_heavy = settled_lift(pt, &w_heavy);
    TEST_ASSERT_DOUBLE_WITHIN(1e-3 * w_heavy, w_heavy, lift_heavy);
    cdpr_design_point_free(pt);
    TEST_ASSERT_EQUAL_INT_MESSAGE(CDPR_OK, cdpr_design_point_new(&sc, 10.0, NULL, &pt, &err),
                                  err.msg);
    double w = 0.0;
    const double lift = settled_lift(pt, &w);
    TEST_ASSERT_DOUBLE_WITHIN(1e-3 * w, w, lift);
    /* The cabin's share of the lift grew by 20 % (the ropes' node-0 masses did not). */
    const double m0 = sc.rig.cabin_mass_kg * pt->plant.params.g_m_per_s2;
    TEST_ASSERT_DOUBLE_WITHIN(2e-3 * m0, 0.2 * m0, lift_heavy - lift);
    cdpr_design_point_free(pt);
    const cdpr_rig_scale_t stiff = {1.2, 1.0, 1.0};
    TEST_ASSERT_EQUAL_INT_MESSAGE(CDPR_OK, cdpr_design_point_new(&sc, 0.0, &stiff, &pt, &err),
                                  err.msg);
    for (int j = 0; j < sc.rig.n_cables; ++j) {
        TEST_ASSERT_EQUAL_DOUBLE(sc.rig.cable[j].rope.ea_N, pt->tr0.model.p.cables[j].cable.ea_N);
        TEST_ASSERT_EQUAL_DOUBLE(1.2 * sc.rig.cable[j].rope.ea_N,
                                 pt->plant.params.cables[j].cable.ea_N);
        TEST_ASSERT_EQUAL_DOUBLE(sc.rig.cable[j].rope.rho_kg_per_m,
                                 pt->plant.params.cables[j].cable.rho_kg_per_m);
    }
    cdpr_design_point_free(pt);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_robust_times);
    RUN_TEST(test_robust_variation_reaches_the_plant_only);
    RUN_TEST(test_zero_order_hold);
    RUN_TEST(test_length_loop_closed_forms);
    RUN_TEST(test_length_loops_of_every_winch);
    RUN_TEST(test_length_loop_too_fast_grows);
    RUN_TEST(test_learning_closed_form);
    RUN_TEST(test_not_finite_refused);
    RUN_TEST(test_feed_forward_is_not_checked);
    return UNITY_END();
}
