/* SPDX-License-Identifier: BSD-3-Clause */
/// @file app_design.c
/// The design check in process (app_design.h): cdpr-design's --verdict and --check.
#include "app_design.h"

#include <math.h>
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

cdpr_status_t cdpr_app_design_check(const char *prog, const char *path, const cdpr_scenario_t *sc,
                                    int quiet)
{
    int checked = 0; /* 0: feed-forward only, nothing computed */
    int warn = 0;
    cdpr_design_error_t err;
    /* Say what is coming: the check's dense algebra grows as the cube of the states (measured:
     * 6 s at 703 states, 81 s at 1417, with Debian's reference LAPACK; docs/performance.md). */
    const long n = design_states(sc);
    const double t0 = cdpr_clock_now_s();
    if (quiet == 0 && cdpr_tracker_has_feedback(&sc->gains) != 0 && n > 0) {
        const double expect_s = CDPR_APP_DESIGN_S_AT_703 * pow((double)n / 703.0, 3.0);
        fprintf(stderr,
                "%s: checking the controller's design on its linearised loop (%ld states of the "
                "robot; about %.0f s on an idle 2-core machine with reference LAPACK, growing as "
                "the cube of the states)...\n",
                prog, n, expect_s);
    }
    const cdpr_status_t st = cdpr_design_check_scenario(sc, path, &checked, &warn, NULL, &err);
    if (quiet == 0 && checked != 0) {
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
