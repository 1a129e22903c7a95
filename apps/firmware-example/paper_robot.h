/* SPDX-License-Identifier: BSD-3-Clause */
/// @file paper_robot.h
/// The paper's 50 m robot as firmware writes it (docs/robots.md, preset paper-50m): pulley exit
/// points [m] (radius 25 m, azimuths 0, 60, ..., 300 deg, height 30 m) and cabin attachments in
/// body axes [m] (radius 2 m at 25, 35, 145, 155, 265, 275 deg, 0.5 m below the origin). Shared
/// by the firmware example (main.c) and the consumer test (tests/consumer/state_bits.c), whose
/// state bits must agree. Include once, after defining N_CABLES (6).
#ifndef CDPR_FIRMWARE_EXAMPLE_PAPER_ROBOT_H
#define CDPR_FIRMWARE_EXAMPLE_PAPER_ROBOT_H

#include "cdpr/config.h"

static const cdpr_real_t EXIT_M[N_CABLES][3] = {{CDPR_R(25.0), CDPR_R(0.0), CDPR_R(30.0)},
                                                {CDPR_R(12.5), CDPR_R(21.6506), CDPR_R(30.0)},
                                                {CDPR_R(-12.5), CDPR_R(21.6506), CDPR_R(30.0)},
                                                {CDPR_R(-25.0), CDPR_R(0.0), CDPR_R(30.0)},
                                                {CDPR_R(-12.5), CDPR_R(-21.6506), CDPR_R(30.0)},
                                                {CDPR_R(12.5), CDPR_R(-21.6506), CDPR_R(30.0)}};
static const cdpr_real_t ATTACH_M[N_CABLES][3] = {
    {CDPR_R(1.81262), CDPR_R(0.84524), CDPR_R(-0.5)},
    {CDPR_R(1.6383), CDPR_R(1.14715), CDPR_R(-0.5)},
    {CDPR_R(-1.6383), CDPR_R(1.14715), CDPR_R(-0.5)},
    {CDPR_R(-1.81262), CDPR_R(0.84524), CDPR_R(-0.5)},
    {CDPR_R(-0.17431), CDPR_R(-1.99239), CDPR_R(-0.5)},
    {CDPR_R(0.17431), CDPR_R(-1.99239), CDPR_R(-0.5)}};

#endif /* CDPR_FIRMWARE_EXAMPLE_PAPER_ROBOT_H */
