/* SPDX-License-Identifier: BSD-3-Clause */
/// @file main.c
/// cdpr-rt: the real-time plant node. Loads a scenario, initialises the robot at static
/// equilibrium, then steps it in a periodic thread, publishing cabin state, cable tensions,
/// cable shape and diagnostics over LCM and taking winch commands back (docs/realtime.md).
///
/// The run settings are the scenario's (run.period_s, run.duration_s, integrator.max_trials,
/// integrator.max_attempts); --rate, --duration, --max-trials and --max-attempts override
/// them, each with a note on stderr when it changes the file's value.
///
/// Exit codes (the apps' one table, app_status.h): 0 run completed, 1 stopped early
/// (SIGINT/SIGTERM/SIGHUP: telemetry printed, --tracker-out written with status
/// "interrupted"), 2 bad command line or scenario, 3 LCM, thread or output failure (the file
/// and strerror on stderr; it outranks 1; also: the scenario file cannot be read).
#include <getopt.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "app_cli.h"
#include "app_run.h"
#include "app_status.h"
#include "cdpr/host/correction.h"
#include "cdpr/host/plant.h"
#include "cdpr/host/cli.h"
#include "cdpr/host/scenario.h"
#include "cdpr/rt/plant_node.h"
#include "cdpr/rt/tracker_node.h"

typedef struct {
    const char *scenario;
    const char *tracker_out;
    int with_tracker;
    int quiet;
    int check_design; /* --check-design */
    cdpr_scenario_overrides_t ov;
    cdpr_rt_plant_opts_t rt;
} options_t;

static void usage(FILE *f)
{
    fprintf(
        f, "usage: cdpr-rt SCENARIO [options]\n"
           "Real-time plant node: the scenario's robot (settled at its initial pose) stepped\n"
           "by a periodic thread; publishes <prefix>CABIN_STATE, CABLE_TENSIONS, CABLE_SHAPE,\n"
           "DIAGNOSTICS and takes <prefix>WINCH_COMMAND (docs/realtime.md).\n\n"
           "  --rate HZ              control rate (default: 1 / the scenario's run.period_s)\n"
           "  --duration S           plant time to run, a whole number of periods; failed\n"
           "                         periods do not count (default: the scenario's\n"
           "                         run.duration_s)\n"
           "  --lockstep             step only when the command answering the last state came\n"
           "                         (deterministic: bit-identical to the in-process loop)\n"
           "  --lockstep-timeout S   lockstep: hold after waiting S for an answer (default 2);\n"
           "                         no answer for 30 s in a row: stop (exit 1)\n"
           "  --realtime             SCHED_FIFO + mlockall when permitted (else says why and\n"
           "                         runs SCHED_OTHER)\n"
           "  --priority N           SCHED_FIFO priority 1..99 (default 80)\n"
           "  --max-trials N         RKF45 trials per attempt (default: the scenario's\n"
           "                         integrator.max_trials)\n"
           "  --max-attempts N       attempts per period; the work bound of a period is\n"
           "                         max-attempts x max-trials (default: the scenario's\n"
           "                         integrator.max_attempts)\n"
           "  --integrator NAME      rkf45, ros34pw2 or ros34pw2-fixed (default: the scenario's\n"
           "                         integrator.method)\n"
           "  --watchdog S           no valid command for S -> winches hold (default: 0.1 s\n"
           "                         or two periods, the longer; free-running: >= 2 periods)\n"
           "  --start-delay S        free-running: wait S before the first period (default 0)\n"
           "  --startup S            free-running: deadline misses in the first S of plant\n"
           "                         time are counted apart (default 1)\n"
           "  --max-misses N         free-running: stop (exit 1) after N deadline misses after\n"
           "                         the start-up (default 0: count only)\n"
           "  --max-misses-in-row N  free-running: stop after N misses in a row (default 0)\n"
           "  --lcm-url URL          LCM provider (default: liblcm's, i.e. $LCM_DEFAULT_URL or\n"
           "                         udpm://239.255.76.67:7667?ttl=0)\n"
           "  --prefix P             channel prefix (default CDPR_)\n"
           "  --with-tracker         also run the example tracker in this process, on the LCM\n"
           "                         thread (what memq:// needs: it is in-process only)\n"
           "  --tracker-out DIR      with --with-tracker: its timeseries.csv, summary.json and\n"
           "                         figures (as cdpr-tracker --out)\n"
           "  --check-design         with --with-tracker: first check the controller's feedback\n"
           "                         and learning on the linearised loop (seconds; exit 2 when\n"
           "                         refused; docs/scenarios.md)\n"
           "  --quiet                no telemetry summary\n"
           "  --help                 this text\n"
           "  --version              version and git description\n\n"
           "exit codes: 0 completed, 1 stopped by a signal or a plant that cannot advance,\n"
           "            2 bad command line or scenario, 3 LCM/thread start-up or output\n"
           "            failure, unreadable scenario, 5 another plant on the channels\n"
           "            SIGINT/SIGTERM/SIGHUP: telemetry, --tracker-out \"interrupted\", exit 1\n");
}

/* The options of cdpr-rt (cdpr_app_option_fn). */
static int take(int c, const char *arg, void *ctx)
{
    options_t *o = ctx;
    const int ov = cdpr_app_run_option("cdpr-rt", c, arg, &o->ov, &o->check_design, &o->quiet);
    if (ov != 1) {
        return ov;
    }
    int bad = 0;
    double v = 0.0;
    switch (c) {
    case 'L':
        bad = (int)cdpr_cli_real("cdpr-rt", "lockstep-timeout", arg, &o->rt.lockstep_timeout_s);
        break;
    case 'P':
        /* Whole and within an int here; its range is cdpr_rt_plant_init's. */
        bad =
            (int)cdpr_cli_number("cdpr-rt", "priority", arg, (double)INT_MIN, (double)INT_MAX, &v);
        bad = (bad == 0 && floor(v) < v)
                  ? (int)cdpr_app_usage_error("cdpr-rt", "--priority: a whole number")
                  : bad;
        o->rt.rt_priority = (int)v;
        break;
    case 'w':
        bad = (int)cdpr_cli_real("cdpr-rt", "watchdog", arg, &o->rt.lcm.watchdog_timeout_s);
        break;
    case 's':
        bad = (int)cdpr_cli_real("cdpr-rt", "start-delay", arg, &o->rt.start_delay_s);
        break;
    case 'U':
        bad = (int)cdpr_cli_real("cdpr-rt", "startup", arg, &o->rt.startup_s);
        break;
    case 'X':
    case 'Y':
        /* Whole, >= 0 and within a long. */
        bad = (int)cdpr_cli_number("cdpr-rt", (c == 'X') ? "max-misses" : "max-misses-in-row", arg,
                                   0.0, 1e15, &v);
        bad = (bad == 0 && floor(v) < v)
                  ? (int)cdpr_app_usage_error("cdpr-rt", "--%s: a whole number",
                                              (c == 'X') ? "max-misses" : "max-misses-in-row")
                  : bad;
        *((c == 'X') ? &o->rt.max_misses : &o->rt.max_misses_in_row) = (long)v;
        break;
    default: {
        const cdpr_app_store_t stores[] = {
            {.code = 'l', .flag = &o->rt.lockstep, .value = 1},
            {.code = 'R', .flag = &o->rt.realtime, .value = 1},
            {.code = 'u', .text = &o->rt.lcm.url},
            {.code = 'p', .text = &o->rt.lcm.channel_prefix},
            {.code = 't', .flag = &o->with_tracker, .value = 1},
            {.code = 'o', .text = &o->tracker_out},
        };
        return cdpr_app_store(stores, sizeof stores / sizeof stores[0], c, arg);
    }
    }
    return (bad != 0) ? -1 : 0;
}

static int parse(int argc, char **argv, options_t *o)
{
    static const struct option longopts[] = {CDPR_APP_RUN_OPTIONS,
                                             {"lockstep", no_argument, NULL, 'l'},
                                             {"lockstep-timeout", required_argument, NULL, 'L'},
                                             {"realtime", no_argument, NULL, 'R'},
                                             {"priority", required_argument, NULL, 'P'},
                                             {"watchdog", required_argument, NULL, 'w'},
                                             {"start-delay", required_argument, NULL, 's'},
                                             {"startup", required_argument, NULL, 'U'},
                                             {"max-misses", required_argument, NULL, 'X'},
                                             {"max-misses-in-row", required_argument, NULL, 'Y'},
                                             CDPR_APP_LCM_OPTIONS,
                                             {"with-tracker", no_argument, NULL, 't'},
                                             {"tracker-out", required_argument, NULL, 'o'},

                                             CDPR_APP_STD_OPTIONS_END};
    if (cdpr_app_parse("cdpr-rt", argc, argv, longopts, usage, take, o) != 0 ||
        cdpr_app_scenario_operand("cdpr-rt", argc, argv, &o->scenario) != CDPR_OK) {
        return -1;
    }
    if (o->tracker_out != NULL && o->with_tracker == 0) {
        (void)cdpr_app_usage_error("cdpr-rt", "--tracker-out needs --with-tracker");
        return -1;
    }
    if (o->check_design != 0 && o->with_tracker == 0) {
        /* without the in-process tracker there is no controller here to check */
        (void)cdpr_app_usage_error("cdpr-rt", "--check-design needs --with-tracker");
        return -1;
    }
    return 0;
}

/* Reports from the node's threads: one line each on stderr. */
static void on_other_plant(int64_t session, void *ctx)
{
    (void)ctx;
    fprintf(stderr,
            "cdpr-rt: warning: another plant (session %lld) publishes on this plant's channels: "
            "one plant per channel prefix (the run will end with exit code 5)\n",
            (long long)session);
}

static void on_overload(long periods, long misses, double rate_hz, void *ctx)
{
    (void)ctx;
    fprintf(stderr,
            "cdpr-rt: warning: %ld of the first %ld periods missed their deadline: this machine "
            "does not hold %.0f Hz (plant time falls behind wall time)\n",
            misses, periods, rate_hz);
}

/* Everything big is static. */
static cdpr_rt_plant_t g_rt;
static cdpr_rt_tracker_t g_tracker;
static cdpr_rt_tracker_record_t g_record;
static cdpr_summary_t g_tracker_sum;

static int tracker_open(lcm_t *lcm, void *ctx)
{
    cdpr_rt_tracker_t *t = ctx;
    return cdpr_rt_tracker_attach(t, lcm);
}

/* The in-process tracker on the bridge thread, recording what it sees. */
/* The work of one period, stated before the run (docs/realtime.md "Real-time contract"): the
 * fixed mode's exact count, or the adaptive schemes' bound. */
static void print_work_per_period(const cdpr_rt_plant_t *rt)
{
    const cdpr_plant_t *p = &rt->plant;
    const int trials = p->pp.max_trials * p->pp.max_attempts;
    switch (p->pp.integrator) {
    case CDPR_PLANT_ROS34PW2_FIXED:
        fprintf(stderr,
                "cdpr-rt: work per period: exactly %d RHS, %d factorisations, %d solves (%d "
                "fixed substeps of %.4g ms), every period\n",
                4 * p->substeps, p->substeps, 4 * p->substeps, p->substeps,
                1e3 * (double)p->pp.period_s / p->substeps);
        break;
    case CDPR_PLANT_ROS34PW2:
        fprintf(stderr,
                "cdpr-rt: work per period: adaptive, at most %d RHS, %d factorisations, %d "
                "solves (%d trials); no worst case below that bound\n",
                4 * trials, trials, 4 * trials, trials);
        break;
    case CDPR_PLANT_RKF45:
    default:
        fprintf(stderr,
                "cdpr-rt: work per period: adaptive, at most %d RHS (%d trials); no worst case "
                "below that bound\n",
                6 * trials, trials);
        break;
    }
}

static cdpr_status_t tracker_setup(const options_t *o, const cdpr_scenario_t *sc)
{
    cdpr_tracker_gains_t g = sc->gains;
    g.wind_m_per_s = g_rt.plant.pp.wind_m_per_s; /* the wind feed-forward's steady wind */
    const double period_s = g_rt.plant.pp.period_s;
    static cdpr_host_correction_t corr; /* controller.precompensation (correction.h) */
    static cdpr_robot_params_t model;   /* the controller's own (controller.model) */
    cdpr_scenario_error_t cerr;
    cdpr_status_t cs = cdpr_host_controller_params(sc, &model, &cerr);
    if (cs == CDPR_OK) {
        cs = cdpr_correction_for_scenario(sc, &corr, &g.correction, &cerr);
    }
    if (cs != CDPR_OK) {
        fprintf(stderr, "cdpr-rt: %s\n", cerr.msg);
        return cs;
    }
    cdpr_diag_t d;
    const cdpr_status_t st =
        cdpr_rt_tracker_init(&g_tracker, &model, g_rt.plant.pp.winch, &sc->traj, &g, period_s,
                             o->rt.lcm.channel_prefix, &d);
    if (st != CDPR_OK) {
        fprintf(stderr, "cdpr-rt: tracker: field '%s': %s\n", d.field, cdpr_status_str(st));
        return st;
    }
    g_tracker.answer_in_handler = 1;
    g_record.traj = &sc->traj;
    g_record.period_s = period_s;
    cdpr_scenario_error_t err;
    const cdpr_status_t rs = cdpr_record_open(&g_record.rec, sc, &g_rt.plant.pp, o->tracker_out,
                                              g_rt.plant.robot.p.n_cables, &g_tracker_sum, &err);
    if (rs != CDPR_OK) {
        fprintf(stderr, "cdpr-rt: %s\n", err.msg);
        return rs;
    }
    g_tracker.on_step = cdpr_rt_tracker_record_step;
    g_tracker.on_step_ctx = &g_record;
    return CDPR_OK;
}

/* The in-process tracker's summary (status: `run` of the plant, or io_error when its CSV
 * failed) and outputs: the CSV's whole rows, summary.json even after a CSV failure (another
 * file: it may fit), the figures only when both were written. CDPR_OK or CDPR_E_IO after
 * printing "cdpr-rt: FILE: why". */
static cdpr_status_t tracker_finish(const options_t *o, const cdpr_scenario_t *sc,
                                    cdpr_status_t run)
{
    cdpr_status_t st = cdpr_record_close(&g_record.rec);
    cdpr_scenario_error_t err;
    if (st != CDPR_OK) {
        cdpr_record_io_error(&g_record.rec, &err);
        fprintf(stderr, "cdpr-rt: %s\n", err.msg);
    }
    g_tracker_sum.max_payout_m_per_s = g_record.max_payout_m_per_s;
    g_tracker_sum.ik_failures = g_tracker.tracker.ik_failures;
    cdpr_record_tracker_counts(&g_tracker.tracker, &g_tracker_sum);
    /* The plant runs in this process: its own counts (as cdpr-sim's summary has them). */
    const cdpr_plant_t *p = &g_rt.plant;
    g_tracker_sum.node_insertions = g_rt.tel.node_insertions;
    g_tracker_sum.node_removals = g_rt.tel.node_removals;
    g_tracker_sum.capacity_hits = 0;
    for (int j = 0; j < p->robot.p.n_cables; ++j) {
        g_tracker_sum.capacity_hits += p->nodes.capacity_hits[j];
    }
    g_tracker_sum.substep_limit_hits = p->stats.substep_limit_hits;
    g_tracker_sum.min_length_periods = p->stats.min_length_periods;
    cdpr_plant_work_t w;
    cdpr_plant_work(p, &w);
    g_tracker_sum.steps_accepted = w.steps_accepted;
    g_tracker_sum.steps_rejected = w.steps_rejected;
    g_tracker_sum.rhs_evals = w.rhs_evals;
    g_tracker_sum.settle_steps = p->settle.steps;
    g_tracker_sum.settle_wall_time_s = (double)NAN; /* not measured by cdpr_rt_plant_init */
    g_tracker_sum.wall_time_s = g_rt.tel.wall_s;
    cdpr_rt_plant_summary_figures(&g_rt, &g_tracker_sum.rt);
    g_tracker_sum.max_rhs_per_period = g_rt.tel.max_rhs_per_period;
    if (p->pp.integrator == CDPR_PLANT_ROS34PW2_FIXED) {
        g_tracker_sum.substeps = p->substeps;
        g_tracker_sum.max_err_norm = (double)p->stats.max_err_norm;
        g_tracker_sum.err_above_one_periods = p->stats.err_above_one_periods;
    }
    g_tracker_sum.status = CDPR_SUMMARY_OK;
    const char *why = "";
    if (st != CDPR_OK) {
        g_tracker_sum.status = CDPR_SUMMARY_IO_ERROR;
        why = "timeseries.csv write failed; ";
    } else if (run == CDPR_E_INTERRUPTED) {
        g_tracker_sum.status = CDPR_SUMMARY_INTERRUPTED;
        why = "interrupted by a signal; ";
    } else if (run == CDPR_E_CONFLICT) {
        g_tracker_sum.status = CDPR_SUMMARY_WARNINGS;
        why = "another plant shared the channels; ";
    } else if (run != CDPR_OK) {
        g_tracker_sum.status = CDPR_SUMMARY_FAILED;
        why = "the plant could not advance; ";
    }
    snprintf(g_tracker_sum.message, sizeof g_tracker_sum.message, "%s%llu commands", why,
             (unsigned long long)g_tracker.stats.answered);
    if (o->quiet == 0) {
        cdpr_summary_print(stdout, "in-process tracker", &g_tracker_sum);
        cdpr_rt_tracker_print_cost(stdout, &g_tracker);
    }
    if (o->tracker_out != NULL) {
        char script[1200];
        (void)cdpr_app_data_file("scripts/plot_sim.gp", script, sizeof script);
        const cdpr_status_t ws = cdpr_app_write_outputs(
            "cdpr-rt", sc, o->tracker_out, &g_tracker_sum, (st == CDPR_OK) ? script : NULL);
        st = (st == CDPR_OK) ? ws : st;
    }
    return st;
}

int main(int argc, char **argv)
{
    options_t o;
    memset(&o, 0, sizeof o);
    cdpr_rt_plant_opts_default(&o.rt);
    cdpr_scenario_overrides_none(&o.ov);
    if (parse(argc, argv, &o) != 0) {
        return cdpr_app_exit_code(CDPR_E_INVALID_ARG);
    }
    cdpr_scenario_t sc;
    cdpr_status_t st = cdpr_app_scenario("cdpr-rt", o.scenario, &o.ov, &sc);
    if (st != CDPR_OK) {
        return cdpr_app_exit_code(st);
    }
    /* The scenario's controller runs only in the in-process tracker. */
    if (o.with_tracker != 0 && (st = cdpr_app_design_gate("cdpr-rt", o.scenario, &sc, &o.ov,
                                                          o.check_design, o.quiet)) != CDPR_OK) {
        return cdpr_app_exit_code(st);
    }
    o.rt.stop = cdpr_app_stop_on_signals();
    o.rt.lcm.on_other_plant = on_other_plant;
    o.rt.on_overload = on_overload;
    if (o.with_tracker != 0) {
        o.rt.lcm.on_open = tracker_open;
        o.rt.lcm.on_open_ctx = &g_tracker;
    }
    if (o.quiet == 0) {
        fprintf(stderr, "cdpr-rt: %s: settling the initial state...\n", o.scenario);
    }
    cdpr_scenario_error_t err;
    st = cdpr_rt_plant_init(&g_rt, &sc, &o.rt, &err);
    if (st != CDPR_OK) {
        fprintf(stderr, "cdpr-rt: %s\n", err.msg);
        return cdpr_app_exit_code(st);
    }
    if (o.with_tracker != 0 && (st = tracker_setup(&o, &sc)) != CDPR_OK) {
        return cdpr_app_exit_code(st);
    }
    if (o.quiet == 0) {
        fprintf(stderr, "cdpr-rt: running %.3g s at %.0f Hz, %d x %d trials (%s) on %s\n",
                sc.duration_s, 1.0 / sc.period_s, sc.integrator.max_attempts,
                sc.integrator.max_trials, (g_rt.o.lockstep != 0) ? "lockstep" : "free-running",
                (o.rt.lcm.url != NULL) ? o.rt.lcm.url : "liblcm's default URL");
        print_work_per_period(&g_rt);
    }
    st = cdpr_rt_plant_run(&g_rt, &err);
    if (st != CDPR_OK) {
        fprintf(stderr, "cdpr-rt: %s\n", err.msg);
    }
    if (st == CDPR_E_IO) {
        return cdpr_app_exit_code(st);
    }
    if (o.quiet == 0) {
        cdpr_rt_plant_print_summary(&g_rt, stdout);
    }
    if (o.with_tracker != 0) {
        /* An output failure (exit 3) outranks a stop by a signal (exit 1). */
        const cdpr_status_t ts = tracker_finish(&o, &sc, st);
        st = (ts != CDPR_OK) ? ts : st;
    }
    return cdpr_app_exit_code(st);
}
