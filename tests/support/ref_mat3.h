/* SPDX-License-Identifier: BSD-3-Clause */
/// @file ref_mat3.h
/// Test-only reference 3x3 linear algebra, written from definitions and independent of the
/// core's vec3.h, so tests can check the core against it. Header-only (static inline).
#ifndef CDPR_TEST_REF_MAT3_H
#define CDPR_TEST_REF_MAT3_H

#include <math.h>

typedef struct {
    double m[3][3];
} mat_t;

static inline mat_t mat_mul(const mat_t *a, const mat_t *b)
{
    mat_t r;
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            double s = 0.0;
            for (int k = 0; k < 3; ++k) {
                s += a->m[i][k] * b->m[k][j];
            }
            r.m[i][j] = s;
        }
    }
    return r;
}

/* Elementary rotations written out from their definitions. */
static inline mat_t rot_x(double a)
{
    const mat_t r = {{{1.0, 0.0, 0.0}, {0.0, cos(a), -sin(a)}, {0.0, sin(a), cos(a)}}};
    return r;
}

static inline mat_t rot_y(double b)
{
    const mat_t r = {{{cos(b), 0.0, sin(b)}, {0.0, 1.0, 0.0}, {-sin(b), 0.0, cos(b)}}};
    return r;
}

static inline mat_t rot_z(double g)
{
    const mat_t r = {{{cos(g), -sin(g), 0.0}, {sin(g), cos(g), 0.0}, {0.0, 0.0, 1.0}}};
    return r;
}

/* docs/model.md §1: R = Rz(gamma) Ry(beta) Rx(alpha), built by explicit matrix products. */
static inline mat_t euler_matrix(double a, double b, double g)
{
    const mat_t rz = rot_z(g);
    const mat_t ry = rot_y(b);
    const mat_t rx = rot_x(a);
    const mat_t zy = mat_mul(&rz, &ry);
    return mat_mul(&zy, &rx);
}

#endif /* CDPR_TEST_REF_MAT3_H */
