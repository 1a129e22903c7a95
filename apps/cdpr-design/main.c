/* SPDX-License-Identifier: BSD-3-Clause */
/// @file main.c
/// cdpr-design: the linear model of a scenario's closed loop about a held pose, for the
/// feedback design of scripts/feedback_design.py (docs/validation.md §8, "Feedback design").
///
/// The scenario's robot is settled at the trajectory's pose at time T (default: the time the
/// trajectory stops, or 0) and the scenario's controller is built to hold that pose. Written
/// to OUT (raw little-endian doubles, row-major, dimensions in OUT/meta.txt; m = the robot's
/// cables, nu = m, nz = 33 + 4 m, nm = 12 + m):
///   A.bin  n x n   ∂f/∂y of cdpr_robot_rhs at the settled state (central differences)
///   B.bin  n x m   ∂f/∂u for the m payout rates
///   Kx.bin m x n, Kz.bin m x nz, Zx.bin nz x n, Zz.bin nz x nz: one cdpr_tracker_step
///          linearised (central differences of the real step on copies of the tracker):
///          u_k = Kx x_k + Kz z_k, z_{k+1} = Zx x_k + Zz z_k, with x the plant state at t_k
///          (measured by cdpr_plant_measure) and z the nz states of the tracker (err_f1,
///          err_f, ten_f, integ, mass_est_kg, l_ff_m, t_ff_N, the weight residual's
///          two filter stages)
///   Ku.bin m x m, Zu.bin nz x m: the same step's dependence on the payout rates in force
///          at t_k (the previous period's command: the measured winch-end tensions carry
///          the rope's damping of the payout), u_k += Ku u_{k-1}, z_{k+1} += Zu u_{k-1}
///   Cm.bin nm x n  the pose (p, rotation vector of q q0^-1), v, ω (world) and the m
///          measured lengths, linearised (for the validation step)
///   J.bin  m x 6   the straight-cable length Jacobian at the settled pose, row j = (u_j,
///          (R b_j) x u_j) (cdpr_tracker_jacobian): the learning's length error is
///          e_L = J (δp, δθ) (tracker.h step 8); meta.txt also gives the scenario trajectory's
///          lap (lap_s, learn_knots) and the learning keys, for feedback_design.py --learning
/// With --step-test J: OUT/step.csv, the nonlinear plant (cdpr_plant_step, rate mode) from
/// the settled state with a payout rate of 1 mm/s (--step-rate R: R m/s) on cable J for 2 s,
/// open loop: the same nm outputs per period minus their initial values.
/// With --check: the analysis in C (lib/design, cdpr/design/design.h: the check the apps run
/// at load) printed as JSON with design.json's names, and OUT/check.json; --zoh: OUT/Phi.bin,
/// OUT/Gam.bin, its zero-order hold. The operating point and the linearisation are
/// lib/design's (cdpr_design_point_new, cdpr_design_linearise), so what this tool writes is
/// what the check at load analyses.
/// The tool allocates (it is a host app); the models it linearises are the library's own.
#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "app_cli.h"
#include "app_design.h"
#include "app_run.h"
#include "app_status.h"
#include "cdpr/design/design.h"
#include "cdpr/host/cli.h"
#include "cdpr/host/clock.h"
#include "cdpr/host/fs.h"
#include "cdpr/host/plant.h"
#include "cdpr/host/scenario.h"
#include "cdpr/control/tracker.h"
#include "cdpr/control/trajectory.h"
#include "cdpr/vec3.h"

#define NM_MAX CDPR_DESIGN_NM_MAX

static int write_bin(const char *dir, const char *name, const double *a, size_t count)
{
    char path[1200];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    FILE *f = cdpr_fs_fopen(path, "wb", NULL, 0);
    if (f == NULL) {
        fprintf(stderr, "cdpr-design: %s: cannot write\n", path);
        return -1;
    }
    const size_t w = fwrite(a, sizeof(double), count, f);
    return (fclose(f) == 0 && w == count) ? 0 : -1;
}

/* Open-loop step of 1 mm/s on cable j for 2 s, nonlinear plant: outputs minus initial. */
static int step_test(cdpr_design_point_t *pt, const char *dir, int j, double rate_m_per_s)
{
    char path[1200];
    snprintf(path, sizeof path, "%s/step.csv", dir);
    FILE *f = cdpr_fs_fopen(path, "w", NULL, 0);
    if (f == NULL) {
        return -1;
    }
    double o0[NM_MAX];
    double o[NM_MAX];
    const int nm = 12 + pt->plant.robot.p.n_cables;
    if (j >= pt->plant.robot.p.n_cables) {
        (void)fclose(f);
        fprintf(stderr, "cdpr-design: --step-test %d: the robot has %d winches (0..%d)\n", j,
                pt->plant.robot.p.n_cables, pt->plant.robot.p.n_cables - 1);
        return -1;
    }
    cdpr_design_outputs(pt, pt->plant.y, o0);
    double u[CDPR_MAX_CABLES] = {0.0};
    u[j] = rate_m_per_s;
    const double period_s = pt->sc.period_s;
    const long steps = (long)floor(2.0 / period_s + 0.5);
    int rc = 0;
    for (long k = 0; k <= steps && rc == 0; ++k) {
        cdpr_design_outputs(pt, pt->plant.y, o);
        fprintf(f, "%.6f", (double)k * period_s);
        for (int i = 0; i < nm; ++i) {
            fprintf(f, ",%.10e", o[i] - o0[i]);
        }
        fprintf(f, "\n");
        int flags = 0;
        if (k < steps && cdpr_plant_step(&pt->plant, CDPR_WINCH_RATE, u, &flags) < 0) {
            rc = -1;
        }
    }
    return (fclose(f) == 0) ? rc : -1;
}

/* The lap of the scenario's trajectory, the tracker's knots for it and the learning keys. */
static void write_learning_meta(FILE *f, const cdpr_design_model_t *m)
{
    fprintf(f, "lap_s %.17g\nlearn_knots %.17g\nk_length_per_s %.17g\n", m->lap_s, m->learn_knots,
            m->k_length_per_s);
    fprintf(f, "learning_gain %.17g\nlearning_lead_s %.17g\nlearning_cutoff_hz %.17g\n",
            m->learning_gain, m->learning_lead_s, m->learning_cutoff_hz);
}

static int write_all(const char *dir, const cdpr_design_point_t *pt, const cdpr_design_model_t *m)
{
    const int n = m->n;
    const size_t nn = (size_t)n;
    const size_t nu = (size_t)m->nu;
    const size_t nz = (size_t)m->nz;
    const size_t nm = (size_t)m->nm;
    int rc = write_bin(dir, "A.bin", m->A, nn * nn) | write_bin(dir, "B.bin", m->B, nn * nu) |
             write_bin(dir, "Kx.bin", m->Kx, nu * nn) | write_bin(dir, "Kz.bin", m->Kz, nu * nz) |
             write_bin(dir, "Zx.bin", m->Zx, nz * nn) | write_bin(dir, "Zz.bin", m->Zz, nz * nz) |
             write_bin(dir, "Cm.bin", m->Cm, nm * nn) | write_bin(dir, "Ku.bin", m->Ku, nu * nu) |
             write_bin(dir, "Zu.bin", m->Zu, nz * nu) | write_bin(dir, "J.bin", m->J, nu * 6u);
    char path[1200];
    snprintf(path, sizeof path, "%s/meta.txt", dir);
    FILE *f = cdpr_fs_fopen(path, "w", NULL, 0);
    if (f != NULL) {
        const double *pose = pt->pose;
        fprintf(f, "n %d\nperiod_s %.17g\nnz %d\nnu %d\nnm %d\n", n, m->period_s, m->nz, m->nu,
                m->nm);
        fprintf(f, "pose %.17g %.17g %.17g %.17g %.17g %.17g\n", pose[0], pose[1], pose[2], pose[3],
                pose[4], pose[5]);
        fprintf(f, "cabin_mass_kg %.17g\n", pt->plant.robot.p.cabin.mass_kg);
        write_learning_meta(f, m);
        for (int j = 0; j < pt->plant.robot.p.n_cables; ++j) {
            const cdpr_robot_cable_params_t *cp = &pt->plant.params.cables[j];
            fprintf(f, "cable %d offset %d nodes %d node_mass_kg %.17g\n", j,
                    pt->plant.robot.offset[j], pt->plant.robot.cable[j].n,
                    cp->cable.rho_kg_per_m * cp->length_m / (double)pt->plant.robot.cable[j].n);
        }
        rc |= (fclose(f) == 0) ? 0 : -1;
    } else {
        rc = -1;
    }
    return rc;
}

/* A JSON number: Infinity for ±inf (as Python's json writes it), null for NaN. */
static void jnum(FILE *f, const char *name, double v, const char *sep)
{
    if (isnan(v)) {
        fprintf(f, "\"%s\": null%s", name, sep);
    } else if (isinf(v)) {
        fprintf(f, "\"%s\": %sInfinity%s", name, (v < 0.0) ? "-" : "", sep);
    } else {
        fprintf(f, "\"%s\": %.17g%s", name, v, sep);
    }
}

/* The C analysis as JSON, with design.json's names. */
static void print_check(FILE *f, const cdpr_design_report_t *r, double seconds)
{
    fprintf(f, "{\n ");
    jnum(f, "check_s", seconds, ",\n ");
    fprintf(f, "\"n_freq\": %d,\n ", r->n_freq);
    jnum(f, "closed_loop_max_abs_eig", r->max_abs_eig, ",\n ");
    jnum(f, "closed_loop_max_growth_per_s", r->growth_per_s, ",\n ");
    jnum(f, "closed_loop_worst_hz", r->growth_hz, ",\n ");
    jnum(f, "sigma_min_I_plus_L", r->alpha, ",\n ");
    jnum(f, "sigma_min_at_hz", r->alpha_hz, ",\n ");
    fprintf(f, "\"active\": %s,\n \"channels\": [", r->active ? "true" : "false");
    for (int j = 0; r->active && j < r->n_channels; ++j) {
        fprintf(f, "%s\n  {\"cable\": %d, ", (j > 0) ? "," : "", j);
        jnum(f, "gm_db", r->gm_db[j], ", ");
        jnum(f, "gm_hz", r->gm_hz[j], ", ");
        jnum(f, "pm_deg", r->pm_deg[j], ", ");
        jnum(f, "pm_hz", r->pm_hz[j], "}");
    }
    fprintf(f, "],\n \"loop_at_a_time_min\": {");
    jnum(f, "gm_db", r->gm_min_db, ", ");
    jnum(f, "gm_hz", r->gm_min_hz, ", ");
    jnum(f, "pm_deg", r->pm_min_deg, ", ");
    jnum(f, "pm_hz", r->pm_min_hz, "},\n ");
    fprintf(f, "\"learning\": {\"analysed\": %s", r->learning ? "true" : "false");
    if (r->learning) {
        fprintf(f, ", ");
        jnum(f, "band_top_hz", r->band_top_hz, ", ");
        jnum(f, "max_rho_at_harmonics", r->max_rho, ", ");
        fprintf(f, "\"worst_harmonic\": %d, \"first_diverging\": %d,\n  \"G_at_0_diag\": [",
                r->worst_harmonic, r->first_diverging);
        for (int i = 0; i < r->n_channels; ++i) {
            fprintf(f, "%s%.17g", (i > 0) ? ", " : "", r->g0_diag[i]);
        }
        fprintf(f, "],\n  \"harmonics\": [");
        for (int h = 0; h < r->n_harmonics; ++h) {
            fprintf(f, "%s\n   [%.17g, %.17g, %.17g, %.17g]", (h > 0) ? "," : "", r->harmonic_hz[h],
                    r->harmonic_q[h], r->rho[h], r->sigma_max[h]);
        }
        fprintf(f, "]");
    }
    fprintf(f, "}\n}\n");
}

static void usage(FILE *f)
{
    fprintf(f,
            "usage: cdpr-design SCENARIO OUT [--at T] [--step-test J] [--check] [--zoh]\n"
            "       cdpr-design SCENARIO --verdict [--quiet] [overrides]\n"
            "Linear model of the scenario's loop holding the trajectory's pose at T (default:\n"
            "where it stops) written into the directory OUT; scripts/feedback_design.py reads\n"
            "it (modes, closed-loop eigenvalues, margins; docs/validation.md \"Feedback\n"
            "design\").\n\n"
            "  --at T          hold the pose of the trajectory at T [s]\n"
            "  --step-test J   also the nonlinear response to a 1 mm/s step on winch J (0..m-1)\n"
            "  --step-rate R   that step's payout rate [m/s] instead (0 < R <= 0.1)\n"
            "  --check         also the analysis in C (the check the apps run with\n"
            "                  --check-design: growth, margins, α, the learning's ρ) as JSON on\n"
            "                  stdout and OUT/check.json\n"
            "  --verdict       only the verdict of that check at the apps' pose, as the apps\n"
            "                  print it (no OUT): refused (exit 5), below the goal margins (a\n"
            "                  warning, exit 0), passed or feed-forward only (exit 0); with\n"
            "                  --quiet only the refusal or the warning is printed\n"
            "  --rate HZ  --duration S  --max-trials N  --max-attempts N  --integrator NAME\n"
            "                  the run settings of cdpr-sim (docs/scenarios.md), applied first\n"
            "  --zoh           also OUT/Phi.bin (n x n) and OUT/Gam.bin (n x m): the zero-order\n"
            "                  hold over the control period as the check computes it\n"
            "  --help          this text\n"
            "  --version       version and git description\n\n"
            "exit codes: 0 done, 1 step test failed, 2 bad command line or scenario,\n"
            "            3 OUT cannot be written, 4 the analysis failed, 5 --verdict: the\n"
            "            controller is refused\n");
}

/* Phi.bin, Gam.bin: the check's zero-order hold of the plant. */
static int write_zoh(const char *dir, const cdpr_design_model_t *m)
{
    const size_t n = (size_t)m->n;
    const size_t nu = (size_t)m->nu;
    double *Phi = malloc(sizeof(double) * n * (n + nu));
    if (Phi == NULL) {
        return CDPR_EXIT_UNKNOWN;
    }
    cdpr_design_error_t err;
    int rc = 0;
    if (cdpr_design_discretise(m, Phi, Phi + n * n, &err) != CDPR_OK) {
        fprintf(stderr, "cdpr-design: %s\n", err.msg);
        rc = CDPR_EXIT_UNKNOWN;
    } else if ((write_bin(dir, "Phi.bin", Phi, n * n) |
                write_bin(dir, "Gam.bin", Phi + n * n, n * nu)) != 0) {
        rc = cdpr_app_exit_code(CDPR_E_IO);
    }
    free(Phi);
    return rc;
}

/* The analysis of model m, printed and written to OUT/check.json. */
static int run_check(const char *dir, const cdpr_design_model_t *m, double t0)
{
    cdpr_design_report_t *r = malloc(sizeof *r);
    if (r == NULL) {
        return CDPR_EXIT_UNKNOWN;
    }
    cdpr_design_error_t err;
    const cdpr_status_t st = cdpr_design_analyse(m, 1, r, &err);
    if (st != CDPR_OK) {
        fprintf(stderr, "cdpr-design: %s\n", err.msg);
        free(r);
        return 4;
    }
    const double dt = cdpr_clock_now_s() - t0;
    print_check(stdout, r, dt);
    char path[1200];
    snprintf(path, sizeof path, "%s/check.json", dir);
    FILE *f = cdpr_fs_fopen(path, "w", NULL, 0);
    int rc = 0;
    if (f == NULL) {
        rc = cdpr_app_exit_code(CDPR_E_IO);
    } else {
        print_check(f, r, dt);
        rc = (fclose(f) == 0) ? 0 : cdpr_app_exit_code(CDPR_E_IO);
    }
    free(r);
    return rc;
}

/* --verdict: the check the apps run with --check-design, at their pose, printed as they print
 * it; one more line on stdout when it passes. Exit 5 when refused. */
static int run_verdict(int argc, char **argv, const cdpr_scenario_overrides_t *ov, int quiet)
{
    if (argc - optind != 1) {
        return cdpr_app_exit_code(
            cdpr_app_usage_error("cdpr-design", "--verdict takes SCENARIO alone (no OUT)"));
    }
    const char *path = argv[optind];
    static cdpr_scenario_t sc;
    const cdpr_status_t ls = cdpr_app_scenario("cdpr-design", path, ov, &sc);
    if (ls != CDPR_OK) {
        return cdpr_app_exit_code(ls);
    }
    const cdpr_status_t st = cdpr_app_design_check("cdpr-design", path, &sc, quiet);
    if (st == CDPR_E_OUT_OF_RANGE) {
        return 5;
    }
    if (st != CDPR_OK) {
        return 4;
    }
    if (quiet != 0) {
        return 0;
    }
    printf("cdpr-design: %s: %s\n", path,
           (cdpr_tracker_has_feedback(&sc.gains) != 0) ? "the controller passes the design check"
                                                       : "feed-forward only: nothing to check");
    return 0;
}

/* The command line of cdpr-design. */
typedef struct {
    double at_s;      /* --at, NaN: not given */
    double cable;     /* --step-test, < 0: not given */
    double step_rate; /* --step-rate [m/s] */
    int check, zoh, verdict, quiet;
    cdpr_scenario_overrides_t ov;
} options_t;

/* The options of cdpr-design (cdpr_app_option_fn). */
static int take(int c, const char *arg, void *ctx)
{
    options_t *o = ctx;
    const int ov = cdpr_app_run_option("cdpr-design", c, arg, &o->ov, NULL, &o->quiet);
    if (ov != 1) {
        return ov;
    }
    cdpr_status_t bad = CDPR_OK;
    if (c == 'a') {
        bad = cdpr_cli_number("cdpr-design", "at", arg, 0.0, 1e6, &o->at_s);
    } else if (c == 's') {
        bad = cdpr_cli_number("cdpr-design", "step-test", arg, 0.0, (double)(CDPR_MAX_CABLES - 1),
                              &o->cable);
        bad = (bad == CDPR_OK && floor(o->cable) < o->cable)
                  ? cdpr_app_usage_error("cdpr-design", "--step-test: a winch 0..m-1")
                  : bad;
    } else if (c == 'p') {
        bad = cdpr_cli_number("cdpr-design", "step-rate", arg, 1e-9, 0.1, &o->step_rate);
    } else {
        const cdpr_app_store_t stores[] = {
            {.code = 'c', .flag = &o->check, .value = 1},
            {.code = 'z', .flag = &o->zoh, .value = 1},
            {.code = 'v', .flag = &o->verdict, .value = 1},
        };
        return cdpr_app_store(stores, sizeof stores / sizeof stores[0], c, arg);
    }
    return (bad != CDPR_OK) ? -1 : 0;
}

int main(int argc, char **argv)
{
    static const struct option longopts[] = {{"at", required_argument, NULL, 'a'},
                                             {"step-test", required_argument, NULL, 's'},
                                             {"step-rate", required_argument, NULL, 'p'},
                                             {"check", no_argument, NULL, 'c'},
                                             {"zoh", no_argument, NULL, 'z'},
                                             {"verdict", no_argument, NULL, 'v'},
                                             CDPR_APP_QUIET_OPTION,
                                             CDPR_APP_OVERRIDE_OPTIONS,
                                             CDPR_APP_STD_OPTIONS_END};
    options_t o;
    memset(&o, 0, sizeof o);
    o.at_s = (double)NAN;
    o.cable = -1.0;
    o.step_rate = 1e-3;
    cdpr_scenario_overrides_none(&o.ov);
    if (cdpr_app_parse("cdpr-design", argc, argv, longopts, usage, take, &o) != 0) {
        return cdpr_app_exit_code(CDPR_E_INVALID_ARG);
    }
    const double at_s = o.at_s;
    const double cable = o.cable;
    const int check = o.check;
    const int zoh = o.zoh;
    const int verdict = o.verdict;
    const int quiet = o.quiet;
    const cdpr_scenario_overrides_t ov = o.ov;
    if (verdict != 0) {
        if (!isnan(at_s) || cable >= 0.0 || check != 0 || zoh != 0) {
            return cdpr_app_exit_code(cdpr_app_usage_error(
                "cdpr-design", "--verdict takes no --at, --step-test, --check or --zoh (it "
                               "checks at the apps' pose and writes nothing)"));
        }
        return run_verdict(argc, argv, &ov, quiet);
    }
    if (quiet != 0) {
        return cdpr_app_exit_code(cdpr_app_usage_error("cdpr-design", "--quiet is for --verdict"));
    }
    if (argc - optind != 2) {
        return cdpr_app_exit_code(cdpr_app_usage_error("cdpr-design", "SCENARIO and OUT expected"));
    }
    const int step_cable = (int)cable;
    const char *dir = argv[optind + 1];
    const double t0 = cdpr_clock_now_s();
    static cdpr_scenario_t sc;
    cdpr_status_t st = cdpr_app_scenario("cdpr-design", argv[optind], &ov, &sc);
    if (st != CDPR_OK) {
        return cdpr_app_exit_code(st);
    }
    cdpr_design_point_t *pt = NULL;
    cdpr_design_error_t err;
    st = cdpr_design_point_new(&sc, at_s, NULL, &pt, &err);
    if (st != CDPR_OK) {
        fprintf(stderr, "cdpr-design: %s\n", err.msg);
        return cdpr_app_exit_code(st);
    }
    cdpr_design_model_t m;
    st = cdpr_design_linearise(pt, &m, &err);
    if (st != CDPR_OK) {
        fprintf(stderr, "cdpr-design: %s\n", err.msg);
        cdpr_design_point_free(pt);
        return cdpr_app_exit_code(st);
    }
    int rc = 0;
    if (write_all(dir, pt, &m) != 0) {
        fprintf(stderr, "cdpr-design: %s: cannot write the model\n", dir);
        rc = cdpr_app_exit_code(CDPR_E_IO);
    }
    if (rc == 0 && step_cable >= 0 && step_test(pt, dir, step_cable, o.step_rate) != 0) {
        fprintf(stderr, "cdpr-design: step test failed\n");
        rc = 1;
    }
    if (rc == 0 && zoh != 0) {
        rc = write_zoh(dir, &m);
    }
    if (rc == 0 && check != 0) {
        rc = run_check(dir, &m, t0);
    }
    cdpr_design_model_free(&m);
    cdpr_design_point_free(pt);
    return rc;
}
