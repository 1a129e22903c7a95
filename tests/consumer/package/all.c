/* SPDX-License-Identifier: BSD-3-Clause */
/// @file all.c
/// Link check of every installed component (tests/consumer/run.sh, CDPR_CONSUMER_ALL): one
/// call into cdpr::gsl, cdpr::rt (and so cdpr::host, cdpr::lcm), cdpr::design (its analysis
/// references LAPACK: the exported dependency must bring it), cdpr::lcmtypes and liblcm.
#include <stdio.h>
#include <string.h>

#include <lcm/lcm.h>

#include "cdpr/design/design.h"
#include "cdpr/gsl/ref.h"
#include "cdpr/rt/plant_node.h"
#include "cdpr/status.h"
#include "cdpr/version.h"
#include "lcmtypes/cdpr_winch_command_t.h"

int main(void)
{
    cdpr_rt_plant_opts_t opts;
    cdpr_winch_command_t cmd;
    cdpr_rt_plant_opts_default(&opts);
    cdpr_gsl_error_handler_off();
    memset(&cmd, 0, sizeof cmd);
    const int bytes = cdpr_winch_command_t_encoded_size(&cmd);
    lcm_t *lcm = lcm_create("memq://");
    if (lcm == NULL || bytes <= 0) {
        printf("cdpr %s: lcm_create or encoded_size failed\n", cdpr_version());
        return 1;
    }
    lcm_destroy(lcm);
    /* An empty model: refused before any LAPACK call, but linked with it. */
    cdpr_design_model_t model;
    memset(&model, 0, sizeof model);
    static cdpr_design_report_t report;
    cdpr_design_error_t err;
    if (cdpr_design_analyse(&model, 0, &report, &err) != CDPR_E_INVALID_ARG) {
        printf("cdpr %s: cdpr_design_analyse accepted an empty model\n", cdpr_version());
        return 1;
    }
    printf("cdpr %s: every component links (winch command: %d bytes, %s)\n", cdpr_version(), bytes,
           cdpr_status_str(CDPR_OK));
    return 0;
}
