/* SPDX-License-Identifier: BSD-3-Clause */
/// @file winch.c
/// Winch commands and node insertion/removal (docs/model.md "Winch and node events").
#include "cdpr/winch.h"

#include <math.h>
#include <stddef.h>

#include "check.h"

void cdpr_winch_params_default(cdpr_winch_params_t *p)
{
    p->u_max_m_per_s = CDPR_R(4.0);
    p->a_max_m_per_s2 = CDPR_R(5.0);
    p->kp_per_s = CDPR_R(5.0);
    p->min_length_m = CDPR_R(0.5);
}

cdpr_status_t cdpr_winch_init(cdpr_winch_t *w, const cdpr_winch_params_t *p, cdpr_diag_t *diag)
{
    if (w == NULL || p == NULL) {
        return cdpr_diag_set(diag, CDPR_E_INVALID_ARG, "winch", -1);
    }
    CDPR_TRY(check_positive(p->u_max_m_per_s, "u_max_m_per_s", -1, diag));
    CDPR_TRY(check_positive(p->a_max_m_per_s2, "a_max_m_per_s2", -1, diag));
    CDPR_TRY(check_positive(p->kp_per_s, "kp_per_s", -1, diag));
    CDPR_TRY(check_positive(p->min_length_m, "min_length_m", -1, diag));
    w->p = *p;
    w->mode = CDPR_WINCH_RATE;
    w->command = CDPR_R(0.0);
    w->u_m_per_s = CDPR_R(0.0);
    w->at_min_length = 0;
    return cdpr_diag_set(diag, CDPR_OK, "", -1);
}

cdpr_status_t cdpr_winch_command(cdpr_winch_t *w, cdpr_winch_mode_t mode, cdpr_real_t value)
{
    if (w == NULL) {
        return CDPR_E_INVALID_ARG;
    }
    if (!isfinite(value)) {
        return CDPR_E_NOT_FINITE;
    }
    if ((mode != CDPR_WINCH_RATE && mode != CDPR_WINCH_LENGTH) ||
        (mode == CDPR_WINCH_LENGTH && !(value > CDPR_R(0.0)))) {
        return CDPR_E_OUT_OF_RANGE;
    }
    w->mode = mode;
    w->command = value;
    return CDPR_OK;
}

static cdpr_real_t clampr(cdpr_real_t x, cdpr_real_t lo, cdpr_real_t hi)
{
    return (x < lo) ? lo : ((x > hi) ? hi : x);
}

cdpr_status_t cdpr_winch_update(cdpr_winch_t *w, cdpr_real_t length_m, cdpr_real_t dt_s)
{
    if (w == NULL || !isfinite(length_m) || !(dt_s > CDPR_R(0.0)) || !isfinite(dt_s)) {
        return CDPR_E_INVALID_ARG;
    }
    const cdpr_real_t target =
        (w->mode == CDPR_WINCH_LENGTH) ? w->p.kp_per_s * (w->command - length_m) : w->command;
    const cdpr_real_t du = w->p.a_max_m_per_s2 * dt_s;
    cdpr_real_t u = clampr(target, w->u_m_per_s - du, w->u_m_per_s + du);
    u = clampr(u, -w->p.u_max_m_per_s, w->p.u_max_m_per_s);
    /* Never haul in below the minimum within this period (the rate is held for dt). */
    const cdpr_real_t u_floor = (w->p.min_length_m - length_m) / dt_s;
    w->at_min_length = 0;
    if (u < u_floor && u < CDPR_R(0.0)) {
        u = (u_floor < CDPR_R(0.0)) ? u_floor : CDPR_R(0.0);
        w->at_min_length = 1;
    }
    w->u_m_per_s = u;
    return (w->at_min_length != 0) ? CDPR_WARN_MIN_LENGTH : CDPR_OK;
}

/* Move y[from, end) by `delta` places (delta may be negative); regions may overlap. */
static void shift(cdpr_real_t *y, int from, int end, int delta)
{
    if (delta > 0) {
        for (int i = end - 1; i >= from; --i) {
            y[i + delta] = y[i];
        }
    } else if (delta < 0) {
        for (int i = from; i < end; ++i) {
            y[i + delta] = y[i];
        }
    } else {
        /* delta == 0: nothing moves. */
    }
}

/* Node n-1 of cable j: position/velocity (the cabin attachment when n = 1). */
static void last_free_node(const cdpr_robot_t *r, int j, const cdpr_cabin_motion_t *m,
                           const cdpr_real_t *y, cdpr_real_t pos[3], cdpr_real_t vel[3])
{
    const cdpr_cable_t *c = &r->cable[j];
    const int nf = c->n - 1;
    if (nf == 0) {
        cdpr_vec3_t a;
        cdpr_vec3_t v;
        cdpr_robot_attachment(r, j, m, &a, &v);
        cdpr_v3_store(a, pos);
        cdpr_v3_store(v, vel);
        return;
    }
    const cdpr_real_t *b = y + r->offset[j];
    for (int k = 0; k < 3; ++k) {
        pos[k] = b[1 + 3 * (nf - 1) + k];
        vel[k] = b[1 + 3 * nf + 3 * (nf - 1) + k];
    }
}

/* Insert a node Delta from node n-1 along the last segment (winch.h). */
static void insert_node(cdpr_robot_t *r, int j, const cdpr_cabin_motion_t *m, cdpr_real_t *y)
{
    cdpr_cable_t *c = &r->cable[j];
    const int o = r->offset[j];
    const int nf = c->n - 1;
    const cdpr_real_t lu_last = y[o];
    const cdpr_real_t delta = c->delta_m;
    cdpr_real_t pa[3];
    cdpr_real_t va[3];
    last_free_node(r, j, m, y, pa, va);
    const cdpr_vec3_t A = r->p.cables[j].exit_point_m;
    const cdpr_real_t pb[3] = {A.x, A.y, A.z};
    /* Unstretched fraction along the straight segment: both halves keep the old strain. */
    const cdpr_real_t f = delta / lu_last;
    /* Make room: everything after this block moves by 6, the velocity block by 3. */
    shift(y, o + 1 + 6 * nf, r->dim, 6);
    shift(y, o + 1 + 3 * nf, o + 1 + 6 * nf, 3);
    for (int k = 0; k < 3; ++k) {
        y[o + 1 + 3 * nf + k] = pa[k] + f * (pb[k] - pa[k]);
        y[o + 1 + 3 * (nf + 1) + 3 * nf + k] = (CDPR_R(1.0) - f) * va[k]; /* pulley at rest */
    }
    c->lu_m[nf] = delta;
    c->n = nf + 2;
    c->lu_m[nf + 1] = lu_last - delta;
    y[o] = lu_last - delta;
}

/* Remove node n-1, merging the last two segments (winch.h). */
static void remove_node(cdpr_robot_t *r, int j, cdpr_real_t *y)
{
    cdpr_cable_t *c = &r->cable[j];
    const int o = r->offset[j];
    const int nf = c->n - 1; /* >= 1 */
    const cdpr_real_t lu_last = y[o];
    const cdpr_real_t lu_prev = c->lu_m[nf - 1];
    const cdpr_real_t rho = c->p.rho_kg_per_m;
    if (nf >= 2) {
        /* Surviving neighbour (node nf-1) takes the mass-weighted mean velocity. */
        const cdpr_real_t lu_pp = c->lu_m[nf - 2];
        const cdpr_real_t m_keep = CDPR_R(0.5) * rho * (lu_pp + lu_prev);
        const cdpr_real_t m_gone = CDPR_R(0.5) * rho * (lu_prev + lu_last);
        cdpr_real_t *vk = y + o + 1 + 3 * nf + 3 * (nf - 2);
        const cdpr_real_t *vg = y + o + 1 + 3 * nf + 3 * (nf - 1);
        for (int k = 0; k < 3; ++k) {
            vk[k] = (m_keep * vk[k] + m_gone * vg[k]) / (m_keep + m_gone);
        }
    }
    /* Drop position slot nf (3 reals) and velocity slot nf (3 reals). */
    shift(y, o + 1 + 3 * nf, o + 1 + 3 * nf + 3 * (nf - 1), -3);
    shift(y, o + 1 + 6 * nf, r->dim, -6);
    c->n = nf;
    c->lu_m[nf - 1] = lu_prev + lu_last;
    c->lu_m[nf] = CDPR_R(0.0);
    y[o] = lu_prev + lu_last;
}

cdpr_status_t cdpr_winch_node_events(cdpr_robot_t *r, cdpr_real_t t_s, cdpr_real_t *y,
                                     cdpr_node_stats_t *stats, int *changed)
{
    if (r == NULL || y == NULL || stats == NULL || changed == NULL) {
        return CDPR_E_INVALID_ARG;
    }
    *changed = 0;
    cdpr_status_t st = CDPR_OK;
    cdpr_cabin_motion_t m;
    cdpr_robot_cabin_motion(r, t_s, y, &m);
    int cabin_dirty = 0;
    for (int j = 0; j < r->p.n_cables; ++j) {
        cdpr_cable_t *c = &r->cable[j];
        /* Bounded: each event moves lu[n-1] by >= Delta/2 toward [Delta/2, 2 Delta], and the
         * node count by one within [1, CDPR_MAX_SEGMENTS]. */
        for (int guard = 0; guard < CDPR_MAX_SEGMENTS; ++guard) {
            const cdpr_real_t lu_last = y[r->offset[j]];
            if (lu_last > CDPR_R(2.0) * c->delta_m) {
                if (c->n >= CDPR_MAX_SEGMENTS) {
                    stats->capacity_hits[j]++;
                    st = CDPR_WARN_CAPACITY;
                    break;
                }
                cabin_dirty |= (c->n == 1) ? 1 : 0;
                insert_node(r, j, &m, y);
                stats->insertions[j]++;
            } else if (lu_last < CDPR_R(0.5) * c->delta_m && c->n > 1) {
                cabin_dirty |= (c->n == 2) ? 1 : 0;
                remove_node(r, j, y);
                stats->removals[j]++;
            } else {
                break;
            }
            cdpr_cable_refresh(c);
            cdpr_robot_update_layout(r);
            *changed = 1;
        }
    }
    if (cabin_dirty != 0) {
        /* lu_0 changed: node 0's lumped mass on the cabin changed with it (robot.h). */
        (void)cdpr_robot_refresh_cabin(r);
    }
    return st;
}
