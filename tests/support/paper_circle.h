/* SPDX-License-Identifier: BSD-3-Clause */
/// @file paper_circle.h
/// The paper's Sim. 1 circle (docs/validation.md §8, simulation 1) written out for the host
/// tests, independently of scenarios/paper-circle.yaml: centre (0, -2, 9.135) m, radius 2 m,
/// 2 m/s, starting at 90 degrees (the point (0, 0, 9.135) m), counter-clockwise, no ramp.
#ifndef CDPR_TEST_PAPER_CIRCLE_H
#define CDPR_TEST_PAPER_CIRCLE_H

#include <string.h>

#include "cdpr/host/trajectory.h"

static inline cdpr_traj_t test_paper_circle(void)
{
    cdpr_traj_t tr;
    memset(&tr, 0, sizeof tr);
    tr.type = CDPR_TRAJ_CIRCLE;
    tr.centre_m[1] = -2.0;
    tr.centre_m[2] = 9.135;
    tr.radius_m = 2.0;
    tr.speed_m_per_s = 2.0;
    tr.start_angle_rad = 1.5707963267948966; /* pi / 2 */
    tr.direction = 1.0;
    return tr;
}

#endif /* CDPR_TEST_PAPER_CIRCLE_H */
