/* SPDX-License-Identifier: BSD-3-Clause */
/// @file main.c
/// cdpr-design: the linear model of a scenario's closed loop about a held pose, for the
/// feedback design of scripts/feedback_design.py (docs/validation.md §8, "Feedback design").
///
/// The scenario's robot is settled at the trajectory's pose at time T (default: the time the
/// trajectory stops, or 0) and the scenario's controller is built to hold that pose. Written
/// to OUT (raw little-endian doubles, row-major, dimensions in OUT/meta.txt):
///   A.bin  n x n   ∂f/∂y of cdpr_robot_rhs at the settled state (central differences)
///   B.bin  n x 6   ∂f/∂u for the six payout rates
///   Kx.bin 6 x n, Kz.bin 6 x 24, Zx.bin 24 x n, Zz.bin 24 x 24: one cdpr_tracker_step
///          linearised (central differences of the real step on copies of the tracker):
///          u_k = Kx x_k + Kz z_k, z_{k+1} = Zx x_k + Zz z_k, with x the plant state at t_k
///          (measured by cdpr_plant_measure) and z the 30 filter states (err_f1, err_f,
///          ten_f)
///   Ku.bin 6 x 6, Zu.bin 30 x 6: the same step's dependence on the payout rates in force
///          at t_k (the previous period's command: the measured winch-end tensions carry
///          the rope's damping of the payout), u_k += Ku u_{k-1}, z_{k+1} += Zu u_{k-1}
///   Cm.bin 18 x n  the pose (p, rotation vector of q q0^-1), v, ω (world) and the six
///          measured lengths, linearised (for the validation step)
///   J.bin  6 x 6   the straight-cable length Jacobian at the settled pose, row j = (u_j,
///          (R b_j) x u_j) (cdpr_tracker_jacobian): the learning's length error is
///          e_L = J (δp, δθ) (tracker.h step 8); meta.txt also gives the scenario trajectory's
///          lap (lap_s, learn_knots) and the learning keys, for feedback_design.py --learning
/// With --step-test J: OUT/step.csv, the nonlinear plant (cdpr_plant_step, rate mode) from
/// the settled state with a payout rate of 1 mm/s on cable J for 2 s, open loop: the same 18
/// outputs per period minus their initial values.
/// The tool allocates (it is a host app); the models it linearises are the library's own.
#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "app_cli.h"
#include "app_run.h"
#include "app_status.h"
#include "cdpr/host/cli.h"
#include "cdpr/host/plant.h"
#include "cdpr/host/scenario.h"
#include "cdpr/host/tracker.h"
#include "cdpr/host/trajectory.h"
#include "cdpr/vec3.h"

#define NZ 30 /* filter states of the tracker: err_f1, err_f (12 each), ten_f (6) */
#define NM 18 /* linearised outputs of Cm */
#define NU 6  /* payout rates */

static cdpr_plant_t g_plant;
static double g_lap_s; /* lap of the scenario's own trajectory (0: not periodic) */
static cdpr_tracker_t g_tr0;
static cdpr_tracker_t g_tr;
static cdpr_scenario_t g_sc;

/* Perturbation of state component i (relative above 1). */
static double step_of(double y, double rel)
{
    return rel * fmax(1.0, fabs(y));
}

static int write_bin(const char *dir, const char *name, const double *a, size_t count)
{
    char path[1200];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    FILE *f = fopen(path, "wb");
    if (f == NULL) {
        fprintf(stderr, "cdpr-design: %s: cannot write\n", path);
        return -1;
    }
    const size_t w = fwrite(a, sizeof(double), count, f);
    return (fclose(f) == 0 && w == count) ? 0 : -1;
}

/* The 18 outputs of the measurement at plant state y (written into the plant temporarily). */
static void outputs_at(const double *y, const cdpr_quat_t q0, double *o)
{
    const int n = g_plant.robot.dim;
    double save[CDPR_ROBOT_STATE_MAX];
    memcpy(save, g_plant.y, sizeof(double) * (size_t)n);
    memcpy(g_plant.y, y, sizeof(double) * (size_t)n);
    cdpr_plant_meas_t m;
    cdpr_plant_measure(&g_plant, &m);
    memcpy(g_plant.y, save, sizeof(double) * (size_t)n);
    const cdpr_quat_t q0i = {q0.w, -q0.x, -q0.y, -q0.z};
    const cdpr_vec3_t th = cdpr_quat_to_rotvec(cdpr_quat_mul(m.cabin.q, q0i));
    cdpr_mat3_t R;
    cdpr_quat_to_mat3(m.cabin.q, &R);
    const cdpr_vec3_t w = cdpr_m3_mul_v3(&R, m.cabin.w_rad_per_s);
    const double v[12] = {
        m.cabin.p_m.x,       m.cabin.p_m.y,       m.cabin.p_m.z,       th.x, th.y, th.z,
        m.cabin.v_m_per_s.x, m.cabin.v_m_per_s.y, m.cabin.v_m_per_s.z, w.x,  w.y,  w.z};
    memcpy(o, v, sizeof v);
    for (int j = 0; j < 6; ++j) {
        o[12 + j] = m.length_m[j];
    }
}

/* One tracker step from the held tracker with filter state z at plant state y and payout
 * rates in force up: the six rate commands into u, the new filter state into zn. */
static void ctrl_at(const double *y, const double *z, const double *up, double *u, double *zn)
{
    const int n = g_plant.robot.dim;
    double save[CDPR_ROBOT_STATE_MAX];
    memcpy(save, g_plant.y, sizeof(double) * (size_t)n);
    memcpy(g_plant.y, y, sizeof(double) * (size_t)n);
    for (int j = 0; j < NU; ++j) {
        g_plant.robot.in.payout_m_per_s[j] = up[j];
    }
    cdpr_plant_meas_t m;
    cdpr_plant_measure(&g_plant, &m);
    for (int j = 0; j < NU; ++j) {
        g_plant.robot.in.payout_m_per_s[j] = 0.0;
    }
    memcpy(g_plant.y, save, sizeof(double) * (size_t)n);
    m.t_s = g_tr0.t_next_s;
    g_tr = g_tr0;
    memcpy(g_tr.err_f1, z, sizeof(double) * 12);
    memcpy(g_tr.err_f, z + 12, sizeof(double) * 12);
    memcpy(g_tr.ten_f, z + 24, sizeof(double) * 6);
    g_tr.filter_primed = 1;
    cdpr_tracker_cmd_t cmd;
    (void)cdpr_tracker_step(&g_tr, &m, &cmd);
    memcpy(u, cmd.rate_m_per_s, sizeof(double) * NU);
    memcpy(zn, g_tr.err_f1, sizeof(double) * 12);
    memcpy(zn + 12, g_tr.err_f, sizeof(double) * 12);
    memcpy(zn + 24, g_tr.ten_f, sizeof(double) * 6);
}

/* A and B by central differences of cdpr_robot_rhs (payout rates zero at the settled state). */
static void plant_jacobians(double *A, double *B)
{
    cdpr_robot_t *r = &g_plant.robot;
    const int n = r->dim;
    double *y = malloc(sizeof(double) * (size_t)n);
    double *fp = malloc(sizeof(double) * (size_t)n);
    double *fm = malloc(sizeof(double) * (size_t)n);
    memcpy(y, g_plant.y, sizeof(double) * (size_t)n);
    for (int j = 0; j < CDPR_MAX_CABLES; ++j) {
        r->in.payout_m_per_s[j] = 0.0;
    }
    for (int i = 0; i < n + NU; ++i) {
        const double h = (i < n) ? step_of(y[i], 1e-6) : 1e-6;
        double *slot = (i < n) ? &y[i] : &r->in.payout_m_per_s[i - n];
        const double y0 = *slot;
        *slot = y0 + h;
        (void)cdpr_robot_rhs(0.0, y, fp, r);
        *slot = y0 - h;
        (void)cdpr_robot_rhs(0.0, y, fm, r);
        *slot = y0;
        for (int k = 0; k < n; ++k) {
            const double d = (fp[k] - fm[k]) / (2.0 * h);
            if (i < n) {
                A[(size_t)k * (size_t)n + (size_t)i] = d;
            } else {
                B[(size_t)k * NU + (size_t)(i - n)] = d;
            }
        }
    }
    free(y);
    free(fp);
    free(fm);
}

/* Kx, Zx, Cm (columns: plant state) and Kz, Zz (columns: filter state) by central
 * differences of the real tracker step and measurement about (y0, z0). */
static void ctrl_jacobians(const double *z0, double *Kx, double *Kz, double *Zx, double *Zz,
                           double *Cm, double *Ku, double *Zu)
{
    const int n = g_plant.robot.dim;
    const cdpr_quat_t q0 = cdpr_quat_normalize(g_plant.pp.initial.q);
    double *y = malloc(sizeof(double) * (size_t)n);
    memcpy(y, g_plant.y, sizeof(double) * (size_t)n);
    double z[NZ];
    memcpy(z, z0, sizeof z);
    double u0[NU] = {0.0};
    double up[NU], um[NU], zp[NZ], zm[NZ], op[NM], om[NM];
    for (int i = 0; i < n + NZ + NU; ++i) {
        double *slot = (i < n) ? &y[i] : (i < n + NZ) ? &z[i - n] : &u0[i - n - NZ];
        const double v0 = *slot;
        const double h = (i < n + NZ) ? step_of(v0, 1e-6) : 1e-6;
        *slot = v0 + h;
        ctrl_at(y, z, u0, up, zp);
        if (i < n) {
            outputs_at(y, q0, op);
        }
        *slot = v0 - h;
        ctrl_at(y, z, u0, um, zm);
        if (i < n) {
            outputs_at(y, q0, om);
        }
        *slot = v0;
        const size_t nc = (i < n) ? (size_t)n : (i < n + NZ) ? NZ : NU;
        const size_t c = (i < n)        ? (size_t)i
                         : (i < n + NZ) ? (size_t)(i - n)
                                        : (size_t)(i - n - NZ);
        double *K = (i < n) ? Kx : (i < n + NZ) ? Kz : Ku;
        double *Z = (i < n) ? Zx : (i < n + NZ) ? Zz : Zu;
        for (int k = 0; k < NU; ++k) {
            K[(size_t)k * nc + c] = (up[k] - um[k]) / (2.0 * h);
        }
        for (int k = 0; k < NZ; ++k) {
            Z[(size_t)k * nc + c] = (zp[k] - zm[k]) / (2.0 * h);
        }
        for (int k = 0; i < n && k < NM; ++k) {
            Cm[(size_t)k * nc + c] = (op[k] - om[k]) / (2.0 * h);
        }
    }
    free(y);
}

/* Load the scenario, replace its trajectory by a hold at the trajectory's pose at `at_s`
 * (NaN: where it stops, or its start for a circle), settle the plant there and build the
 * controller holding it. */
static cdpr_status_t setup(const char *path, double at_s, double pose[6])
{
    cdpr_scenario_overrides_t ov;
    cdpr_scenario_overrides_none(&ov);
    cdpr_status_t st = cdpr_app_scenario("cdpr-design", path, &ov, &g_sc);
    if (st != CDPR_OK) {
        return st;
    }
    double t = at_s;
    if (!isfinite(t)) {
        t = cdpr_traj_end_time(&g_sc.traj);
        t = isfinite(t) ? t : 0.0;
    }
    cdpr_traj_sample_t s;
    cdpr_traj_eval(&g_sc.traj, t, &s);
    memcpy(pose, s.pose, sizeof s.pose);
    g_lap_s = cdpr_traj_lap_s(&g_sc.traj);
    g_sc.traj.type = CDPR_TRAJ_HOLD;
    memcpy(g_sc.traj.hold_pose, s.pose, sizeof s.pose);
    g_sc.has_initial_pose = 0;
    memset(g_sc.initial_offset, 0, sizeof g_sc.initial_offset);
    g_sc.gains.transfer_s = 0.0;
    cdpr_scenario_error_t err;
    st = cdpr_host_plant_init(&g_plant, &g_sc, NULL, &err);
    if (st != CDPR_OK) {
        fprintf(stderr, "cdpr-design: plant: %s\n", cdpr_status_str(st));
        return st;
    }
    cdpr_tracker_gains_t g = g_sc.gains;
    g.wind_m_per_s = g_plant.pp.wind_m_per_s;
    cdpr_diag_t d;
    st = cdpr_tracker_init(&g_tr0, &g_plant.params, &g_sc.traj, &g, g_sc.period_s, 0.0, &d);
    if (st != CDPR_OK) {
        fprintf(stderr, "cdpr-design: controller: field '%s': %s\n", d.field, cdpr_status_str(st));
    }
    return st;
}

/* Filter state at the operating point: both stages primed with the error of the settled
 * state (the discrete equilibrium's small offset from the IK pose). */
static void operating_filter(double *z0)
{
    cdpr_plant_meas_t m;
    cdpr_plant_measure(&g_plant, &m);
    m.t_s = g_tr0.t_next_s;
    g_tr = g_tr0;
    g_tr.filter_primed = 0;
    cdpr_tracker_cmd_t cmd;
    (void)cdpr_tracker_step(&g_tr, &m, &cmd);
    memcpy(z0, g_tr.err_f1, sizeof(double) * 12);
    memcpy(z0 + 12, g_tr.err_f, sizeof(double) * 12);
    memcpy(z0 + 24, g_tr.ten_f, sizeof(double) * 6);
}

/* Open-loop step of 1 mm/s on cable j for 2 s, nonlinear plant: outputs minus initial. */
static int step_test(const char *dir, int j)
{
    char path[1200];
    snprintf(path, sizeof path, "%s/step.csv", dir);
    FILE *f = fopen(path, "w");
    if (f == NULL) {
        return -1;
    }
    const cdpr_quat_t q0 = cdpr_quat_normalize(g_plant.pp.initial.q);
    double o0[NM];
    double o[NM];
    outputs_at(g_plant.y, q0, o0);
    double u[CDPR_MAX_CABLES] = {0.0};
    u[j] = 1e-3;
    const long steps = (long)floor(2.0 / g_sc.period_s + 0.5);
    int rc = 0;
    for (long k = 0; k <= steps && rc == 0; ++k) {
        outputs_at(g_plant.y, q0, o);
        fprintf(f, "%.6f", (double)k * g_sc.period_s);
        for (int i = 0; i < NM; ++i) {
            fprintf(f, ",%.10e", o[i] - o0[i]);
        }
        fprintf(f, "\n");
        int flags = 0;
        if (k < steps && cdpr_plant_step(&g_plant, CDPR_WINCH_RATE, u, &flags) < 0) {
            rc = -1;
        }
    }
    return (fclose(f) == 0) ? rc : -1;
}

/* J.bin: the straight-cable length Jacobian at the settled pose (rows u_j, (R b_j) x u_j). */
static int write_jacobian(const char *dir)
{
    cdpr_plant_meas_t m;
    cdpr_plant_measure(&g_plant, &m);
    double J[NU * 6];
    for (int j = 0; j < NU; ++j) {
        cdpr_vec3_t u;
        cdpr_vec3_t g;
        cdpr_tracker_jacobian(&g_tr0.model, j, &m.cabin, &u, &g);
        const double row[6] = {u.x, u.y, u.z, g.x, g.y, g.z};
        memcpy(&J[j * 6], row, sizeof row);
    }
    return write_bin(dir, "J.bin", J, NU * 6);
}

/* The lap of the scenario's trajectory, the tracker's knots for it and the learning keys. */
static void write_learning_meta(FILE *f)
{
    const double per_lap = floor(g_lap_s / g_sc.period_s + 0.5);
    const double knots =
        (per_lap > (double)CDPR_TRACKER_LEARN_KNOTS) ? (double)CDPR_TRACKER_LEARN_KNOTS : per_lap;
    const cdpr_tracker_gains_t *g = &g_sc.gains;
    fprintf(f, "lap_s %.17g\nlearn_knots %.17g\nk_length_per_s %.17g\n", g_lap_s, knots,
            g->k_length_per_s);
    fprintf(f, "learning_gain %.17g\nlearning_lead_s %.17g\nlearning_cutoff_hz %.17g\n",
            g->learning_gain, g->learning_lead_s, g->learning_cutoff_hz);
}

static int write_all(const char *dir, const double *pose)
{
    const int n = g_plant.robot.dim;
    const size_t nn = (size_t)n;
    double *A = calloc(nn * nn, sizeof(double));
    double *B = calloc(nn * NU, sizeof(double));
    double *Kx = calloc(NU * nn, sizeof(double));
    double *Zx = calloc(NZ * nn, sizeof(double));
    double *Cm = calloc(NM * nn, sizeof(double));
    double Kz[NU * NZ];
    double Zz[NZ * NZ];
    double Ku[NU * NU];
    double Zu[NZ * NU];
    double z0[NZ];
    operating_filter(z0);
    plant_jacobians(A, B);
    ctrl_jacobians(z0, Kx, Kz, Zx, Zz, Cm, Ku, Zu);
    int rc = write_bin(dir, "A.bin", A, nn * nn) | write_bin(dir, "B.bin", B, nn * NU) |
             write_bin(dir, "Kx.bin", Kx, NU * nn) | write_bin(dir, "Kz.bin", Kz, NU * NZ) |
             write_bin(dir, "Zx.bin", Zx, NZ * nn) | write_bin(dir, "Zz.bin", Zz, NZ * NZ) |
             write_bin(dir, "Cm.bin", Cm, NM * nn) | write_bin(dir, "Ku.bin", Ku, NU * NU) |
             write_bin(dir, "Zu.bin", Zu, NZ * NU) | write_jacobian(dir);
    char path[1200];
    snprintf(path, sizeof path, "%s/meta.txt", dir);
    FILE *f = fopen(path, "w");
    if (f != NULL) {
        fprintf(f, "n %d\nperiod_s %.17g\nnz %d\nnu %d\nnm %d\n", n, g_sc.period_s, NZ, NU, NM);
        fprintf(f, "pose %.17g %.17g %.17g %.17g %.17g %.17g\n", pose[0], pose[1], pose[2], pose[3],
                pose[4], pose[5]);
        fprintf(f, "cabin_mass_kg %.17g\n", g_plant.robot.p.cabin.mass_kg);
        write_learning_meta(f);
        for (int j = 0; j < g_plant.robot.p.n_cables; ++j) {
            const cdpr_robot_cable_params_t *cp = &g_plant.params.cables[j];
            fprintf(f, "cable %d offset %d nodes %d node_mass_kg %.17g\n", j,
                    g_plant.robot.offset[j], g_plant.robot.cable[j].n,
                    cp->cable.rho_kg_per_m * cp->length_m / (double)g_plant.robot.cable[j].n);
        }
        rc |= (fclose(f) == 0) ? 0 : -1;
    } else {
        rc = -1;
    }
    free(A);
    free(B);
    free(Kx);
    free(Zx);
    free(Cm);
    return rc;
}

static void usage(FILE *f)
{
    fprintf(f, "usage: cdpr-design SCENARIO OUT [--at T] [--step-test J]\n"
               "Linear model of the scenario's loop holding the trajectory's pose at T (default:\n"
               "where it stops) written into the directory OUT; scripts/feedback_design.py reads\n"
               "it (modes, closed-loop eigenvalues, margins; docs/validation.md \"Feedback\n"
               "design\").\n\n"
               "  --at T          hold the pose of the trajectory at T [s]\n"
               "  --step-test J   also the nonlinear response to a 1 mm/s step on winch J (0..5)\n"
               "  --help          this text\n"
               "  --version       version and git description\n\n"
               "exit codes: 0 done, 1 step test failed, 2 bad command line or scenario,\n"
               "            3 OUT cannot be written\n");
}

int main(int argc, char **argv)
{
    static const struct option longopts[] = {{"at", required_argument, NULL, 'a'},
                                             {"step-test", required_argument, NULL, 's'},
                                             CDPR_APP_STD_OPTIONS,
                                             {NULL, 0, NULL, 0}};
    double at_s = (double)NAN;
    double cable = -1.0;
    int c;
    opterr = 0;
    while ((c = getopt_long(argc, argv, CDPR_APP_OPTSTRING, longopts, NULL)) != -1) {
        cdpr_status_t bad = CDPR_OK;
        if (c == 'a') {
            bad = cdpr_cli_number("cdpr-design", "at", optarg, 0.0, 1e6, &at_s);
        } else if (c == 's') {
            bad = cdpr_cli_number("cdpr-design", "step-test", optarg, 0.0, 5.0, &cable);
            bad = (bad == CDPR_OK && floor(cable) < cable)
                      ? cdpr_app_usage_error("cdpr-design", "--step-test: a winch 0..5")
                      : bad;
        } else {
            return cdpr_app_exit_code(
                cdpr_app_other_option("cdpr-design", c, argv, longopts, usage));
        }
        if (bad != CDPR_OK) {
            return cdpr_app_exit_code(CDPR_E_INVALID_ARG);
        }
    }
    if (argc - optind != 2) {
        return cdpr_app_exit_code(cdpr_app_usage_error("cdpr-design", "SCENARIO and OUT expected"));
    }
    const int step_cable = (int)cable;
    double pose[6];
    const cdpr_status_t st = setup(argv[optind], at_s, pose);
    if (st != CDPR_OK) {
        return cdpr_app_exit_code(st);
    }
    if (write_all(argv[optind + 1], pose) != 0) {
        fprintf(stderr, "cdpr-design: %s: cannot write the model\n", argv[optind + 1]);
        return cdpr_app_exit_code(CDPR_E_IO);
    }
    if (step_cable >= 0 && step_test(argv[optind + 1], step_cable) != 0) {
        fprintf(stderr, "cdpr-design: step test failed\n");
        return 1;
    }
    return 0;
}
