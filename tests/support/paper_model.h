/* SPDX-License-Identifier: BSD-3-Clause */
/// @file paper_model.h
/// The controller tests' model: the paper-50m preset (docs/robots.md) at 8 segments per cable,
/// built by lib/host's preset builder (the robot is the controller's own model here, not the
/// thing under test); optionally initialised into `model`. Their line trajectories:
/// paper_circle.h.
#ifndef CDPR_TEST_PAPER_MODEL_H
#define CDPR_TEST_PAPER_MODEL_H

#include <stddef.h>
#include <string.h>

#include "cdpr/host/presets.h"
#include "cdpr/control/trajectory.h"
#include "paper_circle.h"
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

#endif /* CDPR_TEST_PAPER_MODEL_H */
