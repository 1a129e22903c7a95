/* SPDX-License-Identifier: BSD-3-Clause */
/// @file scenario.h
/// Scenario files: YAML mapped onto C structs by libcyaml's schema (no hand-written parser).
///
/// A file has the sections `robot` (the robot-file schema of rig.h: an embedded description;
/// or `preset:` as its base, every other key then optional and overriding the preset's value,
/// with the preset's polar layout in `towers:` and `attachments:`; or a robot file, `file:`
/// relative to the scenario file), `initial` (optional pose and offset), `trajectory` (type circle
/// | line | cyclic | hold and the matching block), `controller` (gains), `integrator` (optional
/// tolerances and substep bound) and `run` (duration, control period, output rate).
/// docs/scenarios.md lists every key with its unit and range; scenarios/ holds examples.
///
/// Errors name the file, the line (when known) and the key path, e.g.
///   scenarios/x.yaml:12: robot.rope.ea_N (cable 1): not a finite number (nan)
/// Unknown keys, missing required keys, wrong types and malformed YAML are reported by
/// libcyaml (its backtrace gives key path and line); NaN/Inf, out-of-range values,
/// inconsistent sections and robot parameters the core rejects are checked after loading
/// (the line then comes from a libyaml lookup of the key).
///
/// Host library; loading allocates (libcyaml) and frees everything before returning.
#ifndef CDPR_HOST_SCENARIO_H
#define CDPR_HOST_SCENARIO_H

#include <stdint.h>
#include <stdio.h>

#include "cdpr/plant.h"
#include "cdpr/status.h"
#include "cdpr/host/presets.h"
#include "cdpr/host/rig.h"
#include "cdpr/control/tracker.h"
#include "cdpr/control/trajectory.h"

/// Largest integrator.max_trials a scenario accepts.
#define CDPR_SCENARIO_MAX_TRIALS 1000000

/// Integrator settings of a scenario (inputs).
typedef struct {
    double rtol;                    ///< relative tolerance
    double atol_position_m;         ///< absolute tolerance of positions and lengths [m]
    double atol_velocity_m_per_s;   ///< of velocities [m/s]
    double atol_quaternion;         ///< of quaternion components [-]
    double atol_rate_rad_per_s;     ///< of body rates [rad/s]
    double h_max_s;                 ///< largest step [s]
    int max_trials;                 ///< integrator trials per attempt (bounded work)
    int max_attempts;               ///< attempts per period while the budget is refused (>= 1)
    int substeps;                   ///< ros34pw2-fixed: substeps per period (0: derived)
    cdpr_plant_integrator_t method; ///< integrator.method: rkf45 (default), ros34pw2 or
                                    ///< ros34pw2-fixed
} cdpr_scenario_integrator_t;

/// Integration methods a scenario can name (cdpr_plant_integrator_t values 0..N-1).
#define CDPR_SCENARIO_METHODS 3

/// Where a scenario's robot came from (its record is `rig` whatever the source).
typedef enum {
    CDPR_ROBOT_FROM_PRESET = 0, ///< `robot: {preset: ..., overrides}` (rig.name = the preset's)
    CDPR_ROBOT_FROM_FILE = 1,   ///< `robot: {file: ...}` (rig.name = the resolved file)
    CDPR_ROBOT_EMBEDDED = 2     ///< `robot: {cables: [...], cabin: {...}, ...}` ("embedded")
} cdpr_robot_source_t;

/// Time profile of a scenario's wind (`wind.profile`; docs/scenarios.md, "wind").
typedef enum {
    CDPR_WIND_STEADY = 0, ///< the speed from t = 0
    CDPR_WIND_RAMP = 1,   ///< 0 until start_s, rising linearly to the speed over rise_s
    CDPR_WIND_GUST = 2    ///< the speed, plus a (1 - cos) gust of peak gust_m_per_s over
                          ///< [start_s, start_s + rise_s]
} cdpr_wind_profile_t;

/// A scenario's wind (`wind:`): uniform and horizontal, with a time profile. It replaces the
/// robot's steady `wind_m_per_s` for the run (a scenario that names a robot file can set it).
typedef struct {
    int given;                   ///< 1 when the scenario has a wind section
    double speed_m_per_s;        ///< wind.speed_m_per_s, in [0, 100]
    double towards_deg;          ///< wind.towards_deg: the direction the air moves to, from +x
                                 ///< towards +y [deg], in [-360, 360]
    cdpr_wind_profile_t profile; ///< wind.profile (default steady)
    double start_s;              ///< wind.start_s: ramp or gust start [s], >= 0
    double rise_s;               ///< wind.rise_s: ramp rise or gust duration [s], > 0
    double gust_m_per_s;         ///< wind.gust_m_per_s: the gust's peak added speed, [0, 100]
} cdpr_scenario_wind_t;

/// Names of the wind profiles ("steady", "ramp", "gust"), as the scenario file spells them.
const char *cdpr_wind_profile_name(cdpr_wind_profile_t profile);

/// A resolved scenario: every default applied, every value checked (plain data, no
/// pointers; nothing to free).
typedef struct {
    char path[512];                   ///< file it came from ("" if built in code)
    char description[256];            ///< optional free text
    cdpr_robot_source_t robot_source; ///< where the robot came from
    cdpr_preset_t preset;             ///< the base preset (robot_source PRESET only)
    cdpr_rig_t rig;                   ///< the robot: the one host record of it
    int has_initial_pose;             ///< 1 if initial.pose was given
    double initial_pose[6];           ///< initial.pose (else the trajectory at t = 0)
    double initial_offset[6];         ///< added to the initial pose (m, rad)
    cdpr_traj_t traj;                 ///< desired trajectory
    cdpr_tracker_gains_t gains;       ///< controller gains
    /// The controller's own model (controller.model): the robot with these factors (default
    /// 1: the controller knows the robot exactly). The plant is always the robot as written.
    cdpr_rig_scale_t controller_model;
    /// controller.precompensation: the correction file's path as the loader resolved it
    /// (relative to the scenario's folder unless absolute; "" = none): read and checked where
    /// the controller is built (cdpr_correction_for_scenario, correction.h).
    char precompensation[512];
    cdpr_scenario_integrator_t integrator; ///< integrator settings and work bound in use: those
                                           ///< of integrator.method (integrator_for[method])
    /// The settings each method gets, indexed by cdpr_plant_integrator_t: the section's own
    /// keys, then those of its `rkf45:` or `ros34pw2:` subsection (ros34pw2-fixed takes the
    /// `ros34pw2:` one); --integrator (cdpr_scenario_override) switches to one.
    cdpr_scenario_integrator_t integrator_for[CDPR_SCENARIO_METHODS];
    double duration_s;     ///< simulated time [s] (run.duration_s)
    double period_s;       ///< control period of plant, controller and
                           ///< outputs [s] (run.period_s)
    double output_rate_hz; ///< CSV rows per simulated second
    /// The wind section (given = 0: the robot's steady rig.wind_m_per_s). With a section,
    /// rig.wind_m_per_s holds the profile's value at t = 0 (the settled start's wind).
    cdpr_scenario_wind_t wind;
    /// Fingerprint of the values above when cdpr_scenario_load or cdpr_scenario_override last
    /// checked them (0: never): cdpr_scenario_is_checked. Last member; not a value.
    uint64_t checked_stamp;
} cdpr_scenario_t;

/// Error text of a failed load or check: "FILE:LINE: KEY: what".
typedef struct {
    char msg[2048];
} cdpr_scenario_error_t;

/// Defaults for scenarios built in code: the preset's robot, a hold at its nominal pose for
/// 1 s, the default controller and integrator settings (the same defaults a file gets for
/// omitted optional keys).
void cdpr_scenario_default(cdpr_scenario_t *sc, cdpr_preset_t preset);

/// Load, resolve and check a scenario file. Returns CDPR_OK, or with `err` filled (`sc` then
/// holds no meaningful data): CDPR_E_IO (cannot open), CDPR_E_PARSE (malformed YAML, unknown
/// or missing key, wrong type, empty file, a trajectory block that does not match its type,
/// a key that moved), or the error of a value (as cdpr_scenario_check; CDPR_E_OUT_OF_RANGE
/// also for a count that is not a whole number).
cdpr_status_t cdpr_scenario_load(const char *path, cdpr_scenario_t *sc, cdpr_scenario_error_t *err);

/// Check every value of a resolved scenario (finite, in range, consistent, accepted by the
/// core's validation). Returns CDPR_OK, or with `err` naming the first bad key:
/// CDPR_E_NOT_FINITE, CDPR_E_OUT_OF_RANGE (outside its range; a duration that is not a whole
/// number of periods, an output rate that does not divide the control rate), or the core's
/// status for robot values it rejects. Called by the loader and by cdpr_scenario_override;
/// call it for scenarios built in code. The one place where run settings are range-checked.
cdpr_status_t cdpr_scenario_check(const cdpr_scenario_t *sc, cdpr_scenario_error_t *err);

/// 1 when `sc` holds exactly the values that cdpr_scenario_load or cdpr_scenario_override
/// checked (its bytes up to checked_stamp hash to the stamp), else 0: a scenario built in code,
/// or changed since (then call cdpr_scenario_check). Later layers (cdpr_sim_run,
/// cdpr_rt_plant_init) trust a checked scenario instead of checking it again: a scenario is
/// validated once. O(sizeof *sc); cannot fail.
int cdpr_scenario_is_checked(const cdpr_scenario_t *sc);

/// Command-line overrides of a scenario's run settings (inputs). NaN: not given
/// (cdpr_scenario_overrides_none).
typedef struct {
    double rate_hz;      ///< --rate HZ: run.period_s = 1 / HZ
    double duration_s;   ///< --duration S: run.duration_s = S (plant time)
    double max_trials;   ///< --max-trials N (a whole number): integrator.max_trials
    double max_attempts; ///< --max-attempts N (a whole number): integrator.max_attempts
    int method;          ///< --integrator NAME: integrator.method (-1: not given)
} cdpr_scenario_overrides_t;

/// Nothing overridden (every number NaN, method -1).
void cdpr_scenario_overrides_none(cdpr_scenario_overrides_t *ov);

/// Apply the given overrides to `sc` (loaded or built in code), then check it again with
/// cdpr_scenario_check, so options obey the scenario's own ranges. For each value that differs
/// from the scenario's, one line goes to `notes` (may be NULL), e.g.
///   cdpr-rt: --rate 1000 Hz overrides run.period_s = 0.01 s (100 Hz) of scenarios/x.yaml
/// Returns CDPR_OK, or with `err` naming the option(s) given ("--rate 0.05 Hz: FILE:LINE:
/// run.period_s: 20 is outside (0, 10]"): CDPR_E_NOT_FINITE / CDPR_E_OUT_OF_RANGE (a count
/// that is not a whole number, or any error of cdpr_scenario_check: e.g. a duration that is
/// not a whole number of periods). `sc` then holds the overridden, unchecked values.
cdpr_status_t cdpr_scenario_override(cdpr_scenario_t *sc, const cdpr_scenario_overrides_t *ov,
                                     const char *prog, FILE *notes, cdpr_scenario_error_t *err);

/// The key of the scenario's trajectory block as messages name it: "trajectory.hold",
/// "trajectory.circle", "trajectory.line" or "trajectory.cyclic". O(1); cannot fail.
const char *cdpr_scenario_trajectory_key(const cdpr_scenario_t *sc);

/// Name of the scenario's robot: the preset's name, the robot file's path or "embedded".
const char *cdpr_scenario_robot_name(const cdpr_scenario_t *sc);

/// The wind at time t [s] in world axes [m/s]: the wind section's profile, or the robot's
/// steady wind_m_per_s without one. The simulation loops (cdpr_sim_run, cdpr-rt) set the
/// plant's wind each period to its value at the period's midpoint (exact on average for a
/// ramp), and the controller's wind feed-forward to the same value (an ideal anemometer).
/// Directions that are whole multiples of 90 degrees give exact zeros. O(1); cannot fail.
void cdpr_scenario_wind_at(const cdpr_scenario_t *sc, double t, double v[3]);

/// The profile of a wind section at time t [s] in world axes [m/s] (as cdpr_scenario_wind_at;
/// for loops that keep the section without the scenario). A section with given = 0: zero.
void cdpr_scenario_wind_eval(const cdpr_scenario_wind_t *w, double t, double v[3]);

/// Segments of the scenario robot's first cable (the initial discretisation).
int cdpr_scenario_segments(const cdpr_scenario_t *sc);

/// Build the core robot and winch parameters of the scenario (cdpr_rig_build of sc->rig; `w`: NULL
/// or CDPR_MAX_CABLES entries, one per winch; `length_m` and errors as there).
cdpr_status_t cdpr_scenario_build_robot(const cdpr_scenario_t *sc, const double *length_m,
                                        cdpr_robot_params_t *p, cdpr_winch_params_t *w,
                                        cdpr_diag_t *diag);

/// Initial pose: initial.pose (or the trajectory at t = 0) plus initial.offset.
void cdpr_scenario_initial_pose(const cdpr_scenario_t *sc, double pose[6]);

/// Most control periods a run may have (run.duration_s / run.period_s; also the bound on the
/// control periods per output row): 1e9, 11.6 days at 1 kHz, and it fits a 32-bit long, so no
/// count overflows.
#define CDPR_SCENARIO_MAX_PERIODS 1000000000L

/// A count from a double: round(n), 0 for NaN or n <= 0, CDPR_SCENARIO_MAX_PERIODS beyond it
/// (never an overflowing cast).
long cdpr_scenario_count(double n);

/// Number of control periods of the run and control periods per output row (saturating, see
/// cdpr_scenario_count; cdpr_scenario_check keeps both within CDPR_SCENARIO_MAX_PERIODS).
long cdpr_scenario_periods(const cdpr_scenario_t *sc);
long cdpr_scenario_output_every(const cdpr_scenario_t *sc);

/// Format an error about `key` of the scenario: "FILE:LINE: KEY: what", the line looked up
/// in the scenario's file (omitted when unknown, the file part when built in code). Not
/// variadic on purpose: callers format `what` with snprintf (clang-tidy 14's va_list checker
/// misfires on a variadic version when it analyses several files in one run).
void cdpr_scenario_error(const cdpr_scenario_t *sc, const char *key, const char *what,
                         cdpr_scenario_error_t *err);

/// Line (1-based) of the key at dotted path `key` (e.g. "robot.rope.ea_N"; a trailing
/// "[i]" is ignored) in the YAML file `path`, or 0 if it is not there. Uses libyaml.
int cdpr_yaml_key_line(const char *path, const char *key);

/// Name of a trajectory type as written in files ("hold", "circle", "line").
const char *cdpr_traj_type_name(cdpr_traj_type_t type);

#endif /* CDPR_HOST_SCENARIO_H */
