/* SPDX-License-Identifier: BSD-3-Clause */
/// @file app_status.c
/// Status -> exit code (app_status.h).
#include "app_status.h"

int cdpr_app_exit_code(cdpr_status_t st)
{
    switch (st) {
    case CDPR_OK:
    case CDPR_WARN_SUBSTEP_LIMIT:
    case CDPR_WARN_CAPACITY:
    case CDPR_WARN_MIN_LENGTH:
        return CDPR_EXIT_OK;
    case CDPR_E_INTERRUPTED:
    case CDPR_E_MISMATCH:
    case CDPR_E_STATE_NOT_FINITE:
    case CDPR_E_STEP_TOO_SMALL:
    case CDPR_E_RHS:
    case CDPR_E_SUBSTEP_LIMIT:
    case CDPR_E_SINGULAR:
        return CDPR_EXIT_STOPPED;
    case CDPR_E_INVALID_ARG:
    case CDPR_E_NOT_FINITE:
    case CDPR_E_NOT_POSITIVE:
    case CDPR_E_OUT_OF_RANGE:
    case CDPR_E_CAPACITY:
    case CDPR_E_GEOMETRY:
    case CDPR_E_NO_CONVERGENCE:
    case CDPR_E_INFEASIBLE:
    case CDPR_E_PARSE:
        return CDPR_EXIT_INPUT;
    case CDPR_E_IO:
        return CDPR_EXIT_IO;
    case CDPR_E_CONFLICT:
        return CDPR_EXIT_CONFLICT;
    default:
        return CDPR_EXIT_UNKNOWN;
    }
}
