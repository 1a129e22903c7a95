/* SPDX-License-Identifier: BSD-3-Clause */
/// @file app_status.h
/// The apps' one table from library statuses (cdpr_status_t) to process exit codes. Libraries
/// return statuses, never exit codes; every app ends with `return cdpr_app_exit_code(st);`.
///
///   exit 0  CDPR_OK and every warning (CDPR_WARN_*): the run completed
///   exit 1  the run stopped early or did not reproduce its reference: CDPR_E_INTERRUPTED (a
///           signal), CDPR_E_MISMATCH (a replay check failed), and the integrator's
///           CDPR_E_STATE_NOT_FINITE, CDPR_E_STEP_TOO_SMALL, CDPR_E_RHS, CDPR_E_SUBSTEP_LIMIT
///   exit 2  bad input (command line, scenario or robot values): CDPR_E_INVALID_ARG,
///           CDPR_E_NOT_FINITE, CDPR_E_NOT_POSITIVE, CDPR_E_OUT_OF_RANGE, CDPR_E_CAPACITY,
///           CDPR_E_GEOMETRY, CDPR_E_NO_CONVERGENCE, CDPR_E_INFEASIBLE, CDPR_E_PARSE
///   exit 3  an operating-system resource failed: CDPR_E_IO (file, socket, thread, LCM)
///   exit 4  any other value (a status this table does not know: a bug)
///   exit 5  the run shared its channels with another peer of the same role: CDPR_E_CONFLICT
///           (cdpr-rt saw another plant's messages on its channels; docs/realtime.md)
#ifndef CDPR_APP_STATUS_H
#define CDPR_APP_STATUS_H

#include "cdpr/status.h"

/// Exit codes of the apps (the table above).
enum {
    CDPR_EXIT_OK = 0,
    CDPR_EXIT_STOPPED = 1,
    CDPR_EXIT_INPUT = 2,
    CDPR_EXIT_IO = 3,
    CDPR_EXIT_UNKNOWN = 4,
    CDPR_EXIT_CONFLICT = 5
};

/// Exit code of status `st` (the table above).
int cdpr_app_exit_code(cdpr_status_t st);

#endif /* CDPR_APP_STATUS_H */
