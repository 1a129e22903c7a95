/* SPDX-License-Identifier: BSD-3-Clause */
/// @file test_lcm_bridge.c
/// The LCM bridge (lcm_bridge.h) over a real liblcm `memq://` provider, in-process: the
/// bridge thread owns the lcm_t; an example controller runs on that thread (on_open hook,
/// the way a single-process fallback would run one) and answers every cabin state with a winch
/// command; the test's main thread plays the real-time plant.
///
/// Why these can fail: a message lost or reordered between the ring, lcm_publish, the
/// subscription and the mailbox; a command answering state k not arriving, or arriving as
/// something else; a malformed/invalid command that is accepted, miscounted, or displaces the
/// last good one; a watchdog that does not hold when the controller is silent or does not
/// resume; a push that blocks or does not count its drop while the publisher is stalled;
/// queued messages not published at stop; the real-time thread making a heap allocation or an
/// lcm_* call (both counted per thread: allocation interposer, --wrap'ed liblcm calls); a
/// start failure that leaks the thread or the lcm_t.
#include "unity.h"

#include "alloc_count.h"
#include "cdpr/lcm/bridge.h"
#include "lcm_call_count.h"

#include <math.h>
#include <sched.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define MS 1000000LL

// How long a wait for the other thread may take before the test fails: generous, since only a
// deadlock or a lost message (a bug) has to be told from a loaded machine. No assertion depends
// on how fast the threads run.
#define LIMIT_NS (30000 * MS)

/* ---------------------------------------------------------------- example controller */

// Runs on the bridge thread (its handlers are called inside lcm_handle there). The flags are
// set by the test thread, hence the atomics.
typedef struct {
    lcm_t *lcm;
    char command_channel[CDPR_LCM_CHANNEL_MAX];
    int silent;            // 1: do not answer
    int64_t silent_below;  // > 0: do not answer states of a lower seq (by seq, not by the time
                           // a state is handled: states still queued when it changes keep it)
    int stall;             // 1: block in the next state handler until `release`, then reset to 0
    int release;           // 1: end the stall
    int stalling;          // 1 while blocked
    int bad_batch;         // 1: publish every kind of bad command before the answer; 2: no answer
    int64_t next_seq;      // command seq (bridge thread only)
    int64_t plant_session; // of the last state seen (bridge thread only)
    uint64_t states_seen;  // atomic
    uint64_t tensions_seen;
} controller_t;

static controller_t ctl;

static void sleep_ms(long ms)
{
    struct timespec ts;
    ts.tv_sec = ms / 1000;
    ts.tv_nsec = (ms % 1000) * 1000000L;
    (void)nanosleep(&ts, NULL);
}

static void publish_command(controller_t *c, const cdpr_winch_command_t *m, int truncate_by)
{
    unsigned char buf[512];
    const int n = cdpr_winch_command_t_encode(buf, 0, (int)sizeof buf, m);
    // No Unity assertion here: this runs on the bridge thread (Unity is single-threaded); a
    // failed encode shows up as a missing answer in the test thread.
    if (n <= truncate_by) {
        return;
    }
    (void)lcm_publish(c->lcm, c->command_channel, buf, (unsigned int)(n - truncate_by));
}

// The values of the command being built (LCM sizes the array by n_cables: the message holds a
// pointer). Only the bridge thread builds commands, one at a time; answer() resets them.
static double g_value[CDPR_MAX_CABLES];

static cdpr_winch_command_t answer(controller_t *c, int64_t state_seq)
{
    cdpr_winch_command_t m;
    int j;
    memset(&m, 0, sizeof m);
    m.value = g_value;
    m.utime_us = state_seq * 1000;
    m.seq = c->next_seq;
    m.state_seq = state_seq;
    m.controller_session = 1;
    m.plant_session = c->plant_session;
    m.mode = CDPR_WINCH_COMMAND_T_MODE_RATE;
    m.n_cables = 6;
    for (j = 0; j < 6; j++) {
        m.value[j] = 1e-3 * (double)(state_seq % 1000) * (j % 2 == 0 ? 1.0 : -1.0);
    }
    return m;
}

// One command of each invalid kind, plus a truncated one and garbage (10 messages).
static void publish_bad_batch(controller_t *c, int64_t state_seq)
{
    unsigned char garbage[50];
    unsigned char buf[512];
    cdpr_cabin_state_t st;
    cdpr_winch_command_t m;
    int i;
    int n;

    m = answer(c, state_seq);
    publish_command(c, &m, 1); // truncated -> malformed
    for (i = 0; i < (int)sizeof garbage; i++) {
        garbage[i] = (unsigned char)(i * 37 + 11);
    }
    (void)lcm_publish(c->lcm, c->command_channel, garbage, sizeof garbage); // -> wrong type
    memset(&st, 0, sizeof st);
    n = cdpr_cabin_state_t_encode(buf, 0, (int)sizeof buf, &st);
    (void)lcm_publish(c->lcm, c->command_channel, buf, (unsigned int)n); // -> wrong type
    m = answer(c, state_seq);
    m.value[4] = (double)NAN;
    publish_command(c, &m, 0);
    m = answer(c, state_seq);
    m.mode = 3;
    publish_command(c, &m, 0);
    m = answer(c, state_seq);
    m.n_cables = 5;
    publish_command(c, &m, 0);
    m = answer(c, state_seq);
    m.value[1] = 4.5; // > u_max 4 m/s
    publish_command(c, &m, 0);
    m = answer(c, state_seq);
    m.seq = c->next_seq - 2; // older than the last accepted
    publish_command(c, &m, 0);
    m = answer(c, state_seq);
    m.seq = c->next_seq - 1; // the last accepted again
    publish_command(c, &m, 0);
    m = answer(c, state_seq + 5); // a state not published yet
    publish_command(c, &m, 0);
}

static void on_state(const lcm_recv_buf_t *rbuf, const char *channel, void *user)
{
    controller_t *c = (controller_t *)user;
    cdpr_cabin_state_t st;
    cdpr_winch_command_t m;
    int stall;
    int bad;
    (void)channel;

    if (cdpr_cabin_state_t_decode(rbuf->data, 0, (int)rbuf->data_size, &st) < 0) {
        return;
    }
    __atomic_fetch_add(&c->states_seen, 1u, __ATOMIC_RELAXED);
    c->plant_session = st.plant_session;
    stall = __atomic_exchange_n(&c->stall, 0, __ATOMIC_ACQ_REL);
    if (stall != 0) {
        // The bridge thread is stuck here until the test releases it (or LIMIT_NS: the test
        // then fails on `stalling`): nothing is published meanwhile.
        const int64_t t0 = cdpr_lcm_now_ns();
        __atomic_store_n(&c->stalling, 1, __ATOMIC_RELEASE);
        while (!__atomic_load_n(&c->release, __ATOMIC_ACQUIRE) &&
               cdpr_lcm_now_ns() - t0 < LIMIT_NS) {
            sleep_ms(1);
        }
        __atomic_store_n(&c->stalling, 0, __ATOMIC_RELEASE);
    }
    if (__atomic_load_n(&c->silent, __ATOMIC_ACQUIRE) ||
        st.seq < __atomic_load_n(&c->silent_below, __ATOMIC_ACQUIRE)) {
        return;
    }
    bad = __atomic_exchange_n(&c->bad_batch, 0, __ATOMIC_ACQ_REL);
    if (bad != 0) {
        publish_bad_batch(c, st.seq);
        if (bad == 2) {
            return;
        }
    }
    m = answer(c, st.seq);
    c->next_seq++;
    publish_command(c, &m, 0);
}

static void on_tensions(const lcm_recv_buf_t *rbuf, const char *channel, void *user)
{
    controller_t *c = (controller_t *)user;
    (void)rbuf;
    (void)channel;
    __atomic_fetch_add(&c->tensions_seen, 1u, __ATOMIC_RELAXED);
}

static int controller_open(lcm_t *lcm, void *ctx)
{
    controller_t *c = (controller_t *)ctx;
    c->lcm = lcm;
    if (lcm_subscribe(lcm, "CDPR_CABIN_STATE", on_state, c) == NULL ||
        lcm_subscribe(lcm, "CDPR_CABLE_TENSIONS", on_tensions, c) == NULL) {
        return -1;
    }
    return 0;
}

/* ---------------------------------------------------------------- plant side helpers */

static cdpr_lcm_bridge_t bridge;

static void start_bridge_wake(double watchdog_s, int wake_on_push)
{
    cdpr_lcm_bridge_params_t p;
    cdpr_diag_t d;

    memset(&ctl, 0, sizeof ctl);
    strcpy(ctl.command_channel, "CDPR_WINCH_COMMAND");
    ctl.next_seq = 1;
    cdpr_lcm_bridge_params_default(&p);
    p.url = "memq://";
    p.watchdog_timeout_s = watchdog_s;
    p.wake_on_push = wake_on_push;
    p.on_open = controller_open;
    p.on_open_ctx = &ctl;
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_lcm_bridge_init(&bridge, &p, &d));
    TEST_ASSERT_EQUAL_INT_MESSAGE(CDPR_OK, cdpr_lcm_bridge_start(&bridge, &d), d.field);
}

static void start_bridge(double watchdog_s)
{
    start_bridge_wake(watchdog_s, 1);
}

void setUp(void) {}

void tearDown(void)
{
    cdpr_lcm_bridge_stop(&bridge);
}

static cdpr_status_t push_state(int64_t k, int32_t flags)
{
    cdpr_cabin_state_t s;
    memset(&s, 0, sizeof s);
    s.utime_us = k * 1000;
    s.seq = k;
    s.command_seq = -1;
    s.plant_session = cdpr_lcm_bridge_session(&bridge);
    s.orientation[0] = 1.0;
    s.position_m[2] = 2.0 + 1e-6 * (double)k;
    s.flags = flags;
    return cdpr_lcm_bridge_push_cabin_state(&bridge, &s);
}

static cdpr_status_t push_tensions(int64_t k)
{
    cdpr_lcm_wire_tensions_t t;
    cdpr_lcm_wire_tensions_init(&t);
    t.msg.utime_us = k * 1000;
    t.msg.seq = k;
    t.msg.plant_session = cdpr_lcm_bridge_session(&bridge);
    t.msg.n_cables = 6;
    return cdpr_lcm_bridge_push_tensions(&bridge, &t);
}

// Spin (yielding) until the mailbox holds the command answering state k, at most LIMIT_NS.
// Every read is made at `now_ns`, the plant's clock for this wait (e.g. the start of the
// period that pushed state k), not at the time of the read: a command received after now_ns
// is never older than the watchdog timeout there, so how late this thread gets to read (the
// machine's load) cannot put the mailbox on hold. Returns the read flags of the read that saw
// it, or -1 on timeout.
static int wait_for_answer(int64_t k, int64_t now_ns, cdpr_lcm_command_t *out)
{
    const int64_t t0 = cdpr_lcm_now_ns();
    for (;;) {
        const int flags = cdpr_lcm_bridge_read_command(&bridge, now_ns, out);
        if ((flags & CDPR_LCM_READ_HOLD) == 0 && out->state_seq == k) {
            return flags;
        }
        if (cdpr_lcm_now_ns() - t0 > LIMIT_NS) {
            return -1;
        }
        (void)sched_yield();
    }
}

static int cmp_i64(const void *a, const void *b)
{
    const int64_t x = *(const int64_t *)a;
    const int64_t y = *(const int64_t *)b;
    return (x > y) - (x < y);
}

/* ---------------------------------------------------------------- tests */

static void test_init_rejects_bad_params(void)
{
    cdpr_lcm_bridge_params_t p;
    cdpr_diag_t d;
    static char long_url[CDPR_LCM_URL_MAX + 10];

    cdpr_lcm_bridge_params_default(&p);
    p.channel_prefix = "CDPR.";
    TEST_ASSERT_EQUAL_INT(CDPR_E_INVALID_ARG, cdpr_lcm_bridge_init(&bridge, &p, &d));
    TEST_ASSERT_EQUAL_STRING("channel_prefix", d.field);
    TEST_ASSERT_EQUAL_INT(4, d.index);
    p.channel_prefix = "A_VERY_LONG_PREFIX_THAT_DOES_NOT_LEAVE_ROOM_FOR_NAMES_";
    TEST_ASSERT_EQUAL_INT(CDPR_E_OUT_OF_RANGE, cdpr_lcm_bridge_init(&bridge, &p, &d));
    cdpr_lcm_bridge_params_default(&p);
    memset(long_url, 'u', sizeof long_url - 1u);
    p.url = long_url;
    TEST_ASSERT_EQUAL_INT(CDPR_E_OUT_OF_RANGE, cdpr_lcm_bridge_init(&bridge, &p, &d));
    TEST_ASSERT_EQUAL_STRING("url", d.field);
    cdpr_lcm_bridge_params_default(&p);
    p.n_cables = 0;
    TEST_ASSERT_EQUAL_INT(CDPR_E_CAPACITY, cdpr_lcm_bridge_init(&bridge, &p, &d));
    cdpr_lcm_bridge_params_default(&p);
    p.winch[2].u_max_m_per_s = (cdpr_real_t)NAN;
    TEST_ASSERT_TRUE(cdpr_lcm_bridge_init(&bridge, &p, &d) < 0);
    TEST_ASSERT_EQUAL_INT(2, d.index);
    cdpr_lcm_bridge_params_default(&p);
    p.max_length_m = 0.1;
    TEST_ASSERT_EQUAL_INT(CDPR_E_OUT_OF_RANGE, cdpr_lcm_bridge_init(&bridge, &p, &d));
    TEST_ASSERT_EQUAL_STRING("max_length_m", d.field);
    cdpr_lcm_bridge_params_default(&p);
    p.watchdog_timeout_s = (double)NAN;
    TEST_ASSERT_EQUAL_INT(CDPR_E_NOT_FINITE, cdpr_lcm_bridge_init(&bridge, &p, &d));
    p.watchdog_timeout_s = 0.0;
    TEST_ASSERT_EQUAL_INT(CDPR_E_OUT_OF_RANGE, cdpr_lcm_bridge_init(&bridge, &p, &d));
    cdpr_lcm_bridge_params_default(&p);
    p.idle_poll_ms = 0;
    TEST_ASSERT_EQUAL_INT(CDPR_E_OUT_OF_RANGE, cdpr_lcm_bridge_init(&bridge, &p, &d));
    TEST_ASSERT_EQUAL_STRING("idle_poll_ms", d.field);
}

static void test_channel_names_use_the_prefix(void)
{
    cdpr_lcm_bridge_params_t p;
    cdpr_lcm_bridge_params_default(&p);
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_lcm_bridge_init(&bridge, &p, NULL));
    TEST_ASSERT_EQUAL_STRING("CDPR_CABIN_STATE",
                             cdpr_lcm_bridge_channel(&bridge, CDPR_LCM_CH_CABIN_STATE));
    TEST_ASSERT_EQUAL_STRING("CDPR_WINCH_COMMAND",
                             cdpr_lcm_bridge_channel(&bridge, CDPR_LCM_CH_WINCH_COMMAND));
    p.channel_prefix = "rig2/";
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_lcm_bridge_init(&bridge, &p, NULL));
    TEST_ASSERT_EQUAL_STRING("rig2/CABLE_TENSIONS",
                             cdpr_lcm_bridge_channel(&bridge, CDPR_LCM_CH_CABLE_TENSIONS));
    TEST_ASSERT_EQUAL_STRING("", cdpr_lcm_bridge_channel(&bridge, CDPR_LCM_N_CHANNELS));
}

static int refusing_hook(lcm_t *lcm, void *ctx)
{
    (void)lcm;
    (void)ctx;
    return -1;
}

static void test_start_fails_cleanly_on_a_bad_url(void)
{
    cdpr_lcm_bridge_params_t p;
    cdpr_diag_t d;
    cdpr_lcm_bridge_params_default(&p);
    p.url = "nosuchprovider://";
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_lcm_bridge_init(&bridge, &p, &d));
    TEST_ASSERT_EQUAL_INT(CDPR_E_INVALID_ARG, cdpr_lcm_bridge_start(&bridge, &d));
    TEST_ASSERT_EQUAL_STRING("lcm_create (url)", d.field);
    TEST_ASSERT_NULL(cdpr_lcm_bridge_lcm(&bridge));
    cdpr_lcm_bridge_stop(&bridge); // no-op

    // A hook that refuses: start fails, names it, and leaves nothing open.
    p.url = "memq://";
    p.on_open = refusing_hook;
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_lcm_bridge_init(&bridge, &p, &d));
    TEST_ASSERT_EQUAL_INT(CDPR_E_INVALID_ARG, cdpr_lcm_bridge_start(&bridge, &d));
    TEST_ASSERT_EQUAL_STRING("on_open", d.field);
    TEST_ASSERT_NULL(cdpr_lcm_bridge_lcm(&bridge));
    TEST_ASSERT_EQUAL_INT(-1, bridge.wake_fd);
}

// State k out, command answering k back, 2000 times in lockstep over memq. The plant thread
// makes no allocation and no lcm_* call while the bridge thread does both.
static void run_lockstep(int explicit_wake)
{
    enum { N = 2000 };
    static int64_t rtt[N];
    cdpr_lcm_command_t cmd;
    cdpr_lcm_stats_t s;
    unsigned long plant_allocs;
    unsigned long plant_lcm_calls;
    int64_t k;
    int64_t push_ns = 0;

    start_bridge_wake(1.0, !explicit_wake);
    cdpr_alloc_reset();
    cdpr_lcm_calls_reset();
    for (k = 0; k < N; k++) {
        const int64_t t0 = cdpr_lcm_now_ns();
        int flags;
        TEST_ASSERT_EQUAL_INT(CDPR_OK, push_state(k, 0));
        TEST_ASSERT_EQUAL_INT(CDPR_OK, push_tensions(k));
        if (explicit_wake) {
            cdpr_lcm_bridge_wake(&bridge); // once per period
        }
        push_ns += cdpr_lcm_now_ns() - t0;
        flags = wait_for_answer(k, t0, &cmd);
        rtt[k] = cdpr_lcm_now_ns() - t0;
        TEST_ASSERT_TRUE_MESSAGE(flags >= 0, "no answer within 30 s");
        TEST_ASSERT_EQUAL_INT(CDPR_LCM_READ_NEW, flags);
        TEST_ASSERT_EQUAL_INT64(k + 1, cmd.seq);
        TEST_ASSERT_EQUAL_DOUBLE(1e-3 * (double)(k % 1000), cmd.value[0]);
        TEST_ASSERT_EQUAL_DOUBLE(-1e-3 * (double)(k % 1000), cmd.value[1]);
    }
    plant_allocs = cdpr_alloc_count();
    plant_lcm_calls = cdpr_lcm_calls();

    cdpr_lcm_bridge_stats(&bridge, &s);
    TEST_ASSERT_EQUAL_UINT64((uint64_t)N, s.commands_accepted);
    TEST_ASSERT_EQUAL_UINT64((uint64_t)N, s.commands_received);
    TEST_ASSERT_EQUAL_UINT64(0u, s.ring.dropped);
    TEST_ASSERT_EQUAL_UINT64(2u * N, s.ring.pushed);
    TEST_ASSERT_EQUAL_INT64(N, s.last_command_seq);
    TEST_ASSERT_EQUAL_INT64(N - 1, s.published_state_seq);
    TEST_ASSERT_EQUAL_INT(0, s.holding);
    TEST_ASSERT_EQUAL_UINT64(0u, s.publish_errors);
    TEST_ASSERT_EQUAL_UINT64(0u, s.handle_errors);

    qsort(rtt, N, sizeof rtt[0], cmp_i64);
    printf("memq lockstep round trip (push state + tensions -> bridge publishes -> controller "
           "answers -> mailbox), %s, %d rounds: p50 %.1f us, p99 %.1f us, max %.1f us; the "
           "two pushes incl. wake-ups: mean %.0f ns per round (%llu wake-ups)\n",
           explicit_wake ? "one explicit wake per round" : "wake on every push", N,
           (double)rtt[N / 2] / 1e3, (double)rtt[N * 99 / 100] / 1e3, (double)rtt[N - 1] / 1e3,
           (double)push_ns / (double)N, (unsigned long long)s.wakeups);
    if (explicit_wake) {
        TEST_ASSERT_TRUE(s.wakeups <= (uint64_t)N);
    }

    TEST_ASSERT_EQUAL_UINT_MESSAGE(0u, plant_lcm_calls, "the plant thread called lcm_*");
    TEST_ASSERT_TRUE(cdpr_lcm_calls_total() >= 2u * N); // the bridge thread did publish
    if (!cdpr_alloc_counting_available()) {
        TEST_IGNORE_MESSAGE(cdpr_alloc_unavailable_reason());
    }
    // liblcm allocates on every memq publish (bridge thread): a counter that saw nothing at all
    // is not counting (e.g. valgrind replaced malloc), and a zero from it would prove nothing.
    if (cdpr_alloc_count_total() == 0u) {
        TEST_IGNORE_MESSAGE("the allocation counter saw no allocation in any thread: malloc is "
                            "not interposed here (valgrind?), plant-thread count not checked");
    }
    TEST_ASSERT_EQUAL_UINT_MESSAGE(0u, plant_allocs, "the plant thread allocated");
}

static void test_memq_round_trip_lockstep(void)
{
    run_lockstep(0);
}

static void test_memq_round_trip_lockstep_explicit_wake(void)
{
    run_lockstep(1);
}

// Every kind of bad command over the real LCM path is counted under its reason and ignored;
// the plant keeps the last good command.
static void test_malformed_commands_over_lcm_are_counted_and_ignored(void)
{
    cdpr_lcm_command_t cmd;
    cdpr_lcm_stats_t s;
    int64_t t0;
    int64_t rx;

    start_bridge(5.0);
    t0 = cdpr_lcm_now_ns();
    TEST_ASSERT_EQUAL_INT(CDPR_OK, push_state(0, 0));
    TEST_ASSERT_TRUE(wait_for_answer(0, t0, &cmd) >= 0);
    TEST_ASSERT_EQUAL_INT64(1, cmd.seq);

    __atomic_store_n(&ctl.bad_batch, 1, __ATOMIC_RELEASE); // bad batch, then a good answer
    t0 = cdpr_lcm_now_ns();
    TEST_ASSERT_EQUAL_INT(CDPR_OK, push_state(1, 0));
    TEST_ASSERT_TRUE(wait_for_answer(1, t0, &cmd) >= 0);
    TEST_ASSERT_EQUAL_INT64(2, cmd.seq);

    cdpr_lcm_bridge_stats(&bridge, &s);
    TEST_ASSERT_EQUAL_UINT64(12u, s.commands_received);
    TEST_ASSERT_EQUAL_UINT64(2u, s.commands_accepted);
    // Truncated -> malformed; garbage (its first 8 bytes are no known fingerprint) and the
    // cabin_state_t -> wrong type.
    TEST_ASSERT_EQUAL_UINT64(1u, s.rejected[CDPR_LCM_REJECT_MALFORMED]);
    TEST_ASSERT_EQUAL_UINT64(2u, s.rejected[CDPR_LCM_REJECT_WRONG_TYPE]);
    TEST_ASSERT_EQUAL_UINT64(1u, s.rejected[CDPR_LCM_REJECT_NOT_FINITE]);
    TEST_ASSERT_EQUAL_UINT64(1u, s.rejected[CDPR_LCM_REJECT_BAD_MODE]);
    TEST_ASSERT_EQUAL_UINT64(1u, s.rejected[CDPR_LCM_REJECT_CABLE_COUNT]);
    TEST_ASSERT_EQUAL_UINT64(1u, s.rejected[CDPR_LCM_REJECT_OUT_OF_LIMIT]);
    TEST_ASSERT_EQUAL_UINT64(1u, s.rejected[CDPR_LCM_REJECT_STALE]);
    TEST_ASSERT_EQUAL_UINT64(1u, s.rejected[CDPR_LCM_REJECT_REPLAYED]);
    TEST_ASSERT_EQUAL_UINT64(1u, s.rejected[CDPR_LCM_REJECT_FUTURE]);

    // Only bad commands for state 2: the plant keeps running on command 2 (not on hold).
    __atomic_store_n(&ctl.bad_batch, 2, __ATOMIC_RELEASE);
    rx = cmd.rx_time_ns; // of command 2
    TEST_ASSERT_EQUAL_INT(CDPR_OK, push_state(2, 0));
    t0 = cdpr_lcm_now_ns();
    do {
        cdpr_lcm_bridge_stats(&bridge, &s);
        TEST_ASSERT_TRUE_MESSAGE(cdpr_lcm_now_ns() - t0 < LIMIT_NS, "bad batch not received");
        (void)sched_yield();
    } while (s.commands_received < 22u);
    // Read at command 2's arrival: the watchdog is not what this case is about (the silence
    // case is), and a slow test thread must not make command 2 look stale.
    TEST_ASSERT_EQUAL_INT(0, cdpr_lcm_bridge_read_command(&bridge, rx, &cmd));
    TEST_ASSERT_EQUAL_INT64(2, cmd.seq);
    TEST_ASSERT_EQUAL_INT64(1, cmd.state_seq);
    TEST_ASSERT_EQUAL_UINT64(2u, s.commands_accepted);
    TEST_ASSERT_EQUAL_UINT64(2u, s.rejected[CDPR_LCM_REJECT_MALFORMED]);
    TEST_ASSERT_EQUAL_UINT64(4u, s.rejected[CDPR_LCM_REJECT_WRONG_TYPE]);
}

// Controller silence -> hold after the watchdog timeout (rate 0, flag, counters); commands
// resume -> control resumes. The watchdog is the only thing that runs on the wall clock here:
// before the silence and at the resume the mailbox is read at the time the state was pushed
// (wait_for_answer), so a slow test thread cannot make a hold of its own; the silence is by
// state seq, so states still queued when the controller resumes are not answered late.
static void test_controller_silence_holds_then_resumes(void)
{
    const double timeout_s = 0.05;
    cdpr_lcm_command_t cmd;
    cdpr_lcm_stats_t s;
    int64_t k = 0;
    int64_t t0;
    int64_t last_rx;
    int64_t hold_at = 0;
    int flags = 0;

    start_bridge(timeout_s);
    // Start-up: on hold until the first command.
    flags = cdpr_lcm_bridge_read_command(&bridge, cdpr_lcm_now_ns(), &cmd);
    TEST_ASSERT_EQUAL_INT(CDPR_LCM_READ_HOLD | CDPR_LCM_READ_NEVER, flags);
    t0 = cdpr_lcm_now_ns();
    for (k = 0; k < 10; k++) {
        TEST_ASSERT_EQUAL_INT(CDPR_OK, push_state(k, 0));
        TEST_ASSERT_TRUE(wait_for_answer(k, t0, &cmd) >= 0);
    }
    last_rx = cmd.rx_time_ns;
    cdpr_lcm_bridge_stats(&bridge, &s);
    TEST_ASSERT_EQUAL_INT(0, s.holding);
    TEST_ASSERT_EQUAL_UINT64(1u, s.hold_entries); // start-up

    // Silent from state 10 on (state 9 is answered: its command is in the mailbox).
    __atomic_store_n(&ctl.silent_below, INT64_MAX, __ATOMIC_RELEASE);
    for (; k < 10000; k++) { // at least 1 ms per state: at least 10 s
        TEST_ASSERT_EQUAL_INT(CDPR_OK, push_state(k, 0));
        sleep_ms(1);
        flags = cdpr_lcm_bridge_read_command(&bridge, cdpr_lcm_now_ns(), &cmd);
        if ((flags & CDPR_LCM_READ_HOLD) != 0) {
            hold_at = cdpr_lcm_now_ns();
            break;
        }
        TEST_ASSERT_EQUAL_INT64(10, cmd.seq); // still the last good command
    }
    TEST_ASSERT_TRUE_MESSAGE((flags & CDPR_LCM_READ_HOLD) != 0, "never went on hold");
    TEST_ASSERT_EQUAL_INT(0, flags & CDPR_LCM_READ_NEVER);
    TEST_ASSERT_EQUAL_INT64(-1, cmd.seq);
    TEST_ASSERT_EQUAL_DOUBLE(0.0, cmd.value[0]);
    // Not before the timeout (how long after it depends on the machine: printed only).
    TEST_ASSERT_TRUE(hold_at - last_rx > (int64_t)(timeout_s * 1e9));
    printf("watchdog: hold %.1f ms after the last command (timeout %.0f ms)\n",
           (double)(hold_at - last_rx) / 1e6, timeout_s * 1e3);
    cdpr_lcm_bridge_stats(&bridge, &s);
    TEST_ASSERT_EQUAL_INT(1, s.holding);
    TEST_ASSERT_EQUAL_UINT64(2u, s.hold_entries); // start-up + silence

    // Resume from state k + 1 on; the states of the silence still queued stay unanswered. Read
    // at t0 (after hold_at): command 10 is stale there, a command received after it is not.
    t0 = cdpr_lcm_now_ns();
    __atomic_store_n(&ctl.silent_below, k + 1, __ATOMIC_RELEASE);
    TEST_ASSERT_EQUAL_INT(CDPR_OK, push_state(k + 1, 0));
    flags = wait_for_answer(k + 1, t0, &cmd);
    TEST_ASSERT_EQUAL_INT(CDPR_LCM_READ_NEW, flags);
    TEST_ASSERT_EQUAL_INT64(11, cmd.seq);
    cdpr_lcm_bridge_stats(&bridge, &s);
    TEST_ASSERT_EQUAL_INT(0, s.holding);
    TEST_ASSERT_EQUAL_UINT64(2u, s.hold_entries);
}

// Publisher stalled (the bridge thread is stuck in a handler until the test releases it):
// pushes keep returning at once, the ring fills, every further message is dropped and counted;
// after the stall everything queued is published.
static void test_stalled_publisher_drops_and_pushes_never_block(void)
{
    enum { N = 3000 };
    cdpr_lcm_stats_t s;
    int64_t max_push = 0;
    uint32_t ok = 0u;
    uint32_t full = 0u;
    int64_t t0;
    int k;

    start_bridge(5.0);
    __atomic_store_n(&ctl.stall, 1, __ATOMIC_RELEASE);
    TEST_ASSERT_EQUAL_INT(CDPR_OK, push_state(0, 0));
    t0 = cdpr_lcm_now_ns();
    while (!__atomic_load_n(&ctl.stalling, __ATOMIC_ACQUIRE)) {
        TEST_ASSERT_TRUE_MESSAGE(cdpr_lcm_now_ns() - t0 < LIMIT_NS, "stall never began");
        (void)sched_yield();
    }
    for (k = 1; k <= N; k++) {
        const int64_t a = cdpr_lcm_now_ns();
        const cdpr_status_t st = push_state(k, 0);
        const int64_t dt = cdpr_lcm_now_ns() - a;
        max_push = dt > max_push ? dt : max_push;
        if (st == CDPR_OK) {
            ok++;
        } else {
            TEST_ASSERT_EQUAL_INT(CDPR_E_CAPACITY, st);
            full++;
        }
    }
    TEST_ASSERT_TRUE_MESSAGE(__atomic_load_n(&ctl.stalling, __ATOMIC_ACQUIRE),
                             "the stall ended before the pushes did (30 s)");
    cdpr_lcm_bridge_stats(&bridge, &s);
    printf("stalled publisher: %u queued, %u dropped, slowest push %.1f us\n", ok, full,
           (double)max_push / 1e3);
    TEST_ASSERT_EQUAL_UINT32(CDPR_LCM_RING_SLOTS, ok); // state 0 was taken before the stall
    TEST_ASSERT_EQUAL_UINT64((uint64_t)full, s.ring.dropped);
    TEST_ASSERT_EQUAL_UINT32(CDPR_LCM_RING_SLOTS, s.ring.queued);

    // After the stall: all queued states are published (and answered). (`published` counts a
    // message before its slot is released: wait for both.)
    __atomic_store_n(&ctl.release, 1, __ATOMIC_RELEASE);
    t0 = cdpr_lcm_now_ns();
    do {
        cdpr_lcm_bridge_stats(&bridge, &s);
        TEST_ASSERT_TRUE_MESSAGE(cdpr_lcm_now_ns() - t0 < LIMIT_NS, "queue not drained");
        sleep_ms(1);
    } while (s.published < 1u + CDPR_LCM_RING_SLOTS || s.ring.queued != 0u);
    TEST_ASSERT_EQUAL_UINT64(1u + CDPR_LCM_RING_SLOTS, s.published);
    TEST_ASSERT_EQUAL_UINT32(CDPR_LCM_RING_SLOTS, s.ring.high_water);
}

// Messages queued right before stop (e.g. the final diagnostics) are still published.
static void test_stop_publishes_what_is_queued(void)
{
    cdpr_diagnostics_t dg;
    cdpr_lcm_stats_t s;
    int k;

    start_bridge(5.0);
    __atomic_store_n(&ctl.silent, 1, __ATOMIC_RELEASE);
    __atomic_store_n(&ctl.stall, 1, __ATOMIC_RELEASE);
    TEST_ASSERT_EQUAL_INT(CDPR_OK, push_state(0, 0)); // the bridge stalls on this one
    while (!__atomic_load_n(&ctl.stalling, __ATOMIC_ACQUIRE)) {
        (void)sched_yield();
    }
    for (k = 1; k <= 20; k++) {
        TEST_ASSERT_EQUAL_INT(CDPR_OK, push_state(k, 0));
    }
    memset(&dg, 0, sizeof dg);
    cdpr_lcm_bridge_stats(&bridge, &s);
    cdpr_lcm_pack_diagnostics(&dg, &s);
    dg.seq = 20;
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_lcm_bridge_push_diagnostics(&bridge, &dg));
    TEST_ASSERT_EQUAL_UINT64(1u, s.published); // state 0 only: the rest is still queued
    __atomic_store_n(&ctl.release, 1, __ATOMIC_RELEASE);
    cdpr_lcm_bridge_stop(&bridge);
    cdpr_lcm_bridge_stats(&bridge, &s);
    TEST_ASSERT_EQUAL_UINT64(22u, s.published);
    TEST_ASSERT_EQUAL_UINT32(0u, s.ring.queued);
    TEST_ASSERT_NULL(cdpr_lcm_bridge_lcm(&bridge));
}

// Another plant on our state channel: its states (and undecodable bytes there) are counted,
// the hook is called once per new session, our own states are not counted.
static int64_t other_seen[4];
static int other_calls;

static void on_other(int64_t session, void *ctx)
{
    (void)ctx;
    if (other_calls < 4) {
        other_seen[other_calls] = session;
    }
    other_calls++;
}

static void test_another_plant_on_the_channel_is_counted(void)
{
    cdpr_lcm_bridge_params_t p;
    cdpr_lcm_stats_t s;
    cdpr_diag_t d;
    cdpr_cabin_state_t st;
    unsigned char buf[512];
    static const unsigned char junk[12] = {1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12};
    int i;

    memset(&ctl, 0, sizeof ctl);
    strcpy(ctl.command_channel, "CDPR_WINCH_COMMAND");
    ctl.silent = 1;
    other_calls = 0;
    cdpr_lcm_bridge_params_default(&p);
    p.url = "memq://";
    p.plant_session = 1234;
    p.on_open = controller_open;
    p.on_open_ctx = &ctl;
    p.on_other_plant = on_other;
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_lcm_bridge_init(&bridge, &p, &d));
    TEST_ASSERT_EQUAL_INT64(1234, cdpr_lcm_bridge_session(&bridge));
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_lcm_bridge_open(&bridge, &d));
    for (i = 0; i < 3; i++) { // our own states: not counted
        TEST_ASSERT_EQUAL_INT(CDPR_OK, push_state(i, 0));
    }
    memset(&st, 0, sizeof st);
    st.plant_session = 999; // another plant, three states
    const int n = cdpr_cabin_state_t_encode(buf, 0, (int)sizeof buf, &st);
    for (i = 0; i < 3; i++) {
        TEST_ASSERT_EQUAL_INT(
            0, lcm_publish(cdpr_lcm_bridge_lcm(&bridge), "CDPR_CABIN_STATE", buf, (unsigned int)n));
    }
    TEST_ASSERT_EQUAL_INT(
        0, lcm_publish(cdpr_lcm_bridge_lcm(&bridge), "CDPR_CABIN_STATE", junk, sizeof junk));
    for (i = 0; i < 20; i++) {
        (void)cdpr_lcm_bridge_poll(&bridge, 1);
    }
    cdpr_lcm_bridge_stats(&bridge, &s);
    TEST_ASSERT_EQUAL_INT64(1234, s.plant_session);
    TEST_ASSERT_EQUAL_UINT64(4u, s.other_plant_messages);
    TEST_ASSERT_EQUAL_INT64(0, s.other_plant_session); // the last one did not decode
    TEST_ASSERT_EQUAL_INT(2, other_calls);
    TEST_ASSERT_EQUAL_INT64(999, other_seen[0]);
    TEST_ASSERT_EQUAL_INT64(0, other_seen[1]);
    cdpr_lcm_bridge_close(&bridge);
}

// Without a thread: open / poll / close on the caller's thread. The shape message goes
// through its own ring.
static void test_open_poll_close_without_a_thread(void)
{
    static cdpr_lcm_wire_shape_t sh;
    cdpr_lcm_bridge_params_t p;
    cdpr_lcm_command_t cmd;
    cdpr_lcm_stats_t s;
    cdpr_diag_t d;
    int i;

    memset(&ctl, 0, sizeof ctl);
    strcpy(ctl.command_channel, "CDPR_WINCH_COMMAND");
    ctl.next_seq = 1;
    cdpr_lcm_bridge_params_default(&p);
    p.url = "memq://";
    p.on_open = controller_open;
    p.on_open_ctx = &ctl;
    // Not the watchdog's test: with the default 0.1 s, a thread descheduled for ~80 ms after
    // the 20 polls below would find the answer expired (a hold), whatever the code does.
    p.watchdog_timeout_s = 3600.0;
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_lcm_bridge_init(&bridge, &p, &d));
    TEST_ASSERT_EQUAL_INT(-1, cdpr_lcm_bridge_poll(&bridge, 0)); // not open
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_lcm_bridge_open(&bridge, &d));
    TEST_ASSERT_NOT_NULL(cdpr_lcm_bridge_lcm(&bridge));
    cdpr_lcm_wire_shape_init(&sh);
    for (i = 0; i < CDPR_LCM_SHAPE_SLOTS + 3; i++) {
        sh.msg.seq = i;
        (void)cdpr_lcm_bridge_push_shape(&bridge, &sh);
    }
    TEST_ASSERT_EQUAL_INT(CDPR_OK, push_state(0, 0));
    for (i = 0; i < 20; i++) {
        (void)cdpr_lcm_bridge_poll(&bridge, 1);
    }
    TEST_ASSERT_EQUAL_INT(CDPR_LCM_READ_NEW,
                          cdpr_lcm_bridge_read_command(&bridge, cdpr_lcm_now_ns(), &cmd));
    TEST_ASSERT_EQUAL_INT64(0, cmd.state_seq);
    cdpr_lcm_bridge_stats(&bridge, &s);
    TEST_ASSERT_EQUAL_UINT64(CDPR_LCM_SHAPE_SLOTS, s.shape_ring.pushed);
    TEST_ASSERT_EQUAL_UINT64(3u, s.shape_ring.dropped);
    TEST_ASSERT_EQUAL_UINT64(CDPR_LCM_SHAPE_SLOTS + 1u, s.published);
    cdpr_lcm_bridge_close(&bridge);
    cdpr_lcm_bridge_close(&bridge); // twice is fine
    TEST_ASSERT_NULL(cdpr_lcm_bridge_lcm(&bridge));
}

// Cost of packing nothing but encoding + queueing one cabin_state_t and one cable_tensions_t
// (what the plant thread pays per period besides the model), without and with the wake-up
// check (a fence; no eventfd write since no bridge thread sleeps here). The cost of an actual
// wake-up shows in the lockstep test's push time. Printed for docs/realtime.md; not asserted.
static void test_push_cost_is_reported(void)
{
    enum { N = 200 };
    cdpr_lcm_bridge_params_t p;
    cdpr_diag_t d;
    int wake;

    memset(&ctl, 0, sizeof ctl);
    for (wake = 0; wake <= 1; wake++) {
        int64_t best = INT64_MAX;
        int64_t sum = 0;
        int round;
        cdpr_lcm_bridge_params_default(&p);
        p.url = "memq://";
        p.wake_on_push = wake;
        TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_lcm_bridge_init(&bridge, &p, &d));
        TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_lcm_bridge_open(&bridge, &d));
        for (round = 0; round < 20; round++) {
            int64_t t0;
            int64_t dt;
            int k;
            t0 = cdpr_lcm_now_ns();
            for (k = 0; k < N / 2; k++) {
                (void)push_state(k, 0);
                (void)push_tensions(k);
            }
            dt = cdpr_lcm_now_ns() - t0;
            sum += dt;
            best = dt < best ? dt : best;
            (void)cdpr_lcm_bridge_poll(&bridge, 0); // drain (publishes to memq, no subscriber)
        }
        printf("push (encode into slot + commit%s): mean %.0f ns, best-round mean %.0f ns per "
               "message\n",
               wake ? " + wake check, bridge awake" : "", (double)sum / (20.0 * N),
               (double)best / N);
        cdpr_lcm_bridge_close(&bridge);
    }
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_init_rejects_bad_params);
    RUN_TEST(test_channel_names_use_the_prefix);
    RUN_TEST(test_start_fails_cleanly_on_a_bad_url);
    RUN_TEST(test_memq_round_trip_lockstep);
    RUN_TEST(test_memq_round_trip_lockstep_explicit_wake);
    RUN_TEST(test_malformed_commands_over_lcm_are_counted_and_ignored);
    RUN_TEST(test_controller_silence_holds_then_resumes);
    RUN_TEST(test_stalled_publisher_drops_and_pushes_never_block);
    RUN_TEST(test_stop_publishes_what_is_queued);
    RUN_TEST(test_open_poll_close_without_a_thread);
    RUN_TEST(test_another_plant_on_the_channel_is_counted);
    RUN_TEST(test_push_cost_is_reported);
    return UNITY_END() ? 1 : 0;
}
