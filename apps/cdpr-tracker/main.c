/// @file main.c
/// cdpr-tracker: the example external tracking controller. A separate process that speaks only
/// LCM: it subscribes to the plant's cabin state and cable tensions, follows the scenario's
/// trajectory with the sag-aware IK feed-forward plus feedback (tracker.h) and publishes winch
/// rate commands answering each state (docs/realtime.md). With --out it writes what it saw in
/// cdpr-sim's format (timeseries.csv, summary.json, figures).
///
/// Exit codes: 0 finished (answered the state at the end of the run), 1 stopped by a signal
/// or by silence (no state for --idle-exit seconds), 2 bad command line or scenario, 3 LCM
/// failure or output error.
#include <errno.h>
#include <stdint.h>
#include <getopt.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <lcm/eventlog.h>
#include <lcm/lcm.h>

#include "cdpr/host/plant.h"
#include "cdpr/host/cli.h"
#include "cdpr/rt/tracker_node.h"
#include "cdpr/host/scenario.h"

#ifndef CDPR_SOURCE_DIR
#define CDPR_SOURCE_DIR "."
#endif

enum { EXIT_STOPPED = 1, EXIT_USAGE = 2, EXIT_LCM = 3 };

static volatile int g_stop = 0;

static void on_signal(int sig)
{
    (void)sig;
    g_stop = 1;
}

/* SIGINT/SIGTERM set g_stop; the loops check it. */
static void install_stop_handler(void)
{
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_signal;
    sigemptyset(&sa.sa_mask);
    (void)sigaction(SIGINT, &sa, NULL);
    (void)sigaction(SIGTERM, &sa, NULL);
}

typedef struct {
    const char *scenario;
    const char *url;
    const char *prefix;
    const char *out_dir;
    const char *replay;
    double rate_hz;
    double duration_s;
    double idle_exit_s;
    int plot;
    int quiet;
} options_t;

static void usage(FILE *f)
{
    fprintf(
        f, "usage: cdpr-tracker SCENARIO [options]\n"
           "Example tracking controller over LCM: answers every <prefix>CABIN_STATE (+ the\n"
           "CABLE_TENSIONS of the same period) with a <prefix>WINCH_COMMAND following the\n"
           "scenario's trajectory (sag-aware IK feed-forward + feedback; docs/realtime.md).\n\n"
           "  --rate HZ        control rate; must equal cdpr-rt's --rate (default 1000)\n"
           "  --duration S     run length; exits after answering the state at S (default: the\n"
           "                   scenario's run.duration_s)\n"
           "  --idle-exit S    exit when no state came for S seconds after the first (default 5)\n"
           "  --lcm-url URL    LCM provider (default: liblcm's)\n"
           "  --prefix P       channel prefix (default CDPR_)\n"
           "  --out DIR        write DIR/timeseries.csv, summary.json and figures\n"
           "  --replay LOG     instead of computing commands, answer each state k with the\n"
           "                   command recorded for k in the lcm-logger LOG of a lockstep run and\n"
           "                   compare every state with the recorded one (HIL regression: run\n"
           "                   cdpr-rt --lockstep with the same scenario, rate and trials); exit\n"
           "                   0 when every recorded state was reproduced bit for bit\n"
           "  --no-plot        no figures\n"
           "  --quiet          no summary on stdout\n"
           "  --help           this text\n\n"
           "exit codes: 0 finished, 1 stopped (signal or silence), 2 bad command line or\n"
           "            scenario, 3 LCM or output failure\n");
}

static int parse(int argc, char **argv, options_t *o)
{
    static const struct option longopts[] = {{"rate", required_argument, NULL, 'r'},
                                             {"duration", required_argument, NULL, 'd'},
                                             {"idle-exit", required_argument, NULL, 'i'},
                                             {"lcm-url", required_argument, NULL, 'u'},
                                             {"prefix", required_argument, NULL, 'p'},
                                             {"out", required_argument, NULL, 'o'},
                                             {"no-plot", no_argument, NULL, 'n'},
                                             {"replay", required_argument, NULL, 'R'},
                                             {"quiet", no_argument, NULL, 'q'},
                                             {"help", no_argument, NULL, 'h'},
                                             {NULL, 0, NULL, 0}};
    int c;
    while ((c = getopt_long(argc, argv, "h", longopts, NULL)) != -1) {
        int bad = 0;
        switch (c) {
        case 'r':
            bad = cdpr_cli_number("cdpr-tracker", "rate", optarg, 1.0, 100000.0, &o->rate_hz);
            break;
        case 'd':
            bad = cdpr_cli_number("cdpr-tracker", "duration", optarg, 1e-6, 1e7, &o->duration_s);
            break;
        case 'i':
            bad = cdpr_cli_number("cdpr-tracker", "idle-exit", optarg, 0.01, 1e6, &o->idle_exit_s);
            break;
        case 'u':
            o->url = optarg;
            break;
        case 'p':
            o->prefix = optarg;
            break;
        case 'o':
            o->out_dir = optarg;
            break;
        case 'n':
            o->plot = 0;
            break;
        case 'R':
            o->replay = optarg;
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
        if (bad != 0) {
            return -1;
        }
    }
    if (optind >= argc) {
        fprintf(stderr, "cdpr-tracker: missing SCENARIO (try --help)\n");
        return -1;
    }
    o->scenario = argv[optind++];
    if (optind < argc) {
        fprintf(stderr, "cdpr-tracker: unexpected argument '%s'\n", argv[optind]);
        return -1;
    }
    return 0;
}

static double now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* ------------------------------------------------------------------------ replay */

typedef struct {
    cdpr_winch_command_t *cmd; /* by state_seq */
    unsigned char *have_cmd;
    cdpr_cabin_state_t *state; /* by seq */
    unsigned char *have_state;
    long n;        /* array length (largest seq + 1) */
    long last_cmd; /* largest state_seq with a command */
    lcm_t *lcm;
    char ch_command[80];
    long compared, mismatched, answered;
    long done_seq; /* state seq after which the replay is complete */
    int finished;
} replay_t;
static replay_t g_replay;

/* Read the recorded commands and states of a lockstep run. 0 or -1. */
static int replay_load(replay_t *r, const char *path, const char *prefix)
{
    char ch_state[80];
    snprintf(ch_state, sizeof ch_state, "%sCABIN_STATE", prefix);
    snprintf(r->ch_command, sizeof r->ch_command, "%sWINCH_COMMAND", prefix);
    for (int pass = 0; pass < 2; ++pass) {
        lcm_eventlog_t *log = lcm_eventlog_create(path, "r");
        if (log == NULL) {
            fprintf(stderr, "cdpr-tracker: --replay %s: cannot open: %s\n", path, strerror(errno));
            return -1;
        }
        lcm_eventlog_event_t *ev;
        while ((ev = lcm_eventlog_read_next_event(log)) != NULL) {
            if (strcmp(ev->channel, r->ch_command) == 0) {
                cdpr_winch_command_t c;
                if (cdpr_winch_command_t_decode(ev->data, 0, (int)ev->datalen, &c) > 0 &&
                    c.state_seq >= 0 && c.state_seq < 100000000) {
                    if (pass == 0) {
                        r->n = (c.state_seq + 1 > r->n) ? (long)c.state_seq + 1 : r->n;
                    } else if (r->have_cmd[c.state_seq] == 0) {
                        r->cmd[c.state_seq] = c;
                        r->have_cmd[c.state_seq] = 1;
                        r->last_cmd =
                            ((long)c.state_seq > r->last_cmd) ? (long)c.state_seq : r->last_cmd;
                    }
                }
            } else if (strcmp(ev->channel, ch_state) == 0) {
                cdpr_cabin_state_t st;
                if (cdpr_cabin_state_t_decode(ev->data, 0, (int)ev->datalen, &st) > 0 &&
                    st.seq >= 0 && st.seq < 100000000) {
                    if (pass == 0) {
                        r->n = (st.seq + 1 > r->n) ? (long)st.seq + 1 : r->n;
                    } else if (st.seq < r->n && r->have_state[st.seq] == 0) {
                        r->state[st.seq] = st;
                        r->have_state[st.seq] = 1;
                    }
                }
            }
            lcm_eventlog_free_event(ev);
        }
        lcm_eventlog_destroy(log);
        if (pass == 0) {
            if (r->n == 0) {
                fprintf(stderr, "cdpr-tracker: --replay %s: no %s / %s events\n", path, ch_state,
                        r->ch_command);
                return -1;
            }
            r->cmd = calloc((size_t)r->n, sizeof *r->cmd);
            r->have_cmd = calloc((size_t)r->n, 1);
            r->state = calloc((size_t)r->n, sizeof *r->state);
            r->have_state = calloc((size_t)r->n, 1);
            if (r->cmd == NULL || r->have_cmd == NULL || r->state == NULL ||
                r->have_state == NULL) {
                fprintf(stderr, "cdpr-tracker: out of memory\n");
                return -1;
            }
            r->last_cmd = -1;
        }
    }
    r->done_seq = r->n - 1; /* the last recorded state */
    return 0;
}

/* 1 when the n doubles have identical bit patterns (a value compare would let -0 == +0). */
static int same_bits(const double *a, const double *b, int n)
{
    for (int i = 0; i < n; ++i) {
        uint64_t ua;
        uint64_t ub;
        memcpy(&ua, &a[i], sizeof ua);
        memcpy(&ub, &b[i], sizeof ub);
        if (ua != ub) {
            return 0;
        }
    }
    return 1;
}

/* Same state: every field the plant computes (the flags may differ only in FLAG_HOLD, which
 * depends on timing, never in lockstep). */
static int same_state(const cdpr_cabin_state_t *a, const cdpr_cabin_state_t *b)
{
    return a->utime_us == b->utime_us && a->seq == b->seq &&
           same_bits(a->position_m, b->position_m, 3) &&
           same_bits(a->orientation, b->orientation, 4) &&
           same_bits(a->euler_rad, b->euler_rad, 3) &&
           same_bits(a->velocity_m_per_s, b->velocity_m_per_s, 3) &&
           same_bits(a->angular_velocity_rad_per_s, b->angular_velocity_rad_per_s, 3);
}

static void replay_on_state(const lcm_recv_buf_t *rbuf, const char *channel, void *user)
{
    (void)channel;
    replay_t *r = user;
    cdpr_cabin_state_t st;
    if (cdpr_cabin_state_t_decode(rbuf->data, 0, (int)rbuf->data_size, &st) <= 0 || st.seq < 0 ||
        st.seq >= r->n) {
        return;
    }
    if (r->have_state[st.seq] == 1) {
        r->have_state[st.seq] = 2; /* compared (a resent state is not counted twice) */
        r->compared++;
        if (same_state(&st, &r->state[st.seq]) == 0) {
            if (r->mismatched == 0) {
                fprintf(stderr, "cdpr-tracker: replay: state %lld differs from the log\n",
                        (long long)st.seq);
            }
            r->mismatched++;
        }
    }
    if (r->have_cmd[st.seq] != 0) {
        unsigned char buf[256];
        const int len = cdpr_winch_command_t_encode(buf, 0, (int)sizeof buf, &r->cmd[st.seq]);
        if (len > 0 && lcm_publish(r->lcm, r->ch_command, buf, (unsigned int)len) == 0) {
            r->answered++;
        }
    }
    if (st.seq >= r->done_seq) {
        r->finished = 1;
    }
}

static int replay_run(const options_t *o)
{
    replay_t *r = &g_replay;
    const char *prefix = (o->prefix != NULL) ? o->prefix : "CDPR_";
    if (replay_load(r, o->replay, prefix) != 0) {
        return EXIT_USAGE;
    }
    r->lcm = lcm_create(o->url);
    if (r->lcm == NULL) {
        fprintf(stderr, "cdpr-tracker: lcm_create failed\n");
        return EXIT_LCM;
    }
    char ch_state[80];
    snprintf(ch_state, sizeof ch_state, "%sCABIN_STATE", prefix);
    (void)lcm_subscribe(r->lcm, ch_state, replay_on_state, r);
    if (o->quiet == 0) {
        fprintf(stderr, "cdpr-tracker: replaying %ld recorded commands from %s\n", r->last_cmd + 1,
                o->replay);
    }
    double last_rx = now_s();
    long seen = 0;
    while (g_stop == 0 && r->finished == 0) {
        if (lcm_handle_timeout(r->lcm, 50) < 0) {
            break;
        }
        if (r->compared != seen) {
            seen = r->compared;
            last_rx = now_s();
        } else if (seen > 0 && now_s() - last_rx > o->idle_exit_s) {
            fprintf(stderr, "cdpr-tracker: replay: no state for %g s\n", o->idle_exit_s);
            break;
        }
    }
    lcm_destroy(r->lcm);
    printf("cdpr-tracker: replay of %s: %ld commands sent, %ld states compared, %ld differ\n",
           o->replay, r->answered, r->compared, r->mismatched);
    const int ok = r->finished != 0 && r->mismatched == 0 && r->compared == r->n;
    return ok ? 0 : EXIT_STOPPED;
}

static cdpr_plant_t g_model; /* the controller's own model: IK of the initial pose only */
static cdpr_rt_tracker_t g_tracker;
static cdpr_rt_record_t g_record;
static cdpr_sim_summary_t g_sum;

int main(int argc, char **argv)
{
    options_t o = {NULL, NULL, NULL, NULL, NULL, 1000.0, 0.0, 5.0, 1, 0};
    if (parse(argc, argv, &o) != 0) {
        return EXIT_USAGE;
    }
    if (o.replay != NULL) {
        install_stop_handler();
        return replay_run(&o);
    }
    cdpr_scenario_t sc;
    cdpr_scenario_error_t err;
    if (cdpr_scenario_load(o.scenario, &sc, &err) != 0 ||
        cdpr_host_plant_model(&g_model, &sc, &err) != CDPR_OK) {
        fprintf(stderr, "cdpr-tracker: %s\n", err.msg);
        return EXIT_USAGE;
    }
    const double duration = (o.duration_s > 0.0) ? o.duration_s : sc.duration_s;
    const cdpr_tracker_gains_t g = sc.gains;
    const double period_s = 1.0 / o.rate_hz;
    cdpr_diag_t d;
    const cdpr_status_t st = cdpr_rt_tracker_init(&g_tracker, &g_model.params, &g_model.pp.winch,
                                                  &sc.traj, &g, period_s, o.prefix, &d);
    if (st != CDPR_OK) {
        fprintf(stderr, "cdpr-tracker: controller: field '%s': %s\n", d.field, cdpr_status_str(st));
        return EXIT_USAGE;
    }
    g_record.traj = &sc.traj;
    g_record.period_s = period_s;
    if (cdpr_sim_rec_open(&g_record.rec, &sc, o.out_dir, g_model.robot.p.n_cables, duration, &g_sum,
                          &err) != 0) {
        fprintf(stderr, "cdpr-tracker: %s\n", err.msg);
        return EXIT_LCM;
    }
    g_tracker.on_step = cdpr_rt_tracker_record_step;
    g_tracker.on_step_ctx = &g_record;

    lcm_t *lcm = lcm_create(o.url);
    if (lcm == NULL) {
        fprintf(stderr,
                "cdpr-tracker: lcm_create(%s) failed (udpm on loopback needs a multicast "
                "route: ip route add 224.0.0.0/4 dev lo)\n",
                (o.url != NULL) ? o.url : "default URL");
        return EXIT_LCM;
    }
    if (cdpr_rt_tracker_attach(&g_tracker, lcm) != 0) {
        fprintf(stderr, "cdpr-tracker: cannot subscribe\n");
        lcm_destroy(lcm);
        return EXIT_LCM;
    }
    install_stop_handler();
    if (o.quiet == 0) {
        fprintf(stderr, "cdpr-tracker: %s: waiting for %sCABIN_STATE on %s\n", o.scenario,
                (o.prefix != NULL) ? o.prefix : "CDPR_", (o.url != NULL) ? o.url : "default URL");
    }
    int rc = EXIT_STOPPED;
    double last_rx = now_s();
    uint64_t states_seen = 0;
    const double wall0 = now_s();
    while (g_stop == 0) {
        const int h = lcm_handle_timeout(lcm, 50);
        if (h < 0) {
            fprintf(stderr, "cdpr-tracker: lcm_handle failed\n");
            rc = EXIT_LCM;
            break;
        }
        /* Drain what else is queued, then answer only the newest state. */
        while (h > 0 && lcm_handle_timeout(lcm, 0) > 0) {
        }
        (void)cdpr_rt_tracker_service(&g_tracker);
        const double now = now_s();
        if (g_tracker.stats.states != states_seen) {
            states_seen = g_tracker.stats.states;
            last_rx = now;
        }
        if (g_record.periods > 0 && g_record.last_t_s >= duration - 0.5 * period_s) {
            rc = 0;
            break;
        }
        if (states_seen > 0 && now - last_rx > o.idle_exit_s) {
            fprintf(stderr, "cdpr-tracker: no state for %g s: stopping\n", o.idle_exit_s);
            break;
        }
    }
    cdpr_rt_tracker_detach(&g_tracker);
    lcm_destroy(lcm);
    if (cdpr_sim_rec_close(&g_record.rec) != 0) {
        fprintf(stderr, "cdpr-tracker: %s/timeseries.csv: write error\n", o.out_dir);
        rc = EXIT_LCM;
    }
    g_sum.max_payout_m_per_s = g_record.max_payout_m_per_s;
    g_sum.ik_failures = g_tracker.tracker.ik_failures;
    g_sum.wall_time_s = now_s() - wall0;
    g_sum.status =
        (rc == 0) ? ((g_sum.ik_failures > 0) ? CDPR_SIM_WARNINGS : CDPR_SIM_OK) : CDPR_SIM_FAILED;
    const cdpr_rt_tracker_stats_t *s = &g_tracker.stats;
    snprintf(g_sum.message, sizeof g_sum.message,
             "over LCM: %llu states, %llu commands, %llu superseded, %llu clamped",
             (unsigned long long)s->states, (unsigned long long)s->answered,
             (unsigned long long)s->superseded, (unsigned long long)g_tracker.clamped);
    if (o.out_dir != NULL) {
        char path[1100];
        snprintf(path, sizeof path, "%s/summary.json", o.out_dir);
        if (cdpr_sim_write_summary(path, &sc, &g_sum) != 0) {
            fprintf(stderr, "cdpr-tracker: %s: cannot write\n", path);
            rc = EXIT_LCM;
        }
        if (o.plot != 0) {
            const char *kind = (sc.traj.type == CDPR_TRAJ_CIRCLE)
                                   ? "circle"
                                   : ((sc.traj.type == CDPR_TRAJ_LINE) ? "line" : "hold");
            (void)cdpr_sim_plot("cdpr-tracker", CDPR_SOURCE_DIR "/scripts/plot_sim.gp", o.out_dir,
                                kind, (sc.description[0] != '\0') ? sc.description : o.scenario);
        }
    }
    if (o.quiet == 0) {
        printf("cdpr-tracker: %s\n", g_sum.message);
        printf("  tracking error  rms %.4g m, max %.4g m, final %.4g m (initial %.4g m); "
               "attitude rms %.1f mrad, max %.1f mrad\n",
               g_sum.rms_error_m, g_sum.max_error_m, g_sum.final_error_m, g_sum.initial_error_m,
               1e3 * g_sum.rms_error_rad, 1e3 * g_sum.max_error_rad);
        printf("  tensions        %.4g .. %.4g N;  payout |u| <= %.3g m/s; IK failures %lu\n",
               g_sum.min_tension_N, g_sum.max_tension_N, g_sum.max_payout_m_per_s,
               g_sum.ik_failures);
        printf("  segments        %d..%d per cable; decode errors %llu, refused pairs %llu\n",
               g_sum.nodes_min, g_sum.nodes_max, (unsigned long long)s->decode_errors,
               (unsigned long long)s->bad_measurement);
        if (o.out_dir != NULL) {
            printf("  outputs         %s/timeseries.csv, %s/summary.json, figures\n", o.out_dir,
                   o.out_dir);
        }
    }
    return rc;
}
