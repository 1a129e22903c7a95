/* SPDX-License-Identifier: BSD-3-Clause */
/// @file test_real.h
/// Tolerances for the build's real type (cdpr_real_t, config.h).
///
/// The unit tests are written for the default double build. The float build (Cortex-M4,
/// CDPR_REAL_IS_FLOAT) runs the same cases; where a tolerance depends on the precision, the
/// assertion uses TOL(double_tol, float_tol). The double tolerances are never changed.
///
/// How the float tolerances are derived: a double tolerance that bounds rounding error only is
/// k u_d (times the size of the quantity), u_d = 2^-53 = 1.1e-16. The same k roundings in float
/// cost k u_f, u_f = 2^-24 = 6.0e-8 (FLT_EPSILON = 1.2e-7 = 2 u_f): the tolerance scales by
/// u_f / u_d = 2^29 = 5.4e8, rounded up here to one significant digit (1e-14 -> 6e-6). The
/// tests pass their inputs as double literals; rounding those to float adds u_f per input times
/// the problem's condition number, which the same k covers unless a comment at the assertion
/// says otherwise. Tolerances that bound truncation or discretisation error (integrator
/// tolerances, grid convergence) do not scale this way: those are argued where they are used,
/// or the case is skipped in the float build with SKIP_IN_FLOAT(reason).
#ifndef CDPR_TEST_REAL_H
#define CDPR_TEST_REAL_H

#include "cdpr/config.h"
#include "unity.h"

#include <math.h>

#ifdef CDPR_REAL_IS_FLOAT
#define TOL(double_tol, float_tol) (float_tol)
/// Ends the current test case as IGNORE, with the reason, in the float build only.
#define SKIP_IN_FLOAT(reason) TEST_IGNORE_MESSAGE("float build: " reason)
#else
#define TOL(double_tol, float_tol) (double_tol)
#define SKIP_IN_FLOAT(reason)      ((void)0)
#endif

/// Unit round-off of cdpr_real_t: 2^-53 (double) or 2^-24 (float).
#define U_REAL (0.5 * (double)CDPR_EPS)

/// NaN and +infinity typed for what they initialise: double (_D) or cdpr_real_t (_R).
/// <math.h>'s NAN and INFINITY are float constants, so where a double is meant they are an
/// implicit float -> double promotion, which clang's -Wdouble-promotion reports (GCC 12's
/// does not). The conversions are exact; the types just say what is meant.
#define NAN_D ((double)NAN)
#define INF_D ((double)INFINITY)
#define NAN_R ((cdpr_real_t)NAN)
#define INF_R ((cdpr_real_t)INFINITY)

#endif /* CDPR_TEST_REAL_H */
