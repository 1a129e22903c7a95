/* SPDX-License-Identifier: BSD-3-Clause */
/// @file tracker_node.h
/// The tracking controller as an LCM node (apps/cdpr-tracker; also run in-process over
/// memq:// by cdpr-rt --with-tracker). It speaks only LCM: it subscribes to the plant's
/// `<prefix>CABIN_STATE` and `<prefix>CABLE_TENSIONS`, pairs the two messages of one period
/// by their sequence number, turns them into the controller's measurement (pose, velocities,
/// total unstretched lengths), runs cdpr_tracker_step (tracker.h: sag-aware IK feed-forward
/// plus feedback) and publishes a rate-mode `<prefix>WINCH_COMMAND` that answers that state
/// (state_seq = its seq; seq strictly increasing).
///
/// Time: the controller's time for state k is t = n Δt with n = round(utime_us 1e-6 / Δt)
/// (Δt = the control period the node was built with, equal to the plant's period), i.e.
/// exactly the double the plant computes as its own time; so the controller in another process
/// computes bit for bit what the in-process loop computes (cdpr_rt_tracker_meas_from_msgs).
///
/// Service: handlers only store the newest message of each kind; cdpr_rt_tracker_service
/// answers the newest complete pair not answered yet (so a controller that falls behind skips
/// to the newest state instead of working through a backlog; `superseded` counts the states it
/// never answered). With `answer_in_handler` the tensions handler calls service itself (the
/// in-process memq mode, where the handlers run on the plant's bridge thread).
///
/// Sessions (docs/realtime.md, "Sessions"): the node draws a controller session at init and
/// puts it, with the plant session of the state answered, in every command. It follows one
/// plant session: the first it sees, then a new one only after the current plant has sent no
/// state for `plant_silence_s` -- a **plant restart**: counted, on_plant_restart is called, the
/// controller starts again from t = 0 (a new plant starts at t = 0) and answers the new
/// plant's states from seq 0. States of another session while the current one is live are
/// ignored and counted (`other_plant_states`; on_other_plant once per session): two plants
/// share the channels.
///
/// Trust (docs/realtime.md, "The controller side"): every (state, tensions) pair of the
/// followed plant is checked before the controller sees it, as the plant checks commands:
/// - sequence: seq in (last accepted, last accepted + CDPR_RT_STATE_SEQ_WINDOW]; a pair outside
///   the window is refused, and two refused pairs in a row that agree with each other (seq and
///   time) re-anchor the window (`resyncs`: a controller that fell far behind, or a forged
///   anchor, costs two refused updates); backwards only while the anchor has no accepted
///   successor, so replayed old pairs never move an established stream;
/// - time: utime_us never goes back and advances by at most the periods the seq advanced
///   (0 <= dt <= dseq T + 1 us; a failed plant step repeats its time); a step of one period
///   that is not T (±1 us) is counted as `rate_mismatch` (the plant runs at another rate);
/// - plausibility, from the robot the node was built with: every value finite; a unit
///   quaternion (| |q|^2 - 1 | <= 1e-6); |v| and |omega| within what the robot can reach
///   (v_max = sqrt(2 g D) + 2 u_max + 1 m/s, D = the spread of the exit points plus the
///   longest initial cable; omega_max = v_max / the smallest attachment radius, at least
///   0.1 m); winch-end and cabin-end tensions within [0, EA] (MoorDyn slack law: [-EA, EA]);
///   lengths at least the winch's minimum and changed by at most u_max times the time since
///   the last accepted pair; the cabin within twice its cable's length (+ attachment radius)
///   of every exit point.
/// A refused pair is counted by reason (`refused_*`), its reason kept in `last_refusal`, and
/// changes nothing: no filter, no time, no anchor sees it. One bad message costs at most one
/// refused update.
///
/// Control (issue 26): each accepted state names the controller session whose command the
/// plant applied in the step that led to it. After this node's first command, every state is
/// counted as applied_ours, applied_none (0: the plant held) or applied_other (another
/// controller holds the plant); on_other_controller is called once per other session, and
/// on_in_control once, at the first state that applied this node's command (what a script or
/// an operator waits for after a take-over, instead of a fixed delay).
/// cdpr_rt_tracker_in_control tells whether the share not applied stayed within a bound.
///
/// Threads: every function on the thread that owns the lcm_t. The generated *_publish
/// allocates (liblcm); this node is not real-time code and is never run on the plant's RT
/// thread.
#ifndef CDPR_RT_TRACKER_NODE_H
#define CDPR_RT_TRACKER_NODE_H

#include <stdint.h>
#include <stdio.h>

#include <lcm/lcm.h>

#include "cdpr/host/record.h"
#include "cdpr/control/tracker.h"
#include "cdpr/winch.h"
#include "cdpr/lcm/wire.h"
#include "lcmtypes/cdpr_cabin_state_t.h"
#include "lcmtypes/cdpr_diagnostics_t.h"

/// Called after each answered state (e.g. to log the period): the measurement, the command
/// computed, and the two messages it came from.
typedef void (*cdpr_rt_tracker_step_fn)(const cdpr_tracker_meas_t *m, const cdpr_tracker_cmd_t *c,
                                        const cdpr_cabin_state_t *st,
                                        const cdpr_cable_tensions_t *ten, void *ctx);

/// Counters (outputs).
typedef struct {
    uint64_t states;              ///< cabin states received
    uint64_t tensions;            ///< tension messages received
    uint64_t decode_errors;       ///< messages on our channels that did not decode
    uint64_t answered;            ///< commands published
    uint64_t publish_errors;      ///< publications that failed
    uint64_t superseded;          ///< states replaced by a newer one before they were answered
    uint64_t bad_measurement;     ///< pairs refused (non-finite, cable count, time)
    uint64_t ik_failures;         ///< periods whose feed-forward IK failed (last good held)
    uint64_t resent;              ///< commands sent again for a state the plant sent again
    uint64_t plant_restarts;      ///< new plant sessions followed after the first
    uint64_t other_plant_states;  ///< states (and tensions) of a plant session not followed
    uint64_t refused_seq;         ///< pairs outside the sequence window (or stale)
    uint64_t refused_time;        ///< pairs whose time goes back or runs ahead of the seq
    uint64_t refused_implausible; ///< pairs with a value outside its physical range
    uint64_t resyncs;             ///< sequence window re-anchored on two agreeing pairs
    uint64_t rate_mismatch;       ///< one-period steps whose time step is not the period
    uint64_t applied_ours;        ///< states after our first command that applied ours
    uint64_t applied_none;        ///< ... that applied no new command: the plant held, or
                                  ///< applied the same command of another session again (a
                                  ///< controller that stopped, until the watchdog holds)
    uint64_t applied_other;       ///< ... that applied a new command of another session
    uint64_t diagnostics;         ///< the followed plant's diagnostics kept (newest in
                                  ///< cdpr_rt_tracker_t.plant_diag)
} cdpr_rt_tracker_stats_t;

/// Session events (optional callbacks; on the lcm thread). `old_session` 0: none.
typedef void (*cdpr_rt_tracker_session_fn)(int64_t old_session, int64_t new_session, void *ctx);

/// A plant that sent no state for this long may have been restarted [s] (default of
/// cdpr_rt_tracker_t.plant_silence_s).
#define CDPR_RT_PLANT_SILENCE_S 0.5

/// A controller stops when this many pairs in a row were refused (cdpr-tracker: exit 1).
#define CDPR_RT_MAX_REFUSED_IN_ROW 100

/// Sequence window of the states a controller accepts after the last accepted one (1 s at
/// 1 kHz; the plant's command window is the same idea).
#define CDPR_RT_STATE_SEQ_WINDOW 1000

/// Default share of the states (after the first command) that may apply another controller
/// session's command before cdpr_rt_tracker_in_control says no (1 %).
#define CDPR_RT_MAX_OTHER_SHARE 0.01

/// The physical bounds of a measurement (set by cdpr_rt_tracker_init from the robot).
typedef struct {
    double v_max_m_per_s;                  ///< cabin speed
    double w_max_rad_per_s;                ///< cabin angular speed
    double t_min_N[CDPR_MAX_CABLES];       ///< lowest tension (0, or -EA: MoorDyn law)
    double t_max_N[CDPR_MAX_CABLES];       ///< highest tension (EA: a strain of 100 %)
    double l_min_m[CDPR_MAX_CABLES];       ///< the winch's minimum length
    double u_max_m_per_s[CDPR_MAX_CABLES]; ///< the winch's speed limit
    double exit_m[CDPR_MAX_CABLES][3];     ///< exit points
    double attach_r_m[CDPR_MAX_CABLES];    ///< |b_j|
} cdpr_rt_tracker_meas_bounds_t;

/// The node (caller-owned; about 50 kB: declare it static).
/// Resolution range of the controller's step-time histogram: 1 µs bins up to this, one bin
/// above (cdpr_rt_tracker_step_times).
#define CDPR_RT_TRACKER_HIST_US 4000

typedef struct {
    cdpr_tracker_t tracker;
    const cdpr_robot_params_t *model; ///< for a restart (caller-owned, outlives the node)
    const cdpr_traj_t *traj;          ///< for a restart (caller-owned, outlives the node)
    cdpr_tracker_gains_t gains;       ///< for a restart
    int64_t controller_session;       ///< this controller run (> 0)
    int64_t plant_session;            ///< plant session followed (0: none yet)
    int64_t last_state_ns;            ///< CLOCK_MONOTONIC receive time of its last state
    double plant_silence_s;           ///< see CDPR_RT_PLANT_SILENCE_S (settable after init)
    int64_t other_reported;           ///< last other session passed to on_other_plant
    cdpr_rt_tracker_session_fn on_plant_restart; ///< optional
    cdpr_rt_tracker_session_fn on_other_plant;   ///< optional (old_session = the one followed)
    void *on_session_ctx;
    double period_s;
    int n_cables;
    char ch_state[64];
    char ch_tensions[64];
    char ch_command[64];
    char ch_diag[64];
    lcm_t *lcm; ///< not owned
    lcm_subscription_t *sub_state;
    lcm_subscription_t *sub_tensions;
    lcm_subscription_t *sub_diag;
    cdpr_cabin_state_t state;     ///< newest state
    cdpr_lcm_wire_tensions_t ten; ///< newest tensions (ten.msg: the message)
    int have_state;               ///< a state has been received
    int have_ten;                 ///< tensions have been received
    int64_t answered_state_seq;   ///< newest state answered (-1: none)
    int64_t cmd_seq;              ///< seq of the last command published (-1: none)
    unsigned char cmd_buf[64 + 8 * CDPR_MAX_CABLES]; ///< the last command, encoded
    int cmd_len;                                     ///< its length (0: none)
    double u_max_m_per_s[CDPR_MAX_CABLES]; ///< commands are clamped to +-this (winch limits)
    uint64_t clamped;                      ///< command values clamped to the winch speed limit
    int answer_in_handler;                 ///< 1: the tensions handler calls service
    cdpr_rt_tracker_step_fn on_step;       ///< optional
    void *on_step_ctx;
    cdpr_rt_tracker_stats_t stats;
    uint32_t step_hist[CDPR_RT_TRACKER_HIST_US + 1]; ///< cdpr_tracker_step times, 1 µs bins
    uint64_t steps_timed;                            ///< steps in step_hist
    int64_t step_ns_max;                             ///< slowest step [ns]
    cdpr_rt_tracker_meas_bounds_t bounds;            ///< plausibility bounds
    int have_accepted;                               ///< a pair was accepted (this session)
    int64_t acc_seq;                                 ///< last accepted pair: seq
    int64_t acc_utime_us;                            ///< ... its time
    double acc_length_m[CDPR_MAX_CABLES];            ///< ... its lengths
    int have_cand;                                   ///< a refused pair that may re-anchor
    int64_t cand_seq;                                ///< ... its seq
    int64_t cand_utime_us;                           ///< ... its time
    char last_refusal[160];                          ///< why the last pair was refused
    long refused_in_row;                             ///< pairs refused since the last accepted
    long acc_run;                                    ///< pairs accepted since the anchor
    int64_t other_controller;                        ///< last other session reported
    int64_t last_other_session;                      ///< other session of the last state
    int64_t last_other_seq;                          ///< and its command seq (internal)
    cdpr_rt_tracker_session_fn on_other_controller;  ///< optional (old = ours, new = other)
    cdpr_rt_tracker_session_fn on_in_control; ///< optional, once (old = ours, new = state seq)
    /// The newest diagnostics of the plant followed (its work, overruns and health as of state
    /// plant_diag.seq; the plant sends one before its last state). Informational only: they
    /// never change a command. Kept when they decode exactly, name the followed session and
    /// are not older than the one kept; cleared when another plant session is followed.
    cdpr_diagnostics_t plant_diag;
    int have_plant_diag; ///< 1: plant_diag holds one
    /// The scenario's wind section for the wind feed-forward (NULL, or given = 0: the steady
    /// gains.wind_m_per_s): each step assumes its value at the state's time plus half a period,
    /// as the plant (caller-owned; set after cdpr_rt_tracker_init).
    const cdpr_scenario_wind_t *wind;
} cdpr_rt_tracker_t;

/// Build the node: the controller (cdpr_tracker_init with `model` params, `traj`, gains `g`
/// whose period_s is the control period, t0 = 0), the winch speed limits `winch[j]` (rates are
/// clamped to +-u_max before publishing: the plant refuses larger ones, and clamps them itself
/// in the in-process loop, so the result is the same) and the channel names from `prefix`
/// (NULL: "CDPR_"), and draws the controller session. `model` and `traj` must outlive the
/// node (a plant restart re-initialises the controller from them). Errors as
/// cdpr_tracker_init; CDPR_E_INVALID_ARG for a prefix too long.
cdpr_status_t cdpr_rt_tracker_init(cdpr_rt_tracker_t *t, const cdpr_robot_params_t *model,
                                   const cdpr_winch_params_t *winch, const cdpr_traj_t *traj,
                                   const cdpr_tracker_gains_t *g, double period_s,
                                   const char *prefix, cdpr_diag_t *diag);

/// Subscribe on `lcm` (owned by the caller, same thread). CDPR_OK, or CDPR_E_IO (liblcm
/// refused a subscription; none is kept).
cdpr_status_t cdpr_rt_tracker_attach(cdpr_rt_tracker_t *t, lcm_t *lcm);

/// Unsubscribe. Safe to call twice.
void cdpr_rt_tracker_detach(cdpr_rt_tracker_t *t);

/// Answer the newest complete (state, tensions) pair if it is newer than the last one
/// answered. Returns 1 when a command was published, 0 when there was nothing to answer,
/// -1 when the pair was refused or publishing failed (counted).
int cdpr_rt_tracker_service(cdpr_rt_tracker_t *t);

/// Cost of the controller: the wall time (CLOCK_MONOTONIC) of each cdpr_tracker_step the node
/// ran (feed-forward IK, feedback, learning; not LCM), its median and 99th percentile (1 µs
/// resolution; CDPR_RT_TRACKER_HIST_US and above count as the max) and max [ns]; returns the
/// number of steps timed (0: all outputs 0).
uint64_t cdpr_rt_tracker_step_times(const cdpr_rt_tracker_t *t, int64_t *median_ns, int64_t *p99_ns,
                                    int64_t *max_ns);

/// One summary line of cdpr_rt_tracker_step_times on `f` ("  controller step median 41 us,
/// p99 ..."), nothing before the first step.
void cdpr_rt_tracker_print_cost(FILE *f, const cdpr_rt_tracker_t *t);

/// The controller's measurement from the messages of one period (same seq): t from utime_us
/// as described above, pose/velocities from the state, lengths from the tensions. Returns
/// CDPR_OK, CDPR_E_INVALID_ARG when the pair does not fit (seq differs, cable count not
/// `n_cables`, negative time, period not > 0) or CDPR_E_NOT_FINITE (a non-finite value).
cdpr_status_t cdpr_rt_tracker_meas_from_msgs(const cdpr_cabin_state_t *st,
                                             const cdpr_cable_tensions_t *ten, double period_s,
                                             int n_cables, cdpr_tracker_meas_t *m);

/// Check a pair against the node's bounds and its last accepted pair (the rules above).
/// Returns CDPR_OK, or the reason's status: CDPR_E_MISMATCH (sequence window),
/// CDPR_E_OUT_OF_RANGE (time), CDPR_E_NOT_FINITE / CDPR_E_INFEASIBLE (a value outside its
/// range), CDPR_E_INVALID_ARG (the pair does not fit); `why` says which value. Changes nothing.
cdpr_status_t cdpr_rt_tracker_check_pair(const cdpr_rt_tracker_t *t, const cdpr_cabin_state_t *st,
                                         const cdpr_cable_tensions_t *ten, char *why, size_t cap);

/// 1 when the plant applied another controller session's commands in at most `max_share`
/// of the states since this node's first command (and, with no state since, 1).
int cdpr_rt_tracker_in_control(const cdpr_rt_tracker_t *t, double max_share);

/// One line on `f` for each kind of refused state and for the periods not applied, nothing
/// when all is well.
void cdpr_rt_tracker_print_trust(FILE *f, const char *app, const cdpr_rt_tracker_t *t);

/// Recording what the controller sees (the tracker's timeseries.csv and summary, in
/// cdpr-sim's format): use cdpr_rt_tracker_record_step as on_step with a cdpr_rt_tracker_record_t.
typedef struct {
    cdpr_record_t rec;         ///< recorder (cdpr_record_open before the run)
    const cdpr_traj_t *traj;   ///< desired trajectory
    double period_s;           ///< control period
    double max_payout_m_per_s; ///< largest |payout| seen
    double last_t_s;           ///< time of the last period recorded
    long periods;              ///< periods recorded
} cdpr_rt_tracker_record_t;

/// on_step callback: record one period into ((cdpr_rt_tracker_record_t *)ctx)->rec. Tensions,
/// payout rates and node counts come from the tensions message (the plant's values at that state).
/// Rows at run.output_rate_hz by plant time (record.h: a row when the state's time reaches the
/// next output instant, so states the node skipped do not cost rows) and at the run's end. A
/// CSV write failure stops the rows, not the controller; cdpr_record_close reports it.
void cdpr_rt_tracker_record_step(const cdpr_tracker_meas_t *m, const cdpr_tracker_cmd_t *c,
                                 const cdpr_cabin_state_t *st, const cdpr_cable_tensions_t *ten,
                                 void *ctx);

#endif /* CDPR_RT_TRACKER_NODE_H */
