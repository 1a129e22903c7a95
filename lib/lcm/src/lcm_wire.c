/* SPDX-License-Identifier: BSD-3-Clause */
/// @file lcm_wire.c
/// The per-cable messages with storage (wire.h).
///
/// The decoders read the fields in the order of the .lcm files with lcm_coretypes.h's
/// primitives, as the generated decoders do; tests/lcm/test_lcm_wire.c checks them against the
/// generated decoders on encoded, truncated, extended and corrupted messages.

#include "cdpr/lcm/wire.h"

#include <string.h>

#include <lcm/lcm_coretypes.h>

/* A read cursor over one received message: the first failure sticks. */
typedef struct {
    const void *buf;
    int len;
    int pos;
    int bad;
} cursor_t;

static void advance(cursor_t *c, int n)
{
    if (n < 0) {
        c->bad = 1;
    } else {
        c->pos += n;
    }
}

static void get_i8(cursor_t *c, int8_t *p, int n)
{
    if (c->bad == 0) {
        advance(c, __int8_t_decode_array(c->buf, c->pos, c->len - c->pos, p, n));
    }
}

static void get_i32(cursor_t *c, int32_t *p, int n)
{
    if (c->bad == 0) {
        advance(c, __int32_t_decode_array(c->buf, c->pos, c->len - c->pos, p, n));
    }
}

static void get_i64(cursor_t *c, int64_t *p, int n)
{
    if (c->bad == 0) {
        advance(c, __int64_t_decode_array(c->buf, c->pos, c->len - c->pos, p, n));
    }
}

static void get_f64(cursor_t *c, double *p, int n)
{
    if (c->bad == 0) {
        advance(c, __double_decode_array(c->buf, c->pos, c->len - c->pos, p, n));
    }
}

/* The fingerprint: CDPR_LCM_WIRE_OK when the first 8 bytes are `hash`. */
static cdpr_lcm_wire_t open_cursor(cursor_t *c, const void *buf, int len, int64_t hash)
{
    int64_t h = 0;

    c->buf = buf;
    c->len = len;
    c->pos = 0;
    c->bad = (buf == NULL || len < 8) ? 1 : 0;
    get_i64(c, &h, 1);
    return (c->bad == 0 && h == hash) ? CDPR_LCM_WIRE_OK : CDPR_LCM_WIRE_WRONG_TYPE;
}

/* After the cable count: malformed when negative; over capacity when the rest of the message
 * is exactly n_cables x bytes_per_cable (well-formed) but more than the storage holds. */
static cdpr_lcm_wire_t check_count(const cursor_t *c, int n_cables, int bytes_per_cable)
{
    if (c->bad != 0 || n_cables < 0) {
        return CDPR_LCM_WIRE_MALFORMED;
    }
    if (n_cables > CDPR_MAX_CABLES) {
        return (c->len - c->pos == n_cables * bytes_per_cable) ? CDPR_LCM_WIRE_OVER_CAPACITY
                                                               : CDPR_LCM_WIRE_MALFORMED;
    }
    return CDPR_LCM_WIRE_OK;
}

void cdpr_lcm_wire_command_init(cdpr_lcm_wire_command_t *w)
{
    memset(w, 0, sizeof *w);
    w->msg.value = w->value;
}

void cdpr_lcm_wire_tensions_init(cdpr_lcm_wire_tensions_t *w)
{
    memset(w, 0, sizeof *w);
    w->msg.tension_cabin_N = w->tension_cabin_N;
    w->msg.tension_winch_N = w->tension_winch_N;
    w->msg.length_m = w->length_m;
    w->msg.payout_m_per_s = w->payout_m_per_s;
    w->msg.n_segments = w->n_segments;
}

void cdpr_lcm_wire_shape_init(cdpr_lcm_wire_shape_t *w)
{
    memset(w, 0, sizeof *w);
    w->msg.n_segments = w->n_segments;
    w->msg.n_nodes = w->n_nodes;
    w->msg.node_x_m = w->node_x_m;
    w->msg.node_y_m = w->node_y_m;
    w->msg.node_z_m = w->node_z_m;
}

void cdpr_lcm_wire_command_copy(cdpr_lcm_wire_command_t *dst, const cdpr_lcm_wire_command_t *src)
{
    if (dst != src) {
        memcpy(dst, src, sizeof *dst);
        dst->msg.value = dst->value;
    }
}

void cdpr_lcm_wire_tensions_copy(cdpr_lcm_wire_tensions_t *dst, const cdpr_lcm_wire_tensions_t *src)
{
    if (dst != src) {
        memcpy(dst, src, sizeof *dst);
        dst->msg.tension_cabin_N = dst->tension_cabin_N;
        dst->msg.tension_winch_N = dst->tension_winch_N;
        dst->msg.length_m = dst->length_m;
        dst->msg.payout_m_per_s = dst->payout_m_per_s;
        dst->msg.n_segments = dst->n_segments;
    }
}

static int cables_fit(int n_cables)
{
    return (n_cables >= 0 && n_cables <= CDPR_MAX_CABLES) ? 1 : 0;
}

int cdpr_lcm_wire_command_ok(const cdpr_lcm_wire_command_t *w)
{
    return (w != NULL && w->msg.value == w->value && cables_fit(w->msg.n_cables) != 0) ? 1 : 0;
}

int cdpr_lcm_wire_tensions_ok(const cdpr_lcm_wire_tensions_t *w)
{
    return (w != NULL && w->msg.tension_cabin_N == w->tension_cabin_N &&
            w->msg.tension_winch_N == w->tension_winch_N && w->msg.length_m == w->length_m &&
            w->msg.payout_m_per_s == w->payout_m_per_s && w->msg.n_segments == w->n_segments &&
            cables_fit(w->msg.n_cables) != 0)
               ? 1
               : 0;
}

int cdpr_lcm_wire_shape_ok(const cdpr_lcm_wire_shape_t *w)
{
    return (w != NULL && w->msg.n_segments == w->n_segments && w->msg.n_nodes == w->n_nodes &&
            w->msg.node_x_m == w->node_x_m && w->msg.node_y_m == w->node_y_m &&
            w->msg.node_z_m == w->node_z_m && cables_fit(w->msg.n_cables) != 0 &&
            w->msg.n_points >= 0 && w->msg.n_points <= CDPR_LCM_SHAPE_MAX_POINTS)
               ? 1
               : 0;
}

int cdpr_lcm_wire_command_encode(const cdpr_lcm_wire_command_t *w, void *buf, int cap)
{
    return (cdpr_lcm_wire_command_ok(w) != 0 && buf != NULL)
               ? cdpr_winch_command_t_encode(buf, 0, cap, &w->msg)
               : -1;
}

int cdpr_lcm_wire_tensions_encode(const cdpr_lcm_wire_tensions_t *w, void *buf, int cap)
{
    return (cdpr_lcm_wire_tensions_ok(w) != 0 && buf != NULL)
               ? cdpr_cable_tensions_t_encode(buf, 0, cap, &w->msg)
               : -1;
}

int cdpr_lcm_wire_shape_encode(const cdpr_lcm_wire_shape_t *w, void *buf, int cap)
{
    return (cdpr_lcm_wire_shape_ok(w) != 0 && buf != NULL)
               ? cdpr_cable_shape_t_encode(buf, 0, cap, &w->msg)
               : -1;
}

cdpr_lcm_wire_t cdpr_lcm_wire_command_decode(cdpr_lcm_wire_command_t *w, const void *buf, int len)
{
    cdpr_lcm_wire_command_t d;
    cursor_t c;
    cdpr_lcm_wire_t r = open_cursor(&c, buf, len, __cdpr_winch_command_t_get_hash());

    if (r != CDPR_LCM_WIRE_OK) {
        return r;
    }
    cdpr_lcm_wire_command_init(&d);
    get_i64(&c, &d.msg.utime_us, 1);
    get_i64(&c, &d.msg.seq, 1);
    get_i64(&c, &d.msg.state_seq, 1);
    get_i64(&c, &d.msg.controller_session, 1);
    get_i64(&c, &d.msg.plant_session, 1);
    get_i8(&c, &d.msg.mode, 1);
    get_i8(&c, &d.msg.n_cables, 1);
    r = check_count(&c, d.msg.n_cables, 8);
    if (r != CDPR_LCM_WIRE_OK) {
        return r;
    }
    get_f64(&c, d.value, (int)(uint8_t)d.msg.n_cables); // 0..CDPR_MAX_CABLES: checked
    if (c.bad != 0 || c.pos != len) {
        return CDPR_LCM_WIRE_MALFORMED;
    }
    cdpr_lcm_wire_command_copy(w, &d);
    return CDPR_LCM_WIRE_OK;
}

cdpr_lcm_wire_t cdpr_lcm_wire_tensions_decode(cdpr_lcm_wire_tensions_t *w, const void *buf, int len)
{
    cdpr_lcm_wire_tensions_t d;
    cursor_t c;
    cdpr_lcm_wire_t r = open_cursor(&c, buf, len, __cdpr_cable_tensions_t_get_hash());
    int n;

    if (r != CDPR_LCM_WIRE_OK) {
        return r;
    }
    cdpr_lcm_wire_tensions_init(&d);
    get_i64(&c, &d.msg.utime_us, 1);
    get_i64(&c, &d.msg.seq, 1);
    get_i64(&c, &d.msg.plant_session, 1);
    get_i8(&c, &d.msg.n_cables, 1);
    r = check_count(&c, d.msg.n_cables, 4 * 8 + 4);
    if (r != CDPR_LCM_WIRE_OK) {
        return r;
    }
    n = (int)(uint8_t)d.msg.n_cables; // 0..CDPR_MAX_CABLES: checked
    get_f64(&c, d.tension_cabin_N, n);
    get_f64(&c, d.tension_winch_N, n);
    get_f64(&c, d.length_m, n);
    get_f64(&c, d.payout_m_per_s, n);
    get_i32(&c, d.n_segments, n);
    if (c.bad != 0 || c.pos != len) {
        return CDPR_LCM_WIRE_MALFORMED;
    }
    cdpr_lcm_wire_tensions_copy(w, &d);
    return CDPR_LCM_WIRE_OK;
}
