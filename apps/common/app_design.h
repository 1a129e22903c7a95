/* SPDX-License-Identifier: BSD-3-Clause */
/// @file app_design.h
/// The design check of a scenario's controller in process (lib/design, LAPACK): what
/// `cdpr-design --verdict` runs and the scenario-running apps ask for with --check-design
/// (app_run.h, cdpr_app_design_gate, through a cdpr-design child process). Linked by
/// cdpr-design only.
#ifndef CDPR_APP_DESIGN_H
#define CDPR_APP_DESIGN_H

#include "cdpr/host/scenario.h"
#include "cdpr/status.h"

/// The check of the controller's design (cdpr/design/design.h): when sc's controller has
/// feedback or learning (kp, kd_s, damping_N_s_per_m, damping_rot_N_m_s,
/// tension_gain_m_per_s_per_N, learning_gain, integral_per_s > 0), linearise the loop over the
/// robustness set (start, middle and end poses; the plant at ±20 % EA, cabin mass, rope mass;
/// the controller's model as the scenario gives it) and analyse the cases up to the first
/// refused one. Refused (a case's closed loop grows, or its learning's ρ(M) >= 1 at a lap
/// harmonic): prints
/// "PROG: PATH: controller (...): ... at CASE ..." and returns CDPR_E_OUT_OF_RANGE (exit status
/// 2). Stable below the goal margins (6 dB / 30°) in some case: one "PROG: warning: ..." line
/// naming the cases, CDPR_OK. The check itself failing: its status after printing why.
/// Feed-forward only: CDPR_OK at once, nothing computed or printed. Unless `quiet`, the check
/// is announced on stderr with its case and state counts and its expected cost
/// (CDPR_APP_DESIGN_S_AT_703 per case, scaled by the cube of the states), and the set's table
/// and the time taken are printed after.
cdpr_status_t cdpr_app_design_check(const char *prog, const char *path, const cdpr_scenario_t *sc,
                                    int quiet);

/// The design check's cost per case of the robustness set at 703 states (the paper's robot at
/// 20 segments) with Debian's OpenBLAS (serial) on the project's 2-core machine [s] (6 s with
/// the reference LAPACK); cdpr_app_design_check announces this times the case count, scaled by
/// the cube of the state count, before it runs, and the time taken after.
#define CDPR_APP_DESIGN_S_AT_703 1.3

#endif /* CDPR_APP_DESIGN_H */
