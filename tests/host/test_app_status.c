/* SPDX-License-Identifier: BSD-3-Clause */
/// @file test_app_status.c
/// The apps' one status -> exit-code table (apps/common/app_status.h) against its documented
/// values, written out here independently: every status of cdpr/status.h, and an unknown one.
#include "app_status.h"
#include "unity.h"

void setUp(void) {}
void tearDown(void) {}

static void test_every_status_has_its_documented_exit_code(void)
{
    static const struct {
        cdpr_status_t st;
        int code;
    } table[] = {
        {CDPR_OK, 0},
        {CDPR_WARN_SUBSTEP_LIMIT, 0},
        {CDPR_WARN_CAPACITY, 0},
        {CDPR_WARN_MIN_LENGTH, 0},
        {CDPR_E_INTERRUPTED, 1},
        {CDPR_E_MISMATCH, 1},
        {CDPR_E_STATE_NOT_FINITE, 1},
        {CDPR_E_STEP_TOO_SMALL, 1},
        {CDPR_E_RHS, 1},
        {CDPR_E_SUBSTEP_LIMIT, 1},
        {CDPR_E_SINGULAR, 1},
        {CDPR_E_INVALID_ARG, 2},
        {CDPR_E_NOT_FINITE, 2},
        {CDPR_E_NOT_POSITIVE, 2},
        {CDPR_E_OUT_OF_RANGE, 2},
        {CDPR_E_CAPACITY, 2},
        {CDPR_E_GEOMETRY, 2},
        {CDPR_E_NO_CONVERGENCE, 2},
        {CDPR_E_INFEASIBLE, 2},
        {CDPR_E_PARSE, 2},
        {CDPR_E_IO, 3},
        {CDPR_E_CONFLICT, 5},
    };
    /* Every value from CDPR_E_CONFLICT (-18) to CDPR_WARN_MIN_LENGTH (3) is listed. */
    TEST_ASSERT_EQUAL_INT(22, (int)(sizeof table / sizeof table[0]));
    for (size_t i = 0; i < sizeof table / sizeof table[0]; ++i) {
        TEST_ASSERT_EQUAL_INT_MESSAGE(table[i].code, cdpr_app_exit_code(table[i].st),
                                      cdpr_status_str(table[i].st));
    }
}

static void test_an_unknown_status_is_exit_4(void)
{
    TEST_ASSERT_EQUAL_INT(4, cdpr_app_exit_code((cdpr_status_t)-19));
    TEST_ASSERT_EQUAL_INT(4, cdpr_app_exit_code((cdpr_status_t)4));
    TEST_ASSERT_EQUAL_INT(4, cdpr_app_exit_code((cdpr_status_t)-1000));
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_every_status_has_its_documented_exit_code);
    RUN_TEST(test_an_unknown_status_is_exit_4);
    return UNITY_END() ? 1 : 0;
}
