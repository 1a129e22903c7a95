/* SPDX-License-Identifier: BSD-3-Clause */
/// @file app_run.c
/// Scenario, overrides and outputs of the scenario-running apps (app_run.h).
#include "app_run.h"

#include "app_cli.h"

#include <errno.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <spawn.h>
#include <stddef.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include "cdpr/control/tracker.h"
#include "cdpr/host/clock.h"
#include "cdpr/host/cli.h"
#include "cdpr/host/fs.h"
#include "cdpr/host/plot.h"
#include "cdpr/control/trajectory.h"

int cdpr_app_override_opt(const char *prog, int c, const char *arg, cdpr_scenario_overrides_t *ov)
{
    if (c == CDPR_APP_OPT_INTEGRATOR) {
        static const cdpr_plant_integrator_t all[] = {CDPR_PLANT_RKF45, CDPR_PLANT_ROS34PW2,
                                                      CDPR_PLANT_ROS34PW2_FIXED};
        for (size_t i = 0; i < sizeof all / sizeof all[0]; ++i) {
            if (strcmp(arg, cdpr_plant_integrator_name(all[i])) == 0) {
                ov->method = (int)all[i];
                return 0;
            }
        }
        fprintf(stderr, "%s: option --integrator: '%s': not rkf45, ros34pw2 or ros34pw2-fixed\n",
                prog, arg);
        return -1;
    }
    static const int codes[] = {CDPR_APP_OPT_RATE, CDPR_APP_OPT_DURATION, CDPR_APP_OPT_MAX_TRIALS,
                                CDPR_APP_OPT_MAX_ATTEMPTS};
    static const char *const names[] = {"rate", "duration", "max-trials", "max-attempts"};
    double *const fields[] = {&ov->rate_hz, &ov->duration_s, &ov->max_trials, &ov->max_attempts};
    for (size_t i = 0; i < sizeof codes / sizeof codes[0]; ++i) {
        if (c == codes[i]) {
            return (cdpr_cli_real(prog, names[i], arg, fields[i]) == CDPR_OK) ? 0 : -1;
        }
    }
    return 1;
}

int cdpr_app_run_option(const char *prog, int c, const char *arg, cdpr_scenario_overrides_t *ov,
                        int *check_design, int *quiet)
{
    int *flag = NULL;
    if (c == CDPR_APP_OPT_CHECK_DESIGN) {
        flag = check_design;
    } else if (c == 'q') {
        flag = quiet;
    }
    if (flag != NULL) {
        *flag = 1;
        return 0;
    }
    return cdpr_app_override_opt(prog, c, arg, ov);
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
                                     const char *out_dir, const cdpr_summary_t *sum,
                                     const char *plot_script)
{
    char path[1100];
    if (cdpr_fs_path(path, sizeof path, out_dir, "summary.json") != CDPR_OK) {
        fprintf(stderr, "%s: %s/summary.json: path too long\n", prog, out_dir);
        return CDPR_E_IO;
    }
    if (cdpr_summary_write(path, sc, sum) != CDPR_OK) {
        fprintf(stderr, "%s: %s: cannot write: %s\n", prog, path, strerror(errno));
        return CDPR_E_IO;
    }
    if (cdpr_fs_path(path, sizeof path, out_dir, "laps.csv") != CDPR_OK ||
        cdpr_summary_write_laps(path, sum) != CDPR_OK) {
        fprintf(stderr, "%s: %s: cannot write: %s\n", prog, path, strerror(errno));
        return CDPR_E_IO;
    }
    if (plot_script != NULL) {
        (void)cdpr_app_plot(prog, plot_script, out_dir, sc);
    }
    return CDPR_OK;
}

cdpr_status_t cdpr_app_plot(const char *prog, const char *script, const char *dir,
                            const cdpr_scenario_t *sc)
{
    const char *slash = strrchr(sc->path, '/');
    const char *file = (slash != NULL) ? slash + 1 : sc->path;
    char title[800];
    if (sc->description[0] != '\0' && file[0] != '\0') {
        snprintf(title, sizeof title, "%s: %s", file, sc->description);
    } else {
        snprintf(title, sizeof title, "%s", cdpr_app_title(sc));
    }
    return cdpr_plot_run(prog, script, dir, cdpr_traj_type_name(sc->traj.type), title,
                         sc->rig.n_cables, cdpr_app_paper_robot(sc));
}

int cdpr_app_paper_robot(const cdpr_scenario_t *sc)
{
    return (sc->robot_source == CDPR_ROBOT_FROM_PRESET && sc->preset == CDPR_PRESET_PAPER_50M) ? 1
                                                                                               : 0;
}

/* argv[k..] += "--NAME" "%.17g of v" when v was given (not NaN); the value round-trips. */
static int add_number(const char **argv, int k, const char *name, double v, char *buf, size_t cap)
{
    if (isnan(v)) {
        return k;
    }
    snprintf(buf, cap, "%.17g", v);
    argv[k] = name;
    argv[k + 1] = buf;
    return k + 2;
}

/* The check in a child process: cdpr-design (next to this executable, as installed and in the
 * build tree) SCENARIO --verdict with the same overrides, so the apps need no LAPACK. Its
 * messages go straight to our stderr; its exit status is the verdict. */
static cdpr_status_t design_verdict(const char *prog, const char *path,
                                    const cdpr_scenario_overrides_t *ov, int quiet)
{
    char exe[1024];
    char design[1100];
    if (cdpr_app_exe_dir(exe, sizeof exe) != CDPR_OK) {
        fprintf(stderr, "%s: --check-design: cannot locate this executable\n", prog);
        return CDPR_E_IO;
    }
    snprintf(design, sizeof design, "%s/cdpr-design", exe);
    if (access(design, X_OK) != 0) {
        fprintf(stderr,
                "%s: --check-design: %s: %s (the check runs in cdpr-design, installed next to "
                "%s)\n",
                prog, design, strerror(errno), prog);
        return CDPR_E_IO;
    }
    char num[4][40];
    const char *argv[16];
    int k = 0;
    argv[k++] = design;
    argv[k++] = path;
    argv[k++] = "--verdict";
    if (quiet != 0) {
        argv[k++] = "--quiet";
    }
    k = add_number(argv, k, "--rate", ov->rate_hz, num[0], sizeof num[0]);
    k = add_number(argv, k, "--duration", ov->duration_s, num[1], sizeof num[1]);
    k = add_number(argv, k, "--max-trials", ov->max_trials, num[2], sizeof num[2]);
    k = add_number(argv, k, "--max-attempts", ov->max_attempts, num[3], sizeof num[3]);
    const char *method =
        (ov->method >= 0) ? cdpr_plant_integrator_name((cdpr_plant_integrator_t)ov->method) : NULL;
    if (method != NULL) {
        argv[k++] = "--integrator";
        argv[k++] = method;
    }
    argv[k] = NULL;
    pid_t pid = 0;
    const int rc = posix_spawn(&pid, design, NULL, NULL, (char *const *)argv, environ);
    if (rc != 0) {
        fprintf(stderr, "%s: --check-design: cannot run %s: %s\n", prog, design, strerror(rc));
        return CDPR_E_IO;
    }
    int status = 0;
    while (waitpid(pid, &status, 0) < 0) {
        if (errno != EINTR) {
            fprintf(stderr, "%s: --check-design: waiting for %s: %s\n", prog, design,
                    strerror(errno));
            return CDPR_E_IO;
        }
    }
    if (WIFEXITED(status) && WEXITSTATUS(status) == 0) {
        return CDPR_OK;
    }
    if (WIFEXITED(status) && WEXITSTATUS(status) == 5) {
        fprintf(stderr, "%s: %s: the design check refuses the controller (above); not run\n", prog,
                path);
        return CDPR_E_OUT_OF_RANGE;
    }
    if (WIFSIGNALED(status)) {
        fprintf(stderr, "%s: %s: the design check was stopped by signal %d\n", prog, path,
                WTERMSIG(status));
        return CDPR_E_INTERRUPTED;
    }
    fprintf(stderr, "%s: %s: the check of the controller's design failed (cdpr-design exit %d)\n",
            prog, path, WIFEXITED(status) ? WEXITSTATUS(status) : -1);
    return CDPR_E_NO_CONVERGENCE;
}

cdpr_status_t cdpr_app_design_gate(const char *prog, const char *path, const cdpr_scenario_t *sc,
                                   const cdpr_scenario_overrides_t *ov, int check, int quiet)
{
    if (cdpr_tracker_has_feedback(&sc->gains) == 0) {
        return CDPR_OK; /* feed-forward only: nothing to check */
    }
    if (check != 0) {
        return design_verdict(prog, path, ov, quiet);
    }
    if (quiet == 0) {
        fprintf(stderr,
                "%s: note: %s: the controller's feedback/learning is not checked before this "
                "run; --check-design checks it first, or cdpr-design %s --verdict\n",
                prog, path, path);
    }
    return CDPR_OK;
}
