/* SPDX-License-Identifier: BSD-3-Clause */
/// @file clock.c
/// Wall-clock helper (clock.h).
#include "cdpr/host/clock.h"

#include <time.h>

double cdpr_clock_now_s(void)
{
    struct timespec ts;
    if (clock_gettime(CLOCK_MONOTONIC, &ts) != 0) {
        return 0.0;
    }
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}
