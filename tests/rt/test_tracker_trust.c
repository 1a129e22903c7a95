/* SPDX-License-Identifier: BSD-3-Clause */
/// @file test_tracker_trust.c
/// The controller side of the protocol trusts nothing that arrives (tracker_node.h, "Trust";
/// issue 26): the tracker node over a real LCM (memq://) fed by a scripted plant that holds the
/// paper's cabin at rest (state and tensions from the sag-aware IK, seq k, time k T), and the
/// hostile messages of the probes, each against the same run without them:
///  - a forged pair with seq = real + 2^40 (before: every later real state was ignored);
///  - a forged tension of 1e300 N with tension feedback on (before: it stuck in the filter and
///    every winch paid out at the limit);
///  - a forged time far ahead (before: the controller jumped to the end of its run);
///  - implausible values (quaternion, speed, length jump, position, tension);
///  - a forged first state (the window re-anchors after two agreeing pairs);
///  - another controller's session applied (counted, in_control says no);
///  - a plant at another rate (counted).
#include <math.h>
#include <stdint.h>
#include <string.h>

#include <lcm/lcm.h>

#include "cdpr/rt/tracker_node.h"
#include "cdpr/statics.h"
#include "paper_model.h"
#include "unity.h"

#define T_S      0.01
#define N_STATES 60

static cdpr_robot_params_t g_params;
static cdpr_robot_t g_model;
static cdpr_winch_params_t g_winch[CDPR_MAX_CABLES];
static cdpr_traj_t g_traj;
static cdpr_statics_result_t g_ik;
static cdpr_rt_tracker_t g_node;
static lcm_t *g_lcm;

/* Commands received by the scripted plant. */
static long g_commands;
static double g_max_rate;
static int64_t g_last_state_seq;

static void on_command(const lcm_recv_buf_t *rbuf, const char *channel, void *user)
{
    (void)channel;
    (void)user;
    cdpr_lcm_wire_command_t c;
    cdpr_lcm_wire_command_init(&c);
    if (cdpr_lcm_wire_command_decode(&c, rbuf->data, (int)rbuf->data_size) != CDPR_LCM_WIRE_OK) {
        return;
    }
    g_commands++;
    g_last_state_seq = c.msg.state_seq;
    for (int j = 0; j < c.msg.n_cables; ++j) {
        g_max_rate = fmax(g_max_rate, fabs(c.value[j]));
    }
}

static const double HOME[6] = {0.0, 0.0, 9.135, 0.0, 0.0, 0.0};

void setUp(void)
{
    test_paper_model_params(&g_params, &g_model);
    for (int j = 0; j < CDPR_MAX_CABLES; ++j) {
        cdpr_winch_params_default(&g_winch[j]);
    }
    g_traj = test_line(HOME, HOME, 10.0); /* hold the home pose */
    cdpr_statics_opts_t o;
    cdpr_statics_opts_default(&o);
    const cdpr_real_t pose[6] = {0.0, 0.0, 9.135, 0.0, 0.0, 0.0};
    const cdpr_cabin_motion_t m = cdpr_cabin_motion_at_pose(pose);
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_statics_ik(&g_model, &m, &o, &g_ik));
    cdpr_tracker_gains_t g;
    memset(&g, 0, sizeof g);
    g.k_length_per_s = 5.0;
    g.tension_gain_m_per_s_per_N = 1e-3; /* the tension filter a forged tension would poison */
    g.tension_filter_s = 0.05;
    cdpr_diag_t d;
    TEST_ASSERT_EQUAL_INT(
        CDPR_OK, cdpr_rt_tracker_init(&g_node, &g_params, g_winch, &g_traj, &g, T_S, NULL, &d));
    g_lcm = lcm_create("memq://");
    TEST_ASSERT_NOT_NULL(g_lcm);
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_rt_tracker_attach(&g_node, g_lcm));
    TEST_ASSERT_NOT_NULL(lcm_subscribe(g_lcm, "CDPR_WINCH_COMMAND", on_command, NULL));
    g_commands = 0;
    g_max_rate = 0.0;
    g_last_state_seq = -1;
}

void tearDown(void)
{
    cdpr_rt_tracker_detach(&g_node);
    lcm_destroy(g_lcm);
}

/* The plant's messages of period k: the cabin at rest at home, the IK's tensions and lengths. */
static void make_pair(int64_t k, cdpr_cabin_state_t *st, cdpr_lcm_wire_tensions_t *ten)
{
    memset(st, 0, sizeof *st);
    cdpr_lcm_wire_tensions_init(ten);
    st->utime_us = k * (int64_t)llround(T_S * 1e6);
    st->seq = k;
    st->command_seq = -1;
    st->plant_session = 77;
    st->controller_session = (g_node.cmd_seq >= 0) ? g_node.controller_session : 0;
    st->position_m[2] = HOME[2];
    st->orientation[0] = 1.0;
    ten->msg.utime_us = st->utime_us;
    ten->msg.seq = k;
    ten->msg.plant_session = 77;
    ten->msg.n_cables = 6;
    for (int j = 0; j < 6; ++j) {
        ten->tension_cabin_N[j] = g_ik.cable[j].tension_cabin_N;
        ten->tension_winch_N[j] = g_ik.cable[j].tension_winch_N;
        ten->length_m[j] = g_ik.cable[j].length_m;
        ten->n_segments[j] = 8;
    }
}

/* Publish a pair and let the node answer it (memq delivers on lcm_handle). */
static void send(const cdpr_cabin_state_t *st, const cdpr_lcm_wire_tensions_t *ten)
{
    unsigned char buf[1024];
    int n = cdpr_cabin_state_t_encode(buf, 0, (int)sizeof buf, st);
    TEST_ASSERT_TRUE(n > 0);
    TEST_ASSERT_EQUAL_INT(0, lcm_publish(g_lcm, "CDPR_CABIN_STATE", buf, (unsigned)n));
    n = cdpr_lcm_wire_tensions_encode(ten, buf, (int)sizeof buf);
    TEST_ASSERT_TRUE(n > 0);
    TEST_ASSERT_EQUAL_INT(0, lcm_publish(g_lcm, "CDPR_CABLE_TENSIONS", buf, (unsigned)n));
    for (int i = 0; i < 4; ++i) {
        (void)lcm_handle_timeout(g_lcm, 0);
    }
    (void)cdpr_rt_tracker_service(&g_node);
    for (int i = 0; i < 4; ++i) {
        (void)lcm_handle_timeout(g_lcm, 0); /* the command */
    }
}

static void send_real(int64_t k)
{
    cdpr_cabin_state_t st;
    cdpr_lcm_wire_tensions_t ten;
    make_pair(k, &st, &ten);
    send(&st, &ten);
}

static uint64_t refused(void)
{
    const cdpr_rt_tracker_stats_t *s = &g_node.stats;
    return s->refused_seq + s->refused_time + s->refused_implausible + s->bad_measurement;
}

static void test_clean_run_answers_every_state(void)
{
    for (int64_t k = 0; k < N_STATES; ++k) {
        send_real(k);
    }
    TEST_ASSERT_EQUAL_INT(N_STATES, g_commands);
    TEST_ASSERT_EQUAL_UINT64(0, refused());
    TEST_ASSERT_EQUAL_UINT64(0, g_node.stats.rate_mismatch);
    TEST_ASSERT_EQUAL_UINT64(N_STATES - 1, g_node.stats.applied_ours);
    TEST_ASSERT_TRUE(cdpr_rt_tracker_in_control(&g_node, CDPR_RT_MAX_OTHER_SHARE));
    TEST_ASSERT_TRUE_MESSAGE(g_max_rate < 0.05, "at rest the commands are small");
}

static void test_forged_far_seq_costs_one_update(void)
{
    for (int64_t k = 0; k < N_STATES; ++k) {
        if (k == 10) {
            cdpr_cabin_state_t st;
            cdpr_lcm_wire_tensions_t ten;
            make_pair(k + ((int64_t)1 << 40), &st, &ten);
            send(&st, &ten);
        }
        send_real(k);
    }
    TEST_ASSERT_EQUAL_UINT64(1, g_node.stats.refused_seq);
    TEST_ASSERT_EQUAL_INT(N_STATES, g_commands); /* every real state answered */
    TEST_ASSERT_EQUAL_INT64(N_STATES - 1, g_last_state_seq);
    TEST_ASSERT_EQUAL_UINT64(0, g_node.stats.resyncs);
}

static void test_forged_tension_never_reaches_the_filter(void)
{
    for (int64_t k = 0; k < N_STATES; ++k) {
        if (k == 10) {
            /* The forged tensions of period 10 arrive first and pair with the real state. */
            cdpr_cabin_state_t st;
            cdpr_lcm_wire_tensions_t ten;
            make_pair(k, &st, &ten);
            ten.tension_winch_N[2] = 1e300;
            send(&st, &ten);
            TEST_ASSERT_EQUAL_UINT64(1, g_node.stats.refused_implausible);
            TEST_ASSERT_NOT_NULL(strstr(g_node.last_refusal, "cable 3: tension"));
            continue; /* period 10's real pair then finds the state already refused */
        }
        send_real(k);
    }
    TEST_ASSERT_EQUAL_INT(N_STATES - 1, g_commands);
    for (int j = 0; j < 6; ++j) {
        TEST_ASSERT_TRUE(isfinite(g_node.tracker.ten_f[j]) && fabs(g_node.tracker.ten_f[j]) < 1.0);
    }
    TEST_ASSERT_TRUE_MESSAGE(g_max_rate < 0.05, "no winch ran off");
}

static void test_forged_time_ahead_is_refused(void)
{
    for (int64_t k = 0; k < N_STATES; ++k) {
        if (k == 20) {
            cdpr_cabin_state_t st;
            cdpr_lcm_wire_tensions_t ten;
            make_pair(k, &st, &ten);
            st.utime_us = ten.msg.utime_us = 8000000; /* the end of an 8 s run */
            send(&st, &ten);
            TEST_ASSERT_EQUAL_UINT64(1, g_node.stats.refused_time);
        }
        send_real(k);
    }
    TEST_ASSERT_EQUAL_INT(N_STATES, g_commands);
    TEST_ASSERT_TRUE(g_node.tracker.t_next_s < 1.0); /* the controller's clock did not jump */
}

typedef struct {
    const char *name;
    int what;
} bad_t;

static void test_implausible_values_are_refused(void)
{
    static const bad_t bad[] = {{"not a unit quaternion", 0},
                                {"speed", 1},
                                {"angular speed", 2},
                                {"length jump", 3},
                                {"far away", 4},
                                {"negative tension", 5},
                                {"below the winch's minimum", 6}};
    int64_t k = 0;
    send_real(k++);
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; ++i) {
        cdpr_cabin_state_t st;
        cdpr_lcm_wire_tensions_t ten;
        make_pair(k, &st, &ten);
        switch (bad[i].what) {
        case 0:
            st.orientation[1] = 0.1;
            break;
        case 1:
            st.velocity_m_per_s[0] = 1e3;
            break;
        case 2:
            st.angular_velocity_rad_per_s[2] = 1e3;
            break;
        case 3:
            ten.length_m[4] += 1.0; /* 1 m in 10 ms: 100 m/s */
            break;
        case 4:
            st.position_m[0] = 500.0;
            break;
        case 5:
            ten.tension_cabin_N[0] = -5.0;
            break;
        default:
            ten.length_m[1] = 0.1;
            break;
        }
        const uint64_t before = g_node.stats.refused_implausible;
        send(&st, &ten);
        TEST_ASSERT_EQUAL_UINT64_MESSAGE(before + 1, g_node.stats.refused_implausible, bad[i].name);
        send_real(k++); /* the real pair of the same period after it: answered */
    }
    TEST_ASSERT_EQUAL_INT(8, g_commands);
}

static void test_forged_anchor_resyncs_after_two_pairs(void)
{
    cdpr_cabin_state_t st;
    cdpr_lcm_wire_tensions_t ten;
    make_pair((int64_t)1 << 40, &st, &ten); /* the first state ever seen is forged */
    st.utime_us = ten.msg.utime_us = (int64_t)1 << 40;
    send(&st, &ten);
    const long before = g_commands; /* answered or not: nothing to compare it with */
    for (int64_t k = 0; k < 20; ++k) {
        send_real(k);
    }
    TEST_ASSERT_EQUAL_UINT64(1, g_node.stats.resyncs);
    TEST_ASSERT_EQUAL_UINT64(1, g_node.stats.refused_seq); /* real 0; real 1 re-anchors */
    TEST_ASSERT_EQUAL_INT(19, g_commands - before);
    TEST_ASSERT_EQUAL_INT64(19, g_last_state_seq);
}

static int g_in_control_calls;
static int64_t g_in_control_seq;
static void count_in_control(int64_t ours, int64_t state_seq, void *ctx)
{
    (void)ours;
    (void)ctx;
    g_in_control_calls++;
    g_in_control_seq = state_seq;
}

static void test_another_controller_in_control(void)
{
    g_in_control_calls = 0;
    g_node.on_in_control = count_in_control;
    for (int64_t k = 0; k < N_STATES; ++k) {
        cdpr_cabin_state_t st;
        cdpr_lcm_wire_tensions_t ten;
        make_pair(k, &st, &ten);
        if (k >= 30) {
            st.controller_session = 999; /* a take-over: a new command of it every period */
            st.command_seq = 1000 + k;
        } else if (k == 5) {
            st.controller_session = 0; /* one period on hold */
        }
        send(&st, &ten);
    }
    TEST_ASSERT_EQUAL_UINT64(30, g_node.stats.applied_other);
    TEST_ASSERT_EQUAL_UINT64(1, g_node.stats.applied_none);
    TEST_ASSERT_EQUAL_UINT64(28, g_node.stats.applied_ours);
    TEST_ASSERT_EQUAL_INT(1, g_in_control_calls); /* once, at the first state applying ours */
    TEST_ASSERT_EQUAL_INT64(1, g_in_control_seq);
    TEST_ASSERT_FALSE(cdpr_rt_tracker_in_control(&g_node, CDPR_RT_MAX_OTHER_SHARE));
    TEST_ASSERT_TRUE(cdpr_rt_tracker_in_control(&g_node, 0.6));
}

/* A controller that stopped: the plant applies its last command again (same session and seq)
 * until its watchdog holds, and a loaded plant may do so after our first command went out.
 * That is not a rival: counted as none, the controller stays in control. */
static void test_stopped_controller_last_command_is_not_a_rival(void)
{
    for (int64_t k = 0; k < N_STATES; ++k) {
        cdpr_cabin_state_t st;
        cdpr_lcm_wire_tensions_t ten;
        make_pair(k, &st, &ten);
        if (k < 12) {
            st.controller_session = 999;
            st.command_seq = 500; /* its last command, applied again and again */
        }
        send(&st, &ten);
    }
    TEST_ASSERT_EQUAL_UINT64(0, g_node.stats.applied_other);
    TEST_ASSERT_EQUAL_UINT64(11, g_node.stats.applied_none);
    TEST_ASSERT_EQUAL_UINT64(N_STATES - 12, g_node.stats.applied_ours);
    TEST_ASSERT_TRUE(cdpr_rt_tracker_in_control(&g_node, CDPR_RT_MAX_OTHER_SHARE));
}

/* A controller that starts while the plant runs may hear a tensions message before the first
 * state: no plant is followed yet, so it is not "another plant" (that made a restarted
 * cdpr-tracker exit 5 in fault_controller_restart under load). */
static void test_tensions_before_the_first_state_are_not_another_plant(void)
{
    cdpr_cabin_state_t st;
    cdpr_lcm_wire_tensions_t ten;
    make_pair(0, &st, &ten);
    unsigned char buf[1024];
    const int n = cdpr_lcm_wire_tensions_encode(&ten, buf, (int)sizeof buf);
    TEST_ASSERT_TRUE(n > 0);
    TEST_ASSERT_EQUAL_INT(0, lcm_publish(g_lcm, "CDPR_CABLE_TENSIONS", buf, (unsigned)n));
    (void)lcm_handle_timeout(g_lcm, 0);
    for (int64_t k = 1; k < 10; ++k) {
        send_real(k);
    }
    TEST_ASSERT_EQUAL_UINT64(0, g_node.stats.other_plant_states);
    TEST_ASSERT_EQUAL_INT64(9, g_last_state_seq);
}

static void test_plant_at_another_rate(void)
{
    /* A plant at 200 Hz against a 100 Hz controller: every step is half a period. */
    for (int64_t k = 0; k < 20; ++k) {
        cdpr_cabin_state_t st;
        cdpr_lcm_wire_tensions_t ten;
        make_pair(k, &st, &ten);
        st.utime_us = ten.msg.utime_us = k * 5000;
        send(&st, &ten);
    }
    TEST_ASSERT_EQUAL_UINT64(19, g_node.stats.rate_mismatch);
    /* A plant at 50 Hz: its time runs ahead of the periods: every pair refused. */
    cdpr_rt_tracker_detach(&g_node);
    lcm_destroy(g_lcm);
    setUp();
    for (int64_t k = 0; k < 20; ++k) {
        cdpr_cabin_state_t st;
        cdpr_lcm_wire_tensions_t ten;
        make_pair(k, &st, &ten);
        st.utime_us = ten.msg.utime_us = k * 20000;
        send(&st, &ten);
    }
    TEST_ASSERT_TRUE(g_node.stats.refused_time >= 18);
    TEST_ASSERT_TRUE(g_node.refused_in_row >= 18);
}

/* Two plants on one channel prefix, interleaved: the node keeps the plant it follows (its
 * states come every period, far inside CDPR_RT_PLANT_SILENCE_S) and counts the other's
 * (issue 26: the silence timeout x 1e-6 made every other-plant state a "restart"). */
/* The plant's diagnostics of period k (what cdpr-tracker's summary is built from). */
static void send_diag(int64_t seq, int64_t session, int64_t misses)
{
    cdpr_diagnostics_t d;
    memset(&d, 0, sizeof d);
    d.seq = seq;
    d.plant_session = session;
    d.periods = seq;
    d.deadline_misses = misses;
    unsigned char buf[2048];
    const int n = cdpr_diagnostics_t_encode(buf, 0, (int)sizeof buf, &d);
    TEST_ASSERT_TRUE(n > 0);
    TEST_ASSERT_EQUAL_INT(0, lcm_publish(g_lcm, "CDPR_DIAGNOSTICS", buf, (unsigned)n));
    for (int i = 0; i < 4; ++i) {
        (void)lcm_handle_timeout(g_lcm, 0);
    }
}

/* Forged diagnostics (far ahead, another plant session, before any trusted state, older than
 * the copy kept) never replace the plant's own: the copy the summary reads stays the newest
 * genuine one, within one state of the newest accepted pair. */
static void test_forged_diagnostics_never_replace_the_plants(void)
{
    send_diag(0, 77, 555); /* before any accepted pair: nothing to check it against */
    TEST_ASSERT_EQUAL_INT(0, g_node.have_plant_diag);
    for (int64_t k = 0; k < N_STATES; ++k) {
        send_diag(k, 77, k); /* the plant's: sent just before its state */
        if (k == 20) {
            send_diag(k + ((int64_t)1 << 40), 77, 999999); /* far ahead */
            send_diag(k, 78, 999998);                      /* another plant session */
            send_diag(k - 5, 77, 999997);                  /* older than the copy kept */
            TEST_ASSERT_EQUAL_INT64(20, g_node.plant_diag.seq);
            TEST_ASSERT_EQUAL_INT64(20, g_node.plant_diag.deadline_misses);
        }
        send_real(k);
    }
    TEST_ASSERT_EQUAL_INT(1, g_node.have_plant_diag);
    TEST_ASSERT_EQUAL_INT64(N_STATES - 1, g_node.plant_diag.seq);
    TEST_ASSERT_EQUAL_INT64(N_STATES - 1, g_node.plant_diag.deadline_misses);
    /* Kept: the genuine ones from period 1 on (period 0's arrived before the first pair). */
    TEST_ASSERT_EQUAL_UINT64(N_STATES - 1, g_node.stats.diagnostics);
    TEST_ASSERT_EQUAL_INT(N_STATES, g_commands);
}

static void test_second_plant_is_ignored_not_followed(void)
{
    for (int64_t k = 0; k < 20; ++k) {
        send_real(k);
        cdpr_cabin_state_t st;
        cdpr_lcm_wire_tensions_t ten;
        make_pair(k, &st, &ten);
        st.plant_session = ten.msg.plant_session = 88;
        send(&st, &ten);
    }
    TEST_ASSERT_EQUAL_UINT64(0, g_node.stats.plant_restarts);
    TEST_ASSERT_EQUAL_UINT64(40, g_node.stats.other_plant_states); /* states and tensions */
    TEST_ASSERT_EQUAL_INT64(77, g_node.plant_session);
    TEST_ASSERT_EQUAL_INT(20, g_commands);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_clean_run_answers_every_state);
    RUN_TEST(test_forged_far_seq_costs_one_update);
    RUN_TEST(test_forged_tension_never_reaches_the_filter);
    RUN_TEST(test_forged_time_ahead_is_refused);
    RUN_TEST(test_implausible_values_are_refused);
    RUN_TEST(test_forged_anchor_resyncs_after_two_pairs);
    RUN_TEST(test_another_controller_in_control);
    RUN_TEST(test_stopped_controller_last_command_is_not_a_rival);
    RUN_TEST(test_tensions_before_the_first_state_are_not_another_plant);
    RUN_TEST(test_plant_at_another_rate);
    RUN_TEST(test_second_plant_is_ignored_not_followed);
    RUN_TEST(test_forged_diagnostics_never_replace_the_plants);
    return UNITY_END() ? 1 : 0;
}
