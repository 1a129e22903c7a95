/* SPDX-License-Identifier: BSD-3-Clause */
/// @file csv.c
/// CSV writer (csv.h): whole rows in an inline buffer, written with write(2), cut back to the
/// last whole row on a failed write.
#include "cdpr/host/csv.h"

#include <errno.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "cdpr/host/fs.h"

cdpr_status_t cdpr_csv_open(cdpr_csv_t *c, const char *path)
{
    memset(c, 0, sizeof *c);
    if (cdpr_fs_open_regular(path, 1, &c->fd, NULL, 0) != CDPR_OK) {
        c->failed = 1;
        c->error = errno;
        return CDPR_E_IO;
    }
    c->is_open = 1;
    return CDPR_OK;
}

static void fail(cdpr_csv_t *c, int err)
{
    if (c->failed == 0) {
        c->failed = 1;
        c->error = err;
    }
}

/* Write the whole rows of the buffer. On a failure after part of them reached the file, cut
 * the file back to the end of the last row that reached it completely. */
static void write_rows(cdpr_csv_t *c)
{
    size_t done = 0;
    while (c->failed == 0 && done < c->len) {
        const ssize_t n = write(c->fd, c->buf + done, c->len - done);
        if (n > 0) {
            done += (size_t)n;
        } else if (n < 0 && errno == EINTR) {
            continue;
        } else {
            fail(c, (n < 0) ? errno : EIO);
        }
    }
    if (c->failed != 0 && done > 0) {
        size_t keep = done;
        while (keep > 0 && c->buf[keep - 1] != '\n') {
            --keep;
        }
        if (ftruncate(c->fd, (off_t)(c->committed + (long long)keep)) == 0) {
            done = keep;
        }
        /* else: the error already reported stays the first; the file may end in a part row. */
    }
    c->committed += (long long)done;
    /* The current (unfinished) row moves to the front. */
    memmove(c->buf, c->buf + c->len, c->row);
    c->len = 0;
}

/* Append n bytes to the current row; the whole rows are written out first when it would not
 * fit. */
static void put(cdpr_csv_t *c, const char *s, size_t n)
{
    if (c->failed != 0 || c->is_open == 0) {
        return;
    }
    if (c->len + c->row + n > sizeof c->buf) {
        write_rows(c);
        if (c->failed == 0 && c->row + n > sizeof c->buf) {
            fail(c, ENOBUFS); /* one row longer than the buffer */
        }
        if (c->failed != 0) {
            return;
        }
    }
    memcpy(c->buf + c->len + c->row, s, n);
    c->row += n;
}

static void put_str(cdpr_csv_t *c, const char *s)
{
    put(c, s, strlen(s));
}

static void sep(cdpr_csv_t *c)
{
    if (c->col > 0) {
        put(c, ",", 1);
    }
    c->col++;
}

void cdpr_csv_comment(cdpr_csv_t *c, const char *key, const char *value)
{
    put(c, "# ", 2);
    put_str(c, key);
    put(c, ": ", 2);
    const char *v = (value != NULL && value[0] != '\0') ? value : "null";
    for (; *v != '\0'; ++v) {
        const unsigned char ch = (unsigned char)*v;
        /* A control character would break the comment line: shown as '?'. */
        put(c, (ch < 0x20U || ch == 0x7fU) ? "?" : v, 1);
    }
    cdpr_csv_end_row(c);
}

void cdpr_csv_name(cdpr_csv_t *c, const char *name)
{
    sep(c);
    put_str(c, name);
}

void cdpr_csv_num(cdpr_csv_t *c, double v)
{
    sep(c);
    char s[32];
    const int n = snprintf(s, sizeof s, "%.17g", v);
    if (n > 0 && (size_t)n < sizeof s) {
        put(c, s, (size_t)n);
    } else {
        fail(c, EOVERFLOW);
    }
}

void cdpr_csv_end_row(cdpr_csv_t *c)
{
    put(c, "\n", 1);
    c->col = 0;
    if (c->failed == 0) {
        c->len += c->row; /* whole now */
        c->row = 0;
    }
}

cdpr_status_t cdpr_csv_flush(cdpr_csv_t *c)
{
    if (c->is_open != 0 && c->len > 0) {
        write_rows(c);
    }
    return (c->failed != 0) ? CDPR_E_IO : CDPR_OK;
}

cdpr_status_t cdpr_csv_close(cdpr_csv_t *c)
{
    if (c->is_open == 0) {
        return CDPR_E_INVALID_ARG;
    }
    c->row = 0; /* an unfinished row is not written */
    (void)cdpr_csv_flush(c);
    if (close(c->fd) != 0) {
        fail(c, errno);
    }
    c->is_open = 0;
    c->fd = -1;
    return (c->failed != 0) ? CDPR_E_IO : CDPR_OK;
}
