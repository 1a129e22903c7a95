/* SPDX-License-Identifier: BSD-3-Clause */
/// @file version.c
/// cdpr_version(): the version string the core was built with (cdpr/version.h, generated).
#include "cdpr/version.h"

const char *cdpr_version(void)
{
    return CDPR_VERSION_STRING;
}
