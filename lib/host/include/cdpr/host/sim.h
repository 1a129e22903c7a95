/// @file sim.h
/// Batch simulation of a scenario: the plant (lumped-mass robot, RKF45, winches, node events)
/// closed by the tracking controller (tracker.h), with a CSV time series and a summary.
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
/// Outputs in DIR: timeseries.csv (columns in docs/scenarios.md) and summary.json.
/// Deterministic: the same scenario and binary give byte-identical timeseries.csv.
#ifndef CDPR_HOST_SIM_H
#define CDPR_HOST_SIM_H

#include <stdio.h>

#include "cdpr/host/csv.h"
#include "cdpr/host/scenario.h"

/// Run options (inputs).
typedef struct {
    const char *out_dir;     ///< directory for timeseries.csv and summary.json (NULL: none)
    double duration_s;       ///< > 0: overrides run.duration_s (tests, quick looks)
    int progress;            ///< 0 none, 1 one rewritten line (a tty), 2 a line per update
    FILE *progress_stream;   ///< progress goes here (e.g. stderr)
    double progress_after_s; ///< wall time before the first progress output [s]
} cdpr_sim_opts_t;

/// Run status.
typedef enum {
    CDPR_SIM_OK = 0,       ///< ran to the end, no warning
    CDPR_SIM_WARNINGS = 1, ///< ran to the end; substep limit, IK failure, capacity or min length
    CDPR_SIM_FAILED = 2    ///< stopped early (integrator error); outputs hold what was done
} cdpr_sim_status_t;

/// Summary of a run (outputs). Errors are |p - p_d| and the angle of q_d q^-1 over every
/// control period t_k, k = 0..N (t_0 after settling).
typedef struct {
    double rms_error_m;               ///< RMS position error [m]
    double max_error_m;               ///< largest position error [m]
    double final_error_m;             ///< position error at the end [m]
    double initial_error_m;           ///< position error at t = 0 (after settling) [m]
    double rms_error_second_half_m;   ///< RMS position error over t >= duration/2 [m]
    double rms_error_rad;             ///< RMS attitude error [rad]
    double max_error_rad;             ///< largest attitude error [rad]
    double final_error_rad;           ///< attitude error at the end [rad]
    double max_tension_N;             ///< largest end tension, any cable, either end [N]
    double min_tension_N;             ///< smallest end tension [N]
    double max_payout_m_per_s;        ///< largest |payout rate| applied [m/s]
    unsigned long node_insertions;    ///< all cables
    unsigned long node_removals;      ///< all cables
    unsigned long capacity_hits;      ///< node-event calls that wanted a node at capacity
    unsigned long substep_limit_hits; ///< periods with CDPR_WARN_SUBSTEP_LIMIT
    unsigned long ik_failures;        ///< periods whose feed-forward IK failed (held)
    unsigned long min_length_periods; ///< winch-periods held at the minimum length
    unsigned long steps_accepted;     ///< RKF45 accepted steps (run only)
    unsigned long steps_rejected;     ///< RKF45 rejected trials
    unsigned long rhs_evals;          ///< RHS calls (run only)
    long settle_steps;                ///< accepted steps of the initial settling
    int nodes_min;                    ///< fewest segments of any cable during the run
    int nodes_max;                    ///< most segments of any cable during the run
    long periods;                     ///< control periods run
    double sim_time_s;                ///< simulated time reached [s]
    double wall_time_s;               ///< wall-clock time of the run incl. settling [s]
    double settle_wall_time_s;        ///< of which settling [s]
    cdpr_sim_status_t status;         ///< see cdpr_sim_status_t
    char message[256];                ///< what failed or warned, "" if nothing
} cdpr_sim_summary_t;

/// One period's values for the recorder (inputs; arrays of the robot's cable count).
typedef struct {
    double t_s;                      ///< time t_k [s]
    const cdpr_traj_sample_t *des;   ///< desired state at t_k
    const cdpr_tracker_meas_t *meas; ///< measured cabin motion and lengths at t_k
    const double *tension_cabin_N;   ///< cabin-end tensions [N]
    const double *tension_winch_N;   ///< winch-end tensions [N]
    const double *l_ff_m;            ///< feed-forward lengths [m]
    const double *payout_m_per_s;    ///< payout rates [m/s]
    const int *segments;             ///< active segments per cable
} cdpr_sim_row_t;

/// Recorder: timeseries.csv (every output period and the last) and the summary's error,
/// tension and node statistics. Used by cdpr_sim_run and by apps/cdpr-tracker, so a run over
/// LCM writes the same files. Fields are internal.
typedef struct {
    cdpr_csv_t csv;
    int csv_open;
    int n_cables;
    long every;
    double duration_s;
    double sum2_pos, sum2_rot, sum2_pos_late;
    long n, n_late;
    cdpr_sim_summary_t *sum;
} cdpr_sim_rec_t;

/// Start recording into `sum` (zeroed by the caller) and, when out_dir is not NULL,
/// out_dir/timeseries.csv (the directory is created). Returns 0, or 3 with `err` naming the
/// file.
int cdpr_sim_rec_open(cdpr_sim_rec_t *rec, const cdpr_scenario_t *sc, const char *out_dir,
                      int n_cables, double duration_s, cdpr_sim_summary_t *sum,
                      cdpr_scenario_error_t *err);

/// Record period k (t_k = row->t_s); `last` forces a CSV row.
void cdpr_sim_rec_period(cdpr_sim_rec_t *rec, long k, int last, const cdpr_sim_row_t *row);

/// Finish the statistics (RMS values) and close the CSV. Returns 0, or -1 on a write error.
int cdpr_sim_rec_close(cdpr_sim_rec_t *rec);

/// Defaults: no output directory, scenario duration, no progress, 2 s before progress.
void cdpr_sim_opts_default(cdpr_sim_opts_t *o);

/// Run a checked scenario. Returns 0 when the run reached its end (status OK or WARNINGS),
/// 1 when it stopped early (status FAILED; the outputs and `sum` cover what was done),
/// 2 when the scenario cannot start (`err` names the key: infeasible initial pose or
/// trajectory, settling failure), 3 on an output error (`err` names the file).
int cdpr_sim_run(const cdpr_scenario_t *sc, const cdpr_sim_opts_t *o, cdpr_sim_summary_t *sum,
                 cdpr_scenario_error_t *err);

/// Write summary.json for `sum` of scenario `sc`. Returns 0 or -1.
int cdpr_sim_write_summary(const char *path, const cdpr_scenario_t *sc,
                           const cdpr_sim_summary_t *sum);

/// Read a summary.json written by cdpr_sim_write_summary (JSON is YAML, so libcyaml reads it;
/// keys it does not know are ignored). Fills the numeric fields and the status; returns 0, or
/// -1 with `err` naming the file and key.
int cdpr_sim_read_summary(const char *path, cdpr_sim_summary_t *sum, cdpr_scenario_error_t *err);

/// Run `gnuplot -c script dir kind title` (no shell) and wait for it: the figures of a run
/// (scripts/plot_sim.gp: kind circle, line or hold). Warnings go to stderr prefixed `prog`.
/// Returns 0 when gnuplot succeeded, else -1.
int cdpr_sim_plot(const char *prog, const char *script, const char *dir, const char *kind,
                  const char *title);

/// Name of a status as written in summary.json ("ok", "warnings", "failed").
const char *cdpr_sim_status_name(cdpr_sim_status_t st);

#endif /* CDPR_HOST_SIM_H */
