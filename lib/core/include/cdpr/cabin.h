/* SPDX-License-Identifier: BSD-3-Clause */
/// @file cabin.h
/// The cabin: a rigid body driven by the cable forces (docs/model.md "Cabin").
///
/// State block (13 components): p (3) world position of the body origin [m], q (4) unit
/// quaternion body -> world (w, x, y, z), v (3) world velocity of the body origin [m/s],
/// w (3) angular velocity in body axes [rad/s].
///
/// The combined body is the cabin plus point masses (the node-0 masses of the cables,
/// docs/model.md "One cable", boundary nodes) at body-frame points; its mass properties are
/// computed by cdpr_cabin_init.
/// Memory: caller-owned, fixed size, no resources; no function allocates. Pointer arguments
/// must be valid unless a function says it checks them.
#ifndef CDPR_CABIN_H
#define CDPR_CABIN_H

#include "cdpr/config.h"
#include "cdpr/status.h"
#include "cdpr/vec3.h"

/// Offsets inside the cabin's 13-component state block.
enum { CDPR_CABIN_P = 0, CDPR_CABIN_Q = 3, CDPR_CABIN_V = 7, CDPR_CABIN_W = 10 };

/// Cabin rigid-body parameters (inputs).
typedef struct {
    cdpr_real_t mass_kg;           ///< cabin mass M [kg] (> 0); default 40
    cdpr_vec3_t com_body_m;        ///< centre of mass c in body axes [m]; default 0
    cdpr_mat3_t inertia_com_kg_m2; ///< inertia about c, body axes [kg m^2] (symmetric, > 0)
} cdpr_cabin_params_t;

/// Combined mass properties (outputs of init; read-only).
typedef struct {
    cdpr_cabin_params_t p;     ///< the cabin alone
    cdpr_real_t mass_kg;       ///< combined mass [kg]
    cdpr_vec3_t com_body_m;    ///< combined centre of mass, body axes [m]
    cdpr_mat3_t inertia_kg_m2; ///< combined inertia about the combined CoM, body axes
    cdpr_mat3_t inv_inertia;   ///< its inverse [1/(kg m^2)]
} cdpr_cabin_t;

/// Pose and motion of the cabin (input to the prescribed mode, output of conversions).
typedef struct {
    cdpr_vec3_t p_m;         ///< body origin, world [m]
    cdpr_quat_t q;           ///< body -> world
    cdpr_vec3_t v_m_per_s;   ///< body-origin velocity, world [m/s]
    cdpr_vec3_t w_rad_per_s; ///< angular velocity, body axes [rad/s]
} cdpr_cabin_motion_t;

/// Defaults of docs/robots.md set A (`paper-50m`): 40 kg, CoM at the body origin,
/// diag(45, 45, 90) kg m^2. O(1), cannot fail.
void cdpr_cabin_params_default(cdpr_cabin_params_t *p);

/// Check every field. O(1). Returns, for the first bad field (`diag`, may be NULL, names it;
/// index -1 unless given):
/// - CDPR_E_INVALID_ARG: p is NULL ("cabin").
/// - CDPR_E_NOT_FINITE: mass ("cabin.mass_kg"), CoM ("cabin.com_body_m") or an inertia entry
///   ("cabin.inertia_com_kg_m2", index 3 row + column) is NaN/Inf.
/// - CDPR_E_NOT_POSITIVE: mass <= 0 ("cabin.mass_kg"); inertia not positive definite
///   ("cabin.inertia_com_kg_m2").
/// - CDPR_E_OUT_OF_RANGE: inertia not symmetric, |I_ij - I_ji| > 1e-6 (|I_00| + |I_11| + |I_22|)
///   ("cabin.inertia_com_kg_m2", index 3 i + j of the upper entry, i < j).
/// CDPR_OK (diag: status OK, field "", index -1) otherwise.
cdpr_status_t cdpr_cabin_params_validate(const cdpr_cabin_params_t *p, cdpr_diag_t *diag);

/// Combine the cabin with `n_points` point masses `m_kg[i]` at body points `b_m[i]`.
/// Validates everything first; on error `cab` is not written. O(n_points). Returns:
/// - CDPR_E_INVALID_ARG: cab is NULL, n_points < 0, or m_kg/b_m is NULL while n_points > 0
///   ("cabin").
/// - every error of cdpr_cabin_params_validate for p.
/// - CDPR_E_NOT_FINITE: a point mass ("point_mass_kg") or position ("point_body_m") is NaN/Inf
///   (index i); CDPR_E_OUT_OF_RANGE: a point mass < 0 ("point_mass_kg", index i).
/// - CDPR_E_NOT_POSITIVE: the combined inertia has a zero or NaN determinant
///   ("cabin.inertia_com_kg_m2"; not reached once p passed validation, barring overflow).
/// CDPR_OK otherwise.
cdpr_status_t cdpr_cabin_init(cdpr_cabin_t *cab, const cdpr_cabin_params_t *p, int n_points,
                              const cdpr_real_t *m_kg, const cdpr_vec3_t *b_m, cdpr_diag_t *diag);

/// Read the motion out of a 13-component state block (q as stored, not normalised). O(1),
/// cannot fail.
void cdpr_cabin_get_motion(const cdpr_real_t *y, cdpr_cabin_motion_t *m);

/// Motion at rest at `pose` = (x, y, z [m], alpha, beta, gamma [rad]), R = Rz(gamma) Ry(beta)
/// Rx(alpha) (cdpr_quat_from_euler); velocities zero. O(1); no allocation; cannot fail.
cdpr_cabin_motion_t cdpr_cabin_motion_at_pose(const cdpr_real_t pose[6]);

/// Write a motion into a 13-component state block. O(1), cannot fail.
void cdpr_cabin_set_motion(const cdpr_cabin_motion_t *m, cdpr_real_t *y);

/// Rigid-body RHS (docs/model.md "Cabin"). `force_world_N`: sum of all forces on the combined
/// body except gravity (cables, external); `torque_body_Nm`: their moment about the combined
/// CoM in body axes. Writes d/dt of the 13-component block; the rotation uses the normalised
/// q, q_dot the stored one. O(1), cannot fail (NaN/Inf in the inputs propagate to dydt).
void cdpr_cabin_rhs(const cdpr_cabin_t *cab, const cdpr_real_t *y, cdpr_vec3_t force_world_N,
                    cdpr_vec3_t torque_body_Nm, cdpr_real_t g_m_per_s2, cdpr_real_t *dydt);

#endif /* CDPR_CABIN_H */
