/* SPDX-License-Identifier: BSD-3-Clause */
/// @file app_design.c
/// The design check in process (app_design.h): cdpr-design's --verdict and --check.
#include "app_design.h"

#include <math.h>
#include <stddef.h>
#include <stdio.h>

#include "cdpr/control/tracker.h"
#include "cdpr/design/design.h"
#include "cdpr/host/clock.h"

/* The linearised loop's state count: the robot's (13 for the cabin, 1 + 6 (segments - 1) per
 * cable) plus the controller's; 0 when the robot cannot be built (the check then says why). */
static long design_states(const cdpr_scenario_t *sc)
{
    static cdpr_robot_params_t mp; /* 2 kB per cable: not on the stack */
    cdpr_winch_params_t w[CDPR_MAX_CABLES];
    cdpr_diag_t d;
    if (cdpr_scenario_build_robot(sc, NULL, &mp, w, &d) != CDPR_OK) {
        return 0;
    }
    long n = 13;
    for (int j = 0; j < mp.n_cables; ++j) {
        n += 1 + 6L * (long)(mp.cables[j].n_segments - 1);
    }
    return n;
}

/* "8.5" / "inf" for a margin (no crossing on the grid). */
static void margin_cell(char *buf, size_t len, int active, double v)
{
    if (active == 0) {
        snprintf(buf, len, "-");
    } else if (isfinite(v)) {
        snprintf(buf, len, "%.2f", v);
    } else {
        snprintf(buf, len, "inf");
    }
}

/* The robustness set's table on `f`, one line per case. */
static void print_table(FILE *f, const char *prog, const cdpr_design_robust_t *o, int total)
{
    fprintf(f,
            "%s: robustness set, %d of %d cases%s (goal: growth < %g 1/s, loop-at-a-time margins "
            ">= %g dB / %g deg, learning rho < 1):\n",
            prog, o->n_cases, total, (o->n_cases < total) ? ", stopped at the first refusal" : "",
            CDPR_DESIGN_GROWTH_TOL, CDPR_DESIGN_GOAL_GM_DB, CDPR_DESIGN_GOAL_PM_DEG);
    fprintf(f, "  %-44s %11s %8s %8s %7s %8s\n", "case", "growth 1/s", "GM dB", "PM deg", "alpha",
            "rho max");
    for (int i = 0; i < o->n_cases; ++i) {
        const cdpr_design_case_t *c = &o->c[i];
        char gm[24];
        char pm[24];
        char rho[24];
        margin_cell(gm, sizeof gm, c->active, c->gm_min_db);
        margin_cell(pm, sizeof pm, c->active, c->pm_min_deg);
        margin_cell(rho, sizeof rho, c->learning, c->max_rho);
        fprintf(f, "  %-44s %11.2e %8s %8s %7.3f %8s%s\n", c->name, c->growth_per_s, gm, pm,
                c->alpha, rho,
                (c->grows != 0 || (c->learning != 0 && c->first_diverging > 0)) ? "  REFUSED" : "");
    }
}

cdpr_status_t cdpr_app_design_check(const char *prog, const char *path, const cdpr_scenario_t *sc,
                                    int quiet)
{
    int checked = 0; /* 0: feed-forward only, nothing computed */
    int warn = 0;
    cdpr_design_error_t err;
    static cdpr_design_robust_t robust; /* 21 cases: not on the stack */
    /* Say what is coming: the check's dense algebra grows as the cube of the states (measured
     * per case: docs/performance.md). */
    const long n = design_states(sc);
    const double t0 = cdpr_clock_now_s();
    double t[CDPR_DESIGN_ROBUST_POSES];
    const int cases = cdpr_design_robust_times(sc, t) * CDPR_DESIGN_ROBUST_VARIANTS;
    if (quiet == 0 && cdpr_tracker_has_feedback(&sc->gains) != 0 && n > 0) {
        const double expect_s =
            (double)cases * CDPR_APP_DESIGN_S_AT_703 * pow((double)n / 703.0, 3.0);
        fprintf(stderr,
                "%s: checking the controller's design on its linearised loop over the robustness "
                "set (%d cases, %ld states of the robot; about %.0f s on an idle 2-core machine "
                "with OpenBLAS, growing as the cube of the states)...\n",
                prog, cases, n, expect_s);
    }
    const cdpr_status_t st = cdpr_design_check_scenario(sc, path, &checked, &warn, &robust, &err);
    if (quiet == 0 && checked != 0) {
        if (robust.n_cases > 0) {
            print_table(stderr, prog, &robust, cases);
        }
        fprintf(stderr, "%s: design check done in %.1f s\n", prog, cdpr_clock_now_s() - t0);
    }
    if (st == CDPR_E_OUT_OF_RANGE) {
        fprintf(stderr, "%s: %s\n", prog, err.msg);
    } else if (st != CDPR_OK) {
        fprintf(stderr, "%s: %s: the check of the controller's design failed: %s\n", prog, path,
                err.msg);
    } else if (warn != 0) {
        fprintf(stderr, "%s: warning: %s\n", prog, err.msg);
    }
    return st;
}
