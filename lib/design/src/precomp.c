/* SPDX-License-Identifier: BSD-3-Clause */
/// @file precomp.c
/// Offline pre-compensation of a known trajectory (design.h, cdpr_design_precompensate): the
/// lift from the linearised closed loop at poses along the motion, regularised Gauss-Newton
/// steps on the nonlinear model's pose error, the best iterate kept.
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cdpr/design/design.h"
#include "cdpr/host/sim.h"
#include "cdpr/vec3.h"

/* The Fortran routines (reference LAPACK 3.x / any BLAS), with gfortran's hidden lengths of
 * the character arguments. */
void dgemm_(const char *ta, const char *tb, const int *m, const int *n, const int *k,
            const double *alpha, const double *a, const int *lda, const double *b, const int *ldb,
            const double *beta, double *c, const int *ldc, size_t lta, size_t ltb);
void dgemv_(const char *t, const int *m, const int *n, const double *alpha, const double *a,
            const int *lda, const double *x, const int *incx, const double *beta, double *y,
            const int *incy, size_t lt);
void dsyrk_(const char *uplo, const char *t, const int *n, const int *k, const double *alpha,
            const double *a, const int *lda, const double *beta, double *c, const int *ldc,
            size_t lu, size_t lt);
void dpotrf_(const char *uplo, const int *n, double *a, const int *lda, int *info, size_t lu);
void dpotrs_(const char *uplo, const int *n, const int *nrhs, const double *a, const int *lda,
             double *b, const int *ldb, int *info, size_t lu);

#define RMS_AFTER_S 2.0 /* the measure: the pose error after 2 s */

void cdpr_precomp_opts_default(cdpr_precomp_opts_t *o)
{
    o->poses = 5;
    o->spacing_s = 0.3;
    o->max_runs = 8;
    o->floor_N = 20.0;
    o->lambda = 1e-3;
    o->rot_weight_m = 1.0;
    o->log = NULL;
}

static void fail(cdpr_design_error_t *err, const char *fmt, const char *a, double v)
{
    if (err != NULL) {
        snprintf(err->msg, sizeof err->msg, fmt, a, v);
    }
}

/* ---------------------------------------------------------------- model runs */

typedef struct {
    long K;          /* periods with a command: the rows of e */
    int nc;          /* cables */
    double w_rot;    /* attitude weight [m/rad] */
    double *e;       /* K x 6 weighted pose error (position, attitude) */
    double min_T;    /* smallest cable-end tension [N] */
    double sum2;     /* sum of squares of e (the cost) */
    double sum2_pos; /* after RMS_AFTER_S: position error's sum of squares */
    long n_after;
    double max_pos; /* after RMS_AFTER_S */
    double max_rot;
} run_t;

static void on_period(void *ctx, long k, const cdpr_record_row_t *row,
                      const cdpr_tracker_cmd_t *cmd)
{
    run_t *r = ctx;
    for (int j = 0; j < r->nc; ++j) {
        r->min_T = fmin(r->min_T, fmin(row->tension_cabin_N[j], row->tension_winch_N[j]));
    }
    /* The figures as timeseries.csv has them: every row, the last (no command) included. */
    if (row->t_s >= RMS_AFTER_S - 1e-9) {
        const cdpr_vec3_t d = cdpr_v3_sub(row->des->motion.p_m, row->meas->cabin.p_m);
        const double p2 = (double)cdpr_v3_dot(d, d);
        r->sum2_pos += p2;
        r->n_after++;
        r->max_pos = fmax(r->max_pos, sqrt(p2));
    }
    if (cmd == NULL || k >= r->K) {
        return;
    }
    double *e = &r->e[6 * k];
    double r2 = 0.0;
    for (int c = 0; c < 3; ++c) {
        e[c] = cmd->err_pos_m[c];
        e[3 + c] = r->w_rot * cmd->err_rot_rad[c];
        r2 += (double)cmd->err_rot_rad[c] * (double)cmd->err_rot_rad[c];
        r->sum2 += e[c] * e[c] + e[3 + c] * e[3 + c];
    }
    if (row->t_s >= RMS_AFTER_S - 1e-9) {
        r->max_rot = fmax(r->max_rot, sqrt(r2)); /* the periods with a command */
    }
}

/* One nonlinear run of sc with correction c. CDPR_OK (r filled) or the run's status. */
static cdpr_status_t model_run(const cdpr_scenario_t *sc, const cdpr_tracker_correction_t *c,
                               run_t *r, cdpr_design_error_t *err)
{
    r->min_T = HUGE_VAL;
    r->sum2 = 0.0;
    r->sum2_pos = 0.0;
    r->n_after = 0;
    r->max_pos = 0.0;
    r->max_rot = 0.0;
    memset(r->e, 0, sizeof(double) * 6U * (size_t)r->K);
    cdpr_sim_opts_t o;
    cdpr_sim_opts_default(&o);
    o.correction = c;
    o.on_period = on_period;
    o.on_period_ctx = r;
    cdpr_summary_t sum;
    cdpr_scenario_error_t se;
    se.msg[0] = '\0';
    const cdpr_status_t st = cdpr_sim_run(sc, &o, &sum, &se);
    if (st != CDPR_OK && err != NULL) {
        snprintf(err->msg, sizeof err->msg, "model run: %s: %.900s", cdpr_status_str(st),
                 (se.msg[0] != '\0') ? se.msg : sum.message);
    }
    return st;
}

static double rms_after(const run_t *r)
{
    return (r->n_after > 0) ? sqrt(r->sum2_pos / (double)r->n_after) : (double)NAN;
}

/* ---------------------------------------------------------------- the lift */

/* C = op(A) B, column-major. */
static void gemm(const char *ta, int m, int n, int k, const double *A, int lda, const double *B,
                 int ldb, double beta, double *C, int ldc)
{
    const double one = 1.0;
    dgemm_(ta, "N", &m, &n, &k, &one, A, &lda, B, &ldb, &beta, C, &ldc, 1, 1);
}

/* The basis input of one coefficient at sample k: what the tracker adds (step 4c) for a
 * correction whose only coefficient is 1. */
static double basis_input(const cdpr_tracker_correction_t *b, long k, double dt, double k_l)
{
    const double c0 = (double)cdpr_tracker_correction_at(b, 0, (cdpr_real_t)((double)k * dt));
    const double c1 = (double)cdpr_tracker_correction_at(b, 0, (cdpr_real_t)((double)(k + 1) * dt));
    return ((c1 - c0) / dt) + (k_l * c0);
}

/* Pose responses R (K x 6 x nu: R[(k * 6 + c) * nu + j]) of the loop linearised at `at_s` to
 * basis function 0 on each cable j (one column each). */
static cdpr_status_t responses(const cdpr_scenario_t *sc, double at_s, const run_t *shape,
                               double spacing_s, double *R, cdpr_design_error_t *err)
{
    cdpr_design_point_t *pt = NULL;
    cdpr_status_t st = cdpr_design_point_new(sc, at_s, NULL, &pt, err);
    cdpr_design_model_t m;
    memset(&m, 0, sizeof m);
    if (st == CDPR_OK) {
        st = cdpr_design_linearise(pt, &m, err);
    }
    cdpr_design_point_free(pt);
    if (st != CDPR_OK) {
        cdpr_design_model_free(&m);
        return st;
    }
    const int n = m.n;
    const int nu = m.nu;
    const int nz = m.nz;
    const size_t sn = (size_t)n;
    const size_t snu = (size_t)nu;
    const size_t snz = (size_t)nz;
    double *Phi = malloc(sizeof(double) * sn * sn);
    double *Gam = malloc(sizeof(double) * sn * snu);
    double *x = calloc(sn * snu, sizeof(double));
    double *x1 = calloc(sn * snu, sizeof(double));
    double *z = calloc(snz * snu, sizeof(double));
    double *z1 = calloc(snz * snu, sizeof(double));
    double *u = calloc(snu * snu, sizeof(double));
    double *up = calloc(snu * snu, sizeof(double));
    double *y = calloc(6U * snu, sizeof(double));
    if (Phi == NULL || Gam == NULL || x == NULL || x1 == NULL || z == NULL || z1 == NULL ||
        u == NULL || up == NULL || y == NULL) {
        st = CDPR_E_CAPACITY;
        fail(err, "%sout of memory for the lift (%g states)", "", (double)n);
    }
    if (st == CDPR_OK) {
        st = cdpr_design_discretise(&m, Phi, Gam, err);
    }
    const cdpr_real_t one = 1.0;
    const cdpr_tracker_correction_t b = {
        1, 1, 0.0, (cdpr_real_t)spacing_s, (cdpr_real_t)sc->period_s, &one};
    /* Row-major r x c matrices are column-major c x r: op "T" gives the product. */
    for (long k = 0; st == CDPR_OK && k < shape->K; ++k) {
        /* y_k = Cm[0:6] x_k */
        gemm("T", 6, nu, n, m.Cm, n, x, n, 0.0, y, 6);
        for (int c = 0; c < 6; ++c) {
            const double w = (c < 3) ? 1.0 : shape->w_rot;
            for (int j = 0; j < nu; ++j) {
                R[((size_t)k * 6U + (size_t)c) * snu + (size_t)j] =
                    w * y[(size_t)j * 6U + (size_t)c];
            }
        }
        /* u_k = Kx x + Kz z + Ku u_{k-1} + v_k I */
        gemm("T", nu, nu, n, m.Kx, n, x, n, 0.0, u, nu);
        gemm("T", nu, nu, nz, m.Kz, nz, z, nz, 1.0, u, nu);
        gemm("T", nu, nu, nu, m.Ku, nu, up, nu, 1.0, u, nu);
        const double v = basis_input(&b, k, sc->period_s, sc->gains.k_length_per_s);
        for (int j = 0; j < nu; ++j) {
            u[(size_t)j * snu + (size_t)j] += v;
        }
        /* z_{k+1} = Zx x + Zz z + Zu u_{k-1};  x_{k+1} = Phi x + Gam u_k */
        gemm("T", nz, nu, n, m.Zx, n, x, n, 0.0, z1, nz);
        gemm("T", nz, nu, nz, m.Zz, nz, z, nz, 1.0, z1, nz);
        gemm("T", nz, nu, nu, m.Zu, nu, up, nu, 1.0, z1, nz);
        gemm("T", n, nu, n, Phi, n, x, n, 0.0, x1, n);
        gemm("T", n, nu, nu, Gam, nu, u, nu, 1.0, x1, n);
        double *t = x;
        x = x1;
        x1 = t;
        t = z;
        z = z1;
        z1 = t;
        t = up;
        up = u;
        u = t;
    }
    free(Phi);
    free(Gam);
    free(x);
    free(x1);
    free(z);
    free(z1);
    free(u);
    free(up);
    free(y);
    cdpr_design_model_free(&m);
    return st;
}

/* ---------------------------------------------------------------- the iteration */

typedef struct {
    long K;     /* periods */
    int nc;     /* cables */
    int ncoef;  /* coefficients per cable */
    long shift; /* periods between two basis functions */
    int P;      /* nc ncoef */
    double *N;  /* P x P: G^T G + λ' I, then its Cholesky factor */
    double *G;  /* 6K x P */
} lift_t;

static cdpr_status_t build_lift(const cdpr_scenario_t *sc, const cdpr_precomp_opts_t *o,
                                const run_t *shape, lift_t *L, cdpr_design_error_t *err)
{
    const double t_end = fmin(cdpr_traj_end_time(&sc->traj), sc->duration_s);
    const int np = o->poses;
    const size_t rsize = (size_t)L->K * 6U * (size_t)L->nc;
    double *R = calloc(rsize * (size_t)np, sizeof(double));
    if (R == NULL) {
        fail(err, "%sout of memory for the responses (%g poses)", "", (double)np);
        return CDPR_E_CAPACITY;
    }
    cdpr_status_t st = CDPR_OK;
    double at[64] = {0.0};
    for (int p = 0; st == CDPR_OK && p < np; ++p) {
        at[p] = (np == 1) ? 0.5 * t_end : t_end * (double)p / (double)(np - 1);
        if (o->log != NULL) {
            fprintf(o->log, "cdpr-precomp: lift %d/%d: the loop linearised at t = %.4g s\n", p + 1,
                    np, at[p]);
            fflush(o->log);
        }
        st = responses(sc, at[p], shape, o->spacing_s, &R[rsize * (size_t)p], err);
    }
    const size_t rows = 6U * (size_t)L->K;
    for (int i = 0; st == CDPR_OK && i < L->ncoef; ++i) {
        /* the pose nearest the basis function's centre, (i + 2) h */
        const double centre = ((double)i + 2.0) * o->spacing_s;
        int best = 0;
        for (int p = 1; p < np; ++p) {
            if (fabs(at[p] - centre) < fabs(at[best] - centre)) {
                best = p;
            }
        }
        const double *Rp = &R[rsize * (size_t)best];
        const long k0 = (long)i * L->shift;
        for (int j = 0; j < L->nc; ++j) {
            double *col = &L->G[rows * ((size_t)j * (size_t)L->ncoef + (size_t)i)];
            for (long k = k0; k < L->K; ++k) {
                for (int c = 0; c < 6; ++c) {
                    col[(size_t)k * 6U + (size_t)c] =
                        Rp[((size_t)(k - k0) * 6U + (size_t)c) * (size_t)L->nc + (size_t)j];
                }
            }
        }
    }
    free(R);
    if (st != CDPR_OK) {
        return st;
    }
    /* N = G^T G + λ' I and its Cholesky factor */
    const int P = L->P;
    const int nr = (int)rows;
    const double one = 1.0;
    const double zero = 0.0;
    dsyrk_("U", "T", &P, &nr, &one, L->G, &nr, &zero, L->N, &P, 1, 1);
    double tr = 0.0;
    for (int i = 0; i < P; ++i) {
        tr += L->N[(size_t)i * (size_t)P + (size_t)i];
    }
    const double lam = o->lambda * tr / (double)P;
    if (!(lam > 0.0) || !isfinite(lam)) {
        fail(err, "%sthe lift is zero or not finite (trace %g)", "", tr);
        return CDPR_E_SINGULAR;
    }
    for (int i = 0; i < P; ++i) {
        L->N[(size_t)i * (size_t)P + (size_t)i] += lam;
    }
    int info = 0;
    dpotrf_("U", &P, L->N, &P, &info, 1);
    if (info != 0) {
        fail(err, "%sthe lift's normal matrix is not positive definite (LAPACK info %g)", "",
             (double)info);
        return CDPR_E_SINGULAR;
    }
    return CDPR_OK;
}

/* Δa = N^-1 G^T e */
static void gn_step(const lift_t *L, const double *e, double *da)
{
    const int nr = (int)(6 * L->K);
    const int P = L->P;
    const int inc = 1;
    const double one = 1.0;
    const double zero = 0.0;
    dgemv_("T", &nr, &P, &one, L->G, &nr, e, &inc, &zero, da, &inc, 1);
    int info = 0;
    dpotrs_("U", &P, &inc, L->N, &P, da, &P, &info, 1);
}

static cdpr_status_t check_opts(const cdpr_scenario_t *sc, const cdpr_precomp_opts_t *o,
                                cdpr_design_error_t *err)
{
    const double ratio = o->spacing_s / sc->period_s;
    if (o->poses < 1 || o->poses > 64) {
        fail(err, "%s--poses %g: 1 to 64", "", (double)o->poses);
    } else if (!(o->max_runs >= 1 && o->max_runs <= 1000)) {
        fail(err, "%s--runs %g: 1 to 1000", "", (double)o->max_runs);
    } else if (!(ratio >= 1.0 - 1e-9) || fabs(ratio - nearbyint(ratio)) > 1e-6 * ratio) {
        fail(err, "%s--spacing %g s: a whole number of control periods", "", o->spacing_s);
    } else if (!(o->lambda > 0.0) || !isfinite(o->lambda)) {
        fail(err, "%s--lambda %g: > 0", "", o->lambda);
    } else if (!isfinite(o->floor_N) || !(o->rot_weight_m >= 0.0) || !isfinite(o->rot_weight_m)) {
        fail(err, "%sa tension floor or attitude weight that is not a finite number (%g)", "",
             o->floor_N);
    } else if (!(cdpr_traj_end_time(&sc->traj) > 0.0)) {
        fail(err, "%sthe trajectory does not move (type %g): nothing to pre-compensate", "",
             (double)sc->traj.type);
    } else {
        return CDPR_OK;
    }
    return CDPR_E_OUT_OF_RANGE;
}

cdpr_status_t cdpr_design_precompensate(const cdpr_scenario_t *sc_in, const cdpr_precomp_opts_t *o,
                                        cdpr_host_correction_t *hc, cdpr_design_error_t *err)
{
    cdpr_status_t st = check_opts(sc_in, o, err);
    if (st != CDPR_OK) {
        return st;
    }
    cdpr_scenario_t *sc = malloc(sizeof *sc);
    if (sc == NULL) {
        fail(err, "%sout of memory (%g)", "", 0.0);
        return CDPR_E_CAPACITY;
    }
    *sc = *sc_in;
    sc->precompensation[0] = '\0'; /* the iterates, not the scenario's file */
    lift_t L;
    memset(&L, 0, sizeof L);
    L.K = cdpr_scenario_count(sc->duration_s / sc->period_s);
    L.nc = sc->rig.n_cables;
    L.shift = (long)nearbyint(o->spacing_s / sc->period_s);
    L.ncoef = (int)(L.K / L.shift) - 1;
    L.P = L.nc * L.ncoef;
    const double bytes = 8.0 * 6.0 * (double)L.K * (double)L.P;
    if (L.ncoef < 1 || L.ncoef > CDPR_CORRECTION_MAX_COEF || bytes > CDPR_PRECOMP_MAX_LIFT_BYTES) {
        fail(err,
             "%sthe run needs %g coefficients per cable or a lift too large (a longer spacing, "
             "a shorter run.duration_s)",
             "", (double)L.ncoef);
        free(sc);
        return CDPR_E_OUT_OF_RANGE;
    }
    st = cdpr_correction_init(hc, sc, L.ncoef, 0.0, (double)L.shift * sc->period_s);
    run_t best = {L.K, L.nc, o->rot_weight_m, NULL, 0.0, 0.0, 0.0, 0, 0.0, 0.0};
    run_t tr = best;
    const size_t P = (size_t)L.P;
    best.e = malloc(sizeof(double) * 6U * (size_t)L.K);
    tr.e = malloc(sizeof(double) * 6U * (size_t)L.K);
    L.G = calloc(6U * (size_t)L.K * P, sizeof(double));
    L.N = malloc(sizeof(double) * P * P);
    double *a_best = calloc(P, sizeof(double));
    double *da = malloc(sizeof(double) * P);
    if (best.e == NULL || tr.e == NULL || L.G == NULL || L.N == NULL || a_best == NULL ||
        da == NULL) {
        fail(err, "%sout of memory for the lift (%g coefficients)", "", (double)P);
        st = CDPR_E_CAPACITY;
    }
    int runs = 0;
    if (st == CDPR_OK) { /* run 0: no correction (all coefficients 0) */
        st = model_run(sc, &hc->c, &best, err);
        runs = 1;
    }
    const double rms0 = rms_after(&best);
    if (o->log != NULL && st == CDPR_OK) {
        fprintf(o->log,
                "cdpr-precomp: run 1 (no correction): RMS %.3f mm after %g s, max %.3f mm, "
                "%.3f mrad, min tension %.1f N\n",
                1e3 * rms0, RMS_AFTER_S, 1e3 * best.max_pos, 1e3 * best.max_rot, best.min_T);
    }
    if (st == CDPR_OK && o->max_runs > 1) {
        st = build_lift(sc, o, &best, &L, err);
    }
    double alpha = 1.0;
    int halvings = 0;
    while (st == CDPR_OK && runs < o->max_runs) {
        if (halvings == 0) {
            gn_step(&L, best.e, da);
        }
        for (size_t i = 0; i < P; ++i) {
            hc->coef_m[i] = (cdpr_real_t)(a_best[i] + alpha * da[i]);
        }
        const cdpr_status_t rs = model_run(sc, &hc->c, &tr, NULL);
        runs++;
        const int ok = (rs == CDPR_OK && tr.sum2 < best.sum2 && tr.min_T >= o->floor_N) ? 1 : 0;
        if (o->log != NULL) {
            fprintf(o->log,
                    "cdpr-precomp: run %d (step %.3g): %s%s RMS %.3f mm after %g s, max %.3f mm, "
                    "%.3f mrad, min tension %.1f N\n",
                    runs, alpha, (ok != 0) ? "kept" : "refused",
                    (rs != CDPR_OK) ? " (the model run failed)" : ":", 1e3 * rms_after(&tr),
                    RMS_AFTER_S, 1e3 * tr.max_pos, 1e3 * tr.max_rot, tr.min_T);
            fflush(o->log);
        }
        if (ok != 0) {
            for (size_t i = 0; i < P; ++i) {
                a_best[i] = (double)hc->coef_m[i];
            }
            double *t = best.e;
            best = tr;
            tr.e = t;
            alpha = 1.0;
            halvings = 0;
        } else if (halvings < 2) {
            alpha *= 0.5;
            halvings++;
        } else {
            break; /* no step kept: the best iterate stands */
        }
    }
    if (st == CDPR_OK) {
        for (size_t i = 0; i < P; ++i) {
            hc->coef_m[i] = (cdpr_real_t)a_best[i];
        }
        hc->report.iterations = runs;
        hc->report.rms_before_m = rms0;
        hc->report.rms_after_m = rms_after(&best);
        hc->report.max_after_m = best.max_pos;
        hc->report.max_after_rad = best.max_rot;
        hc->report.min_tension_N = best.min_T;
        hc->floor_N = o->floor_N;
    }
    free(best.e);
    free(tr.e);
    free(L.G);
    free(L.N);
    free(a_best);
    free(da);
    free(sc);
    return st;
}
