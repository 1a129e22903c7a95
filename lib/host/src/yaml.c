/* SPDX-License-Identifier: BSD-3-Clause */
/// @file yaml.c
/// The libcyaml loader set-up (yaml.h).
#include "cdpr/host/yaml.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h> /* collect_log (libcyaml hands a va_list) */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h> /* strcasecmp */
#include <sys/stat.h>
#include <unistd.h>
#include <yaml.h>

#include "cdpr/host/fs.h"

/* Error-level lines, appended in order, truncated at the buffer's end. */
static void collect_log(cyaml_log_t level, void *ctx, const char *fmt, va_list args)
{
    cdpr_yaml_log_t *b = ctx;
    if (level < CYAML_LOG_ERROR || b->len + 1 >= sizeof b->text) {
        return;
    }
    const int n = vsnprintf(b->text + b->len, sizeof b->text - b->len, fmt, args);
    if (n > 0) {
        b->len += (size_t)n;
        if (b->len >= sizeof b->text) {
            b->len = sizeof b->text - 1;
        }
    }
}

static cyaml_config_t config(cyaml_cfg_flags_t flags, cdpr_yaml_log_t *log)
{
    const cyaml_config_t cfg = {
        .log_fn = (log != NULL) ? collect_log : NULL,
        .log_ctx = log,
        .mem_fn = cyaml_mem,
        .log_level = CYAML_LOG_ERROR,
        .flags = flags,
    };
    return cfg;
}

/* Up to CDPR_YAML_ECHO_MAX characters of `s` (one line) into out, with "…" when cut. */
void cdpr_yaml_echo(char *out, size_t cap, const char *s)
{
    size_t n = 0;
    while (s[n] != '\0' && s[n] != '\n' && n < CDPR_YAML_ECHO_MAX) {
        ++n;
    }
    const int cut = (s[n] != '\0' && s[n] != '\n') ? 1 : 0;
    snprintf(out, cap, "%.*s%s", (int)n, s, (cut != 0) ? "\u2026" : "");
}

/* libyaml's syntax error as "FILE:LINE:COLUMN: what": the problem where it was found, the
 * construct it was in (an unclosed list or mapping names where it opened). */
static void syntax_error(const char *path, const yaml_parser_t *ps, char *out, size_t cap)
{
    const char *problem = (ps->problem != NULL) ? ps->problem : "malformed YAML";
    const int line = (int)ps->problem_mark.line + 1;
    const int col = (int)ps->problem_mark.column + 1;
    const char *ctx = (ps->context != NULL) ? ps->context : "";
    const int cline = (int)ps->context_mark.line + 1;
    const int ccol = (int)ps->context_mark.column + 1;
    if (strstr(ctx, "flow sequence") != NULL || strstr(ctx, "flow mapping") != NULL) {
        const int list = (strstr(ctx, "sequence") != NULL) ? 1 : 0;
        snprintf(out, cap,
                 "%s:%d:%d: unclosed %s '%c' (opened at line %d, column %d): %s at line %d, "
                 "column %d",
                 path, cline, ccol, (list != 0) ? "list" : "mapping", (list != 0) ? '[' : '{',
                 cline, ccol, problem, line, col);
    } else if (strstr(ctx, "quoted scalar") != NULL) {
        snprintf(out, cap,
                 "%s:%d:%d: unterminated quoted string (opened at line %d, column %d): %s", path,
                 cline, ccol, cline, ccol, problem);
    } else if (strstr(problem, "cannot start any token") != NULL && ps->problem_value == '\t') {
        snprintf(out, cap, "%s:%d:%d: a tab character: YAML indents with spaces only", path, line,
                 col);
    } else if (ctx[0] != '\0') {
        snprintf(out, cap, "%s:%d:%d: %s (%s at line %d, column %d)", path, line, col, problem, ctx,
                 cline, ccol);
    } else {
        snprintf(out, cap, "%s:%d:%d: %s", path, line, col, problem);
    }
}

/* ---------------------------------------------------------------- the checks before a load */

/* One open collection of the check pass. */
typedef struct {
    const cyaml_schema_value_t *schema; /* its schema, NULL where the schema does not reach */
    const cyaml_schema_value_t *value;  /* mapping: the schema of the current key's value */
    int is_map;                         /* mapping (1) or sequence (0) */
    int want_key;                       /* mapping: the next node is a key */
    int index;                          /* sequence: index of the next entry */
    char key[64];                       /* mapping: the current key */
    char path[CDPR_YAML_CHECK_PATH];    /* key path of this collection ("" at the root) */
} check_frame_t;

/* The whole text is a decimal number: [+-] digits [. digits] [e [+-] digits], at least one
 * digit before the exponent; integers without the fraction and the exponent. strtod would
 * also read hex ("0x10"), "inf", "nan" and a prefix of anything ("4O.0", "400 kg"). */
static int is_decimal(const char *s, int integer)
{
    const char *p = s;
    p += (*p == '+' || *p == '-') ? 1 : 0;
    int digits = 0;
    while (*p >= '0' && *p <= '9') {
        ++p;
        ++digits;
    }
    if (integer == 0 && *p == '.') {
        ++p;
        while (*p >= '0' && *p <= '9') {
            ++p;
            ++digits;
        }
    }
    if (digits == 0) {
        return 0;
    }
    if (integer == 0 && (*p == 'e' || *p == 'E')) {
        ++p;
        p += (*p == '+' || *p == '-') ? 1 : 0;
        if (!(*p >= '0' && *p <= '9')) {
            return 0;
        }
        while (*p >= '0' && *p <= '9') {
            ++p;
        }
    }
    return (*p == '\0') ? 1 : 0;
}

static int is_null_text(const char *s)
{
    return (s[0] == '\0' || strcmp(s, "~") == 0 || strcmp(s, "null") == 0 ||
            strcmp(s, "Null") == 0 || strcmp(s, "NULL") == 0)
               ? 1
               : 0;
}

static const cyaml_schema_field_t *find_field(const cyaml_schema_value_t *map, const char *key)
{
    if (map == NULL || map->type != CYAML_MAPPING || map->mapping.fields == NULL) {
        return NULL;
    }
    for (const cyaml_schema_field_t *f = map->mapping.fields; f->key != NULL; ++f) {
        if (strcmp(f->key, key) == 0) {
            return f;
        }
    }
    return NULL;
}

/* The schema of the node that starts now in `top` (NULL: the root, whose schema is `root`),
 * and its key path into `path`. Consumes the mapping's key or the sequence's index. */
static const cyaml_schema_value_t *node_schema(check_frame_t *top, const cyaml_schema_value_t *root,
                                               char *path, size_t cap)
{
    if (top == NULL) {
        path[0] = '\0';
        return root;
    }
    int n;
    const cyaml_schema_value_t *v;
    if (top->is_map != 0) {
        n = snprintf(path, cap, "%s%s%s", top->path, (top->path[0] != '\0') ? "." : "", top->key);
        v = top->value;
        top->want_key = 1;
    } else {
        n = snprintf(path, cap, "%s[%d]", top->path, top->index);
        ++top->index;
        v = (top->schema != NULL) ? top->schema->sequence.entry : NULL;
    }
    if (n < 0 || (size_t)n >= cap) {
        path[cap - 1U] = '\0';
    }
    return v;
}

/* A non-finite number as strtod (libcyaml) reads one: [+-] inf, infinity, nan, and YAML's
 * .inf and .nan, in any case. */
static int is_non_finite_text(const char *s)
{
    static const char *const words[] = {"inf", "infinity", "nan", ".inf", ".nan"};
    const char *p = s + ((s[0] == '+' || s[0] == '-') ? 1 : 0);
    for (size_t i = 0; i < sizeof words / sizeof words[0]; ++i) {
        if (strcasecmp(p, words[i]) == 0) {
            return 1;
        }
    }
    return 0;
}

/* Why a scalar cannot stand where the schema wants a number (NULL if it can), with the
 * status to return. */
static const char *number_problem(const cyaml_schema_value_t *v, const yaml_event_t *ev,
                                  cdpr_status_t *st)
{
    *st = CDPR_E_PARSE;
    if (v == NULL || !(v->type == CYAML_FLOAT || v->type == CYAML_INT || v->type == CYAML_UINT)) {
        return NULL;
    }
    if (ev->type == YAML_ALIAS_EVENT) {
        return "an alias (*name) where a number is wanted: write the number";
    }
    const char *text = (const char *)ev->data.scalar.value;
    const unsigned flags = (unsigned)v->flags;
    if ((flags & ((unsigned)CYAML_FLAG_POINTER_NULL | (unsigned)CYAML_FLAG_POINTER_NULL_STR)) !=
            0U &&
        is_null_text(text) != 0) {
        return NULL;
    }
    if (is_decimal(text, (v->type == CYAML_FLOAT) ? 0 : 1) != 0) {
        return NULL;
    }
    if (is_non_finite_text(text) != 0) {
        *st = CDPR_E_NOT_FINITE;
        return "not finite";
    }
    return "not a number";
}

/* libyaml's pass over the text (every event, nothing kept) with the checks that libyaml and
 * libcyaml do not make: nesting at most CDPR_YAML_MAX_DEPTH deep (checked as each collection
 * opens, so a deeply nested file costs no more than that depth: libyaml's scanner does work
 * proportional to the flow depth for every token), one document, and, where `schema` (may be
 * NULL) wants a number, a whole decimal number. */
static cdpr_status_t check_text(const char *path, const unsigned char *text, size_t len,
                                const cyaml_schema_value_t *schema, char *out, size_t cap)
{
    yaml_parser_t ps;
    check_frame_t *st = calloc(CDPR_YAML_MAX_DEPTH, sizeof *st);
    if (st == NULL || yaml_parser_initialize(&ps) == 0) {
        free(st);
        snprintf(out, cap, "%s: out of memory", path);
        return CDPR_E_IO;
    }
    yaml_parser_set_input_string(&ps, text, len);
    cdpr_status_t st_ok = CDPR_OK;
    int depth = 0;
    int documents = 0;
    /* Bounded by the text (<= CDPR_YAML_MAX_FILE_BYTES): each iteration consumes one event. */
    for (int done = 0; done == 0;) {
        yaml_event_t ev;
        if (yaml_parser_parse(&ps, &ev) == 0) {
            syntax_error(path, &ps, out, cap);
            st_ok = CDPR_E_PARSE;
            break;
        }
        const int line = (int)ev.start_mark.line + 1;
        const int col = (int)ev.start_mark.column + 1;
        check_frame_t *top = (depth > 0) ? &st[depth - 1] : NULL;
        switch (ev.type) {
        case YAML_STREAM_END_EVENT:
            done = 1;
            break;
        case YAML_DOCUMENT_START_EVENT:
            if (++documents > 1) {
                snprintf(out, cap,
                         "%s:%d: a second YAML document ('---'): a cdpr file holds one document",
                         path, line);
                st_ok = CDPR_E_PARSE;
                done = 1;
            }
            break;
        case YAML_SCALAR_EVENT:
        case YAML_ALIAS_EVENT:
        case YAML_MAPPING_START_EVENT:
        case YAML_SEQUENCE_START_EVENT: {
            if (top != NULL && top->is_map != 0 && top->want_key != 0) {
                top->want_key = 0;
                const char *k =
                    (ev.type == YAML_SCALAR_EVENT) ? (const char *)ev.data.scalar.value : "";
                snprintf(top->key, sizeof top->key, "%s", k);
                const cyaml_schema_field_t *f = find_field(top->schema, k);
                top->value = (f != NULL) ? &f->value : NULL;
                if (ev.type == YAML_SCALAR_EVENT || ev.type == YAML_ALIAS_EVENT) {
                    break;
                }
            }
            char key[CDPR_YAML_CHECK_PATH];
            const cyaml_schema_value_t *v = node_schema(top, schema, key, sizeof key);
            if (ev.type == YAML_SCALAR_EVENT || ev.type == YAML_ALIAS_EVENT) {
                cdpr_status_t why_st;
                const char *why = number_problem(v, &ev, &why_st);
                if (why != NULL) {
                    char what[CDPR_YAML_ECHO_MAX + 256];
                    if (ev.type == YAML_SCALAR_EVENT) {
                        char echo[CDPR_YAML_ECHO_MAX + 8];
                        cdpr_yaml_echo(echo, sizeof echo, (const char *)ev.data.scalar.value);
                        snprintf(what, sizeof what,
                                 "'%s' is %s: a decimal number, the whole value (such as 40.0 "
                                 "or 2e6; no unit, hex, digit separator, inf or nan)",
                                 echo, why);
                    } else {
                        snprintf(what, sizeof what, "%s", why);
                    }
                    cdpr_yaml_format_error(out, cap, path, line,
                                           (key[0] != '\0') ? key : "(document)", what);
                    st_ok = why_st;
                    done = 1;
                }
                break;
            }
            if (depth >= CDPR_YAML_MAX_DEPTH) {
                snprintf(out, cap,
                         "%s:%d:%d: nested deeper than %d levels of lists and mappings (a cdpr "
                         "file needs at most 6)",
                         path, line, col, CDPR_YAML_MAX_DEPTH);
                st_ok = CDPR_E_PARSE;
                done = 1;
                break;
            }
            check_frame_t *f = &st[depth++];
            memset(f, 0, sizeof *f);
            f->is_map = (ev.type == YAML_MAPPING_START_EVENT) ? 1 : 0;
            f->want_key = 1;
            if (v != NULL && ((f->is_map != 0 && v->type == CYAML_MAPPING) ||
                              (f->is_map == 0 &&
                               (v->type == CYAML_SEQUENCE || v->type == CYAML_SEQUENCE_FIXED)))) {
                f->schema = v;
            }
            snprintf(f->path, sizeof f->path, "%s", key);
            break;
        }
        case YAML_MAPPING_END_EVENT:
        case YAML_SEQUENCE_END_EVENT:
            depth = (depth > 0) ? depth - 1 : 0;
            break;
        default:
            break;
        }
        yaml_event_delete(&ev);
    }
    yaml_parser_delete(&ps);
    free(st);
    return st_ok;
}

/* The file's bytes into a new buffer (free it), through cdpr_fs_open_regular: a regular file
 * of at most CDPR_YAML_MAX_FILE_BYTES, read once. */
static cdpr_status_t read_file(const char *path, unsigned char **buf, size_t *len, char *out,
                               size_t cap)
{
    *buf = NULL;
    *len = 0;
    char why[256];
    int fd;
    const cdpr_status_t os = cdpr_fs_open_regular(path, 0, &fd, why, sizeof why);
    if (os == CDPR_E_IO) {
        snprintf(out, cap, "%s", why);
        return CDPR_E_IO;
    }
    if (os != CDPR_OK) {
        snprintf(out, cap, "%s: %s, not a YAML file", path, why);
        return CDPR_E_PARSE;
    }
    struct stat sb;
    if (fstat(fd, &sb) == 0 && sb.st_size > (off_t)CDPR_YAML_MAX_FILE_BYTES) {
        (void)close(fd);
        snprintf(out, cap,
                 "%s: %lld bytes: larger than the limit of YAML input files (%ld bytes, 1 MiB)",
                 path, (long long)sb.st_size, (long)CDPR_YAML_MAX_FILE_BYTES);
        return CDPR_E_PARSE;
    }
    /* One byte more than the limit tells a file that grew while read. */
    const size_t room = (size_t)CDPR_YAML_MAX_FILE_BYTES + 1U;
    unsigned char *b = malloc(room);
    if (b == NULL) {
        (void)close(fd);
        snprintf(out, cap, "%s: out of memory", path);
        return CDPR_E_IO;
    }
    size_t n = 0;
    while (n < room) {
        const ssize_t r = read(fd, b + n, room - n);
        if (r < 0 && errno == EINTR) {
            continue;
        }
        if (r < 0) {
            snprintf(out, cap, "%s", strerror(errno));
            free(b);
            (void)close(fd);
            return CDPR_E_IO;
        }
        if (r == 0) {
            break;
        }
        n += (size_t)r;
    }
    (void)close(fd);
    if (n > (size_t)CDPR_YAML_MAX_FILE_BYTES) {
        snprintf(out, cap,
                 "%s: grew past the limit of YAML input files (%ld bytes, 1 MiB) while read", path,
                 (long)CDPR_YAML_MAX_FILE_BYTES);
        free(b);
        return CDPR_E_PARSE;
    }
    *buf = b;
    *len = n;
    return CDPR_OK;
}

cdpr_status_t cdpr_yaml_check_file(const char *path, char *out, size_t cap)
{
    out[0] = '\0';
    unsigned char *buf;
    size_t len;
    cdpr_status_t st = read_file(path, &buf, &len, out, cap);
    if (st == CDPR_OK) {
        st = check_text(path, buf, len, NULL, out, cap);
        free(buf);
    }
    return st;
}

cdpr_status_t cdpr_yaml_load(const char *path, const cyaml_schema_value_t *schema,
                             cyaml_cfg_flags_t flags, void **data, cdpr_yaml_log_t *log)
{
    memset(log, 0, sizeof *log);
    *data = NULL;
    unsigned char *buf;
    size_t len;
    cdpr_status_t cs = read_file(path, &buf, &len, log->text, sizeof log->text);
    if (cs == CDPR_OK) {
        cs = check_text(path, buf, len, schema, log->text, sizeof log->text);
    }
    if (cs != CDPR_OK) {
        free(buf);
        log->len = strlen(log->text);
        log->whole = (cs == CDPR_E_IO) ? 0 : 1;
        log->what_at = (log->whole != 0) ? strlen(path) + 1 : 0;
        return cs;
    }
    /* The bytes checked above, not the path again: what is checked is what is loaded. */
    const cyaml_config_t cfg = config(flags, log);
    cyaml_data_t *out = NULL;
    log->err = cyaml_load_data(buf, len, &cfg, schema, &out, NULL);
    free(buf);
    if (log->err != CYAML_OK) {
        return CDPR_E_PARSE;
    }
    if (out == NULL) {
        log->empty = 1;
        return CDPR_E_PARSE;
    }
    *data = out;
    return CDPR_OK;
}

const char *cdpr_yaml_first_error(const cdpr_yaml_log_t *log, char *buf, size_t cap)
{
    const char *what = log->text + ((log->what_at < log->len) ? log->what_at : 0);
    what += (what[0] == ' ') ? 1 : 0;
    snprintf(buf, cap, "%s", (log->text[0] != '\0') ? what : cyaml_strerror(log->err));
    char *nl = strchr(buf, '\n');
    if (nl != NULL) {
        *nl = '\0';
    }
    return buf;
}

void cdpr_yaml_free(const cyaml_schema_value_t *schema, void *data)
{
    if (data != NULL) {
        const cyaml_config_t cfg = config(CYAML_CFG_DEFAULT, NULL);
        (void)cyaml_free(&cfg, schema, data, 0);
    }
}

/* ---------------------------------------------------------------- key lines */

#define PATH_DEPTH 16
#define PATH_LEN   256

typedef struct {
    int is_map;          /* mapping (1) or sequence (0) */
    int want_key;        /* mapping: the next scalar is a key */
    int index;           /* sequence: index of the next entry */
    int key_line;        /* mapping: line of the current key */
    char key[64];        /* mapping: the current key */
    char path[PATH_LEN]; /* path of this collection */
} frame_t;

/* Path and line of the node that starts now, in the collection `f` (NULL: the root). */
static int node_path(frame_t *f, int ev_line, char *path, size_t cap)
{
    if (f == NULL) {
        path[0] = '\0';
        return ev_line;
    }
    int n;
    int line;
    if (f->is_map != 0) {
        n = snprintf(path, cap, "%s%s%s", f->path, (f->path[0] != '\0') ? "." : "", f->key);
        f->want_key = 1;
        line = f->key_line;
    } else {
        n = snprintf(path, cap, "%s[%d]", f->path, f->index);
        ++f->index;
        line = ev_line;
    }
    if (n < 0 || (size_t)n >= cap) {
        path[0] = '\0'; /* deeper than any scenario key: matches nothing */
    }
    return line;
}

/* One walk of the file: the line of `want`, or 0. Frames live on the heap (16 x 344 bytes). */
static int walk_line(const char *path, const char *want)
{
    FILE *fp = cdpr_fs_fopen(path, "rb", NULL, 0);
    if (fp == NULL) {
        return 0;
    }
    yaml_parser_t parser;
    if (yaml_parser_initialize(&parser) == 0) {
        fclose(fp);
        return 0;
    }
    yaml_parser_set_input_file(&parser, fp);
    frame_t *st = calloc(PATH_DEPTH, sizeof *st);
    int depth = 0;
    int found = 0;
    int done = (st == NULL) ? 1 : 0;
    /* Bounded by the file: every iteration consumes one event; an error or stream end stops. */
    while (done == 0) {
        yaml_event_t ev;
        if (yaml_parser_parse(&parser, &ev) == 0) {
            break;
        }
        const int line = (int)ev.start_mark.line + 1;
        frame_t *top = (depth > 0) ? &st[depth - 1] : NULL;
        switch (ev.type) {
        case YAML_STREAM_END_EVENT:
            done = 1;
            break;
        case YAML_SCALAR_EVENT:
        case YAML_ALIAS_EVENT:
        case YAML_MAPPING_START_EVENT:
        case YAML_SEQUENCE_START_EVENT:
            if (top != NULL && top->is_map != 0 && top->want_key != 0) {
                /* A key (only scalar keys are addressable). */
                snprintf(top->key, sizeof top->key, "%s",
                         (ev.type == YAML_SCALAR_EVENT) ? (const char *)ev.data.scalar.value : "");
                top->key_line = line;
                top->want_key = 0;
                if (ev.type == YAML_SCALAR_EVENT) {
                    break;
                }
            }
            {
                char p[PATH_LEN];
                const int node_line = node_path(top, line, p, sizeof p);
                if (top != NULL && strcmp(p, want) == 0) {
                    found = node_line;
                    done = 1;
                    break;
                }
                if (ev.type == YAML_MAPPING_START_EVENT || ev.type == YAML_SEQUENCE_START_EVENT) {
                    if (depth >= PATH_DEPTH) {
                        done = 1;
                        break;
                    }
                    frame_t *f = &st[depth++];
                    memset(f, 0, sizeof *f);
                    f->is_map = (ev.type == YAML_MAPPING_START_EVENT) ? 1 : 0;
                    f->want_key = 1;
                    snprintf(f->path, sizeof f->path, "%s", p);
                }
            }
            break;
        case YAML_MAPPING_END_EVENT:
        case YAML_SEQUENCE_END_EVENT:
            depth = (depth > 0) ? depth - 1 : 0;
            break;
        default:
            break;
        }
        yaml_event_delete(&ev);
    }
    free(st);
    yaml_parser_delete(&parser);
    fclose(fp);
    return found;
}

int cdpr_yaml_path_line(const char *path, const char *key)
{
    if (path == NULL || path[0] == '\0' || key == NULL) {
        return 0;
    }
    char want[PATH_LEN];
    snprintf(want, sizeof want, "%s", key);
    const int line = walk_line(path, want);
    char *bracket = strrchr(want, '[');
    if (line > 0 || bracket == NULL || strchr(bracket, '.') != NULL) {
        return line;
    }
    *bracket = '\0'; /* a list shorter than the index: the list's own line */
    return walk_line(path, want);
}

/* ---------------------------------------------------------------- error text */

void cdpr_yaml_format_error(char *out, size_t cap, const char *path, int line, const char *key,
                            const char *what)
{
    if (path == NULL || path[0] == '\0') {
        snprintf(out, cap, "scenario: %s: %s", key, what);
    } else if (line > 0) {
        snprintf(out, cap, "%s:%d: %s: %s", path, line, key, what);
    } else {
        snprintf(out, cap, "%s: %s: %s", path, key, what);
    }
}

/* One backtrace entry: "in mapping field 'k' (line: L, ...)", "in sequence entry 'i' (...)",
 * "in mapping (...)". */
typedef struct {
    char kind; /* 'f' field, 's' sequence entry, 'm' mapping */
    char name[64];
    int line;
} trace_t;

static int parse_trace_line(const char *s, trace_t *t)
{
    const char *p;
    const char *open = NULL;
    if ((p = strstr(s, "in mapping field '")) != NULL) {
        t->kind = 'f';
        open = p + strlen("in mapping field '");
    } else if ((p = strstr(s, "in sequence entry '")) != NULL) {
        t->kind = 's';
        open = p + strlen("in sequence entry '");
    } else if (strstr(s, "in mapping") != NULL) {
        t->kind = 'm';
    } else {
        return 0;
    }
    t->name[0] = '\0';
    if (open != NULL) {
        const char *close = strchr(open, '\'');
        if (close == NULL) {
            return 0;
        }
        size_t n = (size_t)(close - open);
        n = (n < sizeof t->name - 1) ? n : sizeof t->name - 1;
        memcpy(t->name, open, n);
        t->name[n] = '\0';
    }
    const char *ln = strstr(s, "(line: ");
    t->line = (ln != NULL) ? (int)strtol(ln + strlen("(line: "), NULL, 10) : 0;
    return 1;
}

void cdpr_yaml_error_message(const char *path, const cdpr_yaml_log_t *lb, char *out, size_t cap)
{
    if (lb->whole != 0) {
        snprintf(out, cap, "%s", lb->text); /* the file check's message, whole */
        return;
    }
    char message[512] = "";
    trace_t trace[PATH_DEPTH];
    memset(trace, 0, sizeof trace);
    int nt = 0;
    /* Walk the collected lines. */
    const char *s = lb->text;
    while (*s != '\0') {
        const char *eol = strchr(s, '\n');
        const size_t n = (eol != NULL) ? (size_t)(eol - s) : strlen(s);
        char line[512];
        const size_t m = (n < sizeof line - 1) ? n : sizeof line - 1;
        memcpy(line, s, m);
        line[m] = '\0';
        if (strncmp(line, "Load: ", 6) == 0 && strstr(line, "Backtrace") == NULL &&
            message[0] == '\0') {
            snprintf(message, sizeof message, "%s", line + 6);
        } else if (nt < PATH_DEPTH && parse_trace_line(line, &trace[nt]) != 0) {
            ++nt;
        }
        s += n;
        if (*s == '\n') {
            ++s;
        }
    }
    /* Which key: a key that libcyaml names in its message, else the innermost field. */
    static const char unexpected[] = "Unexpected key: ";
    static const char missing[] = "Missing required mapping field: ";
    const char *named = NULL;
    int is_unknown = 0;
    int skip_innermost_field = 0;
    if (strstr(message, unexpected) == message) {
        named = message + sizeof unexpected - 1;
        is_unknown = 1;
    } else if (strstr(message, missing) == message) {
        named = message + sizeof missing - 1;
        /* The innermost "field" entry is the mapping's last visited field, not the key. */
        skip_innermost_field = (nt > 0 && trace[0].kind == 'f') ? 1 : 0;
    } else if (strstr(message, " entries (") != NULL && nt > 0 && trace[0].kind == 's') {
        /* "Insufficient/Excessive entries" of a list inside a list: the innermost entry is
         * the count read so far, not a position. */
        skip_innermost_field = 1;
    }
    char key[512] = "";
    for (int i = nt - 1; i >= skip_innermost_field; --i) {
        const size_t k = strlen(key);
        if (trace[i].kind == 'f') {
            snprintf(key + k, sizeof key - k, "%s%.63s", (k > 0) ? "." : "", trace[i].name);
        } else if (trace[i].kind == 's') {
            /* libcyaml counts entries from 1 once it has started one; keys count from 0. */
            const long idx = strtol(trace[i].name, NULL, 10);
            snprintf(key + k, sizeof key - k, "[%ld]", (idx > 0) ? idx - 1 : 0);
        }
    }
    if (named != NULL) {
        const size_t k = strlen(key);
        snprintf(key + k, sizeof key - k, "%s%.63s", (k > 0) ? "." : "", named);
    }
    /* libcyaml's line is where it noticed the problem; prefer the line of the key itself
     * (or, for a missing key, of the mapping that lacks it). */
    int line = (nt > 0) ? trace[0].line : 0;
    char parent[512];
    snprintf(parent, sizeof parent, "%s", key);
    if (named != NULL && is_unknown == 0) {
        char *dot = strrchr(parent, '.');
        parent[(dot != NULL) ? (size_t)(dot - parent) : 0] = '\0';
    }
    const int key_line = (parent[0] != '\0') ? cdpr_yaml_path_line(path, parent) : 0;
    line = (key_line > 0) ? key_line : line;
    char what[640];
    if (is_unknown != 0) {
        snprintf(what, sizeof what, "unknown key");
    } else if (named != NULL) {
        snprintf(what, sizeof what, "missing required key");
    } else if (message[0] != '\0') {
        /* libcyaml echoes the offending value after ": " ("Invalid FLOAT value: heavy"): keep
         * it short. */
        char *value = strstr(message, ": ");
        if (value != NULL) {
            char echo[CDPR_YAML_ECHO_MAX + 8];
            cdpr_yaml_echo(echo, sizeof echo, value + 2);
            snprintf(value + 2, sizeof message - (size_t)(value + 2 - message), "%s", echo);
        }
        snprintf(what, sizeof what, "%s", message);
    } else {
        snprintf(what, sizeof what, "%s", cyaml_strerror(lb->err));
    }
    if (key[0] == '\0') {
        snprintf(key, sizeof key, "(document)");
    }
    cdpr_yaml_format_error(out, cap, path, line, key, what);
}

cdpr_status_t cdpr_yaml_range(const char *base, const double *x, int n, double lo, double hi,
                              int lo_open, char *key, size_t key_cap, char *what, size_t what_cap)
{
    for (int i = 0; i < n; ++i) {
        cdpr_status_t st = CDPR_OK;
        if (!isfinite(x[i])) {
            snprintf(what, what_cap, "not a finite number (%g)", x[i]);
            st = CDPR_E_NOT_FINITE;
        } else if (x[i] > hi || x[i] < lo || (lo_open != 0 && !(x[i] > lo))) {
            snprintf(what, what_cap, "%g is outside %s%g, %g]", x[i], (lo_open != 0) ? "(" : "[",
                     lo, hi);
            st = CDPR_E_OUT_OF_RANGE;
        }
        if (st != CDPR_OK) {
            if (n > 1) {
                snprintf(key, key_cap, "%s[%d]", base, i);
            } else {
                snprintf(key, key_cap, "%s", base);
            }
            return st;
        }
    }
    return CDPR_OK;
}

const char *cdpr_yaml_enum_name(const cyaml_strval_t *names, size_t n, int64_t value,
                                const char *fallback)
{
    for (size_t i = 0; i < n; ++i) {
        if (names[i].val == value) {
            return names[i].str;
        }
    }
    return fallback;
}

int64_t cdpr_yaml_enum_value(const cyaml_strval_t *names, size_t n, const char *name,
                             int64_t fallback)
{
    for (size_t i = 0; (name != NULL) && (i < n); ++i) {
        if (strcmp(names[i].str, name) == 0) {
            return names[i].val;
        }
    }
    return fallback;
}

cdpr_status_t cdpr_yaml_load_reported(const char *path, const char *shown,
                                      const cyaml_schema_value_t *schema, const char *what,
                                      void **data, char *msg, size_t cap)
{
    cdpr_yaml_log_t lg;
    const cdpr_status_t st = cdpr_yaml_load(path, schema, CYAML_CFG_DEFAULT, data, &lg);
    if (st == CDPR_E_IO) {
        snprintf(msg, cap, "%s: cannot open %s: %.512s", shown, what, lg.text);
    } else if (st != CDPR_OK && lg.empty != 0) {
        snprintf(msg, cap, "%s: empty %s", shown, what);
    } else if (st != CDPR_OK) {
        cdpr_yaml_error_message(shown, &lg, msg, cap);
    }
    return st;
}
