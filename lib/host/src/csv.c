/* SPDX-License-Identifier: BSD-3-Clause */
/// @file csv.c
/// CSV writer (csv.h).
#include "cdpr/host/csv.h"

#include <string.h>

cdpr_status_t cdpr_csv_open(cdpr_csv_t *c, const char *path)
{
    memset(c, 0, sizeof *c);
    c->f = fopen(path, "w");
    return (c->f != NULL) ? CDPR_OK : CDPR_E_IO;
}

static void sep(cdpr_csv_t *c)
{
    if (c->col > 0 && fputc(',', c->f) == EOF) {
        c->failed = 1;
    }
    c->col++;
}

void cdpr_csv_comment(cdpr_csv_t *c, const char *key, const char *value)
{
    if (fprintf(c->f, "# %s: ", key) < 0) {
        c->failed = 1;
    }
    const char *v = (value != NULL && value[0] != '\0') ? value : "null";
    for (; *v != '\0'; ++v) {
        const unsigned char ch = (unsigned char)*v;
        if (fputc((ch < 0x20U || ch == 0x7fU) ? '?' : (int)ch, c->f) == EOF) {
            c->failed = 1;
        }
    }
    if (fputc('\n', c->f) == EOF) {
        c->failed = 1;
    }
}

void cdpr_csv_name(cdpr_csv_t *c, const char *name)
{
    sep(c);
    if (fputs(name, c->f) == EOF) {
        c->failed = 1;
    }
}

void cdpr_csv_num(cdpr_csv_t *c, double v)
{
    sep(c);
    if (fprintf(c->f, "%.17g", v) < 0) {
        c->failed = 1;
    }
}

void cdpr_csv_end_row(cdpr_csv_t *c)
{
    if (fputc('\n', c->f) == EOF) {
        c->failed = 1;
    }
    c->col = 0;
}

cdpr_status_t cdpr_csv_close(cdpr_csv_t *c)
{
    if (c->f == NULL) {
        return CDPR_E_INVALID_ARG;
    }
    const int rc = fclose(c->f);
    c->f = NULL;
    return (rc != 0 || c->failed != 0) ? CDPR_E_IO : CDPR_OK;
}
