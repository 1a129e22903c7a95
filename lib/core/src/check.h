/* SPDX-License-Identifier: BSD-3-Clause */
/// @file check.h
/// Internal validation helpers shared by the core's *_validate functions (not installed).
#ifndef CDPR_CHECK_H
#define CDPR_CHECK_H

#include <math.h>

#include "cdpr/status.h"
#include "cdpr/vec3.h"

/// CDPR_E_NOT_FINITE if x is not finite, else `st_bad` if `bad` != 0, else CDPR_OK (diag
/// names `field`, `index`).
static inline cdpr_status_t check_value(cdpr_real_t x, int bad, cdpr_status_t st_bad,
                                        const char *field, int index, cdpr_diag_t *diag)
{
    if (!isfinite(x)) {
        return cdpr_diag_set(diag, CDPR_E_NOT_FINITE, field, index);
    }
    if (bad != 0) {
        return cdpr_diag_set(diag, st_bad, field, index);
    }
    return CDPR_OK;
}

/// CDPR_OK if x is finite and > 0, else the error (diag names `field`, `index`).
static inline cdpr_status_t check_positive(cdpr_real_t x, const char *field, int index,
                                           cdpr_diag_t *diag)
{
    return check_value(x, (x > CDPR_R(0.0)) ? 0 : 1, CDPR_E_NOT_POSITIVE, field, index, diag);
}

/// CDPR_OK if x is finite and >= 0.
static inline cdpr_status_t check_nonnegative(cdpr_real_t x, const char *field, int index,
                                              cdpr_diag_t *diag)
{
    return check_value(x, (x < CDPR_R(0.0)) ? 1 : 0, CDPR_E_OUT_OF_RANGE, field, index, diag);
}

/// CDPR_OK if x is finite.
static inline cdpr_status_t check_finite(cdpr_real_t x, const char *field, int index,
                                         cdpr_diag_t *diag)
{
    return check_value(x, 0, CDPR_OK, field, index, diag);
}

/// CDPR_OK if every component of v is finite.
static inline cdpr_status_t check_finite_v3(cdpr_vec3_t v, const char *field, int index,
                                            cdpr_diag_t *diag)
{
    if (cdpr_v3_isfinite(v) == 0) {
        return cdpr_diag_set(diag, CDPR_E_NOT_FINITE, field, index);
    }
    return CDPR_OK;
}

/* Evaluate a check and return its status from the enclosing function if it failed. */
#define CDPR_TRY(expr)                                                                             \
    do {                                                                                           \
        const cdpr_status_t try_st_ = (expr);                                                      \
        if (try_st_ != CDPR_OK) {                                                                  \
            return try_st_;                                                                        \
        }                                                                                          \
    } while (0)

#endif /* CDPR_CHECK_H */
