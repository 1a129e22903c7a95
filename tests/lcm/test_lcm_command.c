/* SPDX-License-Identifier: BSD-3-Clause */
/// @file test_lcm_command.c
/// Winch command validation, decoding of malformed bytes through the generated decoder, the
/// latest-value mailbox and the watchdog (lcm_command.h). No LCM transport: bytes are made
/// with the generated encoder and fed to cdpr_lcm_validator_accept, exactly what the bridge's
/// subscription handler does with a received payload.
///
/// Why these can fail: a rule that lets a bad command through or rejects a good one, a bad
/// command counted under the wrong reason (or twice, or not at all), a rejected command that
/// still changes the sequence state or the mailbox, a decoder that reads past `len` (ASan) or
/// accepts truncated/trailing bytes, a mailbox that returns a torn or older command, a
/// watchdog that does not hold after the timeout or does not resume, or an allocation on the
/// real-time read path.
#include "unity.h"

#include "alloc_count.h"
#include "cdpr/lcm/command.h"
#include "lcmtypes/cdpr_cabin_state_t.h"

#include <math.h>
#include <pthread.h>
#include <stdint.h>
#include <string.h>

#define N_CABLES 6
#define U_MAX    4.0 // winch defaults (winch.h): u_max 4 m/s, min length 0.5 m
#define L_MIN    0.5
#define L_MAX    120.0              // our chosen longest setpoint
#define MS       ((int64_t)1000000) // [ns]
#define PLANT    ((int64_t)7777)    // this plant's session
#define CTRL_A   ((int64_t)5555)    // the controller sessions of the tests
#define CTRL_B   ((int64_t)6666)
#define TAKEOVER (100 * MS) // silence after which another session may take over

static cdpr_lcm_validator_t v;

void setUp(void)
{
    cdpr_winch_params_t w[CDPR_MAX_CABLES];
    cdpr_lcm_limits_t lim;
    cdpr_diag_t d;
    int j;
    for (j = 0; j < CDPR_MAX_CABLES; j++) {
        cdpr_winch_params_default(&w[j]);
    }
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_lcm_limits_from_winch(&lim, N_CABLES, w, L_MAX, &d));
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_lcm_validator_init(&v, &lim, PLANT, TAKEOVER, &d));
    cdpr_lcm_validator_note_published(&v, 1000); // states 0..1000 exist
}

void tearDown(void) {}

// The values of every message the tests build (the message holds a pointer: LCM sizes its array
// by n_cables): good_rate resets them, so a test changes one value after calling it. Room for
// the largest count the wire can carry (int8_t).
static double g_value[127];

static cdpr_winch_command_t good_rate(int64_t seq, int64_t state_seq)
{
    cdpr_winch_command_t m;
    int j;
    memset(&m, 0, sizeof m);
    memset(g_value, 0, sizeof g_value);
    m.value = g_value;
    m.utime_us = 123456;
    m.seq = seq;
    m.state_seq = state_seq;
    m.controller_session = CTRL_A;
    m.plant_session = PLANT;
    m.mode = CDPR_WINCH_COMMAND_T_MODE_RATE;
    m.n_cables = N_CABLES;
    for (j = 0; j < N_CABLES; j++) {
        m.value[j] = 0.5 * (double)(j - 2); // -1 .. 1.5 m/s
    }
    return m;
}

static int encode(const cdpr_winch_command_t *m, unsigned char *buf, int cap)
{
    const int n = cdpr_winch_command_t_encode(buf, 0, cap, m);
    TEST_ASSERT_TRUE(n > 8);
    return n;
}

static cdpr_lcm_reject_t feed_at(const cdpr_winch_command_t *m, int64_t rx_ns,
                                 cdpr_lcm_command_t *out)
{
    unsigned char buf[2048];
    const int n = encode(m, buf, (int)sizeof buf);
    return cdpr_lcm_validator_accept(&v, buf, (size_t)n, rx_ns, out);
}

static cdpr_lcm_reject_t feed(const cdpr_winch_command_t *m, cdpr_lcm_command_t *out)
{
    return feed_at(m, 42, out);
}

static uint64_t rejected(cdpr_lcm_reject_t r)
{
    uint64_t rej[CDPR_LCM_N_REJECT];
    cdpr_lcm_validator_counts(&v, NULL, rej, NULL);
    return rej[r];
}

static uint64_t total_rejected(void)
{
    uint64_t rej[CDPR_LCM_N_REJECT];
    uint64_t sum = 0u;
    int i;
    cdpr_lcm_validator_counts(&v, NULL, rej, NULL);
    for (i = 0; i < CDPR_LCM_N_REJECT; i++) {
        sum += rej[i];
    }
    return sum;
}

static void test_limits_validation_names_the_field(void)
{
    cdpr_winch_params_t w[CDPR_MAX_CABLES];
    cdpr_lcm_limits_t lim;
    cdpr_diag_t d;
    int j;
    for (j = 0; j < CDPR_MAX_CABLES; j++) {
        cdpr_winch_params_default(&w[j]);
    }
    TEST_ASSERT_EQUAL_INT(CDPR_E_CAPACITY, cdpr_lcm_limits_from_winch(&lim, 0, w, L_MAX, &d));
    TEST_ASSERT_EQUAL_INT(CDPR_E_CAPACITY,
                          cdpr_lcm_limits_from_winch(&lim, CDPR_MAX_CABLES + 1, w, L_MAX, &d));
    TEST_ASSERT_EQUAL_INT(CDPR_E_NOT_FINITE,
                          cdpr_lcm_limits_from_winch(&lim, N_CABLES, w, (double)NAN, &d));
    TEST_ASSERT_EQUAL_STRING("max_length_m", d.field);
    TEST_ASSERT_EQUAL_INT(CDPR_E_OUT_OF_RANGE,
                          cdpr_lcm_limits_from_winch(&lim, N_CABLES, w, 0.4, &d));
    TEST_ASSERT_EQUAL_STRING("max_length_m", d.field);
    w[3].u_max_m_per_s = -1.0;
    TEST_ASSERT_EQUAL_INT(CDPR_E_NOT_POSITIVE,
                          cdpr_lcm_limits_from_winch(&lim, N_CABLES, w, L_MAX, &d));
    TEST_ASSERT_EQUAL_STRING("u_max_m_per_s", d.field);
    TEST_ASSERT_EQUAL_INT(3, d.index);
    w[3].u_max_m_per_s = 4.0;
    w[5].min_length_m = (cdpr_real_t)INFINITY;
    TEST_ASSERT_EQUAL_INT(CDPR_E_NOT_FINITE,
                          cdpr_lcm_limits_from_winch(&lim, N_CABLES, w, L_MAX, &d));
    TEST_ASSERT_EQUAL_STRING("min_length_m", d.field);
    TEST_ASSERT_EQUAL_INT(5, d.index);
}

static void test_good_commands_are_accepted_in_both_modes(void)
{
    cdpr_lcm_command_t out;
    cdpr_winch_command_t m = good_rate(1, 10);
    uint64_t acc;
    int64_t last;
    int j;

    TEST_ASSERT_EQUAL_INT(CDPR_LCM_ACCEPTED, feed(&m, &out));
    TEST_ASSERT_EQUAL_INT64(1, out.seq);
    TEST_ASSERT_EQUAL_INT64(10, out.state_seq);
    TEST_ASSERT_EQUAL_INT64(123456, out.utime_us);
    TEST_ASSERT_EQUAL_INT64(42, out.rx_time_ns);
    TEST_ASSERT_EQUAL_INT(CDPR_WINCH_RATE, out.mode);
    TEST_ASSERT_EQUAL_INT(N_CABLES, out.n_cables);
    for (j = 0; j < N_CABLES; j++) {
        TEST_ASSERT_EQUAL_DOUBLE(m.value[j], out.value[j]); // bit-exact through the wire
    }

    // Length mode at both ends of the range; the same state answered twice is fine.
    m = good_rate(2, 10);
    m.mode = CDPR_WINCH_COMMAND_T_MODE_LENGTH;
    for (j = 0; j < N_CABLES; j++) {
        m.value[j] = j % 2 == 0 ? L_MIN : L_MAX;
    }
    TEST_ASSERT_EQUAL_INT(CDPR_LCM_ACCEPTED, feed(&m, &out));
    TEST_ASSERT_EQUAL_INT(CDPR_WINCH_LENGTH, out.mode);
    // Rate exactly at +-u_max.
    m = good_rate(3, 11);
    m.value[0] = U_MAX;
    m.value[1] = -U_MAX;
    TEST_ASSERT_EQUAL_INT(CDPR_LCM_ACCEPTED, feed(&m, &out));
    // Sequence gaps are fine (a controller may skip).
    m = good_rate(1000, 1000);
    TEST_ASSERT_EQUAL_INT(CDPR_LCM_ACCEPTED, feed(&m, &out));

    cdpr_lcm_validator_counts(&v, &acc, NULL, &last);
    TEST_ASSERT_EQUAL_UINT64(4u, acc);
    TEST_ASSERT_EQUAL_INT64(1000, last);
    TEST_ASSERT_EQUAL_UINT64(0u, total_rejected());
}

// Each bad case is rejected with its own reason, counted once, leaves the sequence state as
// it was (so the next good command is judged against the last GOOD one) and writes nothing.
static void expect_reject(cdpr_winch_command_t m, cdpr_lcm_reject_t reason)
{
    cdpr_lcm_command_t out;
    const uint64_t before = rejected(reason);
    const uint64_t total_before = total_rejected();
    const int64_t last_seq = v.last_seq;
    const int64_t last_state = v.last_state_seq;

    memset(&out, 0xAB, sizeof out);
    TEST_ASSERT_EQUAL_STRING(cdpr_lcm_reject_str(reason), cdpr_lcm_reject_str(feed(&m, &out)));
    TEST_ASSERT_EQUAL_UINT64(before + 1u, rejected(reason));
    TEST_ASSERT_EQUAL_UINT64(total_before + 1u, total_rejected());
    TEST_ASSERT_EQUAL_INT64(last_seq, v.last_seq);
    TEST_ASSERT_EQUAL_INT64(last_state, v.last_state_seq);
    TEST_ASSERT_EQUAL_HEX8(0xAB, ((unsigned char *)&out)[0]); // out untouched
}

static void test_every_bad_field_is_rejected_with_its_reason(void)
{
    cdpr_lcm_command_t out;
    cdpr_winch_command_t m;
    const double nonfinite[3] = {(double)NAN, (double)INFINITY, -(double)INFINITY};
    int j;
    int k;

    m = good_rate(5, 50);
    TEST_ASSERT_EQUAL_INT(CDPR_LCM_ACCEPTED, feed(&m, &out)); // last good: seq 5, state 50

    // NaN / +-Inf in every entry.
    for (k = 0; k < 3; k++) {
        for (j = 0; j < N_CABLES; j++) {
            m = good_rate(6, 50);
            m.value[j] = nonfinite[k];
            expect_reject(m, CDPR_LCM_REJECT_NOT_FINITE);
        }
    }
    // NaN in length mode too.
    m = good_rate(6, 50);
    m.mode = CDPR_WINCH_COMMAND_T_MODE_LENGTH;
    m.value[2] = (double)NAN;
    expect_reject(m, CDPR_LCM_REJECT_NOT_FINITE);

    // Unknown modes.
    m = good_rate(6, 50);
    m.mode = 2;
    expect_reject(m, CDPR_LCM_REJECT_BAD_MODE);
    m.mode = -1;
    expect_reject(m, CDPR_LCM_REJECT_BAD_MODE);
    m.mode = 127;
    expect_reject(m, CDPR_LCM_REJECT_BAD_MODE);

    // Cable count: one less, one more, zero, more than the build holds, the most the wire
    // carries (each a well-formed message of that many values).
    m = good_rate(6, 50);
    m.n_cables = N_CABLES - 1;
    expect_reject(m, CDPR_LCM_REJECT_CABLE_COUNT);
    m.n_cables = N_CABLES + 1;
    expect_reject(m, CDPR_LCM_REJECT_CABLE_COUNT);
    m.n_cables = 0;
    expect_reject(m, CDPR_LCM_REJECT_CABLE_COUNT);
    m.n_cables = CDPR_MAX_CABLES + 1;
    expect_reject(m, CDPR_LCM_REJECT_CABLE_COUNT);
    m.n_cables = 127;
    expect_reject(m, CDPR_LCM_REJECT_CABLE_COUNT);

    // Out of the winch limits, on every cable: rate just above +-u_max, length below the
    // minimum, above the maximum, zero, negative.
    for (j = 0; j < N_CABLES; j++) {
        m = good_rate(6, 50);
        m.value[j] = nextafter(U_MAX, 1e9);
        expect_reject(m, CDPR_LCM_REJECT_OUT_OF_LIMIT);
        m.value[j] = -nextafter(U_MAX, 1e9);
        expect_reject(m, CDPR_LCM_REJECT_OUT_OF_LIMIT);
        m = good_rate(6, 50);
        m.mode = CDPR_WINCH_COMMAND_T_MODE_LENGTH;
        {
            int i;
            for (i = 0; i < N_CABLES; i++) {
                m.value[i] = 10.0;
            }
        }
        m.value[j] = nextafter(L_MIN, 0.0);
        expect_reject(m, CDPR_LCM_REJECT_OUT_OF_LIMIT);
        m.value[j] = nextafter(L_MAX, 1e9);
        expect_reject(m, CDPR_LCM_REJECT_OUT_OF_LIMIT);
        m.value[j] = 0.0;
        expect_reject(m, CDPR_LCM_REJECT_OUT_OF_LIMIT);
        m.value[j] = -10.0;
        expect_reject(m, CDPR_LCM_REJECT_OUT_OF_LIMIT);
    }

    // Sequence: older seq (stale), the same seq again (replayed: the exact good message and a
    // modified one), an older answered state (stale), a negative state, a future state.
    m = good_rate(4, 50);
    expect_reject(m, CDPR_LCM_REJECT_STALE);
    m = good_rate(-1, 50);
    expect_reject(m, CDPR_LCM_REJECT_STALE);
    m = good_rate(5, 50);
    expect_reject(m, CDPR_LCM_REJECT_REPLAYED);
    m.value[0] = 1.0;
    expect_reject(m, CDPR_LCM_REJECT_REPLAYED);
    m = good_rate(6, 49);
    expect_reject(m, CDPR_LCM_REJECT_STALE);
    m = good_rate(6, -1);
    expect_reject(m, CDPR_LCM_REJECT_STALE);
    m = good_rate(6, 1001);
    expect_reject(m, CDPR_LCM_REJECT_FUTURE);
    cdpr_lcm_validator_note_published(&v, 1001);
    TEST_ASSERT_EQUAL_INT(CDPR_LCM_ACCEPTED, feed(&m, &out)); // now that state exists

    // The first failing rule names the reason: NaN + bad mode -> mode (checked first).
    m = good_rate(7, 1001);
    m.mode = 9;
    m.value[0] = (double)NAN;
    expect_reject(m, CDPR_LCM_REJECT_BAD_MODE);
}

// Bytes the generated encoder would never write: a negative cable count (the count byte of a
// good message patched), a count larger than the values that follow, values beyond the count.
static void test_counts_that_do_not_match_the_bytes_are_malformed(void)
{
    static unsigned char buf[2048];
    cdpr_lcm_command_t out;
    cdpr_winch_command_t m = good_rate(6, 50);
    const int at = 8 + 5 * 8 + 1; // fingerprint, five int64, mode: then n_cables
    int n;

    m.n_cables = 0;
    n = encode(&m, buf, (int)sizeof buf);
    TEST_ASSERT_EQUAL_INT(at + 1, n);
    buf[at] = 0xFA; // -6
    TEST_ASSERT_EQUAL_INT(CDPR_LCM_REJECT_MALFORMED,
                          cdpr_lcm_validator_accept(&v, buf, (size_t)n, 42, &out));
    m = good_rate(6, 50);
    n = encode(&m, buf, (int)sizeof buf);
    TEST_ASSERT_EQUAL_INT(at + 1 + 8 * N_CABLES, n);
    buf[at] = (unsigned char)(N_CABLES + 1); // one value short
    TEST_ASSERT_EQUAL_INT(CDPR_LCM_REJECT_MALFORMED,
                          cdpr_lcm_validator_accept(&v, buf, (size_t)n, 42, &out));
    buf[at] = (unsigned char)(N_CABLES - 1); // one value too many
    TEST_ASSERT_EQUAL_INT(CDPR_LCM_REJECT_MALFORMED,
                          cdpr_lcm_validator_accept(&v, buf, (size_t)n, 42, &out));
    buf[at] = 100; // over the capacity, and the values are not there
    TEST_ASSERT_EQUAL_INT(CDPR_LCM_REJECT_MALFORMED,
                          cdpr_lcm_validator_accept(&v, buf, (size_t)n, 42, &out));
    buf[at] = (unsigned char)N_CABLES;
    TEST_ASSERT_EQUAL_INT(CDPR_LCM_ACCEPTED,
                          cdpr_lcm_validator_accept(&v, buf, (size_t)n, 42, &out));
}

// A plant of the build's capacity (eight cables by default): its command carries every value,
// a six-cable command is refused, and the values arrive bit for bit.
static void test_a_plant_of_the_build_capacity_takes_its_commands(void)
{
    cdpr_winch_params_t w[CDPR_MAX_CABLES];
    cdpr_lcm_limits_t lim;
    cdpr_lcm_validator_t big;
    cdpr_lcm_command_t out;
    unsigned char buf[1024];
    cdpr_winch_command_t m = good_rate(1, 0);
    int n;
    int j;

    for (j = 0; j < CDPR_MAX_CABLES; j++) {
        cdpr_winch_params_default(&w[j]);
    }
    TEST_ASSERT_EQUAL_INT(CDPR_OK,
                          cdpr_lcm_limits_from_winch(&lim, CDPR_MAX_CABLES, w, L_MAX, NULL));
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_lcm_validator_init(&big, &lim, PLANT, TAKEOVER, NULL));
    cdpr_lcm_validator_note_published(&big, 0);
    n = encode(&m, buf, (int)sizeof buf); // N_CABLES values
    TEST_ASSERT_EQUAL_INT(N_CABLES == CDPR_MAX_CABLES ? CDPR_LCM_ACCEPTED
                                                      : CDPR_LCM_REJECT_CABLE_COUNT,
                          cdpr_lcm_validator_accept(&big, buf, (size_t)n, 0, &out));
    m.n_cables = CDPR_MAX_CABLES;
    for (j = 0; j < CDPR_MAX_CABLES; j++) {
        g_value[j] = -1.0 + 0.25 * (double)j;
    }
    m.seq = 2;
    n = encode(&m, buf, (int)sizeof buf);
    TEST_ASSERT_EQUAL_INT(CDPR_LCM_ACCEPTED,
                          cdpr_lcm_validator_accept(&big, buf, (size_t)n, 0, &out));
    TEST_ASSERT_EQUAL_INT(CDPR_MAX_CABLES, out.n_cables);
    TEST_ASSERT_EQUAL_MEMORY(g_value, out.value, sizeof(double) * CDPR_MAX_CABLES);
}

static void test_a_fresh_validator_rejects_commands_before_any_state(void)
{
    cdpr_lcm_validator_t fresh;
    cdpr_lcm_command_t out;
    unsigned char buf[256];
    cdpr_winch_command_t m = good_rate(0, 0);
    const int n = encode(&m, buf, (int)sizeof buf);

    TEST_ASSERT_EQUAL_INT(CDPR_E_NOT_POSITIVE,
                          cdpr_lcm_validator_init(&fresh, &v.lim, 0, TAKEOVER, NULL));
    TEST_ASSERT_EQUAL_INT(CDPR_E_NOT_POSITIVE,
                          cdpr_lcm_validator_init(&fresh, &v.lim, PLANT, 0, NULL));
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_lcm_validator_init(&fresh, &v.lim, PLANT, TAKEOVER, NULL));
    TEST_ASSERT_EQUAL_INT(CDPR_LCM_REJECT_FUTURE,
                          cdpr_lcm_validator_accept(&fresh, buf, (size_t)n, 0, &out));
    cdpr_lcm_validator_note_published(&fresh, 0);
    TEST_ASSERT_EQUAL_INT(CDPR_LCM_ACCEPTED,
                          cdpr_lcm_validator_accept(&fresh, buf, (size_t)n, 0, &out));
}

// Sessions and the sequence window (command.h, "Sessions"): one far-future seq is refused and
// never adopted; a second controller cannot take the winches from a live one; a new session
// takes over after the active one has been silent for the take-over time, whatever its seq;
// state_seq never goes back across sessions; another plant's commands are refused.
static void test_sessions_and_the_sequence_window(void)
{
    cdpr_lcm_command_t out;
    cdpr_winch_command_t m;
    int64_t session = -1;
    uint64_t sessions = 99u;

    cdpr_lcm_validator_sessions(&v, &session, &sessions);
    TEST_ASSERT_EQUAL_INT64(0, session);
    TEST_ASSERT_EQUAL_UINT64(0u, sessions);
    m = good_rate(5, 50);
    TEST_ASSERT_EQUAL_INT(CDPR_LCM_ACCEPTED, feed_at(&m, 0, &out));
    TEST_ASSERT_EQUAL_INT64(CTRL_A, out.controller_session);
    cdpr_lcm_validator_sessions(&v, &session, &sessions);
    TEST_ASSERT_EQUAL_INT64(CTRL_A, session);
    TEST_ASSERT_EQUAL_UINT64(1u, sessions);

    // Poisoned sequence numbers of the live session: refused, counted, never adopted.
    m = good_rate(INT64_MAX - 10, 51);
    TEST_ASSERT_EQUAL_INT(CDPR_LCM_REJECT_SEQ_WINDOW, feed_at(&m, 1 * MS, &out));
    m = good_rate(INT64_MAX, 51);
    TEST_ASSERT_EQUAL_INT(CDPR_LCM_REJECT_SEQ_WINDOW, feed_at(&m, 1 * MS, &out));
    m = good_rate(5 + CDPR_LCM_SEQ_WINDOW + 1, 51);
    TEST_ASSERT_EQUAL_INT(CDPR_LCM_REJECT_SEQ_WINDOW, feed_at(&m, 1 * MS, &out));
    TEST_ASSERT_EQUAL_UINT64(3u, rejected(CDPR_LCM_REJECT_SEQ_WINDOW));
    TEST_ASSERT_EQUAL_INT64(5, v.last_seq);
    m = good_rate(6, 51); // the honest controller goes on
    TEST_ASSERT_EQUAL_INT(CDPR_LCM_ACCEPTED, feed_at(&m, 2 * MS, &out));
    m = good_rate(6 + CDPR_LCM_SEQ_WINDOW, 52); // the window's edge is inside
    TEST_ASSERT_EQUAL_INT(CDPR_LCM_ACCEPTED, feed_at(&m, 3 * MS, &out));
    const int64_t last = m.seq;

    // Another controller while A is live; another plant; no session.
    m = good_rate(0, 53);
    m.controller_session = CTRL_B;
    TEST_ASSERT_EQUAL_INT(CDPR_LCM_REJECT_SESSION_BUSY, feed_at(&m, 3 * MS + TAKEOVER, &out));
    m = good_rate(last + 1, 53);
    m.plant_session = PLANT + 1;
    TEST_ASSERT_EQUAL_INT(CDPR_LCM_REJECT_OTHER_PLANT, feed_at(&m, 4 * MS, &out));
    m.plant_session = 0;
    TEST_ASSERT_EQUAL_INT(CDPR_LCM_REJECT_OTHER_PLANT, feed_at(&m, 4 * MS, &out));
    m = good_rate(last + 1, 53);
    m.controller_session = 0;
    TEST_ASSERT_EQUAL_INT(CDPR_LCM_REJECT_NO_SESSION, feed_at(&m, 4 * MS, &out));
    m.controller_session = -CTRL_A;
    TEST_ASSERT_EQUAL_INT(CDPR_LCM_REJECT_NO_SESSION, feed_at(&m, 4 * MS, &out));
    TEST_ASSERT_EQUAL_INT64(last, v.last_seq);

    // A silent (last accepted at 3 ms): B takes over one take-over time later, from seq 0.
    m = good_rate(0, 53);
    m.controller_session = CTRL_B;
    TEST_ASSERT_EQUAL_INT(CDPR_LCM_ACCEPTED, feed_at(&m, 3 * MS + TAKEOVER + 1, &out));
    cdpr_lcm_validator_sessions(&v, &session, &sessions);
    TEST_ASSERT_EQUAL_INT64(CTRL_B, session);
    TEST_ASSERT_EQUAL_UINT64(2u, sessions);
    // Now A is the stranger; B's window starts at 0; state_seq kept across the sessions.
    m = good_rate(last + 1, 54);
    TEST_ASSERT_EQUAL_INT(CDPR_LCM_REJECT_SESSION_BUSY, feed_at(&m, 3 * MS + TAKEOVER + 2, &out));
    m = good_rate(1, 52);
    m.controller_session = CTRL_B;
    TEST_ASSERT_EQUAL_INT(CDPR_LCM_REJECT_STALE, feed_at(&m, 3 * MS + TAKEOVER + 2, &out));
    m = good_rate(1, 53);
    m.controller_session = CTRL_B;
    TEST_ASSERT_EQUAL_INT(CDPR_LCM_ACCEPTED, feed_at(&m, 3 * MS + TAKEOVER + 2, &out));

    // B silent, then B again with a seq behind its anchor: the same session resynchronises.
    m = good_rate(0, 60);
    m.controller_session = CTRL_B;
    TEST_ASSERT_EQUAL_INT(CDPR_LCM_REJECT_STALE, feed_at(&m, 3 * MS + TAKEOVER + 3, &out));
    TEST_ASSERT_EQUAL_INT(CDPR_LCM_ACCEPTED, feed_at(&m, 4 * MS + 2 * TAKEOVER + 3, &out));
    cdpr_lcm_validator_sessions(&v, &session, &sessions);
    TEST_ASSERT_EQUAL_UINT64(2u, sessions); // not a new session
}

// Malformed bytes through the real (generated) decoder: every truncation, trailing bytes,
// a wrong type fingerprint (a valid cabin_state_t), pseudo-random garbage, NULL/empty input.
static void test_malformed_bytes_are_counted_and_ignored(void)
{
    cdpr_lcm_command_t out;
    cdpr_winch_command_t m = good_rate(10, 60);
    cdpr_cabin_state_t st;
    unsigned char buf[512];
    const int n = encode(&m, buf, (int)sizeof buf);
    uint64_t acc;
    uint32_t x = 12345u;
    int len;
    int i;

    // Truncated at every length 0 .. n-1 (lengths < 8 cannot even hold the fingerprint).
    for (len = 0; len < n; len++) {
        TEST_ASSERT_EQUAL_INT(CDPR_LCM_REJECT_MALFORMED,
                              cdpr_lcm_validator_accept(&v, buf, (size_t)len, 0, &out));
    }
    TEST_ASSERT_EQUAL_UINT64((uint64_t)n, rejected(CDPR_LCM_REJECT_MALFORMED));
    // Trailing bytes after a complete message.
    buf[n] = 0;
    TEST_ASSERT_EQUAL_INT(CDPR_LCM_REJECT_MALFORMED,
                          cdpr_lcm_validator_accept(&v, buf, (size_t)n + 1u, 0, &out));
    TEST_ASSERT_EQUAL_INT(CDPR_LCM_REJECT_MALFORMED,
                          cdpr_lcm_validator_accept(&v, NULL, 100u, 0, &out));

    // Another type: a well-formed cabin_state_t on the command channel.
    memset(&st, 0, sizeof st);
    len = cdpr_cabin_state_t_encode(buf, 0, (int)sizeof buf, &st);
    TEST_ASSERT_TRUE(len > 8);
    TEST_ASSERT_EQUAL_INT(CDPR_LCM_REJECT_WRONG_TYPE,
                          cdpr_lcm_validator_accept(&v, buf, (size_t)len, 0, &out));
    // A command with one fingerprint bit flipped.
    (void)encode(&m, buf, (int)sizeof buf);
    buf[3] ^= 0x10u;
    TEST_ASSERT_EQUAL_INT(CDPR_LCM_REJECT_WRONG_TYPE,
                          cdpr_lcm_validator_accept(&v, buf, (size_t)n, 0, &out));
    TEST_ASSERT_EQUAL_UINT64(2u, rejected(CDPR_LCM_REJECT_WRONG_TYPE));

    // Garbage of many lengths (xorshift32): never accepted (the fingerprint would have to
    // match by chance, p = 2^-64 per message).
    for (i = 0; i < 2000; i++) {
        int k;
        len = i % (int)sizeof buf;
        for (k = 0; k < len; k++) {
            x ^= x << 13;
            x ^= x >> 17;
            x ^= x << 5;
            buf[k] = (unsigned char)x;
        }
        TEST_ASSERT_TRUE(cdpr_lcm_validator_accept(&v, buf, (size_t)len, 0, &out) !=
                         CDPR_LCM_ACCEPTED);
    }
    // Garbage after a valid fingerprint: decodes (any bytes are valid numbers) but fails the
    // field rules or the length check; never accepted with these values.
    (void)encode(&m, buf, (int)sizeof buf);
    for (i = 0; i < 2000; i++) {
        int k;
        for (k = 8; k < n; k++) {
            x ^= x << 13;
            x ^= x >> 17;
            x ^= x << 5;
            buf[k] = (unsigned char)x;
        }
        TEST_ASSERT_TRUE(cdpr_lcm_validator_accept(&v, buf, (size_t)n, 0, &out) !=
                         CDPR_LCM_ACCEPTED);
    }

    // Nothing was accepted, and the next good command still is.
    cdpr_lcm_validator_counts(&v, &acc, NULL, NULL);
    TEST_ASSERT_EQUAL_UINT64(0u, acc);
    TEST_ASSERT_EQUAL_INT(CDPR_LCM_ACCEPTED, feed(&m, &out));
    TEST_ASSERT_EQUAL_INT64(10, out.seq);
}

/* ---------------------------------------------------------------- mailbox and watchdog */

static cdpr_lcm_command_t cmd(int64_t seq, int64_t rx_ns, double value)
{
    cdpr_lcm_command_t c;
    int j;
    memset(&c, 0, sizeof c);
    c.seq = seq;
    c.state_seq = seq;
    c.rx_time_ns = rx_ns;
    c.mode = CDPR_WINCH_RATE;
    c.n_cables = N_CABLES;
    for (j = 0; j < N_CABLES; j++) {
        c.value[j] = value;
    }
    return c;
}

static void assert_hold(const cdpr_lcm_command_t *c)
{
    int j;
    TEST_ASSERT_EQUAL_INT64(-1, c->seq);
    TEST_ASSERT_EQUAL_INT(CDPR_WINCH_RATE, c->mode);
    TEST_ASSERT_EQUAL_INT(N_CABLES, c->n_cables);
    for (j = 0; j < CDPR_MAX_CABLES; j++) {
        uint64_t bits;
        memcpy(&bits, &c->value[j], sizeof bits);
        TEST_ASSERT_EQUAL_HEX64(0u, bits); // exactly +0.0
    }
}

static void test_mailbox_init_checks(void)
{
    cdpr_lcm_mailbox_t mb;
    cdpr_diag_t d;
    TEST_ASSERT_EQUAL_INT(CDPR_E_CAPACITY, cdpr_lcm_mailbox_init(&mb, 0, MS, &d));
    TEST_ASSERT_EQUAL_INT(CDPR_E_NOT_POSITIVE, cdpr_lcm_mailbox_init(&mb, 6, 0, &d));
    TEST_ASSERT_EQUAL_INT(CDPR_E_INVALID_ARG, cdpr_lcm_mailbox_init(NULL, 6, MS, &d));
}

// Hold from start-up until the first command; newest wins; silence longer than the timeout
// -> hold (flag, counters) until a newer command arrives; resume.
static void test_watchdog_holds_and_resumes(void)
{
    static cdpr_lcm_mailbox_t mb;
    cdpr_lcm_command_t out;
    cdpr_lcm_command_t c;
    const int64_t timeout = 100 * MS;
    int flags;
    int i;

    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_lcm_mailbox_init(&mb, N_CABLES, timeout, NULL));
    flags = cdpr_lcm_mailbox_read(&mb, 0, &out);
    TEST_ASSERT_EQUAL_INT(CDPR_LCM_READ_HOLD | CDPR_LCM_READ_NEVER, flags);
    assert_hold(&out);
    TEST_ASSERT_EQUAL_UINT32(1u, mb.holding);
    TEST_ASSERT_EQUAL_UINT64(1u, mb.hold_entries);

    c = cmd(1, 1000 * MS, 0.25);
    cdpr_lcm_mailbox_write(&mb, &c);
    c = cmd(2, 1001 * MS, 0.5); // newer one before the reader looked: the reader gets this
    cdpr_lcm_mailbox_write(&mb, &c);
    flags = cdpr_lcm_mailbox_read(&mb, 1002 * MS, &out);
    TEST_ASSERT_EQUAL_INT(CDPR_LCM_READ_NEW, flags);
    TEST_ASSERT_EQUAL_INT64(2, out.seq);
    TEST_ASSERT_EQUAL_DOUBLE(0.5, out.value[5]);
    TEST_ASSERT_EQUAL_UINT32(0u, mb.holding);

    // Same command read again within the timeout: flags 0, same values.
    for (i = 0; i < 10; i++) {
        flags = cdpr_lcm_mailbox_read(&mb, 1001 * MS + timeout, &out); // exactly at the timeout
        TEST_ASSERT_EQUAL_INT(0, flags);
        TEST_ASSERT_EQUAL_INT64(2, out.seq);
    }
    // One nanosecond later: hold.
    flags = cdpr_lcm_mailbox_read(&mb, 1001 * MS + timeout + 1, &out);
    TEST_ASSERT_EQUAL_INT(CDPR_LCM_READ_HOLD, flags);
    assert_hold(&out);
    TEST_ASSERT_EQUAL_UINT32(1u, mb.holding);
    TEST_ASSERT_EQUAL_UINT64(2u, mb.hold_entries);
    // Staying on hold does not count new entries.
    for (i = 0; i < 5; i++) {
        TEST_ASSERT_EQUAL_INT(CDPR_LCM_READ_HOLD, cdpr_lcm_mailbox_read(&mb, 2000 * MS, &out));
    }
    TEST_ASSERT_EQUAL_UINT64(2u, mb.hold_entries);
    TEST_ASSERT_EQUAL_UINT64(7u, mb.hold_reads); // 1 start-up + 1 + 5

    // Commands resume -> control resumes.
    c = cmd(3, 2500 * MS, -0.75);
    cdpr_lcm_mailbox_write(&mb, &c);
    flags = cdpr_lcm_mailbox_read(&mb, 2501 * MS, &out);
    TEST_ASSERT_EQUAL_INT(CDPR_LCM_READ_NEW, flags);
    TEST_ASSERT_EQUAL_INT64(3, out.seq);
    TEST_ASSERT_EQUAL_DOUBLE(-0.75, out.value[0]);
    TEST_ASSERT_EQUAL_UINT32(0u, mb.holding);
}

// The real-time read path (and the receiver's decode + validate + write) allocate nothing.
static void test_read_and_accept_paths_make_no_allocation(void)
{
    static cdpr_lcm_mailbox_t mb;
    cdpr_lcm_command_t out;
    unsigned char buf[256];
    int64_t s;

    if (!cdpr_alloc_counting_available()) {
        TEST_IGNORE_MESSAGE(cdpr_alloc_unavailable_reason());
    }
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_lcm_mailbox_init(&mb, N_CABLES, 100 * MS, NULL));
    cdpr_alloc_reset();
    for (s = 0; s < 500; s++) {
        cdpr_winch_command_t m = good_rate(s, s);
        const int n = cdpr_winch_command_t_encode(buf, 0, (int)sizeof buf, &m);
        if (cdpr_lcm_validator_accept(&v, buf, (size_t)n, s * MS, &out) == CDPR_LCM_ACCEPTED) {
            cdpr_lcm_mailbox_write(&mb, &out);
        }
        (void)cdpr_lcm_mailbox_read(&mb, s * MS, &out);
        (void)cdpr_lcm_validator_accept(&v, buf, 5u, 0, &out); // malformed path
    }
    (void)cdpr_lcm_mailbox_read(&mb, 1000000 * (int64_t)MS, &out); // hold path
    TEST_ASSERT_EQUAL_UINT(0u, cdpr_alloc_count());
    TEST_ASSERT_EQUAL_INT64(-1, out.seq); // the hold path was taken
}

// Writer and reader on two threads: the reader must only ever see complete commands (every
// value equal to the seq) and never go backwards.
static cdpr_lcm_mailbox_t tmb;
static int writer_done;

static void *writer(void *arg)
{
    int64_t s;
    (void)arg;
    for (s = 1; s <= 300000; s++) {
        const cdpr_lcm_command_t c = cmd(s, 1, (double)s);
        cdpr_lcm_mailbox_write(&tmb, &c);
    }
    __atomic_store_n(&writer_done, 1, __ATOMIC_RELEASE);
    return NULL;
}

static void test_mailbox_two_threads_never_tears(void)
{
    pthread_t th;
    cdpr_lcm_command_t out;
    int64_t last = 0;
    uint32_t torn = 0u;
    uint32_t backwards = 0u;
    uint64_t reads = 0u;

    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_lcm_mailbox_init(&tmb, N_CABLES, INT64_MAX / 4, NULL));
    __atomic_store_n(&writer_done, 0, __ATOMIC_RELAXED);
    TEST_ASSERT_EQUAL_INT(0, pthread_create(&th, NULL, writer, NULL));
    for (;;) {
        const int done = __atomic_load_n(&writer_done, __ATOMIC_ACQUIRE);
        const int flags = cdpr_lcm_mailbox_read(&tmb, 2, &out);
        int j;
        reads++;
        if ((flags & CDPR_LCM_READ_HOLD) == 0) {
            for (j = 0; j < N_CABLES; j++) {
                if ((int64_t)out.value[j] != out.seq) { // exact: values are small integers
                    torn++;
                }
            }
            if (out.seq < last) {
                backwards++;
            }
            last = out.seq;
        }
        if (done) {
            (void)cdpr_lcm_mailbox_read(&tmb, 2, &out);
            break;
        }
    }
    TEST_ASSERT_EQUAL_INT(0, pthread_join(th, NULL));
    TEST_ASSERT_EQUAL_UINT32(0u, torn);
    TEST_ASSERT_EQUAL_UINT32(0u, backwards);
    TEST_ASSERT_EQUAL_INT64(300000, out.seq); // the last write is what remains
    TEST_ASSERT_TRUE(reads > 0u);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_limits_validation_names_the_field);
    RUN_TEST(test_good_commands_are_accepted_in_both_modes);
    RUN_TEST(test_every_bad_field_is_rejected_with_its_reason);
    RUN_TEST(test_a_fresh_validator_rejects_commands_before_any_state);
    RUN_TEST(test_sessions_and_the_sequence_window);
    RUN_TEST(test_malformed_bytes_are_counted_and_ignored);
    RUN_TEST(test_mailbox_init_checks);
    RUN_TEST(test_watchdog_holds_and_resumes);
    RUN_TEST(test_read_and_accept_paths_make_no_allocation);
    RUN_TEST(test_counts_that_do_not_match_the_bytes_are_malformed);
    RUN_TEST(test_a_plant_of_the_build_capacity_takes_its_commands);
    RUN_TEST(test_mailbox_two_threads_never_tears);
    return UNITY_END() ? 1 : 0;
}
