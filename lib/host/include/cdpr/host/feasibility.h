/* SPDX-License-Identifier: BSD-3-Clause */
/// @file feasibility.h
/// Is a scenario's trajectory feasible for its robot, before anything runs: the check the batch
/// runner (sim.h) and the real-time plant node (cdpr/rt/plant_node.h) make at load, so that an
/// infeasible scenario is refused with the time, pose and cable named instead of failing
/// mid-run.
#ifndef CDPR_HOST_FEASIBILITY_H
#define CDPR_HOST_FEASIBILITY_H

#include "cdpr/robot.h"
#include "cdpr/status.h"
#include "cdpr/host/scenario.h"

/// Longest unstretched cable length a run accepts at any checked instant [m]: the LCM bridge's
/// longest length command (cdpr_lcm_bridge_params_t.max_length_m, default 1000 m), so the
/// same scenario runs under cdpr-sim and cdpr-rt.
#define CDPR_FEASIBILITY_MAX_LENGTH_M 1000.0

/// The trajectory check cdpr_sim_run (and the plant node, cdpr-rt) makes before its first period:
/// every 0.1 s over `duration_s` and one period after it, the sag-aware IK (cdpr_statics_ik_wrench)
/// of the desired pose under the weight plus controller.inertial_ff times the d'Alembert load of
/// the desired motion (the load the tracker's feed-forward asks of it) must succeed, with every
/// unstretched length in [winch.min_length_m, CDPR_FEASIBILITY_MAX_LENGTH_M]. An infeasible sample
/// is reported with its time, pose and the cable whose straight-cable tension (6x6 chord statics of
/// the same load) is lowest when it would push: "cable 3 would need a tension of -2615 N". `model`:
/// storage for the statics model (caller-owned, overwritten). Work: at most 10 duration_s + 2 IK
/// solves (statics.h bounds); no allocation. Returns CDPR_OK, the IK's error (CDPR_E_INFEASIBLE,
/// ...), CDPR_E_OUT_OF_RANGE (a length) or the model's error, with err filled ("FILE:LINE:
/// trajectory.<type>: ...").
cdpr_status_t cdpr_feasibility_check_trajectory(const cdpr_scenario_t *sc, double duration_s,
                                                cdpr_robot_t *model, cdpr_scenario_error_t *err);

#endif /* CDPR_HOST_FEASIBILITY_H */
