/* SPDX-License-Identifier: BSD-3-Clause */
/// @file lcm_ring.c
/// SPSC ring of encoded message slots (lcm_ring.h).
///
/// Protocol (Lamport's single-producer/single-consumer queue with free-running indices):
///  - the producer owns `head`, the consumer owns `tail`; each only reads the other's index;
///  - slot i (mod n) is the producer's while head - tail < n and i == head, the consumer's while
///    tail != head and i == tail;
///  - the producer writes the slot, then stores head + 1 with release; the consumer loads head
///    with acquire before reading the slot: it sees the bytes;
///  - the consumer finishes reading, then stores tail + 1 with release; the producer loads tail
///    with acquire before reusing the slot: it never overwrites bytes still being read.
/// Indices are uint32_t and wrap; head - tail is exact because n_slots <= 2^16 < 2^31.
/// C99 has no <stdatomic.h>: GCC/clang __atomic builtins (lock-free for 32/64-bit here).

#include "cdpr/lcm/ring.h"

#include <string.h>

static int is_power_of_two(uint32_t x)
{
    return x != 0u && (x & (x - 1u)) == 0u;
}

cdpr_status_t cdpr_lcm_ring_init(cdpr_lcm_ring_t *ring, void *storage, size_t storage_bytes,
                                 uint32_t n_slots, uint32_t slot_bytes, cdpr_diag_t *diag)
{
    size_t rounded;

    if (ring == NULL) {
        return cdpr_diag_set(diag, CDPR_E_INVALID_ARG, "ring", -1);
    }
    if (storage == NULL || ((uintptr_t)storage % 8u) != 0u) {
        return cdpr_diag_set(diag, CDPR_E_INVALID_ARG, "storage", -1);
    }
    if (n_slots < 2u || n_slots > CDPR_LCM_RING_SLOTS_MAX || !is_power_of_two(n_slots)) {
        return cdpr_diag_set(diag, CDPR_E_OUT_OF_RANGE, "n_slots", -1);
    }
    if (slot_bytes < 8u || slot_bytes > CDPR_LCM_SLOT_BYTES_MAX) {
        return cdpr_diag_set(diag, CDPR_E_OUT_OF_RANGE, "slot_bytes", -1);
    }
    if (storage_bytes < CDPR_LCM_RING_STORAGE_BYTES(n_slots, slot_bytes)) {
        return cdpr_diag_set(diag, CDPR_E_CAPACITY, "storage_bytes", -1);
    }
    rounded = CDPR_LCM_RING_ROUND8(slot_bytes);

    memset(ring, 0, sizeof *ring);
    ring->n_slots = n_slots;
    ring->mask = n_slots - 1u;
    ring->slot_bytes = (uint32_t)rounded;
    // Headers first: sizeof(cdpr_lcm_slot_t) is 16, so the data that follows stays 8-aligned.
    ring->hdr = (cdpr_lcm_slot_t *)storage;
    ring->data = (unsigned char *)storage + (size_t)n_slots * sizeof(cdpr_lcm_slot_t);
    return cdpr_diag_set(diag, CDPR_OK, "", -1);
}

unsigned char *cdpr_lcm_ring_claim(cdpr_lcm_ring_t *ring)
{
    const uint32_t head = ring->head; // own index: plain read is exact
    if (ring->claimed == 0u && head - ring->tail_cache >= ring->n_slots) {
        // Looks full: refresh the view of the consumer's index (acquire: its reads of the slot
        // we are about to reuse are complete).
        ring->tail_cache = __atomic_load_n(&ring->tail, __ATOMIC_ACQUIRE);
        if (head - ring->tail_cache >= ring->n_slots) {
            __atomic_store_n(&ring->dropped, ring->dropped + 1u, __ATOMIC_RELAXED);
            return NULL;
        }
    }
    ring->claimed = 1u;
    return ring->data + (size_t)(head & ring->mask) * ring->slot_bytes;
}

cdpr_status_t cdpr_lcm_ring_commit(cdpr_lcm_ring_t *ring, int32_t channel, int32_t len, int64_t seq)
{
    const uint32_t head = ring->head;
    cdpr_lcm_slot_t *h;

    if (ring->claimed == 0u || len <= 0 || (uint32_t)len > ring->slot_bytes) {
        return CDPR_E_INVALID_ARG;
    }
    h = &ring->hdr[head & ring->mask];
    h->channel = channel;
    h->len = len;
    h->seq = seq;
    ring->claimed = 0u;
    __atomic_store_n(&ring->head, head + 1u, __ATOMIC_RELEASE);
    __atomic_store_n(&ring->pushed, ring->pushed + 1u, __ATOMIC_RELAXED);
    return CDPR_OK;
}

cdpr_status_t cdpr_lcm_ring_push(cdpr_lcm_ring_t *ring, int32_t channel, const void *data,
                                 int32_t len, int64_t seq)
{
    unsigned char *slot;

    if (len <= 0 || (uint32_t)len > ring->slot_bytes || data == NULL) {
        return CDPR_E_INVALID_ARG;
    }
    slot = cdpr_lcm_ring_claim(ring);
    if (slot == NULL) {
        return CDPR_E_CAPACITY;
    }
    memcpy(slot, data, (size_t)len);
    return cdpr_lcm_ring_commit(ring, channel, len, seq);
}

const cdpr_lcm_slot_t *cdpr_lcm_ring_peek(cdpr_lcm_ring_t *ring, const unsigned char **data)
{
    const uint32_t tail = ring->tail;
    const uint32_t head = __atomic_load_n(&ring->head, __ATOMIC_ACQUIRE);
    const uint32_t i = tail & ring->mask;

    if (head == tail) {
        return NULL;
    }
    // Occupancy peaks just before the consumer catches up, i.e. here; measuring it on this
    // side keeps the producer free of a load of the consumer's index per commit.
    if (head - tail > ring->high_water) {
        __atomic_store_n(&ring->high_water, head - tail, __ATOMIC_RELAXED);
    }
    ring->peeked = 1u;
    if (data != NULL) {
        *data = ring->data + (size_t)i * ring->slot_bytes;
    }
    return &ring->hdr[i];
}

int cdpr_lcm_ring_pending(const cdpr_lcm_ring_t *ring)
{
    return __atomic_load_n(&ring->head, __ATOMIC_ACQUIRE) != ring->tail;
}

void cdpr_lcm_ring_release(cdpr_lcm_ring_t *ring)
{
    if (ring->peeked == 0u) {
        return;
    }
    ring->peeked = 0u;
    __atomic_store_n(&ring->popped, ring->popped + 1u, __ATOMIC_RELAXED);
    __atomic_store_n(&ring->tail, ring->tail + 1u, __ATOMIC_RELEASE);
}

void cdpr_lcm_ring_stats(const cdpr_lcm_ring_t *ring, cdpr_lcm_ring_stats_t *stats)
{
    const uint32_t tail = __atomic_load_n(&ring->tail, __ATOMIC_ACQUIRE);
    const uint32_t head = __atomic_load_n(&ring->head, __ATOMIC_ACQUIRE);

    stats->pushed = __atomic_load_n(&ring->pushed, __ATOMIC_RELAXED);
    stats->dropped = __atomic_load_n(&ring->dropped, __ATOMIC_RELAXED);
    stats->popped = __atomic_load_n(&ring->popped, __ATOMIC_RELAXED);
    stats->high_water = __atomic_load_n(&ring->high_water, __ATOMIC_RELAXED);
    // tail was read first, so head - tail cannot underflow even if both moved meanwhile; it
    // can overstate when both moved, hence the clamp.
    stats->queued = head - tail;
    if (stats->queued > ring->n_slots) {
        stats->queued = ring->n_slots;
    }
}
