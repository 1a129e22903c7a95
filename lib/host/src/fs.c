/// @file fs.c
/// File-system helpers (fs.h).
#include "cdpr/host/fs.h"

#include <errno.h>
#include <stdio.h>
#include <sys/stat.h>

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
