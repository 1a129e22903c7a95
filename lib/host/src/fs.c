/* SPDX-License-Identifier: BSD-3-Clause */
/// @file fs.c
/// File-system helpers (fs.h).
#include "cdpr/host/fs.h"

#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

cdpr_status_t cdpr_fs_mkdir_p(const char *dir)
{
    char buf[1024];
    if (snprintf(buf, sizeof buf, "%s", dir) >= (int)sizeof buf) {
        errno = ENAMETOOLONG;
        return CDPR_E_IO;
    }
    for (char *p = buf + 1; *p != '\0'; ++p) {
        if (*p == '/') {
            *p = '\0';
            if (mkdir(buf, 0775) != 0 && errno != EEXIST) {
                return CDPR_E_IO;
            }
            *p = '/';
        }
    }
    return (mkdir(buf, 0775) != 0 && errno != EEXIST) ? CDPR_E_IO : CDPR_OK;
}

cdpr_status_t cdpr_fs_path(char *buf, size_t cap, const char *dir, const char *name)
{
    const int n = snprintf(buf, cap, "%s/%s", dir, name);
    if (n < 0 || (size_t)n >= cap) {
        errno = ENAMETOOLONG;
        return CDPR_E_INVALID_ARG;
    }
    return CDPR_OK;
}

static void say(char *why, size_t cap, const char *what)
{
    if (why != NULL && cap > 0U) {
        snprintf(why, cap, "%s", what);
    }
}

cdpr_status_t cdpr_fs_open_regular(const char *path, int for_write, int *fd, char *why, size_t cap)
{
    *fd = -1;
    const int flags = (for_write != 0) ? (O_WRONLY | O_CREAT | O_TRUNC) : O_RDONLY;
    const int f = open(path, flags | O_NONBLOCK | O_NOCTTY | O_CLOEXEC, 0666);
    if (f < 0) {
        const int e = errno;
        say(why, cap, strerror(e));
        errno = e;
        return CDPR_E_IO;
    }
    struct stat sb;
    if (fstat(f, &sb) != 0) {
        const int e = errno;
        say(why, cap, strerror(e));
        (void)close(f);
        errno = e;
        return CDPR_E_IO;
    }
    if (!S_ISREG(sb.st_mode)) {
        say(why, cap,
            S_ISDIR(sb.st_mode) ? "is a directory"
                                : "not a regular file (a pipe, socket or device)");
        (void)close(f);
        errno = S_ISDIR(sb.st_mode) ? EISDIR : EINVAL;
        return CDPR_E_INVALID_ARG;
    }
    const int fl = fcntl(f, F_GETFL);
    if (fl < 0 || fcntl(f, F_SETFL, fl & ~O_NONBLOCK) != 0) {
        const int e = errno;
        say(why, cap, strerror(e));
        (void)close(f);
        errno = e;
        return CDPR_E_IO;
    }
    *fd = f;
    return CDPR_OK;
}

FILE *cdpr_fs_fopen(const char *path, const char *mode, char *why, size_t cap)
{
    const int for_write = (mode[0] == 'w') ? 1 : 0;
    int fd;
    if (cdpr_fs_open_regular(path, for_write, &fd, why, cap) != CDPR_OK) {
        return NULL;
    }
    FILE *f = fdopen(fd, mode);
    if (f == NULL) {
        const int e = errno;
        say(why, cap, strerror(e));
        (void)close(fd);
        errno = e;
    }
    return f;
}
