/* SPDX-License-Identifier: BSD-3-Clause */
/// @file test_lcm_udpm.c
/// The bridge over real UDP multicast on loopback: a controller with its own lcm_t on its own
/// thread (as a separate process would have) answers each cabin state with a winch command;
/// the bridge thread publishes the states and receives the commands through the kernel.
///
/// Run by tests/lcm/run_in_netns.sh inside a private network namespace (`unshare -n`, root)
/// where it adds the 224.0.0.0/4 route to lo, as docs/development.md (platform notes) describes.
/// When that is impossible (not root, no unshare, udpm cannot be created) the test prints the
/// reason and exits with 77, which ctest reports as skipped (SKIP_RETURN_CODE), never as passed.
///
/// Why it can fail: states or commands lost or reordered on loopback (the test paces itself
/// one message at a time, so there is no queue overflow to excuse a loss), a command not
/// reaching the mailbox, the plant thread making an lcm_* call or an allocation.
#include "unity.h"

#include "alloc_count.h"
#include "cdpr/lcm/bridge.h"
#include "lcm_call_count.h"

#include <pthread.h>
#include <stdint.h>
#include <sched.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MS        1000000LL
#define SKIP_CODE 77
#define URL       "udpm://239.255.76.67:7667?ttl=0"

typedef struct {
    lcm_t *lcm;
    int stop;
    int64_t next_seq;
    uint64_t states_seen;
} controller_t;

static controller_t ctl;
static cdpr_lcm_bridge_t bridge;

static void on_state(const lcm_recv_buf_t *rbuf, const char *channel, void *user)
{
    controller_t *c = (controller_t *)user;
    cdpr_cabin_state_t st;
    cdpr_winch_command_t m;
    double values[6];
    unsigned char buf[256];
    int n;
    (void)channel;
    if (cdpr_cabin_state_t_decode(rbuf->data, 0, (int)rbuf->data_size, &st) < 0) {
        return;
    }
    __atomic_fetch_add(&c->states_seen, 1u, __ATOMIC_RELAXED);
    memset(&m, 0, sizeof m);
    m.value = values;
    m.seq = c->next_seq++;
    m.state_seq = st.seq;
    m.controller_session = 1;
    m.plant_session = st.plant_session;
    m.mode = CDPR_WINCH_COMMAND_T_MODE_LENGTH;
    m.n_cables = 6;
    for (n = 0; n < 6; n++) {
        m.value[n] = 50.0 + 1e-3 * (double)st.seq;
    }
    n = cdpr_winch_command_t_encode(buf, 0, (int)sizeof buf, &m);
    if (n > 0) {
        (void)lcm_publish(c->lcm, "CDPR_WINCH_COMMAND", buf, (unsigned int)n);
    }
}

static void *controller_main(void *arg)
{
    controller_t *c = (controller_t *)arg;
    while (!__atomic_load_n(&c->stop, __ATOMIC_ACQUIRE)) {
        (void)lcm_handle_timeout(c->lcm, 10);
    }
    return NULL;
}

static int cmp_i64(const void *a, const void *b)
{
    const int64_t x = *(const int64_t *)a;
    const int64_t y = *(const int64_t *)b;
    return (x > y) - (x < y);
}

void setUp(void) {}
void tearDown(void) {}

static void test_udpm_loopback_round_trip(void)
{
    enum { N = 500 };
    cdpr_lcm_bridge_params_t p;
    cdpr_lcm_command_t cmd;
    cdpr_lcm_stats_t s;
    cdpr_diag_t d;
    pthread_t th;
    int64_t k;
    static int64_t rtt[N];
    unsigned long plant_lcm_calls;
    unsigned long plant_allocs;

    memset(&ctl, 0, sizeof ctl);
    ctl.next_seq = 1;
    ctl.lcm = lcm_create(URL);
    TEST_ASSERT_NOT_NULL(ctl.lcm);
    TEST_ASSERT_NOT_NULL(lcm_subscribe(ctl.lcm, "CDPR_CABIN_STATE", on_state, &ctl));
    (void)lcm_get_fileno(ctl.lcm); // receive thread + self-test now, not during the run
    TEST_ASSERT_EQUAL_INT(0, pthread_create(&th, NULL, controller_main, &ctl));

    cdpr_lcm_bridge_params_default(&p);
    p.url = URL;
    p.max_length_m = 100.0;
    /* The round trip is under test, not the watchdog (test_lcm_bridge's): with the default
     * 0.1 s, a reader descheduled for 0.1 s between the answer's arrival and its read finds it
     * expired, and the mailbox holds until a newer command, which never comes (the next state
     * waits for this answer). Seen under a loaded ASan run; a 0.3 s stall reproduces it. */
    p.watchdog_timeout_s = 3600.0;
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_lcm_bridge_init(&bridge, &p, &d));
    TEST_ASSERT_EQUAL_INT_MESSAGE(CDPR_OK, cdpr_lcm_bridge_start(&bridge, &d), d.field);

    cdpr_alloc_reset();
    cdpr_lcm_calls_reset();
    for (k = 0; k < N; k++) {
        cdpr_cabin_state_t st;
        const int64_t t0 = cdpr_lcm_now_ns();
        memset(&st, 0, sizeof st);
        st.seq = k;
        st.utime_us = k * 1000;
        st.plant_session = cdpr_lcm_bridge_session(&bridge);
        TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_lcm_bridge_push_cabin_state(&bridge, &st));
        for (;;) {
            const int flags = cdpr_lcm_bridge_read_command(&bridge, cdpr_lcm_now_ns(), &cmd);
            if ((flags & CDPR_LCM_READ_HOLD) == 0 && cmd.state_seq == k) {
                break;
            }
            /* a liveness bound (a lost answer), not a speed check */
            TEST_ASSERT_TRUE_MESSAGE(cdpr_lcm_now_ns() - t0 < 30000 * MS,
                                     "no answer within 30 s over udpm");
            (void)sched_yield();
        }
        rtt[k] = cdpr_lcm_now_ns() - t0;
        TEST_ASSERT_EQUAL_INT64(k + 1, cmd.seq);
        TEST_ASSERT_EQUAL_INT(CDPR_WINCH_LENGTH, cmd.mode);
        TEST_ASSERT_EQUAL_DOUBLE(50.0 + 1e-3 * (double)k, cmd.value[3]);
    }
    plant_lcm_calls = cdpr_lcm_calls();
    plant_allocs = cdpr_alloc_count();
    cdpr_lcm_bridge_stats(&bridge, &s);
    qsort(rtt, N, sizeof rtt[0], cmp_i64);
    printf("udpm loopback round trip (state out, command back, two lcm_t), %d rounds: p50 %.1f "
           "us, p99 %.1f us, max %.1f us\n",
           N, (double)rtt[N / 2] / 1e3, (double)rtt[N * 99 / 100] / 1e3, (double)rtt[N - 1] / 1e3);

    __atomic_store_n(&ctl.stop, 1, __ATOMIC_RELEASE);
    (void)pthread_join(th, NULL);
    cdpr_lcm_bridge_stop(&bridge);
    lcm_destroy(ctl.lcm);

    TEST_ASSERT_EQUAL_UINT64((uint64_t)N, s.commands_accepted);
    TEST_ASSERT_EQUAL_UINT64(0u, s.ring.dropped);
    TEST_ASSERT_EQUAL_UINT64(0u, s.publish_errors);
    TEST_ASSERT_EQUAL_UINT(0u, plant_lcm_calls);
    if (cdpr_alloc_counting_available()) {
        TEST_ASSERT_EQUAL_UINT(0u, plant_allocs);
    }
}

int main(void)
{
    // Precondition, checked before Unity starts: udpm must be creatable here. Otherwise this is
    // a skip with its reason (exit 77 -> ctest "Skipped"), never a pass.
    lcm_t *probe = lcm_create(URL);
    if (probe == NULL) {
        printf("SKIPPED: lcm_create(\"%s\") failed: no multicast route on this network "
               "(needs `ip route add 224.0.0.0/4 dev lo`; run through run_in_netns.sh as root)\n",
               URL);
        return SKIP_CODE;
    }
    lcm_destroy(probe);

    UNITY_BEGIN();
    RUN_TEST(test_udpm_loopback_round_trip);
    return UNITY_END() ? 1 : 0;
}
