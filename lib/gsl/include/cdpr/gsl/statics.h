/* SPDX-License-Identifier: BSD-3-Clause */
/// @file statics.h
/// Reference solver for the sag-aware inverse kinematics with GSL's multidimensional root
/// finder, as an independent check of cdpr_statics_ik (statics.h).
///
/// Formulation (different from the core's nested Newton): all 18 unknowns at once —
/// (H_j, V_j, L_j) for the six cables — against 18 equations: the 6-component cabin wrench and,
/// per cable, the two catenary span equations. Solved by gsl_multiroot_fsolver_hybrids (Powell's
/// hybrid method with a finite-difference Jacobian). Host only; links GSL (GPL-3) and allocates.
#ifndef CDPR_GSL_STATICS_H
#define CDPR_GSL_STATICS_H

#include "cdpr/robot.h"
#include "cdpr/statics.h"
#include "cdpr/status.h"

#ifdef CDPR_REAL_IS_FLOAT
#error "cdpr_gsl needs cdpr_real_t == double: build it without CDPR_REAL_IS_FLOAT"
#endif

/// Solve the inverse kinematics at `pose` (6 cables). The starting point is the massless
/// solution (chord tensions from a GSL LU solve of the same load). Fills res->cable[j] (H, V,
/// L, tensions, force, attachment) and res->iterations. CDPR_E_NO_CONVERGENCE after
/// `max_iter` iterations or when GSL stalls; CDPR_E_INFEASIBLE when the massless start does
/// not exist or the root has a non-positive H.
cdpr_status_t cdpr_gsl_statics_ik(const cdpr_robot_t *r, const cdpr_cabin_motion_t *pose,
                                  int max_iter, cdpr_statics_result_t *res);

/// The same with an external wrench on the cabin, as cdpr_statics_ik_wrench defines it: force
/// f_ext_N at the cabin's centre of mass and torque tau_ext_Nm about it, world axes; the
/// wrench equations become sum F_j - M g z + f_ext = 0, sum (R (b_j - c)) x F_j + tau_ext = 0.
cdpr_status_t cdpr_gsl_statics_ik_wrench(const cdpr_robot_t *r, const cdpr_cabin_motion_t *pose,
                                         cdpr_vec3_t f_ext_N, cdpr_vec3_t tau_ext_Nm, int max_iter,
                                         cdpr_statics_result_t *res);

#endif /* CDPR_GSL_STATICS_H */
