/* SPDX-License-Identifier: BSD-3-Clause */
/// @file bridge.h
/// The LCM bridge between a real-time plant thread and the rest of the world.
///
/// Threading model (docs/realtime.md):
///  - The **bridge thread** (normal priority, SCHED_OTHER, created by cdpr_lcm_bridge_start with
///    an explicit scheduling policy so it never inherits SCHED_FIFO) owns the lcm_t: it
///    creates it, subscribes to the command channel, publishes every message the real-time
///    thread queued, receives winch commands (lcm_handle_timeout in a draining loop),
///    validates them and posts the good ones into the mailbox. It is the only thread that calls
///    lcm_*: liblcm 1.3.1 takes a GLib mutex without priority inheritance and makes a blocking
///    sendmsg() in lcm_publish, and its first lcm_handle starts a receive thread that inherits
///    the creator's scheduling policy (docs/development.md, platform notes).
///  - The **real-time thread** uses only the functions marked "RT-safe" below: they make no
///    lcm_* call, no allocation, take no lock and never wait. Pushing encodes the message
///    straight into a ring slot (lcm_ring.h; full ring -> the message is dropped and counted)
///    and wakes the bridge thread so it publishes at once instead of at its next idle poll:
///    after every push (`wake_on_push`, the default) or once per period with
///    cdpr_lcm_bridge_wake. A wake-up writes 8 bytes to a non-blocking eventfd, and only when
///    the bridge thread may be asleep in poll() (see "Wake-ups" in lcm_bridge.c).
///  - Any thread may read the statistics.
///
/// Channels: `<prefix>CABIN_STATE`, `<prefix>CABLE_TENSIONS`, `<prefix>DIAGNOSTICS`,
/// `<prefix>CABLE_SHAPE` (published), `<prefix>WINCH_COMMAND` (subscribed); prefix "CDPR_" by
/// default. The bridge also listens on its own `<prefix>CABIN_STATE`: a state of another
/// plant session there means two plants share the channels (counted, on_other_plant).
///
/// Sessions: the plant's session (params plant_session) goes into every message the plant
/// node packs and is the one the command validator accepts (command.h, "Sessions").
///
/// Memory: cdpr_lcm_bridge_t is caller-owned and large (its ring storage is inline:
/// CDPR_LCM_RING_SLOTS x CDPR_LCM_SLOT_BYTES + CDPR_LCM_SHAPE_SLOTS x CDPR_LCM_SHAPE_SLOT_BYTES,
/// about 150 KiB by default): declare it static. liblcm allocates inside lcm_create, lcm_publish
/// and lcm_handle, all on the bridge thread.
///
/// Lifecycle: params_default -> init (validates, no thread, no lcm_t) -> start (thread + lcm_t)
/// -> RT pushes/reads ... -> stop (publishes what is queued, joins, destroys the lcm_t).
/// Instead of start/stop a caller may drive the bridge from its own thread with open / poll /
/// close (single-threaded tools and tests).
#ifndef CDPR_LCM_BRIDGE_H
#define CDPR_LCM_BRIDGE_H

#include <pthread.h>
#include <stdint.h>

#include <lcm/lcm.h>

#include "cdpr/lcm/command.h"
#include "cdpr/lcm/ring.h"
#include "lcmtypes/cdpr_cabin_state_t.h"
#include "cdpr/lcm/wire.h"
#include "lcmtypes/cdpr_diagnostics_t.h"

/// Slots of the ring for state, tensions and diagnostics (power of two; 256 = 85 ms of three
/// messages per period at 1 kHz before a stalled publisher makes the plant drop messages).
#ifndef CDPR_LCM_RING_SLOTS
#define CDPR_LCM_RING_SLOTS 256
#endif
/// Bytes per slot of that ring; cdpr_lcm_bridge_init checks that every message fits.
#ifndef CDPR_LCM_SLOT_BYTES
#define CDPR_LCM_SLOT_BYTES 512
#endif
/// Slots and slot size of the separate ring for the (large, low-rate) cable shape message, so
/// a shape never takes the room of a state.
#ifndef CDPR_LCM_SHAPE_SLOTS
#define CDPR_LCM_SHAPE_SLOTS 4
#endif
/// A shape takes at most 64 + n_cables x (6 + 12 x CDPR_CABLE_SHAPE_T_MAX_NODES) bytes
/// (6352 at eight cables); cdpr_lcm_bridge_init refuses a plant whose shape may not fit.
#ifndef CDPR_LCM_SHAPE_SLOT_BYTES
#define CDPR_LCM_SHAPE_SLOT_BYTES 8192
#endif
/// Longest channel name (prefix included) and LCM URL [chars].
#define CDPR_LCM_CHANNEL_MAX 64
#define CDPR_LCM_URL_MAX     256

/// Address space a udpm provider's start-up needs beyond what the process uses [bytes]:
/// liblcm's receive thread (an 8 MiB stack) and its buffers, with a margin. Checked by
/// cdpr_lcm_bridge_open before liblcm runs (liblcm does not check all its allocations).
#define CDPR_LCM_UDPM_HEADROOM_BYTES ((size_t)24 * 1024u * 1024u)

/// Channels (indices of cdpr_lcm_bridge_t.channel).
typedef enum {
    CDPR_LCM_CH_CABIN_STATE = 0,
    CDPR_LCM_CH_CABLE_TENSIONS = 1,
    CDPR_LCM_CH_DIAGNOSTICS = 2,
    CDPR_LCM_CH_CABLE_SHAPE = 3,
    CDPR_LCM_CH_WINCH_COMMAND = 4,
    CDPR_LCM_N_CHANNELS = 5
} cdpr_lcm_channel_t;

/// Called on the bridge thread right after the lcm_t is created and the command channel
/// subscribed (e.g. an in-process controller subscribing to the state channel). Its handlers
/// then run on the bridge thread inside lcm_handle and may call lcm_publish. Return 0, or
/// non-zero to make open/start fail.
typedef int (*cdpr_lcm_on_open_fn)(lcm_t *lcm, void *ctx);

/// Called on the bridge thread the first time a message of another plant session (or one that
/// does not decode as a cabin_state_t) arrives on our <prefix>CABIN_STATE channel: another
/// plant shares the channels (`session` is its session, 0 when the message did not decode).
/// Called again for each further session. Must not block (e.g. one line on stderr).
typedef void (*cdpr_lcm_on_other_plant_fn)(int64_t session, void *ctx);

/// A new session id (> 0, 63 random bits from getrandom(2); where that fails, from the clock
/// and the process id). Not RT-safe (a system call).
int64_t cdpr_lcm_new_session(void);

/// Bridge parameters (inputs).
typedef struct {
    const char *url;            ///< LCM provider URL; NULL or "": liblcm's default
    const char *channel_prefix; ///< channel name prefix; default "CDPR_"
    int n_cables;               ///< plant cable count, 1..CDPR_LCM_MAX_CABLES; default 6
    cdpr_winch_params_t winch[CDPR_MAX_CABLES]; ///< limits per winch; default winch defaults
    double max_length_m;         ///< longest length setpoint accepted [m]; default 1000
    double watchdog_timeout_s;   ///< no valid command for this long -> hold [s]; default 0.1
    int idle_poll_ms;            ///< bridge thread's poll timeout when idle [ms]; default 10
    int wake_on_push;            ///< 1: every push wakes the bridge thread; 0: the caller calls
                                 ///< cdpr_lcm_bridge_wake (or relies on idle_poll_ms); default 1
    cdpr_lcm_on_open_fn on_open; ///< optional hook, see above; default NULL
    void *on_open_ctx;           ///< passed to on_open
    int64_t plant_session;       ///< this plant run's session (> 0); 0: init draws one
                                 ///< (cdpr_lcm_new_session); default 0
    cdpr_lcm_on_other_plant_fn on_other_plant; ///< optional, see above; default NULL
    void *on_other_plant_ctx;                  ///< passed to on_other_plant
} cdpr_lcm_bridge_params_t;

/// Statistics snapshot (any thread).
typedef struct {
    cdpr_lcm_ring_stats_t ring;           ///< state/tensions/diagnostics ring
    cdpr_lcm_ring_stats_t shape_ring;     ///< cable shape ring
    uint64_t encode_errors;               ///< pushes whose message did not encode into a slot
    uint64_t wakeups;                     ///< pushes that woke the bridge thread (eventfd)
    uint64_t published;                   ///< lcm_publish calls that succeeded
    uint64_t publish_errors;              ///< lcm_publish calls that failed
    uint64_t handle_errors;               ///< lcm_handle_timeout failures
    uint64_t commands_received;           ///< messages on the command channel
    uint64_t commands_accepted;           ///< of which accepted
    uint64_t rejected[CDPR_LCM_N_REJECT]; ///< of which ignored, by reason
    int64_t last_command_seq;             ///< seq of the last accepted command (-1: none)
    int64_t published_state_seq;          ///< newest state seq handed to lcm_publish (-1: none)
    uint64_t hold_entries;                ///< times the mailbox reader went on hold (start-up too)
    uint64_t hold_reads;                  ///< command reads that returned the hold command
    int holding;                          ///< 1 while on hold
    int64_t plant_session;                ///< this plant run's session
    int64_t controller_session;           ///< active controller session (0: none yet)
    uint64_t controller_sessions;         ///< controller sessions taken over
    uint64_t other_plant_messages;        ///< messages of other plants on our state channel
    int64_t other_plant_session;          ///< the last other plant's session (0: none/undecodable)
} cdpr_lcm_stats_t;

/// The bridge (caller-owned; fields are internal, use the functions).
typedef struct {
    cdpr_lcm_bridge_params_t p; ///< validated copy (url/prefix point into the arrays below)
    char url[CDPR_LCM_URL_MAX];
    char channel[CDPR_LCM_N_CHANNELS][CDPR_LCM_CHANNEL_MAX];
    cdpr_lcm_ring_t ring;
    cdpr_lcm_ring_t shape_ring;
    cdpr_lcm_validator_t validator; ///< bridge thread
    cdpr_lcm_mailbox_t mailbox;     ///< written by the bridge thread, read by the RT thread
    lcm_t *lcm;                     ///< bridge thread only
    lcm_subscription_t *sub;
    lcm_subscription_t *sub_state; ///< our own state channel: other plants (bridge thread)
    uint64_t other_plant_messages; ///< bridge thread (atomic)
    int64_t other_plant_session;   ///< bridge thread (atomic)
    int64_t other_reported;        ///< last session passed to on_other_plant (-1: none)
    int lcm_fd;
    int wake_fd;                 ///< eventfd, or -1
    uint32_t sleeping;           ///< 1 while the bridge thread may be blocked in poll()
    uint64_t wakeups;            ///< eventfd writes by the RT thread (atomic)
    uint64_t encode_errors;      ///< RT thread (atomic)
    uint64_t published;          ///< bridge thread (atomic)
    uint64_t publish_errors;     ///< bridge thread (atomic)
    uint64_t handle_errors;      ///< bridge thread (atomic)
    uint64_t commands_received;  ///< bridge thread (atomic)
    int64_t published_state_seq; ///< bridge thread (atomic)
    pthread_t thread;
    pthread_mutex_t start_lock;
    pthread_cond_t start_cond;
    int start_state;            ///< 0 starting, 1 running, -1 failed (under start_lock)
    const char *start_error;    ///< what failed when start_state is -1
    cdpr_status_t start_status; ///< the status of a failed start (with start_error)
    int running;                ///< thread created and not joined
    int stop;                   ///< stop request (atomic)
    int opened;                 ///< lcm_t exists
    uint64_t ring_storage[CDPR_LCM_RING_STORAGE_BYTES(CDPR_LCM_RING_SLOTS, CDPR_LCM_SLOT_BYTES) /
                          sizeof(uint64_t)];
    uint64_t
        shape_storage[CDPR_LCM_RING_STORAGE_BYTES(CDPR_LCM_SHAPE_SLOTS, CDPR_LCM_SHAPE_SLOT_BYTES) /
                      sizeof(uint64_t)];
} cdpr_lcm_bridge_t;

/// Defaults (see the field comments).
void cdpr_lcm_bridge_params_default(cdpr_lcm_bridge_params_t *p);

/// The plant session of an initialised bridge (the parameter, or the one init drew). Any
/// thread; O(1).
int64_t cdpr_lcm_bridge_session(const cdpr_lcm_bridge_t *b);

/// Validate the parameters and initialise rings, validator and mailbox. No thread, no lcm_t,
/// no allocation; O(CDPR_LCM_RING_SLOTS). On error `b` is unusable and `diag` names the first
/// bad field. Errors: CDPR_E_INVALID_ARG (NULL; a character of channel_prefix outside
/// [A-Za-z0-9_/-]), CDPR_E_OUT_OF_RANGE (channel_prefix or url too long, watchdog_timeout_s
/// or idle_poll_ms outside their ranges), CDPR_E_CAPACITY (n_cables outside
/// 1..CDPR_LCM_MAX_CABLES), CDPR_E_NOT_FINITE (watchdog_timeout_s), and the errors of
/// cdpr_lcm_limits_from_winch / cdpr_lcm_validator_init for the winch limits
/// ("u_max_m_per_s" ..., index = winch).
cdpr_status_t cdpr_lcm_bridge_init(cdpr_lcm_bridge_t *b, const cdpr_lcm_bridge_params_t *p,
                                   cdpr_diag_t *diag);

/// Start the bridge thread (SCHED_OTHER) and wait until it has created the lcm_t and
/// subscribed, or failed. CDPR_E_INVALID_ARG when lcm_create, the subscription, the hook or
/// the thread failed (`diag` says which); CDPR_E_IO when a udpm URL lacks the address space
/// of CDPR_LCM_UDPM_HEADROOM_BYTES (checked before liblcm runs); the bridge is then stopped. Not
/// RT-safe (blocks; may take seconds for udpm, whose self-test runs here).
cdpr_status_t cdpr_lcm_bridge_start(cdpr_lcm_bridge_t *b, cdpr_diag_t *diag);

/// Ask the thread to stop, let it publish what is still queued, join it, destroy the lcm_t.
/// Safe to call twice or without start. Not RT-safe.
void cdpr_lcm_bridge_stop(cdpr_lcm_bridge_t *b);

/// Without a thread: create the lcm_t and subscribe in the calling thread (which then owns it).
cdpr_status_t cdpr_lcm_bridge_open(cdpr_lcm_bridge_t *b, cdpr_diag_t *diag);

/// Without a thread: one iteration of the bridge loop: publish every queued message, wait up
/// to `timeout_ms` [ms] (0: do not wait) for traffic or a wake-up, handle every received
/// message (at most 1000), publish again. Returns the messages handled, or -1 on an error of
/// the LCM file descriptor. Only on the thread that opened the bridge.
int cdpr_lcm_bridge_poll(cdpr_lcm_bridge_t *b, int timeout_ms);

/// Without a thread: destroy the lcm_t. Safe to call twice.
void cdpr_lcm_bridge_close(cdpr_lcm_bridge_t *b);

/// The lcm_t, for code that runs on the owning thread (on_open hook, handlers, a caller that
/// used open/poll); NULL when not open. Never call lcm_* from the real-time thread.
lcm_t *cdpr_lcm_bridge_lcm(cdpr_lcm_bridge_t *b);

/// Full channel name of `ch` ("CDPR_CABIN_STATE"); "" for an unknown channel. Never NULL.
const char *cdpr_lcm_bridge_channel(const cdpr_lcm_bridge_t *b, cdpr_lcm_channel_t ch);

/// RT-safe: encode `msg` into the ring for publication. CDPR_OK, CDPR_E_CAPACITY (ring full:
/// dropped and counted), CDPR_E_INVALID_ARG (does not fit a slot: counted in encode_errors).
/// Work: the generated encoder, O(message size); one non-blocking eventfd write if enabled.
cdpr_status_t cdpr_lcm_bridge_push_cabin_state(cdpr_lcm_bridge_t *b, const cdpr_cabin_state_t *msg);
/// RT-safe: as above for the tensions message (held with its arrays: wire.h; a holder whose
/// pointers or count do not fit it is not encoded: CDPR_E_INVALID_ARG, counted).
cdpr_status_t cdpr_lcm_bridge_push_tensions(cdpr_lcm_bridge_t *b,
                                            const cdpr_lcm_wire_tensions_t *msg);
/// RT-safe: as above for the diagnostics message.
cdpr_status_t cdpr_lcm_bridge_push_diagnostics(cdpr_lcm_bridge_t *b, const cdpr_diagnostics_t *msg);
/// RT-safe: as above for the cable shape message (its own ring of CDPR_LCM_SHAPE_SLOTS).
cdpr_status_t cdpr_lcm_bridge_push_shape(cdpr_lcm_bridge_t *b, const cdpr_lcm_wire_shape_t *msg);

/// RT-safe: wake the bridge thread if it is asleep, so what was pushed is published now (with
/// wake_on_push = 0: call once after the period's pushes; one wake-up instead of one per
/// push). One fence; an eventfd write (non-blocking system call) only when the bridge sleeps.
void cdpr_lcm_bridge_wake(cdpr_lcm_bridge_t *b);

/// RT-safe: the newest valid winch command, or the hold command when the watchdog expired at
/// `now_ns` (cdpr_lcm_now_ns) or none was ever accepted. Returns CDPR_LCM_READ_* flags
/// (lcm_command.h). Wait-free, O(1).
int cdpr_lcm_bridge_read_command(cdpr_lcm_bridge_t *b, int64_t now_ns, cdpr_lcm_command_t *out);

/// RT-safe: statistics snapshot (relaxed atomic loads). O(1).
void cdpr_lcm_bridge_stats(const cdpr_lcm_bridge_t *b, cdpr_lcm_stats_t *s);

/// RT-safe: fill the bridge's part of a diagnostics message from `s` (ring, publication,
/// command and hold counters); the timing and model counters are left as they are.
void cdpr_lcm_pack_diagnostics(cdpr_diagnostics_t *msg, const cdpr_lcm_stats_t *s);

/// RT-safe: CLOCK_MONOTONIC now [ns] (vDSO clock_gettime: no system call on x86-64 Linux).
int64_t cdpr_lcm_now_ns(void);

#endif /* CDPR_LCM_BRIDGE_H */
