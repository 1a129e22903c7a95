/* SPDX-License-Identifier: BSD-3-Clause */
/// @file app_run.h
/// What the scenario-running apps (cdpr-sim, cdpr-rt, cdpr-tracker) share: the override
/// options (--rate, --duration, --max-trials, --max-attempts) applied to the scenario file by
/// cdpr_scenario_override, and the outputs of a tracking run (summary.json, figures).
#ifndef CDPR_APP_RUN_H
#define CDPR_APP_RUN_H

#include "cdpr/status.h"
#include "cdpr/host/scenario.h"
#include "cdpr/host/summary.h"

/// getopt_long codes of the override options (use them in the apps' option tables).
enum {
    CDPR_APP_OPT_RATE = 'r',         ///< --rate HZ         run.period_s = 1 / HZ
    CDPR_APP_OPT_DURATION = 'd',     ///< --duration S      run.duration_s (plant time)
    CDPR_APP_OPT_MAX_TRIALS = 'm',   ///< --max-trials N    integrator.max_trials
    CDPR_APP_OPT_MAX_ATTEMPTS = 'M', ///< --max-attempts N  integrator.max_attempts
    CDPR_APP_OPT_INTEGRATOR = 'I'    ///< --integrator NAME integrator.method (rkf45, ros34pw2)
};

/// The five override options, for the apps' getopt_long tables.
// clang-format off
#define CDPR_APP_OVERRIDE_OPTIONS                                                                  \
    {"rate", required_argument, NULL, CDPR_APP_OPT_RATE},                                          \
    {"duration", required_argument, NULL, CDPR_APP_OPT_DURATION},                                  \
    {"max-trials", required_argument, NULL, CDPR_APP_OPT_MAX_TRIALS},                              \
    {"max-attempts", required_argument, NULL, CDPR_APP_OPT_MAX_ATTEMPTS},                          \
    {"integrator", required_argument, NULL, CDPR_APP_OPT_INTEGRATOR}
// clang-format on

/// If getopt code `c` is an override option, parse its argument into `ov` (any finite number:
/// the ranges are the scenario's, checked by cdpr_app_scenario; --integrator: rkf45, ros34pw2
/// or ros34pw2-fixed). Returns as a cdpr_app_option_fn (app_cli.h): 0 when it was one and
/// parsed, 1 when `c` is not an override option, -1 after printing why the argument is not a
/// number (or not an integrator).
int cdpr_app_override_opt(const char *prog, int c, const char *arg, cdpr_scenario_overrides_t *ov);

/// The options every scenario-running app shares, as a cdpr_app_option_fn (app_cli.h): the
/// override options into `ov` (cdpr_app_override_opt), CDPR_APP_OPT_CHECK_DESIGN (when
/// `check_design` is not NULL) and --quiet ('q', CDPR_APP_QUIET_OPTION; when `quiet` is not
/// NULL) set their flag to 1. Returns 0 when `c` was one of them, 1 when not, -1 after printing
/// why an override's argument is refused.
int cdpr_app_run_option(const char *prog, int c, const char *arg, cdpr_scenario_overrides_t *ov,
                        int *check_design, int *quiet);

/// The --quiet entry of the scenario-running apps' getopt_long tables.
#define CDPR_APP_QUIET_OPTION                                                                      \
    {                                                                                              \
        "quiet", no_argument, NULL, 'q'                                                            \
    }

/// The getopt_long entries of every option cdpr_app_run_option takes: the overrides,
/// --check-design and --quiet.
#define CDPR_APP_RUN_OPTIONS                                                                       \
    CDPR_APP_OVERRIDE_OPTIONS, CDPR_APP_CHECK_DESIGN_OPTION, CDPR_APP_QUIET_OPTION

/// The LCM options of the apps on the bus (cdpr-rt, cdpr-tracker): --lcm-url 'u', --prefix 'p'.
// clang-format off
#define CDPR_APP_LCM_OPTIONS                                                                       \
    {"lcm-url", required_argument, NULL, 'u'},                                                     \
    {"prefix", required_argument, NULL, 'p'}
// clang-format on
/// Load scenario file `path` and apply the overrides `ov` (a note on stderr for each value
/// that differs from the file). Returns CDPR_OK or the status after printing "PROG: error".
cdpr_status_t cdpr_app_scenario(const char *prog, const char *path,
                                const cdpr_scenario_overrides_t *ov, cdpr_scenario_t *sc);

/// The option `--check-design` of the scenario-running apps (cdpr-sim, cdpr-rt --with-tracker,
/// cdpr-tracker): run the design check before anything else. A value beyond any char, so it
/// takes no short option letter.
#define CDPR_APP_OPT_CHECK_DESIGN 0x1c0
#define CDPR_APP_CHECK_DESIGN_OPTION                                                               \
    {                                                                                              \
        "check-design", no_argument, NULL, CDPR_APP_OPT_CHECK_DESIGN                               \
    }

/// The design check at load, for a controller with feedback or learning
/// (cdpr_tracker_has_feedback; feed-forward only: CDPR_OK, nothing printed). When asked for
/// (`check` != 0) it runs `cdpr-design PATH --verdict` with the overrides `ov` as a child
/// process (the executable next to this one; so the apps link no LAPACK), whose messages go to
/// stderr, and returns: CDPR_OK (passed, or a warning below the goal margins),
/// CDPR_E_OUT_OF_RANGE (refused: "PROG: PATH: the design check refuses the controller (above);
/// not run"), CDPR_E_NO_CONVERGENCE (the check failed), CDPR_E_INTERRUPTED (the child was
/// stopped by a signal) or CDPR_E_IO (cdpr-design missing or not started). Otherwise the
/// check does not run (it costs seconds: the apps start at once) and, when `quiet` is 0, one
/// line on stderr says so: "PROG: note: PATH: the controller's feedback/learning is not checked
/// before this run; --check-design checks it first, or cdpr-design PATH --verdict".
cdpr_status_t cdpr_app_design_gate(const char *prog, const char *path, const cdpr_scenario_t *sc,
                                   const cdpr_scenario_overrides_t *ov, int check, int quiet);

/// Install SIGINT, SIGTERM and SIGHUP handlers (alike, without SA_RESTART) that set the
/// returned flag (0 until a signal came; the apps' loops, cdpr_sim_run and the plant node's
/// periodic thread check it). Same flag on every call. The apps then end as for a stop: whole
/// CSV rows, summary.json with status "interrupted", exit 1 (CDPR_E_INTERRUPTED). A SIGHUP
/// that was ignored when the app started (nohup) stays ignored.
const volatile int *cdpr_app_stop_on_signals(void);

/// Title of a run's figures: the scenario's description, else its file.
const char *cdpr_app_title(const cdpr_scenario_t *sc);

/// 1 when the scenario's robot is the paper's (the paper-50m preset): its figures name the
/// paper's Figure 4/5 they follow; else 0.
int cdpr_app_paper_robot(const cdpr_scenario_t *sc);

/// The figures of a run of `sc` in `dir` (cdpr_plot_run with the scenario's trajectory type,
/// title "FILE: description", cable count, and whether the robot is the paper's preset).
cdpr_status_t cdpr_app_plot(const char *prog, const char *script, const char *dir,
                            const cdpr_scenario_t *sc);

/// Write out_dir/summary.json and, when `plot_script` is not NULL, the figures (gnuplot on
/// that script; a failure there is only a warning). Returns CDPR_OK, or CDPR_E_IO after
/// printing "PROG: FILE: cannot write: why".
cdpr_status_t cdpr_app_write_outputs(const char *prog, const cdpr_scenario_t *sc,
                                     const char *out_dir, const cdpr_summary_t *sum,
                                     const char *plot_script);

#endif /* CDPR_APP_RUN_H */
