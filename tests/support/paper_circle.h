/* SPDX-License-Identifier: BSD-3-Clause */
/// @file paper_circle.h
/// The paper's Sim. 1 circle (docs/validation.md §8, simulation 1) written out for the host
/// tests, independently of scenarios/paper-circle.yaml: centre (0, -2, 9.135) m, radius 2 m,
/// 2 m/s, starting at 90 degrees (the point (0, 0, 9.135) m), counter-clockwise, no ramp; and
/// the straight lines of the controller tests. Core and lib/control only (target tests use it).
#ifndef CDPR_TEST_PAPER_CIRCLE_H
#define CDPR_TEST_PAPER_CIRCLE_H

#include <string.h>

#include "cdpr/control/trajectory.h"

static inline cdpr_traj_t test_paper_circle(void)
{
    cdpr_traj_t tr;
    memset(&tr, 0, sizeof tr);
    tr.type = CDPR_TRAJ_CIRCLE;
    tr.centre_m[1] = CDPR_R(-2.0);
    tr.centre_m[2] = CDPR_R(9.135);
    tr.radius_m = CDPR_R(2.0);
    tr.speed_m_per_s = CDPR_R(2.0);
    tr.start_angle_rad = CDPR_R(1.5707963267948966); /* pi / 2 */
    tr.direction = CDPR_R(1.0);
    return tr;
}

/* A straight-line trajectory from `from` to `to` (pose: position [m], Euler angles [rad])
 * over duration_s. */
static inline cdpr_traj_t test_line(const double from[6], const double to[6], double duration_s)
{
    cdpr_traj_t tr;
    memset(&tr, 0, sizeof tr);
    tr.type = CDPR_TRAJ_LINE;
    for (int i = 0; i < 6; ++i) {
        tr.from[i] = (cdpr_real_t)from[i];
        tr.to[i] = (cdpr_real_t)to[i];
    }
    tr.duration_s = (cdpr_real_t)duration_s;
    return tr;
}

#endif /* CDPR_TEST_PAPER_CIRCLE_H */
