/* SPDX-License-Identifier: BSD-3-Clause */
/// @file main.c
/// cdpr-sim: run a scenario file (closed-loop tracking of a trajectory by the lumped-mass
/// robot) and write DIR/timeseries.csv, DIR/summary.json and PNG figures (gnuplot).
///
/// Exit codes (the apps' one table, app_status.h): 0 run completed (also with warnings, see
/// summary.json "status"), 1 the simulation stopped early (integrator; or SIGINT/SIGTERM/SIGHUP:
/// status "interrupted", whole rows, summary written), 2 bad command line or bad scenario,
/// 3 output error, with the file and strerror (summary status "io_error" where it can still be
/// written; also: the scenario file cannot be read).
#include <getopt.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "app_cli.h"
#include "app_run.h"
#include "app_status.h"
#include "cdpr/host/cli.h"
#include "cdpr/host/plot.h"
#include "cdpr/host/scenario.h"
#include "cdpr/host/sim.h"
#include "cdpr/control/trajectory.h"

typedef struct {
    const char *scenario;
    const char *out_dir;
    const char *plot_script;
    cdpr_scenario_overrides_t ov;
    int plot;
    int progress; /* -1 auto (a tty), 0 off, 1 forced */
    int quiet;
    int check_design; /* --check-design (1), --unchecked-gains (-1), neither (0) */
    int validate;     /* --validate: check the operands, run nothing */
    double shapes_hz; /* --shapes HZ: DIR/shapes.csv (0: none) */
} options_t;

/* The default gnuplot script: the installation's (cdpr_app_data_file). */
static char g_default_script[1200];

static void usage(FILE *f)
{
    fprintf(f,
            "usage: cdpr-sim SCENARIO --out DIR [options]\n"
            "       cdpr-sim --validate SCENARIO... [overrides]\n"
            "Run a scenario file (robot, initial pose, trajectory, controller, integrator,\n"
            "duration) in closed loop and write DIR/timeseries.csv, DIR/summary.json and\n"
            "figures with gnuplot, each as PNG and PDF: path (circle: path and error; figure4\n"
            "on the paper's robot, after its Figure 4), errors (error per coordinate; figure5\n"
            "for a line on the paper's robot), tensions (one panel per cable), cables\n"
            "(lengths, payout, segments), laps (periodic). See docs/scenarios.md.\n\n"
            "  --out DIR           output directory (created if missing; required)\n"
            "  --duration S        simulate S seconds instead of run.duration_s (tests and\n"
            "                      quick looks; S must be a whole number of run.period_s)\n"
            "  --integrator NAME   rkf45, ros34pw2 or ros34pw2-fixed instead of integrator.method\n"
            "  --shapes HZ         also write DIR/shapes.csv: every node of every cable at HZ\n"
            "                      (the control rate divided by a whole number), drawn as\n"
            "                      DIR/shapes.png/.pdf (the sag profiles)\n"
            "  --no-plot           do not run gnuplot\n"
            "  --plot-script FILE  gnuplot script; default: share/cdpr/scripts/plot_sim.gp of\n"
            "                      the installation (the source tree's from a build tree):\n"
            "                      %s\n"
            "  --progress          progress on stderr even when it is not a terminal\n"
            "  --quiet             no progress and no summary on stdout\n"
            "  --check-design      first check the controller's feedback and learning on the\n"
            "                      linearised loop (seconds; docs/scenarios.md): refused (exit\n"
            "                      2) when the closed loop grows or the learning diverges\n"
            "  --unchecked-gains   no check and no note that it was skipped (the default runs\n"
            "                      no check and says so once; the last of the two wins)\n"
            "  --validate          load and check each SCENARIO (with the overrides) and run\n"
            "                      nothing: one line per refused file, exit 0 when all pass,\n"
            "                      2 when any is refused (the sweep tool's check, many files\n"
            "                      in one process)\n"
            "  --help              this text\n"
            "  --version           version and git description\n\n"
            "exit codes: 0 run completed (status ok or warnings), 1 simulation stopped early,\n"
            "            2 bad command line or scenario, 3 output error or unreadable scenario\n"
            "            SIGINT/SIGTERM/SIGHUP: whole rows, summary.json \"interrupted\", exit 1\n",
            g_default_script);
}

/* The options of cdpr-sim (cdpr_app_option_fn). */
static int take(int c, const char *arg, void *ctx)
{
    options_t *o = ctx;
    const int ov = cdpr_app_run_option("cdpr-sim", c, arg, &o->ov, &o->check_design, &o->quiet);
    if (ov != 1) {
        return ov;
    }
    if (c == 'S') {
        return (cdpr_cli_number("cdpr-sim", "shapes", arg, 1e-6, 1e6, &o->shapes_hz) == CDPR_OK)
                   ? 0
                   : -1;
    }
    const cdpr_app_store_t stores[] = {
        {.code = 'o', .text = &o->out_dir},
        {.code = 'n', .flag = &o->plot, .value = 0},
        {.code = 's', .text = &o->plot_script},
        {.code = 'p', .flag = &o->progress, .value = 1},
        {.code = 'u', .flag = &o->check_design, .value = -1},
        {.code = 'V', .flag = &o->validate, .value = 1},
    };
    return cdpr_app_store(stores, sizeof stores / sizeof stores[0], c, arg);
}

static int parse(int argc, char **argv, options_t *o)
{
    static const struct option longopts[] = {
        {"out", required_argument, NULL, 'o'},
        {"duration", required_argument, NULL, CDPR_APP_OPT_DURATION},
        {"integrator", required_argument, NULL, CDPR_APP_OPT_INTEGRATOR},
        {"no-plot", no_argument, NULL, 'n'},
        {"shapes", required_argument, NULL, 'S'},
        {"plot-script", required_argument, NULL, 's'},
        {"progress", no_argument, NULL, 'p'},
        CDPR_APP_QUIET_OPTION,
        {"unchecked-gains", no_argument, NULL, 'u'},
        {"validate", no_argument, NULL, 'V'},
        CDPR_APP_CHECK_DESIGN_OPTION,
        CDPR_APP_STD_OPTIONS_END};
    if (cdpr_app_parse("cdpr-sim", argc, argv, longopts, usage, take, o) != 0) {
        return -1;
    }
    if (o->validate != 0) {
        if (optind >= argc) {
            (void)cdpr_app_usage_error("cdpr-sim", "--validate needs at least one scenario file");
            return -1;
        }
        return 0;
    }
    if (cdpr_app_scenario_operand("cdpr-sim", argc, argv, &o->scenario) != CDPR_OK) {
        return -1;
    }
    if (o->out_dir == NULL) {
        (void)cdpr_app_usage_error("cdpr-sim", "--out DIR is required");
        return -1;
    }
    return 0;
}

/* Where the figures are (scripts/plot_sim.gp): each as PNG and PDF. */
static void print_figures(const char *dir, const cdpr_scenario_t *sc, int n_laps)
{
    const int paper = cdpr_app_paper_robot(sc);
    const cdpr_traj_type_t type = sc->traj.type;
    const char *first = "errors";
    if (type == CDPR_TRAJ_CIRCLE) {
        first = (paper != 0) ? "figure4" : "path";
    } else if (type == CDPR_TRAJ_LINE && paper != 0) {
        first = "figure5";
    }
    printf("  figures         %s/%s%s, tensions, cables%s (each .png and .pdf)\n", dir, first,
           (type == CDPR_TRAJ_CIRCLE) ? ", errors" : "", (n_laps > 0) ? ", laps" : "");
}

/* --validate: every operand loaded and checked (cdpr_app_scenario prints why one is refused).
 * Exit code of the first refusal's status, 0 when all pass. */
static int validate(int argc, char **argv, const options_t *o)
{
    static cdpr_scenario_t sc; /* one at a time; static: large for the stack of a loop */
    cdpr_status_t first = CDPR_OK;
    int refused = 0;
    for (int i = optind; i < argc; ++i) {
        const cdpr_status_t st = cdpr_app_scenario("cdpr-sim", argv[i], &o->ov, &sc);
        if (st != CDPR_OK) {
            first = (refused == 0) ? st : first;
            ++refused;
        }
    }
    if (o->quiet == 0) {
        printf("cdpr-sim: %d of %d scenario files pass every check\n", argc - optind - refused,
               argc - optind);
    }
    return cdpr_app_exit_code(first);
}

int main(int argc, char **argv)
{
    options_t o;
    memset(&o, 0, sizeof o);
    (void)cdpr_app_data_file("scripts/plot_sim.gp", g_default_script, sizeof g_default_script);
    o.plot_script = g_default_script;
    o.plot = 1;
    o.progress = -1;
    cdpr_scenario_overrides_none(&o.ov);
    if (parse(argc, argv, &o) != 0) {
        return cdpr_app_exit_code(CDPR_E_INVALID_ARG);
    }
    if (o.validate != 0) {
        return validate(argc, argv, &o);
    }
    cdpr_scenario_t sc;
    const cdpr_status_t ls = cdpr_app_scenario("cdpr-sim", o.scenario, &o.ov, &sc);
    if (ls != CDPR_OK) {
        return cdpr_app_exit_code(ls);
    }
    const cdpr_status_t ds =
        cdpr_app_design_gate("cdpr-sim", o.scenario, &sc, &o.ov, (o.check_design > 0) ? 1 : 0,
                             (o.quiet != 0 || o.check_design < 0) ? 1 : 0);
    if (ds != CDPR_OK) {
        return cdpr_app_exit_code(ds);
    }
    cdpr_sim_opts_t so;
    cdpr_sim_opts_default(&so);
    so.out_dir = o.out_dir;
    so.progress_stream = stderr;
    so.stop = cdpr_app_stop_on_signals();
    so.shapes_rate_hz = o.shapes_hz;
    if (o.quiet == 0) {
        const int tty = isatty(STDERR_FILENO);
        /* A rewritten line on a terminal; plain lines when forced into a file or pipe. */
        so.progress = (tty != 0) ? 1 : ((o.progress > 0) ? 2 : 0);
    }
    cdpr_summary_t sum;
    cdpr_scenario_error_t err;
    err.msg[0] = '\0';
    const cdpr_status_t st = cdpr_sim_run(&sc, &so, &sum, &err);
    if (st != CDPR_OK && err.msg[0] != '\0') { /* could not start, or an output error */
        fprintf(stderr, "cdpr-sim: %s\n", err.msg);
        return cdpr_app_exit_code(st);
    }
    if (st == CDPR_E_INTERRUPTED) {
        fprintf(stderr, "cdpr-sim: %s: %s\n", o.scenario, sum.message);
    } else if (st != CDPR_OK) {
        fprintf(stderr, "cdpr-sim: %s: simulation stopped early: %s\n", o.scenario, sum.message);
    }
    cdpr_status_t plotted = CDPR_E_IO;
    if (o.plot != 0) {
        plotted = cdpr_app_plot("cdpr-sim", o.plot_script, o.out_dir, &sc);
    }
    if (o.quiet == 0) {
        cdpr_summary_print(stdout, o.scenario, &sum);
        printf("  outputs         %s/timeseries.csv, %s/summary.json\n", o.out_dir, o.out_dir);
        if (plotted == CDPR_OK) {
            print_figures(o.out_dir, &sc, sum.n_laps);
        }
    }
    return cdpr_app_exit_code(st);
}
