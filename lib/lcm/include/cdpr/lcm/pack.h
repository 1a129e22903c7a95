/* SPDX-License-Identifier: BSD-3-Clause */
/// @file pack.h
/// Packing the core's state into the LCM messages (lcmtypes/, package cdpr).
///
/// Inputs are the robot (cdpr_robot_t), its state vector `y` at time `t_s` and, for tensions,
/// the outputs of cdpr_robot_outputs at the same (t, y). Every function writes every field of
/// its message (the per-cable ones into a holder of wire.h, whose pointers it binds), so a
/// message can be reused from period to period without clearing. Values are converted from
/// cdpr_real_t (double or float) to the wire types exactly as C converts them.
///
/// Real-time: no allocation, no system call, no lcm_* call; reentrant. Work: O(cables) for the
/// state and tensions, O(total nodes) for the shape. Any cable count of the core (1..
/// CDPR_MAX_CABLES): the per-cable arrays are sized by n_cables on the wire.
#ifndef CDPR_LCM_PACK_H
#define CDPR_LCM_PACK_H

#include <stdint.h>

#include "cdpr/robot.h"
#include "lcmtypes/cdpr_cabin_state_t.h"
#include "cdpr/lcm/wire.h"
#include "lcmtypes/cdpr_diagnostics_t.h"

/// Plant time [s] -> utime_us [us], rounded to the nearest microsecond (ties away from zero).
int64_t cdpr_lcm_utime_us(double t_s);

/// Cabin state at (t_s, y): pose and velocities as cdpr_robot_cabin_motion sees them (the
/// prescription in prescribed mode), the paper's angles from cdpr_quat_to_euler, `seq`,
/// `command_seq` and `flags` (cdpr_cabin_state_t.FLAG_* bits) as given.
void cdpr_lcm_pack_cabin_state(cdpr_cabin_state_t *msg, const cdpr_robot_t *r, const cdpr_real_t *y,
                               double t_s, int64_t seq, int64_t command_seq, int32_t flags);

/// Cabin state from a motion `m` as given (e.g. a plant's measurement): the same fields as
/// cdpr_lcm_pack_cabin_state, every value copied exactly.
void cdpr_lcm_pack_cabin_motion(cdpr_cabin_state_t *msg, const cdpr_cabin_motion_t *m, double t_s,
                                int64_t seq, int64_t command_seq, int32_t flags);

/// Tensions and winch state at (t_s, y): `out` from cdpr_robot_outputs(r, t_s, y, out); total
/// unstretched lengths from cdpr_cable_total_length; payout rates are r->in.payout_m_per_s
/// (the rates applied in the step that led to y).
void cdpr_lcm_pack_tensions(cdpr_lcm_wire_tensions_t *w, const cdpr_robot_t *r,
                            const cdpr_real_t *y, const cdpr_robot_out_t *out, double t_s,
                            int64_t seq);

/// Node i (0..n_sent-1) of the shape message -> node index of a cable with `n_nodes` nodes:
/// the identity when n_nodes <= n_sent, else evenly spread indices round(i (n_nodes-1) /
/// (n_sent-1)), first and last included. Pure, O(1).
int cdpr_lcm_shape_node_index(int i, int n_sent, int n_nodes);

/// Node positions at (t_s, y): node 0 at the cabin attachment (cdpr_robot_attachment), the
/// free nodes from y, the last node at the pulley exit point; subsampled to
/// CDPR_CABLE_SHAPE_T_MAX_NODES per cable when a cable has more nodes (see the .lcm file);
/// the cables' nodes one after the other in node_{x,y,z}_m.
void cdpr_lcm_pack_shape(cdpr_lcm_wire_shape_t *w, const cdpr_robot_t *r, const cdpr_real_t *y,
                         double t_s, int64_t seq);

#endif /* CDPR_LCM_PACK_H */
