/* SPDX-License-Identifier: BSD-3-Clause */
/// @file lcm_pack.c
/// Core state -> LCM messages (lcm_pack.h).

#include "cdpr/lcm/pack.h"

#include <math.h>
#include <string.h>

#include "cdpr/cable.h"
#include "cdpr/vec3.h"
#include "cdpr/lcm/wire.h"
#include "lcm_check.h"

// n_cables is an int8_t on the wire.
CDPR_LCM_STATIC_ASSERT(CDPR_MAX_CABLES <= 127, cables_fit_int8);

int64_t cdpr_lcm_utime_us(double t_s)
{
    return (int64_t)llround(t_s * 1e6);
}

void cdpr_lcm_pack_cabin_motion(cdpr_cabin_state_t *msg, const cdpr_cabin_motion_t *m, double t_s,
                                int64_t seq, int64_t command_seq, int32_t flags)
{
    cdpr_real_t a;
    cdpr_real_t b;
    cdpr_real_t g;

    cdpr_quat_to_euler(m->q, &a, &b, &g);
    msg->utime_us = cdpr_lcm_utime_us(t_s);
    msg->seq = seq;
    msg->command_seq = command_seq;
    msg->position_m[0] = (double)m->p_m.x;
    msg->position_m[1] = (double)m->p_m.y;
    msg->position_m[2] = (double)m->p_m.z;
    msg->orientation[0] = (double)m->q.w;
    msg->orientation[1] = (double)m->q.x;
    msg->orientation[2] = (double)m->q.y;
    msg->orientation[3] = (double)m->q.z;
    msg->euler_rad[0] = (double)a;
    msg->euler_rad[1] = (double)b;
    msg->euler_rad[2] = (double)g;
    msg->velocity_m_per_s[0] = (double)m->v_m_per_s.x;
    msg->velocity_m_per_s[1] = (double)m->v_m_per_s.y;
    msg->velocity_m_per_s[2] = (double)m->v_m_per_s.z;
    msg->angular_velocity_rad_per_s[0] = (double)m->w_rad_per_s.x;
    msg->angular_velocity_rad_per_s[1] = (double)m->w_rad_per_s.y;
    msg->angular_velocity_rad_per_s[2] = (double)m->w_rad_per_s.z;
    msg->flags = flags;
}

void cdpr_lcm_pack_cabin_state(cdpr_cabin_state_t *msg, const cdpr_robot_t *r, const cdpr_real_t *y,
                               double t_s, int64_t seq, int64_t command_seq, int32_t flags)
{
    cdpr_cabin_motion_t m;

    cdpr_robot_cabin_motion(r, (cdpr_real_t)t_s, y, &m);
    cdpr_lcm_pack_cabin_motion(msg, &m, t_s, seq, command_seq, flags);
}

void cdpr_lcm_pack_tensions(cdpr_lcm_wire_tensions_t *w, const cdpr_robot_t *r,
                            const cdpr_real_t *y, const cdpr_robot_out_t *out, double t_s,
                            int64_t seq)
{
    const int n = r->p.n_cables; // 1..CDPR_MAX_CABLES (cdpr_robot_init)
    int j;

    cdpr_lcm_wire_tensions_init(w);
    w->msg.utime_us = cdpr_lcm_utime_us(t_s);
    w->msg.seq = seq;
    w->msg.n_cables = (int8_t)n;
    for (j = 0; j < n; j++) {
        w->tension_cabin_N[j] = (double)out->tension_cabin_N[j];
        w->tension_winch_N[j] = (double)out->tension_winch_N[j];
        w->length_m[j] = (double)cdpr_cable_total_length(&r->cable[j], y + r->offset[j]);
        w->payout_m_per_s[j] = (double)r->in.payout_m_per_s[j];
        w->n_segments[j] = (int32_t)r->cable[j].n;
    }
}

int cdpr_lcm_shape_node_index(int i, int n_sent, int n_nodes)
{
    long num;
    long den;

    if (n_nodes <= n_sent || n_sent < 2) {
        return i;
    }
    // round(i (n_nodes - 1) / (n_sent - 1)) in integers: exact, monotonic, ends included.
    num = (long)i * (long)(n_nodes - 1);
    den = (long)(n_sent - 1);
    return (int)((2 * num + den) / (2 * den));
}

static void put_node(cdpr_lcm_wire_shape_t *w, int k, cdpr_vec3_t p)
{
    w->node_x_m[k] = (float)p.x;
    w->node_y_m[k] = (float)p.y;
    w->node_z_m[k] = (float)p.z;
}

void cdpr_lcm_pack_shape(cdpr_lcm_wire_shape_t *w, const cdpr_robot_t *r, const cdpr_real_t *y,
                         double t_s, int64_t seq)
{
    cdpr_cabin_motion_t m;
    int first = 0; // index of the cable's first sent node in node_*_m
    int j;

    cdpr_robot_cabin_motion(r, (cdpr_real_t)t_s, y, &m);
    cdpr_lcm_wire_shape_init(w);
    w->msg.utime_us = cdpr_lcm_utime_us(t_s);
    w->msg.seq = seq;
    w->msg.n_cables = (int8_t)r->p.n_cables;
    for (j = 0; j < r->p.n_cables; j++) {
        const int n = r->cable[j].n; // segments; nodes 0..n
        const int n_nodes = n + 1;
        const int n_sent =
            n_nodes < CDPR_CABLE_SHAPE_T_MAX_NODES ? n_nodes : CDPR_CABLE_SHAPE_T_MAX_NODES;
        const cdpr_real_t *pos = y + r->offset[j] + 1; // free nodes 1..n-1 (cable.h layout)
        cdpr_vec3_t attach;
        cdpr_vec3_t attach_vel;
        int i;

        cdpr_robot_attachment(r, j, &m, &attach, &attach_vel);
        w->n_segments[j] = (int32_t)n;
        w->n_nodes[j] = (int16_t)n_sent;
        for (i = 0; i < n_sent; i++) {
            const int k = cdpr_lcm_shape_node_index(i, n_sent, n_nodes);
            if (k == 0) {
                put_node(w, first + i, attach);
            } else if (k == n) {
                put_node(w, first + i, r->p.cables[j].exit_point_m);
            } else {
                const cdpr_real_t *p = pos + 3 * (k - 1);
                put_node(w, first + i, cdpr_v3(p[0], p[1], p[2]));
            }
        }
        first += n_sent;
    }
    w->msg.n_points = (int32_t)first;
}
