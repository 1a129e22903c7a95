/* SPDX-License-Identifier: BSD-3-Clause */
/// @file tracker_node.c
/// The tracking controller as an LCM node (tracker_node.h).
#include "cdpr/rt/tracker_node.h"

#include "hist.h"

#include <limits.h>
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

cdpr_status_t cdpr_rt_tracker_meas_from_msgs(const cdpr_cabin_state_t *st,
                                             const cdpr_cable_tensions_t *ten, double period_s,
                                             int n_cables, cdpr_tracker_meas_t *m)
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

/* The physical range of a measurement of this robot (tracker_node.h, "Trust"). */
static void set_bounds(cdpr_rt_tracker_meas_bounds_t *b, const cdpr_robot_params_t *model,
                       const cdpr_winch_params_t *winch)
{
    memset(b, 0, sizeof *b);
    double spread = 0.0;
    double longest = 0.0;
    double u_max = 0.0;
    double r_min = HUGE_VAL;
    for (int j = 0; j < model->n_cables; ++j) {
        const cdpr_robot_cable_params_t *c = &model->cables[j];
        const double ea = (double)c->cable.ea_N;
        b->t_max_N[j] = ea;
        b->t_min_N[j] = (c->cable.slack_law == CDPR_SLACK_MOORDYN) ? -ea : 0.0;
        b->l_min_m[j] = (double)winch[j].min_length_m;
        b->u_max_m_per_s[j] = (double)winch[j].u_max_m_per_s;
        b->exit_m[j][0] = (double)c->exit_point_m.x;
        b->exit_m[j][1] = (double)c->exit_point_m.y;
        b->exit_m[j][2] = (double)c->exit_point_m.z;
        b->attach_r_m[j] = (double)cdpr_v3_norm(c->attach_body_m);
        longest = fmax(longest, (double)c->length_m);
        u_max = fmax(u_max, b->u_max_m_per_s[j]);
        r_min = fmin(r_min, b->attach_r_m[j]);
        for (int i = 0; i < j; ++i) {
            spread = fmax(spread, (double)cdpr_v3_norm(
                                      cdpr_v3_sub(c->exit_point_m, model->cables[i].exit_point_m)));
        }
    }
    b->v_max_m_per_s =
        sqrt(2.0 * (double)model->g_m_per_s2 * (spread + longest)) + 2.0 * u_max + 1.0;
    b->w_max_rad_per_s = b->v_max_m_per_s / fmax(r_min, 0.1);
}

cdpr_status_t cdpr_rt_tracker_init(cdpr_rt_tracker_t *t, const cdpr_robot_params_t *model,
                                   const cdpr_winch_params_t *winch, const cdpr_traj_t *traj,
                                   const cdpr_tracker_gains_t *g, double period_s,
                                   const char *prefix, cdpr_diag_t *diag)
{
    memset(t, 0, sizeof *t);
    cdpr_lcm_wire_tensions_init(&t->ten);
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
    snprintf(t->ch_diag, sizeof t->ch_diag, "%sDIAGNOSTICS", pre);
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
    set_bounds(&t->bounds, model, winch);
    t->other_controller = -1;
    t->last_other_session = 0;
    t->last_other_seq = -1;
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
    t->have_accepted = 0;
    t->have_cand = 0;
    t->answered_state_seq = -1;
    t->have_state = 0;
    t->have_ten = 0;
    t->cmd_len = 0;
    t->have_plant_diag = 0;
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
    if (t->plant_session == 0 && is_state == 0) {
        return 0; /* tensions before the first state: no plant followed yet, none other */
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
    cdpr_lcm_wire_tensions_t msg;
    /* Into fixed storage: no allocation; a plant with more cables than this build holds is
     * counted here (its count never matches ours). */
    cdpr_lcm_wire_tensions_init(&msg);
    if (rbuf->data_size > (uint32_t)INT_MAX ||
        cdpr_lcm_wire_tensions_decode(&msg, rbuf->data, (int)rbuf->data_size) != CDPR_LCM_WIRE_OK) {
        t->stats.decode_errors++;
        return;
    }
    t->stats.tensions++;
    if (from_followed_plant(t, msg.msg.plant_session, 0) == 0) {
        return;
    }
    cdpr_lcm_wire_tensions_copy(&t->ten, &msg);
    t->have_ten = 1;
    if (t->answer_in_handler != 0) {
        (void)cdpr_rt_tracker_service(t);
    }
}

/* The plant's diagnostics: kept for the summary (never used for control). Another session's,
 * or one older than the one kept, is ignored; one that does not decode exactly is counted. */
static void on_diagnostics(const lcm_recv_buf_t *rbuf, const char *channel, void *user)
{
    (void)channel;
    cdpr_rt_tracker_t *t = user;
    cdpr_diagnostics_t msg;
    if (cdpr_diagnostics_t_decode(rbuf->data, 0, (int)rbuf->data_size, &msg) !=
        (int)rbuf->data_size) {
        t->stats.decode_errors++;
        return;
    }
    /* Within the sequence already trusted: at most one state ahead of the newest accepted pair
     * (the plant sends it just before its state), so a forged seq cannot pin a stale copy. */
    if (t->plant_session == 0 || msg.plant_session != t->plant_session || t->have_accepted == 0 ||
        msg.seq < 0 || msg.seq > t->acc_seq + 1 ||
        (t->have_plant_diag != 0 && msg.seq < t->plant_diag.seq)) {
        return;
    }
    t->plant_diag = msg;
    t->have_plant_diag = 1;
    t->stats.diagnostics++;
}

cdpr_status_t cdpr_rt_tracker_attach(cdpr_rt_tracker_t *t, lcm_t *lcm)
{
    t->lcm = lcm;
    t->sub_state = lcm_subscribe(lcm, t->ch_state, on_state, t);
    t->sub_tensions = lcm_subscribe(lcm, t->ch_tensions, on_tensions, t);
    t->sub_diag = lcm_subscribe(lcm, t->ch_diag, on_diagnostics, t);
    if (t->sub_state == NULL || t->sub_tensions == NULL || t->sub_diag == NULL) {
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
        if (t->sub_diag != NULL) {
            (void)lcm_unsubscribe(t->lcm, t->sub_diag);
        }
    }
    t->sub_state = NULL;
    t->sub_tensions = NULL;
    t->sub_diag = NULL;
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

static double norm3(const double *v)
{
    return sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
}

/* The values of one pair within the robot's physical range (no history). */
static cdpr_status_t check_values(const cdpr_rt_tracker_meas_bounds_t *b,
                                  const cdpr_cabin_state_t *st, const cdpr_cable_tensions_t *ten,
                                  int n, char *why, size_t cap)
{
    const double *q = st->orientation;
    const double qn = q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3];
    if (!(fabs(qn - 1.0) <= 1e-6)) {
        snprintf(why, cap, "orientation: |q|^2 = %.9g, not a unit quaternion", qn);
        return CDPR_E_INFEASIBLE;
    }
    const double v = norm3(st->velocity_m_per_s);
    if (!(v <= b->v_max_m_per_s)) {
        snprintf(why, cap, "cabin speed %.4g m/s above the robot's %.4g m/s", v, b->v_max_m_per_s);
        return CDPR_E_INFEASIBLE;
    }
    const double w = norm3(st->angular_velocity_rad_per_s);
    if (!(w <= b->w_max_rad_per_s)) {
        snprintf(why, cap, "cabin angular speed %.4g rad/s above the robot's %.4g rad/s", w,
                 b->w_max_rad_per_s);
        return CDPR_E_INFEASIBLE;
    }
    for (int j = 0; j < n; ++j) {
        const double tw = ten->tension_winch_N[j];
        const double tc = ten->tension_cabin_N[j];
        if (!(tw >= b->t_min_N[j] && tw <= b->t_max_N[j] && tc >= b->t_min_N[j] &&
              tc <= b->t_max_N[j])) {
            snprintf(why, cap,
                     "cable %d: tension %.4g N (winch) / %.4g N (cabin) outside [%.4g, %.4g] N",
                     j + 1, tw, tc, b->t_min_N[j], b->t_max_N[j]);
            return CDPR_E_INFEASIBLE;
        }
        const double l = ten->length_m[j];
        if (!(l >= b->l_min_m[j] * (1.0 - 1e-9))) {
            snprintf(why, cap, "cable %d: length %.6g m below the winch's minimum %.6g m", j + 1, l,
                     b->l_min_m[j]);
            return CDPR_E_INFEASIBLE;
        }
        const double d[3] = {st->position_m[0] - b->exit_m[j][0],
                             st->position_m[1] - b->exit_m[j][1],
                             st->position_m[2] - b->exit_m[j][2]};
        const double reach = 2.0 * l + b->attach_r_m[j];
        if (!(norm3(d) <= reach)) {
            snprintf(why, cap,
                     "cabin %.4g m from exit point %d, beyond its cable's reach %.4g m (twice "
                     "the length %.4g m)",
                     norm3(d), j + 1, reach, l);
            return CDPR_E_INFEASIBLE;
        }
    }
    return CDPR_OK;
}

cdpr_status_t cdpr_rt_tracker_check_pair(const cdpr_rt_tracker_t *t, const cdpr_cabin_state_t *st,
                                         const cdpr_cable_tensions_t *ten, char *why, size_t cap)
{
    why[0] = '\0';
    cdpr_tracker_meas_t m;
    const cdpr_status_t ms = cdpr_rt_tracker_meas_from_msgs(st, ten, t->period_s, t->n_cables, &m);
    if (ms != CDPR_OK) {
        snprintf(why, cap, "%s",
                 (ms == CDPR_E_NOT_FINITE) ? "a value is not finite"
                                           : "the pair does not fit (seq, cable count or time)");
        return ms;
    }
    if (t->have_accepted != 0) {
        const int64_t dseq = st->seq - t->acc_seq;
        if (dseq <= 0 || dseq > CDPR_RT_STATE_SEQ_WINDOW) {
            const int64_t hi = t->acc_seq + CDPR_RT_STATE_SEQ_WINDOW;
            snprintf(why, cap, "seq %lld outside (%lld, %lld] (the last accepted + %d)",
                     (long long)st->seq, (long long)t->acc_seq, (long long)hi,
                     CDPR_RT_STATE_SEQ_WINDOW);
            return CDPR_E_MISMATCH;
        }
        const int64_t dt = st->utime_us - t->acc_utime_us;
        const double ahead = (double)dseq * t->period_s * 1e6 + 1.0;
        if (dt < 0 || (double)dt > ahead) {
            snprintf(why, cap,
                     "time %lld us: %lld us after the last accepted state, %lld periods on "
                     "(0 to %.0f us allowed)",
                     (long long)st->utime_us, (long long)dt, (long long)dseq, ahead);
            return CDPR_E_OUT_OF_RANGE;
        }
        for (int j = 0; j < t->n_cables; ++j) {
            const double dl = fabs(ten->length_m[j] - t->acc_length_m[j]);
            const double room = t->bounds.u_max_m_per_s[j] * (double)dt * 1e-6 +
                                1e-9 * (1.0 + fabs(t->acc_length_m[j]));
            if (!(dl <= room)) {
                snprintf(why, cap,
                         "cable %d: length changed by %.6g m in %.6g s, more than the winch's "
                         "%.4g m/s allow",
                         j + 1, dl, (double)dt * 1e-6, t->bounds.u_max_m_per_s[j]);
                return CDPR_E_INFEASIBLE;
            }
        }
    }
    return check_values(&t->bounds, st, ten, t->n_cables, why, cap);
}

/* Whose command the plant applied in the step that led to an accepted state. */
static void count_control(cdpr_rt_tracker_t *t, const cdpr_cabin_state_t *st)
{
    /* Another session's command applied again (same session and seq as in the state before) is
     * a stopped controller's last command, applied until the plant's watchdog holds, not a
     * controller competing with us: a loaded plant may still apply it after ours was sent. */
    const int repeat =
        (st->controller_session == t->last_other_session && st->command_seq == t->last_other_seq)
            ? 1
            : 0;
    if (st->controller_session != t->controller_session && st->controller_session != 0) {
        t->last_other_session = st->controller_session;
        t->last_other_seq = st->command_seq;
    }
    if (t->cmd_seq < 0) {
        return; /* before our first command nothing of ours could be applied */
    }
    if (st->controller_session == t->controller_session) {
        t->stats.applied_ours++;
        if (t->stats.applied_ours == 1 && t->on_in_control != NULL) {
            t->on_in_control(t->controller_session, st->seq, t->on_session_ctx);
        }
    } else if (st->controller_session == 0 || repeat != 0) {
        t->stats.applied_none++;
    } else {
        t->stats.applied_other++;
        if (st->controller_session != t->other_controller) {
            t->other_controller = st->controller_session;
            if (t->on_other_controller != NULL) {
                t->on_other_controller(t->controller_session, st->controller_session,
                                       t->on_session_ctx);
            }
        }
    }
}

/* A pair refused: counted, remembered as a candidate anchor; two refused pairs in a row
 * that agree (seq within the window, time within its periods) re-anchor the window. Returns
 * 1 when it re-anchored (the pair is then accepted). */
static int refuse(cdpr_rt_tracker_t *t, cdpr_status_t why_st, const char *why)
{
    const cdpr_cabin_state_t *st = &t->state;
    uint64_t *count = (why_st == CDPR_E_MISMATCH)       ? &t->stats.refused_seq
                      : (why_st == CDPR_E_OUT_OF_RANGE) ? &t->stats.refused_time
                                                        : &t->stats.refused_implausible;
    if (why_st == CDPR_E_MISMATCH || why_st == CDPR_E_OUT_OF_RANGE) {
        const int64_t dseq = st->seq - t->cand_seq;
        const int64_t dt = st->utime_us - t->cand_utime_us;
        /* Backwards only while the anchor has no accepted successor: a forged first state;
         * never two replayed old pairs against an established stream. */
        const int backwards = (st->seq < t->acc_seq) ? 1 : 0;
        if (t->have_cand != 0 && dseq > 0 && dseq <= CDPR_RT_STATE_SEQ_WINDOW && dt >= 0 &&
            (double)dt <= (double)dseq * t->period_s * 1e6 + 1.0 &&
            (backwards == 0 || t->acc_run < 2)) {
            t->stats.resyncs++;
            t->have_cand = 0;
            if (st->utime_us < t->acc_utime_us) {
                /* The old anchor was ahead of the plant (a forged first state): the
                 * controller's filters saw its time; start them again (same inputs as at
                 * init, which accepted them: cannot fail). */
                (void)cdpr_tracker_init(&t->tracker, t->model, t->traj, &t->gains, t->period_s, 0.0,
                                        NULL);
            }
            return 1;
        }
        t->have_cand = 1;
        t->cand_seq = st->seq;
        t->cand_utime_us = st->utime_us;
    }
    (*count)++;
    snprintf(t->last_refusal, sizeof t->last_refusal, "%s", why);
    return 0;
}

int cdpr_rt_tracker_service(cdpr_rt_tracker_t *t)
{
    /* A pair is used once: have_state is cleared when it is answered or refused (its order
     * against the pairs before it is the sequence window's to judge). */
    if (t->have_state == 0 || t->have_ten == 0 || t->state.seq != t->ten.msg.seq ||
        t->state.plant_session != t->ten.msg.plant_session || t->lcm == NULL) {
        return 0;
    }
    char why[sizeof t->last_refusal];
    const cdpr_status_t cs = cdpr_rt_tracker_check_pair(t, &t->state, &t->ten.msg, why, sizeof why);
    if (cs != CDPR_OK) {
        t->refused_in_row++;
    }
    if (cs == CDPR_E_NOT_FINITE || cs == CDPR_E_INVALID_ARG) {
        t->stats.bad_measurement++;
        t->have_state = 0; /* this pair only: the next one is checked afresh */
        snprintf(t->last_refusal, sizeof t->last_refusal, "%s", why);
        return -1;
    }
    if (cs != CDPR_OK) {
        /* A re-anchor accepts the pair if its values are plausible. */
        if (refuse(t, cs, why) == 0 || check_values(&t->bounds, &t->state, &t->ten.msg, t->n_cables,
                                                    why, sizeof why) != CDPR_OK) {
            t->have_state = 0;
            return -1;
        }
    }
    /* Accepted: a one-period step of another length than T is a plant at another rate. */
    if (t->have_accepted != 0 && t->state.seq - t->acc_seq == 1 &&
        (t->state.flags & CDPR_CABIN_STATE_T_FLAG_STEP_FAILED) == 0 &&
        fabs((double)(t->state.utime_us - t->acc_utime_us) - t->period_s * 1e6) > 1.0) {
        t->stats.rate_mismatch++;
    }
    t->refused_in_row = 0;
    t->acc_run = (cs == CDPR_OK) ? t->acc_run + 1 : 1;
    t->have_cand = 0;
    t->have_accepted = 1;
    t->acc_seq = t->state.seq;
    t->acc_utime_us = t->state.utime_us;
    for (int j = 0; j < t->n_cables; ++j) {
        t->acc_length_m[j] = t->ten.length_m[j];
    }
    count_control(t, &t->state);
    t->answered_state_seq = t->state.seq;
    t->have_state = 0;
    cdpr_tracker_meas_t m;
    cdpr_tracker_cmd_t c;
    (void)cdpr_rt_tracker_meas_from_msgs(&t->state, &t->ten.msg, t->period_s, t->n_cables, &m);
    if (t->wind != NULL && t->wind->given != 0) {
        double w[3];
        cdpr_scenario_wind_eval(t->wind, m.t_s + 0.5 * t->period_s, w);
        (void)cdpr_tracker_set_wind(&t->tracker, cdpr_v3(w[0], w[1], w[2])); /* finite */
    }
    const int64_t t0 = now_ns();
    const cdpr_status_t st = cdpr_tracker_step(&t->tracker, &m, &c);
    time_step(t, now_ns() - t0);
    if (st != CDPR_OK) {
        t->stats.bad_measurement++;
        return -1;
    }
    t->stats.ik_failures = t->tracker.ik_failures;
    cdpr_lcm_wire_command_t w;
    cdpr_winch_command_t *cmd = &w.msg;
    cdpr_lcm_wire_command_init(&w);
    cmd->utime_us = t->state.utime_us;
    cmd->seq = t->cmd_seq + 1;
    cmd->state_seq = t->state.seq;
    cmd->controller_session = t->controller_session;
    cmd->plant_session = t->state.plant_session;
    cmd->mode = CDPR_WINCH_COMMAND_T_MODE_RATE;
    cmd->n_cables = (int8_t)t->n_cables;
    for (int j = 0; j < t->n_cables; ++j) {
        const double u = fmax(-t->u_max_m_per_s[j], fmin(t->u_max_m_per_s[j], c.rate_m_per_s[j]));
        if (fabs(u - c.rate_m_per_s[j]) > 0.0) {
            t->clamped++;
        }
        cmd->value[j] = u;
    }
    const int len = cdpr_lcm_wire_command_encode(&w, t->cmd_buf, (int)sizeof t->cmd_buf);
    t->cmd_len = (len > 0) ? len : 0;
    if (len <= 0 || lcm_publish(t->lcm, t->ch_command, t->cmd_buf, (unsigned int)len) != 0) {
        t->stats.publish_errors++;
        return -1;
    }
    t->cmd_seq = cmd->seq;
    t->stats.answered++;
    if (t->on_step != NULL) {
        t->on_step(&m, &c, &t->state, &t->ten.msg, t->on_step_ctx);
    }
    return 1;
}

void cdpr_rt_tracker_record_step(const cdpr_tracker_meas_t *m, const cdpr_tracker_cmd_t *c,
                                 const cdpr_cabin_state_t *st, const cdpr_cable_tensions_t *ten,
                                 void *ctx)
{
    (void)st;
    cdpr_rt_tracker_record_t *r = ctx;
    cdpr_traj_sample_t des;
    cdpr_traj_eval(r->traj, m->t_s, &des);
    int segments[CDPR_MAX_CABLES] = {0};
    const int nc = (ten->n_cables <= CDPR_MAX_CABLES) ? ten->n_cables : CDPR_MAX_CABLES;
    for (int j = 0; j < nc; ++j) {
        segments[j] = (int)ten->n_segments[j];
        r->max_payout_m_per_s = fmax(r->max_payout_m_per_s, fabs(ten->payout_m_per_s[j]));
    }
    const cdpr_record_row_t row = {m->t_s,
                                   &des,
                                   m,
                                   ten->tension_cabin_N,
                                   ten->tension_winch_N,
                                   c->l_ff_m,
                                   ten->payout_m_per_s,
                                   segments};
    const long k = (long)llround(m->t_s / r->period_s);
    /* The state at the end of the run gets its row, as in cdpr-sim; a CSV failure is kept in
     * the recorder (cdpr_record_close reports it) and the controller keeps controlling. */
    const int last = (m->t_s >= r->rec.duration_s - 0.5 * r->period_s) ? 1 : 0;
    (void)cdpr_record_period(&r->rec, k, last, &row);
    r->last_t_s = m->t_s;
    r->periods++;
}

int cdpr_rt_tracker_in_control(const cdpr_rt_tracker_t *t, double max_share)
{
    const cdpr_rt_tracker_stats_t *s = &t->stats;
    const uint64_t n = s->applied_ours + s->applied_none + s->applied_other;
    return (n == 0 || (double)s->applied_other <= max_share * (double)n) ? 1 : 0;
}

void cdpr_rt_tracker_print_trust(FILE *f, const char *app, const cdpr_rt_tracker_t *t)
{
    const cdpr_rt_tracker_stats_t *s = &t->stats;
    const uint64_t refused = s->refused_seq + s->refused_time + s->refused_implausible;
    if (refused > 0 || s->bad_measurement > 0) {
        fprintf(f,
                "%s: refused states: %llu outside the sequence window, %llu with a bad time, "
                "%llu implausible, %llu not usable (%llu re-anchors); last: %s\n",
                app, (unsigned long long)s->refused_seq, (unsigned long long)s->refused_time,
                (unsigned long long)s->refused_implausible, (unsigned long long)s->bad_measurement,
                (unsigned long long)s->resyncs, t->last_refusal);
    }
    if (s->rate_mismatch > 0) {
        fprintf(f,
                "%s: %llu state steps were not one control period (%g s): the plant runs at "
                "another rate\n",
                app, (unsigned long long)s->rate_mismatch, t->period_s);
    }
    if (s->applied_other > 0 || s->applied_none > 0) {
        fprintf(f,
                "%s: after its first command the plant applied this controller's commands in "
                "%llu periods, none in %llu (held), another controller's in %llu\n",
                app, (unsigned long long)s->applied_ours, (unsigned long long)s->applied_none,
                (unsigned long long)s->applied_other);
    }
}
