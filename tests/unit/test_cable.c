/* SPDX-License-Identifier: BSD-3-Clause */
/// @file test_cable.c
/// Lumped-mass cable (cable.h, docs/model.md §2): segment forces and the RHS of one cable.
///
/// Every expected value is written out in the test from the model's formulas (hand-derived
/// numbers in the comments), never by calling the function under test. The geometry uses the
/// unit tangent t = (0.48, -0.36, 0.8) and the unit normal n = (0.6, 0.8, 0) (t . n = 0), so
/// chords of 2.5 m have "round" components and the expected values are short closed forms.
///
/// Tolerances (double build): the closed forms below are a few tens of floating-point
/// operations on O(1) numbers, each with relative error <= u = 1.1e-16, and the segment
/// chords are rounded once when stored (relative 1e-16, amplified by at most 1/eps = 4 in the
/// strain). The result is therefore within ~1e-14 relative of the exact value; 1e-12 relative
/// leaves two orders of margin yet catches every modelling error (a wrong sign, factor 1/2,
/// Cm or sqrt(1+eps) factor changes the result by >= 2 %).
///
/// Float build (tests/support/test_real.h): the same rounding argument with u_f = 6e-8 gives
/// REL = 6e-4, which still catches every modelling error above; the largest input rounding
/// amplification here (strain 0.03 in the node-count sweep: 2 u_f / 0.03 = 4e-6 relative on
/// the tension) is far inside it. Exact copies are compared with the input rounded to
/// cdpr_real_t, so they stay exact.
#include "unity.h"

#include "alloc_count.h"
#include "cdpr/cable.h"
#include "test_real.h"

#include <math.h>
#include <string.h>

#define REL TOL(1e-12, 6e-4) /* see the file comment */

void setUp(void) {}

void tearDown(void) {}

/* ---------------------------------------------------------------- helpers */

static const double T_HAT[3] = {0.48, -0.36, 0.8}; /* unit: 0.2304 + 0.1296 + 0.64 = 1 */
static const double N_HAT[3] = {0.6, 0.8, 0.0};    /* unit, t . n = 0.288 - 0.288 = 0 */
static const cdpr_vec3_t RA = {0.3, -0.2, 1.1};    /* segment start, off the origin */

static cdpr_vec3_t v3_comb(cdpr_vec3_t base, double a, const double *u, double b, const double *w)
{
    return cdpr_v3(base.x + a * u[0] + b * w[0], base.y + a * u[1] + b * w[1],
                   base.z + a * u[2] + b * w[2]);
}

static cdpr_vec3_t zero3(void)
{
    return cdpr_v3(0.0, 0.0, 0.0);
}

/* Parameters with drag switched off (rho_air = 0) to isolate the tension. */
static cdpr_cable_params_t params_tension_only(void)
{
    cdpr_cable_params_t p;
    cdpr_cable_params_default(&p);
    p.ea_N = 1000.0;
    p.damping_Ns = 10.0;
    p.rho_air_kg_per_m3 = 0.0;
    return p;
}

/* Parameters for the drag cases: k = 1/2 rho_a d0 Cd = 0.5 * 1.2 * 0.01 * 1.1 = 0.0066. */
static cdpr_cable_params_t params_drag(void)
{
    cdpr_cable_params_t p;
    cdpr_cable_params_default(&p);
    p.ea_N = 1000.0;
    p.damping_Ns = 0.0;
    p.rho_air_kg_per_m3 = 1.2;
    p.d0_m = 0.01;
    p.cd = 1.1;
    p.cm = 0.04;
    return p;
}

#define ASSERT_REL(rel, expected, actual)                                                          \
    TEST_ASSERT_DOUBLE_WITHIN((rel)*fabs(expected), (expected), (actual))

/* |a - e| <= tol per component (caller line reported). */
#define ASSERT_V3(tol, e, a) assert_v3((tol), (e), (a), __LINE__)

static void assert_v3(double tol, cdpr_vec3_t e, cdpr_vec3_t a, int line)
{
    UNITY_TEST_ASSERT_DOUBLE_WITHIN(tol, e.x, a.x, (UNITY_LINE_TYPE)line, "x");
    UNITY_TEST_ASSERT_DOUBLE_WITHIN(tol, e.y, a.y, (UNITY_LINE_TYPE)line, "y");
    UNITY_TEST_ASSERT_DOUBLE_WITHIN(tol, e.z, a.z, (UNITY_LINE_TYPE)line, "z");
}

static cdpr_vec3_t vec_of(const double *u, double s)
{
    return cdpr_v3(s * u[0], s * u[1], s * u[2]);
}

static double norm3(cdpr_vec3_t a)
{
    return sqrt(a.x * a.x + a.y * a.y + a.z * a.z);
}

/* ---------------------------------------------------------------- tension */

static void test_taut_segment_tension_and_direction(void)
{
    const cdpr_cable_params_t p = params_tension_only();
    /* chord 2.5 t, lu = 2: eps = 2.5/2 - 1 = 0.25, T = EA eps = 1000 * 0.25 = 250 N. */
    const cdpr_vec3_t rb = v3_comb(RA, 2.5, T_HAT, 0.0, N_HAT);
    cdpr_segment_t s;
    cdpr_cable_segment_eval(&p, RA, zero3(), rb, zero3(), 2.0, 0.0, zero3(), &s);
    ASSERT_REL(REL, 2.5, s.length_m);
    ASSERT_REL(REL, 0.25, s.strain);
    ASSERT_REL(REL, 250.0, s.tension_N);
    ASSERT_V3(REL, vec_of(T_HAT, 1.0), s.tangent);
    /* No velocity, no wind: no drag at all (exact zero). */
    ASSERT_V3(0.0, zero3(), s.drag_N);

    /* A second stiffness/length: EA = 3e5, lu = 2.4, l = 2.5: T = 3e5 (2.5/2.4 - 1) = 12500. */
    cdpr_cable_params_t p2 = p;
    p2.ea_N = 3e5;
    cdpr_cable_segment_eval(&p2, RA, zero3(), rb, zero3(), 2.4, 0.0, zero3(), &s);
    ASSERT_REL(REL, 3e5 * (2.5 / 2.4 - 1.0), s.tension_N);
}

static void test_damping_sign(void)
{
    const cdpr_cable_params_t p = params_tension_only();
    const cdpr_vec3_t rb = v3_comb(RA, 2.5, T_HAT, 0.0, N_HAT);
    const cdpr_vec3_t va = cdpr_v3(0.2, -0.1, 0.05); /* common motion: no strain rate */
    cdpr_segment_t s;

    /* Stretching at 0.5 m/s along t (+0.7 m/s along n, which must not matter):
     * eps_dot = t.(vb - va)/lu = 0.5/2 = 0.25 1/s, T = 250 + c eps_dot = 250 + 10*0.25 = 252.5 */
    cdpr_vec3_t vb = v3_comb(va, 0.5, T_HAT, 0.7, N_HAT);
    cdpr_cable_segment_eval(&p, RA, va, rb, vb, 2.0, 0.0, zero3(), &s);
    ASSERT_REL(REL, 252.5, s.tension_N);

    /* Shortening at 0.5 m/s: T = 250 - 2.5 = 247.5 (less tension). */
    vb = v3_comb(va, -0.5, T_HAT, 0.7, N_HAT);
    cdpr_cable_segment_eval(&p, RA, va, rb, vb, 2.0, 0.0, zero3(), &s);
    ASSERT_REL(REL, 247.5, s.tension_N);

    /* Moving node a instead of node b flips the sign of the relative velocity:
     * va = -0.5 t relative to vb = 0 stretches the segment: 252.5. */
    cdpr_cable_segment_eval(&p, RA, vec_of(T_HAT, -0.5), rb, zero3(), 2.0, 0.0, zero3(), &s);
    ASSERT_REL(REL, 252.5, s.tension_N);

    /* Shortening at 60 m/s: EA eps + c eps_dot = 250 + 10 * (-60/2) = -50 < 0 -> clipped to
     * exactly 0 (a cable never pushes), while the tangent still reports the chord. */
    vb = v3_comb(va, -60.0, T_HAT, 0.0, N_HAT);
    cdpr_cable_segment_eval(&p, RA, va, rb, vb, 2.0, 0.0, zero3(), &s);
    TEST_ASSERT_DOUBLE_WITHIN(0.0, 0.0, s.tension_N);
    ASSERT_V3(REL, vec_of(T_HAT, 1.0), s.tangent);
    /* Just above the clip: 250 + 10 * (-49/2) = 5 N. */
    vb = v3_comb(va, -49.0, T_HAT, 0.0, N_HAT);
    cdpr_cable_segment_eval(&p, RA, va, rb, vb, 2.0, 0.0, zero3(), &s);
    /* 5 N is a difference of 250 and 245: absolute error ~ u * 250, so 1e-12 * 250. */
    TEST_ASSERT_DOUBLE_WITHIN(REL * 250.0, 5.0, s.tension_N);
}

/* The passive law T = max(0, EA max(eps, 0) + c eps_dot) in slack: at rest or shortening
 * exactly 0 (never pushes); being stretched, the damper alone, c eps_dot. */
static void test_slack_segment_carries_only_its_stretching_damper(void)
{
    const cdpr_cable_params_t p = params_tension_only();
    cdpr_segment_t s;
    /* l = 1.5 < lu = 2 (eps = -0.25) at rest: exactly 0 N. */
    const cdpr_vec3_t rb = v3_comb(RA, 1.5, T_HAT, 0.0, N_HAT);
    cdpr_cable_segment_eval(&p, RA, zero3(), rb, zero3(), 2.0, 0.0, zero3(), &s);
    TEST_ASSERT_DOUBLE_WITHIN(0.0, 0.0, s.tension_N);
    ASSERT_REL(REL, -0.25, s.strain);
    /* Tangent of a slack segment is still the chord direction. */
    ASSERT_V3(REL, vec_of(T_HAT, 1.0), s.tangent);
    /* Pulled apart at 1000 m/s: eps_dot = 1000 / 2 = 500 1/s, T = c eps_dot = 5000 N. */
    cdpr_cable_segment_eval(&p, RA, zero3(), rb, vec_of(T_HAT, 1000.0), 2.0, 0.0, zero3(), &s);
    ASSERT_REL(REL, 5000.0, s.tension_N);
    /* Pushed together at 1000 m/s: the damper would push, the law gives exactly 0 N. */
    cdpr_cable_segment_eval(&p, RA, zero3(), rb, vec_of(T_HAT, -1000.0), 2.0, 0.0, zero3(), &s);
    TEST_ASSERT_DOUBLE_WITHIN(0.0, 0.0, s.tension_N);
    /* Reeling in (u < 0) stretches too: eps_dot = -(l/lu^2) u = (1.5/4) 1000, T = 3750 N. */
    cdpr_cable_segment_eval(&p, RA, zero3(), rb, zero3(), 2.0, -1000.0, zero3(), &s);
    ASSERT_REL(REL, 3750.0, s.tension_N);
}

/* The MoorDyn-compatible option: the same damper, and the total may push. */
static void test_moordyn_law_lets_the_damper_push(void)
{
    cdpr_cable_params_t p = params_tension_only();
    p.slack_law = CDPR_SLACK_MOORDYN;
    cdpr_segment_t s;
    const cdpr_vec3_t rb = v3_comb(RA, 1.5, T_HAT, 0.0, N_HAT);
    cdpr_cable_segment_eval(&p, RA, zero3(), rb, vec_of(T_HAT, -1000.0), 2.0, 0.0, zero3(), &s);
    ASSERT_REL(REL, -5000.0, s.tension_N);
    /* Taut (eps = 0.25) and shortening at 100 m/s: 250 + 10 (-100 / 2) = -250 N. */
    const cdpr_vec3_t rt = v3_comb(RA, 2.5, T_HAT, 0.0, N_HAT);
    cdpr_cable_segment_eval(&p, RA, zero3(), rt, vec_of(T_HAT, -100.0), 2.0, 0.0, zero3(), &s);
    ASSERT_REL(REL, -250.0, s.tension_N);
}

/* No jump at the snap: at eps = 0 the tension is c eps_dot from both sides, and near it the
 * law changes by at most EA |d eps| + c |d eps_dot| (Lipschitz). Axis-aligned chords from the
 * origin give l = lu exactly (correctly rounded square and square root). */
static void test_snap_is_continuous(void)
{
    const cdpr_cable_params_t p = params_tension_only();
    const double lus[] = {0.1, 2.0, 3.0, 7.3, 1.0 / 3.0};
    for (size_t i = 0; i < sizeof lus / sizeof lus[0]; ++i) {
        const double lu = lus[i];
        cdpr_segment_t s;
        cdpr_cable_segment_eval(&p, zero3(), zero3(), cdpr_v3(0.0, 0.0, lu),
                                cdpr_v3(0.0, 0.0, 50.0), lu, 0.0, zero3(), &s);
        TEST_ASSERT_DOUBLE_WITHIN(0.0, (cdpr_real_t)lu, s.length_m);
        ASSERT_REL(TOL(1e-14, 6e-6), 10.0 * 50.0 / lu, s.tension_N);
        /* 1e-6 shorter and longer (slack and taut by 1e-6 strain): within EA * 1e-6 plus the
         * change of eps_dot's l / lu factor (none here: the far node moves along the chord). */
        for (int side = -1; side <= 1; side += 2) {
            cdpr_segment_t n;
            const double l = lu * (1.0 + 1e-6 * side);
            cdpr_cable_segment_eval(&p, zero3(), zero3(), cdpr_v3(0.0, 0.0, l),
                                    cdpr_v3(0.0, 0.0, 50.0), lu, 0.0, zero3(), &n);
            TEST_ASSERT_DOUBLE_WITHIN(1000.0 * 1e-6 * 1.001 + TOL(1e-9, 1e-3), s.tension_N,
                                      n.tension_N);
        }
    }
}

/* Passive: the damper part D = T - EA max(eps, 0) never feeds energy in (D eps_dot >= 0) and
 * T never pushes, over a grid of strains and strain rates around the snap. */
static void test_damper_part_is_passive_and_never_pushes(void)
{
    const cdpr_cable_params_t p = params_tension_only();
    for (int a = -20; a <= 20; ++a) {
        for (int b = -20; b <= 20; ++b) {
            const double l = 2.0 * (1.0 + 0.01 * a);
            const double v = 0.5 * b;
            cdpr_segment_t s;
            cdpr_cable_segment_eval(&p, zero3(), zero3(), cdpr_v3(0.0, 0.0, l),
                                    cdpr_v3(0.0, 0.0, v), 2.0, 0.0, zero3(), &s);
            const double eps = (double)s.strain;
            const double eps_dot = v / 2.0;
            const double damper = (double)s.tension_N - 1000.0 * (eps > 0.0 ? eps : 0.0);
            TEST_ASSERT_TRUE(s.tension_N >= 0.0);
            TEST_ASSERT_TRUE(damper * eps_dot >= -TOL(1e-9, 1e-3));
        }
    }
}

static void test_payout_rate_reduces_tension(void)
{
    const cdpr_cable_params_t p = params_tension_only();
    const cdpr_vec3_t rb = v3_comb(RA, 2.5, T_HAT, 0.0, N_HAT);
    cdpr_segment_t s;
    /* Nodes at rest, paying out u = 0.4 m/s: eps_dot = -(l/lu^2) u = -(2.5/4) 0.4 = -0.25,
     * T = 250 - c * 0.25 = 250 - c l u / lu^2 = 250 - 2.5 = 247.5 N. */
    cdpr_cable_segment_eval(&p, RA, zero3(), rb, zero3(), 2.0, 0.4, zero3(), &s);
    ASSERT_REL(REL, 250.0 - 10.0 * 2.5 * 0.4 / (2.0 * 2.0), s.tension_N);
    ASSERT_REL(REL, 247.5, s.tension_N);
    /* Reeling in (u = -0.4) adds the same amount: 252.5 N. */
    cdpr_cable_segment_eval(&p, RA, zero3(), rb, zero3(), 2.0, -0.4, zero3(), &s);
    ASSERT_REL(REL, 252.5, s.tension_N);
    /* Payout exactly compensated by the nodes separating at (l/lu) u = 0.5 m/s: 250 N. */
    cdpr_cable_segment_eval(&p, RA, zero3(), rb, vec_of(T_HAT, 0.5), 2.0, 0.4, zero3(), &s);
    ASSERT_REL(REL, 250.0, s.tension_N);
}

/* ---------------------------------------------------------------- drag */

/* k = 1/2 rho_a d0 Cd for params_drag(), written out. */
#define K_DRAG (0.5 * 1.2 * 0.01 * 1.1)
#define CM     0.04

static void test_drag_purely_normal(void)
{
    const cdpr_cable_params_t p = params_drag();
    /* l = lu = 2.5 (eps = 0, no tension), mean node velocity 3 n (the two nodes differ by
     * +-w, which cancels in the mean): mu = 3n, |mu_n| mu_n = 9 n,
     * F = -k sqrt(l lu) 9 n = -0.0066 * 2.5 * 9 n = -0.1485 n. */
    const cdpr_vec3_t rb = v3_comb(RA, 2.5, T_HAT, 0.0, N_HAT);
    const double w[3] = {0.1, 0.2, -0.3};
    const cdpr_vec3_t va = v3_comb(zero3(), 3.0, N_HAT, -1.0, w);
    const cdpr_vec3_t vb = v3_comb(zero3(), 3.0, N_HAT, 1.0, w);
    cdpr_segment_t s;
    cdpr_cable_segment_eval(&p, RA, va, rb, vb, 2.5, 0.0, zero3(), &s);
    const double mag = K_DRAG * sqrt(2.5 * 2.5) * 3.0 * 3.0;
    ASSERT_V3(REL * mag, vec_of(N_HAT, -mag), s.drag_N);
    TEST_ASSERT_DOUBLE_WITHIN(REL * mag, 0.1485, norm3(s.drag_N));
}

static void test_drag_purely_tangential(void)
{
    const cdpr_cable_params_t p = params_drag();
    /* mu = 3 t: F = -k Cm sqrt(l lu) |mu_t| mu_t = -0.0066 * 0.04 * 2.5 * 9 t. */
    const cdpr_vec3_t rb = v3_comb(RA, 2.5, T_HAT, 0.0, N_HAT);
    const cdpr_vec3_t v = vec_of(T_HAT, 3.0);
    cdpr_segment_t s;
    cdpr_cable_segment_eval(&p, RA, v, rb, v, 2.5, 0.0, zero3(), &s);
    const double mag = K_DRAG * CM * 2.5 * 9.0;
    ASSERT_V3(REL * mag, vec_of(T_HAT, -mag), s.drag_N);
    /* Moving the other way: the drag flips (|mu_t| mu_t is odd), still opposing mu. */
    cdpr_cable_segment_eval(&p, RA, vec_of(T_HAT, -3.0), rb, vec_of(T_HAT, -3.0), 2.5, 0.0, zero3(),
                            &s);
    ASSERT_V3(REL * mag, vec_of(T_HAT, mag), s.drag_N);
}

static void test_drag_at_45_degrees_splits(void)
{
    const cdpr_cable_params_t p = params_drag();
    /* mu = 3 (t + n)/sqrt(2): mu_t = mu_n magnitude 3/sqrt(2), |mu|mu = 4.5 per direction:
     * F = -k sqrt(l lu) (Cd-part 4.5 n + Cm 4.5 t) = -0.0066 * 2.5 * 4.5 (n + 0.04 t). */
    const cdpr_vec3_t rb = v3_comb(RA, 2.5, T_HAT, 0.0, N_HAT);
    const double c = 3.0 / sqrt(2.0);
    const cdpr_vec3_t v = v3_comb(zero3(), c, T_HAT, c, N_HAT);
    cdpr_segment_t s;
    cdpr_cable_segment_eval(&p, RA, v, rb, v, 2.5, 0.0, zero3(), &s);
    const double a = K_DRAG * 2.5 * 4.5;
    const cdpr_vec3_t expected = v3_comb(zero3(), -a * CM, T_HAT, -a, N_HAT);
    ASSERT_V3(REL * a, expected, s.drag_N);
    /* Components along t and n separately (same numbers, projected). */
    const double ft = s.drag_N.x * T_HAT[0] + s.drag_N.y * T_HAT[1] + s.drag_N.z * T_HAT[2];
    const double fn = s.drag_N.x * N_HAT[0] + s.drag_N.y * N_HAT[1] + s.drag_N.z * N_HAT[2];
    TEST_ASSERT_DOUBLE_WITHIN(REL * a, -a * CM, ft);
    TEST_ASSERT_DOUBLE_WITHIN(REL * a, -a, fn);
}

static void test_drag_from_wind_only(void)
{
    const cdpr_cable_params_t p = params_drag();
    /* Nodes at rest, wind J = 4 n (normal): mu = -J, F = -k sqrt(l lu) |mu| mu
     * = +k * 2.5 * 4 * J = +0.0066 * 2.5 * 16 n: along +J. */
    const cdpr_vec3_t rb = v3_comb(RA, 2.5, T_HAT, 0.0, N_HAT);
    const cdpr_vec3_t wind = vec_of(N_HAT, 4.0);
    cdpr_segment_t s;
    cdpr_cable_segment_eval(&p, RA, zero3(), rb, zero3(), 2.5, 0.0, wind, &s);
    const double mag = K_DRAG * 2.5 * 16.0;
    ASSERT_V3(REL * mag, vec_of(N_HAT, mag), s.drag_N);
    /* Nodes moving with the wind: no relative velocity, no drag (exact). */
    cdpr_cable_segment_eval(&p, RA, wind, rb, wind, 2.5, 0.0, wind, &s);
    ASSERT_V3(0.0, zero3(), s.drag_N);
    /* General wind J = 2 t - 4 n: mu = -2 t + 4 n, |mu_n| mu_n = 16 n, |mu_t| mu_t = -4 t:
     * F = -k 2.5 (16 n + Cm (-4) t) = -k 2.5 * 16 n + k 2.5 * 4 Cm t. */
    const cdpr_vec3_t wind2 = v3_comb(zero3(), 2.0, T_HAT, -4.0, N_HAT);
    cdpr_segment_t s2;
    cdpr_cable_segment_eval(&p, RA, zero3(), rb, zero3(), 2.5, 0.0, wind2, &s2);
    const cdpr_vec3_t expected =
        v3_comb(zero3(), K_DRAG * 2.5 * 4.0 * CM, T_HAT, -K_DRAG * 2.5 * 16.0, N_HAT);
    ASSERT_V3(REL * mag, expected, s2.drag_N);
}

static void test_drag_stretched_area_factor(void)
{
    const cdpr_cable_params_t p = params_drag();
    /* Same lu = 2.5 and normal velocity 3 n; the stretched segment has l = 1.21 * 2.5, so
     * sqrt(1 + eps) = sqrt(1.21) = 1.1: drag x 1.1 (projected area of the stretched cable). */
    const cdpr_vec3_t v = vec_of(N_HAT, 3.0);
    cdpr_segment_t s0;
    cdpr_segment_t s1;
    cdpr_cable_segment_eval(&p, RA, v, v3_comb(RA, 2.5, T_HAT, 0.0, N_HAT), v, 2.5, 0.0, zero3(),
                            &s0);
    cdpr_cable_segment_eval(&p, RA, v, v3_comb(RA, 2.5 * 1.21, T_HAT, 0.0, N_HAT), v, 2.5, 0.0,
                            zero3(), &s1);
    const double mag0 = K_DRAG * 2.5 * 9.0;
    ASSERT_V3(REL * mag0, vec_of(N_HAT, -mag0), s0.drag_N);
    ASSERT_V3(REL * mag0, vec_of(N_HAT, -1.1 * mag0), s1.drag_N);
    ASSERT_REL(REL, 1.1, norm3(s1.drag_N) / norm3(s0.drag_N));
}

/* ---------------------------------------------------------------- RHS of a whole cable */

/* Independent reference of docs/model.md §2 for one segment, written from the formulas (plain
 * arrays, different evaluation order from the core). */
typedef struct {
    double T;    /* tension [N] */
    double t[3]; /* unit tangent */
    double F[3]; /* drag on the segment [N] */
} ref_seg_t;

static ref_seg_t ref_segment(const cdpr_cable_params_t *p, const double *ra, const double *va,
                             const double *rb, const double *vb, double lu, double lu_rate,
                             const double *wind)
{
    ref_seg_t s;
    double d[3], l2 = 0.0;
    for (int i = 0; i < 3; ++i) {
        d[i] = rb[i] - ra[i];
        l2 += d[i] * d[i];
    }
    const double l = sqrt(l2);
    for (int i = 0; i < 3; ++i) {
        s.t[i] = d[i] / l;
    }
    const double eps = l / lu - 1.0;
    double rel = 0.0;
    for (int i = 0; i < 3; ++i) {
        rel += s.t[i] * (vb[i] - va[i]);
    }
    const double eps_dot = rel / lu - (l / (lu * lu)) * lu_rate;
    /* docs/model.md, slack law: T = max(0, EA max(eps, 0) + c eps_dot) (passive), or without
     * the floor (MoorDyn). */
    const double T = p->ea_N * ((eps > 0.0) ? eps : 0.0) + p->damping_Ns * eps_dot;
    s.T = (p->slack_law == CDPR_SLACK_MOORDYN || T > 0.0) ? T : 0.0;
    double mu[3], mt = 0.0;
    for (int i = 0; i < 3; ++i) {
        mu[i] = 0.5 * (va[i] + vb[i]) - wind[i];
        mt += mu[i] * s.t[i];
    }
    double mun[3], mn2 = 0.0;
    for (int i = 0; i < 3; ++i) {
        mun[i] = mu[i] - mt * s.t[i];
        mn2 += mun[i] * mun[i];
    }
    const double pre = -0.5 * p->rho_air_kg_per_m3 * p->d0_m * sqrt(l / lu) * lu;
    for (int i = 0; i < 3; ++i) {
        s.F[i] = pre * (p->cd * sqrt(mn2) * mun[i] + p->cm * p->cd * fabs(mt) * mt * s.t[i]);
    }
    return s;
}

static void v3_to(cdpr_vec3_t a, double *o)
{
    o[0] = a.x;
    o[1] = a.y;
    o[2] = a.z;
}

static cdpr_cable_params_t params_rhs(void)
{
    cdpr_cable_params_t p;
    cdpr_cable_params_default(&p);
    p.d0_m = 0.01;
    p.rho_kg_per_m = 0.5;
    p.ea_N = 2000.0;
    p.damping_Ns = 15.0;
    p.cd = 1.1;
    p.cm = 0.04;
    p.rho_air_kg_per_m3 = 1.2;
    return p;
}

/* 3 segments, lu = {1.0, 1.5, y[0]}; lu_m[2] keeps its init value 1.5 on purpose: cable.h
 * makes the state y[0] authoritative for the pulley-side length. */
static void check_three_segment_rhs(double lu_last, int last_slack)
{
    const cdpr_cable_params_t p = params_rhs();
    cdpr_cable_t c;
    cdpr_diag_t diag;
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_cable_init(&c, &p, 3, 4.5, &diag));
    c.lu_m[0] = 1.0;
    c.lu_m[1] = 1.5;
    cdpr_cable_refresh(&c);
    TEST_ASSERT_EQUAL_INT(13, cdpr_cable_state_dim(&c)); /* 1 + 6 (3 - 1) */

    const double r[4][3] = {{0.1, 0.2, 0.0}, {1.0, 0.5, 1.1}, {2.0, 0.7, 2.6}, {3.0, 1.0, 4.0}};
    const double v[4][3] = {{0.3, -0.1, 0.2}, {0.05, 0.1, -0.2}, {-0.1, 0.2, 0.1}, {0, 0, 0}};
    const double wind[3] = {1.5, -0.5, 0.2};
    const double u = 0.3, g = 9.80665;
    const double lu[3] = {1.0, 1.5, lu_last};

    cdpr_real_t y[13];
    y[0] = lu_last;
    for (int i = 0; i < 3; ++i) {
        y[1 + i] = r[1][i];
        y[4 + i] = r[2][i];
        y[7 + i] = v[1][i];
        y[10 + i] = v[2][i];
    }
    cdpr_cable_bc_t bc;
    bc.r0_m = cdpr_v3(r[0][0], r[0][1], r[0][2]);
    bc.v0_m_per_s = cdpr_v3(v[0][0], v[0][1], v[0][2]);
    bc.rn_m = cdpr_v3(r[3][0], r[3][1], r[3][2]);
    bc.wind_m_per_s = cdpr_v3(wind[0], wind[1], wind[2]);
    bc.payout_m_per_s = u;
    bc.g_m_per_s2 = g;

    cdpr_real_t dydt[13];
    memset(dydt, 0xFF, sizeof dydt); /* NaN pattern: every entry must be written */
    cdpr_cable_out_t out;
    cdpr_cable_rhs(&c, y, &bc, dydt, &out);

    /* Reference: segments k = 0..2; only the pulley-side one changes length (rate u). */
    ref_seg_t s[3];
    for (int k = 0; k < 3; ++k) {
        s[k] = ref_segment(&p, r[k], v[k], r[k + 1], v[k + 1], lu[k], (k == 2) ? u : 0.0, wind);
    }
    /* The geometry really is what the caller claims (taut inner segments, pulley side as
     * requested), so the case exercises what it says. */
    TEST_ASSERT_TRUE(s[0].T > 0.0);
    TEST_ASSERT_TRUE(s[1].T > 0.0);
    TEST_ASSERT_TRUE(last_slack ? !(s[2].T > 0.0) : (s[2].T > 0.0));
    /* d lu[n-1]/dt = payout and d pos/dt = vel: copies, exact. */
    TEST_ASSERT_DOUBLE_WITHIN(0.0, (cdpr_real_t)u, dydt[0]);
    for (int i = 0; i < 6; ++i) {
        TEST_ASSERT_DOUBLE_WITHIN(0.0, y[7 + i], dydt[1 + i]);
    }
    /* Free nodes i = 1, 2: m_i = rho (lu_{i-1} + lu_i)/2,
     * a_i = (T_i t_i - T_{i-1} t_{i-1} + (F_{i-1} + F_i)/2) / m_i - g z.
     * Tolerance: every term is accurate to ~1e-15 relative; the sum may cancel, so the bound
     * is REL times the sum of the magnitudes of the terms (plus g). */
    for (int i = 1; i <= 2; ++i) {
        const double m = p.rho_kg_per_m * (lu[i - 1] + lu[i]) / 2.0;
        for (int a = 0; a < 3; ++a) {
            const double f =
                s[i].T * s[i].t[a] - s[i - 1].T * s[i - 1].t[a] + (s[i - 1].F[a] + s[i].F[a]) / 2.0;
            const double expected = f / m - ((a == 2) ? g : 0.0);
            const double scale =
                (s[i].T + s[i - 1].T + fabs(s[i - 1].F[a]) + fabs(s[i].F[a])) / m + g;
            TEST_ASSERT_DOUBLE_WITHIN(REL * scale, expected, dydt[7 + 3 * (i - 1) + a]);
        }
    }
    /* End forces: F_cabin = T_0 t_0 + F_0/2, T_cabin = T_0, T_winch = T_2. */
    double fc[3];
    v3_to(out.force_on_cabin_N, fc);
    for (int a = 0; a < 3; ++a) {
        const double expected = s[0].T * s[0].t[a] + s[0].F[a] / 2.0;
        TEST_ASSERT_DOUBLE_WITHIN(REL * (s[0].T + fabs(s[0].F[a])), expected, fc[a]);
    }
    TEST_ASSERT_DOUBLE_WITHIN(REL * s[0].T, s[0].T, out.tension_cabin_N);
    TEST_ASSERT_DOUBLE_WITHIN(REL * (s[2].T + 1.0), s[2].T, out.tension_winch_N);

    /* cdpr_cable_end_forces: same values as the RHS's out (same formulas; only last-bit
     * differences could be excused, 1e-14 relative; float 6e-6, test_real.h). */
    cdpr_cable_out_t ef;
    cdpr_cable_end_forces(&c, y, &bc, &ef);
    const double fs = norm3(out.force_on_cabin_N);
    ASSERT_V3(TOL(1e-14, 6e-6) * fs, out.force_on_cabin_N, ef.force_on_cabin_N);
    TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-14, 6e-6) * out.tension_cabin_N, out.tension_cabin_N,
                              ef.tension_cabin_N);
    TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-14, 6e-6) * out.tension_winch_N, out.tension_winch_N,
                              ef.tension_winch_N);

    /* The RHS without `out` writes the same derivatives (bit-identical: same code path). */
    cdpr_real_t dydt2[13];
    cdpr_cable_rhs(&c, y, &bc, dydt2, NULL);
    TEST_ASSERT_EQUAL_MEMORY(dydt, dydt2, sizeof dydt);
}

static void test_rhs_three_segments_all_taut(void)
{
    /* Pulley-side segment: |rn - r2| = sqrt(1 + 0.09 + 1.96) = 1.746 > 1.6: taut. Segments 0
     * and 1 have l = 1.453 > 1.0 and 1.814 > 1.5: all three pull. */
    check_three_segment_rhs(1.6, 0);
}

static void test_rhs_three_segments_slack_pulley_side(void)
{
    /* lu_last = 2.0 > 1.746: the pulley-side segment is slack, T_2 = 0 = winch tension. */
    check_three_segment_rhs(2.0, 1);
}

static void test_rhs_single_segment(void)
{
    /* n = 1: the state block is just lu; the single segment joins cabin and pulley.
     * Cabin node at rest, pulley 2.5 t away, lu = 2, payout 0.4: T = 247.5 (payout case
     * above) at both ends, force on cabin = T t + F/2 with F = 0 (no velocity, no wind). */
    const cdpr_cable_params_t p = params_tension_only();
    cdpr_cable_t c;
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_cable_init(&c, &p, 1, 2.0, NULL));
    TEST_ASSERT_EQUAL_INT(1, cdpr_cable_state_dim(&c));
    cdpr_real_t y[1] = {2.0};
    cdpr_real_t dydt[1];
    cdpr_cable_bc_t bc;
    bc.r0_m = RA;
    bc.v0_m_per_s = zero3();
    bc.rn_m = v3_comb(RA, 2.5, T_HAT, 0.0, N_HAT);
    bc.wind_m_per_s = zero3();
    bc.payout_m_per_s = 0.4;
    bc.g_m_per_s2 = 9.80665;
    cdpr_cable_out_t out;
    cdpr_cable_rhs(&c, y, &bc, dydt, &out);
    TEST_ASSERT_DOUBLE_WITHIN(0.0, CDPR_R(0.4), dydt[0]);
    ASSERT_REL(REL, 247.5, out.tension_cabin_N);
    ASSERT_REL(REL, 247.5, out.tension_winch_N);
    ASSERT_V3(REL * 247.5, vec_of(T_HAT, 247.5), out.force_on_cabin_N);
    cdpr_cable_out_t ef;
    cdpr_cable_end_forces(&c, y, &bc, &ef);
    ASSERT_V3(TOL(1e-14, 6e-6) * 247.5, out.force_on_cabin_N, ef.force_on_cabin_N);
    TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-14, 6e-6) * 247.5, out.tension_winch_N, ef.tension_winch_N);
}

static void check_hanging_chain(int n)
{
    /* A vertical cable of n segments: cabin node 0 at the bottom pulling down with T0 = 50 N,
     * pulley at the top. Equilibrium of free node i (tangents all +z): T_i - T_{i-1} = m_i g,
     * so T_i = T0 + g (m_1 + ... + m_i): each segment carries the cabin pull plus the weight
     * of the nodes below it. Stretched lengths l_k = lu_k (1 + T_k/EA) place the nodes; then
     * every node acceleration must vanish to rounding. Unequal lu_k = 0.5 .. 1.1 m. */
    static double lu[CDPR_MAX_SEGMENTS], T[CDPR_MAX_SEGMENTS], z[CDPR_MAX_SEGMENTS + 1];
    static cdpr_real_t y[CDPR_CABLE_STATE_MAX], dydt[CDPR_CABLE_STATE_MAX];
    cdpr_cable_params_t p = params_rhs();
    p.ea_N = 1.0e4;
    cdpr_cable_t c;
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_cable_init(&c, &p, n, (double)n, NULL));
    double lu_min = INF_D, m_min = INF_D;
    for (int k = 0; k < n; ++k) {
        lu[k] = 0.5 + 0.1 * (double)(k % 7);
        c.lu_m[k] = lu[k];
        lu_min = (lu[k] < lu_min) ? lu[k] : lu_min;
    }
    cdpr_cable_refresh(&c);
    const double g = 9.80665, T0 = 50.0;
    const double px = 0.2, py = -0.3, z0 = 1.0;
    T[0] = T0;
    z[0] = z0;
    for (int k = 0; k < n; ++k) {
        if (k > 0) {
            const double m = p.rho_kg_per_m * (lu[k - 1] + lu[k]) / 2.0;
            m_min = (m < m_min) ? m : m_min;
            T[k] = T[k - 1] + m * g;
        }
        z[k + 1] = z[k] + lu[k] * (1.0 + T[k] / p.ea_N);
    }
    const int nf = n - 1;
    y[0] = lu[n - 1];
    for (int i = 1; i < n; ++i) {
        y[1 + 3 * (i - 1) + 0] = px;
        y[1 + 3 * (i - 1) + 1] = py;
        y[1 + 3 * (i - 1) + 2] = z[i];
        y[1 + 3 * nf + 3 * (i - 1) + 0] = 0.0;
        y[1 + 3 * nf + 3 * (i - 1) + 1] = 0.0;
        y[1 + 3 * nf + 3 * (i - 1) + 2] = 0.0;
    }
    cdpr_cable_bc_t bc;
    bc.r0_m = cdpr_v3(px, py, z0);
    bc.v0_m_per_s = zero3();
    bc.rn_m = cdpr_v3(px, py, z[n]);
    bc.wind_m_per_s = zero3();
    bc.payout_m_per_s = 0.0;
    bc.g_m_per_s2 = g;
    cdpr_cable_out_t out;
    cdpr_cable_rhs(&c, y, &bc, dydt, &out);
    /* Rounding: each stored height z_{k+1} = fl(z_k + l_k) is one rounding (<= ulp(z_max)/2)
     * away from the intended one, and the core's difference and sqrt add ~2 ulp(l): a segment
     * length is off by dl <= ulp(z_max) + 4 ulp(1.1 m), its tension by EA dl / lu_min, and a
     * node's acceleration by 2 EA dl / (lu_min m_min). Tolerance: 4x that bound (~1e-10 m/s^2
     * for n = 8, ~1e-9 for n = 64), while one missing node weight would leave g = 9.8.
     * ulp(1) is 2.2e-16 in double and 1.2e-7 in float (float bound at n = 64: ~4 m/s^2 < g). */
    const double ulp1 = TOL(2.3e-16, 1.2e-7);
    const double dl = z[n] * ulp1 + 4.0 * ulp1 * 1.1;
    const double tol_t = 4.0 * p.ea_N * dl / lu_min;
    const double tol_a = 2.0 * tol_t / m_min;
    for (int i = 0; i < 3 * nf; ++i) {
        TEST_ASSERT_DOUBLE_WITHIN(0.0, 0.0, dydt[1 + i]); /* at rest: exact copies of 0 */
        TEST_ASSERT_DOUBLE_WITHIN(tol_a, 0.0, dydt[1 + 3 * nf + i]);
    }
    /* End tensions: T_cabin = T0, T_winch = T_{n-1}; the cabin force is T0 straight up. */
    TEST_ASSERT_DOUBLE_WITHIN(tol_t, T0, out.tension_cabin_N);
    TEST_ASSERT_DOUBLE_WITHIN(tol_t, T[n - 1], out.tension_winch_N);
    ASSERT_V3(tol_t, cdpr_v3(0.0, 0.0, T0), out.force_on_cabin_N);
}

static void test_hanging_vertical_chain_is_static(void)
{
    /* Node-count sweep (STYLE.md §7): 2, 6, 8 and the capacity. */
    check_hanging_chain(2);
    check_hanging_chain(6);
    check_hanging_chain(8);
    check_hanging_chain(CDPR_MAX_SEGMENTS);
}

/* General n: nodes on a wiggly line between r0 and rn, unequal lu (some segments slack, most
 * taut), moving nodes, wind and payout; every derivative against the reference model. */
static void check_rhs_general(int n)
{
    static cdpr_real_t y[CDPR_CABLE_STATE_MAX], dydt[CDPR_CABLE_STATE_MAX];
    static double r[CDPR_MAX_SEGMENTS + 1][3], v[CDPR_MAX_SEGMENTS + 1][3], lu[CDPR_MAX_SEGMENTS];
    const cdpr_cable_params_t p = params_rhs();
    cdpr_cable_t c;
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_cable_init(&c, &p, n, 5.0, NULL));
    const double r0[3] = {0.1, 0.2, 0.0}, rn[3] = {3.0, 1.0, 4.0};
    const double wind[3] = {1.5, -0.5, 0.2};
    const double u = -0.15, g = 9.80665;
    const double chord = sqrt(2.9 * 2.9 + 0.8 * 0.8 + 4.0 * 4.0);
    for (int k = 0; k <= n; ++k) {
        const double f = (double)k / (double)n;
        const double wig = (k > 0 && k < n) ? 0.3 / (double)n : 0.0;
        for (int a = 0; a < 3; ++a) {
            r[k][a] = r0[a] + f * (rn[a] - r0[a]) + wig * sin(1.3 * (double)k + 2.0 * (double)a);
            v[k][a] = (k == n) ? 0.0 : 0.2 * cos(0.7 * (double)k + (double)a);
        }
    }
    for (int a = 0; a < 3; ++a) {
        r[n][a] = rn[a]; /* exact end points */
        r[0][a] = r0[a];
    }
    for (int k = 0; k < n; ++k) {
        lu[k] = 0.97 * chord / (double)n * (1.0 + 0.04 * sin(2.3 * (double)k));
        c.lu_m[k] = lu[k];
    }
    c.lu_m[n - 1] = 0.5 * lu[n - 1]; /* stale mirror: the state is authoritative */
    cdpr_cable_refresh(&c);
    const int nf = n - 1;
    y[0] = lu[n - 1];
    for (int i = 1; i < n; ++i) {
        for (int a = 0; a < 3; ++a) {
            y[1 + 3 * (i - 1) + a] = r[i][a];
            y[1 + 3 * nf + 3 * (i - 1) + a] = v[i][a];
        }
    }
    cdpr_cable_bc_t bc;
    bc.r0_m = cdpr_v3(r0[0], r0[1], r0[2]);
    bc.v0_m_per_s = cdpr_v3(v[0][0], v[0][1], v[0][2]);
    bc.rn_m = cdpr_v3(rn[0], rn[1], rn[2]);
    bc.wind_m_per_s = cdpr_v3(wind[0], wind[1], wind[2]);
    bc.payout_m_per_s = u;
    bc.g_m_per_s2 = g;
    cdpr_cable_out_t out;
    cdpr_cable_rhs(&c, y, &bc, dydt, &out);

    TEST_ASSERT_DOUBLE_WITHIN(0.0, (cdpr_real_t)u, dydt[0]);
    ref_seg_t prev = ref_segment(&p, r[0], v[0], r[1], v[1], lu[0], (n == 1) ? u : 0.0, wind);
    const ref_seg_t first = prev;
    int taut = 0;
    for (int i = 1; i < n; ++i) {
        const ref_seg_t cur =
            ref_segment(&p, r[i], v[i], r[i + 1], v[i + 1], lu[i], (i == n - 1) ? u : 0.0, wind);
        taut += (cur.T > 0.0) ? 1 : 0;
        const double m = p.rho_kg_per_m * (lu[i - 1] + lu[i]) / 2.0;
        for (int a = 0; a < 3; ++a) {
            const double f = cur.T * cur.t[a] - prev.T * prev.t[a] + (prev.F[a] + cur.F[a]) / 2.0;
            const double scale = (cur.T + prev.T + fabs(prev.F[a]) + fabs(cur.F[a])) / m + g;
            /* see check_three_segment_rhs for the tolerance */
            TEST_ASSERT_DOUBLE_WITHIN(REL * scale, f / m - ((a == 2) ? g : 0.0),
                                      dydt[1 + 3 * nf + 3 * (i - 1) + a]);
            TEST_ASSERT_DOUBLE_WITHIN(0.0, (cdpr_real_t)v[i][a], dydt[1 + 3 * (i - 1) + a]);
        }
        prev = cur;
    }
    TEST_ASSERT_TRUE(n == 1 || taut > 0); /* the sweep exercises tension, not only slack */
    TEST_ASSERT_DOUBLE_WITHIN(REL * (first.T + 1.0), first.T, out.tension_cabin_N);
    TEST_ASSERT_DOUBLE_WITHIN(REL * (prev.T + 1.0), prev.T, out.tension_winch_N);
    double fc[3];
    v3_to(out.force_on_cabin_N, fc);
    for (int a = 0; a < 3; ++a) {
        TEST_ASSERT_DOUBLE_WITHIN(REL * (first.T + fabs(first.F[a]) + 1.0),
                                  first.T * first.t[a] + first.F[a] / 2.0, fc[a]);
    }
    cdpr_cable_out_t ef;
    cdpr_cable_end_forces(&c, y, &bc, &ef);
    ASSERT_V3(TOL(1e-14, 6e-6) * (norm3(out.force_on_cabin_N) + 1.0), out.force_on_cabin_N,
              ef.force_on_cabin_N);
    TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-14, 6e-6) * (out.tension_winch_N + 1.0), out.tension_winch_N,
                              ef.tension_winch_N);
}

static void test_rhs_node_count_sweep(void)
{
    /* STYLE.md §7: node counts {1, 2, 8, CDPR_MAX_SEGMENTS} (1 and 2 take special paths). */
    check_rhs_general(1);
    check_rhs_general(2);
    check_rhs_general(8);
    check_rhs_general(CDPR_MAX_SEGMENTS);
}

/* ---------------------------------------------------------------- set-up helpers */

static void test_place_straight_and_total_length(void)
{
    /* Nodes at unstretched fractions s_i / L on the chord, at rest; y[0] = lu[n-1]. */
    const cdpr_cable_params_t p = params_rhs();
    cdpr_cable_t c;
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_cable_init(&c, &p, 4, 4.0, NULL));
    c.lu_m[0] = 0.5;
    c.lu_m[1] = 1.5;
    c.lu_m[2] = 1.0;
    c.lu_m[3] = 1.0;
    cdpr_cable_refresh(&c);
    const cdpr_vec3_t a = cdpr_v3(1.0, 2.0, 3.0);
    const cdpr_vec3_t b = cdpr_v3(5.0, -2.0, 7.0);
    cdpr_real_t y[1 + 6 * 3];
    cdpr_cable_place_straight(&c, a, b, y);
    TEST_ASSERT_DOUBLE_WITHIN(0.0, 1.0, y[0]);
    /* fractions 0.5/4, 2/4, 3/4; coordinates up to 7: 1e-15 absolute (a few roundings). */
    const double f[3] = {0.125, 0.5, 0.75};
    for (int i = 0; i < 3; ++i) {
        TEST_ASSERT_DOUBLE_WITHIN(1e-15 * 8.0, 1.0 + 4.0 * f[i], y[1 + 3 * i + 0]);
        TEST_ASSERT_DOUBLE_WITHIN(1e-15 * 8.0, 2.0 - 4.0 * f[i], y[1 + 3 * i + 1]);
        TEST_ASSERT_DOUBLE_WITHIN(1e-15 * 8.0, 3.0 + 4.0 * f[i], y[1 + 3 * i + 2]);
        TEST_ASSERT_DOUBLE_WITHIN(0.0, 0.0, y[10 + 3 * i + 0]);
        TEST_ASSERT_DOUBLE_WITHIN(0.0, 0.0, y[10 + 3 * i + 1]);
        TEST_ASSERT_DOUBLE_WITHIN(0.0, 0.0, y[10 + 3 * i + 2]);
    }
    /* Total = sum of lu[0..n-2] + y[0]: 0.5 + 1.5 + 1.0 + 2.25 = 5.25 (exact binaries). */
    y[0] = 2.25;
    TEST_ASSERT_DOUBLE_WITHIN(0.0, 5.25, cdpr_cable_total_length(&c, y));
}

static void test_init_rejects_bad_counts_and_leaves_cable_untouched(void)
{
    cdpr_cable_params_t p;
    cdpr_cable_params_default(&p);
    cdpr_cable_t c;
    memset(&c, 0xA5, sizeof c);
    cdpr_cable_t before;
    memcpy(&before, &c, sizeof c);
    cdpr_diag_t d;
    TEST_ASSERT_EQUAL_INT(CDPR_E_CAPACITY, cdpr_cable_init(&c, &p, 0, 1.0, &d));
    TEST_ASSERT_EQUAL_STRING("n_segments", d.field);
    TEST_ASSERT_EQUAL_INT(CDPR_E_CAPACITY, cdpr_cable_init(&c, &p, CDPR_MAX_SEGMENTS + 1, 1.0, &d));
    TEST_ASSERT_EQUAL_STRING("n_segments", d.field);
    TEST_ASSERT_EQUAL_INT(CDPR_E_NOT_POSITIVE, cdpr_cable_init(&c, &p, 3, 0.0, &d));
    TEST_ASSERT_EQUAL_STRING("length_m", d.field);
    TEST_ASSERT_EQUAL_INT(CDPR_E_NOT_FINITE, cdpr_cable_init(&c, &p, 3, NAN_R, &d));
    TEST_ASSERT_EQUAL_STRING("length_m", d.field);
    p.ea_N = -1.0;
    TEST_ASSERT_EQUAL_INT(CDPR_E_NOT_POSITIVE, cdpr_cable_init(&c, &p, 3, 1.0, &d));
    TEST_ASSERT_EQUAL_STRING("ea_N", d.field);
    TEST_ASSERT_EQUAL_MEMORY(&before, &c, sizeof c);
    /* Capacity itself is accepted. */
    cdpr_cable_params_default(&p);
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_cable_init(&c, &p, CDPR_MAX_SEGMENTS, 1.0, &d));
    TEST_ASSERT_EQUAL_INT(1 + 6 * (CDPR_MAX_SEGMENTS - 1), cdpr_cable_state_dim(&c));
}

static void test_rhs_makes_no_allocation(void)
{
    if (!cdpr_alloc_counting_available()) {
        TEST_IGNORE_MESSAGE(cdpr_alloc_unavailable_reason());
    }
    const cdpr_cable_params_t p = params_rhs();
    static cdpr_cable_t c;
    static cdpr_real_t y[CDPR_CABLE_STATE_MAX];
    static cdpr_real_t dydt[CDPR_CABLE_STATE_MAX];
    cdpr_alloc_reset();
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_cable_init(&c, &p, CDPR_MAX_SEGMENTS, 10.0, NULL));
    cdpr_cable_place_straight(&c, cdpr_v3(0.0, 0.0, 0.0), cdpr_v3(3.0, 4.0, 9.0), y);
    cdpr_cable_bc_t bc;
    bc.r0_m = cdpr_v3(0.0, 0.0, 0.0);
    bc.v0_m_per_s = cdpr_v3(0.1, 0.0, 0.0);
    bc.rn_m = cdpr_v3(3.0, 4.0, 9.0);
    bc.wind_m_per_s = cdpr_v3(2.0, 0.0, 0.0);
    bc.payout_m_per_s = 0.1;
    bc.g_m_per_s2 = 9.80665;
    cdpr_cable_out_t out;
    cdpr_cable_rhs(&c, y, &bc, dydt, &out);
    cdpr_cable_end_forces(&c, y, &bc, &out);
    TEST_ASSERT_EQUAL_UINT(0u, cdpr_alloc_count());
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_taut_segment_tension_and_direction);
    RUN_TEST(test_damping_sign);
    RUN_TEST(test_slack_segment_carries_only_its_stretching_damper);
    RUN_TEST(test_moordyn_law_lets_the_damper_push);
    RUN_TEST(test_snap_is_continuous);
    RUN_TEST(test_damper_part_is_passive_and_never_pushes);
    RUN_TEST(test_payout_rate_reduces_tension);
    RUN_TEST(test_drag_purely_normal);
    RUN_TEST(test_drag_purely_tangential);
    RUN_TEST(test_drag_at_45_degrees_splits);
    RUN_TEST(test_drag_from_wind_only);
    RUN_TEST(test_drag_stretched_area_factor);
    RUN_TEST(test_rhs_three_segments_all_taut);
    RUN_TEST(test_rhs_three_segments_slack_pulley_side);
    RUN_TEST(test_rhs_single_segment);
    RUN_TEST(test_hanging_vertical_chain_is_static);
    RUN_TEST(test_rhs_node_count_sweep);
    RUN_TEST(test_place_straight_and_total_length);
    RUN_TEST(test_init_rejects_bad_counts_and_leaves_cable_untouched);
    RUN_TEST(test_rhs_makes_no_allocation);
    return UNITY_END() ? 1 : 0;
}
