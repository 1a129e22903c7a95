/* SPDX-License-Identifier: BSD-3-Clause */
/// @file analysis.c
/// The analysis of the linear loop (cdpr/design/design.h) with the definitions of
/// scripts/feedback_design.py: zero-order hold (scaling and squaring, Padé degree 13), the
/// closed loop (state x, z, u_prev), the loop broken at the rate commands through the modes of
/// A (loop-at-a-time margins, α = min σ_min(I + L)) and the learning's lap-to-lap map
/// M = Q (I - γ e^{jωλ} G) at the lap harmonics. LAPACK/BLAS (Fortran interface, column-major:
/// every matrix below is column-major unless named row-major).
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cdpr/design/design.h"

/* Last: its macro I would clash with the headers' parameter names. */
#include <complex.h>
#undef I

#define NZ_MAX CDPR_DESIGN_NZ_MAX
#define NU_MAX CDPR_DESIGN_NU_MAX

typedef double complex cplx;

/* The Fortran routines (reference LAPACK 3.x / any BLAS), with gfortran's hidden lengths of
 * the character arguments. */
void dgemm_(const char *ta, const char *tb, const int *m, const int *n, const int *k,
            const double *alpha, const double *a, const int *lda, const double *b, const int *ldb,
            const double *beta, double *c, const int *ldc, size_t lta, size_t ltb);
void zgemm_(const char *ta, const char *tb, const int *m, const int *n, const int *k,
            const cplx *alpha, const cplx *a, const int *lda, const cplx *b, const int *ldb,
            const cplx *beta, cplx *c, const int *ldc, size_t lta, size_t ltb);
void dgesv_(const int *n, const int *nrhs, double *a, const int *lda, int *ipiv, double *b,
            const int *ldb, int *info);
void zgesv_(const int *n, const int *nrhs, cplx *a, const int *lda, int *ipiv, cplx *b,
            const int *ldb, int *info);
void dgeev_(const char *jobvl, const char *jobvr, const int *n, double *a, const int *lda,
            double *wr, double *wi, double *vl, const int *ldvl, double *vr, const int *ldvr,
            double *work, const int *lwork, int *info, size_t l1, size_t l2);
void zgeev_(const char *jobvl, const char *jobvr, const int *n, cplx *a, const int *lda, cplx *w,
            cplx *vl, const int *ldvl, cplx *vr, const int *ldvr, cplx *work, const int *lwork,
            double *rwork, int *info, size_t l1, size_t l2);
void zgesvd_(const char *jobu, const char *jobvt, const int *m, const int *n, cplx *a,
             const int *lda, double *s, cplx *u, const int *ldu, cplx *vt, const int *ldvt,
             cplx *work, const int *lwork, double *rwork, int *info, size_t l1, size_t l2);

static const double k_pi = 3.14159265358979323846;

/* re + j im, exactly (C99: a complex double is an array of two doubles). */
static cplx mk(double re, double im)
{
    const double v[2] = {re, im};
    cplx z;
    memcpy(&z, v, sizeof z);
    return z;
}

/* e^{j x} */
static cplx cis(double x)
{
    return mk(cos(x), sin(x));
}

/* C = A B (column-major, m x k times k x n; lda m, ldb k, ldc m). */
static void mul(int m, int n, int k, const double *A, const double *B, double *C)
{
    const double one = 1.0;
    const double zero = 0.0;
    dgemm_("N", "N", &m, &n, &k, &one, A, &m, B, &k, &zero, C, &m, 1, 1);
}

/* C = A B with leading dimensions (real). */
static void dmul(int m, int n, int k, const double *A, int lda, const double *B, int ldb, double *C,
                 int ldc)
{
    const double one = 1.0;
    const double zero = 0.0;
    dgemm_("N", "N", &m, &n, &k, &one, A, &lda, B, &ldb, &zero, C, &ldc, 1, 1);
}

static void zmul(int m, int n, int k, const cplx *A, int lda, const cplx *B, int ldb, cplx *C,
                 int ldc)
{
    const cplx one = 1.0;
    const cplx zero = 0.0;
    zgemm_("N", "N", &m, &n, &k, &one, A, &lda, B, &ldb, &zero, C, &ldc, 1, 1);
}

static double norm1(int n, const double *A)
{
    double best = 0.0;
    for (int j = 0; j < n; ++j) {
        double s = 0.0;
        for (int i = 0; i < n; ++i) {
            s += fabs(A[(size_t)j * (size_t)n + (size_t)i]);
        }
        best = (s > best) ? s : best;
    }
    return best;
}

/* Row-major r x c into column-major. */
static void to_col(int r, int c, const double *rm, double *cm)
{
    for (int i = 0; i < r; ++i) {
        for (int j = 0; j < c; ++j) {
            cm[(size_t)j * (size_t)r + (size_t)i] = rm[(size_t)i * (size_t)c + (size_t)j];
        }
    }
}

static int all_finite(const double *a, size_t count)
{
    for (size_t i = 0; i < count; ++i) {
        if (!isfinite(a[i])) {
            return 0;
        }
    }
    return 1;
}

/* exp(X) in place (N x N column-major): scaling and squaring with the degree-13 Padé
 * approximant (Higham 2005), the scaling from η = max(‖X^6‖^(1/6), ‖X^8‖^(1/8)) (exact
 * 1-norms of the powers; Al-Mohy & Higham 2009, without their extra correction). */
static cdpr_status_t expm(int N, double *X, cdpr_design_error_t *err)
{
    static const double b[14] = {64764752532480000.0,
                                 32382376266240000.0,
                                 7771770303897600.0,
                                 1187353796428800.0,
                                 129060195264000.0,
                                 10559470521600.0,
                                 670442572800.0,
                                 33522128640.0,
                                 1323241920.0,
                                 40840800.0,
                                 960960.0,
                                 16380.0,
                                 182.0,
                                 1.0};
    const double theta13 = 5.371920351148152;
    const size_t nn = (size_t)N * (size_t)N;
    double *w = malloc(sizeof(double) * nn * 6);
    int *ipiv = malloc(sizeof(int) * (size_t)N);
    if (w == NULL || ipiv == NULL) {
        free(w);
        free(ipiv);
        snprintf(err->msg, sizeof err->msg, "design: out of memory (expm, %d)", N);
        return CDPR_E_CAPACITY;
    }
    double *X2 = w;
    double *X4 = w + nn;
    double *X6 = w + 2 * nn;
    double *U = w + 3 * nn;
    double *V = w + 4 * nn;
    double *T = w + 5 * nn;
    mul(N, N, N, X, X, X2);
    mul(N, N, N, X2, X2, X4);
    mul(N, N, N, X2, X4, X6);
    mul(N, N, N, X4, X4, T); /* X^8, for the scaling only */
    const double eta = fmax(pow(norm1(N, X6), 1.0 / 6.0), pow(norm1(N, T), 1.0 / 8.0));
    int s = (eta > theta13) ? (int)ceil(log2(eta / theta13)) : 0;
    if (!(s >= 0 && s < 1024)) {
        free(w);
        free(ipiv);
        snprintf(err->msg, sizeof err->msg, "design: exp of a matrix with norm %g", eta);
        return CDPR_E_NOT_FINITE;
    }
    const double c = ldexp(1.0, -s);
    const double c2 = c * c;
    const double c4 = c2 * c2;
    const double c6 = c4 * c2;
    for (size_t i = 0; i < nn; ++i) {
        X[i] *= c;
        X2[i] *= c2;
        X4[i] *= c4;
        X6[i] *= c6;
    }
    /* U = X [X6 (b13 X6 + b11 X4 + b9 X2) + b7 X6 + b5 X4 + b3 X2 + b1 I],
     * V = X6 (b12 X6 + b10 X4 + b8 X2) + b6 X6 + b4 X4 + b2 X2 + b0 I. */
    for (size_t i = 0; i < nn; ++i) {
        T[i] = b[13] * X6[i] + b[11] * X4[i] + b[9] * X2[i];
    }
    mul(N, N, N, X6, T, U);
    for (size_t i = 0; i < nn; ++i) {
        U[i] += b[7] * X6[i] + b[5] * X4[i] + b[3] * X2[i];
    }
    for (int i = 0; i < N; ++i) {
        U[(size_t)i * (size_t)N + (size_t)i] += b[1];
    }
    mul(N, N, N, X, U, T); /* T = U */
    for (size_t i = 0; i < nn; ++i) {
        U[i] = b[12] * X6[i] + b[10] * X4[i] + b[8] * X2[i];
    }
    mul(N, N, N, X6, U, V);
    for (size_t i = 0; i < nn; ++i) {
        V[i] += b[6] * X6[i] + b[4] * X4[i] + b[2] * X2[i];
    }
    for (int i = 0; i < N; ++i) {
        V[(size_t)i * (size_t)N + (size_t)i] += b[0];
    }
    /* (V - U) R = V + U */
    for (size_t i = 0; i < nn; ++i) {
        const double u = T[i];
        const double v = V[i];
        X[i] = v + u;
        V[i] = v - u;
    }
    int info = 0;
    dgesv_(&N, &N, V, &N, ipiv, X, &N, &info);
    if (info != 0) {
        free(w);
        free(ipiv);
        snprintf(err->msg, sizeof err->msg, "design: Padé denominator singular (dgesv %d)", info);
        return CDPR_E_SINGULAR;
    }
    for (int k = 0; k < s; ++k) {
        mul(N, N, N, X, X, T);
        memcpy(X, T, sizeof(double) * nn);
    }
    free(w);
    free(ipiv);
    if (!all_finite(X, nn)) {
        snprintf(err->msg, sizeof err->msg, "design: exp of the plant is not finite");
        return CDPR_E_NOT_FINITE;
    }
    return CDPR_OK;
}

/* Phi, Gam column-major (n x n, n x nu). */
static cdpr_status_t discretise_col(const cdpr_design_model_t *m, double *Phi, double *Gam,
                                    cdpr_design_error_t *err)
{
    const int n = m->n;
    const int nu = m->nu;
    const int N = n + nu;
    const size_t NN = (size_t)N;
    double *X = calloc(NN * NN, sizeof(double));
    if (X == NULL) {
        snprintf(err->msg, sizeof err->msg, "design: out of memory (n = %d)", n);
        return CDPR_E_CAPACITY;
    }
    for (int i = 0; i < n; ++i) {
        for (int j = 0; j < n; ++j) {
            X[(size_t)j * NN + (size_t)i] = m->A[(size_t)i * (size_t)n + (size_t)j] * m->period_s;
        }
        for (int j = 0; j < nu; ++j) {
            X[(size_t)(n + j) * NN + (size_t)i] =
                m->B[(size_t)i * (size_t)nu + (size_t)j] * m->period_s;
        }
    }
    const cdpr_status_t st = expm(N, X, err);
    if (st == CDPR_OK) {
        for (int j = 0; j < n; ++j) {
            memcpy(&Phi[(size_t)j * (size_t)n], &X[(size_t)j * NN], sizeof(double) * (size_t)n);
        }
        for (int j = 0; j < nu; ++j) {
            memcpy(&Gam[(size_t)j * (size_t)n], &X[(size_t)(n + j) * NN],
                   sizeof(double) * (size_t)n);
        }
    }
    free(X);
    return st;
}

static cdpr_status_t check_model(const cdpr_design_model_t *m, cdpr_design_error_t *err)
{
    err->msg[0] = '\0';
    if (m->n <= 0 || !(m->period_s > 0.0) || !isfinite(m->period_s) || m->A == NULL ||
        m->B == NULL || m->Kx == NULL || m->Kz == NULL || m->Zx == NULL || m->Zz == NULL ||
        m->Ku == NULL || m->Zu == NULL || m->Cm == NULL) {
        snprintf(err->msg, sizeof err->msg, "design: incomplete model");
        return CDPR_E_INVALID_ARG;
    }
    if (m->nu < 1 || m->nu > NU_MAX || m->nz != CDPR_DESIGN_NZ(m->nu) || m->nm != 12 + m->nu) {
        snprintf(err->msg, sizeof err->msg,
                 "design: model sizes nu %d, nz %d, nm %d (nu 1..%d, nz = 33 + 4 nu, nm = 12 + nu)",
                 m->nu, m->nz, m->nm, NU_MAX);
        return CDPR_E_INVALID_ARG;
    }
    const size_t n = (size_t)m->n;
    const size_t nu = (size_t)m->nu;
    const size_t nz = (size_t)m->nz;
    const size_t nm = (size_t)m->nm;
    const struct {
        const char *name;
        const double *a;
        size_t count;
    } mats[] = {{"A", m->A, n * n},     {"B", m->B, n * nu},    {"Kx", m->Kx, nu * n},
                {"Kz", m->Kz, nu * nz}, {"Zx", m->Zx, nz * n},  {"Zz", m->Zz, nz * nz},
                {"Ku", m->Ku, nu * nu}, {"Zu", m->Zu, nz * nu}, {"Cm", m->Cm, nm * n},
                {"J", m->J, nu * 6u}};
    for (size_t i = 0; i < sizeof mats / sizeof mats[0]; ++i) {
        if (!all_finite(mats[i].a, mats[i].count)) {
            snprintf(err->msg, sizeof err->msg, "design: the linear model's %s is not finite",
                     mats[i].name);
            return CDPR_E_NOT_FINITE;
        }
    }
    const double s[] = {m->lap_s,         m->learn_knots,     m->k_length_per_s,
                        m->learning_gain, m->learning_lead_s, m->learning_cutoff_hz};
    if (!all_finite(s, sizeof s / sizeof s[0])) {
        snprintf(err->msg, sizeof err->msg, "design: a learning setting is not finite");
        return CDPR_E_NOT_FINITE;
    }
    return CDPR_OK;
}

cdpr_status_t cdpr_design_discretise(const cdpr_design_model_t *m, double *Phi, double *Gam,
                                     cdpr_design_error_t *err)
{
    cdpr_status_t st = check_model(m, err);
    if (st != CDPR_OK) {
        return st;
    }
    const size_t n = (size_t)m->n;
    const size_t nu = (size_t)m->nu;
    double *P = malloc(sizeof(double) * n * (n + nu));
    if (P == NULL) {
        snprintf(err->msg, sizeof err->msg, "design: out of memory");
        return CDPR_E_CAPACITY;
    }
    st = discretise_col(m, P, P + n * n, err);
    if (st == CDPR_OK) {
        for (size_t i = 0; i < n; ++i) {
            for (size_t j = 0; j < n; ++j) {
                Phi[i * n + j] = P[j * n + i];
            }
            for (size_t j = 0; j < nu; ++j) {
                Gam[i * nu + j] = P[n * n + j * n + i];
            }
        }
    }
    free(P);
    return st;
}

/* Eigenvalues (and with V != NULL the right eigenvectors, complex, N x N) of the real N x N
 * column-major matrix A (overwritten). */
static cdpr_status_t eig(int N, double *A, cplx *lam, cplx *V, cdpr_design_error_t *err)
{
    double *wr = malloc(sizeof(double) * (size_t)N * 2);
    double *vr = (V != NULL) ? malloc(sizeof(double) * (size_t)N * (size_t)N) : NULL;
    double q = 0.0;
    int lwork = -1;
    int info = 0;
    int one = 1;
    const char *jv = (V != NULL) ? "V" : "N";
    const int ldvr = (V != NULL) ? N : 1;
    if (wr == NULL || (V != NULL && vr == NULL)) {
        free(wr);
        free(vr);
        snprintf(err->msg, sizeof err->msg, "design: out of memory (eig %d)", N);
        return CDPR_E_CAPACITY;
    }
    double *wi = wr + N;
    dgeev_("N", jv, &N, A, &N, wr, wi, NULL, &one, vr, &ldvr, &q, &lwork, &info, 1, 1);
    lwork = (info == 0) ? (int)q : 0;
    double *work = (lwork > 0) ? malloc(sizeof(double) * (size_t)lwork) : NULL;
    if (work == NULL) {
        free(wr);
        free(vr);
        snprintf(err->msg, sizeof err->msg, "design: dgeev workspace (%d)", info);
        return CDPR_E_CAPACITY;
    }
    dgeev_("N", jv, &N, A, &N, wr, wi, NULL, &one, vr, &ldvr, work, &lwork, &info, 1, 1);
    free(work);
    if (info != 0) {
        free(wr);
        free(vr);
        snprintf(err->msg, sizeof err->msg, "design: eigenvalues did not converge (dgeev %d)",
                 info);
        return CDPR_E_NO_CONVERGENCE;
    }
    for (int j = 0; j < N; ++j) {
        lam[j] = mk(wr[j], wi[j]);
    }
    if (V != NULL) {
        const size_t NN = (size_t)N;
        for (int j = 0; j < N; ++j) {
            const double *c = &vr[(size_t)j * NN];
            if (wi[j] > 0.0 && j + 1 < N) {
                const double *d = &vr[(size_t)(j + 1) * NN];
                for (size_t i = 0; i < NN; ++i) {
                    V[(size_t)j * NN + i] = mk(c[i], d[i]);
                    V[(size_t)(j + 1) * NN + i] = mk(c[i], -d[i]);
                }
                ++j;
            } else {
                for (size_t i = 0; i < NN; ++i) {
                    V[(size_t)j * NN + i] = c[i];
                }
            }
        }
    }
    free(wr);
    free(vr);
    return CDPR_OK;
}

/* Solve A X = B in place (complex N x N, nrhs columns). */
static cdpr_status_t zsolve(int N, int nrhs, cplx *A, cplx *B, int *ipiv)
{
    int info = 0;
    zgesv_(&N, &nrhs, A, &N, ipiv, B, &N, &info);
    return (info == 0) ? CDPR_OK : CDPR_E_SINGULAR;
}

/* Singular values of the m x m complex A (overwritten), descending; m <= NU_MAX. */
static int svdn(int m, cplx *A, double *s)
{
    int one = 1;
    int lwork = 64 + 8 * NU_MAX;
    cplx work[64 + 8 * NU_MAX];
    double rwork[5 * NU_MAX];
    int info = 0;
    zgesvd_("N", "N", &m, &m, A, &m, s, NULL, &one, NULL, &one, work, &lwork, rwork, &info, 1, 1);
    return info;
}

/* Eigenvalues of the m x m complex A (overwritten); m <= NU_MAX. */
static int eign(int m, cplx *A, cplx *w)
{
    int one = 1;
    int lwork = 64 + 8 * NU_MAX;
    cplx work[64 + 8 * NU_MAX];
    double rwork[2 * NU_MAX];
    int info = 0;
    zgeev_("N", "N", &m, A, &m, w, NULL, &one, NULL, &one, work, &lwork, rwork, &info, 1, 1);
    return info;
}

static int cmp_double(const void *a, const void *b)
{
    const double x = *(const double *)a;
    const double y = *(const double *)b;
    return (x < y) ? -1 : (x > y) ? 1 : 0;
}

/* numpy.linspace(a, b, num)[i]. */
static double linspace_at(double a, double b, int num, int i)
{
    if (i == num - 1) {
        return b;
    }
    const double step = (b - a) / (double)(num - 1);
    return (double)i * step + a;
}

/* The grid of feedback_design.py: 3000 log points 0.01 Hz .. 0.999 Nyquist, and ±2 % (41
 * points) around each plant mode in 0.01 .. Nyquist, sorted, duplicates removed. */
static double *freq_grid(const cplx *lam, int n, double T, int *count)
{
    const double fmax = 0.5 / T;
    int nm = 0;
    for (int k = 0; k < n; ++k) {
        const double f = cimag(lam[k]) / (2.0 * k_pi);
        nm += (cimag(lam[k]) > 0.0 && f >= 0.01 && f <= fmax) ? 1 : 0;
    }
    const int points = 3000;
    double *f = malloc(sizeof(double) * (size_t)(points + 41 * nm));
    if (f == NULL) {
        return NULL;
    }
    int c = 0;
    const double lo = log10(0.01);
    const double hi = log10(fmax * 0.999);
    for (int i = 0; i < points; ++i) {
        f[c++] = pow(10.0, linspace_at(lo, hi, points, i));
    }
    for (int k = 0; k < n; ++k) {
        const double fm = cimag(lam[k]) / (2.0 * k_pi);
        if (!(cimag(lam[k]) > 0.0 && fm >= 0.01 && fm <= fmax)) {
            continue;
        }
        for (int i = 0; i < 41; ++i) {
            const double x = fm * (1.0 + linspace_at(-0.02, 0.02, 41, i));
            if (x > 0.01 && x < fmax) {
                f[c++] = x;
            }
        }
    }
    qsort(f, (size_t)c, sizeof(double), cmp_double);
    int u = 0;
    for (int i = 0; i < c; ++i) {
        if (u == 0 || f[i] > f[u - 1]) { /* sorted: not a duplicate */
            f[u++] = f[i];
        }
    }
    *count = u;
    return f;
}

/* feedback_design.margins for one channel's l over the grid f. */
static void margins(const double *f, const cplx *l, int stride, int F, double *gm, double *gmf,
                    double *pm, double *pmf)
{
    *gm = HUGE_VAL;
    *gmf = (double)NAN;
    *pm = HUGE_VAL;
    *pmf = (double)NAN;
    for (int k = 0; k + 1 < F; ++k) {
        const cplx a = l[(size_t)k * (size_t)stride];
        const cplx bb = l[(size_t)(k + 1) * (size_t)stride];
        if (cimag(a) * cimag(bb) < 0.0) {
            const double s = cimag(a) / (cimag(a) - cimag(bb));
            const double x = creal(a) + s * (creal(bb) - creal(a));
            if (x < 0.0) {
                const double g = -20.0 * log10(-x);
                if (fabs(g) < fabs(*gm)) {
                    *gm = g;
                    *gmf = f[k] + s * (f[k + 1] - f[k]);
                }
            }
        }
        const double aa = cabs(a);
        const double ab = cabs(bb);
        if ((aa - 1.0) * (ab - 1.0) < 0.0) {
            const double s = (aa - 1.0) / (aa - ab);
            const cplx c = a + s * (bb - a);
            const double p = 180.0 - fabs(carg(c) * 180.0 / k_pi);
            if (p < *pm) {
                *pm = p;
                *pmf = f[k] + s * (f[k + 1] - f[k]);
            }
        }
    }
}

/* Work of the analysis (freed by analysis_free). */
typedef struct {
    double *Phi, *Gam; /* column-major n x n, n x nu */
    double *Acl;       /* column-major Nc x Nc */
    double *scratch;   /* Nc x Nc */
    cplx *lamA, *VA;   /* modes of A */
    cplx *W;           /* n x nu: modal ZOH input */
    cplx *P;           /* nk x n: [Kx; Zx] V (nk = nu + nz) */
    double *R;         /* n x nk nu: R_k[r + nk c] = P[r, k] W[k, c], real form (pairs: Re, Im) */
    double *D;         /* 2 x chunk x n: the modes' 1 / (z - mu) in the same real form */
    double *Y;         /* 2 x chunk x nk nu: [Kx; Zx] X, real and imaginary parts */
    cplx *H;           /* F x nu^2: H(f) column-major nu x nu per frequency */
    double *f;
    cplx *lamC, *VC; /* closed loop */
    int *ipiv;
} work_t;

static void analysis_free(work_t *w)
{
    free(w->Phi);
    free(w->Acl);
    free(w->scratch);
    free(w->lamA);
    free(w->VA);
    free(w->W);
    free(w->P);
    free(w->R);
    free(w->D);
    free(w->Y);
    free(w->H);
    free(w->f);
    free(w->lamC);
    free(w->VC);
    free(w->ipiv);
    memset(w, 0, sizeof *w);
}

#define CHUNK 256

/* H(f) for every grid point (feedback_design.Loop.H). */
static cdpr_status_t loop_response(const cdpr_design_model_t *m, work_t *w, int F,
                                   cdpr_design_error_t *err)
{
    const int n = m->n;
    const int nu = m->nu;
    const int nz = m->nz;
    const int nk = nu + nz;                    /* rows of [Kx; Zx] */
    const size_t nr = (size_t)nk * (size_t)nu; /* columns of R and Y */
    const size_t nn = (size_t)n;
    const double T = m->period_s;
    cplx *mu = malloc(sizeof(cplx) * nn);
    cplx *Vc = malloc(sizeof(cplx) * nn * nn);
    cplx *KZ = malloc(sizeof(cplx) * (size_t)nk * nn);
    w->W = malloc(sizeof(cplx) * nn * (size_t)nu);
    w->P = malloc(sizeof(cplx) * (size_t)nk * nn);
    w->R = malloc(sizeof(double) * nn * nr);
    w->D = malloc(sizeof(double) * 2 * CHUNK * nn);
    w->Y = malloc(sizeof(double) * 2 * CHUNK * nr);
    w->H = malloc(sizeof(cplx) * (size_t)F * ((size_t)nu * (size_t)nu));
    if (mu == NULL || Vc == NULL || KZ == NULL || w->W == NULL || w->P == NULL || w->R == NULL ||
        w->D == NULL || w->Y == NULL || w->H == NULL) {
        free(mu);
        free(Vc);
        free(KZ);
        snprintf(err->msg, sizeof err->msg, "design: out of memory (loop)");
        return CDPR_E_CAPACITY;
    }
    /* W = g .* (V \ B), g = (mu - 1) / lam (T where |lam T| < 1e-9) */
    memcpy(Vc, w->VA, sizeof(cplx) * nn * nn);
    for (int i = 0; i < n; ++i) {
        for (int j = 0; j < nu; ++j) {
            w->W[(size_t)j * nn + (size_t)i] = m->B[(size_t)i * (size_t)nu + (size_t)j];
        }
    }
    if (zsolve(n, nu, Vc, w->W, w->ipiv) != CDPR_OK) {
        free(mu);
        free(Vc);
        free(KZ);
        snprintf(err->msg, sizeof err->msg, "design: the modes of A are not independent");
        return CDPR_E_SINGULAR;
    }
    for (int k = 0; k < n; ++k) {
        const cplx lam = w->lamA[k];
        mu[k] = cexp(lam * T);
        const cplx g = (cabs(lam * T) < 1e-9) ? (cplx)T : (mu[k] - 1.0) / lam;
        for (int j = 0; j < nu; ++j) {
            w->W[(size_t)j * nn + (size_t)k] *= g;
        }
    }
    /* P = [Kx; Zx] V (nk x n) */
    for (int i = 0; i < nk; ++i) {
        for (int k = 0; k < n; ++k) {
            KZ[(size_t)k * (size_t)nk + (size_t)i] = (i < nu)
                                                         ? m->Kx[(size_t)i * nn + (size_t)k]
                                                         : m->Zx[(size_t)(i - nu) * nn + (size_t)k];
        }
    }
    zmul(nk, n, n, KZ, nk, w->VA, n, w->P, nk);
    free(Vc);
    free(KZ);
    /* The sum over the modes, sum_k R_k / (z - mu_k), with a conjugate pair (k, k + 1) (dgeev:
     * positive imaginary part first; R_{k+1} = conj R_k as A is real) taken together:
     * d_k R_k + d_{k+1} conj R_k = (d_k + d_{k+1}) Re R_k + j (d_k - d_{k+1}) Im R_k. So the
     * modal coefficients are real (rows k, k + 1: Re R_k, Im R_k; a real mode: Re R_k) and the
     * sum is two real products (half the work of the complex one). */
    for (int k = 0; k < n; ++k) {
        const int pair = (cimag(w->lamA[k]) > 0.0 && k + 1 < n);
        for (int c = 0; c < nu; ++c) {
            const cplx wk = w->W[(size_t)c * nn + (size_t)k];
            for (int r = 0; r < nk; ++r) {
                const cplx v = w->P[(size_t)k * (size_t)nk + (size_t)r] * wk;
                w->R[(size_t)(r + nk * c) * nn + (size_t)k] = creal(v);
                if (pair) {
                    w->R[(size_t)(r + nk * c) * nn + (size_t)k + 1] = cimag(v);
                }
            }
        }
        k += pair;
    }
    int ipiv[NZ_MAX];
    double *Dr = w->D;
    double *Di = w->D + (size_t)CHUNK * nn;
    double *Yr = w->Y;
    double *Yi = w->Y + (size_t)CHUNK * nr;
    cplx zs[CHUNK];
    for (int f0 = 0; f0 < F; f0 += CHUNK) {
        const int nb = (F - f0 < CHUNK) ? F - f0 : CHUNK;
        for (int i = 0; i < nb; ++i) {
            zs[i] = cis(2.0 * k_pi * w->f[f0 + i] * T);
        }
        for (int k = 0; k < n; ++k) {
            const int pair = (cimag(w->lamA[k]) > 0.0 && k + 1 < n);
            for (int i = 0; i < nb; ++i) {
                const size_t at = (size_t)k * CHUNK + (size_t)i;
                const cplx d1 = 1.0 / (zs[i] - mu[k]);
                if (pair) {
                    const cplx d2 = 1.0 / (zs[i] - mu[k + 1]);
                    const cplx sum = d1 + d2;
                    const cplx dif = d1 - d2; /* times j */
                    Dr[at] = creal(sum);
                    Di[at] = cimag(sum);
                    Dr[at + CHUNK] = -cimag(dif);
                    Di[at + CHUNK] = creal(dif);
                } else {
                    Dr[at] = creal(d1);
                    Di[at] = cimag(d1);
                }
            }
            k += pair;
        }
        dmul(nb, (int)nr, n, Dr, CHUNK, w->R, n, Yr, CHUNK);
        dmul(nb, (int)nr, n, Di, CHUNK, w->R, n, Yi, CHUNK);
        for (int i = 0; i < nb; ++i) {
            const cplx z = zs[i];
            /* Zp = (zI - Zz) \ (ZxV X + Zu / z), H = KxV X + Kz Zp + Ku / z */
            cplx M[NZ_MAX * NZ_MAX];
            cplx Zp[NZ_MAX * NU_MAX];
            for (int r = 0; r < nz; ++r) {
                for (int c = 0; c < nz; ++c) {
                    M[c * nz + r] = ((r == c) ? z : 0.0) - m->Zz[r * nz + c];
                }
                for (int c = 0; c < nu; ++c) {
                    Zp[c * nz + r] = mk(Yr[(size_t)(nu + r + nk * c) * CHUNK + (size_t)i],
                                        Yi[(size_t)(nu + r + nk * c) * CHUNK + (size_t)i]) +
                                     m->Zu[r * nu + c] / z;
                }
            }
            if (zsolve(nz, nu, M, Zp, ipiv) != CDPR_OK) {
                free(mu);
                snprintf(err->msg, sizeof err->msg, "design: zI - Zz singular at %g Hz",
                         w->f[f0 + i]);
                return CDPR_E_SINGULAR;
            }
            cplx *H = &w->H[(size_t)(f0 + i) * ((size_t)nu * (size_t)nu)];
            for (int r = 0; r < nu; ++r) {
                for (int c = 0; c < nu; ++c) {
                    cplx s = mk(Yr[(size_t)(r + nk * c) * CHUNK + (size_t)i],
                                Yi[(size_t)(r + nk * c) * CHUNK + (size_t)i]);
                    for (int q = 0; q < nz; ++q) {
                        s += m->Kz[r * nz + q] * Zp[c * nz + q];
                    }
                    H[c * nu + r] = s + m->Ku[r * nu + c] / z;
                }
            }
        }
    }
    free(mu);
    return CDPR_OK;
}

/* The loop of channel j with the other nu - 1 closed, at one frequency (H column-major
 * nu x nu): l_j = -(H_jj + H_j,o (I - H_oo)^-1 H_o,j). CDPR_OK or CDPR_E_SINGULAR. */
static cdpr_status_t channel_loop(int nu, const cplx *H, int j, cplx *l)
{
    int o[NU_MAX];
    int c = 0;
    for (int i = 0; i < nu; ++i) {
        if (i != j) {
            o[c++] = i;
        }
    }
    cplx M[NU_MAX * NU_MAX];
    cplx u[NU_MAX];
    int ipiv[NU_MAX];
    for (int a = 0; a < c; ++a) {
        for (int b2 = 0; b2 < c; ++b2) {
            M[b2 * c + a] = ((a == b2) ? 1.0 : 0.0) - H[o[b2] * nu + o[a]];
        }
        u[a] = H[j * nu + o[a]];
    }
    if (c > 0 && zsolve(c, 1, M, u, ipiv) != CDPR_OK) {
        return CDPR_E_SINGULAR;
    }
    cplx s = H[j * nu + j];
    for (int a = 0; a < c; ++a) {
        s += H[o[a] * nu + j] * u[a];
    }
    *l = -s;
    return CDPR_OK;
}

/* α, the channel loops and their margins from H over the grid. */
static cdpr_status_t loop_margins(int nu, const work_t *w, int F, cdpr_design_report_t *r,
                                  cdpr_design_error_t *err)
{
    const size_t nh = (size_t)nu * (size_t)nu;
    r->n_channels = nu;
    r->alpha = HUGE_VAL;
    r->alpha_hz = (double)NAN;
    double hmax = 0.0;
    for (int k = 0; k < F; ++k) {
        const cplx *H = &w->H[(size_t)k * nh];
        cplx A[NU_MAX * NU_MAX];
        double s[NU_MAX];
        for (size_t i = 0; i < nh; ++i) {
            A[i] = ((i % (size_t)(nu + 1)) == 0 ? 1.0 : 0.0) - H[i];
            hmax = fmax(hmax, cabs(H[i]));
        }
        if (svdn(nu, A, s) != 0) {
            snprintf(err->msg, sizeof err->msg, "design: SVD failed at %g Hz", w->f[k]);
            return CDPR_E_NO_CONVERGENCE;
        }
        if (s[nu - 1] < r->alpha) {
            r->alpha = s[nu - 1];
            r->alpha_hz = w->f[k];
        }
    }
    r->active = (hmax > 0.0) ? 1 : 0;
    r->gm_min_db = HUGE_VAL;
    r->pm_min_deg = HUGE_VAL;
    r->gm_min_hz = (double)NAN;
    r->pm_min_hz = (double)NAN;
    if (r->active == 0) {
        return CDPR_OK;
    }
    cplx *l = malloc(sizeof(cplx) * (size_t)F * (size_t)nu);
    if (l == NULL) {
        snprintf(err->msg, sizeof err->msg, "design: out of memory (channel loops)");
        return CDPR_E_CAPACITY;
    }
    for (int k = 0; k < F; ++k) {
        const cplx *H = &w->H[(size_t)k * nh];
        for (int j = 0; j < nu; ++j) {
            if (channel_loop(nu, H, j, &l[(size_t)k * (size_t)nu + (size_t)j]) != CDPR_OK) {
                free(l);
                snprintf(err->msg, sizeof err->msg,
                         "design: the other %d loops are singular at %g Hz", nu - 1, w->f[k]);
                return CDPR_E_SINGULAR;
            }
        }
    }
    for (int j = 0; j < nu; ++j) {
        margins(w->f, l + j, nu, F, &r->gm_db[j], &r->gm_hz[j], &r->pm_deg[j], &r->pm_hz[j]);
        if (fabs(r->gm_db[j]) < r->gm_min_db) {
            r->gm_min_db = fabs(r->gm_db[j]);
            r->gm_min_hz = r->gm_hz[j];
        }
        if (r->pm_deg[j] < r->pm_min_deg) {
            r->pm_min_deg = r->pm_deg[j];
            r->pm_min_hz = r->pm_hz[j];
        }
    }
    free(l);
    return CDPR_OK;
}

/* The closed loop (state x, z, u_prev), column-major Nc x Nc. */
static cdpr_status_t closed_loop_matrix(const cdpr_design_model_t *m, const work_t *w, double *Acl)
{
    const int n = m->n;
    const size_t nn = (size_t)n;
    const size_t nu = (size_t)m->nu;
    const size_t nz = (size_t)m->nz;
    const size_t Nc = nn + nz + nu;
    memset(Acl, 0, sizeof(double) * Nc * Nc);
#define AT(i, j) Acl[(size_t)(j)*Nc + (size_t)(i)]
    for (size_t j = 0; j < nn; ++j) {
        memcpy(&AT(0, j), &w->Phi[j * nn], sizeof(double) * nn);
    }
    for (size_t i = 0; i < nz; ++i) {
        for (size_t j = 0; j < nn; ++j) {
            AT(nn + i, j) = m->Zx[i * nn + j];
        }
        for (size_t j = 0; j < nz; ++j) {
            AT(nn + i, nn + j) = m->Zz[i * nz + j];
        }
        for (size_t j = 0; j < nu; ++j) {
            AT(nn + i, nn + nz + j) = m->Zu[i * nu + j];
        }
    }
    /* K = [Kx Kz Ku] (nu x Nc): rows n+nz.. and Phi rows += Gam K */
    double *K = malloc(sizeof(double) * nu * Nc);
    double *GK = malloc(sizeof(double) * nn * Nc);
    for (size_t i = 0; K != NULL && GK != NULL && i < nu; ++i) {
        for (size_t j = 0; j < Nc; ++j) {
            const double v = (j < nn)        ? m->Kx[i * nn + j]
                             : (j < nn + nz) ? m->Kz[i * nz + (j - nn)]
                                             : m->Ku[i * nu + (j - nn - nz)];
            K[j * nu + i] = v;
            AT(nn + nz + i, j) = v;
        }
    }
    if (K != NULL && GK != NULL) {
        mul(n, (int)Nc, (int)nu, w->Gam, K, GK);
        for (size_t j = 0; j < Nc; ++j) {
            for (size_t i = 0; i < nn; ++i) {
                AT(i, j) += GK[j * nn + i];
            }
        }
    }
#undef AT
    const cdpr_status_t st = (K != NULL && GK != NULL) ? CDPR_OK : CDPR_E_CAPACITY;
    free(K);
    free(GK);
    return st;
}

static double learning_q(double f, double fc, double dphi)
{
    if (!(fc > 0.0)) {
        return 1.0;
    }
    const double a = exp(-2.0 * k_pi * fc * dphi);
    const double d = cabs(1.0 - a * cis(-2.0 * k_pi * f * dphi));
    return (1.0 - a) * (1.0 - a) / (d * d);
}

/* feedback_design.learning_report at the harmonics (no band scan). */
static cdpr_status_t learning(const cdpr_design_model_t *m, work_t *w, cdpr_design_report_t *r,
                              cdpr_design_error_t *err)
{
    const double lap = m->lap_s;
    const int knots = (int)m->learn_knots;
    const double gamma = m->learning_gain;
    const double lead = m->learning_lead_s;
    const double fc = m->learning_cutoff_hz;
    r->learning = 0;
    r->max_rho = 0.0;
    if (!(lap > 0.0 && knots >= 2 && gamma > 0.0)) {
        return CDPR_OK;
    }
    r->learning = 1;
    const int n = m->n;
    const int nu = m->nu;
    const size_t nu_s = (size_t)nu;
    const size_t nn = (size_t)n;
    const int Nc = n + m->nz + nu;
    const size_t NC = (size_t)Nc;
    const double T = m->period_s;
    const double dphi = lap / (double)knots;
    const double fnyq = 0.5 / dphi;
    int top = 0;
    for (int i = 0; i < 20000; ++i) {
        if (learning_q(linspace_at(1e-3, fnyq, 20000, i), fc, dphi) >= 0.01) {
            top = i;
        }
    }
    r->band_top_hz = linspace_at(1e-3, fnyq, 20000, top);
    /* CV = (J Cm[0:6]) V[0:n] (nu x Nc), W = V \ Bc, Bc = k_L [Gam; 0; I] */
    cplx *CV = malloc(sizeof(cplx) * nu_s * NC);
    cplx *Wl = malloc(sizeof(cplx) * NC * nu_s);
    cplx *C = malloc(sizeof(cplx) * nu_s * nn);
    if (CV == NULL || Wl == NULL || C == NULL) {
        free(CV);
        free(Wl);
        free(C);
        snprintf(err->msg, sizeof err->msg, "design: out of memory (learning)");
        return CDPR_E_CAPACITY;
    }
    for (int i = 0; i < nu; ++i) {
        for (int k = 0; k < n; ++k) {
            double s = 0.0;
            for (int q = 0; q < 6; ++q) {
                s += m->J[i * 6 + q] * m->Cm[(size_t)q * nn + (size_t)k];
            }
            C[(size_t)k * nu_s + (size_t)i] = s;
        }
    }
    zmul(nu, Nc, n, C, nu, w->VC, Nc, CV, nu);
    free(C);
    for (int j = 0; j < nu; ++j) {
        for (int i = 0; i < Nc; ++i) {
            double v = 0.0;
            if (i < n) {
                v = w->Gam[(size_t)j * nn + (size_t)i];
            } else if (i >= Nc - nu) {
                v = (i - (Nc - nu) == j) ? 1.0 : 0.0;
            }
            Wl[(size_t)j * NC + (size_t)i] = v * m->k_length_per_s;
        }
    }
    cplx *Vc = malloc(sizeof(cplx) * NC * NC);
    int *ipiv = malloc(sizeof(int) * NC);
    cdpr_status_t st = (Vc != NULL && ipiv != NULL) ? CDPR_OK : CDPR_E_CAPACITY;
    if (st == CDPR_OK) {
        memcpy(Vc, w->VC, sizeof(cplx) * NC * NC);
        st = zsolve(Nc, nu, Vc, Wl, ipiv);
    }
    free(Vc);
    free(ipiv);
    if (st != CDPR_OK) {
        free(CV);
        free(Wl);
        snprintf(err->msg, sizeof err->msg, "design: the closed loop's modes (learning): %s",
                 cdpr_status_str(st));
        return st;
    }
    int nh = (int)floor(r->band_top_hz * lap);
    nh = (nh > CDPR_DESIGN_MAX_HARMONICS) ? CDPR_DESIGN_MAX_HARMONICS : nh;
    r->n_harmonics = nh;
    for (int h = 0; h <= nh && st == CDPR_OK; ++h) {
        /* h = 0: G at 1e-4 Hz (G_at_0_diag) */
        const double f = (h == 0) ? 1e-4 : (double)h / lap;
        const cplx z = cis(2.0 * k_pi * f * T);
        cplx G[NU_MAX * NU_MAX];
        for (int i = 0; i < nu; ++i) {
            for (int j = 0; j < nu; ++j) {
                cplx s = 0.0;
                for (int k = 0; k < Nc; ++k) {
                    s += CV[(size_t)k * nu_s + (size_t)i] / (z - w->lamC[k]) *
                         Wl[(size_t)j * NC + (size_t)k];
                }
                G[j * nu + i] = -s;
            }
        }
        if (h == 0) {
            for (int i = 0; i < nu; ++i) {
                r->g0_diag[i] = creal(G[i * (nu + 1)]);
            }
            continue;
        }
        const double q = learning_q(f, fc, dphi);
        const cplx e = cis(2.0 * k_pi * f * lead);
        cplx M[NU_MAX * NU_MAX];
        cplx M2[NU_MAX * NU_MAX];
        for (int i = 0; i < nu * nu; ++i) {
            M[i] = q * (((i % (nu + 1)) == 0 ? 1.0 : 0.0) - gamma * e * G[i]);
            M2[i] = M[i];
        }
        cplx ev[NU_MAX];
        double s[NU_MAX];
        if (eign(nu, M, ev) != 0 || svdn(nu, M2, s) != 0) {
            snprintf(err->msg, sizeof err->msg, "design: learning map at %g Hz", f);
            st = CDPR_E_NO_CONVERGENCE;
            break;
        }
        double rho = 0.0;
        for (int i = 0; i < nu; ++i) {
            rho = fmax(rho, cabs(ev[i]));
        }
        r->harmonic_hz[h - 1] = f;
        r->harmonic_q[h - 1] = q;
        r->rho[h - 1] = rho;
        r->sigma_max[h - 1] = s[0];
        if (rho > r->max_rho) {
            r->max_rho = rho;
            r->worst_harmonic = h;
        }
        if (rho >= 1.0 && r->first_diverging == 0) {
            r->first_diverging = h;
        }
    }
    free(CV);
    free(Wl);
    return st;
}

cdpr_status_t cdpr_design_analyse(const cdpr_design_model_t *m, int learn, cdpr_design_report_t *r,
                                  cdpr_design_error_t *err)
{
    memset(r, 0, sizeof *r);
    cdpr_status_t st = check_model(m, err);
    if (st != CDPR_OK) {
        return st;
    }
    const int n = m->n;
    const size_t nn = (size_t)n;
    const int Nc = n + m->nz + m->nu;
    const size_t NC = (size_t)Nc;
    const double T = m->period_s;
    const int want_learning =
        (learn != 0 && m->lap_s > 0.0 && m->learn_knots >= 2.0 && m->learning_gain > 0.0);
    work_t w;
    memset(&w, 0, sizeof w);
    w.Phi = malloc(sizeof(double) * nn * (nn + (size_t)m->nu));
    w.Acl = malloc(sizeof(double) * NC * NC);
    w.scratch = malloc(sizeof(double) * NC * NC);
    w.lamA = malloc(sizeof(cplx) * nn);
    w.VA = malloc(sizeof(cplx) * nn * nn);
    w.lamC = malloc(sizeof(cplx) * NC);
    w.VC = want_learning ? malloc(sizeof(cplx) * NC * NC) : NULL;
    w.ipiv = malloc(sizeof(int) * NC);
    if (w.Phi == NULL || w.Acl == NULL || w.scratch == NULL || w.lamA == NULL || w.VA == NULL ||
        w.lamC == NULL || (want_learning && w.VC == NULL) || w.ipiv == NULL) {
        analysis_free(&w);
        snprintf(err->msg, sizeof err->msg, "design: out of memory (n = %d)", n);
        return CDPR_E_CAPACITY;
    }
    w.Gam = w.Phi + nn * nn;
    st = discretise_col(m, w.Phi, w.Gam, err);
    /* closed loop */
    if (st == CDPR_OK) {
        st = closed_loop_matrix(m, &w, w.Acl);
        if (st != CDPR_OK) {
            snprintf(err->msg, sizeof err->msg, "design: out of memory (closed loop)");
        } else {
            memcpy(w.scratch, w.Acl, sizeof(double) * NC * NC);
            st = eig(Nc, w.scratch, w.lamC, w.VC, err);
        }
    }
    if (st == CDPR_OK) {
        int k = 0;
        for (int i = 1; i < Nc; ++i) {
            k = (cabs(w.lamC[i]) > cabs(w.lamC[k])) ? i : k;
        }
        r->max_abs_eig = cabs(w.lamC[k]);
        r->growth_per_s = log(r->max_abs_eig) / T;
        r->growth_hz = fabs(carg(w.lamC[k])) / (2.0 * k_pi * T);
        r->grows = (r->growth_per_s > CDPR_DESIGN_GROWTH_TOL) ? 1 : 0;
        /* modes of A */
        to_col(n, n, m->A, w.scratch);
        st = eig(n, w.scratch, w.lamA, w.VA, err);
    }
    int F = 0;
    if (st == CDPR_OK) {
        w.f = freq_grid(w.lamA, n, T, &F);
        if (w.f == NULL) {
            snprintf(err->msg, sizeof err->msg, "design: out of memory (grid)");
            st = CDPR_E_CAPACITY;
        }
    }
    r->n_freq = F;
    if (st == CDPR_OK) {
        st = loop_response(m, &w, F, err);
    }
    if (st == CDPR_OK) {
        st = loop_margins(m->nu, &w, F, r, err);
    }
    if (st == CDPR_OK && want_learning) {
        st = learning(m, &w, r, err);
    }
    analysis_free(&w);
    return st;
}
