/* SPDX-License-Identifier: BSD-3-Clause */
/// @file api_sizeof.c
/// Prints `name bytes` for each caller-owned object of the core, one per line, at the
/// capacities it is compiled with (tests/docs/CMakeLists.txt: one build per column of the
/// table; the headers only). ctest api_sizeof (cmake/CheckApiSizeof.cmake)
/// compares the lines with the sizeof table of docs/api.md.
#include <stdio.h>

#include "cdpr/cabin.h"
#include "cdpr/cable.h"
#include "cdpr/catenary.h"
#include "cdpr/plant.h"
#include "cdpr/rkf45.h"
#include "cdpr/robot.h"
#include "cdpr/robot_w.h"
#include "cdpr/ros34pw2.h"
#include "cdpr/settle.h"
#include "cdpr/statics.h"
#include "cdpr/winch.h"

#define ROW(name, size) printf("%s %lu\n", name, (unsigned long)(size))

int main(void)
{
    ROW("cdpr_plant_t", sizeof(cdpr_plant_t));
    ROW("cdpr_plant_params_t", sizeof(cdpr_plant_params_t));
    ROW("cdpr_plant_meas_t", sizeof(cdpr_plant_meas_t));
    ROW("cdpr_robot_t", sizeof(cdpr_robot_t));
    ROW("cdpr_robot_params_t", sizeof(cdpr_robot_params_t));
    ROW("cdpr_robot_out_t", sizeof(cdpr_robot_out_t));
    ROW("cdpr_cable_t", sizeof(cdpr_cable_t));
    ROW("cdpr_cabin_t", sizeof(cdpr_cabin_t));
    ROW("cdpr_rkf45_t", sizeof(cdpr_rkf45_t));
    ROW("cdpr_ros_t", sizeof(cdpr_ros_t));
    ROW("cdpr_robot_w_t", sizeof(cdpr_robot_w_t));
    ROW("cdpr_winch_t", sizeof(cdpr_winch_t));
    ROW("cdpr_node_stats_t", sizeof(cdpr_node_stats_t));
    ROW("cdpr_statics_result_t", sizeof(cdpr_statics_result_t));
    ROW("cdpr_settle_t", sizeof(cdpr_settle_t));
    ROW("cdpr_catenary_solver_t", sizeof(cdpr_catenary_solver_t));
    ROW("state[CDPR_ROBOT_STATE_MAX]", sizeof(cdpr_real_t) * CDPR_ROBOT_STATE_MAX);
    ROW("rkf45_work[CDPR_RKF45_WORK_PER_DIM*CDPR_ROBOT_STATE_MAX]",
        sizeof(cdpr_real_t) * CDPR_RKF45_WORK_PER_DIM * CDPR_ROBOT_STATE_MAX);
    return 0;
}
