/* SPDX-License-Identifier: BSD-3-Clause */
/// @file paper_model.h
/// The controller tests' model: the paper-50m preset (docs/robots.md) at 8 segments per cable,
/// built by lib/host's preset builder (the robot is the controller's own model here, not the
/// thing under test); optionally initialised into `model`. And their line trajectories.
#ifndef CDPR_TEST_PAPER_MODEL_H
#define CDPR_TEST_PAPER_MODEL_H

#include <stddef.h>
#include <string.h>

#include "cdpr/host/presets.h"
#include "cdpr/host/trajectory.h"
#include "cdpr/robot.h"
#include "unity.h"

static inline void test_paper_model_params(cdpr_robot_params_t *p, cdpr_robot_t *model)
{
    cdpr_preset_config_t c;
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_preset_get(CDPR_PRESET_PAPER_50M, &c));
    c.segments = 8;
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_preset_build(&c, NULL, p, NULL, NULL));
    if (model != NULL) {
        TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_robot_init(model, p, NULL));
    }
}

/* A straight-line trajectory from `from` to `to` (pose: position [m], Euler angles [rad])
 * over duration_s. */
static inline cdpr_traj_t test_line(const double from[6], const double to[6], double duration_s)
{
    cdpr_traj_t tr;
    memset(&tr, 0, sizeof tr);
    tr.type = CDPR_TRAJ_LINE;
    memcpy(tr.from, from, sizeof tr.from);
    memcpy(tr.to, to, sizeof tr.to);
    tr.duration_s = duration_s;
    return tr;
}

#endif /* CDPR_TEST_PAPER_MODEL_H */
