/* SPDX-License-Identifier: BSD-3-Clause */
/// @file lcm_call_count.c
/// Per-thread counting wrappers of liblcm calls (lcm_call_count.h). GNU ld/lld --wrap.
#include "lcm_call_count.h"

lcm_t *__real_lcm_create(const char *provider);
void __real_lcm_destroy(lcm_t *lcm);
int __real_lcm_get_fileno(lcm_t *lcm);
lcm_subscription_t *__real_lcm_subscribe(lcm_t *lcm, const char *channel, lcm_msg_handler_t handler,
                                         void *userdata);
int __real_lcm_unsubscribe(lcm_t *lcm, lcm_subscription_t *handler);
int __real_lcm_publish(lcm_t *lcm, const char *channel, const void *data, unsigned int datalen);
int __real_lcm_handle(lcm_t *lcm);
int __real_lcm_handle_timeout(lcm_t *lcm, int timeout_millis);

static __thread unsigned long thread_calls; // GNU __thread: C99 has no thread-local storage
static unsigned long total_calls;           // __atomic only

static void count(void)
{
    thread_calls++;
    (void)__atomic_fetch_add(&total_calls, 1UL, __ATOMIC_RELAXED);
}

unsigned long cdpr_lcm_calls(void)
{
    return thread_calls;
}

unsigned long cdpr_lcm_calls_total(void)
{
    return __atomic_load_n(&total_calls, __ATOMIC_RELAXED);
}

void cdpr_lcm_calls_reset(void)
{
    thread_calls = 0;
    __atomic_store_n(&total_calls, 0UL, __ATOMIC_RELAXED);
}

lcm_t *__wrap_lcm_create(const char *provider)
{
    count();
    return __real_lcm_create(provider);
}

void __wrap_lcm_destroy(lcm_t *lcm)
{
    count();
    __real_lcm_destroy(lcm);
}

int __wrap_lcm_get_fileno(lcm_t *lcm)
{
    count();
    return __real_lcm_get_fileno(lcm);
}

lcm_subscription_t *__wrap_lcm_subscribe(lcm_t *lcm, const char *channel, lcm_msg_handler_t handler,
                                         void *userdata)
{
    count();
    return __real_lcm_subscribe(lcm, channel, handler, userdata);
}

int __wrap_lcm_unsubscribe(lcm_t *lcm, lcm_subscription_t *handler)
{
    count();
    return __real_lcm_unsubscribe(lcm, handler);
}

int __wrap_lcm_publish(lcm_t *lcm, const char *channel, const void *data, unsigned int datalen)
{
    count();
    return __real_lcm_publish(lcm, channel, data, datalen);
}

int __wrap_lcm_handle(lcm_t *lcm)
{
    count();
    return __real_lcm_handle(lcm);
}

int __wrap_lcm_handle_timeout(lcm_t *lcm, int timeout_millis)
{
    count();
    return __real_lcm_handle_timeout(lcm, timeout_millis);
}
