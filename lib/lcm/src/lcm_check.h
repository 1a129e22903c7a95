/* SPDX-License-Identifier: BSD-3-Clause */
/// @file lcm_check.h
/// Internal: a C99 compile-time assertion (no _Static_assert before C11).
#ifndef CDPR_LCM_CHECK_H
#define CDPR_LCM_CHECK_H

/// Fails to compile (negative array size) when `cond` is false; `name` says what is checked.
#define CDPR_LCM_STATIC_ASSERT(cond, name) typedef char cdpr_lcm_assert_##name[(cond) ? 1 : -1]

#endif /* CDPR_LCM_CHECK_H */
