/// @file cli.c
/// Command-line helpers (cli.h).
#include "cdpr/host/cli.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>

int cdpr_cli_number(const char *prog, const char *opt, const char *arg, double lo, double hi,
                    double *out)
{
    char *end = NULL;
    errno = 0;
    const double v = strtod(arg, &end);
    if (errno != 0 || end == arg || *end != '\0' || !(v >= lo && v <= hi)) {
        fprintf(stderr, "%s: --%s: not a number in [%g, %g]: '%s'\n", prog, opt, lo, hi, arg);
        return -1;
    }
    *out = v;
    return 0;
}
