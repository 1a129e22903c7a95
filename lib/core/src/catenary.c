/* SPDX-License-Identifier: BSD-3-Clause */
/// @file catenary.c
/// Irvine's elastic catenary and its inverse (docs/model.md "Elastic catenary").
#include "cdpr/catenary.h"

#include <math.h>
#include <stddef.h>

#include "check.h"

void cdpr_catenary_point(const cdpr_catenary_cable_t *c, cdpr_real_t H_N, cdpr_real_t va_N,
                         cdpr_real_t s_m, cdpr_real_t *x_m, cdpr_real_t *z_m)
{
    const cdpr_real_t w = c->w_N_per_m;
    const cdpr_real_t vs = va_N + w * s_m;
    const cdpr_real_t t0 = CDPR_SQRT(H_N * H_N + va_N * va_N);
    const cdpr_real_t ts = CDPR_SQRT(H_N * H_N + vs * vs);
    *x_m = H_N * s_m / c->ea_N + (H_N / w) * (CDPR_ASINH(vs / H_N) - CDPR_ASINH(va_N / H_N));
    *z_m = (va_N * s_m + CDPR_R(0.5) * w * s_m * s_m) / c->ea_N + (ts - t0) / w;
}

cdpr_status_t cdpr_catenary_spans(const cdpr_catenary_cable_t *c, cdpr_real_t H_N, cdpr_real_t va_N,
                                  cdpr_real_t L0_m, cdpr_real_t *l_m, cdpr_real_t *h_m)
{
    if (c == NULL || l_m == NULL || h_m == NULL) {
        return CDPR_E_INVALID_ARG;
    }
    CDPR_TRY(check_positive(c->w_N_per_m, "w_N_per_m", -1, NULL));
    CDPR_TRY(check_positive(c->ea_N, "ea_N", -1, NULL));
    CDPR_TRY(check_positive(H_N, "H_N", -1, NULL));
    CDPR_TRY(check_finite(va_N, "va_N", -1, NULL));
    CDPR_TRY(check_positive(L0_m, "L0_m", -1, NULL));
    cdpr_catenary_point(c, H_N, va_N, L0_m, l_m, h_m);
    return CDPR_OK;
}

void cdpr_catenary_solver_default(cdpr_catenary_solver_t *s)
{
    s->max_iter = 50;
#ifdef CDPR_REAL_IS_FLOAT
    s->tol_m = CDPR_R(1e-4);
#else
    s->tol_m = CDPR_R(1e-9);
#endif
    s->iterations = 0;
    s->residual_m = CDPR_R(0.0);
}

void cdpr_catenary_spans_jac(const cdpr_catenary_cable_t *c, cdpr_real_t H_N, cdpr_real_t va_N,
                             cdpr_real_t L0_m, cdpr_real_t span[2], cdpr_real_t d_dH[2],
                             cdpr_real_t d_dV[2], cdpr_real_t d_dL[2])
{
    const cdpr_real_t w = c->w_N_per_m;
    const cdpr_real_t ea = c->ea_N;
    const cdpr_real_t H = H_N;
    const cdpr_real_t va = va_N;
    const cdpr_real_t L0 = L0_m;
    const cdpr_real_t vb = va + w * L0;
    const cdpr_real_t ta = CDPR_SQRT(H * H + va * va);
    const cdpr_real_t tb = CDPR_SQRT(H * H + vb * vb);
    const cdpr_real_t asb = CDPR_ASINH(vb / H);
    const cdpr_real_t asa = CDPR_ASINH(va / H);
    span[0] = H * L0 / ea + (H / w) * (asb - asa);
    span[1] = (va * L0 + CDPR_R(0.5) * w * L0 * L0) / ea + (tb - ta) / w;
    /* d asinh(v/H)/dH = -v / (H T), d asinh(v/H)/dv = 1 / T, d V_B / d L0 = w. */
    d_dH[0] = L0 / ea + (asb - asa) / w + (H / w) * (-vb / (H * tb) + va / (H * ta));
    d_dH[1] = (H / tb - H / ta) / w;
    d_dV[0] = (H / w) * (CDPR_R(1.0) / tb - CDPR_R(1.0) / ta);
    d_dV[1] = L0 / ea + (vb / tb - va / ta) / w;
    d_dL[0] = H / ea + H / tb;
    d_dL[1] = vb / ea + vb / tb;
}

/* Residual (x(L0) - l, z(L0) - h) and its Jacobian with respect to (H, V_A). */
static void residual(const cdpr_catenary_cable_t *c, cdpr_real_t H, cdpr_real_t va, cdpr_real_t L0,
                     cdpr_real_t l, cdpr_real_t h, cdpr_real_t f[2], cdpr_real_t J[2][2])
{
    cdpr_real_t span[2];
    cdpr_real_t dH[2];
    cdpr_real_t dV[2];
    cdpr_real_t dL[2];
    cdpr_catenary_spans_jac(c, H, va, L0, span, dH, dV, dL);
    f[0] = span[0] - l;
    f[1] = span[1] - h;
    J[0][0] = dH[0];
    J[0][1] = dV[0];
    J[1][0] = dH[1];
    J[1][1] = dV[1];
}

static cdpr_real_t norm2(const cdpr_real_t f[2])
{
    return CDPR_SQRT(f[0] * f[0] + f[1] * f[1]);
}

cdpr_status_t cdpr_catenary_solve(const cdpr_catenary_cable_t *c, cdpr_real_t l_m, cdpr_real_t h_m,
                                  cdpr_real_t L0_m, cdpr_catenary_solver_t *s, cdpr_real_t *H_N,
                                  cdpr_real_t *va_N)
{
    if (c == NULL || s == NULL || H_N == NULL || va_N == NULL || s->max_iter < 1) {
        return CDPR_E_INVALID_ARG;
    }
    CDPR_TRY(check_positive(c->w_N_per_m, "w_N_per_m", -1, NULL));
    CDPR_TRY(check_positive(c->ea_N, "ea_N", -1, NULL));
    CDPR_TRY(check_positive(l_m, "l_m", -1, NULL));
    CDPR_TRY(check_finite(h_m, "h_m", -1, NULL));
    CDPR_TRY(check_positive(L0_m, "L0_m", -1, NULL));
    CDPR_TRY(check_positive(s->tol_m, "tol_m", -1, NULL));
    const cdpr_real_t w = c->w_N_per_m;
    const cdpr_real_t chord = CDPR_SQRT(l_m * l_m + h_m * h_m);

    /* Guess 1 (taut): straight elastic cable, tension EA (chord/L0 - 1) + weight share. */
    cdpr_real_t strain = chord / L0_m - CDPR_R(1.0);
    if (strain < CDPR_R(1e-6)) {
        strain = CDPR_R(1e-6);
    }
    const cdpr_real_t t_taut = c->ea_N * strain;
    cdpr_real_t H = t_taut * l_m / chord;
    cdpr_real_t va = t_taut * h_m / chord - CDPR_R(0.5) * w * L0_m;
    /* Guess 2 (slack, inextensible catenary; Peyrot & Goulois 1979): lambda from the length
     * excess, H = w l / (2 lambda), V_A = (w/2)(h coth(lambda) - L0). */
    {
        const cdpr_real_t excess = (L0_m * L0_m - h_m * h_m) / (l_m * l_m);
        const cdpr_real_t lam =
            (excess > CDPR_R(1.0)) ? CDPR_SQRT(CDPR_R(3.0) * (excess - CDPR_R(1.0))) : CDPR_R(0.2);
        const cdpr_real_t H2 = w * l_m / (CDPR_R(2.0) * lam);
        const cdpr_real_t va2 = CDPR_R(0.5) * w * (h_m * CDPR_COSH(lam) / CDPR_SINH(lam) - L0_m);
        cdpr_real_t f1[2];
        cdpr_real_t f2[2];
        cdpr_real_t J[2][2];
        residual(c, H, va, L0_m, l_m, h_m, f1, J);
        residual(c, H2, va2, L0_m, l_m, h_m, f2, J);
        if (!(norm2(f1) <= norm2(f2))) {
            H = H2;
            va = va2;
        }
    }

    cdpr_real_t f[2];
    cdpr_real_t J[2][2];
    residual(c, H, va, L0_m, l_m, h_m, f, J);
    cdpr_real_t fn = norm2(f);
    for (int it = 1; it <= s->max_iter; ++it) {
        s->iterations = it;
        const cdpr_real_t det = J[0][0] * J[1][1] - J[0][1] * J[1][0];
        if (!(CDPR_FABS(det) > CDPR_R(0.0)) || !isfinite(det)) {
            break;
        }
        const cdpr_real_t dH = (-f[0] * J[1][1] + f[1] * J[0][1]) / det;
        const cdpr_real_t dV = (-f[1] * J[0][0] + f[0] * J[1][0]) / det;
        /* Backtracking: halve the step until H stays positive and the residual drops. */
        cdpr_real_t a = CDPR_R(1.0);
        int improved = 0;
        for (int b = 0; b < 40; ++b) {
            const cdpr_real_t Hn = H + a * dH;
            const cdpr_real_t vn = va + a * dV;
            if (Hn > CDPR_R(0.0)) {
                cdpr_real_t fnew[2];
                cdpr_real_t Jn[2][2];
                residual(c, Hn, vn, L0_m, l_m, h_m, fnew, Jn);
                const cdpr_real_t nn = norm2(fnew);
                if (nn < fn || nn <= s->tol_m) {
                    H = Hn;
                    va = vn;
                    f[0] = fnew[0];
                    f[1] = fnew[1];
                    J[0][0] = Jn[0][0];
                    J[0][1] = Jn[0][1];
                    J[1][0] = Jn[1][0];
                    J[1][1] = Jn[1][1];
                    fn = nn;
                    improved = 1;
                    break;
                }
            }
            a *= CDPR_R(0.5);
        }
        s->residual_m = fn;
        if (fn <= s->tol_m) {
            *H_N = H;
            *va_N = va;
            return CDPR_OK;
        }
        if (improved == 0) {
            break;
        }
    }
    s->residual_m = fn;
    return CDPR_E_NO_CONVERGENCE;
}
