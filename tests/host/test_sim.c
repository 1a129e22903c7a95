/* SPDX-License-Identifier: BSD-3-Clause */
/// @file test_sim.c
/// Scenario regression: the paper's circle and line, run from their committed scenario files
/// (shortened to 2.5 s and 4 s for CI time: the circle's violent first seconds with node events
/// and slack cables, and the line's start and first 4 s), compared with the committed
/// summaries tests/regression/paper-{circle,line}.json at stated tolerances; a rerun is
/// bit-identical (timeseries.csv byte for byte). Regenerate the references with
/// `cmake --build --preset debug --target regression-references` and review the diff.
///
/// Also: the deploy-and-retrieve stress case's node events match the length the winches moved.
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "cdpr/host/scenario.h"
#include "cdpr/host/sha256.h"
#include "cdpr/host/sim.h"
#include "cdpr/statics.h"
#include "unity.h"

void setUp(void) {}
void tearDown(void) {}

/* cdpr-sim SCENARIO --duration D [--max-trials N] --out OUT (max_trials 0: the file's):
 * cdpr_sim_run's status and the summary. */
static cdpr_status_t run_status(const char *scenario, double duration, int max_trials,
                                const char *out, cdpr_summary_t *sum)
{
    mkdir(CDPR_TEST_TMP, 0775);
    cdpr_scenario_t sc;
    cdpr_scenario_error_t err;
    TEST_ASSERT_EQUAL_INT_MESSAGE(CDPR_OK, cdpr_scenario_load(scenario, &sc, &err), err.msg);
    cdpr_scenario_overrides_t ov;
    cdpr_scenario_overrides_none(&ov);
    ov.duration_s = duration; /* cdpr-sim --duration */
    if (max_trials > 0) {
        ov.max_trials = (double)max_trials; /* cdpr-sim --max-trials */
    }
    TEST_ASSERT_EQUAL_INT_MESSAGE(CDPR_OK, cdpr_scenario_override(&sc, &ov, "test", NULL, &err),
                                  err.msg);
    cdpr_sim_opts_t o;
    cdpr_sim_opts_default(&o);
    o.out_dir = out;
    return cdpr_sim_run(&sc, &o, sum, &err);
}

static void run(const char *scenario, double duration, const char *out, cdpr_summary_t *sum)
{
    TEST_ASSERT_EQUAL_INT_MESSAGE(CDPR_OK, run_status(scenario, duration, 0, out, sum),
                                  sum->message);
}

static long file_bytes(const char *path, char **buf)
{
    FILE *f = fopen(path, "rb");
    TEST_ASSERT_NOT_NULL_MESSAGE(f, path);
    TEST_ASSERT_EQUAL_INT(0, fseek(f, 0, SEEK_END));
    const long n = ftell(f);
    TEST_ASSERT_TRUE(n > 0);
    rewind(f);
    *buf = malloc((size_t)n + 1U); /* NUL-terminated: the text is searched with strstr */
    TEST_ASSERT_NOT_NULL(*buf);
    TEST_ASSERT_EQUAL_UINT32((unsigned)n, (unsigned)fread(*buf, 1, (size_t)n, f));
    (*buf)[n] = '\0';
    fclose(f);
    return n;
}

static void assert_same_bytes(const char *a, const char *b)
{
    char *x = NULL;
    char *y = NULL;
    const long nx = file_bytes(a, &x);
    const long ny = file_bytes(b, &y);
    TEST_ASSERT_EQUAL_INT32(nx, ny);
    TEST_ASSERT_EQUAL_INT(0, memcmp(x, y, (size_t)nx));
    free(x);
    free(y);
}

/* Relative comparison with a floor for values near zero. */
/* Relative comparison with a floor for values near zero: 1 when outside (printed). */
static int off_rel(const char *what, double ref, double got, double rel, double abs_floor)
{
    if (fabs(got - ref) <= fmax(rel * fabs(ref), abs_floor)) {
        return 0;
    }
    printf("  %s: reference %.10g, got %.10g (relative %.3g, allowed %.3g)\n", what, ref, got,
           (got - ref) / fmax(fabs(ref), 1e-300), rel);
    return 1;
}

static int off_count(const char *what, unsigned long ref, unsigned long got, long allow)
{
    if (labs((long)got - (long)ref) <= allow) {
        return 0;
    }
    printf("  %s: reference %lu, got %lu (allowed +-%ld)\n", what, ref, got, allow);
    return 1;
}

/* Tolerances. The references were produced by the same code; what the comparison must
 * absorb is a different compiler/libm rounding the same arithmetic differently, amplified
 * by the dynamics. Measured amplification (perturbing the initial state by 1e-9 m over these
 * durations): the line's metrics move by <= 3e-7 relative; the circle's errors by <= 5e-5,
 * its peak tension (a slack cable snapping taut, sampled at the control period) by 3e-3.
 * Tolerances: line 1e-4 (300x); circle 5e-4 on errors (10x), 5e-2 on the peak tension
 * (17x). A 1 % change of the cabin mass moves the circle's final position error by 2.5e-3 and
 * its attitude errors by 1.7e-3 to 2.3e-3 (the 1e-2 tolerance before missed it): checked by
 * test_regression_sees_a_1_percent_mass_change. Node event counts: exact for the line, +-1 for
 * the circle (an event can move across a period boundary). */
typedef struct {
    const char *name;
    double duration_s;
    double rel;      /* errors, minimum tension */
    double rel_peak; /* maximum tension */
    long events;
} case_t;

static const case_t CASES[2] = {
    {"paper-circle", 2.5, 5e-4, 5e-2, 1},
    {"paper-line", 4.0, 1e-4, 1e-4, 0},
};

static int off_reference(const case_t *c, const cdpr_summary_t *a);

static void regression(const case_t *c)
{
    char scenario[600];
    char out_a[600];
    char out_b[600];
    snprintf(scenario, sizeof scenario, "%s/scenarios/%s.yaml", CDPR_SOURCE_DIR, c->name);
    snprintf(out_a, sizeof out_a, "%s/%s-a", CDPR_TEST_TMP, c->name);
    snprintf(out_b, sizeof out_b, "%s/%s-b", CDPR_TEST_TMP, c->name);
    cdpr_summary_t a;
    cdpr_summary_t b;
    run(scenario, c->duration_s, out_a, &a);
    run(scenario, c->duration_s, out_b, &b);

    /* Same binary, same input: byte-identical time series. */
    char csv_a[700];
    char csv_b[700];
    snprintf(csv_a, sizeof csv_a, "%s/timeseries.csv", out_a);
    snprintf(csv_b, sizeof csv_b, "%s/timeseries.csv", out_b);
    assert_same_bytes(csv_a, csv_b);
    TEST_ASSERT_EQUAL_DOUBLE(a.rms_error_m, b.rms_error_m);

    /* The written summary reads back to what the run reported (%.17g round-trips). */
    char sum_a[700];
    snprintf(sum_a, sizeof sum_a, "%s/summary.json", out_a);
    cdpr_summary_t back;
    cdpr_scenario_error_t err;
    TEST_ASSERT_EQUAL_INT_MESSAGE(CDPR_OK, cdpr_summary_read(sum_a, &back, &err), err.msg);
    TEST_ASSERT_EQUAL_DOUBLE(a.max_tension_N, back.max_tension_N);
    TEST_ASSERT_EQUAL_UINT32((unsigned)a.node_removals, (unsigned)back.node_removals);
    /* Its provenance: the scenario file's hash and the plant's integrator. */
    char sha[CDPR_SHA256_HEX + 1];
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_sha256_file(scenario, sha));
    TEST_ASSERT_EQUAL_STRING(sha, back.prov.scenario_sha256);
    TEST_ASSERT_EQUAL_STRING("rkf45", back.prov.integrator);

    TEST_ASSERT_EQUAL_INT_MESSAGE(0, off_reference(c, &a), "differs from the reference");
}

/* How many of a run's figures lie outside the case's tolerances around its reference. */
static int off_reference(const case_t *c, const cdpr_summary_t *a)
{
    char ref_path[600];
    snprintf(ref_path, sizeof ref_path, "%s/tests/regression/%s.json", CDPR_SOURCE_DIR, c->name);
    cdpr_summary_t ref;
    cdpr_scenario_error_t err;
    TEST_ASSERT_EQUAL_INT_MESSAGE(CDPR_OK, cdpr_summary_read(ref_path, &ref, &err), err.msg);
    TEST_ASSERT_EQUAL_INT(ref.status, a->status);
    TEST_ASSERT_EQUAL_DOUBLE(ref.sim_time_s, a->sim_time_s);
    int off = 0;
    off += off_rel("rms_error_m", ref.rms_error_m, a->rms_error_m, c->rel, 1e-9);
    off += off_rel("max_error_m", ref.max_error_m, a->max_error_m, c->rel, 1e-9);
    off += off_rel("final_error_m", ref.final_error_m, a->final_error_m, c->rel, 1e-9);
    off += off_rel("initial_error_m", ref.initial_error_m, a->initial_error_m, c->rel, 1e-9);
    off += off_rel("rms_error_rad", ref.rms_error_rad, a->rms_error_rad, c->rel, 1e-9);
    off += off_rel("max_error_rad", ref.max_error_rad, a->max_error_rad, c->rel, 1e-9);
    off += off_rel("max_tension_N", ref.max_tension_N, a->max_tension_N, c->rel_peak, 1e-6);
    /* min tension: 0 N (a slack cable) for the circle; the floor is 0.01 N. */
    off += off_rel("min_tension_N", ref.min_tension_N, a->min_tension_N, c->rel, 1e-2);
    off += off_count("node_insertions", ref.node_insertions, a->node_insertions, c->events);
    off += off_count("node_removals", ref.node_removals, a->node_removals, c->events);
    off += off_count("ik_failures", ref.ik_failures, a->ik_failures, 0);
    off += off_count("substep_limit_hits", ref.substep_limit_hits, a->substep_limit_hits, 0);
    return off;
}

/* The comparison is sharp enough to matter: the same scenarios with the cabin 1 % heavier
 * (40.4 kg) must fall outside the tolerances (issue 26: with 1e-2 on the circle's errors, a
 * 1 % mass change passed). */
static void test_regression_sees_a_1_percent_mass_change(void)
{
    for (int i = 0; i < 2; ++i) {
        const case_t *c = &CASES[i];
        char scenario[600];
        char heavier[700];
        char out[700];
        snprintf(scenario, sizeof scenario, "%s/scenarios/%s.yaml", CDPR_SOURCE_DIR, c->name);
        snprintf(heavier, sizeof heavier, "%s/%s-heavier.yaml", CDPR_TEST_TMP, c->name);
        snprintf(out, sizeof out, "%s/%s-heavier", CDPR_TEST_TMP, c->name);
        char *text = NULL;
        const long n = file_bytes(scenario, &text);
        mkdir(CDPR_TEST_TMP, 0775);
        FILE *f = fopen(heavier, "wb");
        TEST_ASSERT_NOT_NULL(f);
        const char *at = strstr(text, "mass_kg: 40.0");
        TEST_ASSERT_NOT_NULL_MESSAGE(at, "the scenario names its cabin mass");
        const long head = (long)(at - text);
        TEST_ASSERT_EQUAL_UINT32((unsigned)head, (unsigned)fwrite(text, 1, (size_t)head, f));
        fputs("mass_kg: 40.4", f);
        const long tail = n - head - (long)strlen("mass_kg: 40.0");
        TEST_ASSERT_EQUAL_UINT32(
            (unsigned)tail, (unsigned)fwrite(at + strlen("mass_kg: 40.0"), 1, (size_t)tail, f));
        TEST_ASSERT_EQUAL_INT(0, fclose(f));
        free(text);
        cdpr_summary_t a;
        run(heavier, c->duration_s, out, &a);
        printf("%s with a 1 %% heavier cabin:\n", c->name);
        TEST_ASSERT_TRUE_MESSAGE(off_reference(c, &a) > 0, c->name);
    }
}

static void test_paper_circle_regression_and_rerun(void)
{
    regression(&CASES[0]);
}

static void test_paper_line_regression_and_rerun(void)
{
    regression(&CASES[1]);
}

/* Node events as a controller over LCM derives them (cdpr_record_node_events): the rows of
 * `csv` (the segment counts n1..nN, one row every few periods) fed to a fresh recorder. */
static void node_events_from_csv(const char *csv, const cdpr_scenario_t *sc, unsigned long *ins,
                                 unsigned long *rem)
{
    FILE *f = fopen(csv, "r");
    TEST_ASSERT_NOT_NULL_MESSAGE(f, csv);
    static char line[16384];
    int n1 = -1; /* column of n1 */
    int nc = 0;
    do {
        TEST_ASSERT_NOT_NULL(fgets(line, sizeof line, f));
    } while (line[0] == '#'); /* the provenance comments */
    int col = 0;
    for (char *tok = strtok(line, ",\n"); tok != NULL; tok = strtok(NULL, ",\n"), ++col) {
        if (tok[0] == 'n' && tok[1] >= '1' && tok[1] <= '9') {
            n1 = (n1 < 0) ? col : n1;
            nc++;
        }
    }
    TEST_ASSERT_TRUE(n1 > 0 && nc == 6);
    cdpr_summary_t sum;
    memset(&sum, 0, sizeof sum);
    cdpr_record_t rec;
    cdpr_scenario_error_t err;
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_record_open(&rec, sc, NULL, NULL, nc, &sum, &err));
    cdpr_traj_sample_t des;
    memset(&des, 0, sizeof des);
    des.motion.q.w = 1.0;
    cdpr_tracker_meas_t meas;
    memset(&meas, 0, sizeof meas);
    meas.cabin.q.w = 1.0;
    const double zero[CDPR_MAX_CABLES] = {0.0};
    while (fgets(line, sizeof line, f) != NULL) {
        int segments[CDPR_MAX_CABLES] = {0};
        double t = 0.0;
        col = 0;
        for (char *tok = strtok(line, ",\n"); tok != NULL; tok = strtok(NULL, ",\n"), ++col) {
            if (col == 0) {
                t = strtod(tok, NULL);
            } else if (col >= n1 && col < n1 + nc) {
                segments[col - n1] = (int)strtol(tok, NULL, 10);
            }
        }
        const cdpr_record_row_t row = {t, &des, &meas, zero, zero, zero, zero, segments};
        cdpr_record_period(&rec, lround(t / sc->period_s), 0, &row);
    }
    fclose(f);
    long missed = 0;
    cdpr_record_node_events(&rec, ins, rem, &missed);
    TEST_ASSERT_TRUE(missed > 0); /* the rows are every 2 periods: gaps are folded in */
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_record_close(&rec));
}

static void test_deploy_retrieve_node_events(void)
{
    /* The cabin rises from z = 4 m to 15 m in 8 s and waits, then returns. Every cable is hauled
     * in by the same ΔL (symmetric poses), computed here from the statics at both ends. The
     * last segment starts at Δ = L0 / 20 and a node goes each time it falls below Δ/2, after
     * which it is Δ longer: the k-th removal comes after (k - 1/2) Δ of haul-in, so
     * k = floor(ΔL / Δ + 1/2) per cable. Run with 10 segments instead of the file's 20 for CI
     * time (coarser is cheaper twice over: fewer nodes and a softer stiffest mode): ΔL / Δ =
     * 2.1, 0.4 Δ from either boundary. */
    char scenario[600];
    char out[600];
    snprintf(scenario, sizeof scenario, "%s/scenarios/deploy-retrieve.yaml", CDPR_SOURCE_DIR);
    snprintf(out, sizeof out, "%s/deploy", CDPR_TEST_TMP);
    cdpr_scenario_t sc;
    cdpr_scenario_error_t err;
    TEST_ASSERT_EQUAL_INT_MESSAGE(CDPR_OK, cdpr_scenario_load(scenario, &sc, &err), err.msg);
    const int segments = 10;
    for (int j = 0; j < sc.rig.n_cables; ++j) {
        sc.rig.cable[j].segments = segments;
    }
    cdpr_robot_params_t p;
    static cdpr_robot_t model;
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_scenario_build_robot(&sc, NULL, &p, NULL, NULL));
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_robot_init(&model, &p, NULL));
    cdpr_statics_opts_t o;
    cdpr_statics_opts_default(&o);
    cdpr_statics_result_t bottom;
    cdpr_statics_result_t top;
    const cdpr_cabin_motion_t m0 = cdpr_cabin_motion_at_pose(sc.traj.from);
    const cdpr_cabin_motion_t m1 = cdpr_cabin_motion_at_pose(sc.traj.to);
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_statics_ik(&model, &m0, &o, &bottom));
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_statics_ik(&model, &m1, &o, &top));
    const double delta = bottom.cable[0].length_m / segments;
    const double haul = bottom.cable[0].length_m - top.cable[0].length_m;
    const int k = (int)floor(haul / delta + 0.5);
    const double frac = haul / delta + 0.5 - (double)k; /* distance from the boundaries */
    TEST_ASSERT_TRUE(fmin(frac, 1.0 - frac) > 0.2);

    /* The whole run: up, pause, back down to z = 4 m: k nodes go and come back per cable. */
    cdpr_sim_opts_t opt;
    cdpr_sim_opts_default(&opt);
    opt.out_dir = out;
    cdpr_summary_t s;
    TEST_ASSERT_EQUAL_INT_MESSAGE(CDPR_OK, cdpr_sim_run(&sc, &opt, &s, &err), err.msg);
    TEST_ASSERT_EQUAL_INT(CDPR_SUMMARY_OK, s.status);
    TEST_ASSERT_EQUAL_UINT32((unsigned)(6 * k), (unsigned)s.node_removals);
    TEST_ASSERT_EQUAL_UINT32((unsigned)(6 * k), (unsigned)s.node_insertions);
    TEST_ASSERT_EQUAL_INT(segments - k, s.nodes_min);
    TEST_ASSERT_EQUAL_INT(segments, s.nodes_max);

    /* The segment counts of the written rows (every 2 periods, output_rate_hz 50) give the
     * same counts: what cdpr-tracker writes for a run it saw over LCM. */
    char csv[700];
    snprintf(csv, sizeof csv, "%s/timeseries.csv", out);
    unsigned long ins = 0;
    unsigned long rem = 0;
    node_events_from_csv(csv, &sc, &ins, &rem);
    TEST_ASSERT_EQUAL_UINT32((unsigned)s.node_insertions, (unsigned)ins);
    TEST_ASSERT_EQUAL_UINT32((unsigned)s.node_removals, (unsigned)rem);
}

/* The real-time block of a summary (the plant's figures a controller got from cdpr-rt's
 * diagnostics) reads back exactly; a summary without one (a batch run) reads back unknown. */
static void test_summary_real_time_block_round_trip(void)
{
    char scenario[600];
    snprintf(scenario, sizeof scenario, "%s/scenarios/paper-line.yaml", CDPR_SOURCE_DIR);
    static cdpr_scenario_t sc;
    cdpr_scenario_error_t err;
    TEST_ASSERT_EQUAL_INT_MESSAGE(CDPR_OK, cdpr_scenario_load(scenario, &sc, &err), err.msg);
    static cdpr_summary_t sum;
    static cdpr_summary_t back;
    memset(&sum, 0, sizeof sum);
    sum.rt.known = 1;
    sum.rt.seq = 8000;
    sum.rt.periods = 8001;
    sum.rt.deadline_misses = 17;
    sum.rt.startup_misses = 9;
    sum.rt.misses_late_wakeup = 5;
    sum.rt.misses_preempted = 2;
    sum.rt.misses_long_compute = 1;
    sum.rt.misses_in_row_max = 3;
    sum.rt.overrun_stop = 1;
    sum.rt.compute_us_p99 = 412.0;
    sum.rt.compute_us_max = 5327.75;
    sum.rt.cpu_us_p99 = 118.0;
    sum.rt.cpu_us_max = 161.25;
    sum.rt.wake_late_us_max = 4000.5;
    char path[700];
    mkdir(CDPR_TEST_TMP, 0775);
    snprintf(path, sizeof path, "%s/rt-summary.json", CDPR_TEST_TMP);
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_summary_write(path, &sc, &sum));
    TEST_ASSERT_EQUAL_INT_MESSAGE(CDPR_OK, cdpr_summary_read(path, &back, &err), err.msg);
    TEST_ASSERT_EQUAL_INT(1, back.rt.known);
    TEST_ASSERT_EQUAL_INT(8000, back.rt.seq);
    TEST_ASSERT_EQUAL_INT(8001, back.rt.periods);
    TEST_ASSERT_EQUAL_UINT(17, back.rt.deadline_misses);
    TEST_ASSERT_EQUAL_UINT(9, back.rt.startup_misses);
    TEST_ASSERT_EQUAL_UINT(5, back.rt.misses_late_wakeup);
    TEST_ASSERT_EQUAL_UINT(2, back.rt.misses_preempted);
    TEST_ASSERT_EQUAL_UINT(1, back.rt.misses_long_compute);
    TEST_ASSERT_EQUAL_UINT(3, back.rt.misses_in_row_max);
    TEST_ASSERT_EQUAL_INT(1, back.rt.overrun_stop);
    TEST_ASSERT_EQUAL_DOUBLE(412.0, back.rt.compute_us_p99);
    TEST_ASSERT_EQUAL_DOUBLE(5327.75, back.rt.compute_us_max);
    TEST_ASSERT_EQUAL_DOUBLE(118.0, back.rt.cpu_us_p99);
    TEST_ASSERT_EQUAL_DOUBLE(161.25, back.rt.cpu_us_max);
    TEST_ASSERT_EQUAL_DOUBLE(4000.5, back.rt.wake_late_us_max);
    sum.rt.known = 0;
    TEST_ASSERT_EQUAL_INT(CDPR_OK, cdpr_summary_write(path, &sc, &sum));
    TEST_ASSERT_EQUAL_INT_MESSAGE(CDPR_OK, cdpr_summary_read(path, &back, &err), err.msg);
    TEST_ASSERT_EQUAL_INT(0, back.rt.known);
}

/* paper-line with integrator.max_trials = `trials`, 0.1 s: cdpr_sim_run's status, summary. */
static cdpr_status_t run_line_trials(int trials, cdpr_summary_t *sum)
{
    char scenario[600];
    char out[600];
    snprintf(scenario, sizeof scenario, "%s/scenarios/paper-line.yaml", CDPR_SOURCE_DIR);
    snprintf(out, sizeof out, "%s/trials%d", CDPR_TEST_TMP, trials);
    return run_status(scenario, 0.1, trials, out, sum);
}

/* A period that does not fit in its trial budget stops the run with a message that names
 * integrator.max_trials, its value, and a number of steps per period; that number as the
 * budget runs the same case through. */
static void test_substep_limit_names_the_key_and_a_budget_that_works(void)
{
    static cdpr_summary_t sum;
    TEST_ASSERT_EQUAL_INT(CDPR_E_SUBSTEP_LIMIT, run_line_trials(3, &sum));
    TEST_ASSERT_EQUAL_INT_MESSAGE(CDPR_SUMMARY_FAILED, sum.status, sum.message);
    TEST_MESSAGE(sum.message);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(sum.message, "CDPR_E_SUBSTEP_LIMIT"), sum.message);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(sum.message, "integrator.max_trials = 3 trials"),
                                 sum.message);
    const char *up = strstr(sum.message, "a period is up to ");
    TEST_ASSERT_NOT_NULL_MESSAGE(up, sum.message);
    char *end = NULL;
    const long need = strtol(up + strlen("a period is up to "), &end, 10);
    TEST_ASSERT_TRUE_MESSAGE(end != NULL && *end == ' ' && need > 3 && need <= 100000, sum.message);
    TEST_ASSERT_EQUAL_INT(CDPR_OK, run_line_trials((int)need, &sum));
    TEST_ASSERT_EQUAL_INT_MESSAGE(CDPR_SUMMARY_OK, sum.status, sum.message);
    TEST_ASSERT_EQUAL_INT(10, sum.periods);
}

/* Validate once (issue 21): a loaded scenario is trusted by cdpr_sim_run while it holds the
 * values load checked; changed afterwards, it is checked again and a bad value is refused
 * naming its key, before anything is built; an override re-stamps it. */
static void test_a_changed_scenario_is_checked_again(void)
{
    cdpr_scenario_t *sc = malloc(sizeof *sc);
    TEST_ASSERT_NOT_NULL(sc);
    cdpr_scenario_error_t err;
    TEST_ASSERT_EQUAL_INT_MESSAGE(
        CDPR_OK, cdpr_scenario_load(CDPR_SOURCE_DIR "/scenarios/paper-line.yaml", sc, &err),
        err.msg);
    TEST_ASSERT_EQUAL_INT(1, cdpr_scenario_is_checked(sc));
    sc->rig.cable[0].rope.ea_N = (double)NAN;
    TEST_ASSERT_EQUAL_INT(0, cdpr_scenario_is_checked(sc));
    cdpr_sim_opts_t opt;
    cdpr_sim_opts_default(&opt);
    char out[600];
    snprintf(out, sizeof out, "%s/changed", CDPR_TEST_TMP);
    opt.out_dir = out;
    static cdpr_summary_t sum;
    TEST_ASSERT_EQUAL_INT(CDPR_E_NOT_FINITE, cdpr_sim_run(sc, &opt, &sum, &err));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err.msg, "robot.rope.ea_N (cable 1): not a finite number"),
                                 err.msg);
    /* An override checks what changed too, and stamps the scenario when it passes. */
    cdpr_scenario_overrides_t ov;
    cdpr_scenario_overrides_none(&ov);
    TEST_ASSERT_EQUAL_INT(CDPR_E_NOT_FINITE, cdpr_scenario_override(sc, &ov, "t", NULL, &err));
    TEST_ASSERT_EQUAL_INT(0, cdpr_scenario_is_checked(sc));
    sc->rig.cable[0].rope.ea_N = 2.0e6;
    TEST_ASSERT_EQUAL_INT_MESSAGE(CDPR_OK, cdpr_scenario_override(sc, &ov, "t", NULL, &err),
                                  err.msg);
    TEST_ASSERT_EQUAL_INT(1, cdpr_scenario_is_checked(sc));
    free(sc);
}

/* The data rows of a timeseries.csv (comment lines dropped). */
typedef struct {
    char *buf;
    char *row[1024];
    int n;
} rows_t;

static int data_rows(const char *path, rows_t *r)
{
    (void)file_bytes(path, &r->buf);
    r->n = 0;
    for (char *line = strtok(r->buf, "\n"); line != NULL && r->n < 1024;
         line = strtok(NULL, "\n")) {
        if (line[0] != '#') {
            r->row[r->n++] = line;
        }
    }
    return r->n;
}

/* paper-circle.yaml (calm) with its robot wind replaced by `robot_wind` and `wind` appended:
 * written to tmp/NAME.yaml and run for 1 s into tmp/NAME; returns the timeseries path. */
static const char *wind_run(const char *name, const char *robot_wind, const char *wind)
{
    static char out[4][700];
    static int next = 0;
    char *base = NULL;
    (void)file_bytes(CDPR_SOURCE_DIR "/scenarios/paper-circle.yaml", &base);
    const char *calm = "wind_m_per_s: [0.0, 0.0, 0.0]";
    char *at = strstr(base, calm);
    TEST_ASSERT_NOT_NULL(at);
    char path[700];
    snprintf(path, sizeof path, "%s/%s.yaml", CDPR_TEST_TMP, name);
    mkdir(CDPR_TEST_TMP, 0775);
    FILE *f = fopen(path, "wb");
    TEST_ASSERT_NOT_NULL(f);
    fprintf(f, "%.*swind_m_per_s: %s%s%s", (int)(at - base), base, robot_wind, at + strlen(calm),
            wind);
    fclose(f);
    free(base);
    char *o = out[next++ % 4];
    snprintf(o, sizeof out[0], "%s/%s", CDPR_TEST_TMP, name);
    static cdpr_summary_t sum;
    run(path, 1.0, o, &sum);
    static char ts[4][760];
    char *t = ts[(next - 1) % 4];
    snprintf(t, sizeof ts[0], "%s/timeseries.csv", o);
    return t;
}

/* The scenario's wind section in the run (issue 23): a steady section is the robot's
 * wind_m_per_s, bit for bit; a ramp that starts after the run leaves a calm run as it was; a
 * gust changes nothing up to its start and the run from the period after it (the plant takes
 * each period's wind at its midpoint: cdpr_scenario_wind_at). */
static void test_wind_section_in_the_run(void)
{
    static rows_t a;
    static rows_t b;
    static rows_t c;
    static rows_t d;
    const char *robot = wind_run("wind-robot", "[0.0, 4.0, 0.0]", "");
    const char *steady = wind_run("wind-steady", "[0.0, 0.0, 0.0]",
                                  "wind:\n  speed_m_per_s: 4.0\n  towards_deg: 90\n");
    const int n = data_rows(robot, &a);
    TEST_ASSERT_EQUAL_INT(1 + 101, n); /* header, t = 0 .. 1 s at 100 Hz */
    TEST_ASSERT_EQUAL_INT(n, data_rows(steady, &b));
    for (int i = 0; i < n; ++i) {
        TEST_ASSERT_EQUAL_STRING(a.row[i], b.row[i]);
    }
    const char *calm = wind_run("wind-calm", "[0.0, 0.0, 0.0]", "");
    const char *later = wind_run("wind-later", "[0.0, 0.0, 0.0]",
                                 "wind:\n  speed_m_per_s: 4.0\n  towards_deg: 90\n"
                                 "  profile: ramp\n  start_s: 5.0\n  rise_s: 1.0\n");
    TEST_ASSERT_EQUAL_INT(n, data_rows(calm, &c));
    TEST_ASSERT_EQUAL_INT(n, data_rows(later, &d));
    int calm_differs = 0;
    for (int i = 0; i < n; ++i) {
        TEST_ASSERT_EQUAL_STRING(c.row[i], d.row[i]);
        calm_differs += (strcmp(c.row[i], a.row[i]) != 0) ? 1 : 0;
    }
    TEST_ASSERT_TRUE(calm_differs > 50); /* the wind does act on this robot */
    free(c.buf);
    free(d.buf);
    /* A gust from 0.5 s (the row of t = 0.5 s is row 51): the rows up to it as the steady
     * run's, every row after it different. */
    const char *gust = wind_run("wind-gust", "[0.0, 0.0, 0.0]",
                                "wind:\n  speed_m_per_s: 4.0\n  towards_deg: 90\n"
                                "  profile: gust\n  start_s: 0.5\n  rise_s: 0.4\n"
                                "  gust_m_per_s: 6.0\n");
    TEST_ASSERT_EQUAL_INT(n, data_rows(gust, &c));
    for (int i = 0; i < n; ++i) {
        const int same_row = (strcmp(c.row[i], b.row[i]) == 0) ? 1 : 0;
        TEST_ASSERT_EQUAL_INT_MESSAGE((i <= 51) ? 1 : 0, same_row, c.row[i]);
    }
    free(a.buf);
    free(b.buf);
    free(c.buf);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_paper_circle_regression_and_rerun);
    RUN_TEST(test_regression_sees_a_1_percent_mass_change);
    RUN_TEST(test_paper_line_regression_and_rerun);
    RUN_TEST(test_deploy_retrieve_node_events);
    RUN_TEST(test_summary_real_time_block_round_trip);
    RUN_TEST(test_substep_limit_names_the_key_and_a_budget_that_works);
    RUN_TEST(test_a_changed_scenario_is_checked_again);
    RUN_TEST(test_wind_section_in_the_run);
    return UNITY_END() ? 1 : 0;
}
