/* SPDX-License-Identifier: BSD-3-Clause */
/// @file plant_node.h
/// The real-time plant node (apps/cdpr-rt): the scenario's plant (plant.h) stepped by a
/// periodic thread, publishing over LCM through the bridge (lcm_bridge.h), taking winch
/// commands back.
///
/// Threads (docs/realtime.md):
///  - the caller's thread: cdpr_rt_plant_init (scenario, settling; allocates nothing after) and
///    cdpr_rt_plant_run, which starts the bridge thread, optionally locks memory (mlockall),
///    creates the periodic thread (SCHED_FIFO when asked and permitted, else SCHED_OTHER, saying
///    why), waits for it, stops the bridge and fills the telemetry;
///  - the bridge thread (SCHED_OTHER): owns the lcm_t (publishes, receives, validates);
///  - the periodic ("RT") thread: per period, read the newest command from the mailbox, step the
///    plant by exactly one period (bounded trials), push state/tensions (and at lower rates
///    the cable shape and diagnostics) into the ring, wake the bridge once. It calls no lcm_*,
///    no allocator, no stdio, takes no lock; its only system calls are clock_gettime (vDSO),
///    clock_nanosleep and, when the bridge sleeps, one non-blocking eventfd write.
///
/// Free-running mode: periods start at absolute deadlines t0 + k T (clock_nanosleep with
/// TIMER_ABSTIME on CLOCK_MONOTONIC). A period whose work ends after the next period's start
/// is a deadline miss; the loop then skips the start times already past (the plant still
/// advances one period per iteration: plant time falls behind wall time, and the telemetry
/// says by how many periods). The command used is whatever is newest; none for longer than
/// the watchdog timeout -> the winches hold (rate 0, FLAG_HOLD) until commands resume.
///
/// Lockstep mode: after publishing state k the thread waits for the command answering k
/// (state_seq == k) — polling the mailbox every 20 us, sending state k again every 0.1 s (a
/// controller that subscribed late, a datagram lost on udpm) — and steps with it; no answer
/// within lockstep_timeout_s -> hold for that period (counted). Wall time plays no role, so a loop
/// over LCM computes exactly what the in-process loop computes.
///
/// A failed step (integrator error or trial budget, plant.h) keeps the previous state: it is
/// published again with FLAG_STEP_FAILED and the same time; the next period tries again. The
/// run length is plant time: the run ends when the plant has advanced run.duration_s (failed
/// periods do not count), or -- a plant that cannot advance -- after CDPR_RT_STALL_S of
/// periods in a row have failed (the run then ends with the step's error).
///
/// Sessions (docs/realtime.md, "Sessions"): the node draws a plant session at init and puts it
/// in every message; the validator accepts commands of one controller session at a time
/// (lcm/command.h). A state of another plant session on the node's state channel means two
/// plants share the channels: counted, reported through lcm.on_other_plant, and the run ends
/// with CDPR_E_CONFLICT (it ran to its end, but its commands may have been meant for the other
/// plant).
///
/// Overload: when, one second into a free-running run (or at its end, if shorter), more than
/// CDPR_RT_OVERLOAD_RATIO of the periods have missed their deadline, the node calls
/// on_overload once (the machine does not hold this rate) and says so in the telemetry.
#ifndef CDPR_RT_PLANT_NODE_H
#define CDPR_RT_PLANT_NODE_H

#include <stdint.h>

#include "cdpr/lcm/bridge.h"
#include "cdpr/host/plant.h"
#include "cdpr/host/summary.h"

/// Compute-time histogram: 1 us bins up to this many us, plus an overflow bin.
#define CDPR_RT_HIST_US 20000

/// A run stops when its plant could not advance for this much plant time in a row [s].
#define CDPR_RT_STALL_S 1.0

/// Lockstep: the plant stops when no answer came for this long, in whole lockstep timeouts in
/// a row (a plant without a controller; 15 periods at the default 2 s timeout) [s], with
/// CDPR_E_INTERRUPTED and the reason.
#define CDPR_RT_LOCKSTEP_GIVE_UP_S 30.0

/// The watchdog timeout when none is set (cdpr_rt_plant_opts_t.lcm.watchdog_timeout_s = 0): this,
/// or two control periods when that is longer [s].
#define CDPR_RT_WATCHDOG_DEFAULT_S 0.1

/// Fraction of missed deadlines over the first second that reports an overload.
#define CDPR_RT_OVERLOAD_RATIO 0.1

/// Overruns (free-running), each deadline miss classified by what made it late:
/// - late wake-up: the period's work took less than a period of wall time, but the thread woke
///   late (the machine: scheduling, another process);
/// - preempted: the work took more than a period of wall time but less than a period of the
///   thread's CPU time (the machine took the CPU away meanwhile);
/// - long computation: the work took more than a period of the thread's CPU time (the plant:
///   too many segments or substeps for this CPU at this rate).
/// Misses within cdpr_rt_plant_opts_t.startup_s of plant time are counted apart (start-up: page
/// faults, caches, the controller subscribing); after it, cdpr_rt_plant_opts_t.max_misses (in
/// total) and max_misses_in_row stop the run (0: count only).
#define CDPR_RT_STARTUP_DEFAULT_S 1.0

/// Options of the node (inputs). cdpr_rt_plant_opts_default fills the defaults. The run settings
/// are the scenario's: control period run.period_s, plant time run.duration_s, work bound
/// integrator.max_trials x max_attempts (command-line overrides: cdpr_scenario_override).
typedef struct {
    int lockstep;                 ///< 1: lockstep mode; default 0
    double lockstep_timeout_s;    ///< lockstep: wait this long for the answer [s]; default 2
    int realtime;                 ///< 1: try SCHED_FIFO + mlockall; default 0
    int rt_priority;              ///< SCHED_FIFO priority 1..99; default 80
    double shape_rate_hz;         ///< cable shape messages [Hz] (0: none; at or above the
                                  ///< control rate: every period); default 10
    double diag_rate_hz;          ///< diagnostics messages [Hz] (0: only at the end; at or
                                  ///< above the control rate: every period); default 1
    double start_delay_s;         ///< free-running: wait this long before the first period [s],
                                  ///< e.g. for a controller to subscribe; default 0
    cdpr_lcm_bridge_params_t lcm; ///< URL, prefix, watchdog timeout, hooks (n_cables and the
                                  ///< winch limits are set from the scenario). The watchdog
                                  ///< timeout: default 0 = follow the period (the larger of
                                  ///< CDPR_RT_WATCHDOG_DEFAULT_S and two periods); a set one
                                  ///< shorter than two periods is refused when free-running
                                  ///< (no command could ever be applied)
    const volatile int *stop;     ///< optional: non-zero stops the run early (signal handler)
    /// Optional instrumentation, called on the periodic thread right before its first period
    /// (phase 0) and right after its last (phase 1): tests count allocations/lcm calls there.
    void (*on_rt_thread)(int phase, void *ctx);
    void *on_rt_thread_ctx;
    /// Optional: called once on the caller's thread (inside cdpr_rt_plant_run) when the first
    /// second of a free-running run (or the whole run, if shorter) missed more than
    /// CDPR_RT_OVERLOAD_RATIO of its deadlines.
    void (*on_overload)(long periods, long misses, double rate_hz, void *ctx);
    void *on_overload_ctx;
    /// Overrun policy (free-running; see CDPR_RT_STARTUP_DEFAULT_S): plant time at the start
    /// whose misses are counted apart [s], in [0, 3600]; default CDPR_RT_STARTUP_DEFAULT_S.
    double startup_s;
    long max_misses;        ///< stop after this many misses after the start-up (0: count only)
    long max_misses_in_row; ///< stop after this many misses in a row after it (0: count only)
} cdpr_rt_plant_opts_t;

/// Telemetry (outputs of cdpr_rt_plant_run).
typedef struct {
    long periods;              ///< periods run (state seq of the last state published)
    long deadline_misses;      ///< free-running: periods that ended after the next start
    long periods_skipped;      ///< free-running: start times skipped after misses
    int64_t compute_ns_min;    ///< per-period compute time: read command .. publish done
    int64_t compute_ns_median; ///< (1 us resolution above CDPR_RT_HIST_US: the max)
    int64_t compute_ns_p99;
    int64_t compute_ns_max;
    int64_t cpu_ns_median; ///< the same work as the periodic thread's CPU time
    int64_t cpu_ns_p99;    ///< (CLOCK_THREAD_CPUTIME_ID; 1 us bins)
    int64_t cpu_ns_max;
    int64_t wake_late_ns_max;         ///< free-running: latest wake-up after the start-up
    long startup_misses;              ///< misses within opts.startup_s (not in the three below)
    long misses_late_wakeup;          ///< after the start-up: the work fit, the wake-up was late
    long misses_preempted;            ///< the work took > 1 period of wall, < 1 period of CPU time
    long misses_long_compute;         ///< the work took > 1 period of the thread's CPU time
    long misses_in_row_max;           ///< longest run of consecutive misses after the start-up
    int overrun_stop;                 ///< 1: the overrun policy stopped the run
    double wall_s;                    ///< wall time of the periodic loop [s]
    long hold_periods;                ///< periods stepped with the hold command
    long commands_applied;            ///< periods stepped with a new command
    long lockstep_timeouts;           ///< lockstep: periods whose answer did not come in time
    long lockstep_resends;            ///< lockstep: states sent again while waiting (every 0.1 s)
    long step_failures;               ///< periods whose step failed (state kept)
    long substep_limit_hits;          ///< periods whose step met the trial bound
    long min_length_periods;          ///< winch-periods held at the minimum length
    long capacity_periods;            ///< periods whose node events met the capacity
    unsigned long node_insertions;    ///< all cables
    unsigned long node_removals;      ///< all cables
    unsigned long rhs_evals;          ///< integrator work: RHS evaluations in all
    unsigned long factorisations;     ///< factorisations of W (ROS34PW2; 0 for RKF45)
    unsigned long solves;             ///< solves with W (ROS34PW2; 0 for RKF45)
    unsigned long max_rhs_per_period; ///< the most in one period (bound: max_attempts x
                                      ///< max_trials trials of 6 RHS, RKF45, or of 4 RHS,
                                      ///< 4 solves and 1 factorisation, ROS34PW2)
    unsigned long max_factorisations_per_period; ///< the most in one period
    unsigned long max_solves_per_period;         ///< the most in one period
    cdpr_lcm_stats_t lcm;                        ///< bridge statistics at the end
    int sched_fifo;                              ///< 1 if the periodic thread ran under SCHED_FIFO
    int mlocked;                                 ///< 1 if mlockall succeeded
    char rt_note[256];     ///< why SCHED_FIFO/mlockall were not used ("" if they were
                           ///< or were not asked for)
    double final_time_s;   ///< plant time reached [s]
    int overloaded;        ///< 1: the first second missed > CDPR_RT_OVERLOAD_RATIO
    long overload_periods; ///< periods of that first second
    long overload_misses;  ///< deadline misses in it
    long stalled;          ///< 1: the run ended because the plant could not advance
    long no_controller;    ///< lockstep: 1 when the run stopped after
                           ///< CDPR_RT_LOCKSTEP_GIVE_UP_S without an answer
    double watchdog_s;     ///< the watchdog timeout in use [s]
    int64_t plant_session; ///< this run's plant session
} cdpr_rt_plant_telemetry_t;

/// The node (caller-owned, large: declare it static).
typedef struct {
    cdpr_plant_t plant;
    cdpr_lcm_bridge_t bridge;
    cdpr_rt_plant_opts_t o;
    cdpr_rt_plant_telemetry_t tel;
    long give_up_periods;                   ///< lockstep: unanswered periods before it stops
    uint32_t hist[CDPR_RT_HIST_US + 1];     ///< compute-time histogram (RT thread)
    uint32_t hist_cpu[CDPR_RT_HIST_US + 1]; ///< the same in thread CPU time
    long recorded;                          ///< periods in hist and hist_cpu (the newest
                                            ///< period's is added after its messages)
    cdpr_cabin_state_t st_msg;
    cdpr_lcm_wire_tensions_t ten_msg;
    cdpr_diagnostics_t diag_msg;
    cdpr_lcm_wire_shape_t shape_msg;
    cdpr_robot_out_t out;
    cdpr_robot_t check_model;   ///< storage of the trajectory check at init
    int64_t seq;                ///< seq of the newest state published
    int64_t command_seq;        ///< seq of the command applied in the last step (-1: none)
    int64_t command_session;    ///< its controller session (0: none)
    long n_periods;             ///< plant periods to run (plant time run.duration_s)
    long advanced;              ///< periods the plant advanced (plant time = advanced x T)
    long stall_periods;         ///< failed periods in a row that end the run
    cdpr_status_t stall_status; ///< the error of the last failed step
    long shape_every;           ///< periods between shape messages (0: none)
    long diag_every;            ///< periods between diagnostics (0: none)
    int64_t period_ns;
    long startup_periods; ///< periods of opts.startup_s (set by cdpr_rt_plant_init)
    int hold;             ///< the last step used the hold command
    long mon_periods;     ///< periods and misses for the overload check (atomic; RT thread)
    long mon_misses;
    int done; ///< the periodic thread has finished (atomic)
    /// The scenario's wind section (given = 0: the robot's steady wind): set each period to
    /// its value at the period's midpoint (cdpr_scenario_wind_at).
    cdpr_scenario_wind_t wind;
} cdpr_rt_plant_t;

/// Defaults (see the field comments).
void cdpr_rt_plant_opts_default(cdpr_rt_plant_opts_t *o);

/// Check the scenario and the options, build and settle the plant of `sc` (period
/// run.period_s, work bound integrator.max_trials x max_attempts), initialise the bridge.
/// Returns CDPR_OK, or with `err` naming the option or scenario key: the scenario's check or
/// plant errors (cdpr_scenario_check, skipped when cdpr_scenario_is_checked; cdpr_host_plant_init),
/// CDPR_E_OUT_OF_RANGE / CDPR_E_NOT_FINITE for an option, the bridge's (cdpr_lcm_bridge_init).
cdpr_status_t cdpr_rt_plant_init(cdpr_rt_plant_t *rt, const cdpr_scenario_t *sc,
                                 const cdpr_rt_plant_opts_t *o, cdpr_scenario_error_t *err);

/// Run: bridge thread, periodic thread, until run.duration_s of plant time or *stop. Returns
/// CDPR_OK when the run completed, CDPR_E_INTERRUPTED when *stop ended it early, the step's
/// error when the plant could not advance for CDPR_RT_STALL_S (`err` says so),
/// CDPR_E_CONFLICT when another plant's states were seen on the channel (the run completed),
/// CDPR_E_IO when the bridge or the thread could not start (`err` says why). Telemetry in
/// rt->tel.
cdpr_status_t cdpr_rt_plant_run(cdpr_rt_plant_t *rt, cdpr_scenario_error_t *err);

/// The deadline of one free-running period (what the periodic thread calls after each one;
/// public for tests and for loops of their own): the period was scheduled at `start`, its work
/// began at `t0` and ended at `t1` (CLOCK_MONOTONIC, ns) after `cpu_ns` of the thread's CPU
/// time; the period before it is counted in rt->tel.periods. A miss (t1 after start + period)
/// is counted in rt->tel.deadline_misses, and classified (late wake-up, preempted, long
/// computation: CDPR_RT_STARTUP_DEFAULT_S) or counted apart within rt->startup_periods (opts
/// startup_s in periods, set by cdpr_rt_plant_init); `*in_row` carries the misses in a row from
/// call to call (start at 0). Returns 1 when the overrun policy (rt->o.max_misses,
/// max_misses_in_row) stops the run (rt->tel.overrun_stop set), else 0. O(1), no allocation,
/// real-time safe.
int cdpr_rt_plant_judge_period(cdpr_rt_plant_t *rt, int64_t start, int64_t t0, int64_t t1,
                               int64_t cpu_ns, long *in_row);

/// Print the telemetry summary (human-readable) to `f`.
void cdpr_rt_plant_print_summary(const cdpr_rt_plant_t *rt, FILE *f);

/// The real-time figures of a run's summary (summary.json "rt_*") from the telemetry as it is
/// now (after cdpr_rt_plant_run: the whole run). Not real-time safe (computes the percentiles).
void cdpr_rt_plant_summary_figures(cdpr_rt_plant_t *rt, cdpr_summary_rt_t *out);

/// The same from a `diagnostics_t` (a controller's view of the plant, cdpr_rt_tracker_t).
void cdpr_rt_plant_figures_from_diagnostics(const cdpr_diagnostics_t *d, cdpr_summary_rt_t *out);

#endif /* CDPR_RT_PLANT_NODE_H */
