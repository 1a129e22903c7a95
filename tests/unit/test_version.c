/* SPDX-License-Identifier: BSD-3-Clause */
/// @file test_version.c
/// The version header (cdpr/version.h, generated from cmake/version.h.in) and cdpr_version():
/// the library reports the header's version, and both are the project's version
/// (cmake/CdprVersion.cmake, passed by tests/CMakeLists.txt as CDPR_TEST_VERSION*).
#include "unity.h"

#include "cdpr/version.h"

#include <stdio.h>
#include <string.h>

#if !defined(CDPR_TEST_VERSION) || !defined(CDPR_TEST_VERSION_MAJOR) ||                            \
    !defined(CDPR_TEST_VERSION_MINOR) || !defined(CDPR_TEST_VERSION_PATCH)
#error "tests/CMakeLists.txt passes the project's version as CDPR_TEST_VERSION*"
#endif

void setUp(void) {}

void tearDown(void) {}

static void test_library_reports_the_header_version(void)
{
    const char *v = cdpr_version();
    TEST_ASSERT_NOT_NULL(v);
    TEST_ASSERT_EQUAL_STRING(CDPR_VERSION_STRING, v);
}

static void test_macros_are_the_project_version(void)
{
    char joined[32];
    TEST_ASSERT_EQUAL_INT(CDPR_TEST_VERSION_MAJOR, CDPR_VERSION_MAJOR);
    TEST_ASSERT_EQUAL_INT(CDPR_TEST_VERSION_MINOR, CDPR_VERSION_MINOR);
    TEST_ASSERT_EQUAL_INT(CDPR_TEST_VERSION_PATCH, CDPR_VERSION_PATCH);
    TEST_ASSERT_EQUAL_STRING(CDPR_TEST_VERSION, CDPR_VERSION_STRING);
    /* The string is the three numbers. */
    (void)snprintf(joined, sizeof joined, "%d.%d.%d", CDPR_VERSION_MAJOR, CDPR_VERSION_MINOR,
                   CDPR_VERSION_PATCH);
    TEST_ASSERT_EQUAL_STRING(joined, CDPR_VERSION_STRING);
}

static void test_git_describe_is_set(void)
{
    /* A description (`git describe --always --dirty`) or "unknown"; never empty. */
    TEST_ASSERT_TRUE(strlen(CDPR_GIT_DESCRIBE) > 0u);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_library_reports_the_header_version);
    RUN_TEST(test_macros_are_the_project_version);
    RUN_TEST(test_git_describe_is_set);
    return UNITY_END() ? 1 : 0;
}
