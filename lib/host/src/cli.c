/// @file cli.c
/// Command-line helpers (cli.h).
#include "cdpr/host/cli.h"

#include <errno.h>
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

cdpr_status_t cdpr_cli_number(const char *prog, const char *opt, const char *arg, double lo,
                              double hi, double *out)
{
    char *end = NULL;
    errno = 0;
    const double v = strtod(arg, &end);
    if (end == arg || *end != '\0') {
        fprintf(stderr, "%s: --%s: not a number: '%s'\n", prog, opt, arg);
        return CDPR_E_INVALID_ARG;
    }
    if (errno != ERANGE && !isfinite(v)) {
        fprintf(stderr, "%s: --%s: not a finite number: '%s'\n", prog, opt, arg);
        return CDPR_E_NOT_FINITE;
    }
    if (errno == ERANGE || !(v >= lo && v <= hi)) {
        fprintf(stderr, "%s: --%s: '%s' is outside [%g, %g]\n", prog, opt, arg, lo, hi);
        return CDPR_E_OUT_OF_RANGE;
    }
    *out = v;
    return CDPR_OK;
}

cdpr_status_t cdpr_cli_real(const char *prog, const char *opt, const char *arg, double *out)
{
    return cdpr_cli_number(prog, opt, arg, -DBL_MAX, DBL_MAX, out);
}
