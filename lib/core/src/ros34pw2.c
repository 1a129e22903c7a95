/* SPDX-License-Identifier: BSD-3-Clause */
/// @file ros34pw2.c
/// Rosenbrock-W method ROS34PW2 with step control (docs/model.md "Time integration").
///
/// Coefficients: J. Rang and L. Angermann, "New Rosenbrock W-methods of order 3 for partial
/// differential algebraic equations of index 1", BIT 45 (2005) 761-787, method ROS34PW2, in
/// the (alpha, Gamma, b, bhat) form of Hairer & Wanner IV.7:
///   gamma = 0.435866521508459
///   alpha21 = 0.87173304301691801, alpha31 = 0.84457060015369423,
///   alpha32 = -0.11299064236484185, alpha41 = alpha42 = 0, alpha43 = 1
///   gamma21 = -0.87173304301691801, gamma31 = -0.90338057013044082,
///   gamma32 = 0.054180672388095326, gamma41 = 0.24212380706095346,
///   gamma42 = -1.2232505839045147, gamma43 = 0.54526025533510214
///   b    = (0.24212380706095346, -1.2232505839045147, 1.5452602553351020, gamma)
///   bhat = (0.37810903145819369, -0.096042292212423178, 0.5, 0.2179332607542295)
/// and transformed here (30-digit arithmetic) to a = alpha Gamma^-1, c = diag(1/gamma) -
/// Gamma^-1, m = b Gamma^-1, mhat = bhat Gamma^-1, so that no product with J is needed; the
/// stages are solved scaled by 1/(gamma h), with gamma c_ij as constants (ros_try). The
/// order conditions (order 3, embedded 2) hold for these values to 2e-16; tests/unit/
/// test_ros34pw2.c measures the order and the stability function.
#include "cdpr/ros34pw2.h"

#include <math.h>
#include <stddef.h>

#include "check.h"
#include "step.h"

#define GAMMA CDPR_R(0.435866521508459)
/* Stage times alpha_i = sum_j alpha_ij. */
#define ALPHA2 CDPR_R(0.87173304301691801)
#define ALPHA3 CDPR_R(0.73157995778885238)
#define ALPHA4 CDPR_R(1.0)
/* a_ij (stage states). */
#define A21 CDPR_R(2.0000000000000000229)
#define A31 CDPR_R(1.4192173174557646500)
#define A32 CDPR_R(-0.25923221167296971378)
#define A41 CDPR_R(4.1847604823191607312)
#define A42 CDPR_R(-0.28519201735549591370)
#define A43 CDPR_R(2.2942803602790417167)
/* gamma c_ij (stage right-hand sides of the scaled stages v_i = u_i / (gamma h), see ros_try). */
#define GC21 CDPR_R(-2.0000000000000000229282014293589199)
#define GC31 CDPR_R(-1.8239969947745137296274783014252208)
#define GC32 CDPR_R(0.12430565256672007208669333448398830)
#define GC41 CDPR_R(-2.7756761163024680797381504435714465)
#define GC42 CDPR_R(-2.9619836625547887173740055318838396)
#define GC43 CDPR_R(1.2509798950560604161150341212585428)
/* m_i (propagated solution) need no constants: the method is stiffly accurate, m_i = a_4i and
 * m_4 = 1, so the new state is stage 4's state plus the last stage (ros_finish). */
/* e_i = m_i - mhat_i (error estimate). */
#define E1 CDPR_R(0.27774994764796811038)
#define E2 CDPR_R(-1.4032398951759990242)
#define E3 CDPR_R(1.7726301276675507452)
#define E4 CDPR_R(0.5)

/* Workspace slots. */
#define U1   0
#define U2   1
#define U3   2
#define U4   3
#define YTMP 4
#define F1   5
#define FT   6
#define YNEW 7
#define YBAK 8

static cdpr_real_t *ros_slot(const cdpr_ros_t *s, int k)
{
    return s->work + (size_t)k * (size_t)s->dim_max;
}

void cdpr_ros_params_default(cdpr_ros_params_t *p)
{
    cdpr_step_control_default(&p->step, 3); /* error estimate O(h^3) */
    p->jac_reuse_max = 0;
}

cdpr_status_t cdpr_ros_params_validate(const cdpr_ros_params_t *p, int dim, cdpr_diag_t *diag)
{
    if (p == NULL) {
        return cdpr_diag_set(diag, CDPR_E_INVALID_ARG, "ros", -1);
    }
    CDPR_TRY(cdpr_step_control_validate(&p->step, dim, diag));
    if (p->jac_reuse_max < 0) {
        return cdpr_diag_set(diag, CDPR_E_OUT_OF_RANGE, "jac_reuse_max", -1);
    }
    return cdpr_diag_set(diag, CDPR_OK, "", -1);
}

cdpr_status_t cdpr_ros_init(cdpr_ros_t *s, const cdpr_ros_params_t *p, cdpr_real_t *work,
                            int work_len, int dim_max, int dim, cdpr_diag_t *diag)
{
    CDPR_TRY(step_init_check(s, work, work_len, CDPR_ROS_WORK_PER_DIM, dim_max, dim, diag));
    CDPR_TRY(cdpr_ros_params_validate(p, dim, diag));
    s->p = *p;
    s->work = work;
    s->dim_max = dim_max;
    s->dim = dim;
    s->h_s = step_first(&p->step);
    s->last_err = CDPR_R(0.0);
    s->w_gh = CDPR_R(0.0);
    s->w_valid = 0;
    s->w_uses = 0;
    step_stats_reset(&s->stats);
    s->lin.factorisations = 0;
    s->lin.solves = 0;
    s->lin.singular_failures = 0;
    return cdpr_diag_set(diag, CDPR_OK, "", -1);
}

cdpr_status_t cdpr_ros_set_dim(cdpr_ros_t *s, int dim)
{
    if (s == NULL || dim < 1 || dim > s->dim_max) {
        return CDPR_E_CAPACITY;
    }
    s->dim = dim;
    s->w_valid = 0;
    return CDPR_OK;
}

void cdpr_ros_invalidate(cdpr_ros_t *s)
{
    if (s != NULL) {
        s->w_valid = 0;
    }
}

/* One counted call of f. */
static cdpr_status_t ros_eval(cdpr_ros_t *s, const cdpr_ros_problem_t *pb, cdpr_real_t t,
                              const cdpr_real_t *y, cdpr_real_t *dydt)
{
    s->stats.rhs_evals++;
    return (pb->f(t, y, dydt, pb->f_ctx) < 0) ? CDPR_E_RHS : CDPR_OK;
}

/* One counted solve; a refused solve forgets the factorisation. */
static cdpr_status_t ros_solve(cdpr_ros_t *s, const cdpr_ros_problem_t *pb, const cdpr_real_t *b,
                               cdpr_real_t *x)
{
    s->lin.solves++;
    if (pb->solve(pb->lin_ctx, b, x) < 0) {
        s->w_valid = 0;
        return CDPR_E_SINGULAR;
    }
    return CDPR_OK;
}

/* W for gamma h: the one in force while it may be reused, else a counted factorisation. A W
 * made for gamma h' is I - gamma h (h'/h) J: still a W-method matrix (order kept), close to the
 * exact one while h'/h is within 1e-3 of 1 (equal steps of advance differ by rounding). */
static cdpr_status_t ros_prepare_w(cdpr_ros_t *s, const cdpr_ros_problem_t *pb, cdpr_real_t t,
                                   const cdpr_real_t *y, cdpr_real_t gh)
{
    const cdpr_real_t d = gh - s->w_gh;
    if (s->w_valid != 0 && !(CDPR_FABS(d) > CDPR_R(1e-3) * gh) && s->w_uses < s->p.jac_reuse_max) {
        s->w_uses++;
        return CDPR_OK;
    }
    s->lin.factorisations++;
    s->w_valid = 0;
    if (pb->factor(pb->lin_ctx, t, y, gh) < 0) {
        return CDPR_E_SINGULAR;
    }
    s->w_gh = gh;
    s->w_uses = 0;
    s->w_valid = (s->p.jac_reuse_max > 0) ? 1 : 0;
    return CDPR_OK;
}

/* The last pass of a trial: new state (y_out = yt + gamma h v4; y_out may be y), error
 * estimate and its weighted max-norm, without a data-dependent branch. `vec` 1: atol[i] per
 * component, 0: atol[0] for all (a constant once inlined: two specialised loops). Non-finite
 * state: +Inf. The state is checked through the sum of |y_new| (Inf or NaN when a component
 * is, one addition per component instead of a classification); a finite state whose sum
 * overflows is refused too. */
static inline cdpr_real_t ros_finish(const cdpr_ros_t *s, const cdpr_real_t *y, cdpr_real_t *y_out,
                                     cdpr_real_t gh, const cdpr_real_t ge[4],
                                     const cdpr_real_t *atol, int vec)
{
    const int n = s->dim;
    const cdpr_real_t *restrict v1 = ros_slot(s, U1);
    const cdpr_real_t *restrict v2 = ros_slot(s, U2);
    const cdpr_real_t *restrict v3 = ros_slot(s, U3);
    const cdpr_real_t *restrict v4 = ros_slot(s, U4);
    const cdpr_real_t *restrict y4 = ros_slot(s, YTMP);
    const cdpr_real_t rtol = s->p.step.rtol;
    cdpr_real_t emax = CDPR_R(0.0);
    cdpr_real_t sum = CDPR_R(0.0);
    for (int i = 0; i < n; ++i) {
        const cdpr_real_t ay = CDPR_FABS(y[i]);
        const cdpr_real_t yn = y4[i] + gh * v4[i];
        const cdpr_real_t e =
            CDPR_FABS(ge[0] * v1[i] + ge[1] * v2[i] + ge[2] * v3[i] + ge[3] * v4[i]);
        const cdpr_real_t an = CDPR_FABS(yn);
        const cdpr_real_t sc = atol[i * vec] + rtol * ((ay > an) ? ay : an);
        const cdpr_real_t r = e / sc;
        emax = (r <= emax) ? emax : r; /* also propagates NaN */
        sum += an;
        y_out[i] = yn;
    }
    return (isfinite(sum) && isfinite(emax)) ? emax : (cdpr_real_t)INFINITY;
}

/* One trial; `have_f1` says slot F1 already holds f(t, y). The slots never alias each other,
 * y or y_out; y_out may be y itself (the new state is written in place, each component after
 * its last read), so y and y_out are not `restrict`: the stage loops' written slots are, which
 * is what lets the compiler vectorise them.
 *
 * The stages are solved scaled: v_i = u_i / (gamma h) of the (a, c, m) form above, i.e.
 *   W v_i = f(t + alpha_i h, y + h gamma sum_j a_ij v_j) + sum_j (gamma c_ij) v_j,
 *   y_new = y + h gamma sum_i m_i v_i,  err = h gamma sum_i e_i v_i,
 * the same method (W is linear) with the factor gamma h moved from every component into the
 * few scalar coefficients: stage 1 solves f(t, y) as it stands and no stage scales its
 * right-hand side (docs/performance.md "One substep"). */
static cdpr_status_t ros_try(cdpr_ros_t *s, const cdpr_ros_problem_t *pb, cdpr_real_t t,
                             const cdpr_real_t *y, cdpr_real_t h, cdpr_real_t *y_out,
                             cdpr_real_t *err, int have_f1)
{
    const int n = s->dim;
    cdpr_real_t *restrict v1 = ros_slot(s, U1);
    cdpr_real_t *restrict v2 = ros_slot(s, U2);
    cdpr_real_t *restrict v3 = ros_slot(s, U3);
    cdpr_real_t *restrict v4 = ros_slot(s, U4);
    cdpr_real_t *restrict yt = ros_slot(s, YTMP);
    cdpr_real_t *restrict f1 = ros_slot(s, F1);
    cdpr_real_t *restrict ft = ros_slot(s, FT);
    const cdpr_real_t gh = GAMMA * h;

    if (have_f1 == 0) {
        CDPR_TRY(ros_eval(s, pb, t, y, f1));
    }
    CDPR_TRY(ros_prepare_w(s, pb, t, y, gh));
    /* Stage 1: W v1 = f(t, y). */
    CDPR_TRY(ros_solve(s, pb, f1, v1));
    /* Stage 2. */
    const cdpr_real_t a21 = gh * A21;
    for (int i = 0; i < n; ++i) {
        yt[i] = y[i] + a21 * v1[i];
    }
    CDPR_TRY(ros_eval(s, pb, t + ALPHA2 * h, yt, ft));
    for (int i = 0; i < n; ++i) {
        ft[i] = ft[i] + GC21 * v1[i];
    }
    CDPR_TRY(ros_solve(s, pb, ft, v2));
    /* Stage 3. */
    const cdpr_real_t a31 = gh * A31;
    const cdpr_real_t a32 = gh * A32;
    for (int i = 0; i < n; ++i) {
        yt[i] = y[i] + a31 * v1[i] + a32 * v2[i];
    }
    CDPR_TRY(ros_eval(s, pb, t + ALPHA3 * h, yt, ft));
    for (int i = 0; i < n; ++i) {
        ft[i] = ft[i] + GC31 * v1[i] + GC32 * v2[i];
    }
    CDPR_TRY(ros_solve(s, pb, ft, v3));
    /* Stage 4. */
    const cdpr_real_t a41 = gh * A41;
    const cdpr_real_t a42 = gh * A42;
    const cdpr_real_t a43 = gh * A43;
    for (int i = 0; i < n; ++i) {
        yt[i] = y[i] + a41 * v1[i] + a42 * v2[i] + a43 * v3[i];
    }
    CDPR_TRY(ros_eval(s, pb, t + ALPHA4 * h, yt, ft));
    for (int i = 0; i < n; ++i) {
        ft[i] = ft[i] + GC41 * v1[i] + GC42 * v2[i] + GC43 * v3[i];
    }
    CDPR_TRY(ros_solve(s, pb, ft, v4));

    /* Stiffly accurate (m_i = a_4i, m_4 = 1): y_new = (stage 4's state) + gamma h v4. */
    const cdpr_real_t ge[4] = {gh * E1, gh * E2, gh * E3, gh * E4};
    const cdpr_real_t *av = s->p.step.atol_vec;
    const cdpr_real_t emax = (av != NULL) ? ros_finish(s, y, y_out, gh, ge, av, 1)
                                          : ros_finish(s, y, y_out, gh, ge, &s->p.step.atol, 0);
    s->last_err = emax;
    if (err != NULL) {
        *err = emax;
    }
    return CDPR_OK;
}

cdpr_status_t cdpr_ros_trial(cdpr_ros_t *s, const cdpr_ros_problem_t *pb, cdpr_real_t t,
                             const cdpr_real_t *y, cdpr_real_t h, cdpr_real_t *y_out,
                             cdpr_real_t *err)
{
    return ros_try(s, pb, t, y, h, y_out, err, 0);
}

/* Step-size factor from the error norm (error ~ h^3 for the embedded order-2 estimate). */
static cdpr_real_t ros_step_factor(const cdpr_ros_t *s, cdpr_real_t err)
{
    return step_factor(&s->p.step, err, CDPR_R(-1.0) / CDPR_R(3.0));
}

/* A trial that produced NaN/Inf from a non-finite start (y or f(t, y)): no smaller step can
 * help. */
static int ros_start_is_bad(const cdpr_ros_t *s, const cdpr_real_t *y)
{
    return (step_all_finite(y, s->dim) == 0) || (step_all_finite(ros_slot(s, F1), s->dim) == 0);
}

static int ros_problem_ok(const cdpr_ros_problem_t *pb)
{
    return (pb != NULL && pb->f != NULL && pb->factor != NULL && pb->solve != NULL) ? 1 : 0;
}

/* Count a failed call and return its status. */
static cdpr_status_t ros_failed(cdpr_ros_t *s, cdpr_status_t st)
{
    s->stats.failures++;
    if (st == CDPR_E_SINGULAR) {
        s->lin.singular_failures++;
    }
    return st;
}

cdpr_status_t cdpr_ros_step(cdpr_ros_t *s, const cdpr_ros_problem_t *pb, cdpr_real_t *t,
                            cdpr_real_t *y, cdpr_real_t t_end)
{
    if (s == NULL || ros_problem_ok(pb) == 0 || t == NULL || y == NULL || !isfinite(*t) ||
        !isfinite(t_end) || !(t_end > *t)) {
        return CDPR_E_INVALID_ARG;
    }
    if (step_all_finite(y, s->dim) == 0) {
        return ros_failed(s, CDPR_E_STATE_NOT_FINITE);
    }
    cdpr_real_t *yn = ros_slot(s, YNEW);
    int have_f1 = 0;
    /* Bounded: every rejection multiplies h by at most max(safety, shrink_min) < 1, and h_min
     * ends it. */
    for (;;) {
        const cdpr_real_t remaining = t_end - *t;
        cdpr_real_t h = step_bounded(&s->p.step, s->h_s);
        const int last = (h >= remaining) ? 1 : 0;
        if (last != 0) {
            h = remaining;
        }
        cdpr_real_t err = CDPR_R(0.0);
        const cdpr_status_t ts = ros_try(s, pb, *t, y, h, yn, &err, have_f1);
        if (ts != CDPR_OK) {
            return ros_failed(s, ts);
        }
        have_f1 = 1; /* a retry starts from the same (t, y) */
        if (!isfinite(err)) {
            if (ros_start_is_bad(s, y) != 0) {
                return ros_failed(s, CDPR_E_STATE_NOT_FINITE);
            }
            s->stats.nonfinite_rejected++;
            s->h_s = h * s->p.step.shrink_min;
        } else if (err <= CDPR_R(1.0)) {
            step_copy(y, yn, s->dim);
            *t = (last != 0) ? t_end : *t + h;
            s->stats.steps_accepted++;
            const cdpr_real_t h_next = step_bounded(&s->p.step, h * ros_step_factor(s, err));
            /* A step clipped to reach t_end says little about the natural step size. */
            s->h_s = (last != 0 && h_next < s->h_s) ? s->h_s : h_next;
            return CDPR_OK;
        } else {
            s->stats.steps_rejected++;
            s->h_s = h * ros_step_factor(s, err);
        }
        if (s->h_s < s->p.step.h_min_s) {
            s->h_s = s->p.step.h_min_s;
            if (h <= s->p.step.h_min_s) {
                return ros_failed(s, CDPR_E_STEP_TOO_SMALL);
            }
        }
    }
}

/* Where one cdpr_ros_advance is in its interval (internal). */
typedef struct {
    cdpr_real_t tc;    /* time reached */
    cdpr_real_t t_end; /* end of the interval */
    int equal;         /* 1: the rest is covered in equal steps, one per remaining trial */
    int last;          /* 1: this trial's step reaches t_end */
    int forced;        /* equal steps accepted above the tolerance */
    int have_f1;       /* the first stage's f is that of the current state */
} ros_walk_t;

/* The step of the next trial, `budget` trials left: the controller's, or equal steps once the
 * controller's can no longer reach the end within the budget; the rest at once when it is
 * barely longer than the step (no sliver). */
static cdpr_real_t ros_pick_step(const cdpr_ros_t *s, ros_walk_t *w, int budget)
{
    const cdpr_real_t remaining = w->t_end - w->tc;
    cdpr_real_t h = step_bounded(&s->p.step, s->h_s);
    if (w->equal == 0 && (budget == 1 || step_can_reach(&s->p.step, h, budget, remaining) == 0)) {
        w->equal = 1;
    }
    if (w->equal != 0) {
        h = remaining / (cdpr_real_t)budget;
    }
    w->last = (h >= remaining * CDPR_R(0.999)) ? 1 : 0;
    return (w->last != 0) ? remaining : h;
}

/* Accept or reject the trial of step h from y (to yn, error norm err) and choose the next
 * step. Returns CDPR_OK to go on, or the error that ends the advance. */
static cdpr_status_t ros_judge(cdpr_ros_t *s, ros_walk_t *w, cdpr_real_t *y, const cdpr_real_t *yn,
                               cdpr_real_t h, cdpr_real_t err)
{
    cdpr_status_t st = CDPR_OK;
    w->have_f1 = 1; /* until a step is accepted, the next trial starts from here */
    if (!isfinite(err)) {
        if (ros_start_is_bad(s, y) != 0) {
            return CDPR_E_STATE_NOT_FINITE;
        }
        if (w->equal != 0) {
            return CDPR_E_SUBSTEP_LIMIT; /* an equal step cannot shrink */
        }
        s->stats.nonfinite_rejected++;
        s->h_s = h * s->p.step.shrink_min;
    } else if (err <= CDPR_R(1.0) || (w->equal != 0 && err <= s->p.step.force_err_max)) {
        step_copy(y, yn, s->dim);
        w->have_f1 = 0;
        w->tc = (w->last != 0) ? w->t_end : w->tc + h;
        s->stats.steps_accepted++;
        if (err > CDPR_R(1.0)) {
            s->stats.forced_steps++;
            w->forced++;
        }
        const cdpr_real_t h_next = step_bounded(&s->p.step, h * ros_step_factor(s, err));
        s->h_s = (w->last != 0 && h_next < s->h_s) ? s->h_s : h_next;
    } else {
        s->stats.steps_rejected++;
        const cdpr_real_t h_next = h * ros_step_factor(s, err);
        /* An equal step was not the controller's choice: its rejection never raises h_s. */
        s->h_s = (w->equal != 0 && s->h_s < h_next) ? s->h_s : h_next;
        if (w->equal != 0) {
            return CDPR_E_SUBSTEP_LIMIT; /* the rest no longer fits in the budget */
        }
    }
    if (s->h_s < s->p.step.h_min_s) {
        if (h <= s->p.step.h_min_s) {
            st = CDPR_E_STEP_TOO_SMALL;
        } else {
            s->h_s = s->p.step.h_min_s;
        }
    }
    return st;
}

/* The checks on entry of the calls over an interval (advance, fixed): CDPR_E_INVALID_ARG (not
 * counted) for bad arguments or a `count` (trials, steps) below 1, CDPR_E_STATE_NOT_FINITE
 * (counted) for a non-finite y, else CDPR_OK. */
static cdpr_status_t ros_interval_entry(cdpr_ros_t *s, const cdpr_ros_problem_t *pb,
                                        const cdpr_real_t *t, const cdpr_real_t *y, cdpr_real_t dt,
                                        int count)
{
    if (s == NULL || ros_problem_ok(pb) == 0 || t == NULL || y == NULL || !isfinite(*t) ||
        !isfinite(dt) || !(dt > CDPR_R(0.0)) || count < 1) {
        return CDPR_E_INVALID_ARG;
    }
    if (step_all_finite(y, s->dim) == 0) {
        return ros_failed(s, CDPR_E_STATE_NOT_FINITE);
    }
    return CDPR_OK;
}

cdpr_status_t cdpr_ros_advance(cdpr_ros_t *s, const cdpr_ros_problem_t *pb, cdpr_real_t *t,
                               cdpr_real_t *y, cdpr_real_t dt, int max_trials)
{
    const cdpr_status_t in = ros_interval_entry(s, pb, t, y, dt, max_trials);
    if (in != CDPR_OK) {
        return in;
    }
    cdpr_real_t *yn = ros_slot(s, YNEW);
    cdpr_real_t *yb = ros_slot(s, YBAK);
    const cdpr_real_t t0 = *t;
    const cdpr_real_t h_saved = s->h_s;
    ros_walk_t w = {t0, t0 + dt, 0, 0, 0, 0};
    step_copy(yb, y, s->dim);

    cdpr_status_t st = CDPR_OK;
    int trials = 0;
    while ((st == CDPR_OK) && (w.tc < w.t_end)) {
        const int budget = max_trials - trials;
        if (budget < 1) {
            st = CDPR_E_SUBSTEP_LIMIT; /* not reached: the last trial is an equal step */
            break;
        }
        const cdpr_real_t h = ros_pick_step(s, &w, budget);
        cdpr_real_t err = CDPR_R(0.0);
        st = ros_try(s, pb, w.tc, y, h, yn, &err, w.have_f1);
        if (st == CDPR_OK) {
            st = ros_judge(s, &w, y, yn, h, err);
        }
        ++trials;
    }
    if (st < 0) {
        step_copy(y, yb, s->dim);
        *t = t0;
        if (st == CDPR_E_SUBSTEP_LIMIT) {
            s->stats.substep_limit_failures++;
        } else {
            s->h_s = (s->h_s < h_saved) ? s->h_s : h_saved;
        }
        return ros_failed(s, st);
    }
    *t = w.t_end;
    if (w.forced != 0) {
        s->stats.substep_limit_hits++;
        return CDPR_WARN_SUBSTEP_LIMIT;
    }
    return CDPR_OK;
}

cdpr_status_t cdpr_ros_fixed(cdpr_ros_t *s, const cdpr_ros_problem_t *pb, cdpr_real_t *t,
                             cdpr_real_t *y, cdpr_real_t dt, int n, cdpr_real_t *err_max)
{
    const cdpr_status_t in = ros_interval_entry(s, pb, t, y, dt, n);
    if (in != CDPR_OK) {
        return in;
    }
    cdpr_real_t *yb = ros_slot(s, YBAK);
    const cdpr_real_t t0 = *t;
    const cdpr_real_t h = dt / (cdpr_real_t)n;
    step_copy(yb, y, s->dim);
    cdpr_real_t emax = CDPR_R(0.0);
    cdpr_status_t st = CDPR_OK;
    for (int i = 0; i < n && st == CDPR_OK; ++i) {
        cdpr_real_t err = CDPR_R(0.0);
        /* A new W every step: the same work in every call, and the stability margin of the
         * derived n was measured so (one W per call is cheaper but loses margin at 6 x 64:
         * docs/performance.md "One substep, cheaper"). */
        s->w_valid = 0;
        /* In place: a refused substep is undone from the copy taken on entry. */
        st = ros_try(s, pb, t0 + (cdpr_real_t)i * h, y, h, y, &err, 0);
        if (st == CDPR_OK && !isfinite(err)) {
            s->stats.nonfinite_rejected++;
            st = CDPR_E_STATE_NOT_FINITE;
        }
        if (st == CDPR_OK) {
            s->stats.steps_accepted++;
            emax = (err > emax) ? err : emax;
        }
    }
    s->w_valid = 0;
    if (st != CDPR_OK) {
        step_copy(y, yb, s->dim);
        *t = t0;
        return ros_failed(s, st);
    }
    *t = t0 + dt;
    if (err_max != NULL) {
        *err_max = emax;
    }
    return CDPR_OK;
}
