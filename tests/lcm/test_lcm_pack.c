/* SPDX-License-Identifier: BSD-3-Clause */
/// @file test_lcm_pack.c
/// Packing the core's state into the LCM messages (lcm_pack.h), and each message through the
/// generated encoder and decoder.
///
/// The references are independent of the packing code: the state vector read directly with
/// the documented layout (cabin.h, cable.h), the Euler angles the pose was built from, the sum
/// of unstretched lengths, the exit points given in the parameters, cdpr_robot_outputs.
/// Comparisons are exact where the packing is a plain conversion (the value must be the state
/// component converted to the wire type, bit for bit).
///
/// Why these can fail: a field taken from the wrong place (layout offset, node index, cable),
/// a lost sign or unit, a message carrying more or fewer cables than the robot, rounding of
/// utime_us, a shape subsampling that skips an end node or repeats one, a message that does not
/// survive encode/decode unchanged, or an allocation in packing, encoding or decoding.
#include "unity.h"

#include "alloc_count.h"
#include "cdpr/lcm/pack.h"
#include "cdpr/robot.h"
#include "cdpr/vec3.h"
#include "test_real.h"

#include <math.h>
#include <string.h>

#define PI_D     3.14159265358979323846
#define SEGMENTS 8

static cdpr_robot_t robot;
static cdpr_real_t y[CDPR_ROBOT_STATE_MAX];

// Regular polygon of n_cables (six: the hexagon of test_robot.c): exit points on radius 5 m at
// 6 m height, attachments radius 0.4 m.
static void make_robot(int n_cables)
{
    cdpr_robot_params_t p;
    cdpr_diag_t d;
    cdpr_cabin_motion_t m;
    int j;
    int i;

    cdpr_robot_params_default(&p);
    p.n_cables = n_cables;
    for (j = 0; j < n_cables; j++) {
        const double th = (double)j * 2.0 * PI_D / (double)n_cables;
        p.cables[j].exit_point_m =
            cdpr_v3((cdpr_real_t)(5.0 * cos(th)), (cdpr_real_t)(5.0 * sin(th)), CDPR_R(6.0));
        p.cables[j].attach_body_m =
            cdpr_v3((cdpr_real_t)(0.4 * cos(th)), (cdpr_real_t)(0.4 * sin(th)), CDPR_R(0.0));
        p.cables[j].n_segments = SEGMENTS;
        p.cables[j].length_m = CDPR_R(5.5);
    }
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_robot_init(&robot, &p, &d));

    m.p_m = cdpr_v3(CDPR_R(0.1), CDPR_R(-0.2), CDPR_R(2.0));
    m.q = cdpr_quat_from_euler(CDPR_R(0.05), CDPR_R(-0.03), CDPR_R(0.2));
    m.v_m_per_s = cdpr_v3(CDPR_R(0.3), CDPR_R(-0.1), CDPR_R(0.05));
    m.w_rad_per_s = cdpr_v3(CDPR_R(0.01), CDPR_R(0.02), CDPR_R(-0.03));
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_robot_place_straight(&robot, &m, y));
    // Give the free nodes distinct velocities/positions so a wrong index shows.
    for (i = 0; i < robot.dim; i++) {
        if (i >= CDPR_CABIN_STATE_DIM) {
            y[i] += (cdpr_real_t)(1e-3 * (double)(i % 17));
        }
    }
    for (j = 0; j < n_cables; j++) {
        robot.in.payout_m_per_s[j] = (cdpr_real_t)(0.1 * (double)(j + 1));
    }
}

void setUp(void)
{
    memset(&robot, 0, sizeof robot);
    memset(y, 0, sizeof y);
}

void tearDown(void) {}

// Exact: the wire value is the state value converted to double.
#define ASSERT_SAME_DOUBLE(expected_real, actual)                                                  \
    TEST_ASSERT_EQUAL_MEMORY(&(double){(double)(expected_real)}, &(actual), sizeof(double))

static void test_utime_rounds_to_nearest_microsecond(void)
{
    TEST_ASSERT_EQUAL_INT64(0, cdpr_lcm_utime_us(0.0));
    TEST_ASSERT_EQUAL_INT64(1000, cdpr_lcm_utime_us(0.001));
    TEST_ASSERT_EQUAL_INT64(60000000, cdpr_lcm_utime_us(60.0));
    TEST_ASSERT_EQUAL_INT64(2, cdpr_lcm_utime_us(1.6e-6));
    TEST_ASSERT_EQUAL_INT64(1, cdpr_lcm_utime_us(1.4e-6));
    TEST_ASSERT_EQUAL_INT64(-2, cdpr_lcm_utime_us(-1.6e-6));
    // 1 kHz for a day: k * 1e-3 s must give exactly k * 1000 us (no drift from rounding).
    TEST_ASSERT_EQUAL_INT64(86400000000LL, cdpr_lcm_utime_us(86400000.0 * 1e-3));
    TEST_ASSERT_EQUAL_INT64(123456789000LL, cdpr_lcm_utime_us(123456789.0 * 1e-3));
}

static void test_cabin_state_fields_come_from_the_state(void)
{
    cdpr_cabin_state_t s;
    const cdpr_real_t *c = y; // cabin block (cabin.h): p, q, v, w

    make_robot(6);
    memset(&s, 0x5A, sizeof s);
    cdpr_lcm_pack_cabin_state(&s, &robot, y, 1.25, 1250, 1249,
                              CDPR_CABIN_STATE_T_FLAG_HOLD | CDPR_CABIN_STATE_T_FLAG_LOCKSTEP);
    TEST_ASSERT_EQUAL_INT64(1250000, s.utime_us);
    TEST_ASSERT_EQUAL_INT64(1250, s.seq);
    TEST_ASSERT_EQUAL_INT64(1249, s.command_seq);
    TEST_ASSERT_EQUAL_INT32(33, s.flags);
    ASSERT_SAME_DOUBLE(c[CDPR_CABIN_P + 0], s.position_m[0]);
    ASSERT_SAME_DOUBLE(c[CDPR_CABIN_P + 1], s.position_m[1]);
    ASSERT_SAME_DOUBLE(c[CDPR_CABIN_P + 2], s.position_m[2]);
    ASSERT_SAME_DOUBLE(c[CDPR_CABIN_Q + 0], s.orientation[0]);
    ASSERT_SAME_DOUBLE(c[CDPR_CABIN_Q + 1], s.orientation[1]);
    ASSERT_SAME_DOUBLE(c[CDPR_CABIN_Q + 2], s.orientation[2]);
    ASSERT_SAME_DOUBLE(c[CDPR_CABIN_Q + 3], s.orientation[3]);
    ASSERT_SAME_DOUBLE(c[CDPR_CABIN_V + 0], s.velocity_m_per_s[0]);
    ASSERT_SAME_DOUBLE(c[CDPR_CABIN_V + 2], s.velocity_m_per_s[2]);
    ASSERT_SAME_DOUBLE(c[CDPR_CABIN_W + 0], s.angular_velocity_rad_per_s[0]);
    ASSERT_SAME_DOUBLE(c[CDPR_CABIN_W + 2], s.angular_velocity_rad_per_s[2]);
    // The angles the pose was built from (a round trip through the quaternion: a few
    // roundings of angles of size 0.2).
    TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-14, 1e-6), 0.05, s.euler_rad[0]);
    TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-14, 1e-6), -0.03, s.euler_rad[1]);
    TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-14, 1e-6), 0.2, s.euler_rad[2]);
}

// The wire carries exactly the robot's cables: the header (fingerprint, three int64, the count)
// and 4 doubles and one int32 per cable.
static void test_tensions_fields_and_size_follow_the_cable_count(void)
{
    static cdpr_lcm_wire_tensions_t t;
    static unsigned char buf[1024];
    cdpr_robot_out_t out;
    int j;

    make_robot(4);
    cdpr_robot_outputs(&robot, CDPR_R(0.5), y, &out);
    memset(&t, 0x5A, sizeof t); // unbound pointers: the packer binds them
    cdpr_lcm_pack_tensions(&t, &robot, y, &out, 0.5, 500);
    TEST_ASSERT_EQUAL_INT(1, cdpr_lcm_wire_tensions_ok(&t));
    TEST_ASSERT_EQUAL_INT64(500000, t.msg.utime_us);
    TEST_ASSERT_EQUAL_INT64(500, t.msg.seq);
    TEST_ASSERT_EQUAL_INT64(0, t.msg.plant_session); // the plant node sets it
    TEST_ASSERT_EQUAL_INT8(4, t.msg.n_cables);
    for (j = 0; j < 4; j++) {
        const cdpr_real_t *blk = y + robot.offset[j];
        double sum = 0.0;
        int k;
        for (k = 0; k < robot.cable[j].n - 1; k++) {
            sum += (double)robot.cable[j].lu_m[k];
        }
        sum += (double)blk[0]; // lu[n-1] lives in the state (cable.h)
        ASSERT_SAME_DOUBLE(out.tension_cabin_N[j], t.msg.tension_cabin_N[j]);
        ASSERT_SAME_DOUBLE(out.tension_winch_N[j], t.msg.tension_winch_N[j]);
        ASSERT_SAME_DOUBLE(robot.in.payout_m_per_s[j], t.msg.payout_m_per_s[j]);
        TEST_ASSERT_DOUBLE_WITHIN(TOL(1e-14, 1e-5), sum, t.msg.length_m[j]);
        TEST_ASSERT_EQUAL_INT32(SEGMENTS, t.msg.n_segments[j]);
        TEST_ASSERT_TRUE(t.msg.tension_cabin_N[j] >
                         0.0); // taut: 5.5 m unstretched, chords 5.9 .. 6.3 m
    }
    TEST_ASSERT_EQUAL_INT(8 + 3 * 8 + 1 + 4 * (4 * 8 + 4),
                          cdpr_lcm_wire_tensions_encode(&t, buf, (int)sizeof buf));
    make_robot(CDPR_MAX_CABLES);
    cdpr_robot_outputs(&robot, CDPR_R(0.5), y, &out);
    cdpr_lcm_pack_tensions(&t, &robot, y, &out, 0.5, 500);
    TEST_ASSERT_EQUAL_INT(8 + 3 * 8 + 1 + CDPR_MAX_CABLES * (4 * 8 + 4),
                          cdpr_lcm_wire_tensions_encode(&t, buf, (int)sizeof buf));
    ASSERT_SAME_DOUBLE(out.tension_winch_N[CDPR_MAX_CABLES - 1],
                       t.msg.tension_winch_N[CDPR_MAX_CABLES - 1]);
}

static void check_node(const cdpr_lcm_wire_shape_t *s, int k, double x, double y_m, double z)
{
    TEST_ASSERT_EQUAL_FLOAT((float)x, s->msg.node_x_m[k]);
    TEST_ASSERT_EQUAL_FLOAT((float)y_m, s->msg.node_y_m[k]);
    TEST_ASSERT_EQUAL_FLOAT((float)z, s->msg.node_z_m[k]);
}

// Every cable of the build's capacity, its nodes one cable after the other.
static void test_shape_nodes_run_from_attachment_to_exit_point(void)
{
    static cdpr_lcm_wire_shape_t s;
    cdpr_cabin_motion_t m;
    int first = 0;
    int j;

    make_robot(CDPR_MAX_CABLES);
    memset(&s, 0x5A, sizeof s);
    cdpr_lcm_pack_shape(&s, &robot, y, 2.0, 2000);
    cdpr_robot_cabin_motion(&robot, CDPR_R(2.0), y, &m);
    TEST_ASSERT_EQUAL_INT(1, cdpr_lcm_wire_shape_ok(&s));
    TEST_ASSERT_EQUAL_INT64(2000000, s.msg.utime_us);
    TEST_ASSERT_EQUAL_INT64(2000, s.msg.seq);
    TEST_ASSERT_EQUAL_INT8(CDPR_MAX_CABLES, s.msg.n_cables);
    TEST_ASSERT_EQUAL_INT32(CDPR_MAX_CABLES * (SEGMENTS + 1), s.msg.n_points);
    for (j = 0; j < CDPR_MAX_CABLES; j++) {
        cdpr_vec3_t a;
        cdpr_vec3_t av;
        const cdpr_vec3_t e = robot.p.cables[j].exit_point_m;
        const cdpr_real_t *pos = y + robot.offset[j] + 1;
        int i;
        TEST_ASSERT_EQUAL_INT32(SEGMENTS, s.msg.n_segments[j]);
        TEST_ASSERT_EQUAL_INT16(SEGMENTS + 1, s.msg.n_nodes[j]);
        cdpr_robot_attachment(&robot, j, &m, &a, &av);
        check_node(&s, first, (double)a.x, (double)a.y, (double)a.z);
        for (i = 1; i < SEGMENTS; i++) {
            check_node(&s, first + i, (double)pos[3 * (i - 1) + 0], (double)pos[3 * (i - 1) + 1],
                       (double)pos[3 * (i - 1) + 2]);
        }
        check_node(&s, first + SEGMENTS, (double)e.x, (double)e.y, (double)e.z);
        first += SEGMENTS + 1;
    }
}

// Subsampling for builds with more than 65 nodes per cable: first and last node always sent,
// indices strictly increasing, evenly spread (gaps differ by at most one).
static void test_shape_subsampling_indices(void)
{
    const int sizes[] = {66, 100, 129, 257, 4097};
    const int n_sent = CDPR_CABLE_SHAPE_T_MAX_NODES;
    size_t s;
    int i;

    for (i = 0; i < 10; i++) {
        TEST_ASSERT_EQUAL_INT(i, cdpr_lcm_shape_node_index(i, n_sent, 10)); // identity
    }
    for (s = 0; s < sizeof sizes / sizeof sizes[0]; s++) {
        const int n = sizes[s];
        int min_gap = n;
        int max_gap = 0;
        TEST_ASSERT_EQUAL_INT(0, cdpr_lcm_shape_node_index(0, n_sent, n));
        TEST_ASSERT_EQUAL_INT(n - 1, cdpr_lcm_shape_node_index(n_sent - 1, n_sent, n));
        for (i = 1; i < n_sent; i++) {
            const int gap = cdpr_lcm_shape_node_index(i, n_sent, n) -
                            cdpr_lcm_shape_node_index(i - 1, n_sent, n);
            min_gap = gap < min_gap ? gap : min_gap;
            max_gap = gap > max_gap ? gap : max_gap;
        }
        TEST_ASSERT_TRUE(min_gap >= 1);
        TEST_ASSERT_TRUE(max_gap - min_gap <= 1);
    }
    TEST_ASSERT_EQUAL_INT(2 * 17, cdpr_lcm_shape_node_index(17, 65, 129)); // exact halving
}

// Every message survives the encoders and decoders bit for bit, and packing, encoding and
// decoding the per-cable messages into their holders allocate nothing (the real-time thread
// packs and encodes every period; the controller decodes the tensions every period). The
// generated decoders (which allocate the arrays) read the same values.
static void test_messages_round_trip_without_allocation(void)
{
    static cdpr_cabin_state_t s;
    static cdpr_lcm_wire_tensions_t t;
    static cdpr_lcm_wire_shape_t sh;
    static cdpr_diagnostics_t dg;
    static cdpr_cabin_state_t s2;
    static cdpr_lcm_wire_tensions_t t2;
    static cdpr_cable_tensions_t t3;
    static cdpr_cable_shape_t sh3;
    static cdpr_diagnostics_t dg2;
    static unsigned char buf[16384];
    static unsigned char buf_t[1024];
    cdpr_robot_out_t out;
    int n;
    int nt;

    make_robot(CDPR_MAX_CABLES);
    memset(&dg, 0, sizeof dg);
    dg.seq = 7;
    dg.rejected[CDPR_DIAGNOSTICS_T_REJECT_FUTURE] = 3;
    dg.compute_ns_p99 = 12345;
    dg.holding = 1;
    cdpr_lcm_wire_tensions_init(&t2);
    cdpr_alloc_reset();
    cdpr_robot_outputs(&robot, CDPR_R(0.0), y, &out);
    cdpr_lcm_pack_cabin_state(&s, &robot, y, 0.0, 0, -1, 0);
    cdpr_lcm_pack_tensions(&t, &robot, y, &out, 0.0, 0);
    cdpr_lcm_pack_shape(&sh, &robot, y, 0.0, 0);

    n = cdpr_cabin_state_t_encode(buf, 0, (int)sizeof buf, &s);
    TEST_ASSERT_EQUAL_INT(n, cdpr_cabin_state_t_decode(buf, 0, n, &s2));
    nt = cdpr_lcm_wire_tensions_encode(&t, buf_t, (int)sizeof buf_t);
    TEST_ASSERT_TRUE(nt > 0);
    TEST_ASSERT_EQUAL_INT(CDPR_LCM_WIRE_OK, cdpr_lcm_wire_tensions_decode(&t2, buf_t, nt));
    n = cdpr_diagnostics_t_encode(buf, 0, (int)sizeof buf, &dg);
    TEST_ASSERT_EQUAL_INT(n, cdpr_diagnostics_t_decode(buf, 0, n, &dg2));
    n = cdpr_lcm_wire_shape_encode(&sh, buf, (int)sizeof buf);
    TEST_ASSERT_TRUE(n > 0);
    if (cdpr_alloc_counting_available()) {
        TEST_ASSERT_EQUAL_UINT(0u, cdpr_alloc_count());
    }
    // The generated decoders on the same bytes (they allocate: cleaned up below).
    TEST_ASSERT_EQUAL_INT(n, cdpr_cable_shape_t_decode(buf, 0, n, &sh3));
    TEST_ASSERT_EQUAL_INT(nt, cdpr_cable_tensions_t_decode(buf_t, 0, nt, &t3));

    // Compare field by field through memcmp of the members.
    TEST_ASSERT_EQUAL_MEMORY(s.position_m, s2.position_m, sizeof s.position_m);
    TEST_ASSERT_EQUAL_MEMORY(s.orientation, s2.orientation, sizeof s.orientation);
    TEST_ASSERT_EQUAL_MEMORY(s.euler_rad, s2.euler_rad, sizeof s.euler_rad);
    TEST_ASSERT_EQUAL_INT64(s.command_seq, s2.command_seq);
    TEST_ASSERT_EQUAL_INT8(CDPR_MAX_CABLES, t2.msg.n_cables);
    TEST_ASSERT_EQUAL_MEMORY(t.tension_cabin_N, t2.tension_cabin_N, sizeof t.tension_cabin_N);
    TEST_ASSERT_EQUAL_MEMORY(t.tension_winch_N, t2.tension_winch_N, sizeof t.tension_winch_N);
    TEST_ASSERT_EQUAL_MEMORY(t.length_m, t2.length_m, sizeof t.length_m);
    TEST_ASSERT_EQUAL_MEMORY(t.payout_m_per_s, t2.payout_m_per_s, sizeof t.payout_m_per_s);
    TEST_ASSERT_EQUAL_MEMORY(t.n_segments, t2.n_segments, sizeof t.n_segments);
    TEST_ASSERT_EQUAL_INT8(CDPR_MAX_CABLES, t3.n_cables);
    TEST_ASSERT_EQUAL_MEMORY(t.tension_winch_N, t3.tension_winch_N, sizeof t.tension_winch_N);
    TEST_ASSERT_EQUAL_MEMORY(t.n_segments, t3.n_segments, sizeof t.n_segments);
    TEST_ASSERT_EQUAL_INT32(sh.msg.n_points, sh3.n_points);
    TEST_ASSERT_EQUAL_MEMORY(sh.node_x_m, sh3.node_x_m, sizeof(float) * (size_t)sh3.n_points);
    TEST_ASSERT_EQUAL_MEMORY(sh.node_y_m, sh3.node_y_m, sizeof(float) * (size_t)sh3.n_points);
    TEST_ASSERT_EQUAL_MEMORY(sh.node_z_m, sh3.node_z_m, sizeof(float) * (size_t)sh3.n_points);
    TEST_ASSERT_EQUAL_MEMORY(sh.n_nodes, sh3.n_nodes, sizeof(int16_t) * CDPR_MAX_CABLES);
    TEST_ASSERT_EQUAL_MEMORY(dg.rejected, dg2.rejected, sizeof dg.rejected);
    TEST_ASSERT_EQUAL_INT64(12345, dg2.compute_ns_p99);
    TEST_ASSERT_EQUAL_INT8(1, dg2.holding);
    cdpr_cable_shape_t_decode_cleanup(&sh3);
    cdpr_cable_tensions_t_decode_cleanup(&t3);
    if (!cdpr_alloc_counting_available()) {
        TEST_IGNORE_MESSAGE(cdpr_alloc_unavailable_reason());
    }
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_utime_rounds_to_nearest_microsecond);
    RUN_TEST(test_cabin_state_fields_come_from_the_state);
    RUN_TEST(test_tensions_fields_and_size_follow_the_cable_count);
    RUN_TEST(test_shape_nodes_run_from_attachment_to_exit_point);
    RUN_TEST(test_shape_subsampling_indices);
    RUN_TEST(test_messages_round_trip_without_allocation);
    return UNITY_END() ? 1 : 0;
}
