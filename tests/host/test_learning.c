/* SPDX-License-Identifier: BSD-3-Clause */
/// @file test_learning.c
/// Learning over laps (tracker.h step 8) on a linear plant closed in the test: the winch
/// lengths integrate the rate commands exactly, L_{k+1} = L_k + Δt u_k, and the measured pose
/// is placed so that the tracker's length error is e_L = w(φ) - x, x = L - L_ff the lengths'
/// deviation from the feed-forward and w a periodic disturbance (one lap harmonic). With
/// kp = kd = 0 the tracker's law makes x_{k+1} = α x_k + (1 - α) c_k, α = 1 - k_L Δt: the
/// drop of e_L per unit correction is G(z) = (1 - α) / (z - α), and the lap-to-lap map of the
/// learned correction at the harmonic ω is, in closed form (computed here, not by the code),
///   M(ω) = Q(ω) (1 - γ e^{jωλ} G(e^{jωΔt})),  Q = (1 - a)^2 / |1 - a e^{-jωΔ}|^2,
/// so consecutive lap differences of the error's harmonic obey
///   (E_{k+2} - E_{k+1}) / (E_{k+1} - E_k) = M(ω).
/// Checked: that ratio for a converging and a diverging setting, saturation bounded and
/// counted, reset at init, no learning on a line, learning off bit-identical to the tracker
/// without the keys, reruns bit-identical, no heap allocation.
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "alloc_count.h"
#include "cdpr/host/presets.h"
#include "cdpr/host/scenario.h"
#include "cdpr/control/tracker.h"
#include "paper_circle.h"
#include "paper_model.h"
#include "unity.h"

static const double PERIOD_S = 0.01;
static const double K_L = 20.0; /* α = 0.8: the plant's lag settles in 0.05 s */
static const double PI = 3.14159265358979323846;

/* Complex arithmetic (complex.h's I clashes with the rig header's parameter names). */
typedef struct {
    double re;
    double im;
} cx_t;

static cx_t cx(double re, double im)
{
    const cx_t z = {re, im};
    return z;
}
static cx_t cx_expj(double th)
{
    return cx(cos(th), sin(th));
}
static cx_t cx_add(cx_t a, cx_t b)
{
    return cx(a.re + b.re, a.im + b.im);
}
static cx_t cx_sub(cx_t a, cx_t b)
{
    return cx(a.re - b.re, a.im - b.im);
}
static cx_t cx_scale(cx_t a, double s)
{
    return cx(s * a.re, s * a.im);
}
static cx_t cx_mul(cx_t a, cx_t b)
{
    return cx(a.re * b.re - a.im * b.im, a.re * b.im + a.im * b.re);
}
static cx_t cx_div(cx_t a, cx_t b)
{
    const double d = b.re * b.re + b.im * b.im;
    return cx((a.re * b.re + a.im * b.im) / d, (a.im * b.re - a.re * b.im) / d);
}
static double cx_abs(cx_t a)
{
    return hypot(a.re, a.im);
}

void setUp(void) {}
void tearDown(void) {}

static cdpr_tracker_t tracker;
static cdpr_tracker_t tracker2;

static void model_params(cdpr_robot_params_t *p)
{
    test_paper_model_params(p, NULL);
}

static cdpr_tracker_gains_t gains(double gamma, double lead_s, double fc_hz, double limit_m)
{
    cdpr_tracker_gains_t g;
    memset(&g, 0, sizeof g);
    g.k_length_per_s = K_L;
    g.inertial_ff = 1.0;
    g.learning_gain = gamma;
    g.learning_lead_s = lead_s;
    g.learning_cutoff_hz = fc_hz;
    g.learning_limit_m = limit_m;
    return g;
}

/* x = A^-1 b for a 6x6 A (Gaussian elimination with partial pivoting). */
static void solve6(double A[6][6], const double *b, double *x)
{
    double M[6][7];
    for (int i = 0; i < 6; ++i) {
        memcpy(M[i], A[i], sizeof A[i]);
        M[i][6] = b[i];
    }
    for (int c = 0; c < 6; ++c) {
        int p = c;
        for (int i = c + 1; i < 6; ++i) {
            p = (fabs(M[i][c]) > fabs(M[p][c])) ? i : p;
        }
        for (int k = 0; k < 7; ++k) {
            const double t = M[c][k];
            M[c][k] = M[p][k];
            M[p][k] = t;
        }
        for (int i = c + 1; i < 6; ++i) {
            const double f = M[i][c] / M[c][c];
            for (int k = c; k < 7; ++k) {
                M[i][k] -= f * M[c][k];
            }
        }
    }
    for (int i = 5; i >= 0; --i) {
        double s = M[i][6];
        for (int k = i + 1; k < 6; ++k) {
            s -= M[i][k] * x[k];
        }
        x[i] = s / M[i][i];
    }
}

/* The measured pose whose length error (straight-cable Jacobian at that pose) is v: δ with
 * J(p_d + δ) δ = v by fixed-point iteration (|δ| ~ mm: converges to rounding in a few). */
static cdpr_cabin_motion_t pose_with_error(const cdpr_cabin_motion_t *d, const double *v)
{
    double delta[6] = {0.0};
    cdpr_cabin_motion_t m = *d;
    for (int it = 0; it < 8; ++it) {
        m = *d;
        m.p_m = cdpr_v3_add(d->p_m, cdpr_v3(delta[0], delta[1], delta[2]));
        const double a = sqrt(delta[3] * delta[3] + delta[4] * delta[4] + delta[5] * delta[5]);
        const double s = (a > 0.0) ? sin(0.5 * a) / a : 0.5;
        const cdpr_quat_t dq = {cos(0.5 * a), s * delta[3], s * delta[4], s * delta[5]};
        m.q = cdpr_quat_mul(dq, d->q);
        double J[6][6];
        for (int j = 0; j < 6; ++j) {
            cdpr_vec3_t u;
            cdpr_vec3_t g;
            cdpr_tracker_jacobian(&tracker.model, j, &m, &u, &g);
            const double row[6] = {u.x, u.y, u.z, g.x, g.y, g.z};
            memcpy(J[j], row, sizeof row);
        }
        solve6(J, v, delta);
    }
    return m;
}

/* Disturbance of cable j at lap phase f: harmonic n, amplitude 1 mm, phase by cable. */
static double disturbance(int j, int n, double f)
{
    return 1e-3 * sin(2.0 * PI * (double)n * f + 0.7 * (double)j);
}

/* Runs `laps` laps of the linear plant with tracker `tr` (initialised); per lap k the
 * harmonic n of cable 0's e_L, E[k] = (2/N) sum e e^{-j 2π n φ}. Returns the largest |c|. */
static double run_plant(cdpr_tracker_t *tr, int n, int laps, cx_t *E, double *rate_sum)
{
    const cdpr_traj_t *traj = &tr->traj;
    const long steps = (long)ceil((double)laps * cdpr_traj_lap_s(traj) / PERIOD_S);
    double x[6] = {0.0};
    cx_t acc = cx(0.0, 0.0);
    long cnt = 0;
    long lap_prev = 0;
    *rate_sum = 0.0;
    for (long k = 0; k <= steps; ++k) {
        const double t = PERIOD_S * (double)k;
        const long lap = cdpr_traj_lap(traj, t);
        const double f = cdpr_traj_lap_phase(traj, t);
        if (lap != lap_prev) {
            E[lap_prev] = cx_scale(acc, 2.0 / (double)cnt);
            acc = cx(0.0, 0.0);
            cnt = 0;
            lap_prev = lap;
        }
        if (lap >= laps) {
            break;
        }
        double v[6];
        for (int j = 0; j < 6; ++j) {
            v[j] = disturbance(j, n, f) - x[j];
        }
        acc = cx_add(acc, cx_scale(cx_expj(-2.0 * PI * (double)n * f), v[0]));
        cnt++;
        cdpr_traj_sample_t s;
        cdpr_traj_eval(traj, t, &s);
        cdpr_tracker_meas_t m;
        memset(&m, 0, sizeof m);
        m.t_s = t;
        m.cabin = pose_with_error(&s.motion, v);
        for (int j = 0; j < 6; ++j) {
            m.length_m[j] = tr->l_ff_m[j] + x[j];
        }
        cdpr_tracker_cmd_t cmd;
        TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_tracker_step(tr, &m, &cmd));
        TEST_ASSERT_EQUAL_INT(CDPR_OK, cmd.ik_status);
        for (int j = 0; j < 6; ++j) {
            x[j] += PERIOD_S * (cmd.rate_m_per_s[j] - cmd.u_ff_m_per_s[j]);
            *rate_sum += cmd.rate_m_per_s[j];
        }
    }
    double cmax = 0.0;
    for (int j = 0; j < 6; ++j) {
        for (int i = 0; i < tr->learn_knots; ++i) {
            cmax = fmax(cmax, fabs(tr->learn_c[j][i]));
        }
    }
    return cmax;
}

/* The closed-form lap-to-lap factor M at harmonic n. */
static cx_t predicted_m(const cdpr_tracker_gains_t *g, double lap_s, int knots, int n)
{
    const double w = 2.0 * PI * (double)n / lap_s;
    const double alpha = 1.0 - K_L * PERIOD_S;
    const cx_t z = cx_expj(w * PERIOD_S);
    const cx_t G = cx_div(cx(1.0 - alpha, 0.0), cx_sub(z, cx(alpha, 0.0)));
    double q = 1.0;
    if (g->learning_cutoff_hz > 0.0) {
        const double dphi = lap_s / (double)knots;
        const double a = exp(-2.0 * PI * g->learning_cutoff_hz * dphi);
        const double h = cx_abs(cx_sub(cx(1.0, 0.0), cx_scale(cx_expj(-w * dphi), a)));
        q = (1.0 - a) * (1.0 - a) / (h * h);
    }
    const cx_t lg = cx_scale(cx_mul(cx_expj(w * g->learning_lead_s), G), g->learning_gain);
    return cx_scale(cx_sub(cx(1.0, 0.0), lg), q);
}

/* Ratio of consecutive lap differences of E from lap k0 on, against M. The tolerance 0.02
 * (on |M| ~ 0.5 .. 2) covers the plant's lag after each lap's change of c, which the
 * periodic-steady-state formula leaves out: about 2 τ / T_lap |G| = 2 (0.045 s) / 6.28 s. */
static void check_ratio(const cx_t *E, int k0, int k1, cx_t M)
{
    for (int k = k0; k + 2 <= k1; ++k) {
        const cx_t r = cx_div(cx_sub(E[k + 2], E[k + 1]), cx_sub(E[k + 1], E[k]));
        char msg[160];
        snprintf(msg, sizeof msg, "lap %d: ratio %.4f%+.4fi, predicted %.4f%+.4fi", k, r.re, r.im,
                 M.re, M.im);
        TEST_ASSERT_MESSAGE(cx_abs(cx_sub(r, M)) < 0.02 * cx_abs(M) + 0.01, msg);
    }
}

static void test_converges_as_the_closed_form_predicts(void)
{
    cdpr_robot_params_t p;
    model_params(&p);
    const cdpr_traj_t traj = test_paper_circle();
    const cdpr_tracker_gains_t g = gains(0.5, 0.1, 1.0, 0.5);
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_tracker_init(&tracker, &p, &traj, &g, PERIOD_S, 0.0, NULL));
    TEST_ASSERT_EQUAL_INT(512, tracker.learn_knots);
    cx_t E[8];
    double rs;
    (void)run_plant(&tracker, 2, 7, E, &rs);
    const cx_t M = predicted_m(&g, cdpr_traj_lap_s(&traj), 512, 2);
    TEST_ASSERT_TRUE(cx_abs(M) < 1.0);
    /* lap 0 is not recorded (the tracker starts in it), lap 1 is the first; its update acts
     * from lap 2 on: the map holds between laps 2, 3, ... */
    check_ratio(E, 2, 6, M);
    TEST_ASSERT_TRUE(cx_abs(E[6]) < 0.5 * cx_abs(E[1]));
    TEST_ASSERT_EQUAL_UINT32(5u, (unsigned)tracker.learning_updates); /* laps 1-5 */
    TEST_ASSERT_EQUAL_UINT32(0u, (unsigned)tracker.learning_saturations);
}

static void test_diverges_as_predicted_and_saturation_bounds_it(void)
{
    cdpr_robot_params_t p;
    model_params(&p);
    const cdpr_traj_t traj = test_paper_circle();
    const double lap = cdpr_traj_lap_s(&traj);
    /* lead of half a period of harmonic 2 and no filter: M = 1 + γ G, |M| ~ 1.8 */
    cdpr_tracker_gains_t g = gains(1.0, 0.25 * lap, 0.0, 1.0);
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_tracker_init(&tracker, &p, &traj, &g, PERIOD_S, 0.0, NULL));
    cx_t E[8];
    double rs;
    (void)run_plant(&tracker, 2, 6, E, &rs);
    const cx_t M = predicted_m(&g, lap, 512, 2);
    TEST_ASSERT_TRUE(cx_abs(M) > 1.5);
    check_ratio(E, 2, 5, M);
    TEST_ASSERT_EQUAL_UINT32(0u, (unsigned)tracker.learning_saturations);
    /* the same with a bound of 2 mm: the correction stays within it, every clamp counted */
    g.learning_limit_m = 2e-3;
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_tracker_init(&tracker, &p, &traj, &g, PERIOD_S, 0.0, NULL));
    const double cmax = run_plant(&tracker, 2, 6, E, &rs);
    TEST_ASSERT_TRUE(cmax <= 2e-3 && cmax >= 2e-3);
    TEST_ASSERT_TRUE(tracker.learning_saturations > 0u);
    unsigned long at_limit = 0;
    for (int j = 0; j < 6; ++j) {
        for (int i = 0; i < tracker.learn_knots; ++i) {
            at_limit += (fabs(tracker.learn_c[j][i]) >= 2e-3) ? 1u : 0u;
        }
    }
    /* the last update's clamps are the knots at the limit now (earlier ones are counted too) */
    TEST_ASSERT_TRUE(at_limit > 0u && at_limit <= tracker.learning_saturations);
}

static void test_reset_at_init_and_bit_identical_reruns(void)
{
    cdpr_robot_params_t p;
    model_params(&p);
    cdpr_traj_t traj = test_paper_circle();
    const cdpr_tracker_gains_t g = gains(0.5, 0.1, 1.0, 0.5);
    cx_t E[8];
    cx_t E2[8];
    double rs1;
    double rs2;
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_tracker_init(&tracker, &p, &traj, &g, PERIOD_S, 0.0, NULL));
    (void)run_plant(&tracker, 2, 4, E, &rs1);
    TEST_ASSERT_EQUAL_UINT32(2u, (unsigned)tracker.learning_updates);
    TEST_ASSERT_TRUE(fabs(tracker.learn_c[0][100]) > 0.0);
    TEST_ASSERT_EQUAL_INT(CDPR_OK,
                          cdpr_tracker_init(&tracker2, &p, &traj, &g, PERIOD_S, 0.0, NULL));
    (void)run_plant(&tracker2, 2, 4, E2, &rs2);
    TEST_ASSERT_EQUAL_MEMORY(tracker.learn_c, tracker2.learn_c, sizeof tracker.learn_c);
    TEST_ASSERT_EQUAL_MEMORY(E, E2, 4 * sizeof E[0]);
    TEST_ASSERT_EQUAL_MEMORY(&rs1, &rs2, sizeof rs1);
    /* a new trajectory (a slower circle) re-inits: nothing learned is kept */
    traj.speed_m_per_s = 1.0;
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_tracker_init(&tracker, &p, &traj, &g, PERIOD_S, 0.0, NULL));
    TEST_ASSERT_EQUAL_UINT32(0u, (unsigned)tracker.learning_updates);
    for (int i = 0; i < CDPR_TRACKER_LEARN_KNOTS; ++i) {
        TEST_ASSERT_FALSE(fabs(tracker.learn_c[0][i]) > 0.0 || fabs(tracker.learn_c[5][i]) > 0.0);
    }
    TEST_ASSERT_EQUAL_DOUBLE(2.0 * PI * 2.0 / 1.0, tracker.learn_lap_s);
}

static void test_no_learning_on_a_line_and_off_is_bit_identical(void)
{
    cdpr_robot_params_t p;
    model_params(&p);
    const double from[6] = {0.0, 0.0, 9.135, 0.0, 0.0, 0.0};
    const double to[6] = {0.3, 0.2, 9.5, 0.0, 0.0, 0.05};
    const cdpr_traj_t line = test_line(from, to, 20.0);
    TEST_ASSERT_EQUAL_DOUBLE(0.0, cdpr_traj_lap_s(&line));
    const cdpr_tracker_gains_t on = gains(0.5, 0.1, 1.0, 0.5);
    cdpr_tracker_gains_t off = gains(0.0, 0.3, 2.0, 0.1);
    off.learning_settle_laps = 2;
    const cdpr_tracker_gains_t none = gains(0.0, 0.0, 0.0, 0.0);
    cx_t E[8];
    double rs[3];
    const cdpr_tracker_gains_t *gs[3] = {&on, &off, &none};
    for (int i = 0; i < 3; ++i) {
        TEST_ASSERT_EQUAL_INT(CDPR_OK,
                              cdpr_tracker_init(&tracker, &p, &line, gs[i], PERIOD_S, 0.0, NULL));
        TEST_ASSERT_EQUAL_INT(0, tracker.learn_knots);
        /* a line has no laps: run_plant's lap count stays at 0, run 10 s by hand */
        double x[6] = {0.0};
        rs[i] = 0.0;
        for (long k = 0; k < 1000; ++k) {
            cdpr_traj_sample_t s;
            cdpr_traj_eval(&line, PERIOD_S * (double)k, &s);
            double v[6];
            for (int j = 0; j < 6; ++j) {
                v[j] = 1e-3 * sin(0.5 * PERIOD_S * (double)k + (double)j) - x[j];
            }
            cdpr_tracker_meas_t m;
            memset(&m, 0, sizeof m);
            m.t_s = PERIOD_S * (double)k;
            m.cabin = pose_with_error(&s.motion, v);
            for (int j = 0; j < 6; ++j) {
                m.length_m[j] = tracker.l_ff_m[j] + x[j];
            }
            cdpr_tracker_cmd_t cmd;
            TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_tracker_step(&tracker, &m, &cmd));
            for (int j = 0; j < 6; ++j) {
                x[j] += PERIOD_S * (cmd.rate_m_per_s[j] - cmd.u_ff_m_per_s[j]);
                rs[i] += cmd.rate_m_per_s[j];
            }
        }
        TEST_ASSERT_EQUAL_UINT32(0u, (unsigned)tracker.learning_updates);
    }
    TEST_ASSERT_EQUAL_MEMORY(&rs[2], &rs[0], sizeof rs[0]);
    TEST_ASSERT_EQUAL_MEMORY(&rs[2], &rs[1], sizeof rs[0]);
    /* on a periodic trajectory, learning off: the same commands as without the keys */
    const cdpr_traj_t circle = test_paper_circle();
    TEST_ASSERT_EQUAL_INT(CDPR_OK,
                          cdpr_tracker_init(&tracker, &p, &circle, &off, PERIOD_S, 0.0, NULL));
    TEST_ASSERT_EQUAL_INT(0, tracker.learn_knots);
    (void)run_plant(&tracker, 2, 2, E, &rs[0]);
    TEST_ASSERT_EQUAL_INT(CDPR_OK,
                          cdpr_tracker_init(&tracker, &p, &circle, &none, PERIOD_S, 0.0, NULL));
    (void)run_plant(&tracker, 2, 2, E, &rs[1]);
    TEST_ASSERT_EQUAL_MEMORY(&rs[0], &rs[1], sizeof rs[0]);
}

static void test_scenario_refuses_learning_without_laps_and_bad_keys(void)
{
    cdpr_scenario_t sc;
    cdpr_scenario_default(&sc, CDPR_PRESET_PAPER_50M);
    cdpr_scenario_error_t err;
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_scenario_check(&sc, &err));
    TEST_ASSERT_FALSE(cdpr_traj_lap_s(&sc.traj) > 0.0); /* the default scenario holds a pose */
    sc.gains.learning_gain = 0.3;
    TEST_ASSERT_EQUAL_INT(CDPR_E_OUT_OF_RANGE, cdpr_scenario_check(&sc, &err));
    TEST_ASSERT_NOT_NULL(strstr(err.msg, "controller.learning_gain"));
    TEST_ASSERT_NOT_NULL(strstr(err.msg, "periodic"));
    sc.traj = test_paper_circle();
    TEST_ASSERT_EQUAL_INT_MESSAGE(CDPR_OK, cdpr_scenario_check(&sc, &err), err.msg);
    sc.gains.learning_limit_m = 0.0;
    TEST_ASSERT_EQUAL_INT(CDPR_E_OUT_OF_RANGE, cdpr_scenario_check(&sc, &err));
    TEST_ASSERT_NOT_NULL(strstr(err.msg, "controller.learning_limit_m"));
    sc.gains.learning_limit_m = 0.5;
    sc.gains.learning_gain = 2.5;
    TEST_ASSERT_EQUAL_INT(CDPR_E_OUT_OF_RANGE, cdpr_scenario_check(&sc, &err));
    TEST_ASSERT_NOT_NULL(strstr(err.msg, "controller.learning_gain"));
    /* the tracker's own checks name the field */
    cdpr_robot_params_t p;
    model_params(&p);
    cdpr_diag_t d;
    cdpr_tracker_gains_t g = gains(0.5, -0.1, 1.0, 0.5);
    TEST_ASSERT_EQUAL_INT(CDPR_E_OUT_OF_RANGE,
                          cdpr_tracker_init(&tracker, &p, &sc.traj, &g, PERIOD_S, 0.0, &d));
    TEST_ASSERT_EQUAL_STRING("learning_lead_s", d.field);
    g = gains(0.5, 0.1, (double)NAN, 0.5);
    TEST_ASSERT_EQUAL_INT(CDPR_E_NOT_FINITE,
                          cdpr_tracker_init(&tracker, &p, &sc.traj, &g, PERIOD_S, 0.0, &d));
    TEST_ASSERT_EQUAL_STRING("learning_cutoff_hz", d.field);
    g = gains(0.5, 0.1, 1.0, 0.0);
    TEST_ASSERT_EQUAL_INT(CDPR_E_OUT_OF_RANGE,
                          cdpr_tracker_init(&tracker, &p, &sc.traj, &g, PERIOD_S, 0.0, &d));
    TEST_ASSERT_EQUAL_STRING("learning_limit_m", d.field);
}

static void test_learning_makes_no_heap_allocation(void)
{
    if (!cdpr_alloc_counting_available()) {
        TEST_IGNORE_MESSAGE(cdpr_alloc_unavailable_reason());
    }
    cdpr_robot_params_t p;
    model_params(&p);
    const cdpr_traj_t traj = test_paper_circle();
    const cdpr_tracker_gains_t g = gains(0.5, 0.1, 1.0, 0.5);
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_tracker_init(&tracker, &p, &traj, &g, PERIOD_S, 0.0, NULL));
    cx_t E[8];
    double rs;
    cdpr_alloc_reset();
    (void)run_plant(&tracker, 2, 4, E, &rs); /* two updates */
    TEST_ASSERT_EQUAL_UINT32(2u, (unsigned)tracker.learning_updates);
    TEST_ASSERT_EQUAL_UINT32(0u, (unsigned)cdpr_alloc_count());
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_converges_as_the_closed_form_predicts);
    RUN_TEST(test_diverges_as_predicted_and_saturation_bounds_it);
    RUN_TEST(test_reset_at_init_and_bit_identical_reruns);
    RUN_TEST(test_no_learning_on_a_line_and_off_is_bit_identical);
    RUN_TEST(test_scenario_refuses_learning_without_laps_and_bad_keys);
    RUN_TEST(test_learning_makes_no_heap_allocation);
    return UNITY_END() ? 1 : 0;
}
