/* SPDX-License-Identifier: BSD-3-Clause */
/// @file alloc_count.c
/// Counting replacements for the C allocation functions (test executables only).
///
/// glibc allows a program to define malloc & co. itself; every caller in the process,
/// glibc's own internal callers included, then reaches these definitions. They count and
/// forward to glibc's real allocator through its exported __libc_* entry points, so
/// every pointer still comes from, and goes back to, the one glibc heap.
///
/// This file is host-only and deliberately uses GNU extensions: the __thread keyword
/// (C99 has no thread-local storage) and the __atomic builtins.

// Needed for the prototypes of posix_memalign and aligned_alloc (POSIX / C11) under -std=c99.
#define _GNU_SOURCE

#include "alloc_count.h"

#include <errno.h>
#include <stddef.h>
#include <stdlib.h>

// AddressSanitizer interposes malloc itself and must see every allocation; defining our own
// would bypass it (and crash when ASan-owned pointers reach glibc's free). GCC announces ASan
// with __SANITIZE_ADDRESS__, clang with __has_feature.
#if defined(__SANITIZE_ADDRESS__)
#define CDPR_ALLOC_UNDER_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define CDPR_ALLOC_UNDER_ASAN 1
#endif
#endif

// Per thread: a test measuring one code path is not disturbed by allocations in other
// threads (e.g. a publisher thread). Process-wide: catches work handed off to other threads.
static __thread unsigned long thread_count;
static unsigned long total_count; // only accessed with __atomic builtins

#ifndef CDPR_ALLOC_UNDER_ASAN

// glibc's allocator entry points (exported by libc.so.6, not declared in any header).
extern void *__libc_malloc(size_t size);
extern void *__libc_calloc(size_t nmemb, size_t size);
extern void *__libc_realloc(void *ptr, size_t size);
extern void __libc_free(void *ptr);
extern void *__libc_memalign(size_t alignment, size_t size);

static void count_allocation(void)
{
    thread_count++;
    (void)__atomic_fetch_add(&total_count, 1UL, __ATOMIC_RELAXED);
}

static int is_power_of_two(size_t x)
{
    return x != 0u && (x & (x - 1u)) == 0u;
}

void *malloc(size_t size)
{
    count_allocation();
    return __libc_malloc(size);
}

void *calloc(size_t nmemb, size_t size)
{
    count_allocation();
    return __libc_calloc(nmemb, size);
}

void *realloc(void *ptr, size_t size)
{
    // Counted whether it grows, shrinks or moves: any realloc is heap traffic.
    count_allocation();
    return __libc_realloc(ptr, size);
}

void free(void *ptr)
{
    __libc_free(ptr);
}

int posix_memalign(void **memptr, size_t alignment, size_t size)
{
    void *p;

    count_allocation();
    // POSIX: the alignment must be a power of two and a multiple of sizeof(void *).
    if (!is_power_of_two(alignment) || alignment % sizeof(void *) != 0u) {
        return EINVAL;
    }
    p = __libc_memalign(alignment, size);
    if (p == NULL) {
        return ENOMEM;
    }
    *memptr = p;
    return 0;
}

void *aligned_alloc(size_t alignment, size_t size)
{
    count_allocation();
    if (!is_power_of_two(alignment)) {
        errno = EINVAL;
        return NULL;
    }
    return __libc_memalign(alignment, size);
}

#endif // CDPR_ALLOC_UNDER_ASAN

void cdpr_alloc_reset(void)
{
    thread_count = 0;
    __atomic_store_n(&total_count, 0UL, __ATOMIC_RELAXED);
}

unsigned long cdpr_alloc_count(void)
{
    return thread_count;
}

unsigned long cdpr_alloc_count_total(void)
{
    return __atomic_load_n(&total_count, __ATOMIC_RELAXED);
}

int cdpr_alloc_counting_available(void)
{
#ifdef CDPR_ALLOC_UNDER_ASAN
    return 0;
#else
    return 1;
#endif
}

const char *cdpr_alloc_unavailable_reason(void)
{
    return "allocation counting is compiled out under AddressSanitizer";
}
