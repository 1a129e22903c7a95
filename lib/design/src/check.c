/* SPDX-License-Identifier: BSD-3-Clause */
/// @file check.c
/// The check at load (cdpr_design_check_scenario): the design's own margin calculation on the
/// scenario's controller, refused when the linearised closed loop grows or the learning's
/// lap-to-lap map has ρ >= 1 at a lap harmonic.
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
    key(buf, len, "tension_gain_m_per_s_per_N", g->tension_gain_m_per_s_per_N, 0);
    if (g->tension_gain_m_per_s_per_N > 0.0) {
        key(buf, len, "tension_filter_s", g->tension_filter_s, 1);
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

static void fmt_margins(const cdpr_design_report_t *r, char *buf, size_t len)
{
    char gm[40];
    char pm[40];
    fmt_margin(gm, sizeof gm, r->gm_min_db, "dB");
    fmt_margin(pm, sizeof pm, r->pm_min_deg, "°");
    snprintf(buf, len, "loop-at-a-time margins %s / %s, α %.3f; goal %g dB / %g°", gm, pm, r->alpha,
             CDPR_DESIGN_GOAL_GM_DB, CDPR_DESIGN_GOAL_PM_DEG);
}

static cdpr_status_t check(const cdpr_scenario_t *sc, const char *path, int *warn,
                           cdpr_design_report_t *r, cdpr_design_error_t *err)
{
    cdpr_design_point_t *pt = NULL;
    cdpr_status_t st = cdpr_design_point_new(sc, (double)NAN, &pt, err);
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
    const cdpr_tracker_gains_t *g = &sc->gains;
    char keys[256];
    char marg[160];
    feedback_keys(g, keys, sizeof keys);
    fmt_margins(r, marg, sizeof marg);
    if (r->grows != 0) {
        snprintf(err->msg, sizeof err->msg,
                 "%.200s: controller (%s): the linearised closed loop grows at %.3g 1/s at %.3g Hz "
                 "(%s)",
                 path, keys, r->growth_per_s, r->growth_hz, marg);
        return CDPR_E_OUT_OF_RANGE;
    }
    if (r->learning != 0 && r->first_diverging > 0) {
        char list[160] = "";
        for (int h = 0; h < r->n_harmonics; ++h) {
            const size_t used = strlen(list);
            if (r->rho[h] >= 1.0 && used + 8 < sizeof list) {
                snprintf(list + used, sizeof list - used, "%s%d", (used > 0) ? ", " : "", h + 1);
            }
        }
        const int k = r->first_diverging - 1;
        const int wst = r->worst_harmonic - 1;
        snprintf(err->msg, sizeof err->msg,
                 "%.200s: controller.learning_gain %g (lead %g s, cutoff %g Hz): learning diverges "
                 "at lap harmonic %d (%.3f Hz), ρ = %.2f (ρ >= 1 at harmonics %s; largest %.2f "
                 "at harmonic %d)",
                 path, g->learning_gain, g->learning_lead_s, g->learning_cutoff_hz,
                 r->first_diverging, r->harmonic_hz[k], r->rho[k], list, r->rho[wst],
                 r->worst_harmonic);
        return CDPR_E_OUT_OF_RANGE;
    }
    if (r->active != 0 &&
        (r->gm_min_db < CDPR_DESIGN_GOAL_GM_DB || r->pm_min_deg < CDPR_DESIGN_GOAL_PM_DEG)) {
        *warn = 1;
        snprintf(err->msg, sizeof err->msg,
                 "%.200s: controller (%s): below the goal margins: %s (the linearised closed loop "
                 "does not grow)",
                 path, keys, marg);
    }
    return CDPR_OK;
}

cdpr_status_t cdpr_design_check_scenario(const cdpr_scenario_t *sc, const char *path, int *checked,
                                         int *warn, cdpr_design_report_t *rep,
                                         cdpr_design_error_t *err)
{
    *checked = 0;
    *warn = 0;
    err->msg[0] = '\0';
    if (cdpr_tracker_has_feedback(&sc->gains) == 0) {
        return CDPR_OK;
    }
    *checked = 1;
    cdpr_design_report_t *own = (rep != NULL) ? NULL : malloc(sizeof *own);
    cdpr_design_report_t *r = (rep != NULL) ? rep : own;
    if (r == NULL) {
        snprintf(err->msg, sizeof err->msg, "design: out of memory (report)");
        return CDPR_E_CAPACITY;
    }
    const cdpr_status_t st = check(sc, path, warn, r, err);
    free(own);
    return st;
}
