/* SPDX-License-Identifier: BSD-3-Clause */
/// @file sim.h
/// Batch simulation of a scenario: the plant (lumped-mass robot, its integrator -- RKF45,
/// ROS34PW2 or the fixed-cost mode, integrator.method -- winches, node events) closed by the
/// tracking controller (tracker.h), with a CSV time series and a summary.
///
/// Initialisation: sag-aware IK at the initial pose (start pose + initial offset) gives the
/// unstretched lengths; the robot is built with them, its nodes placed on the catenaries
/// (cdpr_statics_place_catenary) and settled to the discrete model's own static equilibrium
/// (cdpr_settle_robot), so it starts at rest. The initial pose and the desired trajectory
/// (sampled every 0.1 s over the run) must be statically feasible, else the scenario is
/// rejected naming the key.
///
/// Each control period Δt_c, at t_k = k Δt_c:
///   measure (cabin motion, total unstretched lengths) -> controller -> payout-rate commands
///   -> cdpr_winch_update (speed/acceleration limits, minimum length) -> row of outputs
///   -> cdpr_rkf45_advance over exactly Δt_c with at most max_trials trials
///   -> cdpr_robot_normalize -> cdpr_winch_node_events (resize the integrator, refresh the
///   per-component tolerances when the layout changed).
///
/// Outputs in DIR: timeseries.csv (columns in docs/scenarios.md; record.h) and summary.json
/// (summary.h). Deterministic: the same scenario and binary give byte-identical timeseries.csv.
/// The run's period, work bound, duration and output rate are the scenario's (run.period_s,
/// integrator.max_trials/max_attempts, run.duration_s, run.output_rate_hz; command-line
/// overrides are applied to the scenario first: cdpr_scenario_override).
#ifndef CDPR_HOST_SIM_H
#define CDPR_HOST_SIM_H

#include <stdio.h>

#include "cdpr/status.h"
#include "cdpr/host/record.h"
#include "cdpr/host/scenario.h"
#include "cdpr/host/summary.h"

/// Run options (inputs).
typedef struct {
    const char *out_dir;      ///< directory for timeseries.csv and summary.json (NULL: none)
    int progress;             ///< 0 none, 1 one rewritten line (a tty), 2 a line per update
    FILE *progress_stream;    ///< progress goes here (e.g. stderr)
    double progress_after_s;  ///< wall time before the first progress output [s]
    const volatile int *stop; ///< optional: non-zero ends the run at the next period (a signal)
    /// Cable shapes: DIR/shapes.csv with every node of every cable at this rate [Hz] (0: none;
    /// else the control rate divided by a whole number). Rows t_s, cable (1-based), node (0 the
    /// cabin attachment .. n the exit point), x_m, y_m, z_m, h_m (horizontal distance from the
    /// cable's exit point), sag_m (height of the straight chord exit point -> attachment above
    /// the node, at its horizontal distance); a blank line after each cable's nodes.
    double shapes_rate_hz;
    /// The controller's pre-compensation (NULL: the scenario's controller.precompensation file,
    /// if any, read and checked: correction.h). The caller's, for the run.
    const cdpr_tracker_correction_t *correction;
    /// Called once per period with the row of t_k (before it is recorded) and the controller's
    /// command of the period that starts there (NULL for the last row, which has none); NULL:
    /// not called. What a caller needs that the CSV would hold, without a file.
    void (*on_period)(void *ctx, long k, const cdpr_record_row_t *row,
                      const cdpr_tracker_cmd_t *cmd);
    void *on_period_ctx; ///< on_period's first argument
} cdpr_sim_opts_t;

/// Defaults: no output directory, no progress, 2 s before progress, no stop flag.
void cdpr_sim_opts_default(cdpr_sim_opts_t *o);

/// Run a scenario (checked here unless cdpr_scenario_is_checked) for its run.duration_s. Returns
///  - CDPR_OK when the run reached its end (sum->status ok or warnings);
///  - CDPR_E_INTERRUPTED when *o->stop ended it early (sum->status interrupted; the CSV holds
///    whole rows up to the last period run, summary.json is written);
///  - CDPR_E_OUT_OF_RANGE with `err` naming --shapes when o->shapes_rate_hz is not the control
///    rate divided by a whole number (nothing run);
///  - CDPR_E_IO when writing timeseries.csv (or shapes.csv) failed during the run: the run stops
///  there
///    (sum->status io_error; the CSV keeps the whole rows written before, summary.json is still
///    tried: it is another file and may fit), `err` says "DIR/timeseries.csv: write failed:
///    strerror"; also when summary.json cannot be written or memory runs out;
///  - the integrator's error (CDPR_E_SUBSTEP_LIMIT, CDPR_E_STATE_NOT_FINITE,
///    CDPR_E_STEP_TOO_SMALL, CDPR_E_RHS) when it stopped early (sum->status failed; the
///    outputs and `sum` cover what was done);
///  - the error of the scenario when it cannot start (`err` names the key): its check's
///    (CDPR_E_OUT_OF_RANGE, ...), an infeasible initial pose or trajectory
///    (CDPR_E_INFEASIBLE, CDPR_E_NO_CONVERGENCE), a settling failure, the controller's;
/// `err` is written only when the run could not start or on an output error (when both the CSV
/// and summary.json failed it names both).
cdpr_status_t cdpr_sim_run(const cdpr_scenario_t *sc, const cdpr_sim_opts_t *o, cdpr_summary_t *sum,
                           cdpr_scenario_error_t *err);

#endif /* CDPR_HOST_SIM_H */
