/* SPDX-License-Identifier: BSD-3-Clause */
/// @file summary.c
/// summary.json writer and reader, and the end-of-run block (summary.h).
#include "cdpr/host/summary.h"

#include <string.h>

#include "cdpr/host/yaml.h"

const char *cdpr_sim_status_name(cdpr_sim_status_t st)
{
    switch (st) {
    case CDPR_SIM_OK:
        return "ok";
    case CDPR_SIM_WARNINGS:
        return "warnings";
    default:
        return "failed";
    }
}

/* ---------------------------------------------------------------- writing summary.json */

/* JSON string body with the characters JSON requires escaped. */
static void json_string(FILE *f, const char *s)
{
    fputc('"', f);
    for (; *s != '\0'; ++s) {
        const unsigned char ch = (unsigned char)*s;
        if (ch == '"' || ch == '\\') {
            fprintf(f, "\\%c", ch);
        } else if (ch < 0x20) {
            fprintf(f, "\\u%04x", ch);
        } else {
            fputc(ch, f);
        }
    }
    fputc('"', f);
}

cdpr_status_t cdpr_sim_write_summary(const char *path, const cdpr_scenario_t *sc,
                                     const cdpr_sim_summary_t *sum)
{
    FILE *f = fopen(path, "w");
    if (f == NULL) {
        return CDPR_E_IO;
    }
    fprintf(f, "{\n  \"scenario\": ");
    json_string(f, sc->path);
    fprintf(f, ",\n  \"robot\": ");
    json_string(f, cdpr_scenario_robot_name(sc));
    fprintf(f, ",\n  \"trajectory\": ");
    json_string(f, cdpr_traj_type_name(sc->traj.type));
    fprintf(f, ",\n  \"status\": ");
    json_string(f, cdpr_sim_status_name(sum->status));
    fprintf(f, ",\n  \"message\": ");
    json_string(f, sum->message);
    const struct {
        const char *k;
        double v;
    } nums[] = {
        {"rms_error_m", sum->rms_error_m},
        {"max_error_m", sum->max_error_m},
        {"final_error_m", sum->final_error_m},
        {"initial_error_m", sum->initial_error_m},
        {"rms_error_second_half_m", sum->rms_error_second_half_m},
        {"rms_error_rad", sum->rms_error_rad},
        {"max_error_rad", sum->max_error_rad},
        {"final_error_rad", sum->final_error_rad},
        {"max_tension_N", sum->max_tension_N},
        {"min_tension_N", sum->min_tension_N},
        {"max_payout_m_per_s", sum->max_payout_m_per_s},
        {"sim_time_s", sum->sim_time_s},
        {"wall_time_s", sum->wall_time_s},
        {"settle_wall_time_s", sum->settle_wall_time_s},
        {"control_period_s", sc->period_s},
    };
    for (size_t i = 0; i < sizeof nums / sizeof nums[0]; ++i) {
        fprintf(f, ",\n  \"%s\": %.17g", nums[i].k, nums[i].v);
    }
    const struct {
        const char *k;
        long v;
    } ints[] = {
        {"node_insertions", (long)sum->node_insertions},
        {"node_removals", (long)sum->node_removals},
        {"capacity_hits", (long)sum->capacity_hits},
        {"substep_limit_hits", (long)sum->substep_limit_hits},
        {"ik_failures", (long)sum->ik_failures},
        {"min_length_periods", (long)sum->min_length_periods},
        {"nodes_min", (long)sum->nodes_min},
        {"nodes_max", (long)sum->nodes_max},
        {"periods", sum->periods},
        {"steps_accepted", (long)sum->steps_accepted},
        {"steps_rejected", (long)sum->steps_rejected},
        {"rhs_evals", (long)sum->rhs_evals},
        {"settle_steps", sum->settle_steps},
        {"segments", (long)cdpr_scenario_segments(sc)},
    };
    for (size_t i = 0; i < sizeof ints / sizeof ints[0]; ++i) {
        fprintf(f, ",\n  \"%s\": %ld", ints[i].k, ints[i].v);
    }
    fprintf(f, "\n}\n");
    /* A full device shows at the flush: check the stream as well as the close. */
    const int failed = (fflush(f) != 0 || ferror(f) != 0) ? 1 : 0;
    return (fclose(f) == 0 && failed == 0) ? CDPR_OK : CDPR_E_IO;
}

/* ---------------------------------------------------------------- reading summary.json */

typedef struct {
    char *status;
    double rms_error_m, max_error_m, final_error_m, initial_error_m, rms_error_second_half_m;
    double rms_error_rad, max_error_rad, final_error_rad;
    double max_tension_N, min_tension_N, max_payout_m_per_s, sim_time_s, wall_time_s;
    double node_insertions, node_removals, capacity_hits, substep_limit_hits, ik_failures;
    double min_length_periods, nodes_min, nodes_max, periods, steps_accepted, steps_rejected;
    double rhs_evals, settle_steps;
} raw_summary_t;

#define SUM_NUM(key) CYAML_FIELD_FLOAT(#key, CYAML_FLAG_STRICT, raw_summary_t, key)

static const cyaml_schema_field_t summary_fields[] = {
    CYAML_FIELD_STRING_PTR("status", CYAML_FLAG_DEFAULT, raw_summary_t, status, 0, 63),
    SUM_NUM(rms_error_m),
    SUM_NUM(max_error_m),
    SUM_NUM(final_error_m),
    SUM_NUM(initial_error_m),
    SUM_NUM(rms_error_second_half_m),
    SUM_NUM(rms_error_rad),
    SUM_NUM(max_error_rad),
    SUM_NUM(final_error_rad),
    SUM_NUM(max_tension_N),
    SUM_NUM(min_tension_N),
    SUM_NUM(max_payout_m_per_s),
    SUM_NUM(sim_time_s),
    SUM_NUM(wall_time_s),
    SUM_NUM(node_insertions),
    SUM_NUM(node_removals),
    SUM_NUM(capacity_hits),
    SUM_NUM(substep_limit_hits),
    SUM_NUM(ik_failures),
    SUM_NUM(min_length_periods),
    SUM_NUM(nodes_min),
    SUM_NUM(nodes_max),
    SUM_NUM(periods),
    SUM_NUM(steps_accepted),
    SUM_NUM(steps_rejected),
    SUM_NUM(rhs_evals),
    SUM_NUM(settle_steps),
    CYAML_FIELD_END,
};
static const cyaml_schema_value_t summary_schema = {
    CYAML_VALUE_MAPPING(CYAML_FLAG_POINTER, raw_summary_t, summary_fields),
};

static void from_raw(const raw_summary_t *r, cdpr_sim_summary_t *sum)
{
    memset(sum, 0, sizeof *sum);
    sum->status =
        (strcmp(r->status, "ok") == 0)
            ? CDPR_SIM_OK
            : ((strcmp(r->status, "warnings") == 0) ? CDPR_SIM_WARNINGS : CDPR_SIM_FAILED);
    sum->rms_error_m = r->rms_error_m;
    sum->max_error_m = r->max_error_m;
    sum->final_error_m = r->final_error_m;
    sum->initial_error_m = r->initial_error_m;
    sum->rms_error_second_half_m = r->rms_error_second_half_m;
    sum->rms_error_rad = r->rms_error_rad;
    sum->max_error_rad = r->max_error_rad;
    sum->final_error_rad = r->final_error_rad;
    sum->max_tension_N = r->max_tension_N;
    sum->min_tension_N = r->min_tension_N;
    sum->max_payout_m_per_s = r->max_payout_m_per_s;
    sum->sim_time_s = r->sim_time_s;
    sum->wall_time_s = r->wall_time_s;
    sum->node_insertions = (unsigned long)r->node_insertions;
    sum->node_removals = (unsigned long)r->node_removals;
    sum->capacity_hits = (unsigned long)r->capacity_hits;
    sum->substep_limit_hits = (unsigned long)r->substep_limit_hits;
    sum->ik_failures = (unsigned long)r->ik_failures;
    sum->min_length_periods = (unsigned long)r->min_length_periods;
    sum->nodes_min = (int)r->nodes_min;
    sum->nodes_max = (int)r->nodes_max;
    sum->periods = (long)r->periods;
    sum->steps_accepted = (unsigned long)r->steps_accepted;
    sum->steps_rejected = (unsigned long)r->steps_rejected;
    sum->rhs_evals = (unsigned long)r->rhs_evals;
    sum->settle_steps = (long)r->settle_steps;
}

cdpr_status_t cdpr_sim_read_summary(const char *path, cdpr_sim_summary_t *sum,
                                    cdpr_scenario_error_t *err)
{
    cdpr_yaml_log_t lg;
    void *data = NULL;
    const cdpr_status_t st =
        cdpr_yaml_load(path, &summary_schema, CYAML_CFG_IGNORE_UNKNOWN_KEYS, &data, &lg);
    if (st != CDPR_OK) {
        char why[512];
        snprintf(err->msg, sizeof err->msg, "%s: %s", path,
                 (lg.empty != 0) ? "empty file" : cdpr_yaml_first_error(&lg, why, sizeof why));
        return st;
    }
    from_raw(data, sum);
    cdpr_yaml_free(&summary_schema, data);
    return CDPR_OK;
}

/* ---------------------------------------------------------------- the end-of-run block */

void cdpr_sim_print_summary(FILE *f, const char *title, const cdpr_sim_summary_t *s)
{
    fprintf(f, "%s: %s%s%s\n", title, cdpr_sim_status_name(s->status),
            (s->message[0] != '\0') ? " - " : "", s->message);
    fprintf(f,
            "  tracking error  rms %.4g m, max %.4g m, final %.4g m (initial %.4g m); "
            "attitude rms %.1f mrad, max %.1f mrad\n",
            s->rms_error_m, s->max_error_m, s->final_error_m, s->initial_error_m,
            1e3 * s->rms_error_rad, 1e3 * s->max_error_rad);
    fprintf(f, "  tensions        %.4g .. %.4g N;  payout |u| <= %.3g m/s\n", s->min_tension_N,
            s->max_tension_N, s->max_payout_m_per_s);
    fprintf(f, "  node events     %lu insertions, %lu removals (segments %d..%d per cable)\n",
            s->node_insertions, s->node_removals, s->nodes_min, s->nodes_max);
    if (s->rhs_evals > 0) {
        fprintf(f,
                "  integrator      %lu steps, %lu rejected, %lu substep-limit periods, "
                "%lu IK failures\n",
                s->steps_accepted, s->steps_rejected, s->substep_limit_hits, s->ik_failures);
    } else {
        fprintf(f, "  controller      %lu IK failures (the plant's integrator ran elsewhere)\n",
                s->ik_failures);
    }
    fprintf(f, "  time            %.3g s simulated in %.3g s wall (settling %.3g s)\n",
            s->sim_time_s, s->wall_time_s, s->settle_wall_time_s);
}
