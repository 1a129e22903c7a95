/// @file main.c
/// cdpr-sim: run a scenario file (closed-loop tracking of a trajectory by the lumped-mass
/// robot) and write DIR/timeseries.csv, DIR/summary.json and PNG figures (gnuplot).
///
/// Exit codes: 0 run completed (also with warnings, see summary.json "status"), 1 the
/// simulation stopped early, 2 bad command line or bad scenario, 3 output error.
#include <errno.h>
#include <getopt.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "cdpr/host/cli.h"
#include "cdpr/host/scenario.h"
#include "cdpr/host/sim.h"

#ifndef CDPR_SOURCE_DIR
#define CDPR_SOURCE_DIR "."
#endif

enum { EXIT_RUN_FAILED = 1, EXIT_USAGE = 2, EXIT_OUTPUT = 3 };

typedef struct {
    const char *scenario;
    const char *out_dir;
    const char *plot_script;
    double duration_s;
    int plot;
    int progress; /* -1 auto (a tty), 0 off, 1 forced */
    int quiet;
} options_t;

static void usage(FILE *f)
{
    fprintf(f,
            "usage: cdpr-sim SCENARIO --out DIR [options]\n"
            "Run a scenario file (robot, initial pose, trajectory, controller, integrator,\n"
            "duration) in closed loop and write DIR/timeseries.csv, DIR/summary.json and\n"
            "figures with gnuplot: figure4.png (circle: path and error, the paper's Figure 4),\n"
            "figure5.png (line: error per coordinate, the paper's Figure 5) or errors.png\n"
            "(error per coordinate otherwise), and tensions.png. See docs/scenarios.md.\n\n"
            "  --out DIR           output directory (created if missing; required)\n"
            "  --duration S        simulate S seconds instead of run.duration_s (tests and\n"
            "                      quick looks; S must be a whole number of control periods)\n"
            "  --no-plot           do not run gnuplot\n"
            "  --plot-script FILE  gnuplot script (default %s/scripts/plot_sim.gp)\n"
            "  --progress          progress on stderr even when it is not a terminal\n"
            "  --quiet             no progress and no summary on stdout\n"
            "  --help              this text\n\n"
            "exit codes: 0 run completed (status ok or warnings), 1 simulation stopped early,\n"
            "            2 bad command line or scenario, 3 output error\n",
            CDPR_SOURCE_DIR);
}

static int parse(int argc, char **argv, options_t *o)
{
    static const struct option longopts[] = {
        {"out", required_argument, NULL, 'o'}, {"duration", required_argument, NULL, 'd'},
        {"no-plot", no_argument, NULL, 'n'},   {"plot-script", required_argument, NULL, 's'},
        {"progress", no_argument, NULL, 'p'},  {"quiet", no_argument, NULL, 'q'},
        {"help", no_argument, NULL, 'h'},      {NULL, 0, NULL, 0}};
    int c;
    while ((c = getopt_long(argc, argv, "h", longopts, NULL)) != -1) {
        switch (c) {
        case 'o':
            o->out_dir = optarg;
            break;
        case 'd':
            if (cdpr_cli_number("cdpr-sim", "duration", optarg, 1e-9, 1e6, &o->duration_s) != 0) {
                return -1;
            }
            break;
        case 'n':
            o->plot = 0;
            break;
        case 's':
            o->plot_script = optarg;
            break;
        case 'p':
            o->progress = 1;
            break;
        case 'q':
            o->quiet = 1;
            break;
        case 'h':
            usage(stdout);
            exit(0);
        default:
            usage(stderr);
            return -1;
        }
    }
    if (optind >= argc) {
        fprintf(stderr, "cdpr-sim: missing SCENARIO (try --help)\n");
        return -1;
    }
    o->scenario = argv[optind++];
    if (optind < argc) {
        fprintf(stderr, "cdpr-sim: unexpected argument '%s' (one scenario per run)\n",
                argv[optind]);
        return -1;
    }
    if (o->out_dir == NULL) {
        fprintf(stderr, "cdpr-sim: --out DIR is required\n");
        return -1;
    }
    return 0;
}

static void print_summary(const options_t *o, const cdpr_sim_summary_t *s)
{
    printf("%s: %s%s%s\n", o->scenario, cdpr_sim_status_name(s->status),
           (s->message[0] != '\0') ? " - " : "", s->message);
    printf("  tracking error  rms %.4g m, max %.4g m, final %.4g m (initial %.4g m); "
           "attitude rms %.1f mrad, max %.1f mrad\n",
           s->rms_error_m, s->max_error_m, s->final_error_m, s->initial_error_m,
           1e3 * s->rms_error_rad, 1e3 * s->max_error_rad);
    printf("  tensions        %.4g .. %.4g N;  payout |u| <= %.3g m/s\n", s->min_tension_N,
           s->max_tension_N, s->max_payout_m_per_s);
    printf("  node events     %lu insertions, %lu removals (segments %d..%d per cable)\n",
           s->node_insertions, s->node_removals, s->nodes_min, s->nodes_max);
    printf("  integrator      %lu steps, %lu rejected, %lu substep-limit periods, "
           "%lu IK failures\n",
           s->steps_accepted, s->steps_rejected, s->substep_limit_hits, s->ik_failures);
    printf("  time            %.3g s simulated in %.3g s wall (settling %.3g s)\n", s->sim_time_s,
           s->wall_time_s, s->settle_wall_time_s);
}

int main(int argc, char **argv)
{
    options_t o = {NULL, NULL, CDPR_SOURCE_DIR "/scripts/plot_sim.gp", 0.0, 1, -1, 0};
    if (parse(argc, argv, &o) != 0) {
        return EXIT_USAGE;
    }
    cdpr_scenario_t sc;
    cdpr_scenario_error_t err;
    if (cdpr_scenario_load(o.scenario, &sc, &err) != 0) {
        fprintf(stderr, "cdpr-sim: %s\n", err.msg);
        return EXIT_USAGE;
    }
    cdpr_sim_opts_t so;
    cdpr_sim_opts_default(&so);
    so.out_dir = o.out_dir;
    so.duration_s = o.duration_s;
    so.progress_stream = stderr;
    if (o.quiet == 0) {
        const int tty = isatty(STDERR_FILENO);
        /* A rewritten line on a terminal; plain lines when forced into a file or pipe. */
        so.progress = (tty != 0) ? 1 : ((o.progress > 0) ? 2 : 0);
    }
    cdpr_sim_summary_t sum;
    const int rc = cdpr_sim_run(&sc, &so, &sum, &err);
    if (rc == 2 || rc == 3) {
        fprintf(stderr, "cdpr-sim: %s\n", err.msg);
        return (rc == 2) ? EXIT_USAGE : EXIT_OUTPUT;
    }
    if (rc == 1) {
        fprintf(stderr, "cdpr-sim: %s: simulation stopped early: %s\n", o.scenario, sum.message);
    }
    int plotted = -1;
    const char *kind = (sc.traj.type == CDPR_TRAJ_CIRCLE)
                           ? "circle"
                           : ((sc.traj.type == CDPR_TRAJ_LINE) ? "line" : "hold");
    if (o.plot != 0) {
        plotted = cdpr_sim_plot("cdpr-sim", o.plot_script, o.out_dir, kind,
                                (sc.description[0] != '\0') ? sc.description : o.scenario);
    }
    if (o.quiet == 0) {
        print_summary(&o, &sum);
        printf("  outputs         %s/timeseries.csv, %s/summary.json\n", o.out_dir, o.out_dir);
        if (plotted == 0) {
            if (sc.traj.type == CDPR_TRAJ_CIRCLE) {
                printf("  figures         %s/figure4.png, %s/errors.png, %s/tensions.png\n",
                       o.out_dir, o.out_dir, o.out_dir);
            } else {
                printf("  figures         %s/%s, %s/tensions.png\n", o.out_dir,
                       (sc.traj.type == CDPR_TRAJ_LINE) ? "figure5.png" : "errors.png", o.out_dir);
            }
        }
    }
    return (rc == 1) ? EXIT_RUN_FAILED : 0;
}
