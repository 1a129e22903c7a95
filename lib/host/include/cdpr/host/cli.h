/* SPDX-License-Identifier: BSD-3-Clause */
/// @file cli.h
/// Command-line helpers shared by the host apps (getopt_long does the parsing).
#ifndef CDPR_HOST_CLI_H
#define CDPR_HOST_CLI_H

#include "cdpr/status.h"

/// Parse option `--opt`'s argument `arg` as a finite number in [lo, hi] (strtod, the whole
/// string). Returns CDPR_OK with *out set, or, after printing "PROG: --OPT: ..." to stderr
/// (*out unchanged): CDPR_E_INVALID_ARG (empty, not a number, trailing characters),
/// CDPR_E_NOT_FINITE (nan, inf), CDPR_E_OUT_OF_RANGE (outside [lo, hi], or beyond a double).
cdpr_status_t cdpr_cli_number(const char *prog, const char *opt, const char *arg, double lo,
                              double hi, double *out);

/// cdpr_cli_number for any finite number: for options whose range is checked where the value
/// is used (scenario overrides: cdpr_scenario_override; the real-time node: cdpr_rt_plant_init).
cdpr_status_t cdpr_cli_real(const char *prog, const char *opt, const char *arg, double *out);

#endif /* CDPR_HOST_CLI_H */
