/// @file test_cli.c
/// Command-line numbers (cli.h): the status of every kind of argument, *out only on success.
#include <math.h>

#include "cdpr/host/cli.h"
#include "unity.h"

void setUp(void) {}
void tearDown(void) {}

/* cdpr_cli_number on [lo, hi] = [1, 100]; *out starts at -7 (kept unless CDPR_OK). */
static cdpr_status_t number(const char *arg, double *out)
{
    *out = -7.0;
    return cdpr_cli_number("test_cli", "opt", arg, 1.0, 100.0, out);
}

static void test_valid_numbers(void)
{
    double v;
    TEST_ASSERT_EQUAL_INT(CDPR_OK, number("42", &v));
    TEST_ASSERT_EQUAL_DOUBLE(42.0, v);
    TEST_ASSERT_EQUAL_INT(CDPR_OK, number("1", &v)); /* both ends are inside */
    TEST_ASSERT_EQUAL_DOUBLE(1.0, v);
    TEST_ASSERT_EQUAL_INT(CDPR_OK, number("1e2", &v));
    TEST_ASSERT_EQUAL_DOUBLE(100.0, v);
    TEST_ASSERT_EQUAL_INT(CDPR_OK, number("2.5", &v));
    TEST_ASSERT_EQUAL_DOUBLE(2.5, v);
}

static void test_out_of_range(void)
{
    double v;
    TEST_ASSERT_EQUAL_INT(CDPR_E_OUT_OF_RANGE, number("0.5", &v));
    TEST_ASSERT_EQUAL_DOUBLE(-7.0, v);
    TEST_ASSERT_EQUAL_INT(CDPR_E_OUT_OF_RANGE, number("100.5", &v));
    TEST_ASSERT_EQUAL_INT(CDPR_E_OUT_OF_RANGE, number("-3", &v));
    TEST_ASSERT_EQUAL_INT(CDPR_E_OUT_OF_RANGE, number("1e999", &v)); /* beyond a double */
    TEST_ASSERT_EQUAL_DOUBLE(-7.0, v);
}

static void test_not_a_number(void)
{
    double v;
    TEST_ASSERT_EQUAL_INT(CDPR_E_INVALID_ARG, number("", &v));
    TEST_ASSERT_EQUAL_INT(CDPR_E_INVALID_ARG, number("abc", &v));
    TEST_ASSERT_EQUAL_INT(CDPR_E_INVALID_ARG, number("12x", &v)); /* trailing garbage */
    TEST_ASSERT_EQUAL_INT(CDPR_E_INVALID_ARG, number("12 ", &v));
    TEST_ASSERT_EQUAL_INT(CDPR_E_INVALID_ARG, number("5,5", &v));
    TEST_ASSERT_EQUAL_DOUBLE(-7.0, v);
}

static void test_nan_and_inf(void)
{
    double v;
    TEST_ASSERT_EQUAL_INT(CDPR_E_NOT_FINITE, number("nan", &v));
    TEST_ASSERT_EQUAL_INT(CDPR_E_NOT_FINITE, number("inf", &v));
    TEST_ASSERT_EQUAL_INT(CDPR_E_NOT_FINITE, number("-Infinity", &v));
    TEST_ASSERT_EQUAL_DOUBLE(-7.0, v);
    /* Any finite number, for options whose range is checked where they are used. */
    TEST_ASSERT_EQUAL_INT(CDPR_E_NOT_FINITE, cdpr_cli_real("test_cli", "opt", "nan", &v));
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_cli_real("test_cli", "opt", "-1e300", &v));
    TEST_ASSERT_EQUAL_DOUBLE(-1e300, v);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_valid_numbers);
    RUN_TEST(test_out_of_range);
    RUN_TEST(test_not_a_number);
    RUN_TEST(test_nan_and_inf);
    return UNITY_END() ? 1 : 0;
}
