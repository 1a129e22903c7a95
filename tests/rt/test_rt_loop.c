/* SPDX-License-Identifier: BSD-3-Clause */
/// @file test_rt_loop.c
/// The real-time plant node (lib/rt) over a real liblcm memq:// provider, in-process:
///  - lockstep closed loop over LCM == the in-process loop (plant + controller called
///    directly), bit for bit, every period;
///  - the periodic thread makes zero heap allocations and zero lcm_* calls;
///  - controller silence -> hold after the watchdog timeout, resume -> control resumes;
///    malformed commands in between are counted and ignored, the plant keeps running
///    (the script moves on by what it has seen, not by state seq or time: how many states
///    the machine's load lets through in a given time changes no assertion);
///  - a stalled publisher (bridge thread blocked) -> the ring drops and counts, the periodic
///    thread keeps stepping (it never waits for the bridge).
/// The stall is ended by the periodic thread's progress, not by a sleep: what is asserted does
/// not depend on how many periods the machine's load lets the thread run in a given time.
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

#include "alloc_count.h"
#include "cdpr/lcm/pack.h"
#include "cdpr/host/plant.h"
#include "cdpr/rt/plant_node.h"
#include "cdpr/rt/tracker_node.h"
#include "lcm_call_count.h"
#include "test_real.h"
#include "unity.h"

#ifndef CDPR_SOURCE_DIR
#define CDPR_SOURCE_DIR "."
#endif

void setUp(void) {}
void tearDown(void) {}

static cdpr_scenario_t g_sc;
static cdpr_rt_plant_t g_rt;
static cdpr_rt_tracker_t g_tracker;
static cdpr_plant_t g_ref;
static cdpr_tracker_t g_ref_ctl;

static void load(const char *name)
{
    char path[1024];
    cdpr_scenario_error_t err;
    snprintf(path, sizeof path, "%s/scenarios/%s.yaml", CDPR_SOURCE_DIR, name);
    TEST_ASSERT_EQUAL_INT_MESSAGE(CDPR_OK, cdpr_scenario_load(path, &g_sc, &err), err.msg);
}

/* The run settings of g_sc as the apps' --rate, --duration, --max-trials set them. */
static void run_settings(double rate_hz, double duration_s, double max_trials)
{
    cdpr_scenario_overrides_t ov;
    cdpr_scenario_overrides_none(&ov);
    ov.rate_hz = rate_hz;
    ov.duration_s = duration_s;
    ov.max_trials = max_trials;
    cdpr_scenario_error_t err;
    TEST_ASSERT_EQUAL_INT_MESSAGE(
        CDPR_OK, cdpr_scenario_override(&g_sc, &ov, "test_rt_loop", NULL, &err), err.msg);
}

/* ------------------------------------------------------------ lockstep == in-process */

/* Lockstep, with the wall clock out of it: the timeout only tells a deadlock from a loaded
 * machine, and the watchdog is as long as it may be, since the mailbox applies it in lockstep
 * too (an answer read more than the watchdog timeout after it arrived would be taken as stale:
 * that period would wait for the lockstep timeout and hold). */
static void lockstep_opts(cdpr_rt_plant_opts_t *o)
{
    o->lockstep = 1;
    o->lockstep_timeout_s = 30.0;
    o->lcm.watchdog_timeout_s = 3600.0;
}

#define MAX_REC 512
typedef struct {
    long n;
    cdpr_tracker_meas_t meas[MAX_REC];
    double rate[MAX_REC][CDPR_MAX_CABLES];
} rec_t;
static rec_t g_lcm_rec;

static void record_lcm(const cdpr_tracker_meas_t *m, const cdpr_tracker_cmd_t *c,
                       const cdpr_cabin_state_t *st, const cdpr_cable_tensions_t *ten, void *ctx)
{
    (void)st;
    (void)ten;
    rec_t *r = ctx;
    if (r->n < MAX_REC) {
        r->meas[r->n] = *m;
        memcpy(r->rate[r->n], c->rate_m_per_s, sizeof r->rate[0]);
        r->n++;
    }
}

static int tracker_open(lcm_t *lcm, void *ctx)
{
    return cdpr_rt_tracker_attach(ctx, lcm);
}

static void bits_equal(const double *a, const double *b, int n, const char *what, long k)
{
    char msg[128];
    snprintf(msg, sizeof msg, "%s differs at period %ld", what, k);
    TEST_ASSERT_EQUAL_MEMORY_MESSAGE(a, b, sizeof(double) * (size_t)n, msg);
}

/* `gust`: 0, or 1 for a wind gust (scenario wind section) with the wind feed-forward on: the
 * plant node and the tracker node take each period's wind from the section, the in-process
 * loop sets the same value (at the period's midpoint) on its plant and controller. */
static void lockstep_equals_in_process(int gust)
{
    load("paper-line");
    const double rate = 100.0;
    const long periods = 150;
    cdpr_scenario_error_t err;
    if (gust != 0) {
        const cdpr_scenario_wind_t w = {1, 4.0, 90.0, CDPR_WIND_GUST, 0.5, 0.4, 6.0};
        g_sc.wind = w;
        cdpr_scenario_wind_at(&g_sc, 0.0, g_sc.rig.wind_m_per_s);
        g_sc.gains.wind_ff = 1.0;
    }

    /* Over LCM: cdpr_rt in lockstep, the tracker node on the bridge thread (memq). */
    cdpr_rt_plant_opts_t o;
    cdpr_rt_plant_opts_default(&o);
    run_settings(rate, (double)periods / rate, (double)NAN);
    lockstep_opts(&o);
    o.lcm.url = "memq://";
    o.lcm.on_open = tracker_open;
    o.lcm.on_open_ctx = &g_tracker;
    TEST_ASSERT_EQUAL_INT_MESSAGE(CDPR_OK, cdpr_rt_plant_init(&g_rt, &g_sc, &o, &err), err.msg);
    const cdpr_tracker_gains_t g = g_sc.gains;
    TEST_ASSERT_EQUAL_INT(CDPR_OK,
                          cdpr_rt_tracker_init(&g_tracker, &g_rt.plant.params, g_rt.plant.pp.winch,
                                               &g_sc.traj, &g, 1.0 / rate, NULL, NULL));
    g_tracker.answer_in_handler = 1;
    g_tracker.on_step = record_lcm;
    g_tracker.on_step_ctx = &g_lcm_rec;
    g_tracker.wind = &g_sc.wind;
    g_lcm_rec.n = 0;
    TEST_ASSERT_EQUAL_INT_MESSAGE(CDPR_OK, cdpr_rt_plant_run(&g_rt, &err), err.msg);
    TEST_ASSERT_EQUAL_INT(periods, g_rt.tel.periods);
    TEST_ASSERT_EQUAL_INT(0, g_rt.tel.lockstep_timeouts);
    TEST_ASSERT_EQUAL_INT(0, g_rt.tel.hold_periods);
    TEST_ASSERT_EQUAL_INT(0, g_rt.tel.step_failures);
    TEST_ASSERT_TRUE(g_lcm_rec.n >= periods);
    /* The controller's cost: every step the node ran is timed, quantiles ordered. */
    int64_t med;
    int64_t p99;
    int64_t mx;
    TEST_ASSERT_EQUAL_UINT64(g_tracker.stats.answered + g_tracker.stats.bad_measurement,
                             cdpr_rt_tracker_step_times(&g_tracker, &med, &p99, &mx));
    TEST_ASSERT_TRUE(med > 0 && med <= p99 && p99 <= mx);
    /* The plant's diagnostics reached the controller (1 Hz: the one at state 100 was handled
     * before the answer to state 101): its session, lockstep's one period per state, its work
     * so far, no overrun in lockstep, the thread CPU quantiles ordered. */
    const cdpr_diagnostics_t *dg = &g_tracker.plant_diag;
    TEST_ASSERT_EQUAL_INT(1, g_tracker.have_plant_diag);
    TEST_ASSERT_TRUE(g_tracker.stats.diagnostics >= 1);
    TEST_ASSERT_TRUE(dg->seq >= 100 && dg->seq <= periods);
    TEST_ASSERT_EQUAL_INT64(g_rt.tel.plant_session, dg->plant_session);
    TEST_ASSERT_EQUAL_INT64(dg->seq, dg->periods);
    TEST_ASSERT_EQUAL_INT(CDPR_DIAGNOSTICS_T_INTEGRATOR_RKF45, dg->integrator);
    TEST_ASSERT_TRUE(dg->rhs_evals > 0 && (unsigned long)dg->rhs_evals <= g_rt.tel.rhs_evals);
    TEST_ASSERT_EQUAL_INT64(0, dg->deadline_misses + dg->startup_misses);
    TEST_ASSERT_EQUAL_INT(0, dg->substeps);
    TEST_ASSERT_TRUE(dg->cpu_ns_median > 0 && dg->cpu_ns_median <= dg->cpu_ns_p99 &&
                     dg->cpu_ns_p99 <= dg->cpu_ns_max);
    if (dg->seq == periods) { /* the one sent before the last state: the whole run's work */
        TEST_ASSERT_EQUAL_UINT64(g_rt.tel.rhs_evals, (uint64_t)dg->rhs_evals);
    }

    /* In-process: the same plant and controller called directly, no LCM. */
    cdpr_scenario_t sc_ref = g_sc;
    sc_ref.period_s = 1.0 / rate;
    TEST_ASSERT_EQUAL_INT_MESSAGE(CDPR_OK, cdpr_host_plant_init(&g_ref, &sc_ref, NULL, &err),
                                  err.msg);
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_tracker_init(&g_ref_ctl, &g_ref.params, &g_sc.traj, &g,
                                                     1.0 / rate, 0.0, NULL));
    for (long k = 0; k < periods; ++k) {
        cdpr_tracker_meas_t m;
        cdpr_plant_measure(&g_ref, &m);
        const cdpr_tracker_meas_t *l = &g_lcm_rec.meas[k];
        TEST_ASSERT_EQUAL_MEMORY(&m.t_s, &l->t_s, sizeof m.t_s);
        bits_equal(&m.cabin.p_m.x, &l->cabin.p_m.x, 3, "position", k);
        bits_equal(&m.cabin.q.w, &l->cabin.q.w, 4, "orientation", k);
        bits_equal(&m.cabin.v_m_per_s.x, &l->cabin.v_m_per_s.x, 3, "velocity", k);
        bits_equal(&m.cabin.w_rad_per_s.x, &l->cabin.w_rad_per_s.x, 3, "angular velocity", k);
        bits_equal(m.length_m, l->length_m, CDPR_ROBOT_CABLES, "lengths", k);
        if (gust != 0) {
            double w[3];
            cdpr_scenario_wind_at(&g_sc, m.t_s + 0.5 * g_ref.pp.period_s, w);
            g_ref.robot.in.wind_m_per_s = cdpr_v3(w[0], w[1], w[2]);
            TEST_ASSERT_EQUAL_INT(CDPR_OK,
                                  cdpr_tracker_set_wind(&g_ref_ctl, g_ref.robot.in.wind_m_per_s));
        }
        cdpr_tracker_cmd_t c;
        TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_tracker_step(&g_ref_ctl, &m, &c));
        /* The tracker node clamps to the winch limit before publishing; the plant's winch
         * clamps the same way in-process, so clamp here to compare what was sent. */
        double sent[CDPR_MAX_CABLES];
        for (int j = 0; j < CDPR_ROBOT_CABLES; ++j) {
            const double u = g_ref.pp.winch[j].u_max_m_per_s;
            sent[j] = fmax(-u, fmin(u, c.rate_m_per_s[j]));
        }
        bits_equal(sent, g_lcm_rec.rate[k], CDPR_ROBOT_CABLES, "command", k);
        int flags = 0;
        TEST_ASSERT_TRUE(cdpr_plant_step(&g_ref, CDPR_WINCH_RATE, c.rate_m_per_s, &flags) >= 0);
    }
    /* The final states agree too (the whole state vector, not only what was measured). */
    TEST_ASSERT_EQUAL_INT(g_ref.robot.dim, g_rt.plant.robot.dim);
    TEST_ASSERT_EQUAL_MEMORY(g_ref.y, g_rt.plant.y, sizeof(double) * (size_t)g_ref.robot.dim);
    /* And the run moved: a loop that never stepped would also "agree". */
    TEST_ASSERT_TRUE(fabs(g_ref.y[0] - g_ref.initial.pose.p_m.x) +
                         fabs(g_ref.y[1] - g_ref.initial.pose.p_m.y) +
                         fabs(g_ref.y[2] - g_ref.initial.pose.p_m.z) >
                     0.1);
}

static void test_lockstep_memq_equals_in_process_loop(void)
{
    lockstep_equals_in_process(0);
}

/* A scenario wind section through the real-time loop (issue 23): the gust reaches the plant
 * node and the controller node's feed-forward exactly as in the in-process loop. */
static void test_lockstep_with_a_wind_gust_equals_in_process_loop(void)
{
    lockstep_equals_in_process(1);
}

/* ------------------------------------------------ RT thread: no allocation, no lcm_* */

typedef struct {
    unsigned long allocs;
    unsigned long lcm_calls;
    int done;
} rt_counts_t;
static rt_counts_t g_counts;

static void count_hook(int phase, void *ctx)
{
    rt_counts_t *c = ctx;
    if (phase == 0) {
        cdpr_alloc_reset();
        cdpr_lcm_calls_reset();
    } else {
        c->allocs = cdpr_alloc_count();
        c->lcm_calls = cdpr_lcm_calls();
        c->done = 1;
    }
}

static void test_rt_thread_makes_no_allocation_and_no_lcm_call(void)
{
    load("paper-line");
    cdpr_scenario_error_t err;
    cdpr_rt_plant_opts_t o;
    cdpr_rt_plant_opts_default(&o);
    run_settings(1000.0, 0.3, 200.0);
    lockstep_opts(&o);
    o.shape_rate_hz = 100.0; /* shapes and diagnostics are on the RT path too */
    o.diag_rate_hz = 50.0;
    o.lcm.url = "memq://";
    o.lcm.on_open = tracker_open;
    o.lcm.on_open_ctx = &g_tracker;
    o.on_rt_thread = count_hook;
    o.on_rt_thread_ctx = &g_counts;
    TEST_ASSERT_EQUAL_INT_MESSAGE(CDPR_OK, cdpr_rt_plant_init(&g_rt, &g_sc, &o, &err), err.msg);
    const cdpr_tracker_gains_t g = g_sc.gains;
    TEST_ASSERT_EQUAL_INT(CDPR_OK,
                          cdpr_rt_tracker_init(&g_tracker, &g_rt.plant.params, g_rt.plant.pp.winch,
                                               &g_sc.traj, &g, 1e-3, NULL, NULL));
    g_tracker.answer_in_handler = 1;
    cdpr_alloc_reset();
    TEST_ASSERT_EQUAL_INT_MESSAGE(CDPR_OK, cdpr_rt_plant_run(&g_rt, &err), err.msg);
    TEST_ASSERT_EQUAL_INT(1, g_counts.done);
    TEST_ASSERT_EQUAL_INT(300, g_rt.tel.periods);
    TEST_ASSERT_EQUAL_INT(0, g_rt.tel.lockstep_timeouts);
    /* The other threads did call liblcm (a counter that saw nothing proves nothing). */
    TEST_ASSERT_TRUE(cdpr_lcm_calls_total() > 300);
    TEST_ASSERT_EQUAL_UINT(0, g_counts.lcm_calls);
    if (cdpr_alloc_counting_available() == 0) {
        TEST_IGNORE_MESSAGE(cdpr_alloc_unavailable_reason());
    }
    TEST_ASSERT_TRUE(cdpr_alloc_count_total() > 0);
    TEST_ASSERT_EQUAL_UINT(0, g_counts.allocs);
}

/* ------------------------------------------- silence, malformed input, resume; stall */

/* The stall: the bridge thread stays blocked in the state handler until the periodic thread has
 * stepped this many periods (the ring's 256 slots hold 128 periods of state + tensions) ... */
#define STALL_PERIODS 300
/* ... or this long [ns], which only a periodic thread that waits for the bridge needs: the
 * test then fails (a generous bound: it only has to tell a deadlock from a loaded machine). */
#define STALL_LIMIT_NS (30LL * 1000000000LL)

/* The silence: resume once the controller has seen this many states on hold. */
#define SILENCE_HOLD_STATES 250
/* A scripted run is stopped (opts.stop) this many periods after the event it waits for; its
 * plant time is only a bound. */
#define SCRIPT_TAIL_PERIODS 100
#define SCRIPT_RUN_S        60.0

/* A scripted controller on the bridge thread: answers every state with a fixed rate command,
 * except while silent; with each of the first `garbage` states from seq `garbage_at` on, sends
 * bad commands first; from `silence_at` on, stays silent until it has seen
 * SILENCE_HOLD_STATES states on hold, then answers again; stalls the bridge thread once, at
 * the first state from `stall_at` on, when `stall` is set. Every step is taken on what the
 * controller has seen (a state of a given seq may have been dropped, or seen late). */
typedef struct {
    lcm_t *lcm;
    int64_t seq;    /* of the last command sent */
    int64_t seq_ns; /* when it was sent (cdpr_lcm_now_ns) */
    long states;
    long garbage_at, garbage, garbage_sent;
    long silence_at;
    int silent;               /* 0 before the silence, 1 in it, 2 after */
    int64_t silence_seq;      /* the first state not answered */
    int64_t hold_after_ns;    /* first state on hold seen - the last command sent */
    long hold_seen;           /* states on hold seen in the silence */
    long not_held_after_hold; /* states not on hold seen in it after the first on hold */
    int64_t resume_seq;       /* the first state answered again */
    int64_t resume_command;   /* its command's seq */
    int64_t resumed_seq;      /* the first state stepped with a command of the resume */
    long hold_after_resumed;  /* states on hold seen after that one (printed only) */
    long stall_at;
    int stall;
    int stall_timed_out;
    int64_t stall_state_seq;
    int64_t rt_seq_before_stall, rt_seq_after_stall;
    uint64_t dropped_before_stall, dropped_after_stall;
} script_t;
static script_t g_script;
static volatile int g_stop;

static int64_t rt_seq(void)
{
    return __atomic_load_n(&g_rt.seq, __ATOMIC_RELAXED);
}

static uint64_t ring_dropped(void)
{
    cdpr_lcm_stats_t s;
    cdpr_lcm_bridge_stats(&g_rt.bridge, &s);
    return s.ring.dropped;
}

/* The stall (bridge thread): block until the periodic thread has stepped STALL_PERIODS periods
 * more (or STALL_LIMIT_NS passed: it did not), polling its seq every millisecond. */
static void stall_bridge(script_t *s, int64_t state_seq)
{
    const struct timespec ms = {0, 1000000L};
    s->stall = 0;
    s->stall_state_seq = state_seq;
    s->dropped_before_stall = ring_dropped();
    s->rt_seq_before_stall = rt_seq();
    const int64_t t0 = cdpr_lcm_now_ns();
    while (rt_seq() - s->rt_seq_before_stall < STALL_PERIODS) {
        if (cdpr_lcm_now_ns() - t0 > STALL_LIMIT_NS) {
            s->stall_timed_out = 1;
            break;
        }
        nanosleep(&ms, NULL);
    }
    s->rt_seq_after_stall = rt_seq();
    s->dropped_after_stall = ring_dropped();
}

/* Garbage, a truncated command, a NaN command (before the answer); the answer again, a
 * replayed seq (after it): one of each reject kind. The replay comes right after the command
 * it replays: the validator takes a replay from a session silent for the watchdog timeout as a
 * new anchor (command.h, "Sessions"), and right after it only a bridge thread kept off the CPU
 * between two messages for that long makes it one. */
static void send_garbage(script_t *s, const cdpr_cabin_state_t *st)
{
    static const unsigned char junk[] = {1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12};
    (void)lcm_publish(s->lcm, "CDPR_WINCH_COMMAND", junk, sizeof junk);
    cdpr_winch_command_t c;
    double values[6] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
    memset(&c, 0, sizeof c);
    c.value = values;
    c.seq = s->seq + 1;
    c.state_seq = st->seq;
    c.controller_session = 1;
    c.plant_session = st->plant_session;
    c.n_cables = 6;
    c.value[2] = NAN_D;
    unsigned char buf[256];
    const int len = cdpr_winch_command_t_encode(buf, 0, (int)sizeof buf, &c);
    (void)lcm_publish(s->lcm, "CDPR_WINCH_COMMAND", buf, (unsigned)len - 3u);
    (void)lcm_publish(s->lcm, "CDPR_WINCH_COMMAND", buf, (unsigned)len);
}

/* The silence (states seen in it). It begins at a state stepped with the last command sent,
 * not on hold: that command is then the newest the plant has, and stays so, so every state on
 * hold in the silence is the watchdog's doing and, once on hold, the plant stays on hold.
 * Returns 1 while silent. */
static int silence(script_t *s, const cdpr_cabin_state_t *st, int hold)
{
    if (s->silent == 0 && st->seq >= s->silence_at && s->garbage_sent == s->garbage && hold == 0 &&
        st->command_seq == s->seq) {
        s->silent = 1;
        s->silence_seq = st->seq;
    }
    if (s->silent != 1) {
        return 0;
    }
    if (hold != 0) {
        if (s->hold_seen == 0) {
            s->hold_after_ns = cdpr_lcm_now_ns() - s->seq_ns;
        }
        s->hold_seen++;
    } else if (s->hold_seen > 0) {
        s->not_held_after_hold++;
    }
    if (s->hold_seen < SILENCE_HOLD_STATES) {
        return 1;
    }
    s->silent = 2;
    s->resume_seq = st->seq;
    s->resume_command = s->seq + 1;
    return 0;
}

static void on_state(const lcm_recv_buf_t *rbuf, const char *channel, void *user)
{
    (void)channel;
    script_t *s = user;
    cdpr_cabin_state_t st;
    if (cdpr_cabin_state_t_decode(rbuf->data, 0, (int)rbuf->data_size, &st) !=
        (int)rbuf->data_size) {
        return;
    }
    s->states++;
    const int hold = ((st.flags & CDPR_CABIN_STATE_T_FLAG_HOLD) != 0) ? 1 : 0;
    /* From stall_at on: a state of seq stall_at itself may have been dropped. */
    if (s->stall != 0 && st.seq >= s->stall_at) {
        stall_bridge(s, st.seq);
    }
    if (s->stall_state_seq > 0 && st.seq >= s->rt_seq_after_stall + SCRIPT_TAIL_PERIODS) {
        g_stop = 1;
    }
    const int garbage = (s->garbage_sent < s->garbage && st.seq >= s->garbage_at) ? 1 : 0;
    if (garbage != 0) {
        send_garbage(s, &st);
    }
    if (garbage == 0 && silence(s, &st, hold) != 0) {
        return;
    }
    if (s->silent == 2) {
        if (s->resumed_seq == 0 && st.command_seq >= s->resume_command) {
            s->resumed_seq = st.seq;
        }
        if (s->resumed_seq > 0) {
            s->hold_after_resumed += hold;
            if (st.seq >= s->resumed_seq + SCRIPT_TAIL_PERIODS) {
                g_stop = 1;
            }
        }
    }
    cdpr_winch_command_t c;
    double values[6];
    memset(&c, 0, sizeof c);
    c.value = values;
    c.seq = ++s->seq;
    c.state_seq = st.seq;
    c.controller_session = 1;
    c.plant_session = st.plant_session;
    c.mode = CDPR_WINCH_COMMAND_T_MODE_RATE;
    c.n_cables = 6;
    for (int j = 0; j < 6; ++j) {
        c.value[j] = 0.01; /* pay out slowly: the cabin sinks */
    }
    unsigned char buf[256];
    const int len = cdpr_winch_command_t_encode(buf, 0, (int)sizeof buf, &c);
    s->seq_ns = cdpr_lcm_now_ns();
    (void)lcm_publish(s->lcm, "CDPR_WINCH_COMMAND", buf, (unsigned)len);
    if (garbage != 0) {
        (void)lcm_publish(s->lcm, "CDPR_WINCH_COMMAND", buf, (unsigned)len); /* replayed */
        s->garbage_sent++;
    }
}

static int script_open(lcm_t *lcm, void *ctx)
{
    script_t *s = ctx;
    s->lcm = lcm;
    return (lcm_subscribe(lcm, "CDPR_CABIN_STATE", on_state, s) != NULL) ? 0 : -1;
}

/* The options of a scripted run: free-running at 1 kHz for `duration_s` of plant time. */
static void scripted_opts(cdpr_rt_plant_opts_t *o, double duration_s)
{
    load("paper-line");
    cdpr_rt_plant_opts_default(o);
    run_settings(1000.0, duration_s, 200.0);
    o->lcm.url = "memq://";
    o->lcm.watchdog_timeout_s = 0.1;
    o->lcm.on_open = script_open;
    o->lcm.on_open_ctx = &g_script;
}

static void test_silence_holds_then_resumes_and_bad_commands_are_ignored(void)
{
    memset(&g_script, 0, sizeof g_script);
    g_stop = 0;
    g_script.garbage_at = 100;
    g_script.garbage = 100;
    g_script.silence_at = 300;
    cdpr_scenario_error_t err;
    cdpr_rt_plant_opts_t o;
    scripted_opts(&o, SCRIPT_RUN_S);
    o.stop = &g_stop;
    TEST_ASSERT_EQUAL_INT_MESSAGE(CDPR_OK, cdpr_rt_plant_init(&g_rt, &g_sc, &o, &err), err.msg);
    /* Stopped by the script (g_stop) once control had resumed; CDPR_OK would mean the run
     * reached its plant time first (the script never got there). */
    TEST_ASSERT_EQUAL_INT_MESSAGE(CDPR_E_INTERRUPTED, cdpr_rt_plant_run(&g_rt, &err),
                                  "the script did not complete");
    const cdpr_rt_plant_telemetry_t *t = &g_rt.tel;
    const cdpr_lcm_stats_t *s = &t->lcm;
    const script_t *sc = &g_script;
    printf("silence from state %lld: hold %.1f ms after the last command (watchdog 100 ms); "
           "resumed at state %lld, stepped with it from state %lld (%ld states on hold seen "
           "after); %ld periods, %ld on hold, %llu hold entries\n",
           (long long)sc->silence_seq, 1e-6 * (double)sc->hold_after_ns, (long long)sc->resume_seq,
           (long long)sc->resumed_seq, sc->hold_after_resumed, t->periods, t->hold_periods,
           (unsigned long long)s->hold_entries);
    /* 100 batches of garbage: each kind counted, none accepted. */
    TEST_ASSERT_EQUAL_INT(100, sc->garbage_sent);
    TEST_ASSERT_EQUAL_UINT64(100u, s->rejected[CDPR_LCM_REJECT_WRONG_TYPE]);
    TEST_ASSERT_EQUAL_UINT64(100u, s->rejected[CDPR_LCM_REJECT_MALFORMED]);
    TEST_ASSERT_EQUAL_UINT64(100u, s->rejected[CDPR_LCM_REJECT_NOT_FINITE]);
    TEST_ASSERT_EQUAL_UINT64(100u, s->rejected[CDPR_LCM_REJECT_REPLAYED]);
    /* Silence: the plant went on hold (the script waited for SILENCE_HOLD_STATES states on
     * hold), not before the watchdog timeout after the last command (the state seen later
     * than the period that held, the command received after it was sent), and stayed on hold
     * until the commands resumed. */
    TEST_ASSERT_TRUE(sc->silence_seq >= 300);
    TEST_ASSERT_EQUAL_INT(SILENCE_HOLD_STATES, sc->hold_seen);
    TEST_ASSERT_TRUE(sc->hold_after_ns > 100000000);
    TEST_ASSERT_EQUAL_INT(0, sc->not_held_after_hold);
    TEST_ASSERT_TRUE(t->hold_periods >= SILENCE_HOLD_STATES);
    TEST_ASSERT_TRUE(s->hold_entries >= 1u);
    /* Resume: the plant stepped with the commands again (a state stepped with one seen). */
    TEST_ASSERT_TRUE(sc->resume_seq > sc->silence_seq);
    TEST_ASSERT_TRUE(sc->resumed_seq >= sc->resume_seq);
    TEST_ASSERT_EQUAL_INT(0, t->step_failures);
}

static void test_stalled_publisher_drops_and_rt_thread_keeps_stepping(void)
{
    memset(&g_script, 0, sizeof g_script);
    memset(&g_counts, 0, sizeof g_counts);
    g_stop = 0;
    g_script.silence_at = 1L << 30;
    g_script.stall_at = 100;
    g_script.stall = 1;
    cdpr_scenario_error_t err;
    cdpr_rt_plant_opts_t o;
    scripted_opts(&o, SCRIPT_RUN_S);
    o.diag_rate_hz = 0.0; /* diagnostics only at the end: the count below is exact */
    o.stop = &g_stop;
    o.on_rt_thread = count_hook;
    o.on_rt_thread_ctx = &g_counts;
    TEST_ASSERT_EQUAL_INT_MESSAGE(CDPR_OK, cdpr_rt_plant_init(&g_rt, &g_sc, &o, &err), err.msg);
    cdpr_alloc_reset();
    /* Stopped by the script (g_stop) once the states flowed again after the stall. */
    TEST_ASSERT_EQUAL_INT_MESSAGE(CDPR_E_INTERRUPTED, cdpr_rt_plant_run(&g_rt, &err), err.msg);
    const cdpr_rt_plant_telemetry_t *t = &g_rt.tel;
    const script_t *s = &g_script;
    const int64_t advanced = s->rt_seq_after_stall - s->rt_seq_before_stall;
    const uint64_t dropped = s->dropped_after_stall - s->dropped_before_stall;
    printf("stall at state %lld: the periodic thread stepped %lld periods meanwhile, the ring "
           "dropped %llu messages; %ld periods in all\n",
           (long long)s->stall_state_seq, (long long)advanced, (unsigned long long)dropped,
           t->periods);
    TEST_ASSERT_TRUE_MESSAGE(s->stall_state_seq >= 100, "the stall never happened");
    /* While the bridge thread was blocked, the periodic thread went on: the stall ended because
     * it stepped STALL_PERIODS periods. A thread that waited for the bridge (or blocked on the
     * full ring) would not, and the stall would end by the time limit instead. */
    TEST_ASSERT_FALSE_MESSAGE(s->stall_timed_out,
                              "the periodic thread stopped stepping while the bridge was blocked");
    TEST_ASSERT_TRUE(advanced >= STALL_PERIODS);
    /* Meanwhile it pushed state + tensions of every period it completed (those of the periods
     * after the one seen at the start of the stall, up to the one seen at its end); nothing was
     * published, so all but the ring's free slots were dropped and counted (drop-newest). */
    TEST_ASSERT_TRUE(dropped >= (uint64_t)(2 * (advanced - 1) - CDPR_LCM_RING_SLOTS));
    /* Every message of the run is either queued or counted as dropped: state + tensions per
     * state (periods + 1 states) and the final diagnostics. */
    TEST_ASSERT_EQUAL_UINT64((uint64_t)(2 * (t->periods + 1) + 1),
                             t->lcm.ring.pushed + t->lcm.ring.dropped);
    TEST_ASSERT_EQUAL_INT(0, t->step_failures);
    /* A full ring costs the periodic thread no allocation and no lcm_* call either. */
    TEST_ASSERT_EQUAL_INT(1, g_counts.done);
    TEST_ASSERT_EQUAL_UINT(0, g_counts.lcm_calls);
    if (cdpr_alloc_counting_available() == 0) {
        TEST_IGNORE_MESSAGE(cdpr_alloc_unavailable_reason());
    }
    TEST_ASSERT_EQUAL_UINT(0, g_counts.allocs);
}

/* The overrun contract on synthetic periods (no clock involved): each miss classified by what
 * made it late, the start-up counted apart, the policy stops at its limits. 1 kHz: T = 1 ms. */
static void test_overruns_classified_and_policy(void)
{
    static cdpr_rt_plant_t rt;
    memset(&rt, 0, sizeof rt);
    cdpr_rt_plant_opts_default(&rt.o);
    rt.o.startup_s = 0.005;
    rt.startup_periods = 5; /* what cdpr_rt_plant_init makes of it at 1 kHz */
    rt.o.max_misses = 4;
    rt.o.max_misses_in_row = 0;
    rt.period_ns = 1000000;
    rt.plant.pp.period_s = 0.001;
    const int64_t T = rt.period_ns;
    long in_row = 0;
    int stop = 0;
    /* start-up: a miss of any kind is counted apart */
    for (int k = 0; k < 5; ++k) {
        rt.tel.periods = k;
        stop |= cdpr_rt_plant_judge_period(&rt, k * T, k * T + 3 * T, k * T + 4 * T, 100, &in_row);
    }
    TEST_ASSERT_EQUAL_INT(5, rt.tel.startup_misses);
    TEST_ASSERT_EQUAL_INT(5, rt.tel.deadline_misses);
    const struct {
        int64_t wake; /* t0 - start */
        int64_t wall; /* t1 - t0 */
        int64_t cpu;  /* thread CPU time */
        long late, pre, lng, row;
    } p[] = {
        {10000, 400000, 390000, 0, 0, 0, 0},   /* on time */
        {800000, 400000, 390000, 1, 0, 0, 1},  /* woke 0.8 ms late, 0.4 ms of work */
        {10000, 1500000, 400000, 1, 1, 0, 2},  /* 1.5 ms of wall, 0.4 ms of CPU: preempted */
        {10000, 1500000, 1200000, 1, 1, 1, 3}, /* 1.2 ms of CPU: the plant is too slow */
        {10000, 990000, 980000, 1, 1, 1, 0},   /* just in time: the run of misses ends */
    };
    for (int i = 0; i < 5; ++i) {
        rt.tel.periods = 5 + i;
        const int64_t start = (5 + i) * T;
        stop |= cdpr_rt_plant_judge_period(&rt, start, start + p[i].wake,
                                           start + p[i].wake + p[i].wall, p[i].cpu, &in_row);
        TEST_ASSERT_EQUAL_INT(p[i].late, rt.tel.misses_late_wakeup);
        TEST_ASSERT_EQUAL_INT(p[i].pre, rt.tel.misses_preempted);
        TEST_ASSERT_EQUAL_INT(p[i].lng, rt.tel.misses_long_compute);
        TEST_ASSERT_EQUAL_INT(p[i].row, in_row);
    }
    TEST_ASSERT_EQUAL_INT(0, stop);
    TEST_ASSERT_EQUAL_INT(3, rt.tel.misses_in_row_max);
    TEST_ASSERT_EQUAL_INT(800000, rt.tel.wake_late_ns_max);
    /* The telemetry goes to diagnostics_t and from it to a summary's real-time block field
     * by field (distinct values, so that no two can be swapped unseen). */
    const cdpr_rt_plant_telemetry_t saved = rt.tel;
    rt.tel.deadline_misses = 16;
    rt.tel.startup_misses = 15;
    rt.tel.misses_late_wakeup = 11;
    rt.tel.misses_preempted = 12;
    rt.tel.misses_long_compute = 13;
    rt.tel.misses_in_row_max = 14;
    rt.tel.wake_late_ns_max = 17000;
    rt.tel.compute_ns_max = 19000;
    rt.tel.cpu_ns_max = 18000;
    rt.tel.overrun_stop = 1;
    cdpr_summary_rt_t fig;
    cdpr_rt_plant_summary_figures(&rt, &fig);
    TEST_ASSERT_EQUAL_INT(16, rt.diag_msg.deadline_misses);
    TEST_ASSERT_EQUAL_INT(1, fig.known);
    TEST_ASSERT_EQUAL_UINT(16, fig.deadline_misses);
    TEST_ASSERT_EQUAL_UINT(15, fig.startup_misses);
    TEST_ASSERT_EQUAL_UINT(11, fig.misses_late_wakeup);
    TEST_ASSERT_EQUAL_UINT(12, fig.misses_preempted);
    TEST_ASSERT_EQUAL_UINT(13, fig.misses_long_compute);
    TEST_ASSERT_EQUAL_UINT(14, fig.misses_in_row_max);
    TEST_ASSERT_EQUAL_DOUBLE(17.0, fig.wake_late_us_max);
    TEST_ASSERT_EQUAL_DOUBLE(19.0, fig.compute_us_max);
    TEST_ASSERT_EQUAL_DOUBLE(18.0, fig.cpu_us_max);
    TEST_ASSERT_EQUAL_INT(1, fig.overrun_stop);
    rt.tel = saved;
    /* the fourth miss after the start-up stops the run */
    rt.tel.periods = 10;
    TEST_ASSERT_EQUAL_INT(1, cdpr_rt_plant_judge_period(&rt, 10 * T, 10 * T, 12 * T, 100, &in_row));
    TEST_ASSERT_EQUAL_INT(1, rt.tel.overrun_stop);
    /* in a row: 2 allowed in a row, the second one stops */
    memset(&rt.tel, 0, sizeof rt.tel);
    rt.o.max_misses = 0;
    rt.o.max_misses_in_row = 2;
    rt.o.startup_s = 0.0;
    rt.startup_periods = 0;
    in_row = 0;
    rt.tel.periods = 1;
    TEST_ASSERT_EQUAL_INT(0, cdpr_rt_plant_judge_period(&rt, T, T, 3 * T, 100, &in_row));
    rt.tel.periods = 2;
    TEST_ASSERT_EQUAL_INT(0,
                          cdpr_rt_plant_judge_period(&rt, 2 * T, 2 * T, 2 * T + 10, 100, &in_row));
    rt.tel.periods = 3;
    TEST_ASSERT_EQUAL_INT(0, cdpr_rt_plant_judge_period(&rt, 3 * T, 3 * T, 5 * T, 100, &in_row));
    rt.tel.periods = 4;
    TEST_ASSERT_EQUAL_INT(1, cdpr_rt_plant_judge_period(&rt, 4 * T, 4 * T, 6 * T, 100, &in_row));
    /* count only (the default): never stops */
    cdpr_rt_plant_opts_default(&rt.o);
    rt.startup_periods = 1000; /* the default 1 s at 1 kHz */
    memset(&rt.tel, 0, sizeof rt.tel);
    in_row = 0;
    for (int k = 0; k < 3000; ++k) {
        rt.tel.periods = k;
        TEST_ASSERT_EQUAL_INT(
            0, cdpr_rt_plant_judge_period(&rt, k * T, k * T, k * T + 2 * T, 2 * T, &in_row));
    }
    TEST_ASSERT_EQUAL_INT(2000, rt.tel.misses_long_compute);
    TEST_ASSERT_EQUAL_INT(1000, rt.tel.startup_misses);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_lockstep_memq_equals_in_process_loop);
    RUN_TEST(test_lockstep_with_a_wind_gust_equals_in_process_loop);
    RUN_TEST(test_rt_thread_makes_no_allocation_and_no_lcm_call);
    RUN_TEST(test_silence_holds_then_resumes_and_bad_commands_are_ignored);
    RUN_TEST(test_stalled_publisher_drops_and_rt_thread_keeps_stepping);
    RUN_TEST(test_overruns_classified_and_policy);
    return UNITY_END();
}
