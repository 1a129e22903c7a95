/* SPDX-License-Identifier: BSD-3-Clause */
/// @file csv.h
/// Minimal CSV writer for time series: comment lines ("# key: value", before the header; gnuplot,
/// pandas' comment='#' and the like skip them), a header row of column names, then rows of
/// numbers printed with %.17g (round-trip exact, so two runs' files are byte-identical exactly
/// when their values are bit-identical).
///
/// Rows are whole in the file, whatever happens. Each row (or comment line) is formatted into
/// the writer's own buffer `buf` and becomes visible to the file only as a whole: the buffer
/// holds whole rows only and is written with write(2) (a loop over short writes and EINTR, so
/// a signal that interrupts a write is no error) when the next row would not fit, at
/// cdpr_csv_flush and at close. If a write fails (ENOSPC, EFBIG, EIO...) after part of the
/// buffer reached the file, the file is cut back with ftruncate(2) to the end of the last row
/// that reached it completely. stdio is not used: a FILE flushing its buffer on ENOSPC stops at
/// an arbitrary byte and leaves a torn row. A row longer than the buffer (it cannot happen with
/// the recorder's at most 21 + 6 x 6 fields of at most 24 bytes) is an error (ENOBUFS) and is
/// not written. After the first error nothing more is written; its errno is kept in `error`
/// and every later call is a no-op, so the file ends with the last whole row written before
/// it. No allocation: the buffer is inline (CDPR_CSV_BUF bytes).
#ifndef CDPR_HOST_CSV_H
#define CDPR_HOST_CSV_H

#include <stddef.h>

#include "cdpr/status.h"

/// Bytes of the writer's buffer (several whole rows).
#define CDPR_CSV_BUF 16384

typedef struct {
    int fd;                 ///< the file (internal; valid when is_open)
    int is_open;            ///< 1 between open and close (internal)
    int col;                ///< fields written in the current row (internal)
    size_t len;             ///< bytes of whole rows in buf (internal)
    size_t row;             ///< bytes of the current, unfinished row after them (internal)
    long long committed;    ///< bytes of whole rows in the file (internal)
    int failed;             ///< a write failed (output)
    int error;              ///< errno of the first failure (output; 0 none)
    char buf[CDPR_CSV_BUF]; ///< whole rows, then the current row (internal)
} cdpr_csv_t;

/// Open `path` for writing (created, truncated). Returns CDPR_OK, or CDPR_E_IO (errno set by
/// open, also in c->error).
cdpr_status_t cdpr_csv_open(cdpr_csv_t *c, const char *path);

/// One comment line "# KEY: VALUE" (VALUE "" or NULL: "null"; control characters in it are
/// written as '?', so the line stays one line). Before the header row.
void cdpr_csv_comment(cdpr_csv_t *c, const char *key, const char *value);

/// One header field (a column name).
void cdpr_csv_name(cdpr_csv_t *c, const char *name);

/// One numeric field.
void cdpr_csv_num(cdpr_csv_t *c, double v);

/// End the current row (it is now whole and will reach the file as a whole).
void cdpr_csv_end_row(cdpr_csv_t *c);

/// Write the whole rows buffered so far. Returns CDPR_OK, or CDPR_E_IO when this or an earlier
/// write failed (c->error: its errno).
cdpr_status_t cdpr_csv_flush(cdpr_csv_t *c);

/// Flush (an unfinished row is dropped) and close. Returns CDPR_OK, CDPR_E_IO if any write, the
/// flush or the close failed (c->error: the first errno), CDPR_E_INVALID_ARG if it was not
/// open.
cdpr_status_t cdpr_csv_close(cdpr_csv_t *c);

#endif /* CDPR_HOST_CSV_H */
