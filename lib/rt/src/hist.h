/* SPDX-License-Identifier: BSD-3-Clause */
/// @file hist.h
/// The real-time nodes' time histograms (1 µs bins 0 .. top - 1, bin top for everything
/// above): the bin in which the q-quantile of `total` samples falls (internal to lib/rt).
#ifndef CDPR_RT_HIST_H
#define CDPR_RT_HIST_H

#include <math.h>
#include <stdint.h>

/// Bin index (0 .. top) of the q-quantile; 0 when total is 0.
static inline int cdpr_rt_hist_quantile_bin(const uint32_t *hist, int top, uint64_t total, double q)
{
    if (total == 0) {
        return 0;
    }
    const uint64_t want = (uint64_t)ceil(q * (double)total);
    uint64_t acc = 0;
    for (int i = 0; i < top; ++i) {
        acc += hist[i];
        if (acc >= want) {
            return i;
        }
    }
    return top;
}

#endif /* CDPR_RT_HIST_H */
