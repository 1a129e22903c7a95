/* SPDX-License-Identifier: BSD-3-Clause */
/// @file check.h
/// Internal validation helpers shared by the core's *_validate functions (not installed).
#ifndef CDPR_CHECK_H
#define CDPR_CHECK_H

#include <math.h>

#include "cdpr/status.h"
#include "cdpr/vec3.h"

/// CDPR_OK if x is finite and > 0, else the error (diag names `field`, `index`).
static inline cdpr_status_t check_positive(cdpr_real_t x, const char *field, int index,
                                           cdpr_diag_t *diag)
{
    if (!isfinite(x)) {
        return cdpr_diag_set(diag, CDPR_E_NOT_FINITE, field, index);
    }
    if (!(x > CDPR_R(0.0))) {
        return cdpr_diag_set(diag, CDPR_E_NOT_POSITIVE, field, index);
    }
    return CDPR_OK;
}

/// CDPR_OK if x is finite and >= 0.
static inline cdpr_status_t check_nonnegative(cdpr_real_t x, const char *field, int index,
                                              cdpr_diag_t *diag)
{
    if (!isfinite(x)) {
        return cdpr_diag_set(diag, CDPR_E_NOT_FINITE, field, index);
    }
    if (x < CDPR_R(0.0)) {
        return cdpr_diag_set(diag, CDPR_E_OUT_OF_RANGE, field, index);
    }
    return CDPR_OK;
}

/// CDPR_OK if x is finite.
static inline cdpr_status_t check_finite(cdpr_real_t x, const char *field, int index,
                                         cdpr_diag_t *diag)
{
    if (!isfinite(x)) {
        return cdpr_diag_set(diag, CDPR_E_NOT_FINITE, field, index);
    }
    return CDPR_OK;
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

/// Step-control settings shared by the adaptive integrators (rkf45.h, ros34pw2.h).
typedef struct {
    cdpr_real_t rtol;
    cdpr_real_t atol;
    const cdpr_real_t *atol_vec;
    cdpr_real_t h_init_s;
    cdpr_real_t h_min_s;
    cdpr_real_t h_max_s;
    cdpr_real_t safety;
    cdpr_real_t shrink_min;
    cdpr_real_t grow_max;
    cdpr_real_t force_err_max;
} check_step_t;

/// Validate step-control settings (the integrators' documented ranges; `diag` names the field,
/// index = component for atol_vec).
static inline cdpr_status_t check_step_control(const check_step_t *p, int dim, cdpr_diag_t *diag)
{
    CDPR_TRY(check_nonnegative(p->rtol, "rtol", -1, diag));
    CDPR_TRY(check_positive(p->atol, "atol", -1, diag));
    if (p->atol_vec != NULL) {
        for (int i = 0; i < dim; ++i) {
            CDPR_TRY(check_positive(p->atol_vec[i], "atol_vec", i, diag));
        }
    }
    CDPR_TRY(check_positive(p->h_init_s, "h_init_s", -1, diag));
    CDPR_TRY(check_positive(p->h_min_s, "h_min_s", -1, diag));
    CDPR_TRY(check_positive(p->h_max_s, "h_max_s", -1, diag));
    if (p->h_max_s < p->h_min_s) {
        return cdpr_diag_set(diag, CDPR_E_OUT_OF_RANGE, "h_max_s", -1);
    }
    CDPR_TRY(check_positive(p->safety, "safety", -1, diag));
    if (!(p->safety < CDPR_R(1.0))) {
        return cdpr_diag_set(diag, CDPR_E_OUT_OF_RANGE, "safety", -1);
    }
    CDPR_TRY(check_positive(p->shrink_min, "shrink_min", -1, diag));
    if (!(p->shrink_min < CDPR_R(1.0))) {
        return cdpr_diag_set(diag, CDPR_E_OUT_OF_RANGE, "shrink_min", -1);
    }
    CDPR_TRY(check_finite(p->grow_max, "grow_max", -1, diag));
    if (!(p->grow_max > CDPR_R(1.0))) {
        return cdpr_diag_set(diag, CDPR_E_OUT_OF_RANGE, "grow_max", -1);
    }
    CDPR_TRY(check_finite(p->force_err_max, "force_err_max", -1, diag));
    if (!(p->force_err_max >= CDPR_R(1.0))) {
        return cdpr_diag_set(diag, CDPR_E_OUT_OF_RANGE, "force_err_max", -1);
    }
    return CDPR_OK;
}

#endif /* CDPR_CHECK_H */
