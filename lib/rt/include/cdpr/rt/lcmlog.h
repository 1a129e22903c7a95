/* SPDX-License-Identifier: BSD-3-Clause */
/// @file lcmlog.h
/// A validating reader of LCM log files (the lcm-logger format), for `cdpr-tracker --replay`.
/// liblcm's own reader trusts the lengths an event claims (an event that claims 2^31 - 1 bytes
/// crashed it) and silently skips to the next sync word after damage (a log cut in half or
/// with flipped bits replayed with exit 0). This one checks every event against the file
/// before it reads it, and stops at the first damage with a message naming the event.
///
/// Format (big-endian): per event a sync word 0xEDA1DA01, the event number (int64), a
/// timestamp (int64, microseconds), the channel length (int32) and the data length (int32),
/// then the channel's bytes (no terminator) and the data.
///
/// Rules: the sync word; a channel of 1 to CDPR_LCMLOG_MAX_CHANNEL bytes; a data length from 0
/// to the bytes left in the file; event numbers strictly increasing; the file a regular file
/// opened without blocking (cdpr_fs_open_regular). Events of the channels a caller wants must
/// also fit its buffer (CDPR_LCMLOG_MAX_DATA); others are skipped without being read. Memory:
/// the caller's buffers, nothing else.
///
/// Host library (stdio); no allocation.
#ifndef CDPR_RT_LCMLOG_H
#define CDPR_RT_LCMLOG_H

#include <stdint.h>
#include <stdio.h>

#include "cdpr/status.h"

/// Longest channel name accepted [bytes] (LCM's own limit is 255).
#define CDPR_LCMLOG_MAX_CHANNEL 255

/// Largest data read for a wanted channel [bytes] (every cdpr message is smaller).
#define CDPR_LCMLOG_MAX_DATA 65536

/// The reader (caller-owned).
typedef struct {
    FILE *f;                                   ///< the log
    long long size;                            ///< its size [bytes]
    long long pos;                             ///< offset of the next event
    long long index;                           ///< events read so far
    int64_t last_number;                       ///< event number of the last event
    char path[512];                            ///< for messages
    char channel[CDPR_LCMLOG_MAX_CHANNEL + 1]; ///< channel of the current event
    unsigned char data[CDPR_LCMLOG_MAX_DATA];  ///< data of the current event (wanted channel)
    int32_t data_len;                          ///< its length
    int64_t utime_us;                          ///< its timestamp
} cdpr_lcmlog_t;

/// Open `path`. CDPR_OK; CDPR_E_IO (cannot open: msg = "PATH: strerror"); CDPR_E_PARSE (not a
/// regular file, or empty: msg says which). `msg` holds at most `cap` bytes.
cdpr_status_t cdpr_lcmlog_open(cdpr_lcmlog_t *l, const char *path, char *msg, size_t cap);

/// The next event. `want(channel, ctx)` returns 1 for a channel whose data should be read into
/// l->data (it must then fit CDPR_LCMLOG_MAX_DATA), 0 to skip the data. Returns 1 with the
/// event in l (channel always; data and data_len when wanted, else data_len = -1), 0 at the
/// end of the file, or -1 on damage with msg = "PATH: event N at byte B: what" (cut, bad sync
/// word, a length out of range, event numbers not increasing, a read error).
int cdpr_lcmlog_next(cdpr_lcmlog_t *l, int (*want)(const char *channel, void *ctx), void *ctx,
                     char *msg, size_t cap);

/// Close (safe to call twice).
void cdpr_lcmlog_close(cdpr_lcmlog_t *l);

#endif /* CDPR_RT_LCMLOG_H */
