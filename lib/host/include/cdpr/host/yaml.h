/* SPDX-License-Identifier: BSD-3-Clause */
/// @file yaml.h
/// The one libcyaml set-up of the host library: configuration, a log callback that collects
/// libcyaml's error lines, load and free. Used by the scenario loader (scenario.h) and the
/// summary.json reader (summary.h) and the robot files (rig.h); key lines and error text. Internal
/// to lib/host (its users include libcyaml anyway).
///
/// Host library; loading allocates (libcyaml); cdpr_yaml_free releases it.
#ifndef CDPR_HOST_YAML_H
#define CDPR_HOST_YAML_H

#include <stddef.h>
#include <stdint.h>

#include <cyaml/cyaml.h>

#include "cdpr/status.h"

/// What a load said (outputs).
typedef struct {
    char text[4096]; ///< libcyaml's error lines in order ("" if none); on CDPR_E_IO the reason
    size_t len;      ///< length of text
    cyaml_err_t err; ///< libcyaml's result (CYAML_OK for an unreadable or empty file)
    int empty;       ///< 1: the file holds no document
    int whole;       ///< 1: text is the whole message of cdpr_yaml_check_file ("FILE...: what")
    size_t what_at;  ///< whole: where the part after "FILE:" starts in text
} cdpr_yaml_log_t;

/// Largest YAML input file [bytes] (1 MiB; the shipped scenarios and robot files are < 4 kB,
/// and the key-line lookups parse the file again for every error, so the work of a refusal is
/// bounded by it). Checked with fstat before anything parses the file.
#define CDPR_YAML_MAX_FILE_BYTES (1024L * 1024L)

/// Deepest nesting of lists and mappings in a YAML input file (the shipped files need at most
/// 6). Checked as each collection opens, before libcyaml reads anything: libyaml's scanner
/// does work proportional to the flow depth for every token, so an unbounded depth makes a
/// 1 MiB file cost minutes.
#define CDPR_YAML_MAX_DEPTH 32

/// Longest key path the checks name [characters] (deeper paths are cut).
#define CDPR_YAML_CHECK_PATH 256

/// Longest piece of a file's text echoed in an error message [characters]; longer pieces are
/// cut and end in "…".
#define CDPR_YAML_ECHO_MAX 60

/// The checks before any parse: the file opens without blocking (cdpr_fs_open_regular: a FIFO
/// or a device never blocks the caller; CDPR_E_IO, out = strerror), is a regular file ("FILE:
/// is a directory, not a YAML file", "FILE: not a regular file (a pipe, socket or device), not
/// a YAML file"), at most CDPR_YAML_MAX_FILE_BYTES, valid YAML syntax (one libyaml pass;
/// "FILE:LINE:COLUMN: what", the construct named where it opened: "unclosed list '[' (opened
/// at line 7, column 11)", "a tab character: YAML indents with spaces only"), nested at most
/// CDPR_YAML_MAX_DEPTH deep, and one document ("FILE:LINE: a second YAML document"); those
/// give CDPR_E_PARSE with the whole message in `out`. Work: one read of at most 1 MiB; the
/// file's bytes and libyaml's parser allocated and freed. Returns CDPR_OK otherwise.
cdpr_status_t cdpr_yaml_check_file(const char *path, char *out, size_t cap);

/// At most CDPR_YAML_ECHO_MAX characters of `s` (up to its first newline) into out, "…"
/// appended when cut.
void cdpr_yaml_echo(char *out, size_t cap, const char *s);

/// Load `path` against `schema` (a CYAML_FLAG_POINTER mapping) into *data: the file read once,
/// cdpr_yaml_check_file's checks on its bytes plus strict numbers (every value where the
/// schema wants a number is a whole decimal number: "mass_kg: 4O.0", "400 kg", "0x10",
/// "2_000_000", "inf" refused as "FILE:LINE: KEY: '4O.0' is not a number: ...", where libcyaml
/// alone would read the prefix), then libcyaml on the same bytes. `flags`: libcyaml configuration
/// flags (CYAML_CFG_DEFAULT, CYAML_CFG_IGNORE_UNKNOWN_KEYS, ...). Returns CDPR_OK (*data set: free
/// it with cdpr_yaml_free), CDPR_E_IO (the file cannot be opened; log->text holds strerror) or
/// CDPR_E_PARSE (the file check refused it: log->whole = 1, log->text its message; or libcyaml
/// refused it, log->err and log->text say why; or the file is empty, log->empty = 1); *data is
/// NULL on error.
cdpr_status_t cdpr_yaml_load(const char *path, const cyaml_schema_value_t *schema,
                             cyaml_cfg_flags_t flags, void **data, cdpr_yaml_log_t *log);

/// cdpr_yaml_load of `path` (CYAML_CFG_DEFAULT) with the failure said in `msg` for a user,
/// naming the file as `shown` (the path the user gave) and its kind as `what` ("robot file"):
/// "SHOWN: cannot open WHAT: why", "SHOWN: empty WHAT", or the parser's first error
/// (cdpr_yaml_error_message). Returns as cdpr_yaml_load; `msg` is untouched on success.
cdpr_status_t cdpr_yaml_load_reported(const char *path, const char *shown,
                                      const cyaml_schema_value_t *schema, const char *what,
                                      void **data, char *msg, size_t cap);

/// First line of the collected error text, else libcyaml's message for log->err, into `buf`.
/// Returns buf.
const char *cdpr_yaml_first_error(const cdpr_yaml_log_t *log, char *buf, size_t cap);

/// Line (1-based) of the node at `key` in the YAML file `path`, or 0 if it is not there. `key`
/// is a dotted path of mapping keys with "[i]" (0-based) for sequence entries:
/// "robot.cables[2].rope.ea_N", "cabin.com_m[1]". A mapping value gives the line of its key, a
/// sequence entry its own line; a path whose last "[i]" is not there (a short list) gives the
/// line of the list. Uses libyaml; reads the file once.
int cdpr_yaml_path_line(const char *path, const char *key);

/// "FILE:LINE: KEY: what" ("FILE: KEY: what" without a line, "scenario: KEY: what" without a
/// file) into out.
void cdpr_yaml_format_error(char *out, size_t cap, const char *path, int line, const char *key,
                            const char *what);

/// libcyaml's error of a failed load (log) as "FILE:LINE: KEY: what": the key path from its
/// backtrace ("unknown key", "missing required key" or libcyaml's message), the line of the
/// key itself where libyaml finds it.
void cdpr_yaml_error_message(const char *path, const cdpr_yaml_log_t *log, char *out, size_t cap);

/// The range check of a file's values: every x[i] (n >= 1) finite and in [lo, hi] ((lo, hi]
/// when lo_open). For the first that is not: its key into `key` ("BASE[i]" when n > 1, else
/// "BASE"), why into `what` ("not a finite number (nan)", "-1 is outside (0, 100]"), and
/// CDPR_E_NOT_FINITE or CDPR_E_OUT_OF_RANGE; CDPR_OK otherwise (nothing written). O(n).
cdpr_status_t cdpr_yaml_range(const char *base, const double *x, int n, double lo, double hi,
                              int lo_open, char *key, size_t key_cap, char *what, size_t what_cap);

/// The name of `value` in a libcyaml enum table (the one a schema parses the key with, so a
/// name is spelled once for reading and writing); `fallback` when the table lacks it. O(n).
const char *cdpr_yaml_enum_name(const cyaml_strval_t *names, size_t n, int64_t value,
                                const char *fallback);

/// The value of `name` in a libcyaml enum table; `fallback` when the table lacks it. O(n).
int64_t cdpr_yaml_enum_value(const cyaml_strval_t *names, size_t n, const char *name,
                             int64_t fallback);

/// Free what cdpr_yaml_load returned (NULL is fine).
void cdpr_yaml_free(const cyaml_schema_value_t *schema, void *data);

#endif /* CDPR_HOST_YAML_H */
