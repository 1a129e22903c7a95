/* SPDX-License-Identifier: BSD-3-Clause */
/// @file status.c
/// Status names and the diagnostic helper.
#include "cdpr/status.h"

#include <stddef.h>

const char *cdpr_status_str(cdpr_status_t st)
{
    switch (st) {
    case CDPR_OK:
        return "CDPR_OK";
    case CDPR_WARN_SUBSTEP_LIMIT:
        return "CDPR_WARN_SUBSTEP_LIMIT";
    case CDPR_WARN_CAPACITY:
        return "CDPR_WARN_CAPACITY";
    case CDPR_WARN_MIN_LENGTH:
        return "CDPR_WARN_MIN_LENGTH";
    case CDPR_E_INVALID_ARG:
        return "CDPR_E_INVALID_ARG";
    case CDPR_E_NOT_FINITE:
        return "CDPR_E_NOT_FINITE";
    case CDPR_E_NOT_POSITIVE:
        return "CDPR_E_NOT_POSITIVE";
    case CDPR_E_OUT_OF_RANGE:
        return "CDPR_E_OUT_OF_RANGE";
    case CDPR_E_CAPACITY:
        return "CDPR_E_CAPACITY";
    case CDPR_E_GEOMETRY:
        return "CDPR_E_GEOMETRY";
    case CDPR_E_STATE_NOT_FINITE:
        return "CDPR_E_STATE_NOT_FINITE";
    case CDPR_E_STEP_TOO_SMALL:
        return "CDPR_E_STEP_TOO_SMALL";
    case CDPR_E_RHS:
        return "CDPR_E_RHS";
    case CDPR_E_NO_CONVERGENCE:
        return "CDPR_E_NO_CONVERGENCE";
    case CDPR_E_INFEASIBLE:
        return "CDPR_E_INFEASIBLE";
    case CDPR_E_SUBSTEP_LIMIT:
        return "CDPR_E_SUBSTEP_LIMIT";
    case CDPR_E_IO:
        return "CDPR_E_IO";
    case CDPR_E_PARSE:
        return "CDPR_E_PARSE";
    case CDPR_E_INTERRUPTED:
        return "CDPR_E_INTERRUPTED";
    case CDPR_E_MISMATCH:
        return "CDPR_E_MISMATCH";
    case CDPR_E_SINGULAR:
        return "CDPR_E_SINGULAR";
    case CDPR_E_CONFLICT:
        return "CDPR_E_CONFLICT";
    default:
        return "CDPR_UNKNOWN";
    }
}

cdpr_status_t cdpr_diag_set(cdpr_diag_t *diag, cdpr_status_t st, const char *field, int index)
{
    if (diag != NULL) {
        diag->status = st;
        diag->field = (field != NULL) ? field : "";
        diag->index = index;
    }
    return st;
}
