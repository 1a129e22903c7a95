/* SPDX-License-Identifier: BSD-3-Clause */
/// @file eight_plant.h
/// The eight-cable robot of docs/robots.md set C (robots/eight-50m.yaml) written out for the
/// core tests, as paper_plant.h does for set A: four towers at 45, 135, 225, 315 deg on a 25 m
/// circle, two exit points each 0.4 rad apart at 30 m; attachments on a 1.5 m circle, each pair
/// 1 rad apart, alternately 0.5 m above and below the centre of mass; the 50 m model's cabin and
/// rope (set A: paper_plant.h), `segments` per cable, the robot's tension distribution 25-500 N
/// (reference 262.5 N) when `with_dist` != 0, the cabin at (0, 0, 13 m) level.
#ifndef CDPR_TEST_EIGHT_PLANT_H
#define CDPR_TEST_EIGHT_PLANT_H

#include <math.h>

#include "cdpr/plant.h"
#include "paper_plant.h"

#if CDPR_MAX_CABLES >= 8
/// Exit point and body attachment of cable j (0..7) of set C [m].
static inline void test_eight_geometry(int j, cdpr_vec3_t *exit_m, cdpr_vec3_t *attach_m)
{
    const int tower = j / 2;
    const double side = (j % 2 != 0) ? 1.0 : -1.0;
    const double th = (double)tower * CDPR_PI / 2.0 + CDPR_PI / 4.0 + 0.2 * side;
    const double az = (double)tower * CDPR_PI / 2.0 + CDPR_PI / 4.0 - 0.5 * side;
    *exit_m = cdpr_v3((cdpr_real_t)(25.0 * cos(th)), (cdpr_real_t)(25.0 * sin(th)), CDPR_R(30.0));
    *attach_m = cdpr_v3((cdpr_real_t)(1.5 * cos(az)), (cdpr_real_t)(1.5 * sin(az)),
                        (cdpr_real_t)(0.5 * side));
}

static inline void test_eight_plant_params(cdpr_plant_params_t *pp, int segments, int with_dist)
{
    test_paper_plant_params(pp, segments);
    pp->robot.n_cables = 8;
    for (int j = 0; j < 8; ++j) {
        pp->robot.cables[j] = pp->robot.cables[0];
        test_eight_geometry(j, &pp->robot.cables[j].exit_point_m,
                            &pp->robot.cables[j].attach_body_m);
        pp->winch[j] = pp->winch[0];
    }
    pp->robot.has_tension_dist = (with_dist != 0) ? 1 : 0;
    pp->robot.tension_min_N = CDPR_R(25.0);
    pp->robot.tension_max_N = CDPR_R(500.0);
    pp->robot.tension_ref_N = CDPR_R(262.5);
    static const cdpr_real_t pose[6] = {CDPR_R(0.0), CDPR_R(0.0), CDPR_R(13.0),
                                        CDPR_R(0.0), CDPR_R(0.0), CDPR_R(0.0)};
    pp->initial = cdpr_cabin_motion_at_pose(pose);
}
#endif

#endif /* CDPR_TEST_EIGHT_PLANT_H */
