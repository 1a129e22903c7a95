/* SPDX-License-Identifier: BSD-3-Clause */
/// @file config.h
/// Compile-time configuration of the cdpr core: the real type and the capacities.
///
/// The capacities and the real type are those the library was built with (the CMake options
/// CDPR_MAX_CABLES, CDPR_MAX_SEGMENTS, CDPR_REAL_FLOAT, recorded in the generated
/// cdpr/build_config.h). Objects declared by the caller (`cdpr_robot_t`, ...) are sized by
/// them; nothing is allocated at run time. A compilation that defines another value than the
/// library's (-DCDPR_MAX_SEGMENTS=16 against a library built with 64, -DCDPR_REAL_IS_FLOAT
/// against a double library or its absence against a float one) stops here with an error that
/// names both values: its objects would not have the library's layout. Build the library with the
/// capacities you need instead. Defining CDPR_CAPACITY_UNCHECKED turns the check off, for programs
/// that compile the core's headers or sources at other capacities without linking the library (size
/// and stack measurements); the capacities then default to 6 cables and 64 segments.
#ifndef CDPR_CONFIG_H
#define CDPR_CONFIG_H

#ifndef CDPR_CAPACITY_UNCHECKED
#include "cdpr/build_config.h"
/* On a mismatch, two declarations of one array with the library's and this compilation's
 * capacity: the compiler's message names both values ("char[16]" vs "char[64]"). */
#if defined(CDPR_MAX_CABLES) && (CDPR_MAX_CABLES != CDPR_BUILD_MAX_CABLES)
#error "CDPR_MAX_CABLES differs from the value libcdpr_core was built with (cdpr/build_config.h)"
extern char cdpr_max_cables_of_the_library[CDPR_BUILD_MAX_CABLES];
extern char cdpr_max_cables_of_the_library[CDPR_MAX_CABLES];
#endif
#if defined(CDPR_MAX_SEGMENTS) && (CDPR_MAX_SEGMENTS != CDPR_BUILD_MAX_SEGMENTS)
#error "CDPR_MAX_SEGMENTS differs from the value libcdpr_core was built with (cdpr/build_config.h)"
extern char cdpr_max_segments_of_the_library[CDPR_BUILD_MAX_SEGMENTS];
extern char cdpr_max_segments_of_the_library[CDPR_MAX_SEGMENTS];
#endif
#if defined(CDPR_REAL_IS_FLOAT) && (CDPR_BUILD_REAL_IS_FLOAT == 0)
#error "CDPR_REAL_IS_FLOAT (float) is defined here but libcdpr_core was built in double"
#endif
#if !defined(CDPR_REAL_IS_FLOAT) && (CDPR_BUILD_REAL_IS_FLOAT != 0)
#error "libcdpr_core was built in float: define CDPR_REAL_IS_FLOAT (cdpr::core and cdpr-core.pc do)"
#endif
#ifndef CDPR_MAX_CABLES
#define CDPR_MAX_CABLES CDPR_BUILD_MAX_CABLES
#endif
#ifndef CDPR_MAX_SEGMENTS
#define CDPR_MAX_SEGMENTS CDPR_BUILD_MAX_SEGMENTS
#endif
#endif /* CDPR_CAPACITY_UNCHECKED */

/// Real type of the whole core. `double` by default; define CDPR_REAL_IS_FLOAT for `float`
/// (single-precision FPUs such as the Cortex-M4). Literals go through CDPR_R() so a float
/// build never promotes to double silently (-Wdouble-promotion stays clean).
#ifdef CDPR_REAL_IS_FLOAT
typedef float cdpr_real_t;
#define CDPR_R(x)     (x##f)
#define CDPR_SQRT     sqrtf
#define CDPR_FABS     fabsf
#define CDPR_POW      powf
#define CDPR_SIN      sinf
#define CDPR_COS      cosf
#define CDPR_ATAN2    atan2f
#define CDPR_ASIN     asinf
#define CDPR_LOG      logf
#define CDPR_EXP      expf
#define CDPR_SINH     sinhf
#define CDPR_COSH     coshf
#define CDPR_ASINH    asinhf
#define CDPR_FLOOR    floorf
#define CDPR_FMOD     fmodf
#define CDPR_FMAX     fmaxf
#define CDPR_COPYSIGN copysignf
#define CDPR_EPS      (1.1920929e-07f)
#else
typedef double cdpr_real_t;
#define CDPR_R(x)     (x)
#define CDPR_SQRT     sqrt
#define CDPR_FABS     fabs
#define CDPR_POW      pow
#define CDPR_SIN      sin
#define CDPR_COS      cos
#define CDPR_ATAN2    atan2
#define CDPR_ASIN     asin
#define CDPR_LOG      log
#define CDPR_EXP      exp
#define CDPR_SINH     sinh
#define CDPR_COSH     cosh
#define CDPR_ASINH    asinh
#define CDPR_FLOOR    floor
#define CDPR_FMOD     fmod
#define CDPR_FMAX     fmax
#define CDPR_COPYSIGN copysign
#define CDPR_EPS      (2.220446049250313e-16)
#endif

/// Maximum number of cables of one robot (the library's, see above).
#ifndef CDPR_MAX_CABLES
#define CDPR_MAX_CABLES 6
#endif
#if (CDPR_MAX_CABLES < 1) || (CDPR_MAX_CABLES > 16)
#error "CDPR_MAX_CABLES must be in [1, 16]"
#endif

/// Maximum number of segments of one cable (nodes = segments + 1; the library's).
#ifndef CDPR_MAX_SEGMENTS
#define CDPR_MAX_SEGMENTS 64
#endif
#if (CDPR_MAX_SEGMENTS < 2) || (CDPR_MAX_SEGMENTS > 4096)
#error "CDPR_MAX_SEGMENTS must be in [2, 4096]"
#endif

/// State components of one cable at capacity: payout length + positions and velocities of the
/// free nodes 1..n-1.
#define CDPR_CABLE_STATE_MAX (1 + 6 * (CDPR_MAX_SEGMENTS - 1))

/// State components of the cabin: position (3), quaternion (4), velocity (3), body rate (3).
#define CDPR_CABIN_STATE_DIM 13

/// Maximum dimension of the robot state vector.
#define CDPR_ROBOT_STATE_MAX (CDPR_CABIN_STATE_DIM + CDPR_MAX_CABLES * CDPR_CABLE_STATE_MAX)

/// pi to double precision, for every layer (wrap with CDPR_R()-free casts where float is
/// meant: `(cdpr_real_t)CDPR_PI`).
#define CDPR_PI 3.14159265358979323846

#endif /* CDPR_CONFIG_H */
