/* SPDX-License-Identifier: BSD-3-Clause */
/// @file lcm_bridge.c
/// The LCM bridge thread, its publisher and receiver, and the real-time side API
/// (lcm_bridge.h). POSIX + Linux (eventfd); built with _GNU_SOURCE by CMake.
///
/// Wake-ups. Waking a thread blocked in poll() costs the waker a system call and a
/// cross-core wake-up (several microseconds on a VM), so the real-time thread only writes the
/// eventfd when the bridge thread says it may be asleep. The handshake is the store-buffering
/// (Dekker) pattern with a sequentially consistent fence on each side:
///   bridge: sleeping = 1; fence; if a ring is non-empty -> do not block; poll(); sleeping = 0
///   RT:     commit (head + 1); fence; if sleeping: exchange it to 0 and, if it was 1, write
///           the eventfd
/// The fences forbid the outcome where the bridge misses the new head AND the RT thread misses
/// sleeping = 1, so a pushed message never waits for the idle timeout. Clearing the flag makes
/// the later pushes of the same period skip the system call: the bridge, once awake, looks at
/// the rings again before it next blocks. A wake-up may be spurious (the bridge had not
/// blocked yet); that costs one empty loop.

#include "cdpr/lcm/bridge.h"

#include <errno.h>
#include <math.h>
#include <poll.h>
#include <sched.h>
#include <string.h>
#include <sys/eventfd.h>
#include <sys/mman.h>
#include <sys/random.h>
#include <time.h>
#include <unistd.h>

/// Upper bound of messages handled per poll, so a flood on the command channel cannot keep
/// the bridge from publishing.
#define MAX_HANDLE_PER_POLL 1000

static const char *const channel_suffix[CDPR_LCM_N_CHANNELS] = {
    "CABIN_STATE", "CABLE_TENSIONS", "DIAGNOSTICS", "CABLE_SHAPE", "WINCH_COMMAND"};

static void bump(uint64_t *counter)
{
    // Single writer per counter: an exact increment; atomic store for concurrent readers.
    __atomic_store_n(counter, *counter + 1u, __ATOMIC_RELAXED);
}

int64_t cdpr_lcm_now_ns(void)
{
    struct timespec ts;
    (void)clock_gettime(CLOCK_MONOTONIC, &ts);
    return (int64_t)ts.tv_sec * 1000000000 + (int64_t)ts.tv_nsec;
}

int64_t cdpr_lcm_new_session(void)
{
    uint64_t x = 0u;
    if (getrandom(&x, sizeof x, 0u) != (ssize_t)sizeof x) {
        // No entropy source (very old kernel, seccomp): clock and pid still differ per run.
        x = (uint64_t)cdpr_lcm_now_ns() * 0x9E3779B97F4A7C15u ^ ((uint64_t)getpid() << 32);
    }
    x &= (uint64_t)INT64_MAX;
    return (x == 0u) ? 1 : (int64_t)x;
}

void cdpr_lcm_bridge_params_default(cdpr_lcm_bridge_params_t *p)
{
    int j;

    memset(p, 0, sizeof *p);
    p->url = NULL;
    p->channel_prefix = "CDPR_";
    p->n_cables = (CDPR_LCM_MAX_CABLES < 6) ? CDPR_LCM_MAX_CABLES : 6; // the paper's robot
    for (j = 0; j < CDPR_MAX_CABLES; j++) {
        cdpr_winch_params_default(&p->winch[j]);
    }
    p->max_length_m = 1000.0;
    p->watchdog_timeout_s = 0.1;
    p->idle_poll_ms = 10;
    p->wake_on_push = 1;
    p->on_open = NULL;
    p->on_open_ctx = NULL;
    p->plant_session = 0;
    p->on_other_plant = NULL;
    p->on_other_plant_ctx = NULL;
}

// Channel names are also LCM subscription regexes: keep the prefix free of regex syntax.
static int prefix_char_ok(char c)
{
    return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_' ||
           c == '-' || c == '/';
}

static int fits(int encoded, uint32_t slot_bytes)
{
    return encoded > 0 && (uint32_t)encoded <= slot_bytes;
}

// Check once that each message of this plant fits its ring's slots: the state and diagnostics
// have fixed sizes, the tensions' size is set by the cable count, the shape's at most by the
// cable count times CDPR_CABLE_SHAPE_T_MAX_NODES. Encoding once also makes the generated code
// compute and cache each type's hash here instead of on the real-time thread.
static cdpr_status_t check_sizes(const cdpr_lcm_bridge_t *b, int n_cables, cdpr_diag_t *diag)
{
    cdpr_lcm_wire_shape_t sh;
    cdpr_cabin_state_t st;
    cdpr_lcm_wire_tensions_t te;
    cdpr_diagnostics_t di;
    unsigned char scratch[CDPR_LCM_SHAPE_SLOT_BYTES];

    memset(&st, 0, sizeof st);
    memset(&di, 0, sizeof di);
    cdpr_lcm_wire_tensions_init(&te);
    te.msg.n_cables = (int8_t)n_cables;
    cdpr_lcm_wire_shape_init(&sh);
    sh.msg.n_cables = (int8_t)n_cables;
    sh.msg.n_points = (int32_t)(n_cables * CDPR_CABLE_SHAPE_T_MAX_NODES);
    if (!fits(cdpr_cabin_state_t_encode(scratch, 0, (int)sizeof scratch, &st),
              b->ring.slot_bytes)) {
        return cdpr_diag_set(diag, CDPR_E_CAPACITY, "CDPR_LCM_SLOT_BYTES (cabin_state_t)", -1);
    }
    if (!fits(cdpr_lcm_wire_tensions_encode(&te, scratch, (int)sizeof scratch),
              b->ring.slot_bytes)) {
        return cdpr_diag_set(diag, CDPR_E_CAPACITY, "CDPR_LCM_SLOT_BYTES (cable_tensions_t)", -1);
    }
    if (!fits(cdpr_diagnostics_t_encode(scratch, 0, (int)sizeof scratch, &di),
              b->ring.slot_bytes)) {
        return cdpr_diag_set(diag, CDPR_E_CAPACITY, "CDPR_LCM_SLOT_BYTES (diagnostics_t)", -1);
    }
    if (!fits(cdpr_lcm_wire_shape_encode(&sh, scratch, (int)sizeof scratch),
              b->shape_ring.slot_bytes)) {
        return cdpr_diag_set(diag, CDPR_E_CAPACITY, "CDPR_LCM_SHAPE_SLOT_BYTES", -1);
    }
    return CDPR_OK;
}

cdpr_status_t cdpr_lcm_bridge_init(cdpr_lcm_bridge_t *b, const cdpr_lcm_bridge_params_t *p,
                                   cdpr_diag_t *diag)
{
    const char *prefix;
    const char *url;
    size_t prefix_len;
    size_t i;
    int j;
    cdpr_lcm_limits_t lim;
    cdpr_status_t st;

    if (b == NULL || p == NULL) {
        return cdpr_diag_set(diag, CDPR_E_INVALID_ARG, b == NULL ? "bridge" : "params", -1);
    }
    prefix = p->channel_prefix != NULL ? p->channel_prefix : "";
    prefix_len = strlen(prefix);
    if (prefix_len + strlen("CABLE_TENSIONS") >= CDPR_LCM_CHANNEL_MAX) {
        return cdpr_diag_set(diag, CDPR_E_OUT_OF_RANGE, "channel_prefix", -1);
    }
    for (i = 0; i < prefix_len; i++) {
        if (!prefix_char_ok(prefix[i])) {
            return cdpr_diag_set(diag, CDPR_E_INVALID_ARG, "channel_prefix", (int)i);
        }
    }
    url = p->url != NULL ? p->url : "";
    if (strlen(url) >= CDPR_LCM_URL_MAX) {
        return cdpr_diag_set(diag, CDPR_E_OUT_OF_RANGE, "url", -1);
    }
    if (p->n_cables < 1 || p->n_cables > CDPR_LCM_MAX_CABLES) {
        return cdpr_diag_set(diag, CDPR_E_CAPACITY, "n_cables", -1);
    }
    for (j = 0; j < p->n_cables; j++) {
        cdpr_winch_t scratch;
        st = cdpr_winch_init(&scratch, &p->winch[j], diag);
        if (st != CDPR_OK) {
            if (diag != NULL) {
                diag->index = j;
            }
            return st;
        }
    }
    st = cdpr_lcm_limits_from_winch(&lim, p->n_cables, p->winch, p->max_length_m, diag);
    if (st != CDPR_OK) {
        return st;
    }
    if (!isfinite(p->watchdog_timeout_s)) {
        return cdpr_diag_set(diag, CDPR_E_NOT_FINITE, "watchdog_timeout_s", -1);
    }
    if (!(p->watchdog_timeout_s > 0.0) || p->watchdog_timeout_s > 3600.0) {
        return cdpr_diag_set(diag, CDPR_E_OUT_OF_RANGE, "watchdog_timeout_s", -1);
    }
    if (p->idle_poll_ms < 1 || p->idle_poll_ms > 1000) {
        return cdpr_diag_set(diag, CDPR_E_OUT_OF_RANGE, "idle_poll_ms", -1);
    }
    if (p->plant_session < 0) {
        return cdpr_diag_set(diag, CDPR_E_NOT_POSITIVE, "plant_session", -1);
    }

    memset(b, 0, sizeof *b);
    b->p = *p;
    memcpy(b->url, url, strlen(url) + 1u);
    b->p.url = b->url;
    for (j = 0; j < CDPR_LCM_N_CHANNELS; j++) {
        memcpy(b->channel[j], prefix, prefix_len);
        memcpy(b->channel[j] + prefix_len, channel_suffix[j], strlen(channel_suffix[j]) + 1u);
    }
    b->p.channel_prefix = NULL; // the caller's string may not outlive init; names are above
    b->lcm_fd = -1;
    b->wake_fd = -1;
    b->published_state_seq = -1;
    b->other_reported = -1;
    if (b->p.plant_session == 0) {
        b->p.plant_session = cdpr_lcm_new_session();
    }

    st = cdpr_lcm_ring_init(&b->ring, b->ring_storage, sizeof b->ring_storage, CDPR_LCM_RING_SLOTS,
                            CDPR_LCM_SLOT_BYTES, diag);
    if (st == CDPR_OK) {
        st = cdpr_lcm_ring_init(&b->shape_ring, b->shape_storage, sizeof b->shape_storage,
                                CDPR_LCM_SHAPE_SLOTS, CDPR_LCM_SHAPE_SLOT_BYTES, diag);
    }
    if (st == CDPR_OK) {
        st = check_sizes(b, p->n_cables, diag);
    }
    if (st == CDPR_OK) {
        st = cdpr_lcm_validator_init(&b->validator, &lim, b->p.plant_session,
                                     (int64_t)llround(p->watchdog_timeout_s * 1e9), diag);
    }
    if (st == CDPR_OK) {
        st = cdpr_lcm_mailbox_init(&b->mailbox, p->n_cables,
                                   (int64_t)llround(p->watchdog_timeout_s * 1e9), diag);
    }
    if (st != CDPR_OK) {
        return st;
    }
    if (pthread_mutex_init(&b->start_lock, NULL) != 0 ||
        pthread_cond_init(&b->start_cond, NULL) != 0) {
        return cdpr_diag_set(diag, CDPR_E_INVALID_ARG, "pthread_mutex/cond_init", -1);
    }
    return cdpr_diag_set(diag, CDPR_OK, "", -1);
}

const char *cdpr_lcm_bridge_channel(const cdpr_lcm_bridge_t *b, cdpr_lcm_channel_t ch)
{
    if ((int)ch < 0 || ch >= CDPR_LCM_N_CHANNELS) {
        return "";
    }
    return b->channel[ch];
}

int64_t cdpr_lcm_bridge_session(const cdpr_lcm_bridge_t *b)
{
    return b->p.plant_session;
}

lcm_t *cdpr_lcm_bridge_lcm(cdpr_lcm_bridge_t *b)
{
    return b->lcm;
}

/* ---------------------------------------------------------------- bridge thread side */

static void on_command(const lcm_recv_buf_t *rbuf, const char *channel, void *user)
{
    cdpr_lcm_bridge_t *b = (cdpr_lcm_bridge_t *)user;
    cdpr_lcm_command_t cmd;
    (void)channel;

    bump(&b->commands_received);
    if (cdpr_lcm_validator_accept(&b->validator, rbuf->data, (size_t)rbuf->data_size,
                                  cdpr_lcm_now_ns(), &cmd) == CDPR_LCM_ACCEPTED) {
        cdpr_lcm_mailbox_write(&b->mailbox, &cmd);
    }
}

/* Our own state channel: every state there that is not ours is another plant's. */
static void on_state(const lcm_recv_buf_t *rbuf, const char *channel, void *user)
{
    cdpr_lcm_bridge_t *b = (cdpr_lcm_bridge_t *)user;
    cdpr_cabin_state_t msg;
    int64_t session = 0;
    (void)channel;

    if (rbuf->data_size <= (uint32_t)INT32_MAX &&
        cdpr_cabin_state_t_decode(rbuf->data, 0, (int)rbuf->data_size, &msg) ==
            (int)rbuf->data_size) {
        if (msg.plant_session == b->p.plant_session) {
            return;
        }
        session = msg.plant_session;
    }
    bump(&b->other_plant_messages);
    __atomic_store_n(&b->other_plant_session, session, __ATOMIC_RELAXED);
    if (session != b->other_reported) {
        b->other_reported = session;
        if (b->p.on_other_plant != NULL) {
            b->p.on_other_plant(session, b->p.on_other_plant_ctx);
        }
    }
}

static void publish_ring(cdpr_lcm_bridge_t *b, cdpr_lcm_ring_t *ring)
{
    uint32_t i;

    // At most one ring's worth per call: a producer that keeps pushing cannot starve receiving.
    for (i = 0; i < ring->n_slots; i++) {
        const unsigned char *data;
        const cdpr_lcm_slot_t *h = cdpr_lcm_ring_peek(ring, &data);
        if (h == NULL) {
            return;
        }
        if (h->channel >= 0 && h->channel < CDPR_LCM_N_CHANNELS &&
            lcm_publish(b->lcm, b->channel[h->channel], data, (unsigned int)h->len) == 0) {
            bump(&b->published);
            if (h->channel == CDPR_LCM_CH_CABIN_STATE) {
                // Commands may now answer this state (validator rule FUTURE).
                cdpr_lcm_validator_note_published(&b->validator, h->seq);
                __atomic_store_n(&b->published_state_seq, b->validator.published_state_seq,
                                 __ATOMIC_RELAXED);
            }
        } else {
            bump(&b->publish_errors);
        }
        cdpr_lcm_ring_release(ring);
    }
}

static void publish_pending(cdpr_lcm_bridge_t *b)
{
    publish_ring(b, &b->ring);
    publish_ring(b, &b->shape_ring);
}

static void close_wake(cdpr_lcm_bridge_t *b)
{
    const int fd = b->wake_fd;
    if (fd >= 0) {
        __atomic_store_n(&b->wake_fd, -1, __ATOMIC_RELAXED);
        (void)close(fd);
    }
}

static void close_lcm(cdpr_lcm_bridge_t *b)
{
    if (b->lcm != NULL) {
        if (b->sub != NULL) {
            (void)lcm_unsubscribe(b->lcm, b->sub);
        }
        if (b->sub_state != NULL) {
            (void)lcm_unsubscribe(b->lcm, b->sub_state);
        }
        lcm_destroy(b->lcm);
    }
    b->lcm = NULL;
    b->sub = NULL;
    b->sub_state = NULL;
    b->lcm_fd = -1;
    b->opened = 0;
}

/* liblcm's udpm provider does not check every allocation of its start-up (lcm_subscribe
 * starts a receive thread; under `ulimit -v` 30-34 MB cdpr-rt crashed inside it): before it
 * runs, the address space it needs must be there. 1 when CDPR_LCM_UDPM_HEADROOM_BYTES of
 * address space can be reserved (and released again) now, or the provider is not udpm. */
static int udpm_headroom(const char *url)
{
    const int udpm = (url[0] == '\0' || strncmp(url, "udpm://", 7) == 0) ? 1 : 0;
    if (udpm == 0) {
        return 1;
    }
    void *p = mmap(NULL, CDPR_LCM_UDPM_HEADROOM_BYTES, PROT_NONE,
                   MAP_PRIVATE | MAP_ANONYMOUS | MAP_NORESERVE, -1, 0);
    if (p == MAP_FAILED) {
        return 0;
    }
    (void)munmap(p, CDPR_LCM_UDPM_HEADROOM_BYTES);
    return 1;
}

cdpr_status_t cdpr_lcm_bridge_open(cdpr_lcm_bridge_t *b, cdpr_diag_t *diag)
{
    if (b->opened) {
        return cdpr_diag_set(diag, CDPR_E_INVALID_ARG, "already open", -1);
    }
    if (udpm_headroom(b->url) == 0) {
        return cdpr_diag_set(diag, CDPR_E_IO,
                             "udpm needs 24 MiB more address space for liblcm's receive thread "
                             "(ulimit -v?)",
                             -1);
    }
    b->lcm = lcm_create(b->url[0] != '\0' ? b->url : NULL);
    if (b->lcm == NULL) {
        return cdpr_diag_set(diag, CDPR_E_INVALID_ARG, "lcm_create (url)", -1);
    }
    b->sub = lcm_subscribe(b->lcm, b->channel[CDPR_LCM_CH_WINCH_COMMAND], on_command, b);
    b->sub_state = lcm_subscribe(b->lcm, b->channel[CDPR_LCM_CH_CABIN_STATE], on_state, b);
    if (b->sub == NULL || b->sub_state == NULL) {
        close_lcm(b);
        return cdpr_diag_set(diag, CDPR_E_INVALID_ARG, "lcm_subscribe", -1);
    }
    // For udpm this starts liblcm's receive thread and its multicast self-test (may block).
    b->lcm_fd = lcm_get_fileno(b->lcm);
    if (b->lcm_fd < 0) {
        close_lcm(b);
        return cdpr_diag_set(diag, CDPR_E_INVALID_ARG, "lcm_get_fileno", -1);
    }
    if (b->wake_fd < 0) {
        const int fd = eventfd(0u, EFD_NONBLOCK | EFD_CLOEXEC);
        if (fd < 0) {
            close_lcm(b);
            return cdpr_diag_set(diag, CDPR_E_INVALID_ARG, "eventfd", -1);
        }
        __atomic_store_n(&b->wake_fd, fd, __ATOMIC_RELEASE);
    }
    b->opened = 1;
    if (b->p.on_open != NULL && b->p.on_open(b->lcm, b->p.on_open_ctx) != 0) {
        cdpr_lcm_bridge_close(b);
        return cdpr_diag_set(diag, CDPR_E_INVALID_ARG, "on_open", -1);
    }
    return cdpr_diag_set(diag, CDPR_OK, "", -1);
}

int cdpr_lcm_bridge_poll(cdpr_lcm_bridge_t *b, int timeout_ms)
{
    struct pollfd pfd[2];
    int handled = 0;
    int rc;

    if (!b->opened) {
        return -1;
    }
    publish_pending(b);
    // Announce the sleep, then look again (see "Wake-ups" above).
    __atomic_store_n(&b->sleeping, 1u, __ATOMIC_RELAXED);
    __atomic_thread_fence(__ATOMIC_SEQ_CST);
    if (cdpr_lcm_ring_pending(&b->ring) || cdpr_lcm_ring_pending(&b->shape_ring)) {
        timeout_ms = 0;
    }
    pfd[0].fd = b->lcm_fd;
    pfd[0].events = POLLIN;
    pfd[0].revents = 0;
    pfd[1].fd = b->wake_fd;
    pfd[1].events = POLLIN;
    pfd[1].revents = 0;
    rc = poll(pfd, 2u, timeout_ms < 0 ? 0 : timeout_ms);
    __atomic_store_n(&b->sleeping, 0u, __ATOMIC_RELAXED);
    if (rc < 0) {
        return errno == EINTR ? 0 : -1;
    }
    if ((pfd[1].revents & POLLIN) != 0) {
        uint64_t n;
        if (read(b->wake_fd, &n, sizeof n) < 0) {
            // EAGAIN: another read emptied it first; nothing to do.
        }
    }
    if ((pfd[0].revents & POLLIN) != 0) {
        // lcm_handle_timeout dispatches one message per call: drain, bounded.
        while (handled < MAX_HANDLE_PER_POLL) {
            rc = lcm_handle_timeout(b->lcm, 0);
            if (rc > 0) {
                handled++;
            } else {
                if (rc < 0) {
                    bump(&b->handle_errors);
                }
                break;
            }
        }
    }
    publish_pending(b);
    if ((pfd[0].revents & (POLLERR | POLLHUP | POLLNVAL)) != 0) {
        return -1;
    }
    return handled;
}

void cdpr_lcm_bridge_close(cdpr_lcm_bridge_t *b)
{
    close_lcm(b);
    close_wake(b);
}

static void set_start_state(cdpr_lcm_bridge_t *b, int state)
{
    (void)pthread_mutex_lock(&b->start_lock);
    b->start_state = state;
    (void)pthread_cond_broadcast(&b->start_cond);
    (void)pthread_mutex_unlock(&b->start_lock);
}

static void *bridge_main(void *arg)
{
    cdpr_lcm_bridge_t *b = (cdpr_lcm_bridge_t *)arg;
    cdpr_diag_t d;

    if (cdpr_lcm_bridge_open(b, &d) != CDPR_OK) {
        b->start_error = d.field; // read by start() after the state change (mutex)
        b->start_status = d.status;
        set_start_state(b, -1);
        return NULL;
    }
    set_start_state(b, 1);
    while (__atomic_load_n(&b->stop, __ATOMIC_ACQUIRE) == 0) {
        if (cdpr_lcm_bridge_poll(b, b->p.idle_poll_ms) < 0) {
            // The LCM descriptor failed: avoid spinning, keep publishing attempts bounded.
            struct timespec pause;
            pause.tv_sec = (time_t)(b->p.idle_poll_ms / 1000);
            pause.tv_nsec = 1000000L * (long)(b->p.idle_poll_ms % 1000);
            bump(&b->handle_errors);
            (void)nanosleep(&pause, NULL);
        }
    }
    publish_pending(b); // what the real-time thread queued before stop (e.g. final diagnostics)
    close_lcm(b);       // the eventfd is closed by stop() after the join
    return NULL;
}

cdpr_status_t cdpr_lcm_bridge_start(cdpr_lcm_bridge_t *b, cdpr_diag_t *diag)
{
    pthread_attr_t attr;
    struct sched_param sp;
    int rc;
    int state;

    if (b->running || b->opened) {
        return cdpr_diag_set(diag, CDPR_E_INVALID_ARG, "already started", -1);
    }
    b->start_state = 0;
    b->start_error = "";
    __atomic_store_n(&b->stop, 0, __ATOMIC_RELEASE);

    // Explicit SCHED_OTHER: started from a SCHED_FIFO thread, the bridge (and the receive
    // thread liblcm creates from it) would otherwise inherit real-time priority.
    memset(&sp, 0, sizeof sp);
    sp.sched_priority = 0;
    if (pthread_attr_init(&attr) != 0) {
        return cdpr_diag_set(diag, CDPR_E_INVALID_ARG, "pthread_attr_init", -1);
    }
    rc = pthread_attr_setinheritsched(&attr, PTHREAD_EXPLICIT_SCHED);
    if (rc == 0) {
        rc = pthread_attr_setschedpolicy(&attr, SCHED_OTHER);
    }
    if (rc == 0) {
        rc = pthread_attr_setschedparam(&attr, &sp);
    }
    if (rc == 0) {
        rc = pthread_create(&b->thread, &attr, bridge_main, b);
    }
    (void)pthread_attr_destroy(&attr);
    if (rc != 0) {
        return cdpr_diag_set(diag, CDPR_E_INVALID_ARG, "pthread_create", -1);
    }
    b->running = 1;

    (void)pthread_mutex_lock(&b->start_lock);
    while (b->start_state == 0) {
        (void)pthread_cond_wait(&b->start_cond, &b->start_lock);
    }
    state = b->start_state;
    (void)pthread_mutex_unlock(&b->start_lock);
    if (state < 0) {
        const char *why = b->start_error;
        const cdpr_status_t st = b->start_status;
        cdpr_lcm_bridge_stop(b);
        return cdpr_diag_set(diag, (st != CDPR_OK) ? st : CDPR_E_INVALID_ARG, why, -1);
    }
    return cdpr_diag_set(diag, CDPR_OK, "", -1);
}

void cdpr_lcm_bridge_stop(cdpr_lcm_bridge_t *b)
{
    if (!b->running) {
        return;
    }
    __atomic_store_n(&b->stop, 1, __ATOMIC_RELEASE);
    if (b->wake_fd >= 0) {
        const uint64_t one = 1u;
        if (write(b->wake_fd, &one, sizeof one) < 0) {
            // EAGAIN: already signalled. The idle poll timeout bounds the wait anyway.
        }
    }
    (void)pthread_join(b->thread, NULL);
    b->running = 0;
    close_wake(b);
}

/* ---------------------------------------------------------------- real-time side */

void cdpr_lcm_bridge_wake(cdpr_lcm_bridge_t *b)
{
    int fd;

    // See "Wake-ups" above: the fence orders the caller's commits before the load of
    // `sleeping`.
    __atomic_thread_fence(__ATOMIC_SEQ_CST);
    if (__atomic_load_n(&b->sleeping, __ATOMIC_RELAXED) == 0u ||
        __atomic_exchange_n(&b->sleeping, 0u, __ATOMIC_RELAXED) == 0u) {
        return; // the bridge thread is awake, or already being woken
    }
    fd = __atomic_load_n(&b->wake_fd, __ATOMIC_ACQUIRE);
    if (fd >= 0) {
        const uint64_t one = 1u;
        bump(&b->wakeups);
        // Non-blocking eventfd: never sleeps; EAGAIN (counter saturated) means a wake-up is
        // pending anyway. Otherwise the idle poll publishes within idle_poll_ms.
        if (write(fd, &one, sizeof one) < 0) {
            return;
        }
    }
}

static cdpr_status_t commit_and_wake(cdpr_lcm_bridge_t *b, cdpr_lcm_ring_t *ring, int len,
                                     cdpr_lcm_channel_t ch, int64_t seq)
{
    if (len <= 0 || cdpr_lcm_ring_commit(ring, (int32_t)ch, (int32_t)len, seq) != CDPR_OK) {
        // Cannot happen with the sizes checked at init; the claim stays open for the next push.
        bump(&b->encode_errors);
        return CDPR_E_INVALID_ARG;
    }
    if (b->p.wake_on_push) {
        cdpr_lcm_bridge_wake(b);
    }
    return CDPR_OK;
}

cdpr_status_t cdpr_lcm_bridge_push_cabin_state(cdpr_lcm_bridge_t *b, const cdpr_cabin_state_t *msg)
{
    unsigned char *slot = cdpr_lcm_ring_claim(&b->ring);
    if (slot == NULL) {
        return CDPR_E_CAPACITY;
    }
    return commit_and_wake(b, &b->ring,
                           cdpr_cabin_state_t_encode(slot, 0, (int)b->ring.slot_bytes, msg),
                           CDPR_LCM_CH_CABIN_STATE, msg->seq);
}

cdpr_status_t cdpr_lcm_bridge_push_tensions(cdpr_lcm_bridge_t *b,
                                            const cdpr_lcm_wire_tensions_t *msg)
{
    unsigned char *slot = cdpr_lcm_ring_claim(&b->ring);
    if (slot == NULL) {
        return CDPR_E_CAPACITY;
    }
    return commit_and_wake(b, &b->ring,
                           cdpr_lcm_wire_tensions_encode(msg, slot, (int)b->ring.slot_bytes),
                           CDPR_LCM_CH_CABLE_TENSIONS, msg->msg.seq);
}

cdpr_status_t cdpr_lcm_bridge_push_diagnostics(cdpr_lcm_bridge_t *b, const cdpr_diagnostics_t *msg)
{
    unsigned char *slot = cdpr_lcm_ring_claim(&b->ring);
    if (slot == NULL) {
        return CDPR_E_CAPACITY;
    }
    return commit_and_wake(b, &b->ring,
                           cdpr_diagnostics_t_encode(slot, 0, (int)b->ring.slot_bytes, msg),
                           CDPR_LCM_CH_DIAGNOSTICS, msg->seq);
}

cdpr_status_t cdpr_lcm_bridge_push_shape(cdpr_lcm_bridge_t *b, const cdpr_lcm_wire_shape_t *msg)
{
    unsigned char *slot = cdpr_lcm_ring_claim(&b->shape_ring);
    if (slot == NULL) {
        return CDPR_E_CAPACITY;
    }
    return commit_and_wake(b, &b->shape_ring,
                           cdpr_lcm_wire_shape_encode(msg, slot, (int)b->shape_ring.slot_bytes),
                           CDPR_LCM_CH_CABLE_SHAPE, msg->msg.seq);
}

int cdpr_lcm_bridge_read_command(cdpr_lcm_bridge_t *b, int64_t now_ns, cdpr_lcm_command_t *out)
{
    return cdpr_lcm_mailbox_read(&b->mailbox, now_ns, out);
}

void cdpr_lcm_bridge_stats(const cdpr_lcm_bridge_t *b, cdpr_lcm_stats_t *s)
{
    memset(s, 0, sizeof *s);
    cdpr_lcm_ring_stats(&b->ring, &s->ring);
    cdpr_lcm_ring_stats(&b->shape_ring, &s->shape_ring);
    s->encode_errors = __atomic_load_n(&b->encode_errors, __ATOMIC_RELAXED);
    s->wakeups = __atomic_load_n(&b->wakeups, __ATOMIC_RELAXED);
    s->published = __atomic_load_n(&b->published, __ATOMIC_RELAXED);
    s->publish_errors = __atomic_load_n(&b->publish_errors, __ATOMIC_RELAXED);
    s->handle_errors = __atomic_load_n(&b->handle_errors, __ATOMIC_RELAXED);
    s->commands_received = __atomic_load_n(&b->commands_received, __ATOMIC_RELAXED);
    cdpr_lcm_validator_counts(&b->validator, &s->commands_accepted, s->rejected,
                              &s->last_command_seq);
    s->published_state_seq = __atomic_load_n(&b->published_state_seq, __ATOMIC_RELAXED);
    s->hold_entries = __atomic_load_n(&b->mailbox.hold_entries, __ATOMIC_RELAXED);
    s->hold_reads = __atomic_load_n(&b->mailbox.hold_reads, __ATOMIC_RELAXED);
    s->holding = (int)__atomic_load_n(&b->mailbox.holding, __ATOMIC_RELAXED);
    s->plant_session = b->p.plant_session;
    cdpr_lcm_validator_sessions(&b->validator, &s->controller_session, &s->controller_sessions);
    s->other_plant_messages = __atomic_load_n(&b->other_plant_messages, __ATOMIC_RELAXED);
    s->other_plant_session = __atomic_load_n(&b->other_plant_session, __ATOMIC_RELAXED);
}

static int64_t i64(uint64_t x)
{
    return x > (uint64_t)INT64_MAX ? INT64_MAX : (int64_t)x;
}

void cdpr_lcm_pack_diagnostics(cdpr_diagnostics_t *msg, const cdpr_lcm_stats_t *s)
{
    int i;

    msg->ring_pushed = i64(s->ring.pushed + s->shape_ring.pushed);
    msg->ring_dropped = i64(s->ring.dropped + s->shape_ring.dropped);
    msg->published = i64(s->published);
    msg->publish_errors = i64(s->publish_errors);
    msg->commands_accepted = i64(s->commands_accepted);
    for (i = 0; i < CDPR_DIAGNOSTICS_T_N_REJECT; i++) {
        msg->rejected[i] = i64(s->rejected[i]);
    }
    msg->last_command_seq = s->last_command_seq;
    msg->hold_entries = i64(s->hold_entries);
    msg->hold_periods = i64(s->hold_reads);
    msg->holding = (int8_t)(s->holding != 0);
    msg->plant_session = s->plant_session;
    msg->controller_session = s->controller_session;
    msg->controller_sessions = i64(s->controller_sessions);
    msg->other_plant_messages = i64(s->other_plant_messages);
    msg->other_plant_session = s->other_plant_session;
}
