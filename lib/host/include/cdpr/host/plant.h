/* SPDX-License-Identifier: BSD-3-Clause */
/// @file plant.h
/// The plant of a scenario: builds the core's cdpr_plant_t (cdpr/plant.h) from a checked
/// scenario, with errors that name the scenario key. The plant itself -- robot, integrator,
/// winches, one control period per call with rollback -- is the core's; this module only
/// translates: preset and overrides -> robot and winch parameters, initial pose, tolerances,
/// the run's period (run.period_s) and work bound (integrator.max_trials, max_attempts).
///
/// Host library; no allocation; not real-time (the initialisation settles the robot).
#ifndef CDPR_HOST_PLANT_H
#define CDPR_HOST_PLANT_H

#include "cdpr/plant.h"
#include "cdpr/host/scenario.h"

/// Most settling steps a host plant takes before it refuses to start [accepted steps]: 10x the
/// most a shipped scenario needs (19 892, example-rig-circle), a tenth of the core's default
/// (2e6), so a robot that settles too slowly is refused in seconds, not minutes.
#define CDPR_HOST_SETTLE_MAX_STEPS 200000L

/// Fill the core plant parameters of scenario `sc` (checked). O(cables); no allocation.
/// Errors (`err` names the key): the robot's values rejected by the core (CDPR_E_NOT_FINITE,
/// CDPR_E_NOT_POSITIVE, CDPR_E_OUT_OF_RANGE, CDPR_E_GEOMETRY, ...: key "robot").
cdpr_status_t cdpr_host_plant_params(const cdpr_scenario_t *sc, cdpr_plant_params_t *pp,
                                     cdpr_scenario_error_t *err);

/// Build and settle the plant of scenario `sc` (cdpr_host_plant_params, cdpr_plant_init).
/// Not real-time: the settling takes up to seconds. `wall_s` (may be NULL) receives the wall
/// time of the initialisation [s]. Errors (`err` names the key and says why): those of
/// cdpr_host_plant_params; an initial pose that is not statically reachable
/// (CDPR_E_INFEASIBLE, CDPR_E_NO_CONVERGENCE, ...: key initial.pose, initial.offset or the
/// trajectory's start); a settling that does not converge (CDPR_E_NO_CONVERGENCE with steps
/// and residual); parameters of the period, winches or integrator the core rejects.
cdpr_status_t cdpr_host_plant_init(cdpr_plant_t *p, const cdpr_scenario_t *sc, double *wall_s,
                                   cdpr_scenario_error_t *err);

/// Step 1 of cdpr_host_plant_init only (cdpr_plant_init_model): what a controller in another
/// process needs to build the same model (`p->params`, `p->initial`). Errors as above.
cdpr_status_t cdpr_host_plant_model(cdpr_plant_t *p, const cdpr_scenario_t *sc,
                                    cdpr_scenario_error_t *err);

/// The controller's own model of scenario `sc`: the robot scaled by sc->controller_model
/// (cdpr_rig_scale; the scenario's controller.model), built as cdpr_host_plant_model builds
/// the plant's (the initial pose's IK lengths), its parameters into *model -- what
/// cdpr_tracker_init takes. With factors 1 it equals cdpr_host_plant_model's p->params. The
/// plant never sees the factors. Host only: allocates a plant for the build and frees it.
/// Errors as cdpr_host_plant_model (the scaled robot's), CDPR_E_CAPACITY without memory.
cdpr_status_t cdpr_host_controller_params(const cdpr_scenario_t *sc, cdpr_robot_params_t *model,
                                          cdpr_scenario_error_t *err);

/// The world positions of cable j's nodes (0: the cabin attachment, 1..n-1 the free nodes, n:
/// the exit point; n the cable's segments now) at the plant's current state, into xyz[3 k + i]
/// for k = 0..n. Returns the node count n + 1, or -1 (nothing written) for a cable outside the
/// robot or `cap` < n + 1 nodes. O(n); no allocation.
int cdpr_host_cable_nodes(const cdpr_plant_t *p, int j, double *xyz, int cap);

#endif /* CDPR_HOST_PLANT_H */
