/* SPDX-License-Identifier: BSD-3-Clause */
/// @file app_cli.c
/// The apps' shared command-line conventions and data-file lookup (app_cli.h).
#include "app_cli.h"

#include <stdarg.h>
#include <stdlib.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "app_status.h"
#include "cdpr/version.h"

/* Relative path from the installed executables to the data directory, e.g. "../share/cdpr"
 * (apps/CMakeLists.txt); the two absolute fallbacks. */
#ifndef CDPR_BIN_TO_DATA
#define CDPR_BIN_TO_DATA "../share/cdpr"
#endif
#ifndef CDPR_SOURCE_DIR
#define CDPR_SOURCE_DIR "."
#endif
#ifndef CDPR_DATA_DIR
#define CDPR_DATA_DIR "/usr/local/share/cdpr"
#endif

void cdpr_app_print_version(const char *prog)
{
    printf("%s %s (git %s)\n", prog, CDPR_VERSION_STRING, CDPR_GIT_DESCRIBE);
}

cdpr_status_t cdpr_app_usage_error(const char *prog, const char *fmt, ...)
{
    char what[512];
    va_list ap;
    va_start(ap, fmt);
    /* clang-tidy 14's va_list checker misfires here when it analyses several files in one
     * run (the same false positive lib/host/include/cdpr/host/scenario.h works around). */
    (void)vsnprintf(what, sizeof what, fmt, ap); // NOLINT(clang-analyzer-valist.Uninitialized)
    va_end(ap);
    fprintf(stderr, "%s: %s; try '%s --help'\n", prog, what, prog);
    return CDPR_E_INVALID_ARG;
}

/* The table entries whose name starts with the `len` characters of `name` (getopt_long takes
 * an unambiguous prefix): how many distinct ones, the first in *first and the exact match, if
 * any, in *exact. */
static int prefix_matches(const struct option *longopts, const char *name, size_t len,
                          const struct option **first, const struct option **exact)
{
    int n = 0;
    *first = NULL;
    *exact = NULL;
    for (const struct option *o = longopts; o->name != NULL; ++o) {
        if (strncmp(o->name, name, len) != 0) {
            continue;
        }
        if (strlen(o->name) == len) {
            *exact = o;
        }
        if (*first == NULL) {
            *first = o;
            n = 1;
        } else if (o->has_arg != (*first)->has_arg || o->flag != (*first)->flag ||
                   o->val != (*first)->val) {
            n++;
        }
    }
    return n;
}

cdpr_status_t cdpr_app_bad_option(const char *prog, int c, char *const argv[],
                                  const struct option *longopts)
{
    /* getopt_long has moved optind past a long option it rejected: argv[optind - 1] is it. */
    const char *arg = (optind > 0) ? argv[optind - 1] : "";
    const int is_long = (strncmp(arg, "--", 2) == 0 && arg[2] != '\0') ? 1 : 0;
    const char *name = (is_long != 0) ? arg + 2 : "";
    const char *eq = strchr(name, '=');
    const size_t len = (eq != NULL) ? (size_t)(eq - name) : strlen(name);
    const struct option *first = NULL;
    const struct option *exact = NULL;
    const int n = (is_long != 0) ? prefix_matches(longopts, name, len, &first, &exact) : 0;
    /* A known long option that getopt_long rejected carries its code in optopt (an unknown or
     * ambiguous one 0); a short one is optopt alone. */
    const struct option *known = (exact != NULL) ? exact : ((n == 1) ? first : NULL);
    const int long_rejected = (known != NULL && optopt != 0 && optopt == known->val) ? 1 : 0;
    if (c == ':') {
        if (long_rejected != 0) {
            return cdpr_app_usage_error(prog, "option '--%s' requires an argument", known->name);
        }
        return cdpr_app_usage_error(prog, "option requires an argument -- '%c'", optopt);
    }
    if (long_rejected != 0) {
        return cdpr_app_usage_error(prog, "option '--%s' doesn't allow an argument", known->name);
    }
    if (is_long != 0 && optopt == 0) {
        if (known == NULL && n > 1) {
            return cdpr_app_usage_error(prog, "option '%.*s' is ambiguous", (int)len + 2, arg);
        }
        return cdpr_app_usage_error(prog, "unrecognized option '%s'", arg);
    }
    if (optopt > 0 && optopt < 0x80) {
        return cdpr_app_usage_error(prog, "invalid option -- '%c'", optopt);
    }
    return cdpr_app_usage_error(prog, "invalid option '%s'", arg);
}

/* dir/rel into buf: CDPR_OK, or CDPR_E_INVALID_ARG when it does not fit. */
static cdpr_status_t join(char *buf, size_t cap, const char *dir, const char *rel)
{
    const int n = snprintf(buf, cap, "%s/%s", dir, rel);
    return (n >= 0 && (size_t)n < cap) ? CDPR_OK : CDPR_E_INVALID_ARG;
}

static int exists(const char *path)
{
    struct stat sb;
    return stat(path, &sb) == 0 && S_ISREG(sb.st_mode);
}

cdpr_status_t cdpr_app_exe_dir(char *dir, size_t cap)
{
    if (cap < 2U) {
        return CDPR_E_IO;
    }
    const ssize_t n = readlink("/proc/self/exe", dir, cap - 1U);
    if (n <= 0 || (size_t)n >= cap - 1U) {
        return CDPR_E_IO;
    }
    dir[n] = '\0';
    char *slash = strrchr(dir, '/');
    if (slash == NULL) {
        return CDPR_E_IO;
    }
    *slash = '\0';
    return CDPR_OK;
}

cdpr_status_t cdpr_app_data_file(const char *rel, char *buf, size_t cap)
{
    if (cap == 0U) {
        return CDPR_E_INVALID_ARG;
    }
    buf[0] = '\0';
    /* 1. Next to the executable: <exe dir>/../share/cdpr/rel. */
    char exe[1024];
    int have_first = 0;
    if (cdpr_app_exe_dir(exe, sizeof exe) == CDPR_OK) {
        char dir[1100];
        if (join(dir, sizeof dir, exe, CDPR_BIN_TO_DATA) != CDPR_OK ||
            join(buf, cap, dir, rel) != CDPR_OK) {
            return CDPR_E_INVALID_ARG;
        }
        if (exists(buf) != 0) {
            return CDPR_OK;
        }
        have_first = 1;
    }
    /* 2. The source tree, 3. the configured data directory. */
    char first[1100];
    snprintf(first, sizeof first, "%s", buf);
    const char *const fallbacks[] = {CDPR_SOURCE_DIR, CDPR_DATA_DIR};
    for (size_t i = 0; i < sizeof fallbacks / sizeof fallbacks[0]; ++i) {
        if (join(buf, cap, fallbacks[i], rel) != CDPR_OK) {
            return CDPR_E_INVALID_ARG;
        }
        if (exists(buf) != 0) {
            return CDPR_OK;
        }
        if (have_first == 0) {
            snprintf(first, sizeof first, "%s", buf);
            have_first = 1;
        }
    }
    snprintf(buf, cap, "%s", first);
    return CDPR_E_IO;
}

cdpr_status_t cdpr_app_other_option(const char *prog, int c, char *const argv[],
                                    const struct option *longopts, void (*usage)(FILE *))
{
    if (c == 'h') {
        usage(stdout);
        exit(cdpr_app_exit_code(CDPR_OK));
    }
    if (c == CDPR_APP_OPT_VERSION) {
        cdpr_app_print_version(prog);
        exit(cdpr_app_exit_code(CDPR_OK));
    }
    return cdpr_app_bad_option(prog, c, argv, longopts);
}

int cdpr_app_store(const cdpr_app_store_t *stores, size_t n, int c, const char *arg)
{
    for (size_t i = 0; i < n; ++i) {
        const cdpr_app_store_t *st = &stores[i];
        if (st->code != c) {
            continue;
        }
        if (st->text != NULL) {
            *st->text = arg;
        } else {
            *st->flag = st->value;
        }
        return 0;
    }
    return 1;
}

int cdpr_app_parse(const char *prog, int argc, char **argv, const struct option *longopts,
                   void (*usage)(FILE *), cdpr_app_option_fn take, void *ctx)
{
    int c;
    opterr = 0;
    while ((c = getopt_long(argc, argv, CDPR_APP_OPTSTRING, longopts, NULL)) != -1) {
        const int r = (c == '?' || c == ':') ? 1 : take(c, optarg, ctx);
        if (r > 0) {
            (void)cdpr_app_other_option(prog, c, argv, longopts, usage);
        }
        if (r != 0) {
            return -1;
        }
    }
    return 0;
}

cdpr_status_t cdpr_app_scenario_operand(const char *prog, int argc, char *const argv[],
                                        const char **scenario)
{
    if (optind >= argc) {
        return cdpr_app_usage_error(prog, "missing SCENARIO");
    }
    *scenario = argv[optind++];
    if (optind < argc) {
        return cdpr_app_usage_error(prog, "unexpected argument '%s'", argv[optind]);
    }
    return CDPR_OK;
}
