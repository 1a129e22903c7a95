/* SPDX-License-Identifier: BSD-3-Clause */
/// @file gsl_statics.c
/// Sag-aware IK with gsl_multiroot (see gsl_statics.h).
#include "cdpr/gsl/statics.h"

#include <math.h>
#include <stddef.h>

#include <gsl/gsl_errno.h>
#include <gsl/gsl_linalg.h>
#include <gsl/gsl_matrix.h>
#include <gsl/gsl_multiroots.h>
#include <gsl/gsl_permutation.h>
#include <gsl/gsl_vector.h>

#include "cdpr/catenary.h"

enum { NCAB = 6, NUNK = 18 };

typedef struct {
    const cdpr_robot_t *r;
    cdpr_vec3_t P[NCAB];   /* attachment, world */
    cdpr_vec3_t arm[NCAB]; /* R (b - c) */
    cdpr_vec3_t e[NCAB];   /* horizontal unit toward the exit point */
    double l[NCAB];
    double h[NCAB];
    double force_scale;  /* cabin weight: equations in comparable units */
    cdpr_vec3_t f_ext;   /* external force at the CoM, world */
    cdpr_vec3_t tau_ext; /* external torque about the CoM, world */
} problem_t;

/* Unknowns x = (H_0, V_0, L_0, H_1, ...). Equations: wrench / weight (6), then per cable the
 * span residuals / span (2). */
static int equations(const gsl_vector *x, void *params, gsl_vector *f)
{
    const problem_t *p = (const problem_t *)params;
    const cdpr_robot_t *r = p->r;
    cdpr_vec3_t force =
        cdpr_v3(p->f_ext.x, p->f_ext.y, p->f_ext.z - r->p.cabin.mass_kg * r->p.g_m_per_s2);
    cdpr_vec3_t moment = p->tau_ext;
    for (int j = 0; j < NCAB; ++j) {
        const double H = gsl_vector_get(x, 3u * (size_t)j);
        const double V = gsl_vector_get(x, 3u * (size_t)j + 1u);
        const double L = gsl_vector_get(x, 3u * (size_t)j + 2u);
        if (!(H > 0.0) || !(L > 0.0)) {
            return GSL_EDOM; /* the catenary needs H > 0 and L > 0; hybrids backs off */
        }
        const cdpr_vec3_t F = cdpr_v3(H * p->e[j].x, H * p->e[j].y, V);
        force = cdpr_v3_add(force, F);
        moment = cdpr_v3_add(moment, cdpr_v3_cross(p->arm[j], F));
        cdpr_catenary_cable_t c;
        c.w_N_per_m = r->p.cables[j].cable.rho_kg_per_m * r->p.g_m_per_s2;
        c.ea_N = r->p.cables[j].cable.ea_N;
        double ls = 0.0;
        double hs = 0.0;
        if (cdpr_catenary_spans(&c, H, V, L, &ls, &hs) != CDPR_OK) {
            return GSL_EDOM;
        }
        const double span = sqrt(p->l[j] * p->l[j] + p->h[j] * p->h[j]);
        gsl_vector_set(f, 6u + 2u * (size_t)j, (ls - p->l[j]) / span);
        gsl_vector_set(f, 6u + 2u * (size_t)j + 1u, (hs - p->h[j]) / span);
    }
    gsl_vector_set(f, 0, force.x / p->force_scale);
    gsl_vector_set(f, 1, force.y / p->force_scale);
    gsl_vector_set(f, 2, force.z / p->force_scale);
    gsl_vector_set(f, 3, moment.x / p->force_scale);
    gsl_vector_set(f, 4, moment.y / p->force_scale);
    gsl_vector_set(f, 5, moment.z / p->force_scale);
    return GSL_SUCCESS;
}

/* Massless start: tensions t_j along the straight chords balancing the same load, from the
 * 6 x 6 system [u_j; arm_j x u_j] t = -(load), solved with GSL's LU. 0, or -1 if singular or
 * a tension is not positive. */
static int massless_start(const problem_t *p, double t[NCAB], double chord[NCAB])
{
    const cdpr_robot_t *r = p->r;
    gsl_matrix *A = gsl_matrix_alloc(6, NCAB);
    gsl_vector *b = gsl_vector_alloc(6);
    gsl_vector *sol = gsl_vector_alloc(NCAB);
    gsl_permutation *perm = gsl_permutation_alloc(6);
    int rc = -1;
    if (A != NULL && b != NULL && sol != NULL && perm != NULL) {
        for (int j = 0; j < NCAB; ++j) {
            chord[j] = sqrt(p->l[j] * p->l[j] + p->h[j] * p->h[j]);
            const cdpr_vec3_t u = cdpr_v3(p->l[j] * p->e[j].x / chord[j],
                                          p->l[j] * p->e[j].y / chord[j], p->h[j] / chord[j]);
            const cdpr_vec3_t mu = cdpr_v3_cross(p->arm[j], u);
            const double col[6] = {u.x, u.y, u.z, mu.x, mu.y, mu.z};
            for (size_t i = 0; i < 6; ++i) {
                gsl_matrix_set(A, i, (size_t)j, col[i]);
            }
        }
        const double w = r->p.cabin.mass_kg * r->p.g_m_per_s2;
        const double load[6] = {p->f_ext.x,   p->f_ext.y,   p->f_ext.z - w,
                                p->tau_ext.x, p->tau_ext.y, p->tau_ext.z};
        for (size_t i = 0; i < 6; ++i) {
            gsl_vector_set(b, i, -load[i]);
        }
        int sign = 0;
        if (gsl_linalg_LU_decomp(A, perm, &sign) == GSL_SUCCESS &&
            gsl_linalg_LU_solve(A, perm, b, sol) == GSL_SUCCESS) {
            rc = 0;
            for (int j = 0; j < NCAB; ++j) {
                t[j] = gsl_vector_get(sol, (size_t)j);
                if (!(t[j] > 0.0)) {
                    rc = -1;
                }
            }
        }
    }
    gsl_permutation_free(perm);
    gsl_vector_free(sol);
    gsl_vector_free(b);
    gsl_matrix_free(A);
    return rc;
}

cdpr_status_t cdpr_gsl_statics_ik(const cdpr_robot_t *r, const cdpr_cabin_motion_t *pose,
                                  int max_iter, cdpr_statics_result_t *res)
{
    return cdpr_gsl_statics_ik_wrench(r, pose, cdpr_v3(0.0, 0.0, 0.0), cdpr_v3(0.0, 0.0, 0.0),
                                      max_iter, res);
}

cdpr_status_t cdpr_gsl_statics_ik_wrench(const cdpr_robot_t *r, const cdpr_cabin_motion_t *pose,
                                         cdpr_vec3_t f_ext_N, cdpr_vec3_t tau_ext_Nm, int max_iter,
                                         cdpr_statics_result_t *res)
{
    if (r == NULL || pose == NULL || res == NULL || r->p.n_cables != NCAB || max_iter < 1) {
        return CDPR_E_INVALID_ARG;
    }
    gsl_set_error_handler_off();
    problem_t p;
    p.r = r;
    p.force_scale = r->p.cabin.mass_kg * r->p.g_m_per_s2;
    p.f_ext = f_ext_N;
    p.tau_ext = tau_ext_Nm;
    cdpr_mat3_t R;
    cdpr_quat_to_mat3(cdpr_quat_normalize(pose->q), &R);
    for (int j = 0; j < NCAB; ++j) {
        const cdpr_vec3_t b = r->p.cables[j].attach_body_m;
        p.P[j] = cdpr_v3_add(pose->p_m, cdpr_m3_mul_v3(&R, b));
        p.arm[j] = cdpr_m3_mul_v3(&R, cdpr_v3_sub(b, r->p.cabin.com_body_m));
        const cdpr_vec3_t d = cdpr_v3_sub(r->p.cables[j].exit_point_m, p.P[j]);
        p.l[j] = sqrt(d.x * d.x + d.y * d.y);
        p.h[j] = d.z;
        p.e[j] = cdpr_v3(d.x / p.l[j], d.y / p.l[j], 0.0);
    }
    /* Start: the massless solution (tensions along the chords) for the same load. */
    double t0[NCAB];
    double chord[NCAB];
    if (massless_start(&p, t0, chord) != 0) {
        return CDPR_E_INFEASIBLE;
    }
    gsl_multiroot_function fn = {equations, NUNK, &p};
    gsl_vector *x = gsl_vector_alloc(NUNK);
    gsl_multiroot_fsolver *s = gsl_multiroot_fsolver_alloc(gsl_multiroot_fsolver_hybrids, NUNK);
    if (x == NULL || s == NULL) {
        gsl_vector_free(x);
        gsl_multiroot_fsolver_free(s);
        return CDPR_E_CAPACITY;
    }
    for (int j = 0; j < NCAB; ++j) {
        const double w = r->p.cables[j].cable.rho_kg_per_m * r->p.g_m_per_s2;
        const double L0 = chord[j] / (1.0 + t0[j] / r->p.cables[j].cable.ea_N);
        gsl_vector_set(x, 3u * (size_t)j, t0[j] * p.l[j] / chord[j]);
        /* The massless V plus half the cable weight hanging at the cabin end. */
        gsl_vector_set(x, 3u * (size_t)j + 1u, t0[j] * p.h[j] / chord[j] - 0.5 * w * L0);
        gsl_vector_set(x, 3u * (size_t)j + 2u, L0);
    }
    cdpr_status_t out = CDPR_E_NO_CONVERGENCE;
    if (gsl_multiroot_fsolver_set(s, &fn, x) == GSL_SUCCESS) {
        int it = 0;
        while (it < max_iter) {
            ++it;
            const int rc = gsl_multiroot_fsolver_iterate(s);
            /* Scaled residual 1e-13: wrench to ~4e-11 N on a 392 N weight. */
            if (gsl_multiroot_test_residual(s->f, 1e-13) == GSL_SUCCESS) {
                out = CDPR_OK;
                break;
            }
            if (rc != GSL_SUCCESS) {
                break;
            }
        }
        res->iterations = it;
    }
    if (out == CDPR_OK) {
        res->n_cables = NCAB;
        double r2 = 0.0;
        for (size_t i = 0; i < 6; ++i) {
            r2 += gsl_vector_get(s->f, i) * gsl_vector_get(s->f, i);
        }
        res->residual = sqrt(r2) * p.force_scale;
        for (int j = 0; j < NCAB; ++j) {
            const double H = gsl_vector_get(s->x, 3u * (size_t)j);
            const double V = gsl_vector_get(s->x, 3u * (size_t)j + 1u);
            const double L = gsl_vector_get(s->x, 3u * (size_t)j + 2u);
            const double w = r->p.cables[j].cable.rho_kg_per_m * r->p.g_m_per_s2;
            if (!(H > 0.0)) {
                out = CDPR_E_INFEASIBLE;
            }
            cdpr_statics_cable_t *c = &res->cable[j];
            c->H_N = H;
            c->v_cabin_N = V;
            c->length_m = L;
            c->tension_cabin_N = sqrt(H * H + V * V);
            c->tension_winch_N = sqrt(H * H + (V + w * L) * (V + w * L));
            c->force_on_cabin_N = cdpr_v3(H * p.e[j].x, H * p.e[j].y, V);
            c->attach_world_m = p.P[j];
        }
        res->pose = *pose;
    }
    gsl_multiroot_fsolver_free(s);
    gsl_vector_free(x);
    return out;
}
