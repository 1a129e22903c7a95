/// @file csv.c
#include "cdpr/host/csv.h"

#include <string.h>

int cdpr_csv_open(cdpr_csv_t *c, const char *path)
{
    memset(c, 0, sizeof *c);
    c->f = fopen(path, "w");
    return (c->f != NULL) ? 0 : -1;
}

static void sep(cdpr_csv_t *c)
{
    if (c->col > 0 && fputc(',', c->f) == EOF) {
        c->failed = 1;
    }
    c->col++;
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

int cdpr_csv_close(cdpr_csv_t *c)
{
    if (c->f == NULL) {
        return -1;
    }
    const int rc = fclose(c->f);
    c->f = NULL;
    return (rc != 0 || c->failed != 0) ? -1 : 0;
}
