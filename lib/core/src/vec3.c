/* SPDX-License-Identifier: BSD-3-Clause */
/// @file vec3.c
/// Vector, matrix and quaternion helpers (see vec3.h).
#include "cdpr/vec3.h"

#include <math.h>

cdpr_real_t cdpr_v3_norm(cdpr_vec3_t a)
{
    return CDPR_SQRT(cdpr_v3_dot(a, a));
}

int cdpr_v3_isfinite(cdpr_vec3_t a)
{
    return (isfinite(a.x) && isfinite(a.y) && isfinite(a.z)) ? 1 : 0;
}

cdpr_vec3_t cdpr_m3_mul_v3(const cdpr_mat3_t *m, cdpr_vec3_t a)
{
    return cdpr_v3(m->m[0][0] * a.x + m->m[0][1] * a.y + m->m[0][2] * a.z,
                   m->m[1][0] * a.x + m->m[1][1] * a.y + m->m[1][2] * a.z,
                   m->m[2][0] * a.x + m->m[2][1] * a.y + m->m[2][2] * a.z);
}

cdpr_vec3_t cdpr_m3t_mul_v3(const cdpr_mat3_t *m, cdpr_vec3_t a)
{
    return cdpr_v3(m->m[0][0] * a.x + m->m[1][0] * a.y + m->m[2][0] * a.z,
                   m->m[0][1] * a.x + m->m[1][1] * a.y + m->m[2][1] * a.z,
                   m->m[0][2] * a.x + m->m[1][2] * a.y + m->m[2][2] * a.z);
}

int cdpr_m3_inverse(const cdpr_mat3_t *m, cdpr_real_t min_abs_det, cdpr_mat3_t *out)
{
    const cdpr_real_t(*a)[3] = m->m;
    const cdpr_real_t c00 = a[1][1] * a[2][2] - a[1][2] * a[2][1];
    const cdpr_real_t c01 = a[1][2] * a[2][0] - a[1][0] * a[2][2];
    const cdpr_real_t c02 = a[1][0] * a[2][1] - a[1][1] * a[2][0];
    const cdpr_real_t det = a[0][0] * c00 + a[0][1] * c01 + a[0][2] * c02;
    if (!(CDPR_FABS(det) > min_abs_det)) {
        return -1;
    }
    const cdpr_real_t s = CDPR_R(1.0) / det;
    out->m[0][0] = c00 * s;
    out->m[1][0] = c01 * s;
    out->m[2][0] = c02 * s;
    out->m[0][1] = (a[0][2] * a[2][1] - a[0][1] * a[2][2]) * s;
    out->m[1][1] = (a[0][0] * a[2][2] - a[0][2] * a[2][0]) * s;
    out->m[2][1] = (a[0][1] * a[2][0] - a[0][0] * a[2][1]) * s;
    out->m[0][2] = (a[0][1] * a[1][2] - a[0][2] * a[1][1]) * s;
    out->m[1][2] = (a[0][2] * a[1][0] - a[0][0] * a[1][2]) * s;
    out->m[2][2] = (a[0][0] * a[1][1] - a[0][1] * a[1][0]) * s;
    return 0;
}

cdpr_quat_t cdpr_quat_mul(cdpr_quat_t a, cdpr_quat_t b)
{
    cdpr_quat_t r;
    r.w = a.w * b.w - a.x * b.x - a.y * b.y - a.z * b.z;
    r.x = a.w * b.x + a.x * b.w + a.y * b.z - a.z * b.y;
    r.y = a.w * b.y - a.x * b.z + a.y * b.w + a.z * b.x;
    r.z = a.w * b.z + a.x * b.y - a.y * b.x + a.z * b.w;
    return r;
}

cdpr_quat_t cdpr_quat_normalize(cdpr_quat_t q)
{
    const cdpr_real_t n = CDPR_SQRT(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z);
    cdpr_quat_t r;
    if (!(n > CDPR_R(0.0))) {
        r.w = CDPR_R(1.0);
        r.x = CDPR_R(0.0);
        r.y = CDPR_R(0.0);
        r.z = CDPR_R(0.0);
        return r;
    }
    const cdpr_real_t s = CDPR_R(1.0) / n;
    r.w = q.w * s;
    r.x = q.x * s;
    r.y = q.y * s;
    r.z = q.z * s;
    return r;
}

void cdpr_quat_to_mat3(cdpr_quat_t q, cdpr_mat3_t *r)
{
    const cdpr_real_t ww = q.w * q.w;
    const cdpr_real_t xx = q.x * q.x;
    const cdpr_real_t yy = q.y * q.y;
    const cdpr_real_t zz = q.z * q.z;
    const cdpr_real_t xy = q.x * q.y;
    const cdpr_real_t xz = q.x * q.z;
    const cdpr_real_t yz = q.y * q.z;
    const cdpr_real_t wx = q.w * q.x;
    const cdpr_real_t wy = q.w * q.y;
    const cdpr_real_t wz = q.w * q.z;
    r->m[0][0] = ww + xx - yy - zz;
    r->m[0][1] = CDPR_R(2.0) * (xy - wz);
    r->m[0][2] = CDPR_R(2.0) * (xz + wy);
    r->m[1][0] = CDPR_R(2.0) * (xy + wz);
    r->m[1][1] = ww - xx + yy - zz;
    r->m[1][2] = CDPR_R(2.0) * (yz - wx);
    r->m[2][0] = CDPR_R(2.0) * (xz - wy);
    r->m[2][1] = CDPR_R(2.0) * (yz + wx);
    r->m[2][2] = ww - xx - yy + zz;
}

cdpr_quat_t cdpr_quat_from_euler(cdpr_real_t alpha_rad, cdpr_real_t beta_rad, cdpr_real_t gamma_rad)
{
    /* q = qz(gamma) (x) qy(beta) (x) qx(alpha), matching R = Rz Ry Rx. */
    const cdpr_real_t ca = CDPR_COS(CDPR_R(0.5) * alpha_rad);
    const cdpr_real_t sa = CDPR_SIN(CDPR_R(0.5) * alpha_rad);
    const cdpr_real_t cb = CDPR_COS(CDPR_R(0.5) * beta_rad);
    const cdpr_real_t sb = CDPR_SIN(CDPR_R(0.5) * beta_rad);
    const cdpr_real_t cg = CDPR_COS(CDPR_R(0.5) * gamma_rad);
    const cdpr_real_t sg = CDPR_SIN(CDPR_R(0.5) * gamma_rad);
    cdpr_quat_t q;
    q.w = cg * cb * ca + sg * sb * sa;
    q.x = cg * cb * sa - sg * sb * ca;
    q.y = cg * sb * ca + sg * cb * sa;
    q.z = sg * cb * ca - cg * sb * sa;
    return q;
}

void cdpr_quat_to_euler(cdpr_quat_t q, cdpr_real_t *alpha_rad, cdpr_real_t *beta_rad,
                        cdpr_real_t *gamma_rad)
{
    cdpr_mat3_t r;
    cdpr_quat_to_mat3(cdpr_quat_normalize(q), &r);
    /* R = Rz Ry Rx: R20 = -sin(beta), R21 = cos(beta) sin(alpha), R22 = cos(beta) cos(alpha),
     * R10 = sin(gamma) cos(beta), R00 = cos(gamma) cos(beta). */
    cdpr_real_t s = -r.m[2][0];
    if (s > CDPR_R(1.0)) {
        s = CDPR_R(1.0);
    }
    if (s < CDPR_R(-1.0)) {
        s = CDPR_R(-1.0);
    }
    *beta_rad = CDPR_ASIN(s);
    *alpha_rad = CDPR_ATAN2(r.m[2][1], r.m[2][2]);
    *gamma_rad = CDPR_ATAN2(r.m[1][0], r.m[0][0]);
}

cdpr_vec3_t cdpr_quat_to_rotvec(cdpr_quat_t q)
{
    /* Shortest rotation: q and -q are the same rotation; take w >= 0. */
    if (q.w < CDPR_R(0.0)) {
        q.w = -q.w;
        q.x = -q.x;
        q.y = -q.y;
        q.z = -q.z;
    }
    const cdpr_vec3_t v = cdpr_v3(q.x, q.y, q.z);
    const cdpr_real_t s = cdpr_v3_norm(v);
    if (s < CDPR_R(1e-12)) {
        return cdpr_v3_scale(v, CDPR_R(2.0)); /* angle ~ 2 s, to first order */
    }
    return cdpr_v3_scale(v, CDPR_R(2.0) * CDPR_ATAN2(s, q.w) / s);
}
