/// @file scenario.h
/// Scenario files: YAML mapped onto C structs by libcyaml's schema (no hand-written parser).
///
/// A file has the sections `robot` (preset name plus optional overrides of every value of
/// presets.h), `initial` (optional pose and offset), `trajectory` (type circle | line | hold
/// and the matching block), `controller` (period and gains), `integrator` (optional
/// tolerances and substep bound) and `run` (duration, output rate). docs/scenarios.md lists
/// every key with its unit and range; scenarios/ holds examples.
///
/// Errors name the file, the line (when known) and the key path, e.g.
///   scenarios/x.yaml:12: robot.cable.ea_N: not a finite number (nan)
/// Unknown keys, missing required keys, wrong types and malformed YAML are reported by
/// libcyaml (its backtrace gives key path and line); NaN/Inf, out-of-range values,
/// inconsistent sections and robot parameters the core rejects are checked after loading
/// (the line then comes from a libyaml lookup of the key).
///
/// Host library; loading allocates (libcyaml) and frees everything before returning.
#ifndef CDPR_HOST_SCENARIO_H
#define CDPR_HOST_SCENARIO_H

#include "cdpr/plant.h"
#include "cdpr/host/presets.h"
#include "cdpr/host/tracker.h"
#include "cdpr/host/trajectory.h"

/// Integrator settings of a scenario (inputs).
typedef struct {
    double rtol;                  ///< relative tolerance
    double atol_position_m;       ///< absolute tolerance of positions and lengths [m]
    double atol_velocity_m_per_s; ///< of velocities [m/s]
    double atol_quaternion;       ///< of quaternion components [-]
    double atol_rate_rad_per_s;   ///< of body rates [rad/s]
    double h_max_s;               ///< largest step [s]
    int max_trials;               ///< integrator trials per attempt (bounded work)
    int max_attempts;             ///< attempts per period while the budget is refused (>= 1)
} cdpr_scenario_integrator_t;

/// A resolved scenario: every default applied, every value checked (plain data, no
/// pointers; nothing to free).
typedef struct {
    char path[512];                        ///< file it came from ("" if built in code)
    char description[256];                 ///< optional free text
    cdpr_preset_config_t robot;            ///< robot (preset + overrides)
    int has_initial_pose;                  ///< 1 if initial.pose was given
    double initial_pose[6];                ///< initial.pose (else the trajectory at t = 0)
    double initial_offset[6];              ///< added to the initial pose (m, rad)
    cdpr_traj_t traj;                      ///< desired trajectory
    cdpr_tracker_gains_t gains;            ///< controller gains
    cdpr_scenario_integrator_t integrator; ///< integrator settings and work bound
    double duration_s;                     ///< simulated time [s] (run.duration_s)
    double period_s;                       ///< control period of plant, controller and
                                           ///< outputs [s] (run.period_s)
    double output_rate_hz;                 ///< CSV rows per simulated second
} cdpr_scenario_t;

/// Error text of a failed load or check: "FILE:LINE: KEY: what".
typedef struct {
    char msg[2048];
} cdpr_scenario_error_t;

/// Defaults for scenarios built in code: the preset's robot, a hold at its nominal pose for
/// 1 s, the default controller and integrator settings (the same defaults a file gets for
/// omitted optional keys).
void cdpr_scenario_default(cdpr_scenario_t *sc, cdpr_preset_t preset);

/// Load, resolve and check a scenario file. Returns 0, or -1 with `err` filled (`sc` then
/// holds no meaningful data).
int cdpr_scenario_load(const char *path, cdpr_scenario_t *sc, cdpr_scenario_error_t *err);

/// Check every value of a resolved scenario (finite, in range, consistent, accepted by the
/// core's validation). Returns 0 or -1 with `err` naming the key. Called by the loader;
/// call it for scenarios built in code.
int cdpr_scenario_check(const cdpr_scenario_t *sc, cdpr_scenario_error_t *err);

/// Initial pose: initial.pose (or the trajectory at t = 0) plus initial.offset.
void cdpr_scenario_initial_pose(const cdpr_scenario_t *sc, double pose[6]);

/// Number of control periods of the run and control periods per output row.
long cdpr_scenario_periods(const cdpr_scenario_t *sc);
long cdpr_scenario_output_every(const cdpr_scenario_t *sc);

/// Format an error about `key` of the scenario: "FILE:LINE: KEY: what", the line looked up
/// in the scenario's file (omitted when unknown, the file part when built in code). Not
/// variadic on purpose: callers format `what` with snprintf (clang-tidy 14's va_list checker
/// misfires on a variadic version when it analyses several files in one run).
void cdpr_scenario_error(const cdpr_scenario_t *sc, const char *key, const char *what,
                         cdpr_scenario_error_t *err);

/// Line (1-based) of the key at dotted path `key` (e.g. "robot.cable.ea_N"; a trailing
/// "[i]" is ignored) in the YAML file `path`, or 0 if it is not there. Uses libyaml.
int cdpr_yaml_key_line(const char *path, const char *key);

/// Name of a trajectory type as written in files ("hold", "circle", "line").
const char *cdpr_traj_type_name(cdpr_traj_type_t type);

#endif /* CDPR_HOST_SCENARIO_H */
