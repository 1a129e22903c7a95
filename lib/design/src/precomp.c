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
    o->robust_mass = 0.0;
    o->robust_ea = 0.0;
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

/* Pose responses R (K x 6 x nu: R[(k * 6 + c) * nu + j]) of the loop linearised at `at_s`, the
 * plant varied by `plant` (the controller's model as sc has it), to basis function 0 on each
 * cable j (one column each). */
static cdpr_status_t responses(const cdpr_scenario_t *sc, const cdpr_rig_scale_t *plant,
                               double at_s, const run_t *shape, double spacing_s, double *R,
                               cdpr_design_error_t *err)
{
    cdpr_design_point_t *pt = NULL;
    cdpr_status_t st = cdpr_design_point_new(sc, at_s, plant, &pt, err);
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

/* One model of the cost: the plant as the scenario has it or varied (robust_mass, robust_ea),
 * the controller's model nominal in every one. */
typedef struct {
    cdpr_rig_scale_t plant; /* the plant's variation */
    cdpr_scenario_t *sc;    /* the scenario with the plant varied, the controller's model kept */
    double *G;              /* 6K x P: the lift of this model */
    run_t best;             /* its run with the best iterate */
    run_t tr;               /* its run with the trial */
} pmodel_t;

typedef struct {
    long K;     /* periods */
    int nc;     /* cables */
    int ncoef;  /* coefficients per cable */
    long shift; /* periods between two basis functions */
    int P;      /* nc ncoef */
    double *N;  /* P x P: sum of G_v^T G_v + λ' I, then its Cholesky factor */
    int nm;     /* models */
    pmodel_t m[CDPR_PRECOMP_MAX_MODELS];
} lift_t;

/* G_v from the responses at the poses: each basis function takes the pose nearest its centre,
 * delayed to its start. */
static cdpr_status_t model_lift(const cdpr_scenario_t *sc, const cdpr_precomp_opts_t *o,
                                const pmodel_t *pm, const double *at, double *R, lift_t *L,
                                cdpr_design_error_t *err)
{
    const int np = o->poses;
    const size_t rsize = (size_t)L->K * 6U * (size_t)L->nc;
    cdpr_status_t st = CDPR_OK;
    for (int p = 0; st == CDPR_OK && p < np; ++p) {
        if (o->log != NULL) {
            fprintf(o->log,
                    "cdpr-precomp: lift %d/%d: the loop linearised at t = %.4g s (plant: EA x "
                    "%.3g, cabin mass x %.3g)\n",
                    p + 1, np, at[p], pm->plant.ea, pm->plant.cabin_mass);
            fflush(o->log);
        }
        st = responses(sc, &pm->plant, at[p], &pm->best, o->spacing_s, &R[rsize * (size_t)p], err);
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
            double *col = &pm->G[rows * ((size_t)j * (size_t)L->ncoef + (size_t)i)];
            for (long k = k0; k < L->K; ++k) {
                for (int c = 0; c < 6; ++c) {
                    col[(size_t)k * 6U + (size_t)c] =
                        Rp[((size_t)(k - k0) * 6U + (size_t)c) * (size_t)L->nc + (size_t)j];
                }
            }
        }
    }
    return st;
}

static cdpr_status_t build_lift(const cdpr_scenario_t *sc, const cdpr_precomp_opts_t *o, lift_t *L,
                                cdpr_design_error_t *err)
{
    const double t_end = fmin(cdpr_traj_end_time(&sc->traj), sc->duration_s);
    const int np = o->poses;
    const size_t rsize = (size_t)L->K * 6U * (size_t)L->nc;
    double *R = calloc(rsize * (size_t)np, sizeof(double));
    if (R == NULL) {
        fail(err, "%sout of memory for the responses (%g poses)", "", (double)np);
        return CDPR_E_CAPACITY;
    }
    double at[64] = {0.0};
    for (int p = 0; p < np; ++p) {
        at[p] = (np == 1) ? 0.5 * t_end : t_end * (double)p / (double)(np - 1);
    }
    cdpr_status_t st = CDPR_OK;
    for (int v = 0; st == CDPR_OK && v < L->nm; ++v) {
        /* the nominal model's scenario: without the scenario's own correction file */
        st = model_lift(L->m[0].sc, o, &L->m[v], at, R, L, err);
    }
    free(R);
    if (st != CDPR_OK) {
        return st;
    }
    /* N = sum_v G_v^T G_v + λ' I and its Cholesky factor */
    const int P = L->P;
    const int nr = (int)(6 * L->K);
    const double one = 1.0;
    for (int v = 0; v < L->nm; ++v) {
        const double beta = (v == 0) ? 0.0 : 1.0;
        dsyrk_("U", "T", &P, &nr, &one, L->m[v].G, &nr, &beta, L->N, &P, 1, 1);
    }
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

/* Δa = N^-1 sum_v G_v^T e_v (the best iterate's errors) */
static void gn_step(const lift_t *L, double *da)
{
    const int nr = (int)(6 * L->K);
    const int P = L->P;
    const int inc = 1;
    const double one = 1.0;
    for (int v = 0; v < L->nm; ++v) {
        const double beta = (v == 0) ? 0.0 : 1.0;
        dgemv_("T", &nr, &P, &one, L->m[v].G, &nr, L->m[v].best.e, &inc, &beta, da, &inc, 1);
    }
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
    } else if (!(o->robust_mass >= 0.0 && o->robust_mass <= CDPR_PRECOMP_MAX_VARIATION)) {
        fail(err, "%s--robust-mass %g: 0 to 0.3", "", o->robust_mass);
    } else if (!(o->robust_ea >= 0.0 && o->robust_ea <= CDPR_PRECOMP_MAX_VARIATION)) {
        fail(err, "%s--robust-ea %g: 0 to 0.3", "", o->robust_ea);
    } else if (!(cdpr_traj_end_time(&sc->traj) > 0.0)) {
        fail(err, "%sthe trajectory does not move (type %g): nothing to pre-compensate", "",
             (double)sc->traj.type);
    } else {
        return CDPR_OK;
    }
    return CDPR_E_OUT_OF_RANGE;
}

/* The models of the cost: the plant as written, then cabin mass and EA (1 ± x) when asked. */
static int model_list(const cdpr_precomp_opts_t *o, cdpr_rig_scale_t plant[])
{
    int n = 0;
    plant[n++] = cdpr_rig_scale_unit();
    const double xs[2] = {o->robust_mass, o->robust_ea};
    for (int k = 0; k < 2; ++k) {
        for (int sign = 1; xs[k] > 0.0 && sign >= -1; sign -= 2) {
            cdpr_rig_scale_t f = cdpr_rig_scale_unit();
            *((k == 0) ? &f.cabin_mass : &f.ea) = 1.0 + (double)sign * xs[k];
            plant[n++] = f;
        }
    }
    return n;
}

/* The scenario of a model: the plant's rig varied, controller.model divided by the same factor
 * so that the controller's model (the rig times controller.model) stays the scenario's. */
static void vary(cdpr_scenario_t *sc, const cdpr_rig_scale_t *f)
{
    cdpr_rig_scale(&sc->rig, f);
    sc->controller_model.ea /= f->ea;
    sc->controller_model.cabin_mass /= f->cabin_mass;
    sc->controller_model.rope_mass /= f->rope_mass;
}

/* Every model with coefficients `c`: into each model's `tr` (trial) or `best` (first run).
 * Returns the first failed run's status; *cost the sum of squares, *min_T the smallest
 * tension, *worst the largest RMS after 2 s over the models. */
static cdpr_status_t run_all(lift_t *L, const cdpr_tracker_correction_t *c, int first, double *cost,
                             double *min_T, double *worst, cdpr_design_error_t *err)
{
    *cost = 0.0;
    *min_T = HUGE_VAL;
    *worst = 0.0;
    for (int v = 0; v < L->nm; ++v) {
        run_t *r = (first != 0) ? &L->m[v].best : &L->m[v].tr;
        const cdpr_status_t st = model_run(L->m[v].sc, c, r, err);
        if (st != CDPR_OK) {
            if (err != NULL && v > 0) { /* which of the varied plants */
                const size_t n = strlen(err->msg);
                (void)snprintf(&err->msg[n], sizeof err->msg - n,
                               " (the plant varied: cabin mass x %.3g, EA x %.3g)",
                               L->m[v].plant.cabin_mass, L->m[v].plant.ea);
            }
            return st;
        }
        *cost += r->sum2;
        *min_T = fmin(*min_T, r->min_T);
        *worst = fmax(*worst, rms_after(r));
    }
    return CDPR_OK;
}

static void free_lift(lift_t *L)
{
    for (int v = 0; v < L->nm; ++v) {
        free(L->m[v].sc);
        free(L->m[v].G);
        free(L->m[v].best.e);
        free(L->m[v].tr.e);
    }
    free(L->N);
}

static cdpr_status_t alloc_lift(const cdpr_scenario_t *sc, const cdpr_precomp_opts_t *o, lift_t *L,
                                cdpr_design_error_t *err)
{
    cdpr_rig_scale_t plant[CDPR_PRECOMP_MAX_MODELS];
    L->nm = model_list(o, plant);
    const size_t P = (size_t)L->P;
    int bad = 0;
    for (int v = 0; v < L->nm; ++v) {
        pmodel_t *pm = &L->m[v];
        const run_t r0 = {L->K, L->nc, o->rot_weight_m, NULL, 0.0, 0.0, 0.0, 0, 0.0, 0.0};
        pm->plant = plant[v];
        pm->best = r0;
        pm->tr = r0;
        pm->sc = malloc(sizeof *pm->sc);
        pm->G = calloc(6U * (size_t)L->K * P, sizeof(double));
        pm->best.e = malloc(sizeof(double) * 6U * (size_t)L->K);
        pm->tr.e = malloc(sizeof(double) * 6U * (size_t)L->K);
        if (pm->sc == NULL || pm->G == NULL || pm->best.e == NULL || pm->tr.e == NULL) {
            bad = 1;
        } else {
            *pm->sc = *sc;
            pm->sc->precompensation[0] = '\0'; /* the iterates, not the scenario's file */
            vary(pm->sc, &pm->plant);
        }
    }
    L->N = malloc(sizeof(double) * P * P);
    if (bad != 0 || L->N == NULL) {
        fail(err, "%sout of memory for the lift (%g coefficients)", "", (double)P);
        return CDPR_E_CAPACITY;
    }
    return CDPR_OK;
}

static void log_run(const cdpr_precomp_opts_t *o, const lift_t *L, int runs, double alpha,
                    const char *what, int first, double worst)
{
    if (o->log == NULL) {
        return;
    }
    const run_t *r = (first != 0) ? &L->m[0].best : &L->m[0].tr;
    fprintf(o->log,
            "cdpr-precomp: run %d (%s): RMS %.3f mm after %g s, max %.3f mm, %.3f mrad, min "
            "tension %.1f N",
            runs, what, 1e3 * rms_after(r), RMS_AFTER_S, 1e3 * r->max_pos, 1e3 * r->max_rot,
            r->min_T);
    if (L->nm > 1) {
        double tmin = HUGE_VAL;
        for (int v = 1; v < L->nm; ++v) {
            tmin = fmin(tmin, ((first != 0) ? &L->m[v].best : &L->m[v].tr)->min_T);
        }
        fprintf(o->log, "; the %d varied plants: worst RMS %.3f mm, min tension %.1f N", L->nm - 1,
                1e3 * worst, tmin);
    }
    fprintf(o->log, " (step %.3g)\n", alpha);
    fflush(o->log);
}

cdpr_status_t cdpr_design_precompensate(const cdpr_scenario_t *sc, const cdpr_precomp_opts_t *o,
                                        cdpr_host_correction_t *hc, cdpr_design_error_t *err)
{
    cdpr_status_t st = check_opts(sc, o, err);
    if (st != CDPR_OK) {
        return st;
    }
    lift_t L;
    memset(&L, 0, sizeof L);
    L.K = cdpr_scenario_count(sc->duration_s / sc->period_s);
    L.nc = sc->rig.n_cables;
    L.shift = (long)nearbyint(o->spacing_s / sc->period_s);
    L.ncoef = (int)(L.K / L.shift) - 1;
    L.P = L.nc * L.ncoef;
    cdpr_rig_scale_t plant[CDPR_PRECOMP_MAX_MODELS];
    const double bytes = 8.0 * 6.0 * (double)L.K * (double)L.P * (double)model_list(o, plant);
    if (L.ncoef < 1 || L.ncoef > CDPR_CORRECTION_MAX_COEF || bytes > CDPR_PRECOMP_MAX_LIFT_BYTES) {
        fail(err,
             "%sthe run needs %g coefficients per cable or a lift too large (a longer spacing, "
             "a shorter run.duration_s, fewer varied plants)",
             "", (double)L.ncoef);
        return CDPR_E_OUT_OF_RANGE;
    }
    st = cdpr_correction_init(hc, sc, L.ncoef, 0.0, (double)L.shift * sc->period_s);
    if (st == CDPR_OK) {
        st = alloc_lift(sc, o, &L, err);
    }
    const size_t P = (size_t)L.P;
    double *a_best = calloc(P, sizeof(double));
    double *da = malloc(sizeof(double) * P);
    if (st == CDPR_OK && (a_best == NULL || da == NULL)) {
        fail(err, "%sout of memory for the lift (%g coefficients)", "", (double)P);
        st = CDPR_E_CAPACITY;
    }
    int runs = 0;
    double cost_best = 0.0;
    double tmin = 0.0;
    double worst = 0.0;
    double tmin_best = 0.0;
    if (st == CDPR_OK) { /* run 0: no correction (all coefficients 0) */
        st = run_all(&L, &hc->c, 1, &cost_best, &tmin_best, &worst, err);
        runs = 1;
    }
    const double rms0 = (st == CDPR_OK) ? rms_after(&L.m[0].best) : (double)NAN;
    if (st == CDPR_OK) {
        log_run(o, &L, runs, 0.0, "no correction", 1, worst);
    }
    if (st == CDPR_OK && o->max_runs > 1) {
        st = build_lift(sc, o, &L, err);
    }
    double alpha = 1.0;
    int halvings = 0;
    while (st == CDPR_OK && runs < o->max_runs) {
        if (halvings == 0) {
            gn_step(&L, da);
        }
        for (size_t i = 0; i < P; ++i) {
            hc->coef_m[i] = (cdpr_real_t)(a_best[i] + alpha * da[i]);
        }
        double cost = 0.0;
        const cdpr_status_t rs = run_all(&L, &hc->c, 0, &cost, &tmin, &worst, NULL);
        runs++;
        /* the floor, or where the best iterate already is when a plant starts below it */
        const int ok =
            (rs == CDPR_OK && cost < cost_best && tmin >= fmin(o->floor_N, tmin_best)) ? 1 : 0;
        log_run(o, &L, runs, alpha,
                (rs != CDPR_OK) ? "refused, a model run failed"
                : (ok != 0)     ? "kept"
                                : "refused",
                0, worst);
        if (ok != 0) {
            for (size_t i = 0; i < P; ++i) {
                a_best[i] = (double)hc->coef_m[i];
            }
            for (int v = 0; v < L.nm; ++v) {
                const run_t t = L.m[v].best;
                L.m[v].best = L.m[v].tr;
                L.m[v].tr = t;
            }
            cost_best = cost;
            tmin_best = tmin;
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
        const run_t *b = &L.m[0].best;
        for (size_t i = 0; i < P; ++i) {
            hc->coef_m[i] = (cdpr_real_t)a_best[i];
        }
        hc->report.iterations = runs;
        hc->report.rms_before_m = rms0;
        hc->report.rms_after_m = rms_after(b);
        hc->report.max_after_m = b->max_pos;
        hc->report.max_after_rad = b->max_rot;
        hc->report.min_tension_N = b->min_T;
        hc->report.robust_mass = o->robust_mass;
        hc->report.robust_ea = o->robust_ea;
        for (int v = 1; v < L.nm; ++v) {
            const run_t *r = &L.m[v].best;
            hc->report.varied_rms_after_m =
                (v == 1) ? rms_after(r) : fmax(hc->report.varied_rms_after_m, rms_after(r));
            hc->report.varied_max_after_m =
                (v == 1) ? r->max_pos : fmax(hc->report.varied_max_after_m, r->max_pos);
            hc->report.varied_max_after_rad =
                (v == 1) ? r->max_rot : fmax(hc->report.varied_max_after_rad, r->max_rot);
            hc->report.varied_min_tension_N =
                (v == 1) ? r->min_T : fmin(hc->report.varied_min_tension_N, r->min_T);
        }
        hc->floor_N = o->floor_N;
    }
    free_lift(&L);
    free(a_best);
    free(da);
    return st;
}
