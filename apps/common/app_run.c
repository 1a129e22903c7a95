/* SPDX-License-Identifier: BSD-3-Clause */
/// @file app_run.c
/// Scenario, overrides and outputs of the scenario-running apps (app_run.h).
#include "app_run.h"

#include <errno.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <string.h>

#include "cdpr/design/design.h"
#include "cdpr/host/clock.h"
#include "cdpr/host/cli.h"
#include "cdpr/host/fs.h"
#include "cdpr/host/plot.h"
#include "cdpr/control/trajectory.h"

int cdpr_app_override_opt(const char *prog, int c, const char *arg, cdpr_scenario_overrides_t *ov)
{
    double *field = NULL;
    const char *name = NULL;
    if (c == CDPR_APP_OPT_INTEGRATOR) {
        if (strcmp(arg, "rkf45") == 0) {
            ov->method = (int)CDPR_PLANT_RKF45;
        } else if (strcmp(arg, "ros34pw2") == 0) {
            ov->method = (int)CDPR_PLANT_ROS34PW2;
        } else if (strcmp(arg, "ros34pw2-fixed") == 0) {
            ov->method = (int)CDPR_PLANT_ROS34PW2_FIXED;
        } else {
            fprintf(stderr,
                    "%s: option --integrator: '%s': not rkf45, ros34pw2 or ros34pw2-fixed\n", prog,
                    arg);
            return -1;
        }
        return 1;
    }
    switch (c) {
    case CDPR_APP_OPT_RATE:
        field = &ov->rate_hz;
        name = "rate";
        break;
    case CDPR_APP_OPT_DURATION:
        field = &ov->duration_s;
        name = "duration";
        break;
    case CDPR_APP_OPT_MAX_TRIALS:
        field = &ov->max_trials;
        name = "max-trials";
        break;
    case CDPR_APP_OPT_MAX_ATTEMPTS:
        field = &ov->max_attempts;
        name = "max-attempts";
        break;
    default:
        return 0;
    }
    return (cdpr_cli_real(prog, name, arg, field) == CDPR_OK) ? 1 : -1;
}

cdpr_status_t cdpr_app_scenario(const char *prog, const char *path,
                                const cdpr_scenario_overrides_t *ov, cdpr_scenario_t *sc)
{
    cdpr_scenario_error_t err;
    cdpr_status_t st = cdpr_scenario_load(path, sc, &err);
    if (st == CDPR_OK) {
        st = cdpr_scenario_override(sc, ov, prog, stderr, &err);
    }
    if (st != CDPR_OK) {
        fprintf(stderr, "%s: %s\n", prog, err.msg);
    }
    return st;
}

static volatile int g_stop = 0;

static void on_signal(int sig)
{
    (void)sig;
    g_stop = 1;
}

const volatile int *cdpr_app_stop_on_signals(void)
{
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_signal;
    sigemptyset(&sa.sa_mask);
    /* No SA_RESTART: a blocking wait (poll, select in lcm_handle) returns EINTR and the
     * app looks at the flag. SIGHUP ignored at start (nohup) stays ignored. */
    (void)sigaction(SIGINT, &sa, NULL);
    (void)sigaction(SIGTERM, &sa, NULL);
    struct sigaction hup;
    if (sigaction(SIGHUP, NULL, &hup) != 0 || hup.sa_handler != SIG_IGN) {
        (void)sigaction(SIGHUP, &sa, NULL);
    }
    return &g_stop;
}

const char *cdpr_app_title(const cdpr_scenario_t *sc)
{
    return (sc->description[0] != '\0') ? sc->description : sc->path;
}

cdpr_status_t cdpr_app_write_outputs(const char *prog, const cdpr_scenario_t *sc,
                                     const char *out_dir, const cdpr_sim_summary_t *sum,
                                     const char *plot_script)
{
    char path[1100];
    if (cdpr_fs_path(path, sizeof path, out_dir, "summary.json") != CDPR_OK) {
        fprintf(stderr, "%s: %s/summary.json: path too long\n", prog, out_dir);
        return CDPR_E_IO;
    }
    if (cdpr_sim_write_summary(path, sc, sum) != CDPR_OK) {
        fprintf(stderr, "%s: %s: cannot write: %s\n", prog, path, strerror(errno));
        return CDPR_E_IO;
    }
    if (cdpr_fs_path(path, sizeof path, out_dir, "laps.csv") != CDPR_OK ||
        cdpr_sim_write_laps(path, sum) != CDPR_OK) {
        fprintf(stderr, "%s: %s: cannot write: %s\n", prog, path, strerror(errno));
        return CDPR_E_IO;
    }
    if (plot_script != NULL) {
        (void)cdpr_sim_plot(prog, plot_script, out_dir, cdpr_traj_type_name(sc->traj.type),
                            cdpr_app_title(sc));
    }
    return CDPR_OK;
}

/* The linearised loop's state count: the robot's (13 for the cabin, 1 + 6 (segments - 1) per
 * cable) plus the controller's; 0 when the robot cannot be built (the check then says why). */
static long design_states(const cdpr_scenario_t *sc)
{
    static cdpr_robot_params_t mp; /* 2 kB per cable: not on the stack */
    cdpr_winch_params_t w[CDPR_MAX_CABLES];
    cdpr_diag_t d;
    if (cdpr_scenario_build_robot(sc, NULL, &mp, w, &d) != CDPR_OK) {
        return 0;
    }
    long n = 13;
    for (int j = 0; j < mp.n_cables; ++j) {
        n += 1 + 6L * (long)(mp.cables[j].n_segments - 1);
    }
    return n;
}

cdpr_status_t cdpr_app_design_check(const char *prog, const char *path, const cdpr_scenario_t *sc,
                                    int quiet)
{
    int checked = 0; /* 0: feed-forward only, nothing computed */
    int warn = 0;
    cdpr_design_error_t err;
    /* Say what is coming: the check's dense algebra grows as the cube of the states (measured:
     * 6 s at 703 states, 81 s at 1417, with Debian's reference LAPACK; docs/performance.md). */
    const long n = design_states(sc);
    const double t0 = cdpr_clock_now_s();
    if (quiet == 0 && cdpr_design_has_feedback(&sc->gains) != 0 && n > 0) {
        const double expect_s = CDPR_APP_DESIGN_S_AT_703 * pow((double)n / 703.0, 3.0);
        fprintf(stderr,
                "%s: checking the controller's design on its linearised loop (%ld states of the "
                "robot; about %.0f s on an idle 2-core machine with reference LAPACK, growing as "
                "the cube of the states)...\n",
                prog, n, expect_s);
    }
    const cdpr_status_t st = cdpr_design_check_scenario(sc, path, &checked, &warn, NULL, &err);
    if (quiet == 0 && checked != 0) {
        fprintf(stderr, "%s: design check done in %.1f s\n", prog, cdpr_clock_now_s() - t0);
    }
    if (st == CDPR_E_OUT_OF_RANGE) {
        fprintf(stderr, "%s: %s\n", prog, err.msg);
    } else if (st != CDPR_OK) {
        fprintf(stderr, "%s: %s: the check of the controller's design failed: %s\n", prog, path,
                err.msg);
    } else if (warn != 0) {
        fprintf(stderr, "%s: warning: %s\n", prog, err.msg);
    }
    return st;
}

cdpr_status_t cdpr_app_design_gate(const char *prog, const char *path, const cdpr_scenario_t *sc,
                                   int check, int quiet)
{
    if (check != 0) {
        return cdpr_app_design_check(prog, path, sc, quiet);
    }
    if (quiet == 0 && cdpr_design_has_feedback(&sc->gains) != 0) {
        fprintf(stderr,
                "%s: note: %s: the controller's feedback/learning is not checked before this "
                "run; --check-design checks it first, or cdpr-design %s --verdict\n",
                prog, path, path);
    }
    return CDPR_OK;
}
