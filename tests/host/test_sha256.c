/* SPDX-License-Identifier: BSD-3-Clause */
/// @file test_sha256.c
/// SHA-256 (sha256.h) against the FIPS 180-4 / NIST example messages ("abc", the empty
/// message, the 448-bit and 896-bit two-block messages, one million 'a'), fed whole and in odd
/// pieces; and files of every length around the padding boundaries against coreutils'
/// sha256sum (an independent implementation), through cdpr_sha256_file.
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>

#include "cdpr/host/sha256.h"
#include "unity.h"

#ifndef CDPR_TEST_TMP
#define CDPR_TEST_TMP "/tmp/test_sha256"
#endif

void setUp(void) {}
void tearDown(void) {}

static void hash_pieces(const char *msg, size_t len, size_t piece, char hex[CDPR_SHA256_HEX + 1])
{
    cdpr_sha256_t s;
    cdpr_sha256_init(&s);
    for (size_t at = 0; at < len; at += piece) {
        cdpr_sha256_update(&s, msg + at, (len - at < piece) ? len - at : piece);
    }
    unsigned char d[CDPR_SHA256_BYTES];
    cdpr_sha256_final(&s, d);
    cdpr_sha256_hex(d, hex);
}

static void check(const char *msg, const char *expected)
{
    char hex[CDPR_SHA256_HEX + 1];
    const size_t len = strlen(msg);
    static const size_t pieces[] = {1, 3, 63, 64, 65, 1000000};
    for (size_t i = 0; i < sizeof pieces / sizeof pieces[0]; ++i) {
        hash_pieces(msg, len, pieces[i], hex);
        TEST_ASSERT_EQUAL_STRING(expected, hex);
    }
}

static void test_fips_180_examples(void)
{
    check("abc", "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
    check("", "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
    check("abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq",
          "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
    check("abcdefghbcdefghicdefghijdefghijkefghijklfghijklmghijklmnhijklmnoijklmnopjklmnopqklmnopqr"
          "lmnopqrsmnopqrstnopqrstu",
          "cf5b16a778af8380036ce59e7b0492370b249b11e8f07a51afac45037afee9d1");
}

static void test_one_million_a(void)
{
    static char msg[1000001];
    memset(msg, 'a', 1000000);
    msg[1000000] = '\0';
    check(msg, "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0");
}

static void test_files_against_sha256sum(void)
{
    /* The reference is another program: run through the shell on purpose. */
    FILE *probe =
        popen("sha256sum --version >/dev/null 2>&1 && echo yes", "r"); // NOLINT(cert-env33-c)
    char yes[8] = "";
    if (probe == NULL || fgets(yes, sizeof yes, probe) == NULL) {
        yes[0] = '\0';
    }
    if (probe != NULL) {
        (void)pclose(probe);
    }
    if (strncmp(yes, "yes", 3) != 0) {
        TEST_IGNORE_MESSAGE("sha256sum not found");
    }
    mkdir(CDPR_TEST_TMP, 0775);
    const char *path = CDPR_TEST_TMP "/bytes.bin";
    for (size_t len = 0; len <= 200; ++len) {
        FILE *f = fopen(path, "wb");
        TEST_ASSERT_NOT_NULL(f);
        for (size_t i = 0; i < len; ++i) {
            fputc((int)((i * 131U + len) & 0xffU), f); /* every byte value, NULs included */
        }
        TEST_ASSERT_EQUAL_INT(0, fclose(f));
        char ours[CDPR_SHA256_HEX + 1];
        TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_sha256_file(path, ours));
        FILE *p = popen("sha256sum " CDPR_TEST_TMP "/bytes.bin", "r"); // NOLINT(cert-env33-c)
        TEST_ASSERT_NOT_NULL(p);
        char theirs[128] = "";
        TEST_ASSERT_NOT_NULL(fgets(theirs, sizeof theirs, p));
        TEST_ASSERT_EQUAL_INT(0, pclose(p));
        theirs[CDPR_SHA256_HEX] = '\0';
        char msg[32];
        snprintf(msg, sizeof msg, "%zu bytes", len);
        TEST_ASSERT_EQUAL_STRING_MESSAGE(theirs, ours, msg);
    }
}

static void test_unreadable_file(void)
{
    char hex[CDPR_SHA256_HEX + 1] = "x";
    TEST_ASSERT_EQUAL_INT(CDPR_E_IO, cdpr_sha256_file(CDPR_TEST_TMP "/no/such/file", hex));
    TEST_ASSERT_EQUAL_STRING("", hex);
    TEST_ASSERT_EQUAL_INT(CDPR_E_IO, cdpr_sha256_file("/", hex)); /* a directory: read fails */
    TEST_ASSERT_EQUAL_STRING("", hex);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_fips_180_examples);
    RUN_TEST(test_one_million_a);
    RUN_TEST(test_files_against_sha256sum);
    RUN_TEST(test_unreadable_file);
    return UNITY_END() ? 1 : 0;
}
