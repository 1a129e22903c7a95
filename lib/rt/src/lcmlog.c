/* SPDX-License-Identifier: BSD-3-Clause */
/// @file lcmlog.c
/// A validating reader of LCM log files (lcmlog.h).
#include "cdpr/rt/lcmlog.h"

#include <errno.h>
#include <string.h>
#include <sys/stat.h>

#include "cdpr/host/fs.h"

#define SYNC_WORD   0xEDA1DA01u
#define HEADER_SIZE 28 /* sync 4, number 8, time 8, channel length 4, data length 4 */

static uint64_t be(const unsigned char *p, int n)
{
    uint64_t v = 0;
    for (int i = 0; i < n; ++i) {
        v = (v << 8) | p[i];
    }
    return v;
}

cdpr_status_t cdpr_lcmlog_open(cdpr_lcmlog_t *l, const char *path, char *msg, size_t cap)
{
    memset(l, 0, sizeof *l);
    snprintf(l->path, sizeof l->path, "%s", path);
    char why[256];
    l->f = cdpr_fs_fopen(path, "rb", why, sizeof why);
    if (l->f == NULL) {
        snprintf(msg, cap, "%s: %s", path, why);
        return (errno == EINVAL || errno == EISDIR) ? CDPR_E_PARSE : CDPR_E_IO;
    }
    struct stat sb;
    if (fstat(fileno(l->f), &sb) != 0 || sb.st_size == 0) {
        snprintf(msg, cap, "%s: an empty log", path);
        cdpr_lcmlog_close(l);
        return CDPR_E_PARSE;
    }
    l->size = (long long)sb.st_size;
    l->last_number = -1;
    return CDPR_OK;
}

static int damaged(cdpr_lcmlog_t *l, char *msg, size_t cap, const char *what)
{
    snprintf(msg, cap, "%s: event %lld at byte %lld: %s", l->path, l->index + 1, l->pos, what);
    return -1;
}

int cdpr_lcmlog_next(cdpr_lcmlog_t *l, int (*want)(const char *channel, void *ctx), void *ctx,
                     char *msg, size_t cap)
{
    if (l->pos == l->size) {
        return 0;
    }
    char what[400];
    const long long left = l->size - l->pos;
    if (left < HEADER_SIZE) {
        snprintf(what, sizeof what,
                 "%lld bytes left, less than an event header (28): the log is cut", left);
        return damaged(l, msg, cap, what);
    }
    unsigned char h[HEADER_SIZE];
    if (fseek(l->f, (long)l->pos, SEEK_SET) != 0 || fread(h, 1, sizeof h, l->f) != sizeof h) {
        return damaged(l, msg, cap, "read error");
    }
    if (be(h, 4) != SYNC_WORD) {
        return damaged(l, msg, cap, "no sync word (0xEDA1DA01): damaged, or not an LCM log");
    }
    const int64_t number = (int64_t)be(h + 4, 8);
    const int64_t utime = (int64_t)be(h + 12, 8);
    const int32_t clen = (int32_t)(uint32_t)be(h + 20, 4);
    const int32_t dlen = (int32_t)(uint32_t)be(h + 24, 4);
    if (number <= l->last_number) {
        snprintf(what, sizeof what, "event number %lld after %lld: not increasing",
                 (long long)number, (long long)l->last_number);
        return damaged(l, msg, cap, what);
    }
    if (clen < 1 || clen > CDPR_LCMLOG_MAX_CHANNEL) {
        snprintf(what, sizeof what, "channel length %ld outside 1..%d", (long)clen,
                 CDPR_LCMLOG_MAX_CHANNEL);
        return damaged(l, msg, cap, what);
    }
    if (dlen < 0 || (long long)clen + (long long)dlen > left - HEADER_SIZE) {
        snprintf(what, sizeof what,
                 "claims %ld bytes of data and %ld of channel, %lld remain: the log is cut or "
                 "damaged",
                 (long)dlen, (long)clen, left - HEADER_SIZE);
        return damaged(l, msg, cap, what);
    }
    if (fread(l->channel, 1, (size_t)clen, l->f) != (size_t)clen) {
        return damaged(l, msg, cap, "read error");
    }
    l->channel[clen] = '\0';
    if (memchr(l->channel, '\0', (size_t)clen) != NULL) {
        return damaged(l, msg, cap, "a NUL byte in the channel name");
    }
    l->data_len = -1;
    if (want != NULL && want(l->channel, ctx) != 0) {
        if (dlen > CDPR_LCMLOG_MAX_DATA) {
            snprintf(what, sizeof what, "%ld bytes of data on %.80s: more than any message of ours",
                     (long)dlen, l->channel);
            return damaged(l, msg, cap, what);
        }
        if (fread(l->data, 1, (size_t)dlen, l->f) != (size_t)dlen) {
            return damaged(l, msg, cap, "read error");
        }
        l->data_len = dlen;
    }
    l->utime_us = utime;
    l->last_number = number;
    l->pos += HEADER_SIZE + (long long)clen + (long long)dlen;
    l->index++;
    return 1;
}

void cdpr_lcmlog_close(cdpr_lcmlog_t *l)
{
    if (l->f != NULL) {
        (void)fclose(l->f);
        l->f = NULL;
    }
}
