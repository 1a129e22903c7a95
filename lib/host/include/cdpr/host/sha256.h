/* SPDX-License-Identifier: BSD-3-Clause */
/// @file sha256.h
/// SHA-256 (FIPS 180-4) of a byte string or a file: the provenance of a run's outputs names
/// the scenario file by the hash of its bytes (summary.json "scenario_sha256").
///
/// Host library; no allocation (a file is read through a fixed buffer).
#ifndef CDPR_HOST_SHA256_H
#define CDPR_HOST_SHA256_H

#include <stddef.h>
#include <stdint.h>

#include "cdpr/status.h"

/// Digest length [bytes] and length of its lower-case hex text without the NUL.
#define CDPR_SHA256_BYTES 32
#define CDPR_SHA256_HEX   64

/// Incremental hash state (fields internal).
typedef struct {
    uint32_t h[8];
    uint64_t bytes; ///< message length so far
    unsigned char block[64];
    size_t used; ///< bytes in `block`
} cdpr_sha256_t;

/// Start a hash.
void cdpr_sha256_init(cdpr_sha256_t *s);

/// Hash `n` more bytes of `data` (n == 0 allowed, data may then be NULL).
void cdpr_sha256_update(cdpr_sha256_t *s, const void *data, size_t n);

/// Finish: the digest into `out`. `s` must be initialised again before reuse.
void cdpr_sha256_final(cdpr_sha256_t *s, unsigned char out[CDPR_SHA256_BYTES]);

/// Lower-case hex of a digest into `hex` (CDPR_SHA256_HEX characters and a NUL).
void cdpr_sha256_hex(const unsigned char digest[CDPR_SHA256_BYTES], char hex[CDPR_SHA256_HEX + 1]);

/// Hex SHA-256 of the bytes of file `path`. Returns CDPR_OK, or CDPR_E_IO (cannot open or
/// read; errno set) with `hex` the empty string.
cdpr_status_t cdpr_sha256_file(const char *path, char hex[CDPR_SHA256_HEX + 1]);

#endif /* CDPR_HOST_SHA256_H */
