/* SPDX-License-Identifier: BSD-3-Clause */
/// @file step_control.h
/// Step-size control shared by the adaptive integrators (rkf45.h, ros34pw2.h): the settings
/// block every scheme takes, its documented ranges, and the counters every scheme keeps.
///
/// A trial of step h from y to y_new with error estimate e is accepted when
///   max_i |e_i| / (atol_i + rtol * max(|y_i|, |y_new_i|)) <= 1,
/// and the next step is h * clamp(safety * err^(-1/q), shrink_min, grow_max) within
/// [h_min_s, h_max_s], q the order of the error estimate's leading term in h (5 for RKF45's
/// embedded 4th-order solution, 3 for ROS34PW2's embedded order 2). A new scheme takes a
/// cdpr_step_control_t in its settings and a cdpr_step_stats_t in its solver object: what a
/// caller sets and reads is then the same whatever the scheme. Nothing allocates; O(1) unless
/// stated.
///
/// The contract every adaptive scheme's functions keep (rkf45.h, ros34pw2.h):
/// - `..._params_validate(p, dim, diag)`: O(dim) with atol_vec, else O(1). Returns, for the
///   first bad field (`diag`, may be NULL, names it by its member name; index -1, or the
///   component for atol_vec), CDPR_E_INVALID_ARG when p is NULL (field: the scheme's prefix,
///   "rkf45" or "ros"), then every error of cdpr_step_control_validate(&p->step, dim, diag),
///   then the scheme's own settings' errors; CDPR_OK (diag: status OK, field "", index -1)
///   otherwise.
/// - `..._init(s, p, work, work_len, dim_max, dim, diag)`: a caller workspace of `work_len`
///   reals for states up to `dim_max` components (work_len >= the scheme's WORK_PER_DIM *
///   dim_max), current dimension `dim`. The first step is min(h_init_s, h_max_s); counters are
///   zeroed; the workspace is not touched. O(dim) with atol_vec, else O(1). On error `s` is not
///   written. Returns (diag, may be NULL): CDPR_E_INVALID_ARG when s ("solver") or work
///   ("work") is NULL; CDPR_E_OUT_OF_RANGE when dim_max < 1 ("dim_max", index dim_max);
///   CDPR_E_CAPACITY when dim is outside [1, dim_max] ("dim", index dim) or work_len is too
///   small ("work_len", index work_len); every error of the scheme's params_validate(p, dim);
///   CDPR_OK otherwise.
#ifndef CDPR_STEP_CONTROL_H
#define CDPR_STEP_CONTROL_H

#include "cdpr/config.h"
#include "cdpr/status.h"

/// Step-control settings (inputs). Defaults from cdpr_step_control_default().
typedef struct {
    cdpr_real_t rtol;            ///< relative tolerance (>= 0); default 1e-6
    cdpr_real_t atol;            ///< absolute tolerance used when atol_vec is NULL (> 0); 1e-8
    const cdpr_real_t *atol_vec; ///< optional per-component absolute tolerances (each > 0)
    cdpr_real_t h_init_s;        ///< first step [s] (> 0); default 1e-4
    cdpr_real_t h_min_s;         ///< smallest step before CDPR_E_STEP_TOO_SMALL [s] (> 0); 1e-12
    cdpr_real_t h_max_s;         ///< largest step [s] (>= h_min_s); default 1.0
    cdpr_real_t safety;          ///< step-size safety factor in (0, 1); default 0.9
    cdpr_real_t shrink_min;      ///< smallest step ratio after a rejection, in (0, 1); default 0.2
    cdpr_real_t grow_max;        ///< largest step ratio after an acceptance (> 1); default 5
    /// Largest error norm of a "forced" equal step of an advance call (finite, >= 1; 1 forbids
    /// them). Default (safety / shrink_min)^q of the defaults, 4.5^q: the largest error that the
    /// step-size formula corrects with a single rejection (1845.28125 for RKF45, q = 5; 91.125
    /// for ROS34PW2, q = 3).
    cdpr_real_t force_err_max;
} cdpr_step_control_t;

/// Counters every adaptive scheme keeps (plain fields, read-only for users; reset by the
/// scheme's init).
typedef struct {
    unsigned long steps_accepted;         ///< accepted steps
    unsigned long steps_rejected;         ///< trials rejected by the error test
    unsigned long nonfinite_rejected;     ///< trials rejected because they produced NaN/Inf
    unsigned long rhs_evals;              ///< calls of f
    unsigned long forced_steps;           ///< equal steps accepted above the tolerance (advance)
    unsigned long substep_limit_hits;     ///< advance calls that returned CDPR_WARN_SUBSTEP_LIMIT
    unsigned long substep_limit_failures; ///< advance calls that returned CDPR_E_SUBSTEP_LIMIT
    unsigned long failures;               ///< step/advance calls that returned an error other than
                                          ///< CDPR_E_INVALID_ARG (state restored)
} cdpr_step_stats_t;

/// Documented defaults for a scheme whose error estimate is O(h^q) (`error_order` = q >= 1;
/// a smaller value is taken as 1): every field as listed above, force_err_max =
/// (safety / shrink_min)^q, exact in double and float for q <= 7. Cannot fail.
void cdpr_step_control_default(cdpr_step_control_t *sc, int error_order);

/// Validate the settings against `dim` (the first dim entries of atol_vec when it is given).
/// O(dim) with atol_vec, else O(1). Returns, for the first bad field (`diag`, may be NULL,
/// names it by its member name; index -1, or the component for atol_vec):
/// - CDPR_E_INVALID_ARG: sc is NULL ("step").
/// - CDPR_E_NOT_FINITE: a field, or an atol_vec entry, is NaN/Inf.
/// - CDPR_E_NOT_POSITIVE: atol, an atol_vec entry, h_init_s, h_min_s, h_max_s, safety or
///   shrink_min <= 0.
/// - CDPR_E_OUT_OF_RANGE: rtol < 0, h_max_s < h_min_s, safety >= 1, shrink_min >= 1,
///   grow_max <= 1 or force_err_max < 1.
/// CDPR_OK (diag: status OK, field "", index -1) otherwise.
cdpr_status_t cdpr_step_control_validate(const cdpr_step_control_t *sc, int dim, cdpr_diag_t *diag);

#endif /* CDPR_STEP_CONTROL_H */
