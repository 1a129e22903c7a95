/* SPDX-License-Identifier: BSD-3-Clause */
/// @file fs.h
/// File-system helpers of the host tools: create an output directory with its parents, build
/// the path of a file in it, and open files without blocking on a pipe or a device.
///
/// Host library (POSIX); no allocation.
#ifndef CDPR_HOST_FS_H
#define CDPR_HOST_FS_H

#include <stddef.h>
#include <stdio.h>

#include "cdpr/status.h"

/// Create directory `dir` and its missing parents (mode 0775), like `mkdir -p`. Returns
/// CDPR_OK (also when it exists), or CDPR_E_IO with errno set (ENAMETOOLONG for a path of
/// 1024 characters or more).
cdpr_status_t cdpr_fs_mkdir_p(const char *dir);

/// "dir/name" into `buf` of `cap` bytes. Returns CDPR_OK, or CDPR_E_INVALID_ARG when it does
/// not fit (buf then holds the truncated path, errno = ENAMETOOLONG).
cdpr_status_t cdpr_fs_path(char *buf, size_t cap, const char *dir, const char *name);

/// Open `path` as a regular file without ever blocking: open(2) with O_NONBLOCK (a FIFO
/// without a peer then fails or returns at once instead of waiting), fstat(2) on the open
/// descriptor, refusal of anything but a regular file, then O_NONBLOCK cleared. `for_write`:
/// 0 opens for reading, 1 creates or truncates for writing (a FIFO or a device found at the
/// path is refused before anything is written). Returns CDPR_OK with *fd set (close it);
/// CDPR_E_IO when open(2) fails (why = strerror); CDPR_E_INVALID_ARG for a directory ("is a
/// directory") or another non-regular file ("not a regular file (a pipe, socket or
/// device)"); *fd is -1 on error. `why` may be NULL.
cdpr_status_t cdpr_fs_open_regular(const char *path, int for_write, int *fd, char *why, size_t cap);

/// cdpr_fs_open_regular as a stdio stream: `mode` "r" or "rb" reads, "w" or "wb" writes.
/// Returns the stream, or NULL with errno set (and `why`, if not NULL, saying why).
FILE *cdpr_fs_fopen(const char *path, const char *mode, char *why, size_t cap);

#endif /* CDPR_HOST_FS_H */
