/* SPDX-License-Identifier: BSD-3-Clause */
/// @file plot.h
/// The figures of a run: gnuplot run on a script (scripts/plot_sim.gp) without a shell.
///
/// Host library (POSIX: fork, execvp, waitpid).
#ifndef CDPR_HOST_PLOT_H
#define CDPR_HOST_PLOT_H

#include "cdpr/status.h"

/// Run `gnuplot -c script dir kind title` and wait for it: kind is the trajectory type name
/// (cdpr_traj_type_name: circle, line or hold). Warnings go to stderr prefixed `prog`.
/// Returns CDPR_OK when gnuplot succeeded, else CDPR_E_IO (no script, no gnuplot, gnuplot
/// failed).
cdpr_status_t cdpr_plot_run(const char *prog, const char *script, const char *dir, const char *kind,
                            const char *title);

#endif /* CDPR_HOST_PLOT_H */
