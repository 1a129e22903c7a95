/// @file yaml.c
/// The libcyaml loader set-up (yaml.h).
#include "cdpr/host/yaml.h"

#include <errno.h>
#include <stdarg.h> /* collect_log (libcyaml hands a va_list) */
#include <stdio.h>
#include <string.h>

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

cdpr_status_t cdpr_yaml_load(const char *path, const cyaml_schema_value_t *schema,
                             cyaml_cfg_flags_t flags, void **data, cdpr_yaml_log_t *log)
{
    memset(log, 0, sizeof *log);
    *data = NULL;
    FILE *probe = fopen(path, "rb");
    if (probe == NULL) {
        snprintf(log->text, sizeof log->text, "%s", strerror(errno));
        log->len = strlen(log->text);
        return CDPR_E_IO;
    }
    fclose(probe);
    const cyaml_config_t cfg = config(flags, log);
    cyaml_data_t *out = NULL;
    log->err = cyaml_load_file(path, &cfg, schema, &out, NULL);
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
    snprintf(buf, cap, "%s", (log->text[0] != '\0') ? log->text : cyaml_strerror(log->err));
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
