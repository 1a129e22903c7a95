/* SPDX-License-Identifier: BSD-3-Clause */
/// @file fuzz_lcm_command.c
/// libFuzzer target: arbitrary bytes on the winch command channel -> the decoder (wire.h) and
/// our validator (cdpr_lcm_validator_accept), then the mailbox and the watchdog read, exactly
/// the receiver's path. Built only with clang (-fsanitize=fuzzer,address,undefined); see
/// docs/realtime.md, "Fuzzing".
///
/// What it finds: reads past `len` or uninitialised reads in decode/validate (ASan, and UBSan
/// for overflow/shift/conversion UB), and it checks the contract directly: an accepted command
/// has only finite values within the limits, a seq greater than every earlier accepted seq,
/// and a state_seq within [previous accepted state_seq, newest published state].
#include "cdpr/lcm/command.h"

#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static cdpr_lcm_validator_t validator;
static cdpr_lcm_mailbox_t mailbox;
static int ready;

static void init_once(void)
{
    cdpr_winch_params_t w[CDPR_MAX_CABLES];
    cdpr_lcm_limits_t lim;
    int j;
    for (j = 0; j < CDPR_MAX_CABLES; j++) {
        cdpr_winch_params_default(&w[j]);
    }
    if (cdpr_lcm_limits_from_winch(&lim, 6, w, 1000.0, NULL) != CDPR_OK ||
        cdpr_lcm_validator_init(&validator, &lim, 1, 100000000, NULL) != CDPR_OK ||
        cdpr_lcm_mailbox_init(&mailbox, 6, 100000000, NULL) != CDPR_OK) {
        abort();
    }
    ready = 1;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    cdpr_lcm_command_t out;
    cdpr_lcm_command_t got;
    int64_t prev_seq;
    int64_t prev_state;
    int j;

    if (!ready) {
        init_once();
    }
    // The plant keeps publishing: states up to 1000 exist (the seeds answer small ones).
    cdpr_lcm_validator_note_published(&validator, 1000);
    prev_seq = validator.last_seq;
    prev_state = validator.last_state_seq;
    if (cdpr_lcm_validator_accept(&validator, data, size, 1, &out) != CDPR_LCM_ACCEPTED) {
        if (validator.last_seq != prev_seq || validator.last_state_seq != prev_state) {
            abort(); // a rejected command changed the sequence state
        }
        return 0;
    }
    if (out.seq <= prev_seq || out.controller_session <= 0 || out.state_seq < prev_state ||
        out.state_seq > 1000 || out.n_cables != 6 ||
        (out.mode != CDPR_WINCH_RATE && out.mode != CDPR_WINCH_LENGTH)) {
        abort();
    }
    for (j = 0; j < 6; j++) {
        const double x = out.value[j];
        if (!isfinite(x) || (out.mode == CDPR_WINCH_RATE && fabs(x) > 4.0) ||
            (out.mode == CDPR_WINCH_LENGTH && (x < 0.5 || x > 1000.0))) {
            abort();
        }
    }
    cdpr_lcm_mailbox_write(&mailbox, &out);
    if ((cdpr_lcm_mailbox_read(&mailbox, 2, &got) & CDPR_LCM_READ_HOLD) != 0 ||
        got.seq != out.seq) {
        abort();
    }
    // Keep the search space open: the sequence state would otherwise only ever grow, making
    // later inputs with small seq numbers uninteresting (stale), and the first session would
    // refuse every other (busy). Restart from scratch.
    validator.last_seq = -1;
    validator.last_state_seq = -1;
    validator.controller_session = 0;
    return 0;
}
