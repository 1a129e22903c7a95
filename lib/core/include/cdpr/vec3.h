/* SPDX-License-Identifier: BSD-3-Clause */
/// @file vec3.h
/// Small 3-vector, 3x3 matrix and unit-quaternion helpers.
///
/// Value types, no allocation, no state. Quaternions are (w, x, y, z), body -> world.
/// Euler angles follow docs/model.md "Frames and geometry": R = Rz(gamma) * Ry(beta) * Rx(alpha)
/// (fixed axes X-Y-Z).
///
/// Every function here is O(1), allocates nothing and cannot fail: NaN/Inf inputs propagate to
/// the result (exceptions: cdpr_m3_inverse and cdpr_quat_normalize, below). Pointer arguments
/// must be valid.
#ifndef CDPR_VEC3_H
#define CDPR_VEC3_H

#include "cdpr/config.h"

typedef struct {
    cdpr_real_t x;
    cdpr_real_t y;
    cdpr_real_t z;
} cdpr_vec3_t;

typedef struct {
    cdpr_real_t m[3][3]; ///< row-major: m[row][col]
} cdpr_mat3_t;

typedef struct {
    cdpr_real_t w;
    cdpr_real_t x;
    cdpr_real_t y;
    cdpr_real_t z;
} cdpr_quat_t;

static inline cdpr_vec3_t cdpr_v3(cdpr_real_t x, cdpr_real_t y, cdpr_real_t z)
{
    cdpr_vec3_t r;
    r.x = x;
    r.y = y;
    r.z = z;
    return r;
}

/// The vector (a[0], a[1], a[2]).
static inline cdpr_vec3_t cdpr_v3_load(const cdpr_real_t *a)
{
    return cdpr_v3(a[0], a[1], a[2]);
}

/// out[0..2] = (v.x, v.y, v.z).
static inline void cdpr_v3_store(cdpr_vec3_t v, cdpr_real_t *out)
{
    out[0] = v.x;
    out[1] = v.y;
    out[2] = v.z;
}

static inline cdpr_vec3_t cdpr_v3_add(cdpr_vec3_t a, cdpr_vec3_t b)
{
    return cdpr_v3(a.x + b.x, a.y + b.y, a.z + b.z);
}

static inline cdpr_vec3_t cdpr_v3_sub(cdpr_vec3_t a, cdpr_vec3_t b)
{
    return cdpr_v3(a.x - b.x, a.y - b.y, a.z - b.z);
}

static inline cdpr_vec3_t cdpr_v3_scale(cdpr_vec3_t a, cdpr_real_t s)
{
    return cdpr_v3(a.x * s, a.y * s, a.z * s);
}

static inline cdpr_real_t cdpr_v3_dot(cdpr_vec3_t a, cdpr_vec3_t b)
{
    return a.x * b.x + a.y * b.y + a.z * b.z;
}

static inline cdpr_vec3_t cdpr_v3_cross(cdpr_vec3_t a, cdpr_vec3_t b)
{
    return cdpr_v3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}

/// Euclidean norm [same unit as a].
cdpr_real_t cdpr_v3_norm(cdpr_vec3_t a);

/// 1 if every component is finite, else 0.
int cdpr_v3_isfinite(cdpr_vec3_t a);

/// m * a.
cdpr_vec3_t cdpr_m3_mul_v3(const cdpr_mat3_t *m, cdpr_vec3_t a);

/// m^T * a.
cdpr_vec3_t cdpr_m3t_mul_v3(const cdpr_mat3_t *m, cdpr_vec3_t a);

/// Inverse of a 3x3 matrix by cofactors. Returns 0 on success, -1 if |det| is not above
/// `min_abs_det` or is NaN (out unchanged).
int cdpr_m3_inverse(const cdpr_mat3_t *m, cdpr_real_t min_abs_det, cdpr_mat3_t *out);

/// Hamilton product a (x) b.
cdpr_quat_t cdpr_quat_mul(cdpr_quat_t a, cdpr_quat_t b);

/// q / |q|. A quaternion whose norm is not > 0 (zero, or NaN) yields the identity; one with an
/// infinite component gives NaN.
cdpr_quat_t cdpr_quat_normalize(cdpr_quat_t q);

/// Rotation matrix of a unit quaternion (body -> world).
void cdpr_quat_to_mat3(cdpr_quat_t q, cdpr_mat3_t *r);

/// Quaternion of R = Rz(gamma) Ry(beta) Rx(alpha) [rad].
cdpr_quat_t cdpr_quat_from_euler(cdpr_real_t alpha_rad, cdpr_real_t beta_rad,
                                 cdpr_real_t gamma_rad);

/// Inverse of cdpr_quat_from_euler for the normalised q: alpha, gamma in (-pi, pi], beta in
/// [-pi/2, pi/2]. At beta = +-pi/2 (gimbal lock) R does not determine alpha and gamma
/// separately: the pair returned comes from rounding and need not reproduce q.
void cdpr_quat_to_euler(cdpr_quat_t q, cdpr_real_t *alpha_rad, cdpr_real_t *beta_rad,
                        cdpr_real_t *gamma_rad);

/// Rotation vector θ of the unit quaternion q: axis times angle, |θ| <= π (q and -q give the
/// same θ). For the error q_d q^-1 of two attitudes it is the error in world axes [rad].
cdpr_vec3_t cdpr_quat_to_rotvec(cdpr_quat_t q);

#endif /* CDPR_VEC3_H */
