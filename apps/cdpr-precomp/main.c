/* SPDX-License-Identifier: BSD-3-Clause */
/// @file main.c
/// cdpr-precomp: the length pre-compensation of a scenario's known trajectory (issue 22 item
/// 1; docs/scenarios.md "Pre-compensation", docs/validation.md §8): iterated offline against
/// the scenario's nonlinear model (cdpr_design_precompensate) and written to a correction file
/// that a scenario names with controller.precompensation. Prints a line per model run and the
/// result; the file's `report:` keeps it.
#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "app_cli.h"
#include "app_run.h"
#include "app_status.h"
#include "cdpr/design/design.h"
#include "cdpr/host/cli.h"
#include "cdpr/host/clock.h"
#include "cdpr/host/correction.h"
#include "cdpr/host/scenario.h"

static void usage(FILE *f)
{
    fprintf(f,
            "usage: cdpr-precomp SCENARIO OUT.yaml [--runs N] [--poses N] [--spacing S]\n"
            "                    [--floor N] [--lambda L] [--rot-weight W] [--quiet] [overrides]\n"
            "The length pre-compensation of the scenario's trajectory: a smooth correction\n"
            "per cable, iterated against the scenario's model (the plant as written, the\n"
            "controller as configured) and written to OUT.yaml, tied to the trajectory, the\n"
            "controller's robot model, its gains and the control period by their hashes. A\n"
            "scenario uses it with `controller: precompensation: OUT.yaml`\n"
            "(docs/scenarios.md \"Pre-compensation\").\n\n"
            "  --runs N        most model runs, the first without correction (default 8)\n"
            "  --poses N       poses along the motion where the loop is linearised (default 5)\n"
            "  --spacing S     knot spacing of the correction [s] (a whole number of control\n"
            "                  periods; default 0.3)\n"
            "  --floor N       smallest cable-end tension an iterate may reach [N] (default 20)\n"
            "  --lambda L      regularisation of the steps (default 1e-3)\n"
            "  --rot-weight W  weight of the attitude error [m/rad] (default 1)\n"
            "  --robust-mass X the cost also over the plant's cabin mass (and inertia) times\n"
            "                  1 + X and 1 - X, the controller's model kept (0 to 0.3; default 0)\n"
            "  --robust-ea X   the same for every rope's EA (0 to 0.3; default 0)\n"
            "  --quiet         no line per run\n"
            "  --rate HZ  --duration S  --max-trials N  --max-attempts N  --integrator NAME\n"
            "                  the run settings of cdpr-sim (docs/scenarios.md), applied first\n"
            "  --help          this text\n"
            "  --version       version and git description\n\n"
            "exit codes: 0 written, 2 bad command line or scenario, 3 OUT cannot be written,\n"
            "            4 the iteration failed (a model run, the linearisation, LAPACK)\n");
}

/* Option codes beyond any char (the override options take letters). */
enum {
    OPT_RUNS = 0x200,
    OPT_POSES,
    OPT_SPACING,
    OPT_FLOOR,
    OPT_LAMBDA,
    OPT_ROT_WEIGHT,
    OPT_ROBUST_MASS,
    OPT_ROBUST_EA
};

typedef struct {
    cdpr_precomp_opts_t po;
    int quiet;
    cdpr_scenario_overrides_t ov;
} options_t;

static int take(int c, const char *arg, void *ctx)
{
    options_t *o = ctx;
    const int ov = cdpr_app_run_option("cdpr-precomp", c, arg, &o->ov, NULL, &o->quiet);
    if (ov != 1) {
        return ov;
    }
    double v = 0.0;
    cdpr_status_t bad = CDPR_OK;
    switch (c) {
    case OPT_RUNS:
        bad = cdpr_cli_number("cdpr-precomp", "runs", arg, 1.0, 1000.0, &v);
        o->po.max_runs = (int)v;
        break;
    case OPT_POSES:
        bad = cdpr_cli_number("cdpr-precomp", "poses", arg, 1.0, 64.0, &v);
        o->po.poses = (int)v;
        break;
    case OPT_SPACING:
        bad = cdpr_cli_number("cdpr-precomp", "spacing", arg, 1e-4, 100.0, &o->po.spacing_s);
        break;
    case OPT_FLOOR:
        bad = cdpr_cli_number("cdpr-precomp", "floor", arg, 0.0, 1e7, &o->po.floor_N);
        break;
    case OPT_LAMBDA:
        bad = cdpr_cli_number("cdpr-precomp", "lambda", arg, 1e-12, 1e3, &o->po.lambda);
        break;
    case OPT_ROT_WEIGHT:
        bad = cdpr_cli_number("cdpr-precomp", "rot-weight", arg, 0.0, 1e3, &o->po.rot_weight_m);
        break;
    case OPT_ROBUST_MASS:
        bad = cdpr_cli_number("cdpr-precomp", "robust-mass", arg, 0.0, CDPR_PRECOMP_MAX_VARIATION,
                              &o->po.robust_mass);
        break;
    case OPT_ROBUST_EA:
        bad = cdpr_cli_number("cdpr-precomp", "robust-ea", arg, 0.0, CDPR_PRECOMP_MAX_VARIATION,
                              &o->po.robust_ea);
        break;
    default:
        return 1;
    }
    if (bad == CDPR_OK && (c == OPT_RUNS || c == OPT_POSES) && floor(v) < v) {
        bad = cdpr_app_usage_error("cdpr-precomp", "--%s: a whole number",
                                   (c == OPT_RUNS) ? "runs" : "poses");
    }
    return (bad != CDPR_OK) ? -1 : 0;
}

int main(int argc, char **argv)
{
    static const struct option longopts[] = {
        {"runs", required_argument, NULL, OPT_RUNS},
        {"poses", required_argument, NULL, OPT_POSES},
        {"spacing", required_argument, NULL, OPT_SPACING},
        {"floor", required_argument, NULL, OPT_FLOOR},
        {"lambda", required_argument, NULL, OPT_LAMBDA},
        {"rot-weight", required_argument, NULL, OPT_ROT_WEIGHT},
        {"robust-mass", required_argument, NULL, OPT_ROBUST_MASS},
        {"robust-ea", required_argument, NULL, OPT_ROBUST_EA},
        CDPR_APP_QUIET_OPTION,
        CDPR_APP_OVERRIDE_OPTIONS,
        CDPR_APP_STD_OPTIONS_END};
    options_t o;
    memset(&o, 0, sizeof o);
    cdpr_precomp_opts_default(&o.po);
    cdpr_scenario_overrides_none(&o.ov);
    if (cdpr_app_parse("cdpr-precomp", argc, argv, longopts, usage, take, &o) != 0) {
        return cdpr_app_exit_code(CDPR_E_INVALID_ARG);
    }
    if (argc - optind != 2) {
        return cdpr_app_exit_code(
            cdpr_app_usage_error("cdpr-precomp", "SCENARIO and OUT.yaml expected"));
    }
    const char *path = argv[optind];
    const char *out = argv[optind + 1];
    static cdpr_scenario_t sc;
    cdpr_status_t st = cdpr_app_scenario("cdpr-precomp", path, &o.ov, &sc);
    if (st != CDPR_OK) {
        return cdpr_app_exit_code(st);
    }
    o.po.log = (o.quiet != 0) ? NULL : stderr;
    static cdpr_host_correction_t hc;
    cdpr_design_error_t err;
    const double t0 = cdpr_clock_now_s();
    st = cdpr_design_precompensate(&sc, &o.po, &hc, &err);
    if (st != CDPR_OK) {
        fprintf(stderr, "cdpr-precomp: %s: %s\n", path, err.msg);
        return (st == CDPR_E_OUT_OF_RANGE) ? 2 : 4;
    }
    /* the command line that made it (what the report does not say: options, overrides) */
    char note[1400] = "made by: cdpr-precomp";
    size_t used = strlen(note);
    for (int i = 1; i < argc && used + 2U < sizeof note; ++i) {
        const int w = snprintf(&note[used], sizeof note - used, " %s", argv[i]);
        used = (w > 0 && (size_t)w < sizeof note - used) ? used + (size_t)w : sizeof note - 1U;
    }
    for (size_t i = 0; i < used; ++i) { /* one comment line in the file, whatever argv holds */
        if ((unsigned char)note[i] < 0x20U || note[i] == 0x7f) {
            note[i] = '?';
        }
    }
    cdpr_scenario_error_t werr;
    st = cdpr_correction_write(out, &hc, note, &werr);
    if (st != CDPR_OK) {
        fprintf(stderr, "cdpr-precomp: %s\n", werr.msg);
        return 3;
    }
    const cdpr_correction_report_t *r = &hc.report;
    printf("cdpr-precomp: %s: %d model runs in %.0f s; RMS after 2 s %.2f -> %.2f mm (max %.2f "
           "mm, %.2f mrad), min cable-end tension %.1f N (floor %.0f N); %d x %d coefficients "
           "every %g s -> %s\n",
           path, r->iterations, cdpr_clock_now_s() - t0, 1e3 * r->rms_before_m,
           1e3 * r->rms_after_m, 1e3 * r->max_after_m, 1e3 * r->max_after_rad, r->min_tension_N,
           hc.floor_N, hc.c.n_cables, hc.c.n_coef, (double)hc.c.spacing_s, out);
    /* a model that started below the floor: its iterates were kept when they did not fall
     * further (cdpr_design_precompensate), so the file can be below it: say so */
    const double t_low =
        fmin(r->min_tension_N,
             (o.po.robust_mass > 0.0 || o.po.robust_ea > 0.0) ? r->varied_min_tension_N : HUGE_VAL);
    if (t_low < hc.floor_N) {
        fprintf(stderr,
                "cdpr-precomp: warning: a model run with this correction reaches %.1f N, below "
                "the floor of %.0f N (the run without correction was already below it); check "
                "the scenario's gains and the controller's model\n",
                t_low, hc.floor_N);
    }
    if (o.po.robust_mass > 0.0 || o.po.robust_ea > 0.0) {
        printf("cdpr-precomp: the varied plants (cabin mass x (1 +- %g), EA x (1 +- %g)): worst "
               "RMS after 2 s %.2f mm, max %.2f mm, %.2f mrad, min cable-end tension %.1f N\n",
               r->robust_mass, r->robust_ea, 1e3 * r->varied_rms_after_m,
               1e3 * r->varied_max_after_m, 1e3 * r->varied_max_after_rad, r->varied_min_tension_N);
    }
    return 0;
}
