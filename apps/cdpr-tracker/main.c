/* SPDX-License-Identifier: BSD-3-Clause */
/// @file main.c
/// cdpr-tracker: the example external tracking controller. A separate process that speaks only
/// LCM: it subscribes to the plant's cabin state and cable tensions, follows the scenario's
/// trajectory with the sag-aware IK feed-forward plus feedback (tracker.h) and publishes winch
/// rate commands answering each state (docs/realtime.md). With --out it writes what it saw in
/// cdpr-sim's format (timeseries.csv, summary.json, figures).
///
/// The control period and run length are the scenario's (run.period_s, run.duration_s);
/// --rate and --duration override them (and --max-trials, --max-attempts, which only the
/// plant uses: pass cdpr-rt's overrides so both read the same scenario), each with a note on
/// stderr when it changes the file's value.
///
/// Exit codes (the apps' one table, app_status.h): 0 finished (answered the state at the end
/// of the run), 1 stopped by a signal (SIGINT/SIGTERM/SIGHUP, also while waiting for the first
/// state: summary.json "interrupted", whole rows) or by silence (no state for --idle-exit
/// seconds: "failed"; 100 states in a row refused or a plant at another rate: "failed"), 2 bad
/// command line or scenario, 3 LCM failure or output error (the file and strerror on stderr;
/// also: the scenario file or the --replay log cannot be read), 5 a second plant on the
/// channels, or not in control (the plant applied another controller's commands in more than
/// 1 % of the periods after the first command: "failed"). States are checked before use
/// (tracker_node.h, "Trust"); the refusals are counted and printed on stderr.
#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdint.h>
#include <getopt.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <lcm/lcm.h>

#include "app_cli.h"
#include "app_run.h"
#include "app_status.h"
#include "cdpr/host/correction.h"
#include "cdpr/host/cli.h"
#include "cdpr/host/clock.h"
#include "cdpr/host/plant.h"
#include "cdpr/host/scenario.h"
#include "cdpr/rt/lcmlog.h"
#include "cdpr/rt/plant_node.h"
#include "cdpr/rt/tracker_node.h"

typedef struct {
    const char *scenario;
    const char *url;
    const char *prefix;
    const char *out_dir;
    const char *replay;
    cdpr_scenario_overrides_t ov;
    double idle_exit_s;
    int plot;
    int quiet;
    int check_design; /* --check-design */
} options_t;

static void usage(FILE *f)
{
    fprintf(
        f, "usage: cdpr-tracker SCENARIO [options]\n"
           "Example tracking controller over LCM: answers every <prefix>CABIN_STATE (+ the\n"
           "CABLE_TENSIONS of the same period) with a <prefix>WINCH_COMMAND following the\n"
           "scenario's trajectory (sag-aware IK feed-forward + feedback; docs/realtime.md).\n\n"
           "  --rate HZ        control rate; must equal cdpr-rt's (default: 1 / the scenario's\n"
           "                   run.period_s)\n"
           "  --duration S     run length, a whole number of periods; exits after answering\n"
           "                   the state at S (default: the scenario's run.duration_s)\n"
           "  --max-trials N   --max-attempts N  --integrator NAME: the plant's (cdpr-rt's); only\n"
           "                   checked here, so both processes can take the same overrides\n"
           "  --idle-exit S    exit when no state came for S seconds after the first (default 5)\n"
           "  --lcm-url URL    LCM provider (default: liblcm's)\n"
           "  --prefix P       channel prefix (default CDPR_)\n"
           "  --out DIR        write DIR/timeseries.csv, summary.json and figures\n"
           "  --replay LOG     instead of computing commands, answer each state k with the\n"
           "                   command recorded for k in the lcm-logger LOG of a lockstep run and\n"
           "                   compare every state with the recorded one (HIL regression: run\n"
           "                   cdpr-rt --lockstep with the same scenario, rate and trials); exit\n"
           "                   0 when every recorded state was reproduced bit for bit\n"
           "  --check-design   first check the controller's feedback and learning on the\n"
           "                   linearised loop (seconds; exit 2 when refused; docs/scenarios.md)\n"
           "  --no-plot        no figures\n"
           "  --quiet          no summary on stdout\n"
           "  --help           this text\n"
           "  --version        version and git description\n\n"
           "exit codes: 0 finished, 1 stopped (signal, silence, 100 states in a row refused, a\n"
           "            plant at another rate) or a replayed state differs, 2 bad command line\n"
           "            or scenario, 3 LCM or output failure, unreadable scenario or log, 5 a\n"
           "            second plant, or not in control (another controller's commands applied\n"
           "            in more than 1 %% of the periods)\n"
           "            SIGINT/SIGTERM/SIGHUP: whole rows, summary.json \"interrupted\", exit 1\n");
}

/* The options of cdpr-tracker (cdpr_app_option_fn). */
static int take(int c, const char *arg, void *ctx)
{
    options_t *o = ctx;
    const int ov = cdpr_app_run_option("cdpr-tracker", c, arg, &o->ov, &o->check_design, &o->quiet);
    if (ov != 1) {
        return ov;
    }
    if (c == 'i') {
        return (cdpr_cli_number("cdpr-tracker", "idle-exit", arg, 0.01, 1e6, &o->idle_exit_s) ==
                CDPR_OK)
                   ? 0
                   : -1;
    }
    const cdpr_app_store_t stores[] = {
        {.code = 'u', .text = &o->url},     {.code = 'p', .text = &o->prefix},
        {.code = 'o', .text = &o->out_dir}, {.code = 'n', .flag = &o->plot, .value = 0},
        {.code = 'R', .text = &o->replay},
    };
    return cdpr_app_store(stores, sizeof stores / sizeof stores[0], c, arg);
}

static int parse(int argc, char **argv, options_t *o)
{
    static const struct option longopts[] = {CDPR_APP_RUN_OPTIONS,
                                             {"idle-exit", required_argument, NULL, 'i'},
                                             CDPR_APP_LCM_OPTIONS,
                                             {"out", required_argument, NULL, 'o'},
                                             {"no-plot", no_argument, NULL, 'n'},
                                             {"replay", required_argument, NULL, 'R'},

                                             CDPR_APP_STD_OPTIONS_END};
    if (cdpr_app_parse("cdpr-tracker", argc, argv, longopts, usage, take, o) != 0 ||
        cdpr_app_scenario_operand("cdpr-tracker", argc, argv, &o->scenario) != CDPR_OK) {
        return -1;
    }
    return 0;
}

/* ------------------------------------------------------------------------ replay */

typedef struct {
    cdpr_lcm_wire_command_t *cmd; /* by state_seq */
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
static const volatile int *g_stop; /* set by SIGINT/SIGTERM (cdpr_app_stop_on_signals) */

typedef struct {
    const char *ch_state;
    const char *ch_command;
} replay_channels_t;

static int replay_want(const char *channel, void *ctx)
{
    const replay_channels_t *c = ctx;
    return (strcmp(channel, c->ch_state) == 0 || strcmp(channel, c->ch_command) == 0) ? 1 : 0;
}

/* Read the recorded commands and states of a lockstep run, validated first (cdpr/rt/lcmlog.h:
 * every event checked against the file before it is read; a cut or damaged log is an error
 * naming the event); every event of our channels must decode; state seqs number the states
 * 0..n-1, so the arrays are bounded by the log's size. CDPR_OK, CDPR_E_IO (cannot open, out of
 * memory) or CDPR_E_PARSE (a damaged log, no events of ours, a seq outside the states). */
static cdpr_status_t replay_load(replay_t *r, const char *path, const char *prefix)
{
    char ch_state[80];
    snprintf(ch_state, sizeof ch_state, "%sCABIN_STATE", prefix);
    snprintf(r->ch_command, sizeof r->ch_command, "%sWINCH_COMMAND", prefix);
    replay_channels_t want = {ch_state, r->ch_command};
    static cdpr_lcmlog_t log; /* 66 kB of buffers */
    long n_states = 0;
    for (int pass = 0; pass < 2; ++pass) {
        char msg[1024];
        const cdpr_status_t os = cdpr_lcmlog_open(&log, path, msg, sizeof msg);
        if (os != CDPR_OK) {
            fprintf(stderr, "cdpr-tracker: --replay %s\n", msg);
            return os;
        }
        int rc;
        while ((rc = cdpr_lcmlog_next(&log, replay_want, &want, msg, sizeof msg)) == 1) {
            if (log.data_len < 0) {
                continue;
            }
            const char *bad = NULL;
            if (strcmp(log.channel, r->ch_command) == 0) {
                cdpr_lcm_wire_command_t c;
                cdpr_lcm_wire_command_init(&c);
                if (cdpr_lcm_wire_command_decode(&c, log.data, log.data_len) != CDPR_LCM_WIRE_OK) {
                    bad = "does not decode as a winch_command_t of this build's cable capacity";
                } else if (c.msg.state_seq < 0 || c.msg.state_seq >= (int64_t)LONG_MAX) {
                    bad = "state_seq out of range";
                } else {
                    const long seq = (long)c.msg.state_seq;
                    if (pass == 1 && seq < r->n && r->have_cmd[seq] == 0) {
                        cdpr_lcm_wire_command_copy(&r->cmd[seq], &c);
                        r->have_cmd[seq] = 1;
                        r->last_cmd = (seq > r->last_cmd) ? seq : r->last_cmd;
                    }
                }
            } else {
                cdpr_cabin_state_t st;
                if (cdpr_cabin_state_t_decode(log.data, 0, log.data_len, &st) != log.data_len) {
                    bad = "does not decode as a cabin_state_t";
                } else if (st.seq < 0 || st.seq >= (int64_t)LONG_MAX) {
                    bad = "seq out of range";
                } else if (pass == 0) {
                    n_states++;
                    r->n = ((long)st.seq + 1 > r->n) ? (long)st.seq + 1 : r->n;
                } else if (r->have_state[st.seq] == 0) {
                    r->state[st.seq] = st;
                    r->have_state[st.seq] = 1;
                }
            }
            if (bad != NULL) {
                fprintf(stderr, "cdpr-tracker: --replay %s: event %lld on %s: %s\n", path,
                        log.index, log.channel, bad);
                cdpr_lcmlog_close(&log);
                return CDPR_E_PARSE;
            }
        }
        cdpr_lcmlog_close(&log);
        if (rc < 0) {
            fprintf(stderr, "cdpr-tracker: --replay %s\n", msg);
            return CDPR_E_PARSE;
        }
        if (pass == 0) {
            if (r->n == 0) {
                fprintf(stderr, "cdpr-tracker: --replay %s: no %s / %s events\n", path, ch_state,
                        r->ch_command);
                return CDPR_E_PARSE;
            }
            /* A state k needs its own event: seqs beyond the events are not a recording. */
            if (r->n > n_states) {
                fprintf(stderr,
                        "cdpr-tracker: --replay %s: state seq %ld, but the log holds %ld state "
                        "events (a recording numbers its states 0, 1, 2, ...)\n",
                        path, r->n - 1, n_states);
                return CDPR_E_PARSE;
            }
            r->cmd = calloc((size_t)r->n, sizeof *r->cmd);
            r->have_cmd = calloc((size_t)r->n, 1);
            r->state = calloc((size_t)r->n, sizeof *r->state);
            r->have_state = calloc((size_t)r->n, 1);
            if (r->cmd == NULL || r->have_cmd == NULL || r->state == NULL ||
                r->have_state == NULL) {
                fprintf(stderr, "cdpr-tracker: out of memory\n");
                return CDPR_E_IO;
            }
            r->last_cmd = -1;
        }
    }
    for (long k = 0; k < r->n; ++k) {
        if (r->have_state[k] == 0) {
            fprintf(stderr, "cdpr-tracker: --replay %s: state %ld is missing from the log\n", path,
                    k);
            return CDPR_E_PARSE;
        }
    }
    r->done_seq = r->n - 1; /* the last recorded state */
    return CDPR_OK;
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
        unsigned char buf[64 + 8 * CDPR_MAX_CABLES];
        /* The fresh plant is a new plant session: answer it, with the recorded values. */
        cdpr_lcm_wire_command_t c;
        cdpr_lcm_wire_command_init(&c);
        cdpr_lcm_wire_command_copy(&c, &r->cmd[st.seq]);
        c.msg.plant_session = st.plant_session;
        const int len = cdpr_lcm_wire_command_encode(&c, buf, (int)sizeof buf);
        if (len > 0 && lcm_publish(r->lcm, r->ch_command, buf, (unsigned int)len) == 0) {
            r->answered++;
        }
    }
    if (st.seq >= r->done_seq) {
        r->finished = 1;
    }
}

/* Replay: CDPR_OK when every recorded state was reproduced bit for bit, CDPR_E_INTERRUPTED
 * after a signal, CDPR_E_MISMATCH when not (silence, a state that differs), or the error that
 * kept it from running. */
static cdpr_status_t replay_run(const options_t *o)
{
    replay_t *r = &g_replay;
    const char *prefix = (o->prefix != NULL) ? o->prefix : "CDPR_";
    const cdpr_status_t ls = replay_load(r, o->replay, prefix);
    if (ls != CDPR_OK) {
        return ls;
    }
    r->lcm = lcm_create(o->url);
    if (r->lcm == NULL) {
        fprintf(stderr, "cdpr-tracker: lcm_create failed\n");
        return CDPR_E_IO;
    }
    char ch_state[80];
    snprintf(ch_state, sizeof ch_state, "%sCABIN_STATE", prefix);
    (void)lcm_subscribe(r->lcm, ch_state, replay_on_state, r);
    if (o->quiet == 0) {
        fprintf(stderr, "cdpr-tracker: replaying %ld recorded commands from %s\n", r->last_cmd + 1,
                o->replay);
    }
    double last_rx = cdpr_clock_now_s();
    long seen = 0;
    while (*g_stop == 0 && r->finished == 0) {
        if (lcm_handle_timeout(r->lcm, 50) < 0) {
            break;
        }
        if (r->compared != seen) {
            seen = r->compared;
            last_rx = cdpr_clock_now_s();
        } else if (seen > 0 && cdpr_clock_now_s() - last_rx > o->idle_exit_s) {
            fprintf(stderr, "cdpr-tracker: replay: no state for %g s\n", o->idle_exit_s);
            break;
        }
    }
    lcm_destroy(r->lcm);
    printf("cdpr-tracker: replay of %s: %ld commands sent, %ld states compared, %ld differ\n",
           o->replay, r->answered, r->compared, r->mismatched);
    const int ok = r->finished != 0 && r->mismatched == 0 && r->compared == r->n;
    if (ok) {
        return CDPR_OK;
    }
    return (*g_stop != 0) ? CDPR_E_INTERRUPTED : CDPR_E_MISMATCH;
}

static cdpr_plant_t g_model;             /* the scenario's robot: IK of the initial pose only */
static cdpr_robot_params_t g_ctl_params; /* the controller's model (controller.model) */
static cdpr_host_correction_t g_corr;    /* controller.precompensation (correction.h) */
static cdpr_rt_tracker_t g_tracker;
static cdpr_rt_tracker_record_t g_record;
static cdpr_summary_t g_sum;
static int g_silence;        /* serve stopped because no state came for --idle-exit */
static int g_refused;        /* serve stopped: CDPR_RT_MAX_REFUSED_IN_ROW states refused in a row */
static int g_not_in_control; /* the plant applied another controller's commands too often */

/* Session events of the node (docs/realtime.md, "Sessions"): one line each on stderr. */
static void on_plant_restart(int64_t old_session, int64_t new_session, void *ctx)
{
    (void)ctx;
    fprintf(stderr,
            "cdpr-tracker: plant restarted (session %lld -> %lld): following the new plant from "
            "t = 0\n",
            (long long)old_session, (long long)new_session);
}

static void on_other_plant(int64_t followed, int64_t other, void *ctx)
{
    (void)ctx;
    fprintf(stderr,
            "cdpr-tracker: warning: another plant (session %lld) publishes on the channels of "
            "plant %lld: its states are ignored; one plant per channel prefix\n",
            (long long)other, (long long)followed);
}

static void on_in_control(int64_t ours, int64_t state_seq, void *ctx)
{
    (void)ctx;
    fprintf(stderr,
            "cdpr-tracker: in control: the plant applied our command (session %lld) "
            "in the step to state %lld\n",
            (long long)ours, (long long)state_seq);
}

static void on_other_controller(int64_t ours, int64_t other, void *ctx)
{
    (void)ctx;
    fprintf(stderr,
            "cdpr-tracker: warning: the plant applied the commands of another controller "
            "(session %lld), not ours (%lld): this controller is not in control\n",
            (long long)other, (long long)ours);
}

/* Warnings the first time states are refused or arrive at another rate. */
static void warn_once(void)
{
    static uint64_t refused_seen;
    static int rate_warned;
    const cdpr_rt_tracker_stats_t *s = &g_tracker.stats;
    const uint64_t refused =
        s->refused_seq + s->refused_time + s->refused_implausible + s->bad_measurement;
    if (refused > 0 && refused_seen == 0) {
        fprintf(stderr, "cdpr-tracker: warning: a state was refused: %s\n", g_tracker.last_refusal);
    }
    refused_seen = refused;
    if (s->rate_mismatch > 0 && rate_warned == 0) {
        rate_warned = 1;
        fprintf(stderr,
                "cdpr-tracker: warning: the plant's states do not advance by one control period "
                "(%g s): plant and controller run at different rates\n",
                g_tracker.period_s);
    }
}

/* The scenario (with the overrides), the controller's model, the node and its recorder. */
static cdpr_status_t setup(const options_t *o, cdpr_scenario_t *sc)
{
    cdpr_status_t st = cdpr_app_scenario("cdpr-tracker", o->scenario, &o->ov, sc);
    if (st != CDPR_OK) {
        return st;
    }
    st = cdpr_app_design_gate("cdpr-tracker", o->scenario, sc, &o->ov, o->check_design, o->quiet);
    if (st != CDPR_OK) {
        return st;
    }
    cdpr_scenario_error_t err;
    st = cdpr_host_plant_model(&g_model, sc, &err);
    if (st != CDPR_OK) {
        fprintf(stderr, "cdpr-tracker: %s\n", err.msg);
        return st;
    }
    st = cdpr_host_controller_params(sc, &g_ctl_params, &err);
    if (st != CDPR_OK) {
        fprintf(stderr, "cdpr-tracker: %s\n", err.msg);
        return st;
    }
    cdpr_tracker_gains_t g = sc->gains;
    g.wind_m_per_s = g_model.pp.wind_m_per_s; /* the wind feed-forward's steady wind */
    st = cdpr_correction_for_scenario(sc, &g_corr, &g.correction, &err);
    if (st != CDPR_OK) {
        fprintf(stderr, "cdpr-tracker: %s\n", err.msg);
        return st;
    }
    cdpr_diag_t d;
    st = cdpr_rt_tracker_init(&g_tracker, &g_ctl_params, g_model.pp.winch, &sc->traj, &g,
                              sc->period_s, o->prefix, &d);
    if (st != CDPR_OK) {
        fprintf(stderr, "cdpr-tracker: controller: field '%s': %s\n", d.field, cdpr_status_str(st));
        return st;
    }
    g_tracker.wind = &sc->wind; /* a wind profile for the feed-forward (sc outlives the run) */
    g_record.traj = &sc->traj;
    g_record.period_s = sc->period_s;
    /* The integrator is the plant's as the scenario configures it (cdpr-rt reads the same). */
    st = cdpr_record_open(&g_record.rec, sc, &g_model.pp, o->out_dir, g_model.robot.p.n_cables,
                          &g_sum, &err);
    if (st != CDPR_OK) {
        fprintf(stderr, "cdpr-tracker: %s\n", err.msg);
        return st;
    }
    g_tracker.on_step = cdpr_rt_tracker_record_step;
    g_tracker.on_step_ctx = &g_record;
    g_tracker.on_plant_restart = on_plant_restart;
    g_tracker.on_other_plant = on_other_plant;
    g_tracker.on_other_controller = on_other_controller;
    g_tracker.on_in_control = (o->quiet == 0) ? on_in_control : NULL;
    return CDPR_OK;
}

/* The LCM instance with the node subscribed. CDPR_OK or CDPR_E_IO. */
static cdpr_status_t open_lcm(const options_t *o, lcm_t **out)
{
    lcm_t *lcm = lcm_create(o->url);
    if (lcm == NULL) {
        fprintf(stderr,
                "cdpr-tracker: lcm_create(%s) failed (udpm on loopback needs a multicast "
                "route: ip route add 224.0.0.0/4 dev lo)\n",
                (o->url != NULL) ? o->url : "default URL");
        return CDPR_E_IO;
    }
    if (cdpr_rt_tracker_attach(&g_tracker, lcm) != CDPR_OK) {
        fprintf(stderr, "cdpr-tracker: cannot subscribe\n");
        lcm_destroy(lcm);
        return CDPR_E_IO;
    }
    *out = lcm;
    return CDPR_OK;
}

/* Answer states until the one at the end of the run (CDPR_OK), a signal or silence
 * (CDPR_E_INTERRUPTED; g_silence says which) or an LCM failure (CDPR_E_IO). */
static cdpr_status_t serve(const options_t *o, const cdpr_scenario_t *sc, lcm_t *lcm)
{
    const double duration = sc->duration_s;
    const double period_s = sc->period_s;
    double last_rx = cdpr_clock_now_s();
    uint64_t states_seen = 0;
    while (*g_stop == 0) {
        const int h = lcm_handle_timeout(lcm, 50);
        if (h < 0 && *g_stop != 0) {
            break; /* the signal interrupted the wait (EINTR): a stop, not an LCM failure */
        }
        if (h < 0 && errno == EINTR) {
            continue;
        }
        if (h < 0) {
            fprintf(stderr, "cdpr-tracker: lcm_handle failed: %s\n", strerror(errno));
            return CDPR_E_IO;
        }
        /* Drain what else is queued, then answer only the newest state. */
        while (h > 0 && lcm_handle_timeout(lcm, 0) > 0) {
        }
        (void)cdpr_rt_tracker_service(&g_tracker);
        warn_once();
        if (g_tracker.refused_in_row >= CDPR_RT_MAX_REFUSED_IN_ROW) {
            fprintf(stderr, "cdpr-tracker: %ld states in a row refused: stopping (last: %s)\n",
                    g_tracker.refused_in_row, g_tracker.last_refusal);
            g_refused = 1;
            return CDPR_E_MISMATCH;
        }
        const double now = cdpr_clock_now_s();
        if (g_tracker.stats.states != states_seen) {
            states_seen = g_tracker.stats.states;
            last_rx = now;
        }
        if (g_record.periods > 0 && g_record.last_t_s >= duration - 0.5 * period_s) {
            return CDPR_OK;
        }
        if (states_seen > 0 && now - last_rx > o->idle_exit_s) {
            fprintf(stderr, "cdpr-tracker: no state for %g s: stopping\n", o->idle_exit_s);
            g_silence = 1;
            return CDPR_E_INTERRUPTED;
        }
    }
    return CDPR_E_INTERRUPTED;
}

/* Status of the tracker's summary: the CSV's failure, the signal, silence, the run's end. */
static void finish_status(cdpr_status_t rc, int csv_failed)
{
    const cdpr_rt_tracker_stats_t *s = &g_tracker.stats;
    const char *why = "";
    if (csv_failed != 0) {
        g_sum.status = CDPR_SUMMARY_IO_ERROR;
        why = "timeseries.csv write failed; ";
    } else if (rc == CDPR_E_CONFLICT && g_not_in_control != 0) {
        g_sum.status = CDPR_SUMMARY_FAILED;
        why = "not in control: the plant applied another controller's commands; ";
    } else if (rc == CDPR_E_MISMATCH) {
        g_sum.status = CDPR_SUMMARY_FAILED;
        why = (g_refused != 0) ? "stopped: the plant's states were refused; "
                               : "the plant runs at another rate; ";
    } else if (rc == CDPR_OK) {
        g_sum.status = (g_sum.ik_failures > 0) ? CDPR_SUMMARY_WARNINGS : CDPR_SUMMARY_OK;
    } else if (rc == CDPR_E_INTERRUPTED && g_silence == 0) {
        g_sum.status = CDPR_SUMMARY_INTERRUPTED;
        why = "interrupted by a signal; ";
    } else {
        g_sum.status = CDPR_SUMMARY_FAILED;
        why = (g_silence != 0) ? "stopped: no state came; " : "";
    }
    const uint64_t refused =
        s->refused_seq + s->refused_time + s->refused_implausible + s->bad_measurement;
    snprintf(g_sum.message, sizeof g_sum.message,
             "%sover LCM: %llu states, %llu commands, %llu superseded, %llu clamped, %llu "
             "refused; applied ours %llu, none %llu, another controller's %llu",
             why, (unsigned long long)s->states, (unsigned long long)s->answered,
             (unsigned long long)s->superseded, (unsigned long long)g_tracker.clamped,
             (unsigned long long)refused, (unsigned long long)s->applied_ours,
             (unsigned long long)s->applied_none, (unsigned long long)s->applied_other);
}

/* The summary of what the controller saw (status `rc` of the run), its files (the CSV's whole
 * rows; summary.json even after a CSV failure: another file, it may fit; figures only when
 * both were written) and the block on stdout. Returns rc, or CDPR_E_IO when an output failed
 * (after printing "cdpr-tracker: FILE: why"). */
static cdpr_status_t finish(const options_t *o, const cdpr_scenario_t *sc, cdpr_status_t rc,
                            double wall0)
{
    int csv_failed = 0;
    if (cdpr_record_close(&g_record.rec) != CDPR_OK) {
        cdpr_scenario_error_t err;
        cdpr_record_io_error(&g_record.rec, &err);
        fprintf(stderr, "cdpr-tracker: %s\n", err.msg);
        csv_failed = 1;
        rc = CDPR_E_IO;
    }
    g_sum.max_payout_m_per_s = g_record.max_payout_m_per_s;
    g_sum.ik_failures = g_tracker.tracker.ik_failures;
    cdpr_record_tracker_counts(&g_tracker.tracker, &g_sum);
    g_sum.wall_time_s = cdpr_clock_now_s() - wall0;
    /* What only the plant knows is unknown here (null in summary.json); the node events are
     * the changes of the segment counts in the tensions messages (cdpr_record_node_events). */
    cdpr_record_node_events(&g_record.rec, &g_sum.node_insertions, &g_sum.node_removals, NULL);
    cdpr_summary_plant_unknown(&g_sum);
    if (g_tracker.have_plant_diag != 0) {
        /* The plant's own figures as its newest diagnostics gave them (it sends one before
         * its last state): work per period, health of the fixed mode, overruns. */
        const cdpr_diagnostics_t *d = &g_tracker.plant_diag;
        cdpr_rt_plant_figures_from_diagnostics(d, &g_sum.rt);
        g_sum.rhs_evals = (unsigned long)d->rhs_evals;
        g_sum.max_rhs_per_period = (unsigned long)d->max_rhs_per_period;
        g_sum.substep_limit_hits = (unsigned long)d->substep_limit_hits;
        g_sum.capacity_hits = (unsigned long)d->capacity_hits;
        if (d->integrator == CDPR_DIAGNOSTICS_T_INTEGRATOR_ROS34PW2_FIXED && d->substeps > 0) {
            g_sum.substeps = (int)d->substeps;
            g_sum.max_err_norm = d->max_err_norm;
            g_sum.err_above_one_periods = (unsigned long)d->err_above_one_periods;
        }
    }
    finish_status(rc, csv_failed);
    const cdpr_rt_tracker_stats_t *s = &g_tracker.stats;
    char script[1200];
    (void)cdpr_app_data_file("scripts/plot_sim.gp", script, sizeof script);
    const int plot = (o->plot != 0 && csv_failed == 0) ? 1 : 0;
    if (o->out_dir != NULL && cdpr_app_write_outputs("cdpr-tracker", sc, o->out_dir, &g_sum,
                                                     (plot != 0) ? script : NULL) != CDPR_OK) {
        rc = CDPR_E_IO;
    }
    if (o->quiet == 0) {
        cdpr_summary_print(stdout, "cdpr-tracker", &g_sum);
        const uint64_t refused =
            s->bad_measurement + s->refused_seq + s->refused_time + s->refused_implausible;
        printf("  LCM             decode errors %llu, refused pairs %llu\n",
               (unsigned long long)s->decode_errors, (unsigned long long)refused);
        cdpr_rt_tracker_print_cost(stdout, &g_tracker);
        if (o->out_dir != NULL) {
            printf("  outputs         %s/timeseries.csv, %s/summary.json, figures\n", o->out_dir,
                   o->out_dir);
        }
    }
    return rc;
}

int main(int argc, char **argv)
{
    options_t o;
    memset(&o, 0, sizeof o);
    cdpr_scenario_overrides_none(&o.ov);
    o.idle_exit_s = 5.0;
    o.plot = 1;
    if (parse(argc, argv, &o) != 0) {
        return cdpr_app_exit_code(CDPR_E_INVALID_ARG);
    }
    if (o.replay != NULL) {
        g_stop = cdpr_app_stop_on_signals();
        return cdpr_app_exit_code(replay_run(&o));
    }
    cdpr_scenario_t sc;
    cdpr_status_t st = setup(&o, &sc);
    lcm_t *lcm = NULL;
    if (st == CDPR_OK) {
        st = open_lcm(&o, &lcm);
    }
    if (st != CDPR_OK) {
        return cdpr_app_exit_code(st);
    }
    g_stop = cdpr_app_stop_on_signals();
    if (o.quiet == 0) {
        fprintf(stderr, "cdpr-tracker: %s: waiting for %sCABIN_STATE on %s (%g Hz)\n", o.scenario,
                (o.prefix != NULL) ? o.prefix : "CDPR_", (o.url != NULL) ? o.url : "default URL",
                1.0 / sc.period_s);
    }
    const double wall0 = cdpr_clock_now_s();
    st = serve(&o, &sc, lcm);
    if (st == CDPR_OK && g_tracker.stats.other_plant_states > 0) {
        st = CDPR_E_CONFLICT; /* completed, but next to another plant */
    }
    if ((st == CDPR_OK || st == CDPR_E_CONFLICT) &&
        cdpr_rt_tracker_in_control(&g_tracker, CDPR_RT_MAX_OTHER_SHARE) == 0) {
        g_not_in_control = 1;
        st = CDPR_E_CONFLICT;
    }
    if (st == CDPR_OK && g_tracker.stats.rate_mismatch > 0) {
        st = CDPR_E_MISMATCH;
    }
    cdpr_rt_tracker_print_trust(stderr, "cdpr-tracker", &g_tracker);
    cdpr_rt_tracker_detach(&g_tracker);
    lcm_destroy(lcm);
    return cdpr_app_exit_code(finish(&o, &sc, st, wall0));
}
