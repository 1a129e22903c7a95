/// @file test_robot.c
/// The robot object (robot.h): parameter validation (every field, its status, diag.field and
/// diag.index), transactional init, state layout, the full RHS against its parts, outputs,
/// the symmetric six-cable robot, allocation-freedom and NaN handling with the integrator.
/// Tolerances are rounding bounds derived for double; the float build scales them as
/// tests/support/test_real.h explains (TOL), and exact copies are compared with the input
/// rounded to cdpr_real_t. The largest float amplification is the symmetric robot's strain of
/// 1.6 %: 62 x 2 u_f = 7e-6 relative on the tensions, inside the scaled 6e-4.
#include "unity.h"

#include "alloc_count.h"
#include "cdpr/rkf45.h"
#include "cdpr/robot.h"
#include "test_real.h"

#include <math.h>
#include <string.h>

#define PI_D  3.14159265358979323846
#define G_STD 9.80665

/* Hexagon geometry used throughout: exit points on radius 5 m at height 6 m, attachments on
 * radius 0.4 m in the body x-y plane at the same azimuths (theta_j = j * 60 deg), cabin
 * origin at (0, 0, 2). Chord from attachment to exit: horizontal 4.6 m, vertical 4 m. */
#define HEX_A  5.0
#define HEX_H  6.0
#define HEX_R  0.4
#define HEX_Z0 2.0
#define HEX_EA 2.0e4

static cdpr_robot_t robot;
static cdpr_real_t y_state[CDPR_ROBOT_STATE_MAX];
static cdpr_real_t dydt_state[CDPR_ROBOT_STATE_MAX];

void setUp(void)
{
    memset(&robot, 0, sizeof robot);
}

void tearDown(void) {}

#define REQUIRE_SIX_CABLES()                                                                       \
    do {                                                                                           \
        if (CDPR_MAX_CABLES < 6) {                                                                 \
            TEST_IGNORE_MESSAGE("needs CDPR_MAX_CABLES >= 6");                                     \
        }                                                                                          \
    } while (0)

static void hexagon_params(cdpr_robot_params_t *p, int n_cables, int n_seg, double length)
{
    cdpr_robot_params_default(p);
    p->n_cables = n_cables;
    for (int j = 0; j < n_cables; ++j) {
        const double th = (double)j * PI_D / 3.0;
        cdpr_robot_cable_params_t *c = &p->cables[j];
        c->exit_point_m = cdpr_v3(HEX_A * cos(th), HEX_A * sin(th), HEX_H);
        c->attach_body_m = cdpr_v3(HEX_R * cos(th), HEX_R * sin(th), 0.0);
        c->n_segments = n_seg;
        c->length_m = length;
        c->cable.ea_N = HEX_EA;
    }
}

static cdpr_cabin_motion_t motion_at(double x, double y, double z, cdpr_quat_t q)
{
    cdpr_cabin_motion_t m;
    m.p_m = cdpr_v3(x, y, z);
    m.q = q;
    m.v_m_per_s = cdpr_v3(0.0, 0.0, 0.0);
    m.w_rad_per_s = cdpr_v3(0.0, 0.0, 0.0);
    return m;
}

static cdpr_quat_t quat_identity(void)
{
    cdpr_quat_t q;
    q.w = 1.0;
    q.x = 0.0;
    q.y = 0.0;
    q.z = 0.0;
    return q;
}

static void init_robot(const cdpr_robot_params_t *p)
{
    cdpr_diag_t d;
    const cdpr_status_t st = cdpr_robot_init(&robot, p, &d);
    TEST_ASSERT_EQUAL_INT_MESSAGE(CDPR_OK, st, d.field);
}

static double norm3(cdpr_vec3_t a)
{
    return sqrt(a.x * a.x + a.y * a.y + a.z * a.z);
}

/* ---------------------------------------------------------------- invalid parameters */

typedef enum {
    K_G,
    K_MODE,
    K_NCABLES,
    K_NSEG,
    K_LENGTH,
    K_EXIT_X,
    K_EXIT_Y,
    K_EXIT_Z,
    K_ATT_X,
    K_ATT_Y,
    K_ATT_Z,
    K_D0,
    K_RHO,
    K_EA,
    K_DAMP,
    K_CD,
    K_CM,
    K_RHOAIR,
    K_MASS,
    K_INERTIA_ASYM
} which_t;

#define ANY_INDEX (-1000) /* diag.index not asserted (global counts and enums) */
#define CABLE_J   (-2000) /* diag.index must be the cable under test */

typedef struct {
    const char *name;
    which_t which;
    double value;
    cdpr_status_t status;
    const char *field;
    int index;
} robot_case_t;

static const robot_case_t robot_cases[] = {
    {"g NaN", K_G, NAN_D, CDPR_E_NOT_FINITE, "g_m_per_s2", -1},
    {"g Inf", K_G, INF_D, CDPR_E_NOT_FINITE, "g_m_per_s2", -1},
    {"g 0", K_G, 0.0, CDPR_E_NOT_POSITIVE, "g_m_per_s2", -1},
    {"g -9.8", K_G, -9.8, CDPR_E_NOT_POSITIVE, "g_m_per_s2", -1},
    {"mode 2", K_MODE, 2.0, CDPR_E_OUT_OF_RANGE, "mode", ANY_INDEX},
    {"mode -1", K_MODE, -1.0, CDPR_E_OUT_OF_RANGE, "mode", ANY_INDEX},
    {"n_cables 0", K_NCABLES, 0.0, CDPR_E_CAPACITY, "n_cables", ANY_INDEX},
    {"n_cables -1", K_NCABLES, -1.0, CDPR_E_CAPACITY, "n_cables", ANY_INDEX},
    {"n_cables max+1", K_NCABLES, (double)(CDPR_MAX_CABLES + 1), CDPR_E_CAPACITY, "n_cables",
     ANY_INDEX},
    {"n_segments 0", K_NSEG, 0.0, CDPR_E_CAPACITY, "n_segments", CABLE_J},
    {"n_segments -1", K_NSEG, -1.0, CDPR_E_CAPACITY, "n_segments", CABLE_J},
    {"n_segments max+1", K_NSEG, (double)(CDPR_MAX_SEGMENTS + 1), CDPR_E_CAPACITY, "n_segments",
     CABLE_J},
    {"length NaN", K_LENGTH, NAN_D, CDPR_E_NOT_FINITE, "length_m", CABLE_J},
    {"length Inf", K_LENGTH, INF_D, CDPR_E_NOT_FINITE, "length_m", CABLE_J},
    {"length 0", K_LENGTH, 0.0, CDPR_E_NOT_POSITIVE, "length_m", CABLE_J},
    {"length -1", K_LENGTH, -1.0, CDPR_E_NOT_POSITIVE, "length_m", CABLE_J},
    {"exit x NaN", K_EXIT_X, NAN_D, CDPR_E_NOT_FINITE, "exit_point_m", CABLE_J},
    {"exit y Inf", K_EXIT_Y, INF_D, CDPR_E_NOT_FINITE, "exit_point_m", CABLE_J},
    {"exit z NaN", K_EXIT_Z, NAN_D, CDPR_E_NOT_FINITE, "exit_point_m", CABLE_J},
    {"attach x NaN", K_ATT_X, NAN_D, CDPR_E_NOT_FINITE, "attach_body_m", CABLE_J},
    {"attach y -Inf", K_ATT_Y, -INF_D, CDPR_E_NOT_FINITE, "attach_body_m", CABLE_J},
    {"attach z NaN", K_ATT_Z, NAN_D, CDPR_E_NOT_FINITE, "attach_body_m", CABLE_J},
    {"d0 NaN", K_D0, NAN_D, CDPR_E_NOT_FINITE, "d0_m", CABLE_J},
    {"d0 Inf", K_D0, INF_D, CDPR_E_NOT_FINITE, "d0_m", CABLE_J},
    {"d0 0", K_D0, 0.0, CDPR_E_NOT_POSITIVE, "d0_m", CABLE_J},
    {"d0 -1", K_D0, -1.0, CDPR_E_NOT_POSITIVE, "d0_m", CABLE_J},
    {"rho NaN", K_RHO, NAN_D, CDPR_E_NOT_FINITE, "rho_kg_per_m", CABLE_J},
    {"rho Inf", K_RHO, INF_D, CDPR_E_NOT_FINITE, "rho_kg_per_m", CABLE_J},
    {"rho 0", K_RHO, 0.0, CDPR_E_NOT_POSITIVE, "rho_kg_per_m", CABLE_J},
    {"rho -1", K_RHO, -1.0, CDPR_E_NOT_POSITIVE, "rho_kg_per_m", CABLE_J},
    {"EA NaN", K_EA, NAN_D, CDPR_E_NOT_FINITE, "ea_N", CABLE_J},
    {"EA Inf", K_EA, INF_D, CDPR_E_NOT_FINITE, "ea_N", CABLE_J},
    {"EA 0", K_EA, 0.0, CDPR_E_NOT_POSITIVE, "ea_N", CABLE_J},
    {"EA -1", K_EA, -1.0, CDPR_E_NOT_POSITIVE, "ea_N", CABLE_J},
    {"damping NaN", K_DAMP, NAN_D, CDPR_E_NOT_FINITE, "damping_Ns", CABLE_J},
    {"damping Inf", K_DAMP, INF_D, CDPR_E_NOT_FINITE, "damping_Ns", CABLE_J},
    {"damping -1", K_DAMP, -1.0, CDPR_E_OUT_OF_RANGE, "damping_Ns", CABLE_J},
    {"cd NaN", K_CD, NAN_D, CDPR_E_NOT_FINITE, "cd", CABLE_J},
    {"cd Inf", K_CD, INF_D, CDPR_E_NOT_FINITE, "cd", CABLE_J},
    {"cd -1", K_CD, -1.0, CDPR_E_OUT_OF_RANGE, "cd", CABLE_J},
    {"cm NaN", K_CM, NAN_D, CDPR_E_NOT_FINITE, "cm", CABLE_J},
    {"cm Inf", K_CM, INF_D, CDPR_E_NOT_FINITE, "cm", CABLE_J},
    {"cm -1", K_CM, -1.0, CDPR_E_OUT_OF_RANGE, "cm", CABLE_J},
    {"rho_air NaN", K_RHOAIR, NAN_D, CDPR_E_NOT_FINITE, "rho_air_kg_per_m3", CABLE_J},
    {"rho_air Inf", K_RHOAIR, INF_D, CDPR_E_NOT_FINITE, "rho_air_kg_per_m3", CABLE_J},
    {"rho_air -1", K_RHOAIR, -1.0, CDPR_E_OUT_OF_RANGE, "rho_air_kg_per_m3", CABLE_J},
    {"cabin mass NaN", K_MASS, NAN_D, CDPR_E_NOT_FINITE, "cabin.mass_kg", -1},
    {"cabin mass 0", K_MASS, 0.0, CDPR_E_NOT_POSITIVE, "cabin.mass_kg", -1},
    {"cabin inertia asymmetric", K_INERTIA_ASYM, 5.0, CDPR_E_OUT_OF_RANGE,
     "cabin.inertia_com_kg_m2", 1},
};

static int is_cable_param(which_t w)
{
    return w >= K_D0 && w <= K_RHOAIR;
}

static void apply_case(cdpr_robot_params_t *p, const robot_case_t *c, int j)
{
    cdpr_robot_cable_params_t *cp = &p->cables[j];
    switch (c->which) {
    case K_G:
        p->g_m_per_s2 = c->value;
        break;
    case K_MODE:
        p->mode = (cdpr_cabin_mode_t)(int)c->value;
        break;
    case K_NCABLES:
        p->n_cables = (int)c->value;
        break;
    case K_NSEG:
        cp->n_segments = (int)c->value;
        break;
    case K_LENGTH:
        cp->length_m = c->value;
        break;
    case K_EXIT_X:
        cp->exit_point_m.x = c->value;
        break;
    case K_EXIT_Y:
        cp->exit_point_m.y = c->value;
        break;
    case K_EXIT_Z:
        cp->exit_point_m.z = c->value;
        break;
    case K_ATT_X:
        cp->attach_body_m.x = c->value;
        break;
    case K_ATT_Y:
        cp->attach_body_m.y = c->value;
        break;
    case K_ATT_Z:
        cp->attach_body_m.z = c->value;
        break;
    case K_D0:
        cp->cable.d0_m = c->value;
        break;
    case K_RHO:
        cp->cable.rho_kg_per_m = c->value;
        break;
    case K_EA:
        cp->cable.ea_N = c->value;
        break;
    case K_DAMP:
        cp->cable.damping_Ns = c->value;
        break;
    case K_CD:
        cp->cable.cd = c->value;
        break;
    case K_CM:
        cp->cable.cm = c->value;
        break;
    case K_RHOAIR:
        cp->cable.rho_air_kg_per_m3 = c->value;
        break;
    case K_MASS:
        p->cabin.mass_kg = c->value;
        break;
    case K_INERTIA_ASYM:
        p->cabin.inertia_com_kg_m2.m[0][1] = c->value;
        p->cabin.inertia_com_kg_m2.m[1][0] = 0.0;
        break;
    default:
        TEST_FAIL_MESSAGE("unknown case");
        break;
    }
}

static void check_case_on_cable(const robot_case_t *c, int j, const cdpr_robot_t *fresh_before)
{
    cdpr_robot_params_t p;
    hexagon_params(&p, CDPR_MAX_CABLES, 4, 6.0);
    apply_case(&p, c, j);
    cdpr_diag_t d;
    memset(&d, 0, sizeof d);

    /* (1) a never-initialised object filled with a byte pattern stays bit-identical. */
    memset(&robot, 0xA5, sizeof robot);
    static cdpr_robot_t pattern;
    memcpy(&pattern, &robot, sizeof robot);
    TEST_ASSERT_EQUAL_INT_MESSAGE(c->status, cdpr_robot_init(&robot, &p, &d), c->name);
    TEST_ASSERT_EQUAL_INT_MESSAGE(c->status, d.status, c->name);
    TEST_ASSERT_EQUAL_STRING_MESSAGE(c->field, d.field, c->name);
    if (c->index == CABLE_J) {
        TEST_ASSERT_EQUAL_INT_MESSAGE(j, d.index, c->name);
    } else if (c->index != ANY_INDEX) {
        TEST_ASSERT_EQUAL_INT_MESSAGE(c->index, d.index, c->name);
    }
    TEST_ASSERT_EQUAL_MEMORY_MESSAGE(&pattern, &robot, sizeof robot, c->name);

    /* (2) a valid robot is not modified by a failed re-init either. */
    memcpy(&robot, fresh_before, sizeof robot);
    TEST_ASSERT_EQUAL_INT_MESSAGE(c->status, cdpr_robot_init(&robot, &p, &d), c->name);
    TEST_ASSERT_EQUAL_MEMORY_MESSAGE(fresh_before, &robot, sizeof robot, c->name);

    /* (3) cable parameters: the cable-level validator names the same field (index -1). */
    if (is_cable_param(c->which)) {
        TEST_ASSERT_EQUAL_INT_MESSAGE(c->status, cdpr_cable_params_validate(&p.cables[j].cable, &d),
                                      c->name);
        TEST_ASSERT_EQUAL_STRING_MESSAGE(c->field, d.field, c->name);
        TEST_ASSERT_EQUAL_INT_MESSAGE(-1, d.index, c->name);
    }
}

static void test_every_invalid_parameter_is_named_and_robot_untouched(void)
{
    static cdpr_robot_t valid;
    cdpr_robot_params_t p;
    hexagon_params(&p, CDPR_MAX_CABLES, 4, 6.0);
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_robot_init(&valid, &p, NULL));
    /* First cable and last cable: the index must follow the cable, and all cables before
     * the bad one having validated must not leave anything behind. */
    const int js[2] = {0, CDPR_MAX_CABLES - 1};
    for (size_t k = 0; k < sizeof robot_cases / sizeof robot_cases[0]; ++k) {
        for (int ij = 0; ij < 2; ++ij) {
            check_case_on_cable(&robot_cases[k], js[ij], &valid);
        }
    }
}

static void test_inactive_cables_are_not_validated(void)
{
    /* Only cables 0..n_cables-1 are read: garbage in the unused slots is fine. */
    if (CDPR_MAX_CABLES < 2) {
        TEST_IGNORE_MESSAGE("needs CDPR_MAX_CABLES >= 2");
    }
    cdpr_robot_params_t p;
    hexagon_params(&p, CDPR_MAX_CABLES, 4, 6.0);
    p.n_cables = 1;
    p.cables[1].cable.ea_N = NAN_R;
    p.cables[1].n_segments = 0;
    p.cables[1].exit_point_m.x = NAN_R;
    cdpr_diag_t d;
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_robot_init(&robot, &p, &d));
    TEST_ASSERT_EQUAL_INT(CDPR_OK, d.status);
}

static void test_null_arguments(void)
{
    cdpr_robot_params_t p;
    cdpr_robot_params_default(&p);
    cdpr_diag_t d;
    TEST_ASSERT_EQUAL_INT(CDPR_E_INVALID_ARG, cdpr_robot_init(NULL, &p, &d));
    TEST_ASSERT_EQUAL_STRING("robot", d.field);
    TEST_ASSERT_EQUAL_INT(CDPR_E_INVALID_ARG, cdpr_robot_init(&robot, NULL, &d));
    TEST_ASSERT_EQUAL_STRING("params", d.field);
    /* The defaults are a valid robot (one cable). */
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_robot_init(&robot, &p, &d));
    TEST_ASSERT_EQUAL_INT(1, robot.p.n_cables);
}

static void test_capacity_limits_are_accepted(void)
{
    /* n_cables = CDPR_MAX_CABLES and n_segments = CDPR_MAX_SEGMENTS are valid, as are 1 and 1. */
    cdpr_robot_params_t p;
    hexagon_params(&p, CDPR_MAX_CABLES, CDPR_MAX_SEGMENTS, 6.0);
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_robot_init(&robot, &p, NULL));
    TEST_ASSERT_EQUAL_INT(CDPR_ROBOT_STATE_MAX, cdpr_robot_state_dim(&robot));
    hexagon_params(&p, 1, 1, 6.0);
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_robot_init(&robot, &p, NULL));
    TEST_ASSERT_EQUAL_INT(CDPR_CABIN_STATE_DIM + 1, cdpr_robot_state_dim(&robot));
}

/* ---------------------------------------------------------------- geometry and layout */

static void test_coincident_attachment_and_exit_point(void)
{
    REQUIRE_SIX_CABLES();
    cdpr_robot_params_t p;
    hexagon_params(&p, 6, 4, 6.0);
    /* Cable 2's exit point exactly at its attachment for the pose (0, 0, 2), identity:
     * attachment = p + R b = (b.x, b.y, 2) with R = I (exact). */
    p.cables[2].exit_point_m =
        cdpr_v3(p.cables[2].attach_body_m.x, p.cables[2].attach_body_m.y, HEX_Z0);
    init_robot(&p); /* init cannot know the pose: accepted */
    const cdpr_cabin_motion_t m = motion_at(0.0, 0.0, HEX_Z0, quat_identity());
    memset(y_state, 0x5A, sizeof y_state);
    static cdpr_real_t before[CDPR_ROBOT_STATE_MAX];
    memcpy(before, y_state, sizeof y_state);
    TEST_ASSERT_EQUAL_INT(CDPR_E_GEOMETRY, cdpr_robot_place_straight(&robot, &m, y_state));
    TEST_ASSERT_EQUAL_MEMORY(before, y_state, sizeof y_state);
    /* A different pose separates them again. */
    const cdpr_cabin_motion_t m2 = motion_at(0.0, 0.0, HEX_Z0 - 0.5, quat_identity());
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_robot_place_straight(&robot, &m2, y_state));
}

static void test_state_layout_and_straight_placement(void)
{
    REQUIRE_SIX_CABLES();
    const int nseg[6] = {1, 2, 3, 7, 20, CDPR_MAX_SEGMENTS};
    cdpr_robot_params_t p;
    hexagon_params(&p, 6, 1, 6.0);
    for (int j = 0; j < 6; ++j) {
        p.cables[j].n_segments = nseg[j];
        p.cables[j].length_m = 5.0 + 0.25 * (double)j;
    }
    init_robot(&p);
    /* dim = 13 + sum_j (1 + 6 (n_j - 1)); offsets are the running sums. */
    int expected_dim = 13;
    for (int j = 0; j < 6; ++j) {
        TEST_ASSERT_EQUAL_INT(expected_dim, robot.offset[j]);
        expected_dim += 1 + 6 * (nseg[j] - 1);
    }
    TEST_ASSERT_EQUAL_INT(expected_dim, cdpr_robot_state_dim(&robot));
    TEST_ASSERT_EQUAL_INT(13 + 1 + 7 + 13 + 37 + 115 + 1 + 6 * (CDPR_MAX_SEGMENTS - 1),
                          cdpr_robot_state_dim(&robot));

    /* Straight placement at the pose (0.1, -0.2, 2) with a yaw of 0.3 rad: cabin block is the
     * motion, cable j's nodes sit at k/n of the chord from its attachment a_j to A_j (equal
     * segments), y[offset] = L/n, velocities 0. */
    const double yaw = 0.3;
    cdpr_quat_t q;
    q.w = cos(0.5 * yaw);
    q.x = 0.0;
    q.y = 0.0;
    q.z = sin(0.5 * yaw);
    cdpr_cabin_motion_t m = motion_at(0.1, -0.2, HEX_Z0, q);
    memset(y_state, 0x5A, sizeof y_state);
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_robot_place_straight(&robot, &m, y_state));
    TEST_ASSERT_DOUBLE_WITHIN(0.0, CDPR_R(0.1), y_state[CDPR_CABIN_P + 0]);
    TEST_ASSERT_DOUBLE_WITHIN(0.0, HEX_Z0, y_state[CDPR_CABIN_P + 2]);
    TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-16, 6e-8), q.z, y_state[CDPR_CABIN_Q + 3]);
    for (int j = 0; j < 6; ++j) {
        const cdpr_real_t *blk = y_state + robot.offset[j];
        const int n = nseg[j];
        const double L = 5.0 + 0.25 * (double)j;
        /* L/n: init divides once; 1e-15 relative. */
        TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-15, 6e-7) * L, L / (double)n, blk[0]);
        const cdpr_vec3_t b = p.cables[j].attach_body_m;
        /* attachment = p + Rz(yaw) b, written out */
        const double ax = 0.1 + cos(yaw) * b.x - sin(yaw) * b.y;
        const double ay = -0.2 + sin(yaw) * b.x + cos(yaw) * b.y;
        const double az = HEX_Z0 + b.z;
        const cdpr_vec3_t A = p.cables[j].exit_point_m;
        for (int i = 1; i < n; ++i) {
            const double f = (double)i / (double)n;
            /* coordinates <= 6 m, a few roundings: 1e-14 m */
            TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-14, 6e-6), ax + f * (A.x - ax),
                                      blk[1 + 3 * (i - 1) + 0]);
            TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-14, 6e-6), ay + f * (A.y - ay),
                                      blk[1 + 3 * (i - 1) + 1]);
            TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-14, 6e-6), az + f * (A.z - az),
                                      blk[1 + 3 * (i - 1) + 2]);
            for (int a = 0; a < 3; ++a) {
                TEST_ASSERT_DOUBLE_WITHIN(0.0, 0.0, blk[1 + 3 * (n - 1) + 3 * (i - 1) + a]);
            }
        }
    }
    /* Per-component absolute tolerances follow the same layout. */
    static cdpr_real_t atol[CDPR_ROBOT_STATE_MAX];
    cdpr_robot_fill_atol(&robot, 1e-6, 1e-5, 1e-9, 1e-7, atol);
    TEST_ASSERT_DOUBLE_WITHIN(0.0, CDPR_R(1e-6), atol[CDPR_CABIN_P]);
    TEST_ASSERT_DOUBLE_WITHIN(0.0, CDPR_R(1e-9), atol[CDPR_CABIN_Q + 3]);
    TEST_ASSERT_DOUBLE_WITHIN(0.0, CDPR_R(1e-5), atol[CDPR_CABIN_V + 1]);
    TEST_ASSERT_DOUBLE_WITHIN(0.0, CDPR_R(1e-7), atol[CDPR_CABIN_W + 2]);
    for (int j = 0; j < 6; ++j) {
        const int nf = nseg[j] - 1;
        const cdpr_real_t *a = atol + robot.offset[j];
        TEST_ASSERT_DOUBLE_WITHIN(0.0, CDPR_R(1e-6), a[0]);
        for (int i = 0; i < 3 * nf; ++i) {
            TEST_ASSERT_DOUBLE_WITHIN(0.0, CDPR_R(1e-6), a[1 + i]);
            TEST_ASSERT_DOUBLE_WITHIN(0.0, CDPR_R(1e-5), a[1 + 3 * nf + i]);
        }
    }
}

/* ---------------------------------------------------------------- forces */

static void test_symmetric_six_cable_robot(void)
{
    REQUIRE_SIX_CABLES();
    /* Cabin at the centre, identity orientation, every cable straight and at rest with the same
     * strain: chord l = sqrt(4.6^2 + 4^2), L = 6 m, T = EA (l/L - 1) along the chord in every
     * segment. By the 6-fold symmetry the horizontal forces and all torques cancel; the
     * vertical force is 6 T (4/l). */
    cdpr_robot_params_t p;
    hexagon_params(&p, 6, 8, 6.0);
    init_robot(&p);
    const cdpr_cabin_motion_t m = motion_at(0.0, 0.0, HEX_Z0, quat_identity());
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_robot_place_straight(&robot, &m, y_state));
    cdpr_robot_out_t out;
    cdpr_robot_outputs(&robot, 0.0, y_state, &out);

    const double l = sqrt(4.6 * 4.6 + 4.0 * 4.0);
    const double T = HEX_EA * (l / 6.0 - 1.0);
    /* Strain 1.6 %: the chord's rounding (1e-16 relative) is amplified by 1/eps = 62 in T,
     * and the node positions are rounded too: 1e-12 relative is still ~100x the error. */
    double sum_abs = 0.0, sum_moment = 0.0;
    for (int j = 0; j < 6; ++j) {
        TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-12, 6e-4) * T, T, out.tension_cabin_N[j]);
        TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-12, 6e-4) * T, T, out.tension_winch_N[j]);
        TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-12, 6e-4) * T, T, norm3(out.force_on_cabin_N[j]));
        sum_abs += norm3(out.force_on_cabin_N[j]);
        sum_moment += HEX_R * norm3(out.force_on_cabin_N[j]);
    }
    /* Cancellation of six ~T-sized terms: rounding ~6 u T; allow 1e-12 of the sum. */
    TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-12, 6e-4) * sum_abs, 0.0, out.total_force_N.x);
    TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-12, 6e-4) * sum_abs, 0.0, out.total_force_N.y);
    TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-12, 6e-4) * sum_abs, 6.0 * T * 4.0 / l, out.total_force_N.z);
    TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-12, 6e-4) * sum_moment, 0.0, out.total_torque_Nm.x);
    TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-12, 6e-4) * sum_moment, 0.0, out.total_torque_Nm.y);
    TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-12, 6e-4) * sum_moment, 0.0, out.total_torque_Nm.z);

    /* The RHS agrees: no horizontal acceleration, no angular acceleration, vertical
     * acceleration (F_z)/M - g with M the combined mass. */
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_robot_rhs(0.0, y_state, dydt_state, &robot));
    const double M = robot.cabin.mass_kg;
    TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-12, 6e-4) * sum_abs / M, 0.0, dydt_state[CDPR_CABIN_V + 0]);
    TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-12, 6e-4) * sum_abs / M, 0.0, dydt_state[CDPR_CABIN_V + 1]);
    TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-12, 6e-4) * (sum_abs / M + G_STD),
                              6.0 * T * 4.0 / l / M - G_STD, dydt_state[CDPR_CABIN_V + 2]);
    for (int i = 0; i < 3; ++i) {
        /* |I^-1| <= 1/45 for the default cabin plus point masses */
        TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-12, 6e-4) * sum_moment / 45.0, 0.0,
                                  dydt_state[CDPR_CABIN_W + i]);
    }
    /* Combined mass = 40 kg + 6 node-0 masses rho lu_0 / 2 = 6 * 0.14 * (6/8) / 2. */
    TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-14, 6e-6) * 40.0, 40.0 + 6.0 * 0.14 * 0.75 / 2.0, M);
}

static void test_all_slack_is_free_fall(void)
{
    REQUIRE_SIX_CABLES();
    /* Cables 1 m longer than their chords, at rest, no wind: no cable force at all, so the
     * cabin falls with exactly -g (every other term is a product with zero). */
    cdpr_robot_params_t p;
    hexagon_params(&p, 6, 5, 7.1);
    init_robot(&p);
    cdpr_quat_t q = cdpr_quat_from_euler(0.1, -0.2, 0.3);
    const cdpr_cabin_motion_t m = motion_at(0.2, 0.1, HEX_Z0, q);
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_robot_place_straight(&robot, &m, y_state));
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_robot_rhs(0.0, y_state, dydt_state, &robot));
    TEST_ASSERT_DOUBLE_WITHIN(0.0, 0.0, dydt_state[CDPR_CABIN_V + 0]);
    TEST_ASSERT_DOUBLE_WITHIN(0.0, 0.0, dydt_state[CDPR_CABIN_V + 1]);
    TEST_ASSERT_DOUBLE_WITHIN(0.0, -(cdpr_real_t)G_STD, dydt_state[CDPR_CABIN_V + 2]);
    for (int i = 0; i < 3; ++i) {
        TEST_ASSERT_DOUBLE_WITHIN(0.0, 0.0, dydt_state[CDPR_CABIN_W + i]);
    }
    cdpr_robot_out_t out;
    cdpr_robot_outputs(&robot, 0.0, y_state, &out);
    for (int j = 0; j < 6; ++j) {
        TEST_ASSERT_DOUBLE_WITHIN(0.0, 0.0, out.tension_cabin_N[j]);
        TEST_ASSERT_DOUBLE_WITHIN(0.0, 0.0, out.tension_winch_N[j]);
    }
    /* Free cable nodes fall with g too (slack segments, no drag at rest). */
    const cdpr_real_t *d = dydt_state + robot.offset[3];
    const int nf = 4;
    for (int i = 0; i < nf; ++i) {
        TEST_ASSERT_DOUBLE_WITHIN(0.0, -(cdpr_real_t)G_STD, d[1 + 3 * nf + 3 * i + 2]);
    }
}

/* R = Rz(g) Ry(b) Rx(a) written out, for the independent torque check. */
static void euler_matrix(double a, double b, double g, double R[3][3])
{
    const double ca = cos(a), sa = sin(a), cb = cos(b), sb = sin(b), cg = cos(g), sg = sin(g);
    R[0][0] = cg * cb;
    R[0][1] = cg * sb * sa - sg * ca;
    R[0][2] = cg * sb * ca + sg * sa;
    R[1][0] = sg * cb;
    R[1][1] = sg * sb * sa + cg * ca;
    R[1][2] = sg * sb * ca - cg * sa;
    R[2][0] = -sb;
    R[2][1] = cb * sa;
    R[2][2] = cb * ca;
}

static void test_outputs_equal_rhs_parts(void)
{
    REQUIRE_SIX_CABLES();
    /* An asymmetric, moving robot: three cables with 1, 3 and 6 segments, perturbed nodes,
     * node and cabin velocities, wind, payout, external loads. */
    cdpr_robot_params_t p;
    hexagon_params(&p, 3, 1, 6.0);
    p.cables[1].n_segments = 3;
    p.cables[2].n_segments = 6;
    p.cables[0].length_m = 5.5;
    p.cables[1].length_m = 5.6;
    p.cables[2].length_m = 5.55;
    p.cabin.com_body_m = cdpr_v3(0.02, -0.01, 0.05);
    init_robot(&p);
    const double ea = 0.1, eb = -0.05, eg = 0.3;
    cdpr_cabin_motion_t m = motion_at(0.3, -0.2, 2.1, cdpr_quat_from_euler(ea, eb, eg));
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_robot_place_straight(&robot, &m, y_state));
    const double v[3] = {0.2, 0.1, -0.1}, w[3] = {0.05, -0.1, 0.2};
    for (int i = 0; i < 3; ++i) {
        y_state[CDPR_CABIN_V + i] = v[i];
        y_state[CDPR_CABIN_W + i] = w[i];
    }
    for (int j = 0; j < 3; ++j) {
        const int nf = robot.cable[j].n - 1;
        cdpr_real_t *blk = y_state + robot.offset[j];
        for (int i = 0; i < 3 * nf; ++i) {
            blk[1 + i] += 0.01 * sin(1.7 * (double)(i + 3 * j));
            blk[1 + 3 * nf + i] = 0.1 * cos(0.9 * (double)(i + 5 * j));
        }
    }
    robot.in.payout_m_per_s[0] = 0.1;
    robot.in.payout_m_per_s[1] = -0.2;
    robot.in.payout_m_per_s[2] = 0.05;
    robot.in.wind_m_per_s = cdpr_v3(1.0, -0.5, 0.2);
    robot.in.ext_force_world_N = cdpr_v3(3.0, -2.0, 1.0);
    robot.in.ext_torque_body_Nm = cdpr_v3(0.5, 0.25, -0.75);

    cdpr_robot_out_t out;
    cdpr_robot_outputs(&robot, 0.0, y_state, &out);
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_robot_rhs(0.0, y_state, dydt_state, &robot));

    cdpr_cabin_motion_t mm;
    cdpr_cabin_get_motion(y_state, &mm);
    double R[3][3];
    euler_matrix(ea, eb, eg, R);
    const cdpr_vec3_t C = robot.cabin.com_body_m;
    cdpr_vec3_t sumF = cdpr_v3(0.0, 0.0, 0.0);
    double tq[3] = {0.0, 0.0, 0.0}, scale_f = 0.0, scale_t = 0.0;
    static cdpr_real_t dcable[CDPR_CABLE_STATE_MAX];
    for (int j = 0; j < 3; ++j) {
        /* Boundary conditions as the robot's documentation describes them. */
        cdpr_cable_bc_t bc;
        cdpr_robot_attachment(&robot, j, &mm, &bc.r0_m, &bc.v0_m_per_s);
        {
            /* docs/model.md §2: r_0 = p + R b, v_0 = v + (R w) x (R b), with the test's own R.
             * Positions ~6 m and velocities ~0.3 m/s from ~10 roundings: 1e-14 absolute. */
            const cdpr_vec3_t bj = p.cables[j].attach_body_m;
            const double rb[3] = {R[0][0] * bj.x + R[0][1] * bj.y + R[0][2] * bj.z,
                                  R[1][0] * bj.x + R[1][1] * bj.y + R[1][2] * bj.z,
                                  R[2][0] * bj.x + R[2][1] * bj.y + R[2][2] * bj.z};
            const double ww[3] = {R[0][0] * w[0] + R[0][1] * w[1] + R[0][2] * w[2],
                                  R[1][0] * w[0] + R[1][1] * w[1] + R[1][2] * w[2],
                                  R[2][0] * w[0] + R[2][1] * w[1] + R[2][2] * w[2]};
            TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-14, 6e-6), 0.3 + rb[0], bc.r0_m.x);
            TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-14, 6e-6), -0.2 + rb[1], bc.r0_m.y);
            TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-14, 6e-6), 2.1 + rb[2], bc.r0_m.z);
            TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-14, 6e-6), v[0] + ww[1] * rb[2] - ww[2] * rb[1],
                                      bc.v0_m_per_s.x);
            TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-14, 6e-6), v[1] + ww[2] * rb[0] - ww[0] * rb[2],
                                      bc.v0_m_per_s.y);
            TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-14, 6e-6), v[2] + ww[0] * rb[1] - ww[1] * rb[0],
                                      bc.v0_m_per_s.z);
        }
        bc.rn_m = p.cables[j].exit_point_m;
        bc.wind_m_per_s = robot.in.wind_m_per_s;
        bc.payout_m_per_s = robot.in.payout_m_per_s[j];
        bc.g_m_per_s2 = G_STD;
        cdpr_cable_out_t co;
        const int dimj = cdpr_cable_state_dim(&robot.cable[j]);
        cdpr_cable_rhs(&robot.cable[j], y_state + robot.offset[j], &bc, dcable, &co);
        TEST_ASSERT_TRUE(co.tension_cabin_N > 0.0); /* taut: the forces are not trivial */
        /* Same function on the same inputs: the robot's cable blocks are bit-identical. */
        TEST_ASSERT_EQUAL_MEMORY(dcable, dydt_state + robot.offset[j],
                                 (size_t)dimj * sizeof(cdpr_real_t));
        /* cdpr_robot_outputs = the RHS's `out` (end_forces evaluates the same expressions:
         * only last-bit differences would be excusable, 1e-14 relative). */
        const double fs = norm3(co.force_on_cabin_N);
        TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-14, 6e-6) * fs, co.force_on_cabin_N.x,
                                  out.force_on_cabin_N[j].x);
        TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-14, 6e-6) * fs, co.force_on_cabin_N.y,
                                  out.force_on_cabin_N[j].y);
        TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-14, 6e-6) * fs, co.force_on_cabin_N.z,
                                  out.force_on_cabin_N[j].z);
        TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-14, 6e-6) * co.tension_cabin_N, co.tension_cabin_N,
                                  out.tension_cabin_N[j]);
        TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-14, 6e-6) * (co.tension_winch_N + 1.0), co.tension_winch_N,
                                  out.tension_winch_N[j]);
        /* Independent torque about the combined CoM: (b_j - C) x (R^T F_j). */
        const cdpr_vec3_t F = co.force_on_cabin_N;
        const double Fb[3] = {R[0][0] * F.x + R[1][0] * F.y + R[2][0] * F.z,
                              R[0][1] * F.x + R[1][1] * F.y + R[2][1] * F.z,
                              R[0][2] * F.x + R[1][2] * F.y + R[2][2] * F.z};
        const cdpr_vec3_t b = p.cables[j].attach_body_m;
        const double r[3] = {b.x - C.x, b.y - C.y, b.z - C.z};
        tq[0] += r[1] * Fb[2] - r[2] * Fb[1];
        tq[1] += r[2] * Fb[0] - r[0] * Fb[2];
        tq[2] += r[0] * Fb[1] - r[1] * Fb[0];
        sumF = cdpr_v3_add(sumF, F);
        scale_f += fs;
        scale_t += sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]) * fs;
    }
    /* Unused cable slots report zero. */
    for (int j = 3; j < CDPR_MAX_CABLES; ++j) {
        TEST_ASSERT_DOUBLE_WITHIN(0.0, 0.0, out.tension_cabin_N[j]);
    }
    /* Totals: sums of the per-cable values (1e-14 of the summed magnitudes); the torque from
     * the test's own rotation matrix (entries ~1e-15 off): 1e-13 of the moment scale. */
    TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-14, 6e-6) * scale_f, sumF.x, out.total_force_N.x);
    TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-14, 6e-6) * scale_f, sumF.y, out.total_force_N.y);
    TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-14, 6e-6) * scale_f, sumF.z, out.total_force_N.z);
    TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-13, 6e-5) * scale_t, tq[0], out.total_torque_Nm.x);
    TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-13, 6e-5) * scale_t, tq[1], out.total_torque_Nm.y);
    TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-13, 6e-5) * scale_t, tq[2], out.total_torque_Nm.z);

    /* The robot's cabin block = the cabin RHS driven by (cable totals + external loads).
     * Summation order differs (external first vs last): rounding ~u |F|; the derivatives are
     * bounded by (|F| / M + g) and (|tau| / I_min + |w|^2 I_max/I_min): 1e-12 of those. */
    static cdpr_real_t dcab[CDPR_CABIN_STATE_DIM];
    cdpr_cabin_rhs(&robot.cabin, y_state,
                   cdpr_v3_add(out.total_force_N, robot.in.ext_force_world_N),
                   cdpr_v3_add(out.total_torque_Nm, robot.in.ext_torque_body_Nm), G_STD, dcab);
    const double sv = (scale_f + 4.0) / robot.cabin.mass_kg + G_STD;
    const double sw = (scale_t + 1.0) / 40.0 + 1.0;
    for (int i = 0; i < 3; ++i) {
        TEST_ASSERT_DOUBLE_WITHIN(0.0, dcab[CDPR_CABIN_P + i], dydt_state[CDPR_CABIN_P + i]);
        TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-12, 6e-4) * sv, dcab[CDPR_CABIN_V + i],
                                  dydt_state[CDPR_CABIN_V + i]);
        TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-12, 6e-4) * sw, dcab[CDPR_CABIN_W + i],
                                  dydt_state[CDPR_CABIN_W + i]);
    }
    for (int i = 0; i < 4; ++i) {
        TEST_ASSERT_DOUBLE_WITHIN(0.0, dcab[CDPR_CABIN_Q + i], dydt_state[CDPR_CABIN_Q + i]);
    }
}

/* ---------------------------------------------------------------- memory and NaN */

static void test_init_and_rhs_make_no_allocation(void)
{
    REQUIRE_SIX_CABLES();
    if (!cdpr_alloc_counting_available()) {
        TEST_IGNORE_MESSAGE(cdpr_alloc_unavailable_reason());
    }
    cdpr_robot_params_t p;
    hexagon_params(&p, 6, CDPR_MAX_SEGMENTS, 6.0);
    const cdpr_cabin_motion_t m = motion_at(0.0, 0.0, HEX_Z0, quat_identity());
    cdpr_robot_out_t out;
    cdpr_alloc_reset();
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_robot_init(&robot, &p, NULL));
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_robot_place_straight(&robot, &m, y_state));
    robot.in.wind_m_per_s = cdpr_v3(2.0, 0.0, 0.0);
    for (int k = 0; k < 10; ++k) {
        TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_robot_rhs(0.0, y_state, dydt_state, &robot));
    }
    cdpr_robot_outputs(&robot, 0.0, y_state, &out);
    cdpr_robot_normalize(&robot, y_state);
    TEST_ASSERT_EQUAL_UINT(0u, cdpr_alloc_count());
}

static cdpr_real_t rk_work[CDPR_RKF45_WORK_PER_DIM * CDPR_ROBOT_STATE_MAX];

static void test_nan_in_robot_state_is_refused_by_the_integrator(void)
{
    REQUIRE_SIX_CABLES();
    cdpr_robot_params_t p;
    hexagon_params(&p, 6, 4, 6.0);
    init_robot(&p);
    const cdpr_cabin_motion_t m = motion_at(0.0, 0.0, HEX_Z0, quat_identity());
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_robot_place_straight(&robot, &m, y_state));
    const int dim = cdpr_robot_state_dim(&robot);
    cdpr_rkf45_params_t rp;
    cdpr_rkf45_params_default(&rp);
    cdpr_rkf45_t rk;
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_rkf45_init(&rk, &rp, rk_work,
                                                   (int)(sizeof rk_work / sizeof rk_work[0]),
                                                   CDPR_ROBOT_STATE_MAX, dim, NULL));
    /* NaN in a node position of cable 2, and separately in the cabin quaternion. */
    const int where[2] = {robot.offset[2] + 4, CDPR_CABIN_Q + 1};
    static cdpr_real_t before[CDPR_ROBOT_STATE_MAX];
    for (int k = 0; k < 2; ++k) {
        TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_robot_place_straight(&robot, &m, y_state));
        y_state[where[k]] = NAN_R;
        memcpy(before, y_state, sizeof y_state);
        cdpr_real_t t = 0.5;
        const cdpr_real_t t_before = t;
        TEST_ASSERT_EQUAL_INT(
            CDPR_E_STATE_NOT_FINITE,
            cdpr_rkf45_advance(&rk, cdpr_robot_rhs, &robot, &t, y_state, 1e-3, 50));
        TEST_ASSERT_EQUAL_MEMORY(before, y_state, (size_t)dim * sizeof(cdpr_real_t));
        TEST_ASSERT_EQUAL_MEMORY(&t_before, &t, sizeof t);
    }
    /* Without the NaN the same call succeeds (the refusal was about the NaN). */
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_robot_place_straight(&robot, &m, y_state));
    cdpr_real_t t = 0.5;
    const cdpr_status_t st = cdpr_rkf45_advance(&rk, cdpr_robot_rhs, &robot, &t, y_state, 1e-3, 50);
    TEST_ASSERT_TRUE(st == CDPR_OK || st == CDPR_WARN_SUBSTEP_LIMIT);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_every_invalid_parameter_is_named_and_robot_untouched);
    RUN_TEST(test_inactive_cables_are_not_validated);
    RUN_TEST(test_null_arguments);
    RUN_TEST(test_capacity_limits_are_accepted);
    RUN_TEST(test_coincident_attachment_and_exit_point);
    RUN_TEST(test_state_layout_and_straight_placement);
    RUN_TEST(test_symmetric_six_cable_robot);
    RUN_TEST(test_all_slack_is_free_fall);
    RUN_TEST(test_outputs_equal_rhs_parts);
    RUN_TEST(test_init_and_rhs_make_no_allocation);
    RUN_TEST(test_nan_in_robot_state_is_refused_by_the_integrator);
    return UNITY_END() ? 1 : 0;
}
