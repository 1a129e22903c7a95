/* SPDX-License-Identifier: BSD-3-Clause */
/// @file csv.h
/// Minimal CSV writer for time series: comment lines ("# key: value", before the header; gnuplot,
/// pandas' comment='#' and the like skip them), a header row of column names, then rows of
/// numbers printed with %.17g (round-trip exact, so two runs' files are byte-identical exactly
/// when their values are bit-identical). Write errors are remembered and reported at close.
#ifndef CDPR_HOST_CSV_H
#define CDPR_HOST_CSV_H

#include <stdio.h>

#include "cdpr/status.h"

typedef struct {
    FILE *f;    ///< open file (internal)
    int col;    ///< fields written in the current row (internal)
    int failed; ///< a write failed (output)
} cdpr_csv_t;

/// Open `path` for writing. Returns CDPR_OK, or CDPR_E_IO (errno set by fopen).
cdpr_status_t cdpr_csv_open(cdpr_csv_t *c, const char *path);

/// One comment line "# KEY: VALUE" (VALUE "" or NULL: "null"; control characters in it are
/// written as '?', so the line stays one line). Before the header row.
void cdpr_csv_comment(cdpr_csv_t *c, const char *key, const char *value);

/// One header field (a column name).
void cdpr_csv_name(cdpr_csv_t *c, const char *name);

/// One numeric field.
void cdpr_csv_num(cdpr_csv_t *c, double v);

/// End the current row.
void cdpr_csv_end_row(cdpr_csv_t *c);

/// Close. Returns CDPR_OK, CDPR_E_IO if any write (or the close) failed, CDPR_E_INVALID_ARG
/// if it was not open.
cdpr_status_t cdpr_csv_close(cdpr_csv_t *c);

#endif /* CDPR_HOST_CSV_H */
