/* SPDX-License-Identifier: BSD-3-Clause */
/// @file plant_node.c
/// The real-time plant node (plant_node.h).
#include "cdpr/rt/plant_node.h"

#include "hist.h"

#include <errno.h>
#include <math.h>
#include <pthread.h>
#include <sched.h>
#include <stdio.h>
#include <string.h>
#include <sys/mman.h>
#include <time.h>

#include "cdpr/host/feasibility.h"
#include "cdpr/lcm/pack.h"

/* Lockstep: how often the periodic thread looks at the mailbox while it waits [ns]. */
static const int64_t LOCKSTEP_POLL_NS = 20000;
/* Lockstep: how long before the state waiting for its answer is sent again [ns]. */
static const int64_t LOCKSTEP_RESEND_NS = 100000000;
/* Stack the periodic thread touches before its first period (page faults happen up front). */
#define PREFAULT_STACK_BYTES (64 * 1024)

void cdpr_rt_plant_opts_default(cdpr_rt_plant_opts_t *o)
{
    memset(o, 0, sizeof *o); /* lockstep, realtime, start_delay_s, max_misses(_in_row): 0 */
    o->lockstep_timeout_s = 2.0;
    o->rt_priority = 80;
    o->shape_rate_hz = 10.0;
    o->diag_rate_hz = 1.0;
    o->startup_s = CDPR_RT_STARTUP_DEFAULT_S;
    cdpr_lcm_bridge_params_default(&o->lcm);
    o->lcm.watchdog_timeout_s = 0.0; /* follow the period (cdpr_rt_plant_init) */
}

/* A bad option: "option --NAME: what", NOT_FINITE or OUT_OF_RANGE. */
static cdpr_status_t opt_error(const char *opt, double v, const char *what,
                               cdpr_scenario_error_t *err)
{
    snprintf(err->msg, sizeof err->msg, "option --%s: %g: %s", opt, v, what);
    return isfinite(v) ? CDPR_E_OUT_OF_RANGE : CDPR_E_NOT_FINITE;
}

/* The node's own options (the run settings are the scenario's: cdpr_scenario_check). */
static cdpr_status_t check_opts(const cdpr_rt_plant_opts_t *op, cdpr_scenario_error_t *err)
{
    if (!(op->lockstep_timeout_s > 0.0 && op->lockstep_timeout_s <= 3600.0)) {
        return opt_error("lockstep-timeout", op->lockstep_timeout_s, "must be in (0, 3600] s", err);
    }
    if (op->rt_priority < 1 || op->rt_priority > 99) {
        return opt_error("priority", (double)op->rt_priority, "must be in 1..99", err);
    }
    /* A message rate above the control rate means every period (every()). */
    if (!(op->shape_rate_hz >= 0.0 && op->shape_rate_hz < 1e12)) {
        return opt_error("shape-rate", op->shape_rate_hz, "must be >= 0 Hz", err);
    }
    if (!(op->diag_rate_hz >= 0.0 && op->diag_rate_hz < 1e12)) {
        return opt_error("diag-rate", op->diag_rate_hz, "must be >= 0 Hz", err);
    }
    if (!(op->start_delay_s >= 0.0 && op->start_delay_s <= 3600.0)) {
        return opt_error("start-delay", op->start_delay_s, "must be in [0, 3600] s", err);
    }
    if (!(op->startup_s >= 0.0 && op->startup_s <= 3600.0)) {
        return opt_error("startup", op->startup_s, "must be in [0, 3600] s", err);
    }
    if (op->max_misses < 0) {
        return opt_error("max-misses", (double)op->max_misses, "must be >= 0 (0: count only)", err);
    }
    if (op->max_misses_in_row < 0) {
        return opt_error("max-misses-in-row", (double)op->max_misses_in_row,
                         "must be >= 0 (0: count only)", err);
    }
    return CDPR_OK;
}

/* The bridge for the plant's cables and winch limits. */
static cdpr_status_t init_bridge(cdpr_rt_plant_t *rt, cdpr_scenario_error_t *err)
{
    cdpr_lcm_bridge_params_t bp = rt->o.lcm;
    bp.n_cables = rt->plant.robot.p.n_cables;
    for (int j = 0; j < bp.n_cables; ++j) {
        bp.winch[j] = rt->plant.pp.winch[j];
    }
    /* Length commands within the lengths a scenario may have (cdpr_feasibility_check_trajectory).
     */
    bp.max_length_m = CDPR_FEASIBILITY_MAX_LENGTH_M;
    cdpr_diag_t d;
    memset(&d, 0, sizeof d);
    const cdpr_status_t st = cdpr_lcm_bridge_init(&rt->bridge, &bp, &d);
    if (st != CDPR_OK) {
        if (strcmp(d.field, "watchdog_timeout_s") == 0) {
            snprintf(err->msg, sizeof err->msg, "option --watchdog: %g: must be in (0, 3600] s",
                     bp.watchdog_timeout_s);
        } else {
            snprintf(err->msg, sizeof err->msg, "LCM bridge: field '%s': %s", d.field,
                     cdpr_status_str(d.status));
        }
    }
    return st;
}

/* Periods between two messages of rate `hz` (0: none; at least every period). */
static long every(double rate_hz, double hz)
{
    if (!(hz > 0.0)) {
        return 0;
    }
    const double n = floor(rate_hz / hz + 0.5);
    return (n < 1.0) ? 1 : (n > 1e9 ? 1000000000L : (long)n);
}

cdpr_status_t cdpr_rt_plant_init(cdpr_rt_plant_t *rt, const cdpr_scenario_t *sc,
                                 const cdpr_rt_plant_opts_t *o, cdpr_scenario_error_t *err)
{
    memset(rt, 0, sizeof *rt);
    rt->o = *o;
    rt->wind = sc->wind;
    cdpr_status_t st = (cdpr_scenario_is_checked(sc) != 0) ? CDPR_OK : cdpr_scenario_check(sc, err);
    if (st != CDPR_OK) {
        return st;
    }
    const double rate_hz = 1.0 / sc->period_s;
    st = check_opts(&rt->o, err);
    if (st != CDPR_OK) {
        return st;
    }
    rt->period_ns = (int64_t)llround(sc->period_s * 1e9);
    rt->startup_periods = (long)llround(rt->o.startup_s / sc->period_s); /* checked: <= 3600 s */
    if (rt->period_ns < 1) {
        cdpr_scenario_error(sc, "run.period_s", "shorter than the clock's 1 ns", err);
        return CDPR_E_OUT_OF_RANGE;
    }
    /* The watchdog follows the period: a free-running command older than the watchdog is
     * never applied, so a watchdog shorter than two periods would hold every period. */
    const double auto_wd = fmax(CDPR_RT_WATCHDOG_DEFAULT_S, 2.0 * sc->period_s);
    if (fpclassify(rt->o.lcm.watchdog_timeout_s) == FP_ZERO) {
        rt->o.lcm.watchdog_timeout_s = auto_wd;
    } else if (rt->o.lockstep == 0 && rt->o.lcm.watchdog_timeout_s < 2.0 * sc->period_s) {
        snprintf(err->msg, sizeof err->msg,
                 "option --watchdog: %g s is shorter than two control periods (2 x %g s): no "
                 "command could ever be applied; use at least %g s, or leave it out (default: "
                 "the larger of %g s and two periods)",
                 rt->o.lcm.watchdog_timeout_s, sc->period_s, 2.0 * sc->period_s,
                 CDPR_RT_WATCHDOG_DEFAULT_S);
        return CDPR_E_OUT_OF_RANGE;
    }
    rt->tel.watchdog_s = rt->o.lcm.watchdog_timeout_s;
    rt->give_up_periods = (long)ceil(CDPR_RT_LOCKSTEP_GIVE_UP_S / rt->o.lockstep_timeout_s);
    rt->n_periods = cdpr_scenario_periods(sc);
    rt->shape_every = every(rate_hz, rt->o.shape_rate_hz);
    rt->diag_every = every(rate_hz, rt->o.diag_rate_hz);
    rt->stall_periods = (long)ceil(CDPR_RT_STALL_S / sc->period_s);
    /* The trajectory check of cdpr-sim (feasible, lengths within the limits) before the
     * plant's settle, which costs far more. */
    st = cdpr_feasibility_check_trajectory(sc, sc->duration_s, &rt->check_model, err);
    if (st != CDPR_OK) {
        return st;
    }
    st = cdpr_host_plant_init(&rt->plant, sc, NULL, err);
    if (st != CDPR_OK) {
        return st;
    }
    st = init_bridge(rt, err);
    if (st != CDPR_OK) {
        return st;
    }
    rt->seq = 0;
    rt->command_seq = -1;
    rt->command_session = 0;
    rt->tel.plant_session = cdpr_lcm_bridge_session(&rt->bridge);
    return CDPR_OK;
}

/* ------------------------------------------------------------------ periodic thread */

static void sleep_until(int64_t t_ns)
{
    struct timespec ts;
    ts.tv_sec = (time_t)(t_ns / 1000000000);
    ts.tv_nsec = (long)(t_ns % 1000000000);
    while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, NULL) == EINTR) {
    }
}

static int64_t hist_quantile(const uint32_t *hist, long total, double q)
{
    const uint64_t n = (total > 0) ? (uint64_t)total : 0;
    return (int64_t)cdpr_rt_hist_quantile_bin(hist, CDPR_RT_HIST_US, n, q) * 1000;
}

/* The periodic thread's CPU time [ns]. */
static int64_t thread_cpu_ns(void)
{
    struct timespec ts;
    if (clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts) != 0) {
        return 0;
    }
    return (int64_t)ts.tv_sec * 1000000000 + (int64_t)ts.tv_nsec;
}

static void record(cdpr_rt_plant_t *rt, int64_t ns, int64_t cpu_ns)
{
    cdpr_rt_plant_telemetry_t *t = &rt->tel;
    rt->recorded++;
    const int64_t us = ns / 1000;
    rt->hist[(us < CDPR_RT_HIST_US) ? us : CDPR_RT_HIST_US]++;
    const int64_t cpu_us = cpu_ns / 1000;
    rt->hist_cpu[(cpu_us < CDPR_RT_HIST_US) ? cpu_us : CDPR_RT_HIST_US]++;
    if (cpu_ns > t->cpu_ns_max) {
        t->cpu_ns_max = cpu_ns;
    }
    if (t->periods == 1 || ns < t->compute_ns_min) {
        t->compute_ns_min = ns;
    }
    if (ns > t->compute_ns_max) {
        t->compute_ns_max = ns;
    }
}

static void fill_stats(cdpr_rt_plant_t *rt)
{
    cdpr_rt_plant_telemetry_t *t = &rt->tel;
    const cdpr_plant_t *p = &rt->plant;
    t->compute_ns_median = hist_quantile(rt->hist, rt->recorded, 0.5);
    t->compute_ns_p99 = hist_quantile(rt->hist, rt->recorded, 0.99);
    if (t->compute_ns_p99 > t->compute_ns_max) {
        t->compute_ns_p99 = t->compute_ns_max;
    }
    if (t->compute_ns_median > t->compute_ns_max) {
        t->compute_ns_median = t->compute_ns_max;
    }
    t->cpu_ns_median = hist_quantile(rt->hist_cpu, rt->recorded, 0.5);
    t->cpu_ns_p99 = hist_quantile(rt->hist_cpu, rt->recorded, 0.99);
    t->cpu_ns_p99 = (t->cpu_ns_p99 < t->cpu_ns_max) ? t->cpu_ns_p99 : t->cpu_ns_max;
    t->cpu_ns_median = (t->cpu_ns_median < t->cpu_ns_max) ? t->cpu_ns_median : t->cpu_ns_max;
    t->step_failures = (long)p->stats.step_failures;
    t->substep_limit_hits = (long)p->stats.substep_limit_hits;
    t->min_length_periods = (long)p->stats.min_length_periods;
    t->capacity_periods = (long)p->stats.capacity_periods;
    t->node_insertions = 0;
    t->node_removals = 0;
    for (int j = 0; j < p->robot.p.n_cables; ++j) {
        t->node_insertions += p->nodes.insertions[j];
        t->node_removals += p->nodes.removals[j];
    }
    t->final_time_s = cdpr_plant_time(p);
    cdpr_plant_work_t w;
    cdpr_plant_work(p, &w);
    t->rhs_evals = w.rhs_evals;
    t->factorisations = w.factorisations;
    t->solves = w.solves;
    t->max_rhs_per_period = p->stats.max_rhs_evals;
    t->max_factorisations_per_period = p->stats.max_factorisations;
    t->max_solves_per_period = p->stats.max_solves;
}

/* rt->diag_msg from the telemetry as it is now. */
static void fill_diagnostics(cdpr_rt_plant_t *rt)
{
    cdpr_diagnostics_t *m = &rt->diag_msg;
    cdpr_rt_plant_telemetry_t *t = &rt->tel;
    fill_stats(rt);
    memset(m, 0, sizeof *m);
    cdpr_lcm_stats_t s;
    cdpr_lcm_bridge_stats(&rt->bridge, &s);
    cdpr_lcm_pack_diagnostics(m, &s);
    m->utime_us = cdpr_lcm_utime_us(cdpr_plant_time(&rt->plant));
    m->seq = rt->seq;
    m->periods = t->periods;
    m->deadline_misses = t->deadline_misses;
    m->compute_ns_min = t->compute_ns_min;
    m->compute_ns_median = t->compute_ns_median;
    m->compute_ns_p99 = t->compute_ns_p99;
    m->compute_ns_max = t->compute_ns_max;
    m->hold_periods = t->hold_periods;
    m->node_insertions = (int64_t)t->node_insertions;
    m->node_removals = (int64_t)t->node_removals;
    m->capacity_hits = t->capacity_periods;
    m->substep_limit_hits = t->substep_limit_hits;
    m->step_failures = t->step_failures;
    m->integrator = (int8_t)rt->plant.pp.integrator;
    m->rhs_evals = (int64_t)t->rhs_evals;
    m->factorisations = (int64_t)t->factorisations;
    m->solves = (int64_t)t->solves;
    m->max_rhs_per_period = (int32_t)t->max_rhs_per_period;
    m->max_factorisations_per_period = (int32_t)t->max_factorisations_per_period;
    m->max_solves_per_period = (int32_t)t->max_solves_per_period;
    if (rt->plant.pp.integrator == CDPR_PLANT_ROS34PW2_FIXED) {
        m->substeps = (int32_t)rt->plant.substeps;
        m->max_err_norm = (double)rt->plant.stats.max_err_norm;
        m->err_above_one_periods = (int64_t)rt->plant.stats.err_above_one_periods;
    }
    m->cpu_ns_median = t->cpu_ns_median;
    m->cpu_ns_p99 = t->cpu_ns_p99;
    m->cpu_ns_max = t->cpu_ns_max;
    m->wake_late_ns_max = t->wake_late_ns_max;
    m->startup_misses = t->startup_misses;
    m->misses_late_wakeup = t->misses_late_wakeup;
    m->misses_preempted = t->misses_preempted;
    m->misses_long_compute = t->misses_long_compute;
    m->misses_in_row_max = t->misses_in_row_max;
    m->overrun_stop = (int8_t)t->overrun_stop;
}

static void push_diagnostics(cdpr_rt_plant_t *rt)
{
    fill_diagnostics(rt);
    (void)cdpr_lcm_bridge_push_diagnostics(&rt->bridge, &rt->diag_msg);
}

/* State rt->seq of the plant as it is now: cabin state, tensions, shape and diagnostics when
 * due; one wake-up of the bridge. With the last state of the run, the diagnostics go first: a
 * controller that stops at the last state has then received the run's figures (its summary
 * reports them), whatever the machine's load. */
static void publish(cdpr_rt_plant_t *rt, int plant_flags)
{
    cdpr_plant_t *p = &rt->plant;
    const int last = (rt->advanced >= rt->n_periods) ? 1 : 0;
    if (last != 0 && rt->diag_every > 0) {
        push_diagnostics(rt);
    }
    cdpr_tracker_meas_t m;
    cdpr_plant_measure_out(p, &m, &rt->out); /* the tensions message's values too */
    int32_t flags = (int32_t)plant_flags;
    if (rt->hold != 0) {
        flags |= CDPR_CABIN_STATE_T_FLAG_HOLD;
    }
    if (rt->o.lockstep != 0) {
        flags |= CDPR_CABIN_STATE_T_FLAG_LOCKSTEP;
    }
    const int64_t session = rt->tel.plant_session;
    cdpr_lcm_pack_cabin_motion(&rt->st_msg, &m.cabin, m.t_s, rt->seq, rt->command_seq, flags);
    rt->st_msg.plant_session = session;
    rt->st_msg.controller_session = rt->command_session;
    (void)cdpr_lcm_bridge_push_cabin_state(&rt->bridge, &rt->st_msg);
    cdpr_lcm_pack_tensions(&rt->ten_msg, &p->robot, p->y, &rt->out, m.t_s, rt->seq);
    rt->ten_msg.msg.plant_session = session;
    (void)cdpr_lcm_bridge_push_tensions(&rt->bridge, &rt->ten_msg);
    if (rt->shape_every > 0 && rt->seq % rt->shape_every == 0) {
        cdpr_lcm_pack_shape(&rt->shape_msg, &p->robot, p->y, m.t_s, rt->seq);
        rt->shape_msg.msg.plant_session = session;
        (void)cdpr_lcm_bridge_push_shape(&rt->bridge, &rt->shape_msg);
    }
    if (last == 0 && rt->diag_every > 0 && rt->seq > 0 && rt->seq % rt->diag_every == 0) {
        push_diagnostics(rt);
    }
    cdpr_lcm_bridge_wake(&rt->bridge);
}

/* Lockstep: wait for the command answering state rt->seq, sending the state again every
 * LOCKSTEP_RESEND_NS (a controller that subscribed late, or a datagram lost on udpm). 1 when
 * the answer came, 0 on timeout. */
static int wait_answer(cdpr_rt_plant_t *rt, cdpr_lcm_command_t *cmd, int *read_flags)
{
    const int64_t t0 = cdpr_lcm_now_ns();
    const int64_t limit = t0 + (int64_t)llround(rt->o.lockstep_timeout_s * 1e9);
    int64_t resend = t0 + LOCKSTEP_RESEND_NS;
    for (;;) {
        const int64_t now = cdpr_lcm_now_ns();
        /* Read as of the wait's start: the answer to this state arrived after it, so the
         * watchdog never makes it stale, however late this thread reads it (a loaded machine
         * changes no lockstep result). */
        *read_flags = cdpr_lcm_bridge_read_command(&rt->bridge, t0, cmd);
        if ((*read_flags & CDPR_LCM_READ_HOLD) == 0 && cmd->state_seq == rt->seq) {
            return 1;
        }
        if (now >= limit || (rt->o.stop != NULL && *rt->o.stop != 0)) {
            return 0;
        }
        if (now >= resend) {
            (void)cdpr_lcm_bridge_push_cabin_state(&rt->bridge, &rt->st_msg);
            (void)cdpr_lcm_bridge_push_tensions(&rt->bridge, &rt->ten_msg);
            cdpr_lcm_bridge_wake(&rt->bridge);
            rt->tel.lockstep_resends++;
            resend = now + LOCKSTEP_RESEND_NS;
        }
        sleep_until(now + LOCKSTEP_POLL_NS);
    }
}

/* The command of the next period: in lockstep the answer to the last state (or hold after the
 * timeout), free-running the newest one at the period's start `next`. Counts holds and new
 * commands; returns the time the period's work starts. */
static int64_t take_command(cdpr_rt_plant_t *rt, int64_t next, cdpr_lcm_command_t *cmd)
{
    cdpr_rt_plant_telemetry_t *t = &rt->tel;
    int rf = 0;
    int64_t t0;
    if (rt->o.lockstep != 0) {
        if (wait_answer(rt, cmd, &rf) == 0) {
            t->lockstep_timeouts++;
            cdpr_lcm_command_hold(rt->plant.robot.p.n_cables, cmd);
            rf = CDPR_LCM_READ_HOLD;
        } else {
            rf |= CDPR_LCM_READ_NEW;
        }
        t0 = cdpr_lcm_now_ns();
    } else {
        sleep_until(next);
        t0 = cdpr_lcm_now_ns();
        rf = cdpr_lcm_bridge_read_command(&rt->bridge, t0, cmd);
    }
    rt->hold = ((rf & CDPR_LCM_READ_HOLD) != 0) ? 1 : 0;
    if (rt->hold != 0) {
        t->hold_periods++;
    } else if ((rf & CDPR_LCM_READ_NEW) != 0) {
        t->commands_applied++;
    }
    return t0;
}

static void prefault_stack(void)
{
    volatile unsigned char buf[PREFAULT_STACK_BYTES];
    for (size_t i = 0; i < sizeof buf; i += 4096) {
        buf[i] = 0;
    }
}

int cdpr_rt_plant_judge_period(cdpr_rt_plant_t *rt, int64_t start, int64_t t0, int64_t t1,
                               int64_t cpu, long *in_row)
{
    cdpr_rt_plant_telemetry_t *t = &rt->tel;
    const cdpr_rt_plant_opts_t *o = &rt->o;
    const int64_t T = rt->period_ns;
    const int startup = (t->periods < rt->startup_periods) ? 1 : 0;
    const int64_t late = t0 - start;
    if (startup == 0 && late > t->wake_late_ns_max) {
        t->wake_late_ns_max = late;
    }
    if (t1 <= start + T) {
        *in_row = 0;
        return 0;
    }
    t->deadline_misses++;
    if (startup != 0) {
        t->startup_misses++;
        return 0;
    }
    if (cpu > T) {
        t->misses_long_compute++;
    } else if (t1 - t0 > T) {
        t->misses_preempted++;
    } else {
        t->misses_late_wakeup++;
    }
    (*in_row)++;
    t->misses_in_row_max = (*in_row > t->misses_in_row_max) ? *in_row : t->misses_in_row_max;
    const long after = t->misses_long_compute + t->misses_preempted + t->misses_late_wakeup;
    if ((o->max_misses > 0 && after >= o->max_misses) ||
        (o->max_misses_in_row > 0 && *in_row >= o->max_misses_in_row)) {
        t->overrun_stop = 1;
        return 1;
    }
    return 0;
}

static void *periodic(void *arg)
{
    cdpr_rt_plant_t *rt = arg;
    cdpr_rt_plant_telemetry_t *t = &rt->tel;
    const cdpr_rt_plant_opts_t *o = &rt->o;
    prefault_stack();
    if (o->on_rt_thread != NULL) {
        o->on_rt_thread(0, o->on_rt_thread_ctx);
    }
    const int64_t T = rt->period_ns;
    int64_t start = cdpr_lcm_now_ns();
    if (o->lockstep == 0) {
        start += (int64_t)llround(o->start_delay_s * 1e9);
        sleep_until(start);
    }
    rt->hold = 1;
    publish(rt, 0);
    int64_t next = start + T;
    long failed_in_row = 0;
    long unanswered_in_row = 0;
    long missed_in_row = 0;
    while (rt->advanced < rt->n_periods) {
        if (o->stop != NULL && *o->stop != 0) {
            break;
        }
        cdpr_lcm_command_t cmd;
        const long timeouts_before = t->lockstep_timeouts;
        const int64_t t0 = take_command(rt, next, &cmd);
        const int64_t cpu0 = thread_cpu_ns();
        unanswered_in_row = (t->lockstep_timeouts > timeouts_before) ? unanswered_in_row + 1 : 0;
        if (unanswered_in_row >= rt->give_up_periods) {
            t->no_controller = 1; /* a lockstep plant without a controller: stop, say so */
            break;
        }
        const cdpr_winch_mode_t mode =
            (cmd.mode == CDPR_WINCH_LENGTH) ? CDPR_WINCH_LENGTH : CDPR_WINCH_RATE;
        int pf = 0;
        if (rt->wind.given != 0) { /* the coming period's wind, at its midpoint */
            double w[3];
            cdpr_scenario_wind_eval(&rt->wind,
                                    cdpr_plant_time(&rt->plant) + 0.5 * rt->plant.pp.period_s, w);
            rt->plant.robot.in.wind_m_per_s = cdpr_v3(w[0], w[1], w[2]);
        }
        const cdpr_status_t st = cdpr_plant_step(&rt->plant, mode, cmd.value, &pf);
        if (st >= 0) {
            rt->command_seq = cmd.seq;
            rt->command_session = cmd.controller_session;
            rt->advanced++;
            failed_in_row = 0;
        } else {
            rt->stall_status = st;
            failed_in_row++;
        }
        rt->seq++;
        t->periods++;
        publish(rt, pf);
        const int64_t t1 = cdpr_lcm_now_ns();
        const int64_t cpu = thread_cpu_ns() - cpu0;
        record(rt, t1 - t0, cpu);
        if (o->lockstep == 0) {
            const int stop = cdpr_rt_plant_judge_period(rt, next, t0, t1, cpu, &missed_in_row);
            next += T;
            while (t1 - next >= T) { /* start times already past: skipped, not run late */
                next += T;
                t->periods_skipped++;
            }
            __atomic_store_n(&rt->mon_misses, t->deadline_misses, __ATOMIC_RELAXED);
            __atomic_store_n(&rt->mon_periods, t->periods, __ATOMIC_RELAXED);
            if (stop != 0) {
                break;
            }
        }
        if (failed_in_row >= rt->stall_periods) {
            t->stalled = 1;
            break;
        }
    }
    t->wall_s = 1e-9 * (double)(cdpr_lcm_now_ns() - start);
    push_diagnostics(rt);
    cdpr_lcm_bridge_wake(&rt->bridge);
    if (o->on_rt_thread != NULL) {
        o->on_rt_thread(1, o->on_rt_thread_ctx);
    }
    __atomic_store_n(&rt->done, 1, __ATOMIC_RELEASE);
    return NULL;
}

/* The overload report: more than CDPR_RT_OVERLOAD_RATIO of the periods so far missed. */
static void check_overload(cdpr_rt_plant_t *rt)
{
    const long n = __atomic_load_n(&rt->mon_periods, __ATOMIC_RELAXED);
    const long m = __atomic_load_n(&rt->mon_misses, __ATOMIC_RELAXED);
    if (n > 0 && (double)m > CDPR_RT_OVERLOAD_RATIO * (double)n) {
        rt->tel.overloaded = 1;
        rt->tel.overload_periods = n;
        rt->tel.overload_misses = m;
        if (rt->o.on_overload != NULL) {
            rt->o.on_overload(n, m, 1e9 / (double)rt->period_ns, rt->o.on_overload_ctx);
        }
    }
}

/* The caller's thread while the periodic thread runs: one look at the deadline misses after
 * the first second of a free-running run (or at its end, when shorter), then wait. */
static void watch(cdpr_rt_plant_t *rt)
{
    const struct timespec tick = {0, 20000000}; /* 20 ms */
    const int64_t t_check = cdpr_lcm_now_ns() + (int64_t)llround((rt->o.start_delay_s + 1.0) * 1e9);
    int checked = (rt->o.lockstep != 0) ? 1 : 0;
    while (__atomic_load_n(&rt->done, __ATOMIC_ACQUIRE) == 0) {
        (void)nanosleep(&tick, NULL);
        if (checked == 0 && cdpr_lcm_now_ns() >= t_check) {
            checked = 1;
            check_overload(rt);
        }
    }
    if (checked == 0) {
        check_overload(rt);
    }
}

/* How the run ended (cdpr_rt_plant_run). */
static cdpr_status_t run_status(const cdpr_rt_plant_t *rt, cdpr_scenario_error_t *err)
{
    const cdpr_rt_plant_telemetry_t *t = &rt->tel;
    if (t->stalled != 0) {
        snprintf(err->msg, sizeof err->msg,
                 "the plant could not advance: %ld periods in a row failed at t = %.6g s (%s)",
                 rt->stall_periods, t->final_time_s, cdpr_status_str(rt->stall_status));
        return rt->stall_status;
    }
    if (t->overrun_stop != 0) {
        snprintf(err->msg, sizeof err->msg,
                 "overrun policy: %ld deadline misses after the %g s start-up (%ld in a row at "
                 "most; limits %ld in total, %ld in a row) at t = %.6g s: stopping",
                 t->misses_late_wakeup + t->misses_preempted + t->misses_long_compute,
                 rt->o.startup_s, t->misses_in_row_max, rt->o.max_misses, rt->o.max_misses_in_row,
                 t->final_time_s);
        return CDPR_E_INTERRUPTED;
    }
    if (t->no_controller != 0) {
        snprintf(err->msg, sizeof err->msg,
                 "lockstep: no controller answered for %ld periods in a row (%g s each, %g s) "
                 "at t = %.6g s: stopping (start the controller first, or run free-running)",
                 rt->give_up_periods, rt->o.lockstep_timeout_s,
                 (double)rt->give_up_periods * rt->o.lockstep_timeout_s, t->final_time_s);
        return CDPR_E_INTERRUPTED;
    }
    if (rt->advanced < rt->n_periods) {
        snprintf(err->msg, sizeof err->msg, "stopped by a signal at t = %.6g s", t->final_time_s);
        return CDPR_E_INTERRUPTED;
    }
    if (t->lcm.other_plant_messages > 0) {
        snprintf(err->msg, sizeof err->msg,
                 "another plant shared the channels: %llu of its states seen (session %lld)",
                 (unsigned long long)t->lcm.other_plant_messages,
                 (long long)t->lcm.other_plant_session);
        return CDPR_E_CONFLICT;
    }
    return CDPR_OK;
}

cdpr_status_t cdpr_rt_plant_run(cdpr_rt_plant_t *rt, cdpr_scenario_error_t *err)
{
    cdpr_rt_plant_telemetry_t *t = &rt->tel;
    cdpr_diag_t d;
    memset(&d, 0, sizeof d);
    /* The bridge thread first, under the caller's (normal) policy: liblcm's receive thread
     * inherits the policy of the thread that creates it. */
    if (cdpr_lcm_bridge_start(&rt->bridge, &d) != CDPR_OK) {
        snprintf(err->msg, sizeof err->msg, "LCM: cannot start the bridge (%s): %s", d.field,
                 cdpr_status_str(d.status));
        return CDPR_E_IO;
    }
    t->rt_note[0] = '\0';
    pthread_attr_t attr;
    pthread_attr_init(&attr);
    int fifo = 0;
    if (rt->o.realtime != 0) {
        if (mlockall(MCL_CURRENT | MCL_FUTURE) == 0) {
            t->mlocked = 1;
        } else {
            snprintf(t->rt_note, sizeof t->rt_note, "mlockall failed (%s); ", strerror(errno));
        }
        struct sched_param sp;
        memset(&sp, 0, sizeof sp);
        sp.sched_priority = rt->o.rt_priority;
        if (pthread_attr_setinheritsched(&attr, PTHREAD_EXPLICIT_SCHED) == 0 &&
            pthread_attr_setschedpolicy(&attr, SCHED_FIFO) == 0 &&
            pthread_attr_setschedparam(&attr, &sp) == 0) {
            fifo = 1;
        }
    }
    pthread_t th;
    int rc = pthread_create(&th, &attr, periodic, rt);
    if (rc != 0 && fifo != 0) {
        const size_t len = strlen(t->rt_note);
        snprintf(t->rt_note + len, sizeof t->rt_note - len,
                 "SCHED_FIFO priority %d not permitted (%s): running SCHED_OTHER",
                 rt->o.rt_priority, strerror(rc));
        pthread_attr_destroy(&attr);
        pthread_attr_init(&attr);
        fifo = 0;
        rc = pthread_create(&th, &attr, periodic, rt);
    }
    pthread_attr_destroy(&attr);
    if (rc != 0) {
        cdpr_lcm_bridge_stop(&rt->bridge);
        snprintf(err->msg, sizeof err->msg, "cannot create the periodic thread: %s", strerror(rc));
        return CDPR_E_IO;
    }
    t->sched_fifo = fifo;
    watch(rt);
    pthread_join(th, NULL);
    cdpr_lcm_bridge_stop(&rt->bridge);
    if (t->mlocked != 0) {
        (void)munlockall();
    }
    fill_stats(rt);
    cdpr_lcm_bridge_stats(&rt->bridge, &t->lcm);
    return run_status(rt, err);
}

static double to_us(int64_t ns)
{
    return 1e-3 * (double)ns;
}

void cdpr_rt_plant_print_summary(const cdpr_rt_plant_t *rt, FILE *f)
{
    const cdpr_rt_plant_telemetry_t *t = &rt->tel;
    const cdpr_lcm_stats_t *s = &t->lcm;
    const double period_us = 1e-3 * (double)rt->period_ns;
    fprintf(f, "cdpr-rt telemetry\n");
    fprintf(f, "  mode               %s, %.0f Hz, %s%s\n",
            (rt->o.lockstep != 0) ? "lockstep" : "free-running", 1.0 / rt->plant.pp.period_s,
            (t->sched_fifo != 0) ? "SCHED_FIFO" : "SCHED_OTHER",
            (t->mlocked != 0) ? " + mlockall" : "");
    if (t->rt_note[0] != '\0') {
        fprintf(f, "  real-time note     %s\n", t->rt_note);
    }
    fprintf(f, "  sessions           plant %lld; controller %lld (%llu taken over)\n",
            (long long)t->plant_session, (long long)s->controller_session,
            (unsigned long long)s->controller_sessions);
    if (s->other_plant_messages > 0) {
        fprintf(f,
                "  OTHER PLANT        %llu states of another plant on our channel (session %lld)\n",
                (unsigned long long)s->other_plant_messages, (long long)s->other_plant_session);
    }
    if (t->overloaded != 0) {
        fprintf(f,
                "  OVERLOAD           %ld of the first %ld periods missed their deadline: this "
                "machine does not hold %.0f Hz\n",
                t->overload_misses, t->overload_periods, 1.0 / rt->plant.pp.period_s);
    }
    fprintf(f, "  periods            %ld (plant time %.3f s, wall %.3f s)\n", t->periods,
            t->final_time_s, t->wall_s);
    fprintf(f,
            "  compute time [us]  min %.1f  median %.0f  p99 %.0f  max %.1f  (%.1f %% of the "
            "period at p99)\n",
            to_us(t->compute_ns_min), to_us(t->compute_ns_median), to_us(t->compute_ns_p99),
            to_us(t->compute_ns_max), 100.0 * to_us(t->compute_ns_p99) / period_us);
    fprintf(f,
            "  thread CPU [us]    median %.0f  p99 %.0f  max %.1f  (%.1f %% of the period at "
            "p99)\n",
            to_us(t->cpu_ns_median), to_us(t->cpu_ns_p99), to_us(t->cpu_ns_max),
            100.0 * to_us(t->cpu_ns_p99) / period_us);
    if (rt->o.lockstep == 0) {
        fprintf(f, "  deadline misses    %ld (start times skipped: %ld)\n", t->deadline_misses,
                t->periods_skipped);
        fprintf(f,
                "  overruns           start-up (first %g s) %ld; then %ld late wake-ups, %ld "
                "preempted, %ld long computations (most in a row %ld); latest wake-up %.1f us\n",
                rt->o.startup_s, t->startup_misses, t->misses_late_wakeup, t->misses_preempted,
                t->misses_long_compute, t->misses_in_row_max, to_us(t->wake_late_ns_max));
    } else {
        fprintf(f, "  lockstep           %ld timeouts, %ld states sent again\n",
                t->lockstep_timeouts, t->lockstep_resends);
    }
    fprintf(f, "  commands           %ld periods with a new command, %ld on hold (entries %llu)\n",
            t->commands_applied, t->hold_periods, (unsigned long long)s->hold_entries);
    unsigned long long bad = 0;
    for (int i = 0; i < CDPR_LCM_N_REJECT; ++i) {
        bad += (unsigned long long)s->rejected[i];
    }
    fprintf(f, "  received           %llu accepted, %llu ignored",
            (unsigned long long)s->commands_accepted, bad);
    for (int i = 0; i < CDPR_LCM_N_REJECT; ++i) {
        if (s->rejected[i] != 0) {
            fprintf(f, " [%s %llu]", cdpr_lcm_reject_str((cdpr_lcm_reject_t)i),
                    (unsigned long long)s->rejected[i]);
        }
    }
    fprintf(f, "\n");
    fprintf(f,
            "  published          %llu (ring dropped %llu, shape dropped %llu, publish "
            "errors %llu)\n",
            (unsigned long long)s->published, (unsigned long long)s->ring.dropped,
            (unsigned long long)s->shape_ring.dropped, (unsigned long long)s->publish_errors);
    fprintf(f, "  nodes              %lu insertions, %lu removals, capacity hit in %ld periods\n",
            t->node_insertions, t->node_removals, t->capacity_periods);
    fprintf(f,
            "  accuracy bound     %ld periods at the trial limit, %ld failed steps (%lu refused "
            "for their trial budget: state kept)\n",
            t->substep_limit_hits, t->step_failures, rt->plant.stats.budget_refusals);
    const double np = (t->periods > 0) ? (double)t->periods : 1.0;
    if (rt->plant.pp.integrator == CDPR_PLANT_ROS34PW2_FIXED) {
        const int n = rt->plant.substeps;
        fprintf(f,
                "  integrator         ROS34PW2, fixed: %d substeps, per period %.2f RHS, %.2f "
                "factorisations, %.2f solves on average, at most %lu / %lu / %lu (fixed: %d / %d "
                "/ %d); error norm max %.3g, above 1 in %lu periods\n",
                n, (double)t->rhs_evals / np, (double)t->factorisations / np,
                (double)t->solves / np, t->max_rhs_per_period, t->max_factorisations_per_period,
                t->max_solves_per_period, 4 * n, n, 4 * n, (double)rt->plant.stats.max_err_norm,
                rt->plant.stats.err_above_one_periods);
    } else if (rt->plant.pp.integrator == CDPR_PLANT_ROS34PW2) {
        fprintf(f,
                "  integrator         ROS34PW2: per period %.2f RHS, %.2f factorisations, %.2f "
                "solves on average, at most %lu / %lu / %lu (bound %d trials: %d / %d / %d)\n",
                (double)t->rhs_evals / np, (double)t->factorisations / np, (double)t->solves / np,
                t->max_rhs_per_period, t->max_factorisations_per_period, t->max_solves_per_period,
                rt->plant.pp.max_trials * rt->plant.pp.max_attempts,
                4 * rt->plant.pp.max_trials * rt->plant.pp.max_attempts,
                rt->plant.pp.max_trials * rt->plant.pp.max_attempts,
                4 * rt->plant.pp.max_trials * rt->plant.pp.max_attempts);
    } else {
        fprintf(f,
                "  integrator         RKF45: per period %.2f RHS on average, at most %lu (bound "
                "%d trials: %d)\n",
                (double)t->rhs_evals / np, t->max_rhs_per_period,
                rt->plant.pp.max_trials * rt->plant.pp.max_attempts,
                6 * rt->plant.pp.max_trials * rt->plant.pp.max_attempts);
    }
    fprintf(f, "  winches            %ld winch-periods at the minimum length\n",
            t->min_length_periods);
}

void cdpr_rt_plant_figures_from_diagnostics(const cdpr_diagnostics_t *d, cdpr_summary_rt_t *out)
{
    memset(out, 0, sizeof *out);
    out->known = 1;
    out->seq = (long)d->seq;
    out->periods = (long)d->periods;
    out->deadline_misses = (unsigned long)d->deadline_misses;
    out->startup_misses = (unsigned long)d->startup_misses;
    out->misses_late_wakeup = (unsigned long)d->misses_late_wakeup;
    out->misses_preempted = (unsigned long)d->misses_preempted;
    out->misses_long_compute = (unsigned long)d->misses_long_compute;
    out->misses_in_row_max = (unsigned long)d->misses_in_row_max;
    out->overrun_stop = (d->overrun_stop != 0) ? 1 : 0;
    out->compute_us_p99 = to_us(d->compute_ns_p99);
    out->compute_us_max = to_us(d->compute_ns_max);
    out->cpu_us_p99 = to_us(d->cpu_ns_p99);
    out->cpu_us_max = to_us(d->cpu_ns_max);
    out->wake_late_us_max = to_us(d->wake_late_ns_max);
}

void cdpr_rt_plant_summary_figures(cdpr_rt_plant_t *rt, cdpr_summary_rt_t *out)
{
    fill_diagnostics(rt);
    cdpr_rt_plant_figures_from_diagnostics(&rt->diag_msg, out);
}
