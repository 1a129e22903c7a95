/* SPDX-License-Identifier: BSD-3-Clause */
/// @file alloc_count.h
/// Heap allocation counter for the host unit tests.
///
/// Linking tests/support/alloc_count.c into a test executable replaces malloc, calloc,
/// realloc, free, posix_memalign and aligned_alloc with thin wrappers that count and then
/// forward to glibc's allocator. Tests use it to prove that a code path makes no heap
/// allocation. Host (glibc) only.
#ifndef CDPR_ALLOC_COUNT_H
#define CDPR_ALLOC_COUNT_H

/// Sets the calling thread's counter and the process-wide counter to zero.
/// Other threads' own counters are not touched.
void cdpr_alloc_reset(void);

/// Allocating calls (malloc, calloc, realloc, posix_memalign, aligned_alloc) made by the
/// calling thread since its last cdpr_alloc_reset(). free() is not counted.
unsigned long cdpr_alloc_count(void);

/// Allocating calls made by all threads since the last cdpr_alloc_reset().
unsigned long cdpr_alloc_count_total(void);

/// 1 when the counter works; 0 when it is compiled out because AddressSanitizer owns malloc
/// (then both counts stay 0 and tests should TEST_IGNORE_MESSAGE with that reason).
int cdpr_alloc_counting_available(void);

/// Why counting is unavailable (for TEST_IGNORE_MESSAGE): AddressSanitizer on the host, or a
/// bare-metal target build (tests/target/alloc_count_target.c). Never NULL.
const char *cdpr_alloc_unavailable_reason(void);

#endif
