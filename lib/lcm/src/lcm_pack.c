/* SPDX-License-Identifier: BSD-3-Clause */
/// @file lcm_pack.c
/// Core state -> LCM messages (lcm_pack.h).

#include "cdpr/lcm/pack.h"

#include <math.h>
#include <string.h>

#include "cdpr/lcm/command.h"
#include "cdpr/cable.h"
#include "cdpr/vec3.h"
#include "lcm_check.h"
#include "lcmtypes/cdpr_winch_command_t.h"

// The wire format's capacities. A plant with more cables than the messages carry is refused
// before anything is packed (CDPR_LCM_MAX_CABLES, command.h); the packers clamp to it anyway.
#define ARRAY_LEN(a) (sizeof(a) / sizeof((a)[0]))
CDPR_LCM_STATIC_ASSERT(ARRAY_LEN(((cdpr_winch_command_t *)0)->value) ==
                           CDPR_WINCH_COMMAND_T_MAX_CABLES,
                       command_capacity);
CDPR_LCM_STATIC_ASSERT(ARRAY_LEN(((cdpr_cable_tensions_t *)0)->tension_cabin_N) ==
                           CDPR_CABLE_TENSIONS_T_MAX_CABLES,
                       tensions_capacity);
CDPR_LCM_STATIC_ASSERT(CDPR_CABLE_TENSIONS_T_MAX_CABLES == CDPR_WINCH_COMMAND_T_MAX_CABLES,
                       tensions_command_cables);
CDPR_LCM_STATIC_ASSERT(ARRAY_LEN(((cdpr_cable_shape_t *)0)->node_m) ==
                           CDPR_CABLE_SHAPE_T_MAX_CABLES,
                       shape_cables);
CDPR_LCM_STATIC_ASSERT(ARRAY_LEN(((cdpr_cable_shape_t *)0)->node_m[0]) ==
                           CDPR_CABLE_SHAPE_T_MAX_NODES,
                       shape_nodes);

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

void cdpr_lcm_pack_tensions(cdpr_cable_tensions_t *msg, const cdpr_robot_t *r, const cdpr_real_t *y,
                            const cdpr_robot_out_t *out, double t_s, int64_t seq)
{
    const int n = (r->p.n_cables < CDPR_LCM_MAX_CABLES) ? r->p.n_cables : CDPR_LCM_MAX_CABLES;
    int j;

    memset(msg, 0, sizeof *msg);
    msg->utime_us = cdpr_lcm_utime_us(t_s);
    msg->seq = seq;
    msg->n_cables = (int8_t)n;
    for (j = 0; j < n; j++) {
        msg->tension_cabin_N[j] = (double)out->tension_cabin_N[j];
        msg->tension_winch_N[j] = (double)out->tension_winch_N[j];
        msg->length_m[j] = (double)cdpr_cable_total_length(&r->cable[j], y + r->offset[j]);
        msg->payout_m_per_s[j] = (double)r->in.payout_m_per_s[j];
        msg->n_segments[j] = (int32_t)r->cable[j].n;
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

static void put_node(cdpr_cable_shape_t *msg, int j, int i, cdpr_vec3_t p)
{
    msg->node_m[j][i][0] = (float)p.x;
    msg->node_m[j][i][1] = (float)p.y;
    msg->node_m[j][i][2] = (float)p.z;
}

void cdpr_lcm_pack_shape(cdpr_cable_shape_t *msg, const cdpr_robot_t *r, const cdpr_real_t *y,
                         double t_s, int64_t seq)
{
    cdpr_cabin_motion_t m;
    int j;

    cdpr_robot_cabin_motion(r, (cdpr_real_t)t_s, y, &m);
    memset(msg, 0, sizeof *msg);
    msg->utime_us = cdpr_lcm_utime_us(t_s);
    msg->seq = seq;
    const int nc = (r->p.n_cables < CDPR_LCM_MAX_CABLES) ? r->p.n_cables : CDPR_LCM_MAX_CABLES;
    msg->n_cables = (int8_t)nc;
    for (j = 0; j < nc; j++) {
        const int n = r->cable[j].n; // segments; nodes 0..n
        const int n_nodes = n + 1;
        const int n_sent =
            n_nodes < CDPR_CABLE_SHAPE_T_MAX_NODES ? n_nodes : CDPR_CABLE_SHAPE_T_MAX_NODES;
        const cdpr_real_t *pos = y + r->offset[j] + 1; // free nodes 1..n-1 (cable.h layout)
        cdpr_vec3_t attach;
        cdpr_vec3_t attach_vel;
        int i;

        cdpr_robot_attachment(r, j, &m, &attach, &attach_vel);
        msg->n_segments[j] = (int32_t)n;
        msg->n_nodes[j] = (int16_t)n_sent;
        for (i = 0; i < n_sent; i++) {
            const int k = cdpr_lcm_shape_node_index(i, n_sent, n_nodes);
            if (k == 0) {
                put_node(msg, j, i, attach);
            } else if (k == n) {
                put_node(msg, j, i, r->p.cables[j].exit_point_m);
            } else {
                const cdpr_real_t *p = pos + 3 * (k - 1);
                put_node(msg, j, i, cdpr_v3(p[0], p[1], p[2]));
            }
        }
    }
}
