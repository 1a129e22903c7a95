/* SPDX-License-Identifier: BSD-3-Clause */
/// @file fuzz_lcm_seeds.c
/// Writes a seed corpus for fuzz_lcm_command into the directory given as argv[1]: valid winch
/// commands in both modes (so the fuzzer starts past the 8-byte fingerprint check) and one of
/// each invalid kind. Built with the fuzz target; see docs/realtime.md, "Fuzzing".
#include "lcmtypes/cdpr_winch_command_t.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

static int write_seed(const char *dir, const char *name, const cdpr_winch_command_t *m)
{
    unsigned char buf[256];
    char path[4096];
    FILE *f;
    const int n = cdpr_winch_command_t_encode(buf, 0, (int)sizeof buf, m);
    if (n <= 0 || snprintf(path, sizeof path, "%s/%s", dir, name) >= (int)sizeof path) {
        return 1;
    }
    f = fopen(path, "wb");
    if (f == NULL) {
        perror(path);
        return 1;
    }
    if (fwrite(buf, 1u, (size_t)n, f) != (size_t)n) {
        (void)fclose(f);
        return 1;
    }
    return fclose(f) != 0;
}

int main(int argc, char **argv)
{
    cdpr_winch_command_t m;
    double values[6];
    int j;
    int rc = 0;

    if (argc != 2) {
        fprintf(stderr, "usage: %s <corpus-dir>\n", argv[0]);
        return 2;
    }
    memset(&m, 0, sizeof m);
    m.value = values;
    m.seq = 1;
    m.state_seq = 1;
    m.controller_session = 2; // any > 0
    m.plant_session = 1;      // the fuzzer's plant (fuzz_lcm_command.c)
    m.mode = CDPR_WINCH_COMMAND_T_MODE_RATE;
    m.n_cables = 6;
    for (j = 0; j < 6; j++) {
        m.value[j] = 0.5 * (double)(j - 3);
    }
    rc |= write_seed(argv[1], "rate", &m);
    m.mode = CDPR_WINCH_COMMAND_T_MODE_LENGTH;
    for (j = 0; j < 6; j++) {
        m.value[j] = 50.0 + (double)j;
    }
    rc |= write_seed(argv[1], "length", &m);
    m.value[2] = (double)NAN;
    rc |= write_seed(argv[1], "nan", &m);
    m.value[2] = 50.0;
    m.n_cables = 5;
    rc |= write_seed(argv[1], "count", &m);
    return rc;
}
