/* SPDX-License-Identifier: BSD-3-Clause */
/// @file correction.h
/// Length pre-compensation files (issue 22 item 1; docs/scenarios.md "Pre-compensation"): the
/// correction c_j(t) of the tracker's step 4c (cdpr_tracker_correction_t) computed offline for
/// one scenario (cdpr-precomp), written to a YAML file and named by a scenario's
/// controller.precompensation key.
///
/// A correction belongs to the trajectory, the robot the controller knows and the closed loop
/// it was iterated against: the file holds the SHA-256 of each, of canonical text of the
/// scenario's values (every number as %.9g, so a value that only differs in its last bits, as
/// 2.2e6 / 1.1, hashes the same):
///  - trajectory_sha256: the trajectory section (its type and every parameter);
///  - robot_sha256: the controller's model, the robot scaled by controller.model (geometry,
///    ropes, winches, cabin, gravity, steady wind, tension distribution; not its name, the
///    nominal pose or the segments' count): a plant that differs from what the controller
///    knows (a scenario that varies the robot with controller.model undoing it) keeps the
///    correction, as a real robot would;
///  - controller_sha256: the controller's gains (every controller key but model and
///    precompensation);
/// and the control period it was made for. Loading refuses a file whose hashes or period differ
/// from the scenario's, naming which, and a correction that demands a slack cable: at every
/// knot of its support (t_s + i h within the run), the controller's model held statically at
/// the trajectory's pose with the lengths of its static inverse kinematics plus c_j(t)
/// (cdpr_statics_forward) has a cable-end tension below the file's floor_N (the time, cable
/// and tension named). A catenary always holds some tension (its weight): a cable paid out by
/// far too much still shows tens of newtons, so "slack" is the floor the correction was made
/// for (cdpr-precomp --floor, 20 N by default), not 0.
///
/// Host only. The file is read once (cdpr_yaml_load: strict numbers, at most 1 MiB); the
/// coefficients live in the caller's cdpr_host_correction_t (no allocation survives a call).
#ifndef CDPR_HOST_CORRECTION_H
#define CDPR_HOST_CORRECTION_H

#include "cdpr/status.h"
#include "cdpr/control/tracker.h"
#include "cdpr/host/scenario.h"
#include "cdpr/host/sha256.h"

/// Most coefficients per cable a file may hold (204.8 s at h = 0.1 s).
#define CDPR_CORRECTION_MAX_COEF 2048

/// The format line of a correction file (its `format:` key).
#define CDPR_CORRECTION_FORMAT "cdpr-correction-1"

/// How the correction was made (the file's `report:`; NaN / 0 where unknown).
typedef struct {
    int iterations;       ///< model runs of the iteration (the first: no correction)
    double rms_before_m;  ///< RMS position error without correction, after 2 s [m]
    double rms_after_m;   ///< with the correction [m]
    double max_after_m;   ///< largest position error with it, after 2 s [m]
    double max_after_rad; ///< largest attitude error with it, after 2 s [rad]
    double min_tension_N; ///< smallest cable-end tension of the run with it [N]
    /// The cost's varied plants (cdpr-precomp --robust-mass / --robust-ea): the plant's cabin
    /// mass and EA times 1 ± these, the controller's model nominal (0: none)
    double robust_mass;
    double robust_ea;
    double varied_rms_after_m;   ///< worst RMS position error over those plants, after 2 s [m]
    double varied_max_after_m;   ///< worst largest position error, after 2 s [m]
    double varied_max_after_rad; ///< worst largest attitude error, after 2 s [rad]
    double varied_min_tension_N; ///< smallest cable-end tension over their runs [N]
} cdpr_correction_report_t;

/// The tension floor of a new correction (cdpr_correction_init) [N]: 20 N, the issue's.
#define CDPR_CORRECTION_FLOOR_N 20.0

/// A correction and its storage (caller-owned; c.coef_m points into coef_m).
typedef struct {
    cdpr_tracker_correction_t c;
    cdpr_real_t coef_m[CDPR_MAX_CABLES * CDPR_CORRECTION_MAX_COEF];
    char trajectory_sha256[CDPR_SHA256_HEX + 1];
    char robot_sha256[CDPR_SHA256_HEX + 1];
    char controller_sha256[CDPR_SHA256_HEX + 1];
    double floor_N; ///< the smallest cable-end tension it may demand (the file's floor_N) [N]
    cdpr_correction_report_t report;
} cdpr_host_correction_t;

/// The three hashes of scenario `sc` (see above). Host only: builds nothing, O(cables).
void cdpr_correction_hashes(const cdpr_scenario_t *sc, char traj[CDPR_SHA256_HEX + 1],
                            char robot[CDPR_SHA256_HEX + 1], char controller[CDPR_SHA256_HEX + 1]);

/// An empty correction for `sc`: its hashes and period, n_cables, n_coef coefficients (1 ..
/// CDPR_CORRECTION_MAX_COEF) from start_s at spacing_s, all 0. CDPR_OK or CDPR_E_OUT_OF_RANGE.
cdpr_status_t cdpr_correction_init(cdpr_host_correction_t *hc, const cdpr_scenario_t *sc,
                                   int n_coef, double start_s, double spacing_s);

/// Write `hc` to `path` (YAML; written to PATH.tmp, flushed to disk and renamed, so a reader
/// never sees half a file and a full disk leaves the old file). `note`: a comment line (may be
/// NULL). CDPR_OK or CDPR_E_IO (`err`: the file and strerror).
cdpr_status_t cdpr_correction_write(const char *path, const cdpr_host_correction_t *hc,
                                    const char *note, cdpr_scenario_error_t *err);

/// Read `path` into `hc` (no check against a scenario). Errors: CDPR_E_IO (cannot open),
/// CDPR_E_PARSE (not a correction file: syntax, unknown or missing keys, a number that is not
/// one, the format line), CDPR_E_OUT_OF_RANGE (cables of different lengths, more than
/// CDPR_MAX_CABLES cables or CDPR_CORRECTION_MAX_COEF coefficients, a spacing or period <= 0,
/// a coefficient NaN/Inf or above 10 m); `err` says "FILE:LINE: KEY: what".
cdpr_status_t cdpr_correction_read(const char *path, cdpr_host_correction_t *hc,
                                   cdpr_scenario_error_t *err);

/// Check `hc` against scenario `sc` (see above: hashes, period, cables, slack demand). `path`
/// names the file in the errors. CDPR_OK, CDPR_E_OUT_OF_RANGE (another trajectory, robot,
/// controller, period or cable count), CDPR_E_INFEASIBLE (a slack demand, or the statics
/// failing at a knot: the time named), or the model's build errors.
cdpr_status_t cdpr_correction_check(const cdpr_scenario_t *sc, const cdpr_host_correction_t *hc,
                                    const char *path, cdpr_scenario_error_t *err);

/// The correction the scenario names (controller.precompensation), read and checked into
/// `hc`: *out = &hc->c, or NULL when the scenario names none (CDPR_OK). Errors as
/// cdpr_correction_read and cdpr_correction_check, with the key controller.precompensation.
cdpr_status_t cdpr_correction_for_scenario(const cdpr_scenario_t *sc, cdpr_host_correction_t *hc,
                                           const cdpr_tracker_correction_t **out,
                                           cdpr_scenario_error_t *err);

#endif /* CDPR_HOST_CORRECTION_H */
