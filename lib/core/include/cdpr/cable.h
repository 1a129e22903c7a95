/* SPDX-License-Identifier: BSD-3-Clause */
/// @file cable.h
/// One cable discretised by the lumped-mass method (docs/model.md "One cable", paper §3.1).
///
/// Nodes i = 0..n: node 0 moves with the cabin attachment, node n is the pulley exit point
/// (fixed in space). Segment k joins nodes k and k+1 and has unstretched length lu[k]. Forces
/// per segment: elastic tension with slack (never compressive) and strain-rate damping; per
/// node: gravity and half the aerodynamic drag of each adjacent segment.
///
/// State block of one cable inside a state vector (all [SI]):
///   y[0]                      lu[n-1], unstretched length of the pulley-side segment [m]
///   y[1 .. 3(n-1)]            positions r_1..r_{n-1} of the free nodes, xyz interleaved [m]
///   y[1+3(n-1) .. 6(n-1)]     velocities v_1..v_{n-1} [m/s]
/// Only the pulley-side segment changes length continuously (d lu[n-1]/dt = payout rate u);
/// the other lu[k] change only at node events (winch module) and live in the cable object.
///
/// Memory: the object is caller-owned, sizeof(cdpr_cable_t) grows with CDPR_MAX_SEGMENTS.
/// Nothing allocates; the object holds no resources (no deinit). Reentrant across objects.
/// Pointer arguments must be valid unless a function says it checks them; n below is the
/// cable's current segment count c->n.
#ifndef CDPR_CABLE_H
#define CDPR_CABLE_H

#include "cdpr/config.h"
#include "cdpr/status.h"
#include "cdpr/vec3.h"

/// Axial law of a segment: tension from strain eps = l/lu - 1 and strain rate eps_dot
/// (docs/model.md "One cable", "Slack, snap and damping").
typedef enum {
    /// T = max(0, EA max(eps, 0) + c eps_dot): Lipschitz in (eps, eps_dot), never pushes,
    /// passive (the damper only ever removes energy), and its damper acts whenever the segment
    /// is being stretched -- also while it is still slack, so a snap has no force jump.
    CDPR_SLACK_PASSIVE = 0,
    /// T = EA max(eps, 0) + c eps_dot: the damper acts in slack and taut alike and the total
    /// may be negative (a damper that pushes), as in MoorDyn. For side-by-side comparisons.
    CDPR_SLACK_MOORDYN = 1
} cdpr_slack_law_t;

/// Physical parameters of one cable (inputs). Defaults from cdpr_cable_params_default().
///
/// Damping is given either as the raw Kelvin-Voigt coefficient c (damping_Ns) or as a modal
/// damping ratio zeta at a frequency f (damping_ratio > 0, damping_ref_hz): Kelvin-Voigt damping
/// of the axial modes is zeta(omega) = c omega / (2 EA), so the core uses
/// c = zeta EA / (pi f), converted once by cdpr_cable_init. Give one of the two, not both.
typedef struct {
    cdpr_real_t d0_m;              ///< unstretched diameter [m] (> 0); default 0.006
    cdpr_real_t rho_kg_per_m;      ///< mass per unstretched length [kg/m] (> 0); default 0.14
    cdpr_real_t ea_N;              ///< axial stiffness EA [N] (> 0); default 2e6
    cdpr_real_t damping_Ns;        ///< strain-rate damping c [N s] (>= 0); default 170
    cdpr_real_t damping_ratio;     ///< or: axial damping ratio zeta [-] in [0, 1]; default 0
    cdpr_real_t damping_ref_hz;    ///< frequency where zeta holds [Hz] (> 0); default 5
    cdpr_real_t cd;                ///< normal drag coefficient Cd [-] (>= 0); default 1.2
    cdpr_real_t cm;                ///< tangential factor Cm [-] (>= 0), paper pi*C_F = Cm*Cd; 0.03
    cdpr_real_t rho_air_kg_per_m3; ///< air density [kg/m^3] (>= 0); default 1.225
    cdpr_slack_law_t slack_law;    ///< axial law; default CDPR_SLACK_PASSIVE
} cdpr_cable_params_t;

/// One cable's discretisation (internal fields maintained by the core; read-only for users).
typedef struct {
    cdpr_cable_params_t p;                 ///< copy of the validated parameters
    int n;                                 ///< active segments, 1..CDPR_MAX_SEGMENTS
    cdpr_real_t delta_m;                   ///< nominal segment length Delta [m] (winch.h)
    cdpr_real_t lu_m[CDPR_MAX_SEGMENTS];   ///< unstretched lengths; for k = n-1 the state y[0] is
                                           ///< authoritative (lu_m[n-1]: value at init/last event)
    cdpr_real_t inv_lu[CDPR_MAX_SEGMENTS]; ///< 1/lu_m[k] for k < n-1 [1/m]
    cdpr_real_t inv_m[CDPR_MAX_SEGMENTS];  ///< 1/m_i for free nodes i = 1..n-2 [1/kg]
    cdpr_real_t drag_k;                    ///< 0.5 rho_air d0 Cd [kg/m^2]
} cdpr_cable_t;

/// Motion of the two end nodes and the environment, for one RHS evaluation (inputs).
typedef struct {
    cdpr_vec3_t r0_m;           ///< node 0 position (cabin attachment) [m]
    cdpr_vec3_t v0_m_per_s;     ///< node 0 velocity [m/s]
    cdpr_vec3_t rn_m;           ///< node n position (pulley exit point, fixed) [m]
    cdpr_vec3_t wind_m_per_s;   ///< uniform wind velocity J [m/s]
    cdpr_real_t payout_m_per_s; ///< winch payout rate u = d lu[n-1]/dt [m/s], + = pay out
    cdpr_real_t g_m_per_s2;     ///< gravity magnitude [m/s^2], acting along -z
} cdpr_cable_bc_t;

/// What the cable does to its ends (outputs of one RHS evaluation).
typedef struct {
    cdpr_vec3_t force_on_cabin_N; ///< T_0 t_0 + F_0/2: elastic + half segment-0 drag [N]
    cdpr_real_t tension_cabin_N;  ///< T_0, cabin-end tension [N]
    cdpr_real_t tension_winch_N;  ///< T_{n-1}, winch-end tension [N]
} cdpr_cable_out_t;

/// Forces of one segment (output of cdpr_cable_segment_eval).
typedef struct {
    cdpr_real_t length_m;  ///< stretched length l [m]
    cdpr_real_t strain;    ///< l/lu - 1 [-]
    cdpr_real_t tension_N; ///< T [N] (>= 0 except with CDPR_SLACK_MOORDYN)
    cdpr_vec3_t tangent;   ///< unit vector from node k to node k+1 (zero if l = 0)
    cdpr_vec3_t drag_N;    ///< aerodynamic force on the whole segment F_k [N]
} cdpr_segment_t;

/// Fill `p` with the defaults of docs/robots.md set A (`paper-50m`: 6 mm steel wire rope).
/// O(1), cannot fail.
void cdpr_cable_params_default(cdpr_cable_params_t *p);

/// Check every field. O(1). Returns, for the first bad field (`diag`, may be NULL, names it
/// by its member name, index -1):
/// - CDPR_E_INVALID_ARG: p is NULL ("params").
/// - CDPR_E_NOT_FINITE: a field is NaN/Inf.
/// - CDPR_E_NOT_POSITIVE: d0_m, rho_kg_per_m or ea_N <= 0.
/// - CDPR_E_OUT_OF_RANGE: damping_Ns, cd, cm or rho_air_kg_per_m3 < 0.
/// CDPR_OK (diag: status OK, field "", index -1) otherwise.
cdpr_status_t cdpr_cable_params_validate(const cdpr_cable_params_t *p, cdpr_diag_t *diag);

/// Kelvin-Voigt coefficient c = zeta EA / (pi f) [N s] that gives the axial modes the damping
/// ratio `zeta` at frequency `f_hz` (zeta(omega) = c omega / (2 EA)). O(1); no checks (the
/// caller validated the inputs); cannot fail.
cdpr_real_t cdpr_cable_damping_from_ratio(cdpr_real_t ea_N, cdpr_real_t zeta, cdpr_real_t f_hz);

/// Initialise a cable of `n_segments` equal segments and total unstretched length
/// `length_m` [m]. Validates everything first; on error `c` is not written. O(CDPR_MAX_SEGMENTS).
/// Returns (diag, may be NULL, names the first bad field):
/// - CDPR_E_INVALID_ARG: c is NULL ("cable") or p is NULL ("params").
/// - every error of cdpr_cable_params_validate for p.
/// - CDPR_E_CAPACITY: n_segments outside [1, CDPR_MAX_SEGMENTS] ("n_segments", index
///   n_segments).
/// - CDPR_E_NOT_FINITE / CDPR_E_NOT_POSITIVE: length_m NaN/Inf / <= 0 ("length_m").
/// CDPR_OK otherwise.
cdpr_status_t cdpr_cable_init(cdpr_cable_t *c, const cdpr_cable_params_t *p, int n_segments,
                              cdpr_real_t length_m, cdpr_diag_t *diag);

/// Number of state components of the cable's current block: 1 + 6 (n - 1). O(1), cannot fail.
int cdpr_cable_state_dim(const cdpr_cable_t *c);

/// Total unstretched length sum(lu) [m]; `y` is the cable's state block (for lu[n-1]). O(n),
/// cannot fail.
cdpr_real_t cdpr_cable_total_length(const cdpr_cable_t *c, const cdpr_real_t *y);

/// Recompute the cached reciprocals and node masses from lu_m[] and p after they changed
/// (node events). Needs lu_m[k] > 0 for k < n - 1. O(CDPR_MAX_SEGMENTS), cannot fail.
void cdpr_cable_refresh(cdpr_cable_t *c);

/// Write the state block (cdpr_cable_state_dim components; y[0] = lu_m[n-1]) for nodes on the
/// straight line r0 -> rn at their unstretched arclength fractions of lu_m[], at rest. O(n),
/// cannot fail.
void cdpr_cable_place_straight(const cdpr_cable_t *c, cdpr_vec3_t r0_m, cdpr_vec3_t rn_m,
                               cdpr_real_t *y);

/// Node force model of one segment (docs/model.md "One cable"): tension with slack and
/// strain-rate damping, drag split in normal and tangential parts relative to the wind.
/// `lu_rate_m_per_s` is d lu/dt of this segment; lu_m must be > 0. Pure function; O(1), cannot
/// fail.
void cdpr_cable_segment_eval(const cdpr_cable_params_t *p, cdpr_vec3_t ra, cdpr_vec3_t va,
                             cdpr_vec3_t rb, cdpr_vec3_t vb, cdpr_real_t lu_m,
                             cdpr_real_t lu_rate_m_per_s, cdpr_vec3_t wind_m_per_s,
                             cdpr_segment_t *out);

/// Right-hand side of one cable: writes d/dt of the cable's state block `y` into `dydt`
/// (same layout) and, if `out` is not NULL, the end forces. Paper eqs. (3.1)-(3.4).
/// Work: O(n), 3 square roots and 1 division per segment, with or without drag. No
/// allocation; stack scratch of 13 (CDPR_MAX_SEGMENTS + 1) reals (6.8 kB at 64 segments in
/// double). Cannot fail (NaN/Inf in the inputs propagate to dydt).
void cdpr_cable_rhs(const cdpr_cable_t *c, const cdpr_real_t *y, const cdpr_cable_bc_t *bc,
                    cdpr_real_t *dydt, cdpr_cable_out_t *out);

/// End forces only (segments 0 and n-1), without the node accelerations: what the cabin
/// feels and what the winch measures. Same values as cdpr_cable_rhs's `out`. O(1), cannot
/// fail.
void cdpr_cable_end_forces(const cdpr_cable_t *c, const cdpr_real_t *y, const cdpr_cable_bc_t *bc,
                           cdpr_cable_out_t *out);

#endif /* CDPR_CABLE_H */
