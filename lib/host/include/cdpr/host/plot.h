/* SPDX-License-Identifier: BSD-3-Clause */
/// @file plot.h
/// The figures of a run: gnuplot run on a script (scripts/plot_sim.gp) without a shell.
///
/// Host library (POSIX: fork, execvp, waitpid).
#ifndef CDPR_HOST_PLOT_H
#define CDPR_HOST_PLOT_H

#include "cdpr/status.h"

/// Run `gnuplot -c script dir kind title n_cables paper` and wait for it: kind is the trajectory
/// type name (cdpr_traj_type_name: circle, line, hold or cyclic), n_cables the robot's cable
/// count (1..CDPR_MAX_CABLES: one tension panel each), paper 1 for the paper's robot (the
/// figures then name the paper's Figure 4/5 they follow). Warnings go to stderr prefixed `prog`.
/// Returns CDPR_OK when gnuplot succeeded, else CDPR_E_IO (no script, no gnuplot, gnuplot
/// failed).
cdpr_status_t cdpr_plot_run(const char *prog, const char *script, const char *dir, const char *kind,
                            const char *title, int n_cables, int paper);

#endif /* CDPR_HOST_PLOT_H */
