/* SPDX-License-Identifier: BSD-3-Clause */
/// @file ring.h
/// Lock-free single-producer / single-consumer ring of preallocated, fixed-size message slots.
///
/// The real-time thread (the only producer) encodes each outgoing LCM message straight into a
/// free slot (claim, encode, commit); the publisher thread (the only consumer) hands committed
/// slots to lcm_publish (peek, publish, release). Nothing is copied twice and nothing is
/// allocated: the caller gives the storage.
///
/// Overflow policy: **drop-newest**. When every slot is committed and not yet released, claim
/// returns NULL, the message is not queued and `dropped` is incremented; queued messages are
/// never overwritten. Why not drop-oldest: the consumer may be reading the oldest slot at that
/// very moment (lcm_publish blocks in sendmsg), so overwriting it would need the producer to
/// take slots back from the consumer with compare-and-swap retry loops; drop-newest keeps both
/// sides wait-free, O(1), with one acquire load and one release store each. A subscriber sees
/// the loss as a gap in the sequence numbers.
///
/// Guarantees: every committed slot is seen by the consumer exactly once, in commit order,
/// with the bytes the producer wrote (release/acquire on the indices, GCC __atomic builtins,
/// lock-free on x86-64, AArch64 and Cortex-M7). pushed == popped + (slots still queued);
/// every claim either succeeds or counts one drop. Any thread may read the statistics.
/// Two producers (or two consumers) on one ring are not supported.
///
/// Memory: storage of CDPR_LCM_RING_STORAGE_BYTES(n_slots, slot_bytes) bytes, 8-byte aligned,
/// owned by the caller for the lifetime of the ring. Work: O(1) per call (push: + memcpy).
#ifndef CDPR_LCM_RING_H
#define CDPR_LCM_RING_H

#include <stddef.h>
#include <stdint.h>

#include "cdpr/status.h"

/// Largest slot count (a power of two) and slot size [bytes].
#define CDPR_LCM_RING_SLOTS_MAX 65536u
#define CDPR_LCM_SLOT_BYTES_MAX (1u << 24)

/// Slot sizes are rounded up to a multiple of 8 bytes.
#define CDPR_LCM_RING_ROUND8(n) ((((size_t)(n)) + 7u) & ~(size_t)7u)

/// Storage a ring of `n_slots` slots of `slot_bytes` bytes needs [bytes].
#define CDPR_LCM_RING_STORAGE_BYTES(n_slots, slot_bytes)                                           \
    ((size_t)(n_slots) * (sizeof(cdpr_lcm_slot_t) + CDPR_LCM_RING_ROUND8(slot_bytes)))

/// Header of one slot (written by the producer before commit, read-only for the consumer).
typedef struct {
    int32_t channel; ///< caller's channel id (cdpr_lcm_channel_t for the bridge)
    int32_t len;     ///< encoded bytes in the slot's data
    int64_t seq;     ///< caller's sequence number of the message (state seq k), or -1
} cdpr_lcm_slot_t;

/// Statistics (a consistent-enough snapshot: each field is read atomically).
typedef struct {
    uint64_t pushed;     ///< slots committed by the producer
    uint64_t dropped;    ///< claims refused because the ring was full (drop-newest)
    uint64_t popped;     ///< slots released by the consumer
    uint32_t queued;     ///< slots committed and not yet released
    uint32_t high_water; ///< largest `queued` the consumer found when it peeked
} cdpr_lcm_ring_stats_t;

/// The ring (caller-owned). Fields are internal; use the functions.
typedef struct {
    // Producer side (written only by the producer thread).
    uint32_t head;                  ///< next slot index to commit (free-running; atomic)
    uint32_t tail_cache;            ///< producer's last view of `tail`
    uint32_t claimed;               ///< 1 between a successful claim and its commit
    uint64_t pushed;                ///< atomic
    uint64_t dropped;               ///< atomic
    unsigned char pad_producer[64]; ///< keeps producer and consumer fields on separate lines
    // Consumer side (written only by the consumer thread).
    uint32_t tail;       ///< next slot index to release (free-running; atomic)
    uint32_t peeked;     ///< 1 between a successful peek and its release
    uint32_t high_water; ///< atomic
    uint64_t popped;     ///< atomic
    unsigned char pad_consumer[64];
    // Read-only after init.
    uint32_t n_slots;     ///< power of two
    uint32_t mask;        ///< n_slots - 1
    uint32_t slot_bytes;  ///< capacity of one slot, multiple of 8
    cdpr_lcm_slot_t *hdr; ///< n_slots headers (in the caller's storage)
    unsigned char *data;  ///< n_slots * slot_bytes bytes (in the caller's storage)
} cdpr_lcm_ring_t;

/// Initialise an empty ring on caller storage. `n_slots`: a power of two in
/// [2, CDPR_LCM_RING_SLOTS_MAX]; `slot_bytes` in [8, CDPR_LCM_SLOT_BYTES_MAX] (rounded up to a
/// multiple of 8); `storage` 8-byte aligned with at least CDPR_LCM_RING_STORAGE_BYTES bytes.
/// CDPR_E_INVALID_ARG / CDPR_E_OUT_OF_RANGE / CDPR_E_CAPACITY name the bad argument in `diag`
/// (may be NULL); on error nothing is written. Not thread-safe (call before the threads start).
cdpr_status_t cdpr_lcm_ring_init(cdpr_lcm_ring_t *ring, void *storage, size_t storage_bytes,
                                 uint32_t n_slots, uint32_t slot_bytes, cdpr_diag_t *diag);

/// Producer: a free slot of ring->slot_bytes bytes to write into, or NULL when the ring is full
/// (one drop is counted; the message is lost). A second claim before the commit returns the
/// same slot. Wait-free, O(1), no allocation, no system call.
unsigned char *cdpr_lcm_ring_claim(cdpr_lcm_ring_t *ring);

/// Producer: queue the claimed slot with `len` bytes (1..slot_bytes) for the consumer.
/// CDPR_E_INVALID_ARG (nothing queued, the claim stays open) without a claim or for a bad
/// `len`. Wait-free, O(1).
cdpr_status_t cdpr_lcm_ring_commit(cdpr_lcm_ring_t *ring, int32_t channel, int32_t len,
                                   int64_t seq);

/// Producer: claim + memcpy + commit. CDPR_E_CAPACITY when the ring is full (counted as a
/// drop), CDPR_E_INVALID_ARG when `len` is 0 or larger than a slot (not counted).
cdpr_status_t cdpr_lcm_ring_push(cdpr_lcm_ring_t *ring, int32_t channel, const void *data,
                                 int32_t len, int64_t seq);

/// Consumer: the oldest committed slot (header; its bytes in `*data`), or NULL when empty.
/// The slot stays valid and unchanged until cdpr_lcm_ring_release. Wait-free, O(1).
const cdpr_lcm_slot_t *cdpr_lcm_ring_peek(cdpr_lcm_ring_t *ring, const unsigned char **data);

/// Consumer: 1 when a committed slot is waiting (what peek would return), else 0. Acquire load
/// of the producer's index; used by a consumer about to sleep. Wait-free, O(1).
int cdpr_lcm_ring_pending(const cdpr_lcm_ring_t *ring);

/// Consumer: give the slot returned by the last peek back to the producer. No-op without one.
void cdpr_lcm_ring_release(cdpr_lcm_ring_t *ring);

/// Statistics; any thread. Wait-free, O(1).
void cdpr_lcm_ring_stats(const cdpr_lcm_ring_t *ring, cdpr_lcm_ring_stats_t *stats);

#endif /* CDPR_LCM_RING_H */
