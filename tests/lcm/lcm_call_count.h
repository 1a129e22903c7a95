/* SPDX-License-Identifier: BSD-3-Clause */
/// @file lcm_call_count.h
/// Counts liblcm calls per thread in a test executable (tests/lcm only).
///
/// The test is linked with `-Wl,--wrap=<fn>` for each function below (see CMakeLists.txt):
/// every call to <fn> from our libraries and the test then reaches __wrap_<fn>, which counts
/// it for the calling thread and forwards to liblcm's __real_<fn>. liblcm's internal calls
/// are not counted (they are resolved inside liblcm.so).
#ifndef CDPR_LCM_CALL_COUNT_H
#define CDPR_LCM_CALL_COUNT_H

#include <lcm/lcm.h>

/// lcm_* calls made by the calling thread since its last cdpr_lcm_calls_reset().
unsigned long cdpr_lcm_calls(void);

/// lcm_* calls made by all threads since the last reset.
unsigned long cdpr_lcm_calls_total(void);

/// Zero the calling thread's and the process-wide counters.
void cdpr_lcm_calls_reset(void);

lcm_t *__wrap_lcm_create(const char *provider);
void __wrap_lcm_destroy(lcm_t *lcm);
int __wrap_lcm_get_fileno(lcm_t *lcm);
lcm_subscription_t *__wrap_lcm_subscribe(lcm_t *lcm, const char *channel, lcm_msg_handler_t handler,
                                         void *userdata);
int __wrap_lcm_unsubscribe(lcm_t *lcm, lcm_subscription_t *handler);
int __wrap_lcm_publish(lcm_t *lcm, const char *channel, const void *data, unsigned int datalen);
int __wrap_lcm_handle(lcm_t *lcm);
int __wrap_lcm_handle_timeout(lcm_t *lcm, int timeout_millis);

#endif
