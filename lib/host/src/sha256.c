/* SPDX-License-Identifier: BSD-3-Clause */
/// @file sha256.c
/// SHA-256 after FIPS 180-4, sections 4.1.2, 4.2.2, 5.1.1, 5.3.3 and 6.2 (sha256.h).
#include "cdpr/host/sha256.h"

#include <stdio.h>
#include <string.h>

#include "cdpr/host/fs.h"

/* The first 32 bits of the fractional parts of the cube roots of the first 64 primes. */
static const uint32_t K[64] = {
    0x428a2f98U, 0x71374491U, 0xb5c0fbcfU, 0xe9b5dba5U, 0x3956c25bU, 0x59f111f1U, 0x923f82a4U,
    0xab1c5ed5U, 0xd807aa98U, 0x12835b01U, 0x243185beU, 0x550c7dc3U, 0x72be5d74U, 0x80deb1feU,
    0x9bdc06a7U, 0xc19bf174U, 0xe49b69c1U, 0xefbe4786U, 0x0fc19dc6U, 0x240ca1ccU, 0x2de92c6fU,
    0x4a7484aaU, 0x5cb0a9dcU, 0x76f988daU, 0x983e5152U, 0xa831c66dU, 0xb00327c8U, 0xbf597fc7U,
    0xc6e00bf3U, 0xd5a79147U, 0x06ca6351U, 0x14292967U, 0x27b70a85U, 0x2e1b2138U, 0x4d2c6dfcU,
    0x53380d13U, 0x650a7354U, 0x766a0abbU, 0x81c2c92eU, 0x92722c85U, 0xa2bfe8a1U, 0xa81a664bU,
    0xc24b8b70U, 0xc76c51a3U, 0xd192e819U, 0xd6990624U, 0xf40e3585U, 0x106aa070U, 0x19a4c116U,
    0x1e376c08U, 0x2748774cU, 0x34b0bcb5U, 0x391c0cb3U, 0x4ed8aa4aU, 0x5b9cca4fU, 0x682e6ff3U,
    0x748f82eeU, 0x78a5636fU, 0x84c87814U, 0x8cc70208U, 0x90befffaU, 0xa4506cebU, 0xbef9a3f7U,
    0xc67178f2U};

static uint32_t rotr(uint32_t x, unsigned n)
{
    return (x >> n) | (x << (32U - n));
}

/* One 512-bit block (6.2.2). */
static void compress(uint32_t h[8], const unsigned char b[64])
{
    uint32_t w[64];
    for (unsigned t = 0; t < 16U; ++t) {
        w[t] = ((uint32_t)b[4U * t] << 24) | ((uint32_t)b[4U * t + 1U] << 16) |
               ((uint32_t)b[4U * t + 2U] << 8) | (uint32_t)b[4U * t + 3U];
    }
    for (unsigned t = 16; t < 64U; ++t) {
        const uint32_t s0 = rotr(w[t - 15U], 7) ^ rotr(w[t - 15U], 18) ^ (w[t - 15U] >> 3);
        const uint32_t s1 = rotr(w[t - 2U], 17) ^ rotr(w[t - 2U], 19) ^ (w[t - 2U] >> 10);
        w[t] = w[t - 16U] + s0 + w[t - 7U] + s1;
    }
    uint32_t a = h[0], bb = h[1], c = h[2], d = h[3], e = h[4], f = h[5], g = h[6], hh = h[7];
    for (unsigned t = 0; t < 64U; ++t) {
        const uint32_t t1 =
            hh + (rotr(e, 6) ^ rotr(e, 11) ^ rotr(e, 25)) + ((e & f) ^ (~e & g)) + K[t] + w[t];
        const uint32_t t2 =
            (rotr(a, 2) ^ rotr(a, 13) ^ rotr(a, 22)) + ((a & bb) ^ (a & c) ^ (bb & c));
        hh = g;
        g = f;
        f = e;
        e = d + t1;
        d = c;
        c = bb;
        bb = a;
        a = t1 + t2;
    }
    h[0] += a;
    h[1] += bb;
    h[2] += c;
    h[3] += d;
    h[4] += e;
    h[5] += f;
    h[6] += g;
    h[7] += hh;
}

void cdpr_sha256_init(cdpr_sha256_t *s)
{
    /* 5.3.3: the first 32 bits of the fractional parts of the square roots of the first 8
     * primes. */
    static const uint32_t H0[8] = {0x6a09e667U, 0xbb67ae85U, 0x3c6ef372U, 0xa54ff53aU,
                                   0x510e527fU, 0x9b05688cU, 0x1f83d9abU, 0x5be0cd19U};
    memcpy(s->h, H0, sizeof H0);
    s->bytes = 0U;
    s->used = 0U;
}

void cdpr_sha256_update(cdpr_sha256_t *s, const void *data, size_t n)
{
    const unsigned char *p = data;
    s->bytes += (uint64_t)n;
    while (n > 0U) {
        const size_t take = (n < 64U - s->used) ? n : 64U - s->used;
        memcpy(s->block + s->used, p, take);
        s->used += take;
        p += take;
        n -= take;
        if (s->used == 64U) {
            compress(s->h, s->block);
            s->used = 0U;
        }
    }
}

void cdpr_sha256_final(cdpr_sha256_t *s, unsigned char out[CDPR_SHA256_BYTES])
{
    /* 5.1.1: a 1 bit, zeros to 448 mod 512 bits, the length in bits as 64-bit big-endian. */
    const uint64_t bits = s->bytes * 8U;
    s->block[s->used++] = 0x80U;
    if (s->used > 56U) {
        memset(s->block + s->used, 0, 64U - s->used);
        compress(s->h, s->block);
        s->used = 0U;
    }
    memset(s->block + s->used, 0, 56U - s->used);
    for (unsigned i = 0; i < 8U; ++i) {
        s->block[56U + i] = (unsigned char)(bits >> (56U - 8U * i));
    }
    compress(s->h, s->block);
    for (unsigned i = 0; i < 8U; ++i) {
        out[4U * i] = (unsigned char)(s->h[i] >> 24);
        out[4U * i + 1U] = (unsigned char)(s->h[i] >> 16);
        out[4U * i + 2U] = (unsigned char)(s->h[i] >> 8);
        out[4U * i + 3U] = (unsigned char)s->h[i];
    }
}

void cdpr_sha256_hex(const unsigned char digest[CDPR_SHA256_BYTES], char hex[CDPR_SHA256_HEX + 1])
{
    static const char digits[] = "0123456789abcdef";
    for (unsigned i = 0; i < (unsigned)CDPR_SHA256_BYTES; ++i) {
        hex[2U * i] = digits[digest[i] >> 4];
        hex[2U * i + 1U] = digits[digest[i] & 0x0fU];
    }
    hex[CDPR_SHA256_HEX] = '\0';
}

cdpr_status_t cdpr_sha256_file(const char *path, char hex[CDPR_SHA256_HEX + 1])
{
    hex[0] = '\0';
    FILE *f = cdpr_fs_fopen(path, "rb", NULL, 0);
    if (f == NULL) {
        return CDPR_E_IO;
    }
    cdpr_sha256_t s;
    cdpr_sha256_init(&s);
    unsigned char buf[4096];
    size_t n;
    while ((n = fread(buf, 1, sizeof buf, f)) > 0U) {
        cdpr_sha256_update(&s, buf, n);
    }
    const int failed = ferror(f);
    if (fclose(f) != 0 || failed != 0) {
        return CDPR_E_IO;
    }
    unsigned char d[CDPR_SHA256_BYTES];
    cdpr_sha256_final(&s, d);
    cdpr_sha256_hex(d, hex);
    return CDPR_OK;
}
