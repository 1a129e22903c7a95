/* SPDX-License-Identifier: BSD-3-Clause */
/// @file status.h
/// One status enum for every library of the project, and the diagnostic that names the first
/// bad field.
///
/// Zero is success, positive is success with a caveat (a warning: the result is valid but an
/// accuracy or capacity bound was hit), negative is an error. After an error a transactional
/// call (cdpr_rkf45_advance, cdpr_plant_step, every *_init's output object) leaves the state it
/// integrates as it was; what a call does leave behind on error (counters, a learned step
/// size, an iteration count) is stated in its header. The core
/// returns CDPR_OK .. CDPR_E_SUBSTEP_LIMIT and CDPR_E_SINGULAR; the host layers (files, LCM,
/// threads) add CDPR_E_IO, CDPR_E_PARSE, CDPR_E_INTERRUPTED, CDPR_E_MISMATCH and CDPR_E_CONFLICT.
/// Libraries return these; only the apps map them to process exit codes (one table, docs/api.md).
#ifndef CDPR_STATUS_H
#define CDPR_STATUS_H

typedef enum {
    CDPR_OK = 0,
    CDPR_WARN_SUBSTEP_LIMIT = 1,  ///< advance reached t+dt, but some substeps missed the tolerance
    CDPR_WARN_CAPACITY = 2,       ///< node capacity reached: last segment keeps growing
    CDPR_WARN_MIN_LENGTH = 3,     ///< a winch reached its minimum cable length and stopped
    CDPR_E_INVALID_ARG = -1,      ///< NULL pointer or argument outside its domain
    CDPR_E_NOT_FINITE = -2,       ///< a parameter or input is NaN or infinite
    CDPR_E_NOT_POSITIVE = -3,     ///< a physical quantity that must be > 0 is not
    CDPR_E_OUT_OF_RANGE = -4,     ///< a value outside its documented range
    CDPR_E_CAPACITY = -5,         ///< a count exceeds a compile-time capacity
    CDPR_E_GEOMETRY = -6,         ///< inconsistent geometry (e.g. coincident end points)
    CDPR_E_STATE_NOT_FINITE = -7, ///< NaN/Inf appeared in the state; step undone
    CDPR_E_STEP_TOO_SMALL = -8,   ///< the step size fell below its lower bound; step undone
    CDPR_E_RHS = -9,              ///< the right-hand side refused to evaluate; step undone
    CDPR_E_NO_CONVERGENCE = -10,  ///< an iterative solver hit its iteration bound
    CDPR_E_INFEASIBLE = -11,      ///< no solution with all cables in tension
    CDPR_E_SUBSTEP_LIMIT = -12,   ///< advance could not reach t+dt stably within its trial bound
    CDPR_E_IO = -13,              ///< host: a file, socket, thread or LCM provider failed
    CDPR_E_PARSE = -14,           ///< host: an input file is malformed (syntax, key, type)
    CDPR_E_INTERRUPTED = -15,     ///< host: stopped early on request (a signal); work kept
    CDPR_E_MISMATCH = -16,        ///< host: a result differs from its reference (replay check)
    CDPR_E_SINGULAR = -17,        ///< a linear system (W of ros34pw2.h) is singular or not finite
    CDPR_E_CONFLICT = -18         ///< host: another peer of the same role on the channel
} cdpr_status_t;

/// Name of a status ("CDPR_E_GEOMETRY"). Never NULL (unknown values give "CDPR_UNKNOWN").
/// O(1); no allocation; cannot fail.
const char *cdpr_status_str(cdpr_status_t st);

/// Diagnostic filled by validation: the first offending field and its index.
typedef struct {
    cdpr_status_t status; ///< same value the function returned
    const char *field;    ///< static string naming the field ("ea_N", "exit_point"), or ""
    int index;            ///< array index / cable number of the field, or -1
} cdpr_diag_t;

/// Write a diagnostic if `diag` is not NULL; returns `st` for tail calls. O(1); cannot fail.
cdpr_status_t cdpr_diag_set(cdpr_diag_t *diag, cdpr_status_t st, const char *field, int index);

#endif /* CDPR_STATUS_H */
