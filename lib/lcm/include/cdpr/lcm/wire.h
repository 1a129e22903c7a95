/* SPDX-License-Identifier: BSD-3-Clause */
/// @file wire.h
/// The per-cable messages (winch_command_t, cable_tensions_t, cable_shape_t) with storage.
///
/// Their arrays are sized by n_cables on the wire (and n_points for the shape's nodes), so the
/// generated C structs hold pointers. A `cdpr_lcm_wire_*_t` is such a struct (`msg`) together
/// with fixed arrays for up to CDPR_MAX_CABLES cables that `msg`'s pointers point into: fill
/// `msg` (the packers in pack.h do), encode it with the generated encoder or the checked
/// `*_encode` below, hand `&w.msg` to code written for the generated type. Initialise one
/// with `*_init` (binds the pointers); copy one with `*_copy`, never by assignment (the copy
/// would point into the source).
///
/// Decoding into a holder (`*_decode`) reads one whole message with LCM's own primitives
/// (lcm_coretypes.h) into its arrays: no allocation (the generated decoder allocates the
/// arrays), the cable count checked against the storage before a value is read. The result
/// names why a message was refused: not this type, not exactly one well-formed message, or
/// well-formed with more cables than this build holds (a plant of another robot).
///
/// Real-time: init, copy, encode and decode make no allocation, no system call, no lcm_* call;
/// O(message size).
#ifndef CDPR_LCM_WIRE_H
#define CDPR_LCM_WIRE_H

#include <stdint.h>

#include "cdpr/config.h"
#include "lcmtypes/cdpr_cable_shape_t.h"
#include "lcmtypes/cdpr_cable_tensions_t.h"
#include "lcmtypes/cdpr_winch_command_t.h"

/// Nodes a shape holder stores: CDPR_CABLE_SHAPE_T_MAX_NODES for each of CDPR_MAX_CABLES.
#define CDPR_LCM_SHAPE_MAX_POINTS (CDPR_MAX_CABLES * CDPR_CABLE_SHAPE_T_MAX_NODES)

/// What a decode found.
typedef enum {
    CDPR_LCM_WIRE_OK = 0,           ///< one well-formed message, every byte used
    CDPR_LCM_WIRE_WRONG_TYPE = 1,   ///< fewer than 8 bytes, or the fingerprint is another type's
    CDPR_LCM_WIRE_MALFORMED = 2,    ///< truncated, trailing bytes, or a negative count
    CDPR_LCM_WIRE_OVER_CAPACITY = 3 ///< well-formed, but n_cables > CDPR_MAX_CABLES
} cdpr_lcm_wire_t;

/// A winch command with room for CDPR_MAX_CABLES values.
typedef struct {
    cdpr_winch_command_t msg;      ///< msg.value points at value
    double value[CDPR_MAX_CABLES]; ///< rate [m/s] or length [m] per cable
} cdpr_lcm_wire_command_t;

/// Tensions and winch state with room for CDPR_MAX_CABLES cables.
typedef struct {
    cdpr_cable_tensions_t msg; ///< its arrays point at the ones below
    double tension_cabin_N[CDPR_MAX_CABLES];
    double tension_winch_N[CDPR_MAX_CABLES];
    double length_m[CDPR_MAX_CABLES];
    double payout_m_per_s[CDPR_MAX_CABLES];
    int32_t n_segments[CDPR_MAX_CABLES];
} cdpr_lcm_wire_tensions_t;

/// Cable shapes with room for CDPR_MAX_CABLES cables of CDPR_CABLE_SHAPE_T_MAX_NODES nodes.
typedef struct {
    cdpr_cable_shape_t msg; ///< its arrays point at the ones below
    int32_t n_segments[CDPR_MAX_CABLES];
    int16_t n_nodes[CDPR_MAX_CABLES];
    float node_x_m[CDPR_LCM_SHAPE_MAX_POINTS];
    float node_y_m[CDPR_LCM_SHAPE_MAX_POINTS];
    float node_z_m[CDPR_LCM_SHAPE_MAX_POINTS];
} cdpr_lcm_wire_shape_t;

/// Zero every field (n_cables 0, n_points 0) and bind msg's pointers to the storage.
void cdpr_lcm_wire_command_init(cdpr_lcm_wire_command_t *w);
void cdpr_lcm_wire_tensions_init(cdpr_lcm_wire_tensions_t *w);
void cdpr_lcm_wire_shape_init(cdpr_lcm_wire_shape_t *w);

/// Copy `src` into `dst` (both initialised); dst's pointers stay bound to dst.
void cdpr_lcm_wire_command_copy(cdpr_lcm_wire_command_t *dst, const cdpr_lcm_wire_command_t *src);
void cdpr_lcm_wire_tensions_copy(cdpr_lcm_wire_tensions_t *dst,
                                 const cdpr_lcm_wire_tensions_t *src);

/// 1 when w's pointers point at its own storage and its counts fit it (0 <= n_cables <=
/// CDPR_MAX_CABLES; for the shape also 0 <= n_points <= CDPR_LCM_SHAPE_MAX_POINTS), else 0.
int cdpr_lcm_wire_command_ok(const cdpr_lcm_wire_command_t *w);
int cdpr_lcm_wire_tensions_ok(const cdpr_lcm_wire_tensions_t *w);
int cdpr_lcm_wire_shape_ok(const cdpr_lcm_wire_shape_t *w);

/// Encode w->msg into buf[0..cap) with the generated encoder after the check above. Returns
/// the bytes written, or -1 (w not ok, or cap too small).
int cdpr_lcm_wire_command_encode(const cdpr_lcm_wire_command_t *w, void *buf, int cap);
int cdpr_lcm_wire_tensions_encode(const cdpr_lcm_wire_tensions_t *w, void *buf, int cap);
int cdpr_lcm_wire_shape_encode(const cdpr_lcm_wire_shape_t *w, void *buf, int cap);

/// Decode buf[0..len) as exactly one message into w (initialised). On CDPR_LCM_WIRE_OK every
/// field of w->msg is the sender's; otherwise w is unchanged.
cdpr_lcm_wire_t cdpr_lcm_wire_command_decode(cdpr_lcm_wire_command_t *w, const void *buf, int len);
cdpr_lcm_wire_t cdpr_lcm_wire_tensions_decode(cdpr_lcm_wire_tensions_t *w, const void *buf,
                                              int len);

#endif /* CDPR_LCM_WIRE_H */
