/* SPDX-License-Identifier: BSD-3-Clause */
/// @file text_files.h
/// Helpers of the host tests that write variants of a text file (scenario and robot files
/// with one line changed): the test's temporary directory (CDPR_TEST_TMP), writing a text,
/// replacing the first occurrence of a snippet, and the line of a marker.
#ifndef CDPR_TEST_TEXT_FILES_H
#define CDPR_TEST_TEXT_FILES_H

#include <stdio.h>
#include <string.h>
#include <sys/stat.h>

#include "unity.h"

static char tmp_dir[512];

/* The test's temporary directory (CDPR_TEST_TMP) into tmp_dir, created if missing. */
static inline void make_tmp(void)
{
    snprintf(tmp_dir, sizeof tmp_dir, "%s", CDPR_TEST_TMP);
    mkdir(tmp_dir, 0775); /* parent (the build directory) exists; EEXIST is fine */
}

static inline void write_text(const char *path, const char *text)
{
    FILE *f = fopen(path, "w");
    TEST_ASSERT_NOT_NULL_MESSAGE(f, path);
    TEST_ASSERT_TRUE(fputs(text, f) >= 0);
    TEST_ASSERT_EQUAL_INT(0, fclose(f));
}

/* text with the first occurrence of `from` replaced by `to` (into out). */
static inline void replace(const char *text, const char *from, const char *to, char *out,
                           size_t cap)
{
    const char *at = strstr(text, from);
    TEST_ASSERT_NOT_NULL_MESSAGE(at, from);
    const size_t head = (size_t)(at - text);
    TEST_ASSERT_TRUE(head + strlen(to) + strlen(at + strlen(from)) < cap);
    memcpy(out, text, head);
    strcpy(out + head, to);
    strcat(out, at + strlen(from));
}

/* 1-based line of the first line containing `marker`, or 0. */
static inline int line_of(const char *text, const char *marker)
{
    const char *at = strstr(text, marker);
    if (at == NULL) {
        return 0;
    }
    int line = 1;
    for (const char *p = text; p < at; ++p) {
        line += (*p == '\n') ? 1 : 0;
    }
    return line;
}

#endif /* CDPR_TEST_TEXT_FILES_H */
