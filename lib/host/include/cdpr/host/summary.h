/* SPDX-License-Identifier: BSD-3-Clause */
/// @file summary.h
/// The summary of a tracking run: what cdpr-sim, cdpr-tracker and cdpr-rt --with-tracker
/// compute (record.h fills the statistics), write to summary.json, read back and print.
///
/// summary.json: one JSON object, keys in docs/scenarios.md; numbers printed with %.17g
/// (round-trip exact). A value the writer cannot know (a count of the plant's integrator when
/// the plant ran in another process) is null, never 0: CDPR_SUMMARY_UNKNOWN in a count, a negative
/// settle_steps, a non-finite double, "" in a provenance string. Host library; the reader
/// allocates through libcyaml and frees it.
#ifndef CDPR_HOST_SUMMARY_H
#define CDPR_HOST_SUMMARY_H

#include <limits.h>
#include <stdio.h>

#include "cdpr/plant.h"
#include "cdpr/status.h"
#include "cdpr/host/scenario.h"
#include "cdpr/host/sha256.h"

/// An unknown count (unsigned long fields of cdpr_summary_t): written as null.
#define CDPR_SUMMARY_UNKNOWN ULONG_MAX

/// Where a run's outputs come from (summary.json and the comment lines of timeseries.csv).
/// "" is unknown (written as null).
typedef struct {
    char version[32];                          ///< CDPR_VERSION_STRING of the writer's build
    char git_describe[64];                     ///< CDPR_GIT_DESCRIBE of the writer's build
    char build_type[32];                       ///< CMAKE_BUILD_TYPE of the host library
    char scenario_sha256[CDPR_SHA256_HEX + 1]; ///< SHA-256 of the scenario file's bytes (hex)
    char robot_sha256[CDPR_SHA256_HEX + 1];    ///< SHA-256 of the robot file's bytes (hex; ""
                                               ///< for a robot the scenario writes itself)
    char integrator[32];                       ///< the plant's scheme ("rkf45")
} cdpr_summary_provenance_t;

/// Provenance of a run of the scenario file `scenario_path` whose robot is the robot file
/// `robot_path` (NULL or "": the scenario describes the robot itself) with plant parameters
/// `pp` (NULL: integrator unknown): both files' bytes are hashed now ("" when one cannot be
/// read); version, git description and build type of this build.
void cdpr_summary_provenance_init(cdpr_summary_provenance_t *prov, const char *scenario_path,
                                  const char *robot_path, const cdpr_plant_params_t *pp);

/// Laps of a periodic trajectory the summary keeps statistics of (the first ones).
#define CDPR_SUMMARY_MAX_LAPS 100

/// Run status (summary.json "status": the name of cdpr_summary_status_name).
typedef enum {
    CDPR_SUMMARY_OK = 0,          ///< "ok": ran to the end, no warning
    CDPR_SUMMARY_WARNINGS = 1,    ///< "warnings": ran to the end; substep limit, IK failure, ...
    CDPR_SUMMARY_FAILED = 2,      ///< "failed": stopped early (integrator error); outputs hold what
                                  ///< was done
    CDPR_SUMMARY_INTERRUPTED = 3, ///< "interrupted": stopped by a signal (SIGINT, SIGTERM, SIGHUP);
                                  ///< outputs hold what was done
    CDPR_SUMMARY_IO_ERROR = 4     ///< "io_error": writing timeseries.csv failed; it holds the whole
                                  ///< rows written before, `message` says why
} cdpr_summary_status_t;

/// The real-time plant's figures in a summary: cdpr-rt's own telemetry (its in-process
/// tracker), or the plant's newest `diagnostics_t` received by a controller over LCM. Not known
/// in a batch run (cdpr-sim), nor when no diagnostics came.
typedef struct {
    int known;                         ///< 1: the figures below are the plant's
    long seq;                          ///< plant state they are as of
    long periods;                      ///< control periods run by then
    unsigned long deadline_misses;     ///< free-running: periods that ended after the next start
    unsigned long startup_misses;      ///< misses within the start-up allowance
    unsigned long misses_late_wakeup;  ///< after it: the work fit, the wake-up was late
    unsigned long misses_preempted;    ///< > 1 period of wall time, < 1 period of CPU time
    unsigned long misses_long_compute; ///< > 1 period of the thread's CPU time
    unsigned long misses_in_row_max;   ///< most misses in a row after the start-up
    int overrun_stop;                  ///< 1: the overrun policy stopped the plant
    double compute_us_p99;             ///< a period's work, wall time: p99 [us]
    double compute_us_max;             ///< ... max [us]
    double cpu_us_p99;                 ///< the same in the periodic thread's CPU time: p99 [us]
    double cpu_us_max;                 ///< ... max [us]
    double wake_late_us_max;           ///< latest wake-up after the start-up [us]
} cdpr_summary_rt_t;

/// Summary of a run (outputs). Errors are |p - p_d| and the angle of q_d q^-1 over every
/// control period t_k, k = 0..N (t_0 after settling). Unknown values: see the file comment.
typedef struct {
    double rms_error_m;                  ///< RMS position error [m]
    double max_error_m;                  ///< largest position error [m]
    double final_error_m;                ///< position error at the end [m]
    double initial_error_m;              ///< position error at t = 0 (after settling) [m]
    double rms_error_second_half_m;      ///< RMS position error over t >= duration/2 [m]
    double rms_error_rad;                ///< RMS attitude error [rad]
    double max_error_rad;                ///< largest attitude error [rad]
    double final_error_rad;              ///< attitude error at the end [rad]
    double max_tension_N;                ///< largest end tension, any cable, either end [N]
    double min_tension_N;                ///< smallest end tension [N]
    double max_payout_m_per_s;           ///< largest |payout rate| applied [m/s]
    unsigned long node_insertions;       ///< all cables (over LCM: from the segment counts seen)
    unsigned long node_removals;         ///< all cables (over LCM: from the segment counts seen)
    unsigned long capacity_hits;         ///< node-event calls that wanted a node at capacity
    unsigned long substep_limit_hits;    ///< periods with CDPR_WARN_SUBSTEP_LIMIT
    unsigned long ik_failures;           ///< periods whose feed-forward IK failed (held)
    unsigned long min_length_periods;    ///< winch-periods held at the minimum length
    unsigned long steps_accepted;        ///< RKF45 accepted steps (run only)
    unsigned long steps_rejected;        ///< RKF45 rejected trials
    unsigned long rhs_evals;             ///< RHS calls (run only)
    unsigned long max_rhs_per_period;    ///< most RHS calls of one period (= the mean in the
                                         ///< fixed mode)
    int substeps;                        ///< fixed mode: substeps per period (0: another scheme)
    double max_err_norm;                 ///< fixed mode: largest error norm of a substep (NaN:
                                         ///< unknown or another scheme; > 1: the adaptive
                                         ///< control would have rejected that step)
    unsigned long err_above_one_periods; ///< fixed mode: periods with an error norm above 1
    long settle_steps;                   ///< accepted steps of the initial settling (< 0: unknown)
    int nodes_min;                       ///< fewest segments of any cable during the run
    int nodes_max;                       ///< most segments of any cable during the run
    long periods;                        ///< control periods run
    double sim_time_s;                   ///< simulated time reached [s]
    double wall_time_s;                  ///< wall-clock time of the run incl. settling [s]
    double settle_wall_time_s;           ///< of which settling [s] (NaN: unknown)
    double rms_error_after_transfer_m;   ///< RMS position error over t >= controller.transfer_s
                                         ///< (the whole run without a transfer) [m]
    int n_cables;                        ///< cables of the per-cable counts below (0: unknown)
    unsigned long rate_limited_periods[CDPR_MAX_CABLES]; ///< recorded periods whose payout rate
                                                         ///< of cable j the winch limited: it
                                                         ///< changed by a_max T from the period
                                                         ///< before (recorded too) or sat at
                                                         ///< +-u_max
    unsigned long slack_periods[CDPR_MAX_CABLES];        ///< recorded periods with cable j's cabin-
                                                         ///< or winch-end tension <= 0 (the plant)
    unsigned long slack_demand_periods[CDPR_MAX_CABLES]; ///< periods whose feed-forward
                                                         ///< demanded tension <= 0 of cable j
    double cable_max_tension_N[CDPR_MAX_CABLES]; ///< largest tension of cable j, either end [N]
    double cable_min_tension_N[CDPR_MAX_CABLES]; ///< smallest tension of cable j, either end [N]
    int first_slack_demand_cable;       ///< 1-based cable of the first slack demand (0: none)
    double first_slack_demand_t_s;      ///< its time [s] (NaN: none)
    double first_slack_demand_N;        ///< its straight-cable tension [N] (NaN: none)
    unsigned long learning_updates;     ///< laps learned by the controller (tracker.h step 8)
    unsigned long learning_saturations; ///< learned knot values clamped to the limit
    int n_laps;                         ///< complete laps of a periodic trajectory recorded
                                        ///< (cdpr_traj_lap; at most CDPR_SUMMARY_MAX_LAPS; 0: none)
    double lap_rms_m[CDPR_SUMMARY_MAX_LAPS];   ///< RMS position error of each complete lap [m]
    double lap_max_m[CDPR_SUMMARY_MAX_LAPS];   ///< largest position error of each lap [m]
    double lap_rms_rad[CDPR_SUMMARY_MAX_LAPS]; ///< RMS attitude error of each lap [rad]
    cdpr_summary_rt_t rt;                      ///< the real-time plant's figures (rt.known)
    cdpr_summary_status_t status;              ///< see cdpr_summary_status_t
    char message[256];                         ///< what failed or warned, "" if nothing
    cdpr_summary_provenance_t prov;            ///< where the outputs come from
} cdpr_summary_t;

/// Name of a status as written in summary.json ("ok", "warnings", "failed", "interrupted",
/// "io_error"; "failed" for a value not in the enum).
const char *cdpr_summary_status_name(cdpr_summary_status_t st);

/// Mark what only the plant knows as unknown (null in summary.json): its limit counts
/// (capacity_hits, substep_limit_hits, min_length_periods), the integrator's work and error
/// (steps_accepted, steps_rejected, rhs_evals, max_rhs_per_period, max_err_norm,
/// err_above_one_periods) and the settling (settle_steps, settle_wall_time_s). What a
/// controller over LCM writes before it fills in what the plant's diagnostics tell. O(1).
void cdpr_summary_plant_unknown(cdpr_summary_t *sum);

/// Write summary.json for `sum` of scenario `sc` to `path`. Returns CDPR_OK, or CDPR_E_IO
/// (cannot create, or a write or the close failed; errno set: the first failure's). A regular
/// file that could not be written whole is emptied (no torn JSON is left behind).
cdpr_status_t cdpr_summary_write(const char *path, const cdpr_scenario_t *sc,
                                 const cdpr_summary_t *sum);

/// Write `path` (laps.csv: columns lap, rms_m, max_m, rms_rad; one row per complete lap) when
/// the summary has laps (sum->n_laps > 0; else nothing is written). Rows whole (csv.h).
/// Returns CDPR_OK, or CDPR_E_IO with errno set.
cdpr_status_t cdpr_summary_write_laps(const char *path, const cdpr_summary_t *sum);

/// Read a summary.json written by cdpr_summary_write (JSON is YAML, so libcyaml reads it;
/// keys it does not know are ignored). Fills the numeric fields, the status (a name this
/// library does not know reads as CDPR_SUMMARY_FAILED) and the
/// provenance (optional keys: files written before they existed have none); a null reads as
/// unknown (CDPR_SUMMARY_UNKNOWN, settle_steps -1, NaN, ""). Returns CDPR_OK, or with `err` naming
/// the file (and libcyaml's reason): CDPR_E_IO (cannot open), CDPR_E_PARSE (malformed, a key
/// missing or of the wrong type, empty).
cdpr_status_t cdpr_summary_read(const char *path, cdpr_summary_t *sum, cdpr_scenario_error_t *err);

/// Print the end-of-run block of `s` to `f` (cdpr-sim's): "TITLE: status - message", then
/// tracking error, tensions, node events, integrator (when its counts are unknown or zero --
/// the plant ran elsewhere -- the controller's IK failures instead) and time.
void cdpr_summary_print(FILE *f, const char *title, const cdpr_summary_t *s);

#endif /* CDPR_HOST_SUMMARY_H */
