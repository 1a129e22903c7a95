/* SPDX-License-Identifier: BSD-3-Clause */
/// @file step_control.c
/// The step-control settings shared by the adaptive integrators: defaults and validation.
#include "cdpr/step_control.h"

#include <stddef.h>

#include "check.h"

void cdpr_step_control_default(cdpr_step_control_t *sc, int error_order)
{
    sc->rtol = CDPR_R(1e-6);
    sc->atol = CDPR_R(1e-8);
    sc->atol_vec = NULL;
    sc->h_init_s = CDPR_R(1e-4);
    sc->h_min_s = CDPR_R(1e-12);
    sc->h_max_s = CDPR_R(1.0);
    sc->safety = CDPR_R(0.9);
    sc->shrink_min = CDPR_R(0.2);
    sc->grow_max = CDPR_R(5.0);
    /* (safety / shrink_min)^q by repeated products of 4.5 = 9/2: 9^q / 2^q is exact while
     * 9^q fits the significand (q <= 7 in float, 16 in double). */
    const cdpr_real_t ratio = CDPR_R(4.5);
    cdpr_real_t f = ratio;
    for (int i = 1; i < error_order; ++i) {
        f *= ratio;
    }
    sc->force_err_max = f;
}

cdpr_status_t cdpr_step_control_validate(const cdpr_step_control_t *sc, int dim, cdpr_diag_t *diag)
{
    if (sc == NULL) {
        return cdpr_diag_set(diag, CDPR_E_INVALID_ARG, "step", -1);
    }
    CDPR_TRY(check_nonnegative(sc->rtol, "rtol", -1, diag));
    CDPR_TRY(check_positive(sc->atol, "atol", -1, diag));
    if (sc->atol_vec != NULL) {
        for (int i = 0; i < dim; ++i) {
            CDPR_TRY(check_positive(sc->atol_vec[i], "atol_vec", i, diag));
        }
    }
    CDPR_TRY(check_positive(sc->h_init_s, "h_init_s", -1, diag));
    CDPR_TRY(check_positive(sc->h_min_s, "h_min_s", -1, diag));
    CDPR_TRY(check_positive(sc->h_max_s, "h_max_s", -1, diag));
    if (sc->h_max_s < sc->h_min_s) {
        return cdpr_diag_set(diag, CDPR_E_OUT_OF_RANGE, "h_max_s", -1);
    }
    CDPR_TRY(check_positive(sc->safety, "safety", -1, diag));
    if (!(sc->safety < CDPR_R(1.0))) {
        return cdpr_diag_set(diag, CDPR_E_OUT_OF_RANGE, "safety", -1);
    }
    CDPR_TRY(check_positive(sc->shrink_min, "shrink_min", -1, diag));
    if (!(sc->shrink_min < CDPR_R(1.0))) {
        return cdpr_diag_set(diag, CDPR_E_OUT_OF_RANGE, "shrink_min", -1);
    }
    CDPR_TRY(check_finite(sc->grow_max, "grow_max", -1, diag));
    if (!(sc->grow_max > CDPR_R(1.0))) {
        return cdpr_diag_set(diag, CDPR_E_OUT_OF_RANGE, "grow_max", -1);
    }
    CDPR_TRY(check_finite(sc->force_err_max, "force_err_max", -1, diag));
    if (!(sc->force_err_max >= CDPR_R(1.0))) {
        return cdpr_diag_set(diag, CDPR_E_OUT_OF_RANGE, "force_err_max", -1);
    }
    return cdpr_diag_set(diag, CDPR_OK, "", -1);
}
