/* SPDX-License-Identifier: BSD-3-Clause */
/// @file step.h
/// Internal pieces of step-size control shared by the adaptive integrators (not installed):
/// the setup checks of an init call, the counters' reset and the step-size arithmetic of
/// step_control.h. Static inline: the integrators' inner loops keep them inlined.
#ifndef CDPR_STEP_H
#define CDPR_STEP_H

#include <math.h>
#include <stddef.h>

#include "cdpr/status.h"
#include "cdpr/step_control.h"

/// The checks of an integrator's init call that do not depend on the scheme, in the documented
/// order (diag names the argument): solver or work NULL (CDPR_E_INVALID_ARG, "solver"/"work"),
/// dim_max < 1 (CDPR_E_OUT_OF_RANGE), dim outside [1, dim_max] or work_len below
/// per_dim * dim_max (CDPR_E_CAPACITY). CDPR_OK otherwise (diag not written).
static inline cdpr_status_t step_init_check(const void *solver, const cdpr_real_t *work,
                                            int work_len, int per_dim, int dim_max, int dim,
                                            cdpr_diag_t *diag)
{
    if (solver == NULL || work == NULL) {
        return cdpr_diag_set(diag, CDPR_E_INVALID_ARG, (solver == NULL) ? "solver" : "work", -1);
    }
    if (dim_max < 1) {
        return cdpr_diag_set(diag, CDPR_E_OUT_OF_RANGE, "dim_max", dim_max);
    }
    if (dim < 1 || dim > dim_max) {
        return cdpr_diag_set(diag, CDPR_E_CAPACITY, "dim", dim);
    }
    if ((long)work_len < (long)per_dim * (long)dim_max) {
        return cdpr_diag_set(diag, CDPR_E_CAPACITY, "work_len", work_len);
    }
    return CDPR_OK;
}

/// Zero every counter.
static inline void step_stats_reset(cdpr_step_stats_t *st)
{
    st->steps_accepted = 0;
    st->steps_rejected = 0;
    st->nonfinite_rejected = 0;
    st->rhs_evals = 0;
    st->forced_steps = 0;
    st->substep_limit_hits = 0;
    st->substep_limit_failures = 0;
    st->failures = 0;
}

static inline cdpr_real_t step_clamp(cdpr_real_t x, cdpr_real_t lo, cdpr_real_t hi)
{
    return (x < lo) ? lo : ((x > hi) ? hi : x);
}

/// The first step of a solver: min(h_init_s, h_max_s).
static inline cdpr_real_t step_first(const cdpr_step_control_t *sc)
{
    return (sc->h_init_s < sc->h_max_s) ? sc->h_init_s : sc->h_max_s;
}

/// The controller's next step from h_s, within [h_min_s, h_max_s].
static inline cdpr_real_t step_bounded(const cdpr_step_control_t *sc, cdpr_real_t h_s)
{
    return step_clamp(h_s, sc->h_min_s, sc->h_max_s);
}

/// Elementary step-size factor from the error norm: safety err^expo clamped to
/// [shrink_min, grow_max], expo = -1/q; grow_max for err <= 0 or NaN.
static inline cdpr_real_t step_factor(const cdpr_step_control_t *sc, cdpr_real_t err,
                                      cdpr_real_t expo)
{
    if (!(err > CDPR_R(0.0))) {
        return sc->grow_max;
    }
    const cdpr_real_t fac = sc->safety * CDPR_POW(err, expo);
    return step_clamp(fac, sc->shrink_min, sc->grow_max);
}

/// 1 if `budget` accepted steps starting at h, each growing by grow_max (capped at h_max),
/// could cover `remaining`. An advance call gives up the adaptive steps for equal steps only
/// when even this cannot reach the end: a step size that collapsed at a kink of the RHS (a
/// slack segment turning taut) recovers geometrically and is given the chance. O(budget).
static inline int step_can_reach(const cdpr_step_control_t *sc, cdpr_real_t h, int budget,
                                 cdpr_real_t remaining)
{
    cdpr_real_t sum = CDPR_R(0.0);
    cdpr_real_t hi = (h < sc->h_max_s) ? h : sc->h_max_s;
    for (int i = 0; i < budget; ++i) {
        sum += hi;
        if (sum >= remaining) {
            return 1;
        }
        hi *= sc->grow_max;
        hi = (hi < sc->h_max_s) ? hi : sc->h_max_s;
    }
    return 0;
}

/// 1 if the n components of v are finite.
static inline int step_all_finite(const cdpr_real_t *v, int n)
{
    for (int i = 0; i < n; ++i) {
        if (!isfinite(v[i])) {
            return 0;
        }
    }
    return 1;
}

static inline void step_copy(cdpr_real_t *dst, const cdpr_real_t *src, int n)
{
    for (int i = 0; i < n; ++i) {
        dst[i] = src[i];
    }
}

#endif /* CDPR_STEP_H */
