/* SPDX-License-Identifier: BSD-3-Clause */
/// @file command.h
/// Winch commands received over LCM: decoding, validation, the latest-value mailbox the
/// real-time thread reads, and the watchdog that holds the winches when commands stop.
///
/// Data flow: receiver thread -> cdpr_lcm_validator_accept (decode + validate + count) ->
/// cdpr_lcm_mailbox_write; real-time thread -> cdpr_lcm_mailbox_read every period.
///
/// Validation (every rule, in this order; the first one that fails names the reason, the
/// command is counted under it and ignored, the last good command stays in the mailbox):
///   MALFORMED     fewer than 8 bytes, or the fingerprint matches but the bytes do not decode
///                 as exactly one winch_command_t (truncated, trailing bytes after it, or a
///                 negative n_cables)
///   WRONG_TYPE    the first 8 bytes are not winch_command_t's fingerprint: another type (e.g.
///                 a cabin_state_t on the wrong channel) or garbage
///   BAD_MODE      mode is neither MODE_RATE nor MODE_LENGTH
///   CABLE_COUNT   n_cables differs from the plant's cable count (also a well-formed command
///                 with more cables than this build can hold: it is for another robot)
///   NOT_FINITE    any of the value[] entries is NaN or infinite
///   OUT_OF_LIMIT  rate mode: |value[j]| > u_max_m_per_s of winch j; length mode: value[j]
///                 outside [min_length_m of winch j, max_length_m]
///   NO_SESSION    controller_session <= 0
///   OTHER_PLANT   plant_session is not this plant's: the command answers another plant on the
///                 channel, or this channel's plant before a restart
///   STALE         seq < 0
///   SESSION_BUSY  controller_session is not the active one and the active one is not silent
///   STALE         (active session) seq < last accepted seq
///   REPLAYED      (active session) seq == last accepted seq
///   SEQ_WINDOW    (active session) seq > last accepted seq + CDPR_LCM_SEQ_WINDOW
///   STALE         state_seq < 0 or < the state_seq of the last accepted command (any session)
///   FUTURE        state_seq > the last state seq the plant published
///
/// Sessions. One controller session is active at a time. It is **silent** when no command
/// has been accepted for `takeover_ns` (the watchdog timeout: the plant is holding). While the
/// active session is not silent, commands of any other session are refused (SESSION_BUSY): a
/// stray or second controller cannot take the winches from a live one. When it is silent (or
/// none was active yet), the next command that passes every other rule is accepted whatever
/// its seq, and its session becomes the active one with its seq as the new anchor: a restarted
/// controller takes over within one watchdog timeout; a controller whose own sequence went
/// wrong resynchronises the same way. The sequence window bounds how far one command may move
/// the anchor while its session is live, so one far-future seq (a corrupted or forged packet)
/// is refused and counted, never adopted. state_seq only ever grows within a plant run, across
/// controller sessions, so a recorded command replayed later is STALE.
///
/// Mailbox: a triple buffer (one writer, one reader). The writer fills its private buffer and
/// swaps it with the shared "middle" one in one atomic exchange that also sets a "fresh" bit;
/// the reader swaps its buffer with the middle only when the bit is set. Both sides are
/// wait-free (one atomic exchange, one struct copy), the reader always gets a complete, most
/// recent command, no data is ever read while being written. (A seqlock would make the reader
/// retry; a double buffer with an atomic index lets a fast writer overwrite the buffer the
/// reader is copying.)
///
/// Watchdog: every accepted command carries its receive time (CLOCK_MONOTONIC [ns], stamped by
/// the receiver). A read at `now_ns` holds when no command has been accepted yet or the newest
/// one was received more than `timeout_ns` ago: it returns the hold command (rate mode, every
/// value 0) and CDPR_LCM_READ_HOLD, and stays on hold until a newer command arrives.
///
/// Memory: caller-owned, fixed size; no allocation anywhere in this module (decoding goes into
/// fixed storage for CDPR_MAX_CABLES values: wire.h). Threads: the validator and
/// the mailbox writer belong to the receiver thread, the mailbox reader to the real-time
/// thread; statistics may be read from any thread.
#ifndef CDPR_LCM_COMMAND_H
#define CDPR_LCM_COMMAND_H

#include <stddef.h>
#include <stdint.h>

#include "cdpr/config.h"
#include "cdpr/status.h"
#include "cdpr/winch.h"
#include "lcmtypes/cdpr_winch_command_t.h"

/// Cables a plant may have over LCM: the messages size their per-cable arrays by n_cables (an
/// int8_t), so the limit is the core's capacity. A plant with more is refused by
/// cdpr_lcm_bridge_init, the limits and the mailbox with CDPR_E_CAPACITY naming n_cables.
#define CDPR_LCM_MAX_CABLES CDPR_MAX_CABLES

/// Why a command was ignored (indices of the counters; equal to diagnostics_t.REJECT_*).
typedef enum {
    CDPR_LCM_ACCEPTED = -1, ///< not a rejection: the command passed every rule
    CDPR_LCM_REJECT_MALFORMED = 0,
    CDPR_LCM_REJECT_WRONG_TYPE = 1,
    CDPR_LCM_REJECT_NOT_FINITE = 2,
    CDPR_LCM_REJECT_BAD_MODE = 3,
    CDPR_LCM_REJECT_CABLE_COUNT = 4,
    CDPR_LCM_REJECT_OUT_OF_LIMIT = 5,
    CDPR_LCM_REJECT_STALE = 6,
    CDPR_LCM_REJECT_REPLAYED = 7,
    CDPR_LCM_REJECT_FUTURE = 8,
    CDPR_LCM_REJECT_NO_SESSION = 9,
    CDPR_LCM_REJECT_OTHER_PLANT = 10,
    CDPR_LCM_REJECT_SESSION_BUSY = 11,
    CDPR_LCM_REJECT_SEQ_WINDOW = 12,
    CDPR_LCM_N_REJECT = 13
} cdpr_lcm_reject_t;

/// How far ahead of the last accepted seq a command of the live session may be (equal to
/// winch_command_t.SEQ_WINDOW): more than any controller sends within one watchdog timeout.
#define CDPR_LCM_SEQ_WINDOW 65536

/// Name of a reason ("accepted", "malformed", "wrong type", ...); never NULL.
const char *cdpr_lcm_reject_str(cdpr_lcm_reject_t reason);

/// A decoded, validated command (what the real-time thread reads).
typedef struct {
    int64_t seq;                   ///< command sequence number; -1 for the hold command
    int64_t controller_session;    ///< session of the controller; 0 for the hold command
    int64_t state_seq;             ///< state it answers; -1 for the hold command
    int64_t utime_us;              ///< controller time in the message [us]
    int64_t rx_time_ns;            ///< CLOCK_MONOTONIC receive time [ns] (0 for the hold command)
    cdpr_winch_mode_t mode;        ///< rate or length
    int n_cables;                  ///< = the plant's cable count
    double value[CDPR_MAX_CABLES]; ///< rate [m/s] or length [m]; 0 beyond n_cables
} cdpr_lcm_command_t;

/// Limits every command is checked against (inputs).
typedef struct {
    int n_cables;                          ///< plant's cable count, 1..CDPR_LCM_MAX_CABLES
    double u_max_m_per_s[CDPR_MAX_CABLES]; ///< |rate| limit per winch [m/s] (> 0)
    double min_length_m[CDPR_MAX_CABLES];  ///< shortest length setpoint per winch [m] (> 0)
    double max_length_m;                   ///< longest length setpoint [m] (> every min)
} cdpr_lcm_limits_t;

/// Fill limits from the winch parameters of `n_cables` winches (u_max_m_per_s, min_length_m)
/// and a longest cable length [m]. Validates: CDPR_E_CAPACITY for n_cables outside
/// 1..CDPR_LCM_MAX_CABLES, CDPR_E_NOT_FINITE / CDPR_E_NOT_POSITIVE / CDPR_E_OUT_OF_RANGE naming the
/// field and winch in `diag`. On error `lim` is not written.
cdpr_status_t cdpr_lcm_limits_from_winch(cdpr_lcm_limits_t *lim, int n_cables,
                                         const cdpr_winch_params_t *winch, double max_length_m,
                                         cdpr_diag_t *diag);

/// Validator state (receiver thread) and its counters (atomic; any thread may read them).
typedef struct {
    cdpr_lcm_limits_t lim;                ///< validated copy
    int64_t plant_session;                ///< this plant run's session (> 0)
    int64_t takeover_ns;                  ///< silence after which another session may take over
    int64_t controller_session;           ///< active controller session (0: none yet; atomic)
    int64_t last_accept_ns;               ///< receive time of the last accepted command
    uint64_t sessions;                    ///< controller sessions taken over (atomic)
    int64_t last_seq;                     ///< last accepted seq (-1: none yet)
    int64_t last_state_seq;               ///< state_seq of the last accepted command (-1)
    int64_t published_state_seq;          ///< newest state seq published (-1: none yet)
    uint64_t accepted;                    ///< commands accepted (atomic)
    uint64_t rejected[CDPR_LCM_N_REJECT]; ///< commands ignored, by reason (atomic)
    unsigned char fingerprint[8];         ///< winch_command_t's first 8 encoded bytes
} cdpr_lcm_validator_t;

/// Initialise with validated limits (cdpr_lcm_limits_from_winch), the plant's session
/// (> 0) and the silence after which another controller session may take over (> 0 ns; the
/// watchdog timeout); counters zero, no command and no state seen yet. CDPR_E_INVALID_ARG for
/// NULL or a limits struct that fails the same checks, CDPR_E_NOT_POSITIVE for the session
/// ("plant_session") or the silence ("takeover_ns"). Takes the type fingerprint from a test
/// encoding, which also makes the generated code compute and cache its hash here rather than
/// in a later (concurrent) call.
cdpr_status_t cdpr_lcm_validator_init(cdpr_lcm_validator_t *v, const cdpr_lcm_limits_t *lim,
                                      int64_t plant_session, int64_t takeover_ns,
                                      cdpr_diag_t *diag);

/// Record that state `seq` was published (commands may answer states up to the newest one).
void cdpr_lcm_validator_note_published(cdpr_lcm_validator_t *v, int64_t seq);

/// Check a decoded message received at `rx_time_ns` (CLOCK_MONOTONIC [ns]) against every
/// rule except decoding (pure: no counter, no state change). Returns CDPR_LCM_ACCEPTED or the
/// first failing reason. msg->value is read only once n_cables equals the plant's (it must
/// then point to that many values, as a decoded holder's does: wire.h). O(CDPR_MAX_CABLES).
cdpr_lcm_reject_t cdpr_lcm_validator_check(const cdpr_lcm_validator_t *v,
                                           const cdpr_winch_command_t *msg, int64_t rx_time_ns);

/// Decode `len` bytes (one LCM message payload) with the generated decoder, check it, count
/// the outcome and, when accepted, advance the sequence state and write the command into
/// `*out` (rx_time_ns = `rx_time_ns`). On rejection `*out` is not written. Never allocates,
/// reads at most `len` bytes of `buf` (any bytes: this is the fuzzed entry point). O(len).
cdpr_lcm_reject_t cdpr_lcm_validator_accept(cdpr_lcm_validator_t *v, const void *buf, size_t len,
                                            int64_t rx_time_ns, cdpr_lcm_command_t *out);

/// Session snapshot (any thread): the active controller session (0: none yet) and how many
/// sessions have taken over (the first controller counts 1).
void cdpr_lcm_validator_sessions(const cdpr_lcm_validator_t *v, int64_t *controller_session,
                                 uint64_t *sessions);

/// Counters snapshot (any thread).
void cdpr_lcm_validator_counts(const cdpr_lcm_validator_t *v, uint64_t *accepted,
                               uint64_t rejected[CDPR_LCM_N_REJECT], int64_t *last_seq);

/// Flags returned by cdpr_lcm_mailbox_read.
enum {
    CDPR_LCM_READ_NEW = 1,  ///< `out` holds a command not returned by an earlier read
    CDPR_LCM_READ_HOLD = 2, ///< watchdog: `out` is the hold command (rate 0 on every winch)
    CDPR_LCM_READ_NEVER = 4 ///< with HOLD: no command has been accepted since start
};

/// Mailbox + watchdog (caller-owned).
typedef struct {
    cdpr_lcm_command_t buf[3]; ///< triple buffer
    uint32_t middle;           ///< index of the shared buffer | fresh bit (atomic)
    uint32_t back;             ///< writer's buffer (writer thread only)
    uint32_t front;            ///< reader's buffer (reader thread only)
    int have;                  ///< reader: a command has been taken (reader only)
    int n_cables;              ///< cable count of the hold command
    int64_t timeout_ns;        ///< watchdog timeout [ns]
    uint32_t holding;          ///< 1 while on hold (atomic; written by the reader)
    uint64_t hold_entries;     ///< transitions into hold, start-up included (atomic)
    uint64_t hold_reads;       ///< reads that returned the hold command (atomic)
    uint64_t reads;            ///< reads (atomic)
} cdpr_lcm_mailbox_t;

/// Initialise: empty (reads hold until the first command), watchdog `timeout_ns` [ns] (> 0),
/// hold command for `n_cables` winches (1..CDPR_LCM_MAX_CABLES). Before the threads start. O(1);
/// no allocation. Errors (diag names the field): CDPR_E_INVALID_ARG (NULL), CDPR_E_CAPACITY
/// (n_cables), CDPR_E_NOT_POSITIVE (timeout_ns).
cdpr_status_t cdpr_lcm_mailbox_init(cdpr_lcm_mailbox_t *mb, int n_cables, int64_t timeout_ns,
                                    cdpr_diag_t *diag);

/// Writer (receiver thread): publish `cmd` as the newest command. Wait-free, O(1), no
/// allocation, no system call.
void cdpr_lcm_mailbox_write(cdpr_lcm_mailbox_t *mb, const cdpr_lcm_command_t *cmd);

/// Reader (real-time thread): the newest command, or the hold command when the watchdog has
/// expired at `now_ns` (CLOCK_MONOTONIC [ns]) or nothing was ever accepted. Returns
/// CDPR_LCM_READ_* flags (0: the same command as the previous read, still valid).
/// Wait-free, O(1), no allocation, no system call, no lcm_* call.
int cdpr_lcm_mailbox_read(cdpr_lcm_mailbox_t *mb, int64_t now_ns, cdpr_lcm_command_t *out);

/// The hold command for `n_cables` winches: rate mode, values 0, seq/state_seq -1, session 0.
void cdpr_lcm_command_hold(int n_cables, cdpr_lcm_command_t *out);

#endif /* CDPR_LCM_COMMAND_H */
