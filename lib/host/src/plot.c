/* SPDX-License-Identifier: BSD-3-Clause */
/// @file plot.c
/// gnuplot runner (plot.h).
#include "cdpr/host/plot.h"

#include <errno.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

cdpr_status_t cdpr_plot_run(const char *prog, const char *script, const char *dir, const char *kind,
                            const char *title, int n_cables, int paper)
{
    char n_arg[16];
    snprintf(n_arg, sizeof n_arg, "%d", n_cables);
    struct stat sb;
    if (stat(script, &sb) != 0) {
        fprintf(stderr, "%s: warning: plot script %s: %s; no figures\n", prog, script,
                strerror(errno));
        return CDPR_E_IO;
    }
    fflush(NULL);
    const pid_t pid = fork();
    if (pid < 0) {
        fprintf(stderr, "%s: warning: fork: %s; no figures\n", prog, strerror(errno));
        return CDPR_E_IO;
    }
    if (pid == 0) {
        char *const args[] = {"gnuplot",    "-c",          (char *)script, (char *)dir,
                              (char *)kind, (char *)title, n_arg,          (paper != 0) ? "1" : "0",
                              NULL};
        execvp("gnuplot", args);
        fprintf(stderr, "%s: warning: cannot run gnuplot: %s; no figures\n", prog, strerror(errno));
        _exit(127);
    }
    int status = 0;
    while (waitpid(pid, &status, 0) < 0) {
        if (errno != EINTR) {
            return CDPR_E_IO;
        }
    }
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
        if (!WIFEXITED(status) || WEXITSTATUS(status) != 127) {
            fprintf(stderr, "%s: warning: gnuplot failed (%s); figures may be missing\n", prog,
                    script);
        }
        return CDPR_E_IO;
    }
    return CDPR_OK;
}
