/* SPDX-License-Identifier: BSD-3-Clause */
/// @file check.c
/// The check at load (cdpr_design_check_scenario): the design's own margin calculation on the
/// scenario's controller over the robustness set (cdpr_design_robust), refused when a case's
/// linearised closed loop grows or its learning's lap-to-lap map has ρ >= 1 at a lap harmonic.
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cdpr/design/design.h"

/* Append "name value" to the key list when v > 0 (or always with force). */
static void key(char *buf, size_t len, const char *name, double v, int force)
{
    if (!(v > 0.0) && force == 0) {
        return;
    }
    const size_t used = strlen(buf);
    if (used + 1 < len) {
        snprintf(buf + used, len - used, "%s%s %g", (used > 0) ? ", " : "", name, v);
    }
}

/* The feedback keys that are set, with their filters ("kd_s 0.1, filter_s 0.1"). */
static void feedback_keys(const cdpr_tracker_gains_t *g, char *buf, size_t len)
{
    buf[0] = '\0';
    key(buf, len, "kp", g->kp, 0);
    key(buf, len, "kd_s", g->kd_s, 0);
    key(buf, len, "damping_N_s_per_m", g->damping_N_s_per_m, 0);
    key(buf, len, "damping_rot_N_m_s", g->damping_rot_N_m_s, 0);
    const int pose =
        (g->kp > 0.0 || g->kd_s > 0.0 || g->damping_N_s_per_m > 0.0 || g->damping_rot_N_m_s > 0.0);
    if (pose) {
        key(buf, len, "filter_s", g->filter_s, 1);
    }
    key(buf, len, "integral_per_s", g->integral_per_s, 0);
    key(buf, len, "weight_estimate_s", g->weight_estimate_s, 0);
    key(buf, len, "tension_gain_m_per_s_per_N", g->tension_gain_m_per_s_per_N, 0);
    if (g->tension_gain_m_per_s_per_N > 0.0) {
        key(buf, len, "tension_filter_s", g->tension_filter_s, 1);
        key(buf, len, "tension_washout_s", g->tension_washout_s, 0);
    }
    if (buf[0] == '\0') {
        snprintf(buf, len, "feed-forward, k_length_per_s %g", g->k_length_per_s);
    }
}

/* "4.5 dB" / "inf" for a margin that does not exist on the grid. */
static void fmt_margin(char *buf, size_t len, double v, const char *unit)
{
    if (isfinite(v)) {
        snprintf(buf, len, (unit[0] == 'd') ? "%.1f %s" : "%.1f%s", v, unit);
    } else {
        snprintf(buf, len, "no %s crossing", (unit[0] == 'd') ? "-180°" : "unity");
    }
}

int cdpr_design_robust_times(const cdpr_scenario_t *sc, double t[CDPR_DESIGN_ROBUST_POSES])
{
    double end = cdpr_traj_end_time(&sc->traj);
    end = isfinite(end) ? end : sc->duration_s;
    const double want[CDPR_DESIGN_ROBUST_POSES] = {0.0, 0.5 * end, end};
    double pose[CDPR_DESIGN_ROBUST_POSES][6];
    int n = 0;
    for (int i = 0; i < CDPR_DESIGN_ROBUST_POSES; ++i) {
        cdpr_traj_sample_t s;
        cdpr_traj_eval(&sc->traj, want[i], &s);
        int seen = 0;
        for (int k = 0; k < n; ++k) {
            int same = 1;
            for (int c = 0; c < 6; ++c) {
                same &= (fabs(pose[k][c] - s.pose[c]) > 0.0) ? 0 : 1; /* equal, bit for bit */
            }
            seen |= same;
        }
        if (seen == 0) {
            memcpy(pose[n], s.pose, sizeof s.pose);
            t[n] = want[i];
            ++n;
        }
    }
    return n;
}

/* Variation v (0..6) of the set: nominal, then EA, cabin mass, rope mass, each +step, -step. */
static cdpr_rig_scale_t variation(int v, char *label, size_t len)
{
    cdpr_rig_scale_t f = cdpr_rig_scale_unit();
    static const char *const what[3] = {"EA", "cabin mass", "rope mass"};
    if (v == 0) {
        snprintf(label, len, "plant as the model");
        return f;
    }
    const int k = (v - 1) / 2;
    const double sign = ((v - 1) % 2 == 0) ? 1.0 : -1.0;
    const double x = 1.0 + sign * CDPR_DESIGN_ROBUST_STEP;
    double *slot = (k == 0) ? &f.ea : (k == 1) ? &f.cabin_mass : &f.rope_mass;
    *slot = x;
    snprintf(label, len, "plant %s %+.0f %%", what[k], 100.0 * sign * CDPR_DESIGN_ROBUST_STEP);
    return f;
}

/* Linearise and analyse one case into c (r: scratch report). */
static cdpr_status_t run_case(const cdpr_scenario_t *sc, cdpr_design_case_t *c,
                              cdpr_design_report_t *r, cdpr_design_error_t *err)
{
    cdpr_design_point_t *pt = NULL;
    cdpr_status_t st = cdpr_design_point_new(sc, c->at_s, &c->plant, &pt, err);
    if (st != CDPR_OK) {
        return st;
    }
    cdpr_design_model_t m;
    st = cdpr_design_linearise(pt, &m, err);
    cdpr_design_point_free(pt);
    if (st != CDPR_OK) {
        return st;
    }
    st = cdpr_design_analyse(&m, 1, r, err);
    cdpr_design_model_free(&m);
    if (st != CDPR_OK) {
        return st;
    }
    c->growth_per_s = r->growth_per_s;
    c->growth_hz = r->growth_hz;
    c->grows = r->grows;
    c->active = r->active;
    c->gm_min_db = r->gm_min_db;
    c->pm_min_deg = r->pm_min_deg;
    c->alpha = r->alpha;
    c->learning = r->learning;
    c->max_rho = r->max_rho;
    c->worst_harmonic = r->worst_harmonic;
    c->first_diverging = r->first_diverging;
    return CDPR_OK;
}

/* The quantity the set's worst case is chosen by (smallest wins): 0 gain margin, 1 phase
 * margin, 2 α, 3 -ρ; NaN where the case has none (no active loop, no learning). */
static double case_value(const cdpr_design_case_t *c, int which)
{
    switch (which) {
    case 0:
        return (c->active != 0) ? c->gm_min_db : (double)NAN;
    case 1:
        return (c->active != 0) ? c->pm_min_deg : (double)NAN;
    case 2:
        return c->alpha;
    default:
        return (c->learning != 0) ? -c->max_rho : (double)NAN;
    }
}

/* Index of the case with the smallest case_value (-1 when no case has one). */
static int worst_of(const cdpr_design_robust_t *o, int which)
{
    int best = -1;
    for (int i = 0; i < o->n_cases; ++i) {
        const double v = case_value(&o->c[i], which);
        if (!isnan(v) && (best < 0 || v < case_value(&o->c[best], which))) {
            best = i;
        }
    }
    return best;
}

cdpr_status_t cdpr_design_robust(const cdpr_scenario_t *sc, int stop_at_refusal,
                                 cdpr_design_robust_t *o, cdpr_design_error_t *err)
{
    memset(o, 0, sizeof *o);
    o->refused = -1;
    err->msg[0] = '\0';
    cdpr_design_report_t *r = malloc(sizeof *r);
    if (r == NULL) {
        snprintf(err->msg, sizeof err->msg, "design: out of memory (report)");
        return CDPR_E_CAPACITY;
    }
    double t[CDPR_DESIGN_ROBUST_POSES];
    const int n_poses = cdpr_design_robust_times(sc, t);
    static const char *const pose_name[CDPR_DESIGN_ROBUST_POSES] = {"start", "middle", "end"};
    cdpr_status_t st = CDPR_OK;
    for (int p = 0; p < n_poses && st == CDPR_OK && (stop_at_refusal == 0 || o->refused < 0); ++p) {
        /* A deduplicated pose keeps the name of the time it was found at. */
        const int name = (t[p] <= 0.0) ? 0 : (p == n_poses - 1) ? 2 : 1;
        for (int v = 0; v < CDPR_DESIGN_ROBUST_VARIANTS && st == CDPR_OK &&
                        (stop_at_refusal == 0 || o->refused < 0);
             ++v) {
            cdpr_design_case_t *c = &o->c[o->n_cases];
            char label[48];
            c->plant = variation(v, label, sizeof label);
            c->at_s = t[p];
            snprintf(c->name, sizeof c->name, "%s (t = %g s), %s",
                     (n_poses == 1) ? "the pose" : pose_name[name], t[p], label);
            st = run_case(sc, c, r, err);
            if (st != CDPR_OK) {
                char why[sizeof err->msg];
                snprintf(why, sizeof why, "%s", err->msg);
                snprintf(err->msg, sizeof err->msg, "%s: %.900s", c->name, why);
                break;
            }
            const int diverges = (c->learning != 0 && c->first_diverging > 0) ? 1 : 0;
            o->n_grow += c->grows;
            o->n_diverge += diverges;
            if (o->refused < 0 && (c->grows != 0 || diverges != 0)) {
                o->refused = o->n_cases;
            }
            ++o->n_cases;
        }
    }
    free(r);
    o->worst_gm = worst_of(o, 0);
    o->worst_pm = worst_of(o, 1);
    o->worst_alpha = worst_of(o, 2);
    o->worst_rho = worst_of(o, 3);
    return st;
}

/* The verdict on the set (complete, or up to its first refused case). */
static cdpr_status_t verdict(const cdpr_scenario_t *sc, const char *path,
                             const cdpr_design_robust_t *o, int *warn, cdpr_design_error_t *err)
{
    const cdpr_tracker_gains_t *g = &sc->gains;
    char keys[256];
    feedback_keys(g, keys, sizeof keys);
    double t[CDPR_DESIGN_ROBUST_POSES];
    const int total = cdpr_design_robust_times(sc, t) * CDPR_DESIGN_ROBUST_VARIANTS;
    if (o->refused >= 0) {
        const cdpr_design_case_t *c = &o->c[o->refused];
        if (c->grows != 0) {
            char gm[40];
            char pm[40];
            fmt_margin(gm, sizeof gm, c->gm_min_db, "dB");
            fmt_margin(pm, sizeof pm, c->pm_min_deg, "°");
            snprintf(err->msg, sizeof err->msg,
                     "%.200s: controller (%s): the linearised closed loop grows at %.3g 1/s at "
                     "%.3g Hz at %s (case %d of the robustness set's %d; that case's "
                     "loop-at-a-time margins %s / %s, α %.3f)",
                     path, keys, c->growth_per_s, c->growth_hz, c->name, o->refused + 1, total, gm,
                     pm, c->alpha);
        } else {
            snprintf(err->msg, sizeof err->msg,
                     "%.200s: controller.learning_gain %g (lead %g s, cutoff %g Hz): learning "
                     "diverges at %s: lap harmonic %d first, largest ρ = %.2f at harmonic %d "
                     "(case %d of the robustness set's %d)",
                     path, g->learning_gain, g->learning_lead_s, g->learning_cutoff_hz, c->name,
                     c->first_diverging, c->max_rho, c->worst_harmonic, o->refused + 1, total);
        }
        return CDPR_E_OUT_OF_RANGE;
    }
    const int wg = o->worst_gm;
    const int wp = o->worst_pm;
    if (wg >= 0 && wp >= 0 &&
        (o->c[wg].gm_min_db < CDPR_DESIGN_GOAL_GM_DB ||
         o->c[wp].pm_min_deg < CDPR_DESIGN_GOAL_PM_DEG)) {
        *warn = 1;
        char gm[40];
        char pm[40];
        fmt_margin(gm, sizeof gm, o->c[wg].gm_min_db, "dB");
        fmt_margin(pm, sizeof pm, o->c[wp].pm_min_deg, "°");
        snprintf(err->msg, sizeof err->msg,
                 "%.200s: controller (%s): below the goal margins (%g dB / %g°) in the "
                 "robustness set: gain margin %s at %s, phase margin %s at %s, smallest α %.3f "
                 "(no case of %d grows)",
                 path, keys, CDPR_DESIGN_GOAL_GM_DB, CDPR_DESIGN_GOAL_PM_DEG, gm, o->c[wg].name, pm,
                 o->c[wp].name, o->c[o->worst_alpha].alpha, o->n_cases);
    }
    return CDPR_OK;
}

cdpr_status_t cdpr_design_check_scenario(const cdpr_scenario_t *sc, const char *path, int *checked,
                                         int *warn, cdpr_design_robust_t *robust,
                                         cdpr_design_error_t *err)
{
    *checked = 0;
    *warn = 0;
    err->msg[0] = '\0';
    if (cdpr_tracker_has_feedback(&sc->gains) == 0) {
        return CDPR_OK;
    }
    *checked = 1;
    cdpr_design_robust_t *own = (robust != NULL) ? NULL : malloc(sizeof *own);
    cdpr_design_robust_t *o = (robust != NULL) ? robust : own;
    if (o == NULL) {
        snprintf(err->msg, sizeof err->msg, "design: out of memory (robustness set)");
        return CDPR_E_CAPACITY;
    }
    cdpr_status_t st = cdpr_design_robust(sc, 1, o, err);
    if (st == CDPR_OK) {
        st = verdict(sc, path, o, warn, err);
    }
    free(own);
    return st;
}
