/* SPDX-License-Identifier: BSD-3-Clause */
/// @file test_lcm_wire.c
/// The per-cable messages with storage (wire.h) against the generated LCM code.
///
/// The reference is lcm-gen's own encoder and decoder of the same .lcm files: every message the
/// generated encoder writes (0 .. CDPR_MAX_CABLES + 3 cables, random values) decodes into a
/// holder with the same fields bit for bit, or as over capacity beyond CDPR_MAX_CABLES; cut,
/// extended and corrupted byte strings are refused by the holder's decoder exactly when the
/// generated decoder does not consume them whole (a negative count, which the generated
/// decoder would hand to malloc, is checked on its own; the generated decoder's arrays are freed
/// after a failure too, since it allocates before it finds the bytes missing).
///
/// Why these can fail: a field read out of the .lcm order or at the wrong width, a count
/// trusted before the bytes behind it, trailing bytes accepted, a value read past the storage,
/// a holder copy that still points into its source, an encoder that runs on a holder whose
/// pointers or count do not fit it.
#include "unity.h"

#include "alloc_count.h"
#include "cdpr/lcm/wire.h"

#include <string.h>

#define TRIALS 400

static uint64_t g_rng = 0x9E3779B97F4A7C15u;

static uint32_t next_u32(void)
{
    g_rng = g_rng * 6364136223846793005u + 1442695040888963407u;
    return (uint32_t)(g_rng >> 33);
}

static double next_double(void)
{
    uint64_t bits = ((uint64_t)next_u32() << 32) | next_u32();
    double x;
    memcpy(&x, &bits, sizeof x); // any bit pattern: NaNs and infinities travel too
    return x;
}

void setUp(void) {}
void tearDown(void) {}

static void same_bits(const double *a, const double *b, int n)
{
    if (n > 0) {
        TEST_ASSERT_EQUAL_MEMORY(a, b, sizeof(double) * (size_t)n);
    }
}

/* Compare one byte string through both decoders. `count_at`: the offset of n_cables. */
static void check_command_bytes(const unsigned char *buf, int len, int count_at)
{
    static cdpr_lcm_wire_command_t w;
    cdpr_winch_command_t g;
    cdpr_lcm_wire_t r;
    int gn;

    cdpr_lcm_wire_command_init(&w);
    w.msg.seq = 424242; // must stay when refused
    r = cdpr_lcm_wire_command_decode(&w, buf, len);
    if (len > count_at && (signed char)buf[count_at] < 0) {
        // The generated decoder would malloc a negative size: ours must refuse it.
        TEST_ASSERT_TRUE(r != CDPR_LCM_WIRE_OK && r != CDPR_LCM_WIRE_OVER_CAPACITY);
        TEST_ASSERT_EQUAL_INT64(424242, w.msg.seq);
        return;
    }
    memset(&g, 0, sizeof g);
    gn = cdpr_winch_command_t_decode(buf, 0, len, &g);
    if (gn == len) {
        if (g.n_cables > CDPR_MAX_CABLES) {
            TEST_ASSERT_EQUAL_INT(CDPR_LCM_WIRE_OVER_CAPACITY, r);
        } else {
            TEST_ASSERT_EQUAL_INT(CDPR_LCM_WIRE_OK, r);
            TEST_ASSERT_EQUAL_INT64(g.utime_us, w.msg.utime_us);
            TEST_ASSERT_EQUAL_INT64(g.seq, w.msg.seq);
            TEST_ASSERT_EQUAL_INT64(g.state_seq, w.msg.state_seq);
            TEST_ASSERT_EQUAL_INT64(g.controller_session, w.msg.controller_session);
            TEST_ASSERT_EQUAL_INT64(g.plant_session, w.msg.plant_session);
            TEST_ASSERT_EQUAL_INT8(g.mode, w.msg.mode);
            TEST_ASSERT_EQUAL_INT8(g.n_cables, w.msg.n_cables);
            same_bits(g.value, w.value, g.n_cables);
            TEST_ASSERT_TRUE(w.msg.value == w.value);
        }
    } else {
        TEST_ASSERT_TRUE(r != CDPR_LCM_WIRE_OK && r != CDPR_LCM_WIRE_OVER_CAPACITY);
        TEST_ASSERT_EQUAL_INT64(424242, w.msg.seq);
    }
    cdpr_winch_command_t_decode_cleanup(&g); // also after a failure: it may have allocated
}

static void check_tensions_bytes(const unsigned char *buf, int len, int count_at)
{
    static cdpr_lcm_wire_tensions_t w;
    cdpr_cable_tensions_t g;
    cdpr_lcm_wire_t r;
    int gn;

    cdpr_lcm_wire_tensions_init(&w);
    w.msg.seq = 424242;
    r = cdpr_lcm_wire_tensions_decode(&w, buf, len);
    if (len > count_at && (signed char)buf[count_at] < 0) {
        TEST_ASSERT_TRUE(r != CDPR_LCM_WIRE_OK && r != CDPR_LCM_WIRE_OVER_CAPACITY);
        TEST_ASSERT_EQUAL_INT64(424242, w.msg.seq);
        return;
    }
    memset(&g, 0, sizeof g);
    gn = cdpr_cable_tensions_t_decode(buf, 0, len, &g);
    if (gn == len) {
        if (g.n_cables > CDPR_MAX_CABLES) {
            TEST_ASSERT_EQUAL_INT(CDPR_LCM_WIRE_OVER_CAPACITY, r);
        } else {
            TEST_ASSERT_EQUAL_INT(CDPR_LCM_WIRE_OK, r);
            TEST_ASSERT_EQUAL_INT64(g.utime_us, w.msg.utime_us);
            TEST_ASSERT_EQUAL_INT64(g.seq, w.msg.seq);
            TEST_ASSERT_EQUAL_INT64(g.plant_session, w.msg.plant_session);
            TEST_ASSERT_EQUAL_INT8(g.n_cables, w.msg.n_cables);
            same_bits(g.tension_cabin_N, w.tension_cabin_N, g.n_cables);
            same_bits(g.tension_winch_N, w.tension_winch_N, g.n_cables);
            same_bits(g.length_m, w.length_m, g.n_cables);
            same_bits(g.payout_m_per_s, w.payout_m_per_s, g.n_cables);
            if (g.n_cables > 0) {
                TEST_ASSERT_EQUAL_MEMORY(g.n_segments, w.n_segments,
                                         sizeof(int32_t) * (size_t)g.n_cables);
            }
            TEST_ASSERT_EQUAL_INT(1, cdpr_lcm_wire_tensions_ok(&w));
        }
    } else {
        TEST_ASSERT_TRUE(r != CDPR_LCM_WIRE_OK && r != CDPR_LCM_WIRE_OVER_CAPACITY);
        TEST_ASSERT_EQUAL_INT64(424242, w.msg.seq);
    }
    cdpr_cable_tensions_t_decode_cleanup(&g); // also after a failure: it may have allocated
}

/* The byte strings of one encoded message: itself, every cut, two extensions, and 8 single
 * corrupted bytes. */
typedef void (*check_fn)(const unsigned char *buf, int len, int count_at);

static void mutate_and_check(const unsigned char *enc, int n, int count_at, check_fn check)
{
    static unsigned char buf[4096];
    int k;

    memcpy(buf, enc, (size_t)n);
    check(buf, n, count_at);
    for (k = 0; k < n; k++) {
        check(buf, k, count_at); // cut
    }
    buf[n] = 0;
    buf[n + 1] = 7;
    check(buf, n + 1, count_at); // trailing bytes
    check(buf, n + 2, count_at);
    for (k = 0; k < 8; k++) {
        const int at = (k == 0) ? count_at : (int)(next_u32() % (uint32_t)n);
        memcpy(buf, enc, (size_t)n);
        buf[at] = (unsigned char)next_u32();
        check(buf, n, count_at);
    }
}

static void test_commands_decode_as_the_generated_decoder_does(void)
{
    static unsigned char enc[4096];
    static double values[CDPR_MAX_CABLES + 3];
    int t;
    int over = 0;

    for (t = 0; t < TRIALS; t++) {
        cdpr_winch_command_t m;
        const int nc = (int)(next_u32() % (uint32_t)(CDPR_MAX_CABLES + 4));
        int j;
        int n;

        memset(&m, 0, sizeof m);
        m.utime_us = (int64_t)next_u32() << 20;
        m.seq = (int64_t)next_u32() - 5;
        m.state_seq = (int64_t)next_u32();
        m.controller_session = (int64_t)next_u32() << 30;
        m.plant_session = (int64_t)next_u32();
        m.mode = (int8_t)(next_u32() % 3u);
        m.n_cables = (int8_t)nc;
        for (j = 0; j < nc; j++) {
            values[j] = next_double();
        }
        m.value = values;
        n = cdpr_winch_command_t_encode(enc, 0, (int)sizeof enc, &m);
        TEST_ASSERT_EQUAL_INT(8 + 5 * 8 + 2 + 8 * nc, n);
        over += (nc > CDPR_MAX_CABLES) ? 1 : 0;
        mutate_and_check(enc, n, 8 + 5 * 8 + 1, check_command_bytes);
    }
    TEST_ASSERT_TRUE(over > 0); // the over-capacity path was taken
}

static void test_tensions_decode_as_the_generated_decoder_does(void)
{
    static unsigned char enc[4096];
    static double a[4][CDPR_MAX_CABLES + 3];
    static int32_t segs[CDPR_MAX_CABLES + 3];
    int t;

    for (t = 0; t < TRIALS; t++) {
        cdpr_cable_tensions_t m;
        const int nc = (int)(next_u32() % (uint32_t)(CDPR_MAX_CABLES + 4));
        int j;
        int n;

        memset(&m, 0, sizeof m);
        m.utime_us = (int64_t)next_u32() << 20;
        m.seq = (int64_t)next_u32();
        m.plant_session = (int64_t)next_u32();
        m.n_cables = (int8_t)nc;
        for (j = 0; j < nc; j++) {
            a[0][j] = next_double();
            a[1][j] = next_double();
            a[2][j] = next_double();
            a[3][j] = next_double();
            segs[j] = (int32_t)next_u32();
        }
        m.tension_cabin_N = a[0];
        m.tension_winch_N = a[1];
        m.length_m = a[2];
        m.payout_m_per_s = a[3];
        m.n_segments = segs;
        n = cdpr_cable_tensions_t_encode(enc, 0, (int)sizeof enc, &m);
        TEST_ASSERT_EQUAL_INT(8 + 3 * 8 + 1 + 36 * nc, n);
        mutate_and_check(enc, n, 8 + 3 * 8, check_tensions_bytes);
    }
}

// Holders: a copy points into itself; decoding allocates nothing; encoders refuse a holder
// whose pointers were changed or whose count does not fit, and a buffer too small.
static void test_holders_copy_encode_and_refuse(void)
{
    static cdpr_lcm_wire_tensions_t a;
    static cdpr_lcm_wire_tensions_t b;
    static cdpr_lcm_wire_command_t c;
    static cdpr_lcm_wire_shape_t s;
    unsigned char buf[1024];
    int n;

    cdpr_lcm_wire_tensions_init(&a);
    a.msg.n_cables = (int8_t)CDPR_MAX_CABLES;
    a.tension_winch_N[CDPR_MAX_CABLES - 1] = 123.0;
    memset(&b, 0x77, sizeof b);
    cdpr_lcm_wire_tensions_copy(&b, &a);
    TEST_ASSERT_TRUE(b.msg.tension_winch_N == b.tension_winch_N);
    TEST_ASSERT_EQUAL_INT(1, cdpr_lcm_wire_tensions_ok(&b));
    a.tension_winch_N[CDPR_MAX_CABLES - 1] = 0.0;
    TEST_ASSERT_EQUAL_DOUBLE(123.0, b.msg.tension_winch_N[CDPR_MAX_CABLES - 1]);

    n = cdpr_lcm_wire_tensions_encode(&b, buf, (int)sizeof buf);
    TEST_ASSERT_TRUE(n > 0);
    cdpr_alloc_reset();
    TEST_ASSERT_EQUAL_INT(CDPR_LCM_WIRE_OK, cdpr_lcm_wire_tensions_decode(&a, buf, n));
    if (cdpr_alloc_counting_available()) {
        TEST_ASSERT_EQUAL_UINT(0u, cdpr_alloc_count());
    }
    TEST_ASSERT_EQUAL_DOUBLE(123.0, a.tension_winch_N[CDPR_MAX_CABLES - 1]);
    TEST_ASSERT_EQUAL_INT(-1, cdpr_lcm_wire_tensions_encode(&b, buf, n - 1));

    b = a; // an assignment: b's pointers now point into a
    TEST_ASSERT_EQUAL_INT(0, cdpr_lcm_wire_tensions_ok(&b));
    TEST_ASSERT_EQUAL_INT(-1, cdpr_lcm_wire_tensions_encode(&b, buf, (int)sizeof buf));
    cdpr_lcm_wire_tensions_init(&b);
    b.msg.n_cables = (int8_t)(CDPR_MAX_CABLES + 1);
    TEST_ASSERT_EQUAL_INT(-1, cdpr_lcm_wire_tensions_encode(&b, buf, (int)sizeof buf));
    b.msg.n_cables = -1;
    TEST_ASSERT_EQUAL_INT(-1, cdpr_lcm_wire_tensions_encode(&b, buf, (int)sizeof buf));

    cdpr_lcm_wire_command_init(&c);
    c.msg.n_cables = (int8_t)(CDPR_MAX_CABLES + 1);
    TEST_ASSERT_EQUAL_INT(-1, cdpr_lcm_wire_command_encode(&c, buf, (int)sizeof buf));
    c.msg.n_cables = (int8_t)CDPR_MAX_CABLES;
    TEST_ASSERT_EQUAL_INT(8 + 5 * 8 + 2 + 8 * CDPR_MAX_CABLES,
                          cdpr_lcm_wire_command_encode(&c, buf, (int)sizeof buf));
    TEST_ASSERT_EQUAL_INT(-1, cdpr_lcm_wire_command_encode(NULL, buf, (int)sizeof buf));

    cdpr_lcm_wire_shape_init(&s);
    s.msg.n_cables = 1;
    s.msg.n_points = CDPR_LCM_SHAPE_MAX_POINTS + 1;
    TEST_ASSERT_EQUAL_INT(0, cdpr_lcm_wire_shape_ok(&s));
    TEST_ASSERT_EQUAL_INT(-1, cdpr_lcm_wire_shape_encode(&s, buf, (int)sizeof buf));

    // Another type's bytes, and fewer than 8: the wrong type.
    n = cdpr_lcm_wire_tensions_encode(&a, buf, (int)sizeof buf);
    TEST_ASSERT_TRUE(n > 0);
    TEST_ASSERT_EQUAL_INT(CDPR_LCM_WIRE_WRONG_TYPE, cdpr_lcm_wire_command_decode(&c, buf, n));
    TEST_ASSERT_EQUAL_INT(CDPR_LCM_WIRE_WRONG_TYPE, cdpr_lcm_wire_tensions_decode(&a, buf, 7));
    TEST_ASSERT_EQUAL_INT(CDPR_LCM_WIRE_WRONG_TYPE, cdpr_lcm_wire_tensions_decode(&a, NULL, 64));
    if (!cdpr_alloc_counting_available()) {
        TEST_IGNORE_MESSAGE(cdpr_alloc_unavailable_reason());
    }
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_commands_decode_as_the_generated_decoder_does);
    RUN_TEST(test_tensions_decode_as_the_generated_decoder_does);
    RUN_TEST(test_holders_copy_encode_and_refuse);
    return UNITY_END() ? 1 : 0;
}
