/* SPDX-License-Identifier: BSD-3-Clause */
/// @file test_alloc_count.c
/// Self-test of tests/support/alloc_count.c: the counter must see the allocations the other
/// tests rely on it to catch.
#include "unity.h"

#include "alloc_count.h"

#include <stdlib.h>

// Stored through a volatile pointer so the compiler cannot elide a malloc/free pair whose
// result is otherwise unused (GCC removes such pairs at -O2).
static void *volatile sink;

#define SKIP_IF_UNAVAILABLE()                                                                      \
    do {                                                                                           \
        if (!cdpr_alloc_counting_available()) {                                                    \
            TEST_IGNORE_MESSAGE("allocation counting is compiled out under AddressSanitizer");     \
        }                                                                                          \
    } while (0)

void setUp(void)
{
    cdpr_alloc_reset();
}

void tearDown(void)
{
    free(sink);
    sink = NULL;
}

static void test_nothing_counted_without_allocation(void)
{
    SKIP_IF_UNAVAILABLE();
    TEST_ASSERT_EQUAL_UINT(0u, cdpr_alloc_count());
    TEST_ASSERT_EQUAL_UINT(0u, cdpr_alloc_count_total());
}

static void test_malloc_is_counted(void)
{
    SKIP_IF_UNAVAILABLE();
    sink = malloc(32);
    TEST_ASSERT_NOT_NULL(sink);
    TEST_ASSERT_EQUAL_UINT(1u, cdpr_alloc_count());
    TEST_ASSERT_EQUAL_UINT(1u, cdpr_alloc_count_total());
}

static void test_calloc_is_counted(void)
{
    SKIP_IF_UNAVAILABLE();
    sink = calloc(4, 8);
    TEST_ASSERT_NOT_NULL(sink);
    TEST_ASSERT_EQUAL_UINT(1u, cdpr_alloc_count());
    TEST_ASSERT_EQUAL_UINT(1u, cdpr_alloc_count_total());
}

static void test_free_is_not_counted(void)
{
    SKIP_IF_UNAVAILABLE();
    sink = malloc(16);
    free(sink);
    sink = NULL;
    TEST_ASSERT_EQUAL_UINT(1u, cdpr_alloc_count());
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_nothing_counted_without_allocation);
    RUN_TEST(test_malloc_is_counted);
    RUN_TEST(test_calloc_is_counted);
    RUN_TEST(test_free_is_not_counted);
    return UNITY_END() ? 1 : 0;
}
