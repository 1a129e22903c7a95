/* SPDX-License-Identifier: BSD-3-Clause */
/// @file trajectory.c
/// Circle, line and hold trajectories (docs/validation.md §8; scenario geometry in docs/robots.md).
#include "cdpr/control/trajectory.h"

#include <math.h>
#include <string.h>

#include "cdpr/vec3.h"

cdpr_vec3_t cdpr_euler_rates_to_body(const cdpr_real_t euler[3], const cdpr_real_t rates[3])
{
    /* R = Rz(γ) Ry(β) Rx(α): ω_world = γ' z + β' Rz(γ) y + α' Rz(γ) Ry(β) x. */
    const cdpr_real_t cb = CDPR_COS(euler[1]);
    const cdpr_real_t sb = CDPR_SIN(euler[1]);
    const cdpr_real_t cg = CDPR_COS(euler[2]);
    const cdpr_real_t sg = CDPR_SIN(euler[2]);
    const cdpr_vec3_t w_world =
        cdpr_v3(rates[0] * cg * cb - rates[1] * sg, rates[0] * sg * cb + rates[1] * cg,
                -rates[0] * sb + rates[2]);
    cdpr_mat3_t R;
    cdpr_quat_to_mat3(cdpr_quat_from_euler(euler[0], euler[1], euler[2]), &R);
    return cdpr_m3t_mul_v3(&R, w_world);
}

cdpr_vec3_t cdpr_euler_accel_to_body(const cdpr_real_t euler[3], const cdpr_real_t rates[3],
                                     const cdpr_real_t accels[3])
{
    /* Differentiate ω_world = α' (cγ cβ, sγ cβ, -sβ) + β' (-sγ, cγ, 0) + γ' (0, 0, 1). */
    const cdpr_real_t cb = CDPR_COS(euler[1]);
    const cdpr_real_t sb = CDPR_SIN(euler[1]);
    const cdpr_real_t cg = CDPR_COS(euler[2]);
    const cdpr_real_t sg = CDPR_SIN(euler[2]);
    const cdpr_real_t da = rates[0];
    const cdpr_real_t db = rates[1];
    const cdpr_real_t dg = rates[2];
    const cdpr_vec3_t dw_world = cdpr_v3(
        accels[0] * cg * cb - accels[1] * sg + da * (-sg * dg * cb - cg * sb * db) - db * cg * dg,
        accels[0] * sg * cb + accels[1] * cg + da * (cg * dg * cb - sg * sb * db) - db * sg * dg,
        -accels[0] * sb + accels[2] - da * cb * db);
    cdpr_mat3_t R;
    cdpr_quat_to_mat3(cdpr_quat_from_euler(euler[0], euler[1], euler[2]), &R);
    return cdpr_m3t_mul_v3(&R, dw_world);
}

cdpr_real_t cdpr_traj_cycle_s(const cdpr_traj_t *tr)
{
    return (tr->type == CDPR_TRAJ_CYCLIC) ? CDPR_R(2.0) * (tr->duration_s + tr->pause_s)
                                          : CDPR_R(0.0);
}

cdpr_real_t cdpr_traj_end_time(const cdpr_traj_t *tr)
{
    switch (tr->type) {
    case CDPR_TRAJ_CIRCLE:
        return (cdpr_real_t)INFINITY;
    case CDPR_TRAJ_LINE:
        return (tr->back_and_forth != 0) ? CDPR_R(2.0) * tr->duration_s + tr->pause_s
                                         : tr->duration_s;
    case CDPR_TRAJ_CYCLIC:
        return (tr->cycles > 0) ? (cdpr_real_t)tr->cycles * cdpr_traj_cycle_s(tr)
                                : (cdpr_real_t)INFINITY;
    default:
        return CDPR_R(0.0);
    }
}

/* Laps travelled at t >= 0 as a real number (its floor is the lap), or -1 when the trajectory
 * is not periodic or t is past a cyclic trajectory's last cycle. */
static cdpr_real_t laps_at(const cdpr_traj_t *tr, cdpr_real_t t_s)
{
    cdpr_real_t laps = -CDPR_R(1.0);
    if (tr->type == CDPR_TRAJ_CIRCLE && tr->speed_m_per_s > CDPR_R(0.0) &&
        tr->radius_m > CDPR_R(0.0)) {
        const cdpr_real_t s = (t_s < tr->ramp_s)
                                  ? CDPR_R(0.5) * tr->speed_m_per_s * t_s * t_s / tr->ramp_s
                                  : tr->speed_m_per_s * (t_s - CDPR_R(0.5) * tr->ramp_s);
        laps = s / (CDPR_R(2.0) * (cdpr_real_t)CDPR_PI * tr->radius_m);
    } else if (tr->type == CDPR_TRAJ_CYCLIC && cdpr_traj_cycle_s(tr) > CDPR_R(0.0)) {
        laps = t_s / cdpr_traj_cycle_s(tr);
        if (tr->cycles > 0 && CDPR_FLOOR(laps) >= (cdpr_real_t)tr->cycles) {
            laps = -CDPR_R(1.0);
        }
    } else {
        /* hold, line, a cyclic move of no duration: not periodic (-1 above) */
    }
    return laps;
}

long cdpr_traj_lap(const cdpr_traj_t *tr, cdpr_real_t t_s)
{
    if (!(t_s >= CDPR_R(0.0))) {
        return -1;
    }
    const cdpr_real_t laps = CDPR_FLOOR(laps_at(tr, t_s));
    return (laps >= CDPR_R(0.0) && laps < CDPR_R(1e9)) ? (long)laps : -1;
}

cdpr_real_t cdpr_traj_lap_s(const cdpr_traj_t *tr)
{
    if (tr->type == CDPR_TRAJ_CIRCLE && tr->speed_m_per_s > CDPR_R(0.0) &&
        tr->radius_m > CDPR_R(0.0)) {
        return CDPR_R(2.0) * (cdpr_real_t)CDPR_PI * tr->radius_m / tr->speed_m_per_s;
    }
    return cdpr_traj_cycle_s(tr); /* 0 for hold and line */
}

cdpr_real_t cdpr_traj_lap_phase(const cdpr_traj_t *tr, cdpr_real_t t_s)
{
    const long lap = cdpr_traj_lap(tr, t_s);
    if (lap < 0) {
        return -CDPR_R(1.0);
    }
    const cdpr_real_t f = laps_at(tr, t_s) - (cdpr_real_t)lap;
    return (f >= CDPR_R(0.0) && f < CDPR_R(1.0)) ? f : CDPR_R(0.0);
}

static void circle(const cdpr_traj_t *tr, cdpr_real_t t, cdpr_traj_sample_t *o)
{
    const cdpr_real_t tt = (t > CDPR_R(0.0)) ? t : CDPR_R(0.0);
    cdpr_real_t s;     /* path length travelled [m] */
    cdpr_real_t sdot;  /* path speed [m/s] */
    cdpr_real_t sddot; /* path acceleration [m/s^2] */
    if (t < CDPR_R(0.0)) {
        s = CDPR_R(0.0); /* before the start: at rest at the start point */
        sdot = CDPR_R(0.0);
        sddot = CDPR_R(0.0);
    } else if (tt < tr->ramp_s) {
        s = CDPR_R(0.5) * tr->speed_m_per_s * tt * tt / tr->ramp_s;
        sdot = tr->speed_m_per_s * tt / tr->ramp_s;
        sddot = tr->speed_m_per_s / tr->ramp_s;
    } else {
        s = tr->speed_m_per_s * (tt - CDPR_R(0.5) * tr->ramp_s);
        sdot = tr->speed_m_per_s;
        sddot = CDPR_R(0.0);
    }
    const cdpr_real_t th = tr->start_angle_rad + tr->direction * s / tr->radius_m;
    const cdpr_real_t thdot = tr->direction * sdot / tr->radius_m;
    const cdpr_real_t thddot = tr->direction * sddot / tr->radius_m;
    const cdpr_real_t c = CDPR_COS(th);
    const cdpr_real_t sn = CDPR_SIN(th);
    o->pose[0] = tr->centre_m[0] + tr->radius_m * c;
    o->pose[1] = tr->centre_m[1] + tr->radius_m * sn;
    o->pose[2] = tr->centre_m[2];
    o->rate[0] = -tr->radius_m * thdot * sn;
    o->rate[1] = tr->radius_m * thdot * c;
    o->rate[2] = CDPR_R(0.0);
    /* Tangential (r θ'') and centripetal (r θ'^2, toward the centre) parts. */
    o->accel[0] = -tr->radius_m * (thddot * sn + thdot * thdot * c);
    o->accel[1] = tr->radius_m * (thddot * c - thdot * thdot * sn);
    o->accel[2] = CDPR_R(0.0);
    for (int i = 0; i < 3; ++i) {
        o->pose[3 + i] = tr->attitude_rad[i];
        o->rate[3 + i] = CDPR_R(0.0);
        o->accel[3 + i] = CDPR_R(0.0);
    }
}

/* Linear interpolation a -> b over [0, T): fraction f and its rate (accel stays 0: every
 * coordinate is linear in time). */
static void lerp(const cdpr_real_t *a, const cdpr_real_t *b, cdpr_real_t f, cdpr_real_t fdot,
                 cdpr_traj_sample_t *o)
{
    for (int i = 0; i < 6; ++i) {
        o->pose[i] = a[i] + f * (b[i] - a[i]);
        o->rate[i] = fdot * (b[i] - a[i]);
    }
}

static void line(const cdpr_traj_t *tr, cdpr_real_t t, cdpr_traj_sample_t *o)
{
    const cdpr_real_t T = tr->duration_s;
    const cdpr_real_t back = T + tr->pause_s; /* start of the way back */
    if (t > CDPR_R(0.0) && t < T) {
        lerp(tr->from, tr->to, t / T, CDPR_R(1.0) / T, o);
    } else if (t >= T && (tr->back_and_forth == 0 || t < back)) {
        lerp(tr->from, tr->to, CDPR_R(1.0), CDPR_R(0.0), o); /* at `to` (held, or pausing) */
    } else if (t >= back && t < back + T) {
        lerp(tr->to, tr->from, (t - back) / T, CDPR_R(1.0) / T, o);
    } else {
        lerp(tr->from, tr->to, CDPR_R(0.0), CDPR_R(0.0), o); /* not started, or back at `from` */
    }
}

/* One cycloidal leg a -> b at u = leg time / T in [0, 1]: s = u - sin(2 pi u) / (2 pi),
 * ds/dt = (1 - cos 2 pi u) / T, d2s/dt2 = 2 pi sin(2 pi u) / T^2. */
static void cycloid(const cdpr_real_t *a, const cdpr_real_t *b, cdpr_real_t u, cdpr_real_t T,
                    cdpr_traj_sample_t *o)
{
    const cdpr_real_t w = CDPR_R(2.0) * (cdpr_real_t)CDPR_PI * u;
    const cdpr_real_t s = u - CDPR_SIN(w) / (CDPR_R(2.0) * (cdpr_real_t)CDPR_PI);
    const cdpr_real_t sd = (CDPR_R(1.0) - CDPR_COS(w)) / T;
    const cdpr_real_t sdd = CDPR_R(2.0) * (cdpr_real_t)CDPR_PI * CDPR_SIN(w) / (T * T);
    for (int i = 0; i < 6; ++i) {
        const cdpr_real_t d = b[i] - a[i];
        o->pose[i] = a[i] + s * d;
        o->rate[i] = sd * d;
        o->accel[i] = sdd * d;
    }
}

static void cyclic(const cdpr_traj_t *tr, cdpr_real_t t, cdpr_traj_sample_t *o)
{
    const cdpr_real_t T = tr->duration_s;
    const cdpr_real_t P = cdpr_traj_cycle_s(tr);
    const int ended = (tr->cycles > 0 && t >= (cdpr_real_t)tr->cycles * P) ? 1 : 0;
    const cdpr_real_t tau =
        (t > CDPR_R(0.0) && ended == 0) ? CDPR_FMOD(t, P) : CDPR_R(0.0); /* time within the cycle */
    if (tau < T) {
        cycloid(tr->from, tr->to, tau / T, T, o); /* out (at `from`, at rest, for tau = 0) */
    } else if (tau < T + tr->pause_s) {
        cycloid(tr->from, tr->to, CDPR_R(1.0), T, o); /* pausing at `to` */
    } else if (tau < CDPR_R(2.0) * T + tr->pause_s) {
        cycloid(tr->to, tr->from, (tau - T - tr->pause_s) / T, T, o); /* back */
    } else {
        cycloid(tr->to, tr->from, CDPR_R(1.0), T, o); /* pausing at `from` */
    }
}

void cdpr_traj_eval(const cdpr_traj_t *tr, cdpr_real_t t_s, cdpr_traj_sample_t *out)
{
    (void)memset(out, 0, sizeof *out);
    switch (tr->type) {
    case CDPR_TRAJ_CIRCLE:
        circle(tr, t_s, out);
        break;
    case CDPR_TRAJ_LINE:
        line(tr, t_s, out);
        break;
    case CDPR_TRAJ_CYCLIC:
        cyclic(tr, t_s, out);
        break;
    default:
        (void)memcpy(out->pose, tr->hold_pose, sizeof out->pose);
        break;
    }
    out->motion.p_m = cdpr_v3(out->pose[0], out->pose[1], out->pose[2]);
    out->motion.q = cdpr_quat_from_euler(out->pose[3], out->pose[4], out->pose[5]);
    out->motion.v_m_per_s = cdpr_v3(out->rate[0], out->rate[1], out->rate[2]);
    out->motion.w_rad_per_s = cdpr_euler_rates_to_body(out->pose + 3, out->rate + 3);
    out->a_m_per_s2 = cdpr_v3(out->accel[0], out->accel[1], out->accel[2]);
    out->dw_rad_per_s2 = cdpr_euler_accel_to_body(out->pose + 3, out->rate + 3, out->accel + 3);
}

void cdpr_transfer_blend(cdpr_real_t tau, cdpr_real_t *s, cdpr_real_t *ds_dtau,
                         cdpr_real_t *d2s_dtau2)
{
    const cdpr_real_t x =
        (tau < CDPR_R(0.0)) ? CDPR_R(0.0) : ((tau > CDPR_R(1.0)) ? CDPR_R(1.0) : tau);
    const cdpr_real_t x2 = x * x;
    const cdpr_real_t x3 = x2 * x;
    *s = x2 * x2 * (CDPR_R(35.0) + x * (-CDPR_R(84.0) + x * (CDPR_R(70.0) - CDPR_R(20.0) * x)));
    *ds_dtau =
        x3 * (CDPR_R(140.0) + x * (-CDPR_R(420.0) + x * (CDPR_R(420.0) - CDPR_R(140.0) * x)));
    *d2s_dtau2 =
        x2 * (CDPR_R(420.0) + x * (-CDPR_R(1680.0) + x * (CDPR_R(2100.0) - CDPR_R(840.0) * x)));
}

void cdpr_transfer_init(cdpr_transfer_t *x, const cdpr_traj_t *traj, cdpr_real_t t0_s,
                        cdpr_real_t duration_s, const cdpr_cabin_motion_t *m0, int from_rest)
{
    (void)memset(x, 0, sizeof *x);
    x->t0_s = t0_s;
    x->duration_s = duration_s;
    if (from_rest != 0) {
        x->from_rest = 1;
        x->v0_m_per_s = m0->v_m_per_s;
    }
    cdpr_traj_sample_t d;
    cdpr_traj_eval(traj, t0_s, &d);
    x->offset_m = cdpr_v3_sub(m0->p_m, d.motion.p_m);
    const cdpr_quat_t q0 = cdpr_quat_normalize(m0->q);
    const cdpr_quat_t qd_inv = {d.motion.q.w, -d.motion.q.x, -d.motion.q.y, -d.motion.q.z};
    x->theta0_rad = cdpr_quat_to_rotvec(cdpr_quat_mul(q0, qd_inv));
}

/* Unit quaternion of the rotation vector th. */
static cdpr_quat_t quat_from_rotvec(cdpr_vec3_t th)
{
    const cdpr_real_t a = cdpr_v3_norm(th);
    if (a <= CDPR_R(0.0)) { /* a norm: only 0 (sin(a / 2) / a is exact enough down to subnormals) */
        const cdpr_quat_t id = {CDPR_R(1.0), CDPR_R(0.0), CDPR_R(0.0), CDPR_R(0.0)};
        return id;
    }
    const cdpr_real_t k = CDPR_SIN(CDPR_R(0.5) * a) / a;
    const cdpr_quat_t q = {CDPR_COS(CDPR_R(0.5) * a), k * th.x, k * th.y, k * th.z};
    return q;
}

/* The attitude part of the transfer: q_r = exp((1 - s) θ0) q_traj, its body rate and
 * acceleration, into `o` (which holds the trajectory's sample). */
static void transfer_attitude(const cdpr_transfer_t *x, cdpr_real_t s, cdpr_real_t sd,
                              cdpr_real_t sdd, cdpr_traj_sample_t *o)
{
    const cdpr_quat_t e = quat_from_rotvec(cdpr_v3_scale(x->theta0_rad, CDPR_R(1.0) - s));
    cdpr_mat3_t Rt;
    cdpr_mat3_t E;
    cdpr_quat_to_mat3(o->motion.q, &Rt);
    cdpr_quat_to_mat3(e, &E);
    const cdpr_vec3_t w_t = cdpr_m3_mul_v3(&Rt, o->motion.w_rad_per_s); /* world */
    const cdpr_vec3_t dw_t = cdpr_m3_mul_v3(&Rt, o->dw_rad_per_s2);     /* world */
    const cdpr_vec3_t w_e = cdpr_v3_scale(x->theta0_rad, -sd);
    const cdpr_vec3_t ew = cdpr_m3_mul_v3(&E, w_t);
    const cdpr_vec3_t w_r = cdpr_v3_add(w_e, ew);
    const cdpr_vec3_t dw_r =
        cdpr_v3_add(cdpr_v3_add(cdpr_v3_scale(x->theta0_rad, -sdd), cdpr_v3_cross(w_e, ew)),
                    cdpr_m3_mul_v3(&E, dw_t));
    o->motion.q = cdpr_quat_normalize(cdpr_quat_mul(e, o->motion.q));
    cdpr_mat3_t R;
    cdpr_quat_to_mat3(o->motion.q, &R);
    o->motion.w_rad_per_s = cdpr_m3t_mul_v3(&R, w_r);
    o->dw_rad_per_s2 = cdpr_m3t_mul_v3(&R, dw_r);
    cdpr_quat_to_euler(o->motion.q, &o->pose[3], &o->pose[4], &o->pose[5]);
}

/* From rest: the trajectory sampled on the clock w(t) = t0 + (t - t0) s(τ), its rates scaled
 * by w' and its accelerations by w'^2 plus the rates times w'' (cdpr_transfer_t). */
static void warped_sample(const cdpr_transfer_t *x, const cdpr_traj_t *traj, cdpr_real_t tau,
                          cdpr_real_t s, cdpr_real_t ds, cdpr_real_t d2s, cdpr_traj_sample_t *out)
{
    const cdpr_real_t T = x->duration_s;
    const cdpr_real_t tc = (tau < CDPR_R(0.0)) ? CDPR_R(0.0) : tau;
    const cdpr_real_t w1 = s + tc * ds;
    const cdpr_real_t w2 = (CDPR_R(2.0) * ds + tc * d2s) / T;
    cdpr_traj_eval(traj, x->t0_s + (tc * T) * s, out);
    for (int i = 0; i < 6; ++i) {
        out->accel[i] = w1 * w1 * out->accel[i] + w2 * out->rate[i];
        out->rate[i] *= w1;
    }
    out->a_m_per_s2 = cdpr_v3_add(cdpr_v3_scale(out->a_m_per_s2, w1 * w1),
                                  cdpr_v3_scale(out->motion.v_m_per_s, w2));
    out->motion.v_m_per_s = cdpr_v3_scale(out->motion.v_m_per_s, w1);
    out->dw_rad_per_s2 = cdpr_v3_add(cdpr_v3_scale(out->dw_rad_per_s2, w1 * w1),
                                     cdpr_v3_scale(out->motion.w_rad_per_s, w2));
    out->motion.w_rad_per_s = cdpr_v3_scale(out->motion.w_rad_per_s, w1);
}

void cdpr_transfer_eval(const cdpr_transfer_t *x, const cdpr_traj_t *traj, cdpr_real_t t_s,
                        cdpr_traj_sample_t *out)
{
    if (!(x->duration_s > CDPR_R(0.0)) || t_s >= x->t0_s + x->duration_s) {
        cdpr_traj_eval(traj, t_s, out);
        return; /* no transfer, or after it: the trajectory itself */
    }
    const cdpr_real_t T = x->duration_s;
    const cdpr_real_t tau = (t_s - x->t0_s) / T;
    cdpr_real_t s;
    cdpr_real_t sd;
    cdpr_real_t sdd;
    cdpr_transfer_blend(tau, &s, &sd, &sdd);
    if (x->from_rest != 0) {
        warped_sample(x, traj, tau, s, sd, sdd, out);
    } else {
        cdpr_traj_eval(traj, t_s, out);
    }
    sd /= T;
    sdd /= T * T;
    /* Position: the start offset decays, p_r = p_traj + (1 - s) (p0 - p_traj(t0)). */
    const cdpr_vec3_t off = x->offset_m;
    cdpr_vec3_t p = cdpr_v3_add(out->motion.p_m, cdpr_v3_scale(off, CDPR_R(1.0) - s));
    cdpr_vec3_t v = cdpr_v3_sub(out->motion.v_m_per_s, cdpr_v3_scale(off, sd));
    cdpr_vec3_t a = cdpr_v3_sub(out->a_m_per_s2, cdpr_v3_scale(off, sdd));
    if (x->from_rest != 0) {
        /* the measured velocity, taken over: + T h(τ) v0, h = τ (1 - τ)^4 */
        const cdpr_real_t tc = (tau < CDPR_R(0.0)) ? CDPR_R(0.0) : tau;
        const cdpr_real_t r = CDPR_R(1.0) - tc;
        const cdpr_real_t h = tc * r * r * r * r;
        const cdpr_real_t h1 = r * r * r * (CDPR_R(1.0) - CDPR_R(5.0) * tc);
        const cdpr_real_t h2 = r * r * (CDPR_R(20.0) * tc - CDPR_R(8.0));
        p = cdpr_v3_add(p, cdpr_v3_scale(x->v0_m_per_s, T * h));
        v = cdpr_v3_add(v, cdpr_v3_scale(x->v0_m_per_s, h1));
        a = cdpr_v3_add(a, cdpr_v3_scale(x->v0_m_per_s, h2 / T));
    }
    out->motion.p_m = p;
    out->motion.v_m_per_s = v;
    out->a_m_per_s2 = a;
    const cdpr_real_t pv[3][3] = {{p.x, p.y, p.z}, {v.x, v.y, v.z}, {a.x, a.y, a.z}};
    for (int i = 0; i < 3; ++i) {
        out->pose[i] = pv[0][i];
        out->rate[i] = pv[1][i];
        out->accel[i] = pv[2][i];
    }
    transfer_attitude(x, s, sd, sdd, out);
}
