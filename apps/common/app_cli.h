/* SPDX-License-Identifier: BSD-3-Clause */
/// @file app_cli.h
/// What every app's command line shares (GNU conventions):
///
///   --help      the usage on stdout, exit 0
///   --version   one line "PROG 0.1.0 (git DESCRIBE)" on stdout (cdpr/version.h), exit 0
///   a usage error (unknown, ambiguous or malformed option, missing argument or operand) is
///               ONE line on stderr, "PROG: what; try 'PROG --help'", and exit 2 (the status
///               table: CDPR_E_INVALID_ARG, app_status.h)
///
/// The apps call getopt_long with opterr = 0 and an optstring starting with ':' (so a missing
/// argument returns ':'), and hand '?' and ':' to cdpr_app_bad_option, which prints the line
/// getopt would have printed, plus the hint. And the data files the apps read (gnuplot
/// scripts) are found relative to the executable (cdpr_app_data_file).
#ifndef CDPR_APP_CLI_H
#define CDPR_APP_CLI_H

#include <getopt.h>
#include <stddef.h>
#include <stdio.h>

#include "cdpr/status.h"

/// getopt_long code of --version (beyond every short option character).
#define CDPR_APP_OPT_VERSION 0x100

/// The optstring of every app: ':' first (a missing argument returns ':'), then -h.
#define CDPR_APP_OPTSTRING ":h"

/// The tail of every app's getopt_long table: the --help and --version entries and the
/// terminating all-zero entry.
// clang-format off
#define CDPR_APP_STD_OPTIONS_END                                                                   \
    {"help", no_argument, NULL, 'h'},                                                              \
    {"version", no_argument, NULL, CDPR_APP_OPT_VERSION},                                          \
    {NULL, 0, NULL, 0}
// clang-format on

#if defined(__GNUC__)
#define CDPR_APP_PRINTF(f, a) __attribute__((format(printf, f, a)))
#else
#define CDPR_APP_PRINTF(f, a)
#endif

/// Print "PROG VERSION (git DESCRIBE)\n" on stdout (CDPR_VERSION_STRING, CDPR_GIT_DESCRIBE).
void cdpr_app_print_version(const char *prog);

/// Print "PROG: MESSAGE; try 'PROG --help'" on stderr (MESSAGE: printf format and arguments).
/// Returns CDPR_E_INVALID_ARG.
cdpr_status_t cdpr_app_usage_error(const char *prog, const char *fmt, ...) CDPR_APP_PRINTF(2, 3);

/// After getopt_long (opterr = 0, CDPR_APP_OPTSTRING) returned `c`, '?' or ':': print the one
/// line (unrecognized option '--frob', option '--out' requires an argument, option '--quiet'
/// doesn't allow an argument, option '--p' is ambiguous, invalid option -- 'x'; each followed
/// by "; try 'PROG --help'"). `longopts` is the table given to getopt_long. Returns
/// CDPR_E_INVALID_ARG.
cdpr_status_t cdpr_app_bad_option(const char *prog, int c, char *const argv[],
                                  const struct option *longopts);

/// The `default:` of every app's getopt switch: `c` = 'h' prints `usage` on stdout and exits 0,
/// CDPR_APP_OPT_VERSION prints the version line and exits 0, anything else is the one-line
/// usage error of cdpr_app_bad_option. Returns CDPR_E_INVALID_ARG (it only returns for errors).
cdpr_status_t cdpr_app_other_option(const char *prog, int c, char *const argv[],
                                    const struct option *longopts, void (*usage)(FILE *));

/// An app's own options, for cdpr_app_parse: called with each getopt_long code `c` that is
/// not a usage error (and its argument, NULL for a flag). Returns 0 when it took the option,
/// 1 when `c` is not one of its options (cdpr_app_other_option then handles it: --help,
/// --version), or -1 after printing a usage error (a bad argument).
typedef int (*cdpr_app_option_fn)(int c, const char *arg, void *ctx);

/// An option that only stores, for cdpr_app_store: a text option's argument goes to *text; a
/// flag (text NULL) sets *flag = value.
typedef struct {
    int code;          ///< the getopt_long code
    const char **text; ///< where the argument goes, or NULL for a flag
    int *flag;         ///< where `value` goes (a flag)
    int value;         ///< a flag's value
} cdpr_app_store_t;

/// The stored options of a cdpr_app_option_fn: when `c` is the code of one of the `n` entries
/// of `stores`, store as it says and return 0; else return 1 (the caller's other options).
int cdpr_app_store(const cdpr_app_store_t *stores, size_t n, int c, const char *arg);

/// The getopt_long loop of every app: opterr = 0, CDPR_APP_OPTSTRING, `longopts`; each code to
/// `take(c, optarg, ctx)`, what it does not take to cdpr_app_other_option (which exits 0 for
/// --help and --version). Returns 0 when every option was taken (optind then indexes the first
/// operand), or -1 after the one-line usage error.
int cdpr_app_parse(const char *prog, int argc, char **argv, const struct option *longopts,
                   void (*usage)(FILE *), cdpr_app_option_fn take, void *ctx);

/// The one operand of the scenario-running apps: `*scenario` = argv[optind], CDPR_OK; or the
/// one-line usage error for a missing or an extra operand (CDPR_E_INVALID_ARG).
cdpr_status_t cdpr_app_scenario_operand(const char *prog, int argc, char *const argv[],
                                        const char **scenario);

/// Path of data file `rel` (relative to the data directory <prefix>/share/cdpr, e.g.
/// "scripts/plot_sim.gp") into `buf`: the first that exists of
///   1. <directory of the executable>/../share/cdpr/rel (the installation this executable is
///      part of, wherever the prefix was moved; /proc/self/exe),
///   2. the source tree's rel (CDPR_SOURCE_DIR: an executable run from its build tree),
///   3. the configured data directory's rel (CDPR_DATA_DIR: the executable copied elsewhere).
/// Returns CDPR_OK, or CDPR_E_IO when none exists (buf then holds candidate 1, or 2 when the
/// executable's path is unknown, for the message), or CDPR_E_INVALID_ARG when a path does not
/// fit in `cap` bytes.
cdpr_status_t cdpr_app_data_file(const char *rel, char *buf, size_t cap);

/// The directory of the running executable (/proc/self/exe, links resolved) into `dir`:
/// CDPR_OK, or CDPR_E_IO when it cannot be read or does not fit in `cap` bytes. Where the apps
/// find each other (cdpr-design next to cdpr-sim) and their data (cdpr_app_data_file).
cdpr_status_t cdpr_app_exe_dir(char *dir, size_t cap);

#endif /* CDPR_APP_CLI_H */
