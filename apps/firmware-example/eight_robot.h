/* SPDX-License-Identifier: BSD-3-Clause */
/// @file eight_robot.h
/// The eight-cable robot robots/eight-50m.yaml as firmware writes it (docs/robots.md set C):
/// pulley exit points [m] (two per tower of four towers on a 25 m circle, 30 m high, each pair
/// 0.4 rad apart) and cabin attachments in body axes [m] (a 1.5 m circle, pairs 1 rad apart,
/// alternately 0.5 m below and above the origin), and its tension distribution [N]. The values
/// are the robot file's, rounded to 0.1 mm. Include once, after defining N_CABLES (8).
#ifndef CDPR_FIRMWARE_EXAMPLE_EIGHT_ROBOT_H
#define CDPR_FIRMWARE_EXAMPLE_EIGHT_ROBOT_H

#include "cdpr/config.h"

static const cdpr_real_t EXIT_M[N_CABLES][3] = {{CDPR_R(20.8373), CDPR_R(13.8133), CDPR_R(30.0)},
                                                {CDPR_R(13.8133), CDPR_R(20.8373), CDPR_R(30.0)},
                                                {CDPR_R(-13.8133), CDPR_R(20.8373), CDPR_R(30.0)},
                                                {CDPR_R(-20.8373), CDPR_R(13.8133), CDPR_R(30.0)},
                                                {CDPR_R(-20.8373), CDPR_R(-13.8133), CDPR_R(30.0)},
                                                {CDPR_R(-13.8133), CDPR_R(-20.8373), CDPR_R(30.0)},
                                                {CDPR_R(13.8133), CDPR_R(-20.8373), CDPR_R(30.0)},
                                                {CDPR_R(20.8373), CDPR_R(-13.8133), CDPR_R(30.0)}};
static const cdpr_real_t ATTACH_M[N_CABLES][3] = {{CDPR_R(0.4223), CDPR_R(1.4393), CDPR_R(-0.5)},
                                                  {CDPR_R(1.4393), CDPR_R(0.4223), CDPR_R(0.5)},
                                                  {CDPR_R(-1.4393), CDPR_R(0.4223), CDPR_R(-0.5)},
                                                  {CDPR_R(-0.4223), CDPR_R(1.4393), CDPR_R(0.5)},
                                                  {CDPR_R(-0.4223), CDPR_R(-1.4393), CDPR_R(-0.5)},
                                                  {CDPR_R(-1.4393), CDPR_R(-0.4223), CDPR_R(0.5)},
                                                  {CDPR_R(1.4393), CDPR_R(-0.4223), CDPR_R(-0.5)},
                                                  {CDPR_R(0.4223), CDPR_R(-1.4393), CDPR_R(0.5)}};
/* The tension distribution (robots/eight-50m.yaml): lowest tension along every cable >= 25 N,
 * highest <= 500 N, the lowest tensions closest to the mid-range 262.5 N. */
static const cdpr_real_t TENSION_MIN_N = CDPR_R(25.0);
static const cdpr_real_t TENSION_MAX_N = CDPR_R(500.0);
static const cdpr_real_t TENSION_REF_N = CDPR_R(262.5);

#endif /* CDPR_FIRMWARE_EXAMPLE_EIGHT_ROBOT_H */
