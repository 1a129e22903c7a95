/* SPDX-License-Identifier: BSD-3-Clause */
/// @file tracker_node.c
/// The tracking controller as an LCM node (tracker_node.h).
#include "cdpr/rt/tracker_node.h"

#include "hist.h"

#include <math.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

#include "cdpr/lcm/bridge.h"

static int all_finite(const double *v, int n)
{
    for (int i = 0; i < n; ++i) {
        if (!isfinite(v[i])) {
            return 0;
        }
    }
    return 1;
}

cdpr_status_t cdpr_rt_meas_from_msgs(const cdpr_cabin_state_t *st, const cdpr_cable_tensions_t *ten,
                                     double period_s, int n_cables, cdpr_tracker_meas_t *m)
{
    if (st->seq != ten->seq || ten->n_cables != n_cables || !(period_s > 0.0) || st->utime_us < 0) {
        return CDPR_E_INVALID_ARG;
    }
    if (all_finite(st->position_m, 3) == 0 || all_finite(st->orientation, 4) == 0 ||
        all_finite(st->velocity_m_per_s, 3) == 0 ||
        all_finite(st->angular_velocity_rad_per_s, 3) == 0 ||
        all_finite(ten->length_m, n_cables) == 0 ||
        all_finite(ten->tension_winch_N, n_cables) == 0) {
        return CDPR_E_NOT_FINITE;
    }
    /* n = round(utime 1e-6 / dt); t = n dt is the plant's own k dt. A time beyond 2^53
     * periods (a garbled message) has no such n: refused. */
    const double periods = (double)st->utime_us * 1e-6 / period_s;
    if (!(periods <= 9007199254740992.0)) {
        return CDPR_E_INVALID_ARG;
    }
    const double n = (double)llround(periods);
    m->t_s = n * period_s;
    m->cabin.p_m = cdpr_v3(st->position_m[0], st->position_m[1], st->position_m[2]);
    m->cabin.q.w = st->orientation[0];
    m->cabin.q.x = st->orientation[1];
    m->cabin.q.y = st->orientation[2];
    m->cabin.q.z = st->orientation[3];
    m->cabin.v_m_per_s =
        cdpr_v3(st->velocity_m_per_s[0], st->velocity_m_per_s[1], st->velocity_m_per_s[2]);
    m->cabin.w_rad_per_s =
        cdpr_v3(st->angular_velocity_rad_per_s[0], st->angular_velocity_rad_per_s[1],
                st->angular_velocity_rad_per_s[2]);
    for (int j = 0; j < CDPR_MAX_CABLES; ++j) {
        m->length_m[j] = (j < n_cables) ? ten->length_m[j] : 0.0;
        m->tension_winch_N[j] = (j < n_cables) ? ten->tension_winch_N[j] : 0.0;
    }
    return CDPR_OK;
}

cdpr_status_t cdpr_rt_tracker_init(cdpr_rt_tracker_t *t, const cdpr_robot_params_t *model,
                                   const cdpr_winch_params_t *winch, const cdpr_traj_t *traj,
                                   const cdpr_tracker_gains_t *g, double period_s,
                                   const char *prefix, cdpr_diag_t *diag)
{
    memset(t, 0, sizeof *t);
    const char *pre = (prefix != NULL) ? prefix : "CDPR_";
    if (strlen(pre) > 40) {
        if (diag != NULL) {
            memset(diag, 0, sizeof *diag);
            diag->status = CDPR_E_INVALID_ARG;
            diag->field = "channel_prefix";
        }
        return CDPR_E_INVALID_ARG;
    }
    snprintf(t->ch_state, sizeof t->ch_state, "%sCABIN_STATE", pre);
    snprintf(t->ch_tensions, sizeof t->ch_tensions, "%sCABLE_TENSIONS", pre);
    snprintf(t->ch_command, sizeof t->ch_command, "%sWINCH_COMMAND", pre);
    const cdpr_status_t st = cdpr_tracker_init(&t->tracker, model, traj, g, period_s, 0.0, diag);
    if (st != CDPR_OK) {
        return st;
    }
    t->model = model;
    t->traj = traj;
    t->gains = *g;
    t->controller_session = cdpr_lcm_new_session();
    t->plant_session = 0;
    t->plant_silence_s = CDPR_RT_PLANT_SILENCE_S;
    t->other_reported = -1;
    t->period_s = period_s;
    t->n_cables = model->n_cables;
    for (int j = 0; j < CDPR_MAX_CABLES; ++j) {
        t->u_max_m_per_s[j] = winch[j].u_max_m_per_s;
    }
    t->answered_state_seq = -1;
    t->cmd_seq = -1;
    return CDPR_OK;
}

/* A new plant session: the controller starts again (the new plant starts at t = 0). */
static void follow_plant(cdpr_rt_tracker_t *t, int64_t session)
{
    const int64_t old = t->plant_session;
    t->plant_session = session;
    t->other_reported = -1;
    if (old == 0) {
        return;
    }
    t->stats.plant_restarts++;
    t->answered_state_seq = -1;
    t->have_state = 0;
    t->have_ten = 0;
    t->cmd_len = 0;
    /* Same inputs as at init, which accepted them: cannot fail. */
    (void)cdpr_tracker_init(&t->tracker, t->model, t->traj, &t->gains, t->period_s, 0.0, NULL);
    if (t->on_plant_restart != NULL) {
        t->on_plant_restart(old, session, t->on_session_ctx);
    }
}

/* 1 when a message of plant session `session` is to be used: the one followed, or a new one
 * after the followed one fell silent (a restart); else counted as another plant's. */
static int from_followed_plant(cdpr_rt_tracker_t *t, int64_t session, int is_state)
{
    const int64_t now = cdpr_lcm_now_ns();
    if (session == t->plant_session) {
        if (is_state != 0) {
            t->last_state_ns = now;
        }
        return 1;
    }
    const int silent =
        t->plant_session == 0 || (double)(now - t->last_state_ns) > t->plant_silence_s * 1e9;
    if (is_state != 0 && silent != 0) {
        follow_plant(t, session);
        t->last_state_ns = now;
        return 1;
    }
    t->stats.other_plant_states++;
    if (session != t->other_reported) {
        t->other_reported = session;
        if (t->on_other_plant != NULL) {
            t->on_other_plant(t->plant_session, session, t->on_session_ctx);
        }
    }
    return 0;
}

static void on_state(const lcm_recv_buf_t *rbuf, const char *channel, void *user)
{
    (void)channel;
    cdpr_rt_tracker_t *t = user;
    cdpr_cabin_state_t msg;
    if (cdpr_cabin_state_t_decode(rbuf->data, 0, (int)rbuf->data_size, &msg) !=
        (int)rbuf->data_size) {
        t->stats.decode_errors++;
        return;
    }
    t->stats.states++;
    if (from_followed_plant(t, msg.plant_session, 1) == 0) {
        return;
    }
    if (msg.seq == t->answered_state_seq && t->cmd_len > 0) {
        /* The plant sent the state we answered again (lockstep resend): our answer was lost
         * or late; send the same command again (the plant ignores it as replayed if it had
         * it). */
        if (lcm_publish(t->lcm, t->ch_command, t->cmd_buf, (unsigned int)t->cmd_len) != 0) {
            t->stats.publish_errors++;
        }
        t->stats.resent++;
        return;
    }
    if (t->have_state != 0 && t->state.seq > t->answered_state_seq && msg.seq > t->state.seq) {
        t->stats.superseded++;
    }
    t->state = msg;
    t->have_state = 1;
}

static void on_tensions(const lcm_recv_buf_t *rbuf, const char *channel, void *user)
{
    (void)channel;
    cdpr_rt_tracker_t *t = user;
    cdpr_cable_tensions_t msg;
    if (cdpr_cable_tensions_t_decode(rbuf->data, 0, (int)rbuf->data_size, &msg) !=
        (int)rbuf->data_size) {
        t->stats.decode_errors++;
        return;
    }
    t->stats.tensions++;
    if (from_followed_plant(t, msg.plant_session, 0) == 0) {
        return;
    }
    t->ten = msg;
    t->have_ten = 1;
    if (t->answer_in_handler != 0) {
        (void)cdpr_rt_tracker_service(t);
    }
}

cdpr_status_t cdpr_rt_tracker_attach(cdpr_rt_tracker_t *t, lcm_t *lcm)
{
    t->lcm = lcm;
    t->sub_state = lcm_subscribe(lcm, t->ch_state, on_state, t);
    t->sub_tensions = lcm_subscribe(lcm, t->ch_tensions, on_tensions, t);
    if (t->sub_state == NULL || t->sub_tensions == NULL) {
        cdpr_rt_tracker_detach(t);
        return CDPR_E_IO;
    }
    return CDPR_OK;
}

void cdpr_rt_tracker_detach(cdpr_rt_tracker_t *t)
{
    if (t->lcm != NULL) {
        if (t->sub_state != NULL) {
            (void)lcm_unsubscribe(t->lcm, t->sub_state);
        }
        if (t->sub_tensions != NULL) {
            (void)lcm_unsubscribe(t->lcm, t->sub_tensions);
        }
    }
    t->sub_state = NULL;
    t->sub_tensions = NULL;
    t->lcm = NULL;
}

static int64_t now_ns(void)
{
    struct timespec ts;
    (void)clock_gettime(CLOCK_MONOTONIC, &ts);
    return (int64_t)ts.tv_sec * 1000000000 + (int64_t)ts.tv_nsec;
}

static void time_step(cdpr_rt_tracker_t *t, int64_t ns)
{
    const int64_t us = (ns > 0) ? ns / 1000 : 0;
    t->step_hist[(us < CDPR_RT_TRACKER_HIST_US) ? us : CDPR_RT_TRACKER_HIST_US]++;
    t->steps_timed++;
    if (ns > t->step_ns_max) {
        t->step_ns_max = ns;
    }
}

static int64_t step_quantile(const cdpr_rt_tracker_t *t, double q)
{
    const int bin =
        cdpr_rt_hist_quantile_bin(t->step_hist, CDPR_RT_TRACKER_HIST_US, t->steps_timed, q);
    const int64_t ns = (int64_t)bin * 1000;
    return (bin < CDPR_RT_TRACKER_HIST_US && ns < t->step_ns_max) ? ns : t->step_ns_max;
}

uint64_t cdpr_rt_tracker_step_times(const cdpr_rt_tracker_t *t, int64_t *median_ns, int64_t *p99_ns,
                                    int64_t *max_ns)
{
    *median_ns = 0;
    *p99_ns = 0;
    *max_ns = 0;
    if (t->steps_timed == 0) {
        return 0;
    }
    *median_ns = step_quantile(t, 0.5);
    *p99_ns = step_quantile(t, 0.99);
    *max_ns = t->step_ns_max;
    return t->steps_timed;
}

void cdpr_rt_tracker_print_cost(FILE *f, const cdpr_rt_tracker_t *t)
{
    int64_t med;
    int64_t p99;
    int64_t mx;
    const uint64_t n = cdpr_rt_tracker_step_times(t, &med, &p99, &mx);
    if (n > 0) {
        fprintf(f,
                "  controller step median %.0f us, p99 %.0f us, max %.0f us over %llu periods "
                "(cdpr_tracker_step: IK, feedback, learning)\n",
                1e-3 * (double)med, 1e-3 * (double)p99, 1e-3 * (double)mx, (unsigned long long)n);
    }
}

int cdpr_rt_tracker_service(cdpr_rt_tracker_t *t)
{
    if (t->have_state == 0 || t->have_ten == 0 || t->state.seq != t->ten.seq ||
        t->state.plant_session != t->ten.plant_session || t->state.seq <= t->answered_state_seq ||
        t->lcm == NULL) {
        return 0;
    }
    t->answered_state_seq = t->state.seq;
    cdpr_tracker_meas_t m;
    cdpr_tracker_cmd_t c;
    if (cdpr_rt_meas_from_msgs(&t->state, &t->ten, t->period_s, t->n_cables, &m) != CDPR_OK) {
        t->stats.bad_measurement++;
        return -1;
    }
    const int64_t t0 = now_ns();
    const cdpr_status_t st = cdpr_tracker_step(&t->tracker, &m, &c);
    time_step(t, now_ns() - t0);
    if (st != CDPR_OK) {
        t->stats.bad_measurement++;
        return -1;
    }
    t->stats.ik_failures = t->tracker.ik_failures;
    cdpr_winch_command_t cmd;
    memset(&cmd, 0, sizeof cmd);
    cmd.utime_us = t->state.utime_us;
    cmd.seq = t->cmd_seq + 1;
    cmd.state_seq = t->state.seq;
    cmd.controller_session = t->controller_session;
    cmd.plant_session = t->state.plant_session;
    cmd.mode = CDPR_WINCH_COMMAND_T_MODE_RATE;
    cmd.n_cables = (int8_t)t->n_cables;
    for (int j = 0; j < t->n_cables; ++j) {
        const double u = fmax(-t->u_max_m_per_s[j], fmin(t->u_max_m_per_s[j], c.rate_m_per_s[j]));
        if (fabs(u - c.rate_m_per_s[j]) > 0.0) {
            t->clamped++;
        }
        cmd.value[j] = u;
    }
    const int len = cdpr_winch_command_t_encode(t->cmd_buf, 0, (int)sizeof t->cmd_buf, &cmd);
    t->cmd_len = (len > 0) ? len : 0;
    if (len <= 0 || lcm_publish(t->lcm, t->ch_command, t->cmd_buf, (unsigned int)len) != 0) {
        t->stats.publish_errors++;
        return -1;
    }
    t->cmd_seq = cmd.seq;
    t->stats.answered++;
    if (t->on_step != NULL) {
        t->on_step(&m, &c, &t->state, &t->ten, t->on_step_ctx);
    }
    return 1;
}

void cdpr_rt_tracker_record_step(const cdpr_tracker_meas_t *m, const cdpr_tracker_cmd_t *c,
                                 const cdpr_cabin_state_t *st, const cdpr_cable_tensions_t *ten,
                                 void *ctx)
{
    (void)st;
    cdpr_rt_record_t *r = ctx;
    cdpr_traj_sample_t des;
    cdpr_traj_eval(r->traj, m->t_s, &des);
    int segments[CDPR_MAX_CABLES] = {0};
    const int nc = (ten->n_cables <= CDPR_MAX_CABLES) ? ten->n_cables : CDPR_MAX_CABLES;
    for (int j = 0; j < nc; ++j) {
        segments[j] = (int)ten->n_segments[j];
        r->max_payout_m_per_s = fmax(r->max_payout_m_per_s, fabs(ten->payout_m_per_s[j]));
    }
    const cdpr_sim_row_t row = {m->t_s,
                                &des,
                                m,
                                ten->tension_cabin_N,
                                ten->tension_winch_N,
                                c->l_ff_m,
                                ten->payout_m_per_s,
                                segments};
    const long k = (long)llround(m->t_s / r->period_s);
    /* The state at the end of the run gets its row, as in cdpr-sim; a CSV failure is kept in
     * the recorder (cdpr_sim_rec_close reports it) and the controller keeps controlling. */
    const int last = (m->t_s >= r->rec.duration_s - 0.5 * r->period_s) ? 1 : 0;
    (void)cdpr_sim_rec_period(&r->rec, k, last, &row);
    r->last_t_s = m->t_s;
    r->periods++;
}
