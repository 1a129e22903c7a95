/* SPDX-License-Identifier: BSD-3-Clause */
/// @file alloc_count_target.c
/// The allocation counter's interface for bare-metal test builds, where it cannot count.
///
/// tests/support/alloc_count.c replaces glibc's malloc; newlib on a target has no such hook
/// and the core must not reference an allocator there at all. So counting is reported as
/// unavailable and the allocation test cases are IGNOREd with the reason below; the
/// core_symbols test proves the stronger property on the cross-built libcdpr_core.a.
#include "alloc_count.h"

void cdpr_alloc_reset(void) {}

unsigned long cdpr_alloc_count(void)
{
    return 0UL;
}

unsigned long cdpr_alloc_count_total(void)
{
    return 0UL;
}

int cdpr_alloc_counting_available(void)
{
    return 0;
}

const char *cdpr_alloc_unavailable_reason(void)
{
    return "no malloc interposer on a bare-metal target (core_symbols: no allocator referenced)";
}
