/// @file cli.h
/// Command-line helpers shared by the host apps (getopt_long does the parsing).
#ifndef CDPR_HOST_CLI_H
#define CDPR_HOST_CLI_H

/// Parse option `--opt`'s argument `arg` as a number in [lo, hi] (strtod, the whole string).
/// Returns 0 with *out set, or -1 after printing "PROG: --OPT: not a number in [lo, hi]: 'ARG'"
/// to stderr (*out unchanged).
int cdpr_cli_number(const char *prog, const char *opt, const char *arg, double lo, double hi,
                    double *out);

#endif /* CDPR_HOST_CLI_H */
