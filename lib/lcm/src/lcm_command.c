/* SPDX-License-Identifier: BSD-3-Clause */
/// @file lcm_command.c
/// Winch command decoding, validation, mailbox and watchdog (lcm_command.h).

#include "cdpr/lcm/command.h"

#include <limits.h>
#include <math.h>
#include <string.h>

#include "cdpr/lcm/wire.h"
#include "lcm_check.h"
#include "lcmtypes/cdpr_diagnostics_t.h"

// The reason codes are the indices of diagnostics_t.rejected[] on the wire.
CDPR_LCM_STATIC_ASSERT(CDPR_LCM_N_REJECT == CDPR_DIAGNOSTICS_T_N_REJECT, n_reject_matches_wire);
CDPR_LCM_STATIC_ASSERT(CDPR_LCM_REJECT_FUTURE == CDPR_DIAGNOSTICS_T_REJECT_FUTURE, future_index);
CDPR_LCM_STATIC_ASSERT(CDPR_LCM_REJECT_MALFORMED == CDPR_DIAGNOSTICS_T_REJECT_MALFORMED,
                       malformed_index);
CDPR_LCM_STATIC_ASSERT(CDPR_LCM_REJECT_SEQ_WINDOW == CDPR_DIAGNOSTICS_T_REJECT_SEQ_WINDOW,
                       seq_window_index);
CDPR_LCM_STATIC_ASSERT(CDPR_LCM_REJECT_OTHER_PLANT == CDPR_DIAGNOSTICS_T_REJECT_OTHER_PLANT,
                       other_plant_index);
CDPR_LCM_STATIC_ASSERT(CDPR_LCM_SEQ_WINDOW == CDPR_WINCH_COMMAND_T_SEQ_WINDOW, seq_window_wire);
CDPR_LCM_STATIC_ASSERT(CDPR_WINCH_COMMAND_T_MODE_RATE == (int)CDPR_WINCH_RATE, mode_rate);
CDPR_LCM_STATIC_ASSERT(CDPR_WINCH_COMMAND_T_MODE_LENGTH == (int)CDPR_WINCH_LENGTH, mode_length);

#define FRESH_BIT  4u
#define INDEX_MASK 3u

const char *cdpr_lcm_reject_str(cdpr_lcm_reject_t reason)
{
    switch (reason) {
    case CDPR_LCM_ACCEPTED:
        return "accepted";
    case CDPR_LCM_REJECT_MALFORMED:
        return "malformed";
    case CDPR_LCM_REJECT_WRONG_TYPE:
        return "wrong type";
    case CDPR_LCM_REJECT_NOT_FINITE:
        return "not finite";
    case CDPR_LCM_REJECT_BAD_MODE:
        return "unknown mode";
    case CDPR_LCM_REJECT_CABLE_COUNT:
        return "wrong cable count";
    case CDPR_LCM_REJECT_OUT_OF_LIMIT:
        return "out of limit";
    case CDPR_LCM_REJECT_STALE:
        return "stale";
    case CDPR_LCM_REJECT_REPLAYED:
        return "replayed";
    case CDPR_LCM_REJECT_FUTURE:
        return "future state";
    case CDPR_LCM_REJECT_NO_SESSION:
        return "no session";
    case CDPR_LCM_REJECT_OTHER_PLANT:
        return "other plant";
    case CDPR_LCM_REJECT_SESSION_BUSY:
        return "session busy";
    case CDPR_LCM_REJECT_SEQ_WINDOW:
        return "seq beyond window";
    case CDPR_LCM_N_REJECT:
    default:
        return "unknown";
    }
}

static cdpr_status_t check_limits(const cdpr_lcm_limits_t *lim, cdpr_diag_t *diag)
{
    int j;

    if (lim->n_cables < 1 || lim->n_cables > CDPR_LCM_MAX_CABLES) {
        return cdpr_diag_set(diag, CDPR_E_CAPACITY, "n_cables", -1);
    }
    if (!isfinite(lim->max_length_m)) {
        return cdpr_diag_set(diag, CDPR_E_NOT_FINITE, "max_length_m", -1);
    }
    for (j = 0; j < lim->n_cables; j++) {
        if (!isfinite(lim->u_max_m_per_s[j])) {
            return cdpr_diag_set(diag, CDPR_E_NOT_FINITE, "u_max_m_per_s", j);
        }
        if (!(lim->u_max_m_per_s[j] > 0.0)) {
            return cdpr_diag_set(diag, CDPR_E_NOT_POSITIVE, "u_max_m_per_s", j);
        }
        if (!isfinite(lim->min_length_m[j])) {
            return cdpr_diag_set(diag, CDPR_E_NOT_FINITE, "min_length_m", j);
        }
        if (!(lim->min_length_m[j] > 0.0)) {
            return cdpr_diag_set(diag, CDPR_E_NOT_POSITIVE, "min_length_m", j);
        }
        if (!(lim->max_length_m > lim->min_length_m[j])) {
            return cdpr_diag_set(diag, CDPR_E_OUT_OF_RANGE, "max_length_m", j);
        }
    }
    return cdpr_diag_set(diag, CDPR_OK, "", -1);
}

cdpr_status_t cdpr_lcm_limits_from_winch(cdpr_lcm_limits_t *lim, int n_cables,
                                         const cdpr_winch_params_t *winch, double max_length_m,
                                         cdpr_diag_t *diag)
{
    cdpr_lcm_limits_t l;
    cdpr_status_t st;
    int j;

    if (lim == NULL || winch == NULL) {
        return cdpr_diag_set(diag, CDPR_E_INVALID_ARG, lim == NULL ? "lim" : "winch", -1);
    }
    if (n_cables < 1 || n_cables > CDPR_LCM_MAX_CABLES) {
        return cdpr_diag_set(diag, CDPR_E_CAPACITY, "n_cables", -1);
    }
    memset(&l, 0, sizeof l);
    l.n_cables = n_cables;
    l.max_length_m = max_length_m;
    for (j = 0; j < n_cables; j++) {
        l.u_max_m_per_s[j] = (double)winch[j].u_max_m_per_s;
        l.min_length_m[j] = (double)winch[j].min_length_m;
    }
    st = check_limits(&l, diag);
    if (st == CDPR_OK) {
        *lim = l;
    }
    return st;
}

cdpr_status_t cdpr_lcm_validator_init(cdpr_lcm_validator_t *v, const cdpr_lcm_limits_t *lim,
                                      int64_t plant_session, int64_t takeover_ns, cdpr_diag_t *diag)
{
    cdpr_winch_command_t probe;
    unsigned char buf[64];
    cdpr_status_t st;

    if (v == NULL || lim == NULL) {
        return cdpr_diag_set(diag, CDPR_E_INVALID_ARG, v == NULL ? "validator" : "lim", -1);
    }
    st = check_limits(lim, diag);
    if (st != CDPR_OK) {
        return st;
    }
    if (plant_session <= 0) {
        return cdpr_diag_set(diag, CDPR_E_NOT_POSITIVE, "plant_session", -1);
    }
    if (takeover_ns <= 0) {
        return cdpr_diag_set(diag, CDPR_E_NOT_POSITIVE, "takeover_ns", -1);
    }
    memset(&probe, 0, sizeof probe);
    if (cdpr_winch_command_t_encode(buf, 0, (int)sizeof buf, &probe) < 8) {
        return cdpr_diag_set(diag, CDPR_E_INVALID_ARG, "winch_command_t encoding", -1);
    }
    memset(v, 0, sizeof *v);
    v->lim = *lim;
    v->plant_session = plant_session;
    v->takeover_ns = takeover_ns;
    v->controller_session = 0;
    v->last_seq = -1;
    v->last_state_seq = -1;
    v->published_state_seq = -1;
    memcpy(v->fingerprint, buf, sizeof v->fingerprint);
    return cdpr_diag_set(diag, CDPR_OK, "", -1);
}

void cdpr_lcm_validator_note_published(cdpr_lcm_validator_t *v, int64_t seq)
{
    if (seq > v->published_state_seq) {
        v->published_state_seq = seq;
    }
}

/* The rules on the values alone (mode, cable count, finite, limits). */
static cdpr_lcm_reject_t check_values(const cdpr_lcm_limits_t *lim, const cdpr_winch_command_t *msg)
{
    int j;

    if (msg->mode != CDPR_WINCH_COMMAND_T_MODE_RATE &&
        msg->mode != CDPR_WINCH_COMMAND_T_MODE_LENGTH) {
        return CDPR_LCM_REJECT_BAD_MODE;
    }
    if ((int)msg->n_cables != lim->n_cables) {
        return CDPR_LCM_REJECT_CABLE_COUNT;
    }
    for (j = 0; j < lim->n_cables; j++) {
        if (!isfinite(msg->value[j])) {
            return CDPR_LCM_REJECT_NOT_FINITE;
        }
    }
    for (j = 0; j < lim->n_cables; j++) {
        const double x = msg->value[j];
        if (msg->mode == CDPR_WINCH_COMMAND_T_MODE_RATE) {
            if (fabs(x) > lim->u_max_m_per_s[j]) {
                return CDPR_LCM_REJECT_OUT_OF_LIMIT;
            }
        } else if (x < lim->min_length_m[j] || x > lim->max_length_m) {
            return CDPR_LCM_REJECT_OUT_OF_LIMIT;
        }
    }
    return CDPR_LCM_ACCEPTED;
}

/* 1 when the active session is silent (or there is none): another session, or a new anchor,
 * may take over. */
static int session_silent(const cdpr_lcm_validator_t *v, int64_t rx_time_ns)
{
    return v->controller_session == 0 || rx_time_ns - v->last_accept_ns > v->takeover_ns;
}

/* The session and sequence rules (header: "Sessions"). */
static cdpr_lcm_reject_t check_sequence(const cdpr_lcm_validator_t *v,
                                        const cdpr_winch_command_t *msg, int64_t rx_time_ns)
{
    if (msg->controller_session <= 0) {
        return CDPR_LCM_REJECT_NO_SESSION;
    }
    if (msg->plant_session != v->plant_session) {
        return CDPR_LCM_REJECT_OTHER_PLANT;
    }
    if (msg->seq < 0) {
        return CDPR_LCM_REJECT_STALE;
    }
    if (session_silent(v, rx_time_ns) == 0) {
        if (msg->controller_session != v->controller_session) {
            return CDPR_LCM_REJECT_SESSION_BUSY;
        }
        if (msg->seq < v->last_seq) {
            return CDPR_LCM_REJECT_STALE;
        }
        if (msg->seq == v->last_seq) {
            return CDPR_LCM_REJECT_REPLAYED;
        }
        // seq > last_seq >= -1 here; the difference in unsigned arithmetic cannot overflow.
        if ((uint64_t)msg->seq - (uint64_t)v->last_seq > (uint64_t)CDPR_LCM_SEQ_WINDOW) {
            return CDPR_LCM_REJECT_SEQ_WINDOW;
        }
    }
    if (msg->state_seq < 0 || msg->state_seq < v->last_state_seq) {
        return CDPR_LCM_REJECT_STALE;
    }
    if (msg->state_seq > v->published_state_seq) {
        return CDPR_LCM_REJECT_FUTURE;
    }
    return CDPR_LCM_ACCEPTED;
}

cdpr_lcm_reject_t cdpr_lcm_validator_check(const cdpr_lcm_validator_t *v,
                                           const cdpr_winch_command_t *msg, int64_t rx_time_ns)
{
    const cdpr_lcm_reject_t r = check_values(&v->lim, msg);
    return (r != CDPR_LCM_ACCEPTED) ? r : check_sequence(v, msg, rx_time_ns);
}

static cdpr_lcm_reject_t count(cdpr_lcm_validator_t *v, cdpr_lcm_reject_t reason)
{
    // Single writer (the receiver thread): load + store is an exact increment; the atomic
    // store makes the value readable from other threads without a data race.
    if (reason == CDPR_LCM_ACCEPTED) {
        __atomic_store_n(&v->accepted, v->accepted + 1u, __ATOMIC_RELAXED);
    } else {
        __atomic_store_n(&v->rejected[reason], v->rejected[reason] + 1u, __ATOMIC_RELAXED);
    }
    return reason;
}

cdpr_lcm_reject_t cdpr_lcm_validator_accept(cdpr_lcm_validator_t *v, const void *buf, size_t len,
                                            int64_t rx_time_ns, cdpr_lcm_command_t *out)
{
    cdpr_lcm_wire_command_t w;
    const cdpr_winch_command_t *msg = &w.msg;
    cdpr_lcm_wire_t dec;
    cdpr_lcm_reject_t reason;
    int j;

    if (buf == NULL || len < sizeof v->fingerprint || len > (size_t)INT_MAX) {
        return count(v, CDPR_LCM_REJECT_MALFORMED);
    }
    if (memcmp(buf, v->fingerprint, sizeof v->fingerprint) != 0) {
        return count(v, CDPR_LCM_REJECT_WRONG_TYPE);
    }
    // Into fixed storage (wire.h): no allocation; more cables than this build holds is a
    // well-formed command for another plant.
    cdpr_lcm_wire_command_init(&w);
    dec = cdpr_lcm_wire_command_decode(&w, buf, (int)len);
    if (dec == CDPR_LCM_WIRE_OVER_CAPACITY) {
        return count(v, CDPR_LCM_REJECT_CABLE_COUNT);
    }
    if (dec != CDPR_LCM_WIRE_OK) {
        return count(v, CDPR_LCM_REJECT_MALFORMED);
    }
    reason = cdpr_lcm_validator_check(v, msg, rx_time_ns);
    if (reason != CDPR_LCM_ACCEPTED) {
        return count(v, reason);
    }

    if (msg->controller_session != v->controller_session) {
        // A take-over (the first controller included): read by cdpr_lcm_validator_sessions.
        __atomic_store_n(&v->controller_session, msg->controller_session, __ATOMIC_RELAXED);
        __atomic_store_n(&v->sessions, v->sessions + 1u, __ATOMIC_RELAXED);
    }
    // read by cdpr_lcm_validator_counts
    __atomic_store_n(&v->last_seq, msg->seq, __ATOMIC_RELAXED);
    v->last_state_seq = msg->state_seq;
    v->last_accept_ns = rx_time_ns;
    memset(out, 0, sizeof *out);
    out->seq = msg->seq;
    out->controller_session = msg->controller_session;
    out->state_seq = msg->state_seq;
    out->utime_us = msg->utime_us;
    out->rx_time_ns = rx_time_ns;
    out->mode = msg->mode == CDPR_WINCH_COMMAND_T_MODE_RATE ? CDPR_WINCH_RATE : CDPR_WINCH_LENGTH;
    out->n_cables = v->lim.n_cables; // == msg->n_cables (checked)
    for (j = 0; j < v->lim.n_cables; j++) {
        out->value[j] = msg->value[j];
    }
    return count(v, CDPR_LCM_ACCEPTED);
}

void cdpr_lcm_validator_counts(const cdpr_lcm_validator_t *v, uint64_t *accepted,
                               uint64_t rejected[CDPR_LCM_N_REJECT], int64_t *last_seq)
{
    if (accepted != NULL) {
        *accepted = __atomic_load_n(&v->accepted, __ATOMIC_RELAXED);
    }
    if (rejected != NULL) {
        for (int i = 0; i < CDPR_LCM_N_REJECT; i++) {
            rejected[i] = __atomic_load_n(&v->rejected[i], __ATOMIC_RELAXED);
        }
    }
    if (last_seq != NULL) {
        *last_seq = __atomic_load_n(&v->last_seq, __ATOMIC_RELAXED);
    }
}

void cdpr_lcm_validator_sessions(const cdpr_lcm_validator_t *v, int64_t *controller_session,
                                 uint64_t *sessions)
{
    if (controller_session != NULL) {
        *controller_session = __atomic_load_n(&v->controller_session, __ATOMIC_RELAXED);
    }
    if (sessions != NULL) {
        *sessions = __atomic_load_n(&v->sessions, __ATOMIC_RELAXED);
    }
}

void cdpr_lcm_command_hold(int n_cables, cdpr_lcm_command_t *out)
{
    memset(out, 0, sizeof *out);
    out->seq = -1;
    out->state_seq = -1;
    out->mode = CDPR_WINCH_RATE;
    out->n_cables = n_cables;
}

cdpr_status_t cdpr_lcm_mailbox_init(cdpr_lcm_mailbox_t *mb, int n_cables, int64_t timeout_ns,
                                    cdpr_diag_t *diag)
{
    if (mb == NULL) {
        return cdpr_diag_set(diag, CDPR_E_INVALID_ARG, "mailbox", -1);
    }
    if (n_cables < 1 || n_cables > CDPR_LCM_MAX_CABLES) {
        return cdpr_diag_set(diag, CDPR_E_CAPACITY, "n_cables", -1);
    }
    if (timeout_ns <= 0) {
        return cdpr_diag_set(diag, CDPR_E_NOT_POSITIVE, "timeout_ns", -1);
    }
    memset(mb, 0, sizeof *mb);
    mb->back = 0u;
    mb->middle = 1u; // no fresh bit: nothing written yet
    mb->front = 2u;
    mb->n_cables = n_cables;
    mb->timeout_ns = timeout_ns;
    return cdpr_diag_set(diag, CDPR_OK, "", -1);
}

void cdpr_lcm_mailbox_write(cdpr_lcm_mailbox_t *mb, const cdpr_lcm_command_t *cmd)
{
    uint32_t prev;

    mb->buf[mb->back] = *cmd;
    // Release: the reader that takes this buffer (acquire) sees the copy above. Acquire: the
    // buffer we get back is no longer being read by the reader (it gave it up in its own
    // exchange, after its last read of it).
    prev = __atomic_exchange_n(&mb->middle, mb->back | FRESH_BIT, __ATOMIC_ACQ_REL);
    mb->back = prev & INDEX_MASK;
}

static void set_holding(cdpr_lcm_mailbox_t *mb, uint32_t holding)
{
    if (holding != 0u && mb->holding == 0u) {
        __atomic_store_n(&mb->hold_entries, mb->hold_entries + 1u, __ATOMIC_RELAXED);
    }
    if (holding != mb->holding) {
        __atomic_store_n(&mb->holding, holding, __ATOMIC_RELAXED);
    }
}

int cdpr_lcm_mailbox_read(cdpr_lcm_mailbox_t *mb, int64_t now_ns, cdpr_lcm_command_t *out)
{
    int flags = 0;
    const cdpr_lcm_command_t *c;

    __atomic_store_n(&mb->reads, mb->reads + 1u, __ATOMIC_RELAXED);
    if ((__atomic_load_n(&mb->middle, __ATOMIC_RELAXED) & FRESH_BIT) != 0u) {
        const uint32_t prev = __atomic_exchange_n(&mb->middle, mb->front, __ATOMIC_ACQ_REL);
        mb->front = prev & INDEX_MASK;
        mb->have = 1;
        flags |= CDPR_LCM_READ_NEW;
    }
    c = &mb->buf[mb->front];
    if (mb->have == 0 || now_ns - c->rx_time_ns > mb->timeout_ns) {
        // Start-up (counted as the first hold entry) or a silent controller.
        flags = CDPR_LCM_READ_HOLD | (mb->have == 0 ? CDPR_LCM_READ_NEVER : 0);
        set_holding(mb, 1u);
        __atomic_store_n(&mb->hold_reads, mb->hold_reads + 1u, __ATOMIC_RELAXED);
        cdpr_lcm_command_hold(mb->n_cables, out);
        return flags;
    }
    set_holding(mb, 0u);
    *out = *c;
    return flags;
}
