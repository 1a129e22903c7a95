/* SPDX-License-Identifier: BSD-3-Clause */
/// @file clock.h
/// Wall-clock helper of the host tools (progress, run times; never the plant's time).
#ifndef CDPR_HOST_CLOCK_H
#define CDPR_HOST_CLOCK_H

/// Seconds on CLOCK_MONOTONIC (an arbitrary origin: use differences). O(1); no allocation;
/// cannot fail on Linux (returns 0 if the clock is unavailable).
double cdpr_clock_now_s(void);

#endif /* CDPR_HOST_CLOCK_H */
