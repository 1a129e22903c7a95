/// @file fs.h
/// File-system helpers of the host tools: create an output directory with its parents and
/// build the path of a file in it.
///
/// Host library (POSIX); no allocation.
#ifndef CDPR_HOST_FS_H
#define CDPR_HOST_FS_H

#include <stddef.h>

#include "cdpr/status.h"

/// Create directory `dir` and its missing parents (mode 0775), like `mkdir -p`. Returns
/// CDPR_OK (also when it exists), or CDPR_E_IO with errno set (ENAMETOOLONG for a path of
/// 1024 characters or more).
cdpr_status_t cdpr_fs_mkdir_p(const char *dir);

/// "dir/name" into `buf` of `cap` bytes. Returns CDPR_OK, or CDPR_E_INVALID_ARG when it does
/// not fit (buf then holds the truncated path, errno = ENAMETOOLONG).
cdpr_status_t cdpr_fs_path(char *buf, size_t cap, const char *dir, const char *name);

#endif /* CDPR_HOST_FS_H */
