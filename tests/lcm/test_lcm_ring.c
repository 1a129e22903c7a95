/* SPDX-License-Identifier: BSD-3-Clause */
/// @file test_lcm_ring.c
/// The SPSC ring of encoded slots (lcm_ring.h): argument checks, fill to capacity, the
/// drop-newest policy and its counters, index wrap-around, claim/commit semantics, and a
/// two-thread stress test that checks every message arrives once, in order, intact.
///
/// Why these can fail: a wrong full/empty test (off by one in head - tail), a lost or double
/// count, overwriting a queued slot (drop-oldest behaviour), missing release/acquire ordering
/// (the stress test sees a slot whose bytes do not match its header), or an allocation on the
/// producer path.
#include "unity.h"

#include "alloc_count.h"
#include "cdpr/lcm/ring.h"

#include <pthread.h>
#include <sched.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

#define SLOTS      8u
#define SLOT_BYTES 24u

static uint64_t storage[CDPR_LCM_RING_STORAGE_BYTES(SLOTS, SLOT_BYTES) / sizeof(uint64_t)];
static cdpr_lcm_ring_t ring;

void setUp(void)
{
    cdpr_diag_t d;
    TEST_ASSERT_EQUAL_INT(
        CDPR_OK, cdpr_lcm_ring_init(&ring, storage, sizeof storage, SLOTS, SLOT_BYTES, &d));
}

void tearDown(void) {}

static cdpr_status_t push_u32(uint32_t v)
{
    return cdpr_lcm_ring_push(&ring, 7, &v, (int32_t)sizeof v, (int64_t)v);
}

static uint32_t pop_u32(void)
{
    const unsigned char *data = NULL;
    const cdpr_lcm_slot_t *h = cdpr_lcm_ring_peek(&ring, &data);
    uint32_t v;
    TEST_ASSERT_NOT_NULL(h);
    TEST_ASSERT_EQUAL_INT32(7, h->channel);
    TEST_ASSERT_EQUAL_INT32((int32_t)sizeof v, h->len);
    memcpy(&v, data, sizeof v);
    TEST_ASSERT_EQUAL_INT64((int64_t)v, h->seq);
    cdpr_lcm_ring_release(&ring);
    return v;
}

static void test_init_rejects_bad_arguments(void)
{
    cdpr_lcm_ring_t r;
    cdpr_diag_t d;
    unsigned char *misaligned = (unsigned char *)storage + 1;

    TEST_ASSERT_EQUAL_INT(CDPR_E_INVALID_ARG,
                          cdpr_lcm_ring_init(NULL, storage, sizeof storage, 8u, 24u, &d));
    TEST_ASSERT_EQUAL_INT(CDPR_E_INVALID_ARG,
                          cdpr_lcm_ring_init(&r, NULL, sizeof storage, 8u, 24u, &d));
    TEST_ASSERT_EQUAL_INT(CDPR_E_INVALID_ARG,
                          cdpr_lcm_ring_init(&r, misaligned, sizeof storage - 8u, 2u, 8u, &d));
    TEST_ASSERT_EQUAL_STRING("storage", d.field);
    TEST_ASSERT_EQUAL_INT(CDPR_E_OUT_OF_RANGE,
                          cdpr_lcm_ring_init(&r, storage, sizeof storage, 6u, 24u, &d));
    TEST_ASSERT_EQUAL_STRING("n_slots", d.field);
    TEST_ASSERT_EQUAL_INT(CDPR_E_OUT_OF_RANGE,
                          cdpr_lcm_ring_init(&r, storage, sizeof storage, 1u, 24u, &d));
    TEST_ASSERT_EQUAL_INT(CDPR_E_OUT_OF_RANGE,
                          cdpr_lcm_ring_init(&r, storage, sizeof storage, 8u, 4u, &d));
    TEST_ASSERT_EQUAL_STRING("slot_bytes", d.field);
    TEST_ASSERT_EQUAL_INT(CDPR_E_CAPACITY,
                          cdpr_lcm_ring_init(&r, storage, sizeof storage, 16u, 24u, &d));
    TEST_ASSERT_EQUAL_STRING("storage_bytes", d.field);
    // Slot size rounded up to 8: 20 -> 24 fits exactly the storage sized for 24.
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_lcm_ring_init(&r, storage, sizeof storage, 8u, 20u, &d));
    TEST_ASSERT_EQUAL_UINT32(24u, r.slot_bytes);
}

static void test_empty_ring_peeks_nothing(void)
{
    cdpr_lcm_ring_stats_t s;
    TEST_ASSERT_NULL(cdpr_lcm_ring_peek(&ring, NULL));
    cdpr_lcm_ring_release(&ring); // no peek: must be a no-op
    cdpr_lcm_ring_stats(&ring, &s);
    TEST_ASSERT_EQUAL_UINT64(0u, s.popped);
    TEST_ASSERT_EQUAL_UINT32(0u, s.queued);
}

// Fill to capacity, then every further push is dropped (drop-newest) and counted, and the
// queued messages come out unchanged and in order.
static void test_fill_then_drop_newest_counted(void)
{
    cdpr_lcm_ring_stats_t s;
    uint32_t i;

    for (i = 0; i < SLOTS; i++) {
        TEST_ASSERT_EQUAL_INT(CDPR_OK, push_u32(100u + i));
    }
    for (i = 0; i < 5u; i++) {
        TEST_ASSERT_EQUAL_INT(CDPR_E_CAPACITY, push_u32(900u + i));
    }
    TEST_ASSERT_NULL(cdpr_lcm_ring_claim(&ring));
    cdpr_lcm_ring_stats(&ring, &s);
    TEST_ASSERT_EQUAL_UINT64(SLOTS, s.pushed);
    TEST_ASSERT_EQUAL_UINT64(6u, s.dropped); // 5 pushes + 1 claim
    TEST_ASSERT_EQUAL_UINT32(SLOTS, s.queued);

    for (i = 0; i < SLOTS; i++) {
        TEST_ASSERT_EQUAL_UINT32(100u + i, pop_u32());
    }
    TEST_ASSERT_NULL(cdpr_lcm_ring_peek(&ring, NULL));
    cdpr_lcm_ring_stats(&ring, &s);
    TEST_ASSERT_EQUAL_UINT64(SLOTS, s.popped);
    TEST_ASSERT_EQUAL_UINT32(0u, s.queued);
    TEST_ASSERT_EQUAL_UINT32(SLOTS, s.high_water);

    // One slot freed -> exactly one push fits again.
    TEST_ASSERT_EQUAL_INT(CDPR_OK, push_u32(1u));
    TEST_ASSERT_EQUAL_UINT32(1u, pop_u32());
}

// Many times around the ring (free-running indices wrap the slot index every SLOTS pushes),
// with the occupancy varying between 1 and SLOTS.
static void test_wrap_around_keeps_order(void)
{
    uint32_t next_in = 0u;
    uint32_t next_out = 0u;
    uint32_t round;

    for (round = 0; round < 1000u; round++) {
        const uint32_t burst = 1u + round % SLOTS;
        uint32_t k;
        for (k = 0; k < burst; k++) {
            TEST_ASSERT_EQUAL_INT(CDPR_OK, push_u32(next_in++));
        }
        for (k = 0; k < burst; k++) {
            TEST_ASSERT_EQUAL_UINT32(next_out++, pop_u32());
        }
    }
    TEST_ASSERT_NULL(cdpr_lcm_ring_peek(&ring, NULL));
}

// Indices near UINT32_MAX: head - tail must stay exact across the 2^32 wrap.
static void test_index_wrap_at_uint32_max(void)
{
    uint32_t i;
    ring.head = UINT32_MAX - 3u;
    ring.tail = UINT32_MAX - 3u;
    ring.tail_cache = UINT32_MAX - 3u;
    for (i = 0; i < SLOTS; i++) {
        TEST_ASSERT_EQUAL_INT(CDPR_OK, push_u32(i));
    }
    TEST_ASSERT_EQUAL_INT(CDPR_E_CAPACITY, push_u32(99u));
    for (i = 0; i < SLOTS; i++) {
        TEST_ASSERT_EQUAL_UINT32(i, pop_u32());
    }
    TEST_ASSERT_NULL(cdpr_lcm_ring_peek(&ring, NULL));
}

static void test_claim_commit_semantics(void)
{
    unsigned char *a = cdpr_lcm_ring_claim(&ring);
    unsigned char *b = cdpr_lcm_ring_claim(&ring);
    cdpr_lcm_ring_stats_t s;

    TEST_ASSERT_NOT_NULL(a);
    TEST_ASSERT_EQUAL_PTR(a, b); // a second claim before commit returns the same slot
    TEST_ASSERT_EQUAL_INT(CDPR_E_INVALID_ARG, cdpr_lcm_ring_commit(&ring, 1, 0, 0));
    TEST_ASSERT_EQUAL_INT(CDPR_E_INVALID_ARG,
                          cdpr_lcm_ring_commit(&ring, 1, (int32_t)SLOT_BYTES + 1, 0));
    TEST_ASSERT_NULL(cdpr_lcm_ring_peek(&ring, NULL)); // nothing queued by the bad commits
    // A push now uses the open claim's slot and commits it.
    TEST_ASSERT_EQUAL_INT(CDPR_OK, push_u32(0u));
    cdpr_lcm_ring_stats(&ring, &s);
    TEST_ASSERT_EQUAL_UINT64(1u, s.pushed);
    TEST_ASSERT_EQUAL_INT(CDPR_E_INVALID_ARG, cdpr_lcm_ring_commit(&ring, 1, 4, 0)); // no claim
    TEST_ASSERT_EQUAL_INT(CDPR_E_INVALID_ARG, cdpr_lcm_ring_push(&ring, 1, "x", 0, 0));
    TEST_ASSERT_EQUAL_INT(CDPR_E_INVALID_ARG,
                          cdpr_lcm_ring_push(&ring, 1, storage, (int32_t)SLOT_BYTES + 1, 0));
    cdpr_lcm_ring_stats(&ring, &s);
    TEST_ASSERT_EQUAL_UINT64(0u, s.dropped); // invalid pushes are not drops
}

static void test_producer_path_makes_no_allocation(void)
{
    uint32_t i;
    if (!cdpr_alloc_counting_available()) {
        TEST_IGNORE_MESSAGE(cdpr_alloc_unavailable_reason());
    }
    cdpr_alloc_reset();
    for (i = 0; i < 3u * SLOTS; i++) {
        (void)push_u32(i); // fills, then drops
    }
    while (cdpr_lcm_ring_peek(&ring, NULL) != NULL) {
        cdpr_lcm_ring_release(&ring);
    }
    TEST_ASSERT_EQUAL_UINT(0u, cdpr_alloc_count());
}

/* ---------------------------------------------------------------- two-thread stress */

#define STRESS_SLOTS 64u
#define STRESS_BYTES 64u
#define STRESS_N     500000u

static uint64_t
    stress_storage[CDPR_LCM_RING_STORAGE_BYTES(STRESS_SLOTS, STRESS_BYTES) / sizeof(uint64_t)];
static cdpr_lcm_ring_t sring;
static int producer_done;
static uint64_t producer_nulls;   // claims that found the ring full (each counts a drop)
static uint64_t producer_gave_up; // messages abandoned after a full ring

// Message i: length 8 + i % 57 bytes, every byte a function of (i, position), seq = i.
static unsigned char pattern(uint32_t i, uint32_t k)
{
    return (unsigned char)((i * 2654435761u + k * 40503u) >> 13);
}

// Most messages are retried until they fit (so the two threads really exchange millions of
// slots concurrently); every 8th is abandoned at the first full ring (a real drop).
static void *producer(void *arg)
{
    uint64_t nulls = 0u;
    uint64_t gave_up = 0u;
    uint32_t i;
    (void)arg;
    for (i = 0; i < STRESS_N; i++) {
        const uint32_t len = 8u + i % 57u;
        unsigned char *slot;
        uint32_t k;
        for (;;) {
            slot = cdpr_lcm_ring_claim(&sring);
            if (slot != NULL) {
                break;
            }
            nulls++;
            if (i % 8u == 0u) {
                break;
            }
            (void)sched_yield(); // the consumer may be descheduled (busy CI machine)
        }
        if (slot == NULL) {
            gave_up++;
            continue;
        }
        for (k = 0; k < len; k++) {
            slot[k] = pattern(i, k);
        }
        (void)cdpr_lcm_ring_commit(&sring, (int32_t)(i & 0xffu), (int32_t)len, (int64_t)i);
    }
    producer_nulls = nulls;
    producer_gave_up = gave_up;
    __atomic_store_n(&producer_done, 1, __ATOMIC_RELEASE); // publishes the two counts
    return NULL;
}

static void test_spsc_stress_two_threads(void)
{
    pthread_t th;
    cdpr_diag_t d;
    cdpr_lcm_ring_stats_t s;
    uint64_t received = 0u;
    int64_t last = -1;
    uint32_t bad = 0u;

    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_lcm_ring_init(&sring, stress_storage, sizeof stress_storage,
                                                      STRESS_SLOTS, STRESS_BYTES, &d));
    __atomic_store_n(&producer_done, 0, __ATOMIC_RELAXED);
    TEST_ASSERT_EQUAL_INT(0, pthread_create(&th, NULL, producer, NULL));
    for (;;) {
        const unsigned char *data;
        const cdpr_lcm_slot_t *h = cdpr_lcm_ring_peek(&sring, &data);
        if (h == NULL) {
            if (__atomic_load_n(&producer_done, __ATOMIC_ACQUIRE) &&
                cdpr_lcm_ring_peek(&sring, NULL) == NULL) {
                break;
            }
            continue;
        }
        {
            const uint32_t i = (uint32_t)h->seq;
            uint32_t k;
            // In order (drops leave gaps, never reorderings) with intact header and bytes.
            if (h->seq <= last || h->channel != (int32_t)(i & 0xffu) ||
                h->len != (int32_t)(8u + i % 57u)) {
                bad++;
            } else {
                for (k = 0; k < (uint32_t)h->len; k++) {
                    if (data[k] != pattern(i, k)) {
                        bad++;
                        break;
                    }
                }
            }
            last = h->seq;
        }
        received++;
        cdpr_lcm_ring_release(&sring);
    }
    TEST_ASSERT_EQUAL_INT(0, pthread_join(th, NULL));
    cdpr_lcm_ring_stats(&sring, &s);
    printf("spsc stress: %u messages, %llu received, %llu abandoned, %llu full claims, high "
           "water %u/%u\n",
           STRESS_N, (unsigned long long)received, (unsigned long long)producer_gave_up,
           (unsigned long long)s.dropped, s.high_water, STRESS_SLOTS);
    TEST_ASSERT_EQUAL_UINT32(0u, bad);
    TEST_ASSERT_EQUAL_UINT64(producer_nulls, s.dropped); // every full claim counted once
    TEST_ASSERT_EQUAL_UINT64(STRESS_N - producer_gave_up, s.pushed);
    TEST_ASSERT_EQUAL_UINT64(s.pushed, received); // nothing lost once committed
    TEST_ASSERT_EQUAL_UINT64(received, s.popped);
    TEST_ASSERT_TRUE(received >= STRESS_N - STRESS_N / 8u); // the threads really exchanged
    TEST_ASSERT_TRUE(s.high_water <= STRESS_SLOTS);
}

// Cost of one push of a 200-byte message (about a cabin_state_t) with the consumer idle;
// printed, not asserted (timing is the benchmark's business, not a test's).
static void test_push_cost_is_reported(void)
{
    static uint64_t big[CDPR_LCM_RING_STORAGE_BYTES(1024u, 256u) / sizeof(uint64_t)];
    static unsigned char msg[200];
    cdpr_lcm_ring_t r;
    cdpr_diag_t d;
    struct timespec t0;
    struct timespec t1;
    uint32_t i;
    double ns;

    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_lcm_ring_init(&r, big, sizeof big, 1024u, 256u, &d));
    // Warm-up round: the first touch of the storage pays page faults, not the ring.
    for (i = 0; i < 1000u; i++) {
        (void)cdpr_lcm_ring_push(&r, 0, msg, (int32_t)sizeof msg, (int64_t)i);
    }
    while (cdpr_lcm_ring_peek(&r, NULL) != NULL) {
        cdpr_lcm_ring_release(&r);
    }
    (void)clock_gettime(CLOCK_MONOTONIC, &t0);
    for (i = 0; i < 1000u; i++) {
        (void)cdpr_lcm_ring_push(&r, 0, msg, (int32_t)sizeof msg, (int64_t)i);
    }
    (void)clock_gettime(CLOCK_MONOTONIC, &t1);
    ns = ((double)(t1.tv_sec - t0.tv_sec) * 1e9 + (double)(t1.tv_nsec - t0.tv_nsec)) / 1000.0;
    printf("ring push (200 B memcpy + commit): %.1f ns\n", ns);
    TEST_ASSERT_TRUE(ns > 0.0);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_init_rejects_bad_arguments);
    RUN_TEST(test_empty_ring_peeks_nothing);
    RUN_TEST(test_fill_then_drop_newest_counted);
    RUN_TEST(test_wrap_around_keeps_order);
    RUN_TEST(test_index_wrap_at_uint32_max);
    RUN_TEST(test_claim_commit_semantics);
    RUN_TEST(test_producer_path_makes_no_allocation);
    RUN_TEST(test_spsc_stress_two_threads);
    RUN_TEST(test_push_cost_is_reported);
    return UNITY_END() ? 1 : 0;
}
