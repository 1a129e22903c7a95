/* SPDX-License-Identifier: BSD-3-Clause */
/// @file main.c
/// cdpr-settle: a single cable released from the straight line between two fixed points,
/// settled to rest by the lumped-mass dynamics, compared with Irvine's elastic catenary.
///
/// This is the validation case of the foundation (docs/validation.md): it prints, for a sweep
/// of segment counts, the settled mid-span sag and end tensions next to the closed form and
/// writes the node positions as CSV.
#include <errno.h>
#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "app_cli.h"
#include "app_status.h"
#include "cdpr/catenary.h"
#include "cdpr/host/cli.h"
#include "cdpr/host/clock.h"
#include "cdpr/host/fs.h"
#include "cdpr/robot.h"
#include "cdpr/rkf45.h"
#include "cdpr/settle.h"

typedef struct {
    double length_m;
    double span_m;
    double height_m;
    double ea_N;
    double rho_kg_per_m;
    const char *out_dir;
    int segments[8];
    int n_runs;
} options_t;

/* Results of one settled run. */
typedef struct {
    int n;
    long steps;
    long resets;
    double sim_time_s;
    double wall_s;
    double sag_m;     /* mid-span sag below the chord (interpolated at x = l/2) */
    double t_a_N;     /* support force magnitude at A (node 0, the "cabin" end) */
    double t_b_N;     /* support force magnitude at B (node n, the "winch" end) */
    double max_dev_m; /* max node distance from the catenary at the same arclength */
} result_t;

static cdpr_robot_t robot;
static cdpr_real_t y[CDPR_ROBOT_STATE_MAX];
static cdpr_real_t scratch[CDPR_ROBOT_STATE_MAX];
static cdpr_real_t work[CDPR_RKF45_WORK_PER_DIM * CDPR_ROBOT_STATE_MAX];

static void usage(FILE *f)
{
    fprintf(f, "usage: cdpr-settle [options]\n"
               "Release one cable from the straight line between two fixed points, let it\n"
               "settle under gravity, and compare with the elastic catenary (Irvine).\n\n"
               "  --out DIR         write CSV files to DIR (default out/settle)\n"
               "  --length L        unstretched length [m] (default 100)\n"
               "  --span S          horizontal span [m] (default 80)\n"
               "  --height H        height of the far end above the near end [m] (default 10)\n"
               "  --ea EA           axial stiffness [N] (default 2e4: ~0.5 %% strain)\n"
               "  --rho RHO         mass per length [kg/m] (default 0.14)\n"
               "  --segments LIST   comma-separated segment counts (default 8,16,32,64)\n"
               "  --help            this text\n"
               "  --version         version and git description\n\n"
               "exit codes: 0 done, 1 a settling run failed, 2 bad command line or cable, 3 output "
               "error\n");
}

static int parse_segments(const char *s, options_t *o)
{
    char buf[128];
    if (strlen(s) >= sizeof buf) {
        fprintf(stderr, "cdpr-settle: --segments: longer than %zu characters\n", sizeof buf - 1);
        return -1;
    }
    snprintf(buf, sizeof buf, "%s", s);
    o->n_runs = 0;
    for (char *tok = strtok(buf, ","); tok != NULL; tok = strtok(NULL, ",")) {
        char *end = NULL;
        const long v = strtol(tok, &end, 10);
        if (*end != '\0' || v < 1 || v > CDPR_MAX_SEGMENTS || o->n_runs >= 8) {
            fprintf(stderr, "cdpr-settle: --segments: '%s' is not in [1, %d] (max 8 values)\n", tok,
                    CDPR_MAX_SEGMENTS);
            return -1;
        }
        o->segments[o->n_runs++] = (int)v;
    }
    if (o->n_runs == 0) {
        fprintf(stderr, "cdpr-settle: --segments: no value in '%s'\n", s);
        return -1;
    }
    return 0;
}

/* The options of cdpr-settle (cdpr_app_option_fn). */
static int take(int c, const char *arg, void *ctx)
{
    options_t *o = ctx;
    int rc = 0;
    switch (c) {
    case 'o':
        o->out_dir = arg;
        break;
    case 'L':
        rc = (int)cdpr_cli_real("cdpr-settle", "length", arg, &o->length_m);
        break;
    case 's':
        rc = (int)cdpr_cli_real("cdpr-settle", "span", arg, &o->span_m);
        break;
    case 'H':
        rc = (int)cdpr_cli_real("cdpr-settle", "height", arg, &o->height_m);
        break;
    case 'e':
        rc = (int)cdpr_cli_real("cdpr-settle", "ea", arg, &o->ea_N);
        break;
    case 'r':
        rc = (int)cdpr_cli_real("cdpr-settle", "rho", arg, &o->rho_kg_per_m);
        break;
    case 'n':
        rc = parse_segments(arg, o);
        break;
    default:
        return 1;
    }
    return (rc != 0) ? -1 : 0;
}

static int parse(int argc, char **argv, options_t *o)
{
    static const struct option longopts[] = {
        {"out", required_argument, NULL, 'o'},      {"length", required_argument, NULL, 'L'},
        {"span", required_argument, NULL, 's'},     {"height", required_argument, NULL, 'H'},
        {"ea", required_argument, NULL, 'e'},       {"rho", required_argument, NULL, 'r'},
        {"segments", required_argument, NULL, 'n'}, CDPR_APP_STD_OPTIONS_END};
    if (cdpr_app_parse("cdpr-settle", argc, argv, longopts, usage, take, o) != 0) {
        return -1;
    }
    if (optind < argc) {
        (void)cdpr_app_usage_error("cdpr-settle", "unexpected argument '%s'", argv[optind]);
        return -1;
    }
    return 0;
}

/* Build the robot: one cable from the held "cabin" point A = origin to the fixed point B. */
static int build(const options_t *o, int n, cdpr_diag_t *d)
{
    cdpr_robot_params_t p;
    cdpr_robot_params_default(&p);
    p.mode = CDPR_CABIN_PRESCRIBED; /* motion_fn NULL: the cabin (end A) is held */
    p.n_cables = 1;
    p.cables[0].cable.ea_N = o->ea_N;
    p.cables[0].cable.rho_kg_per_m = o->rho_kg_per_m;
    p.cables[0].exit_point_m = cdpr_v3(o->span_m, 0.0, o->height_m);
    p.cables[0].attach_body_m = cdpr_v3(0.0, 0.0, 0.0);
    p.cables[0].n_segments = n;
    p.cables[0].length_m = o->length_m;
    return cdpr_robot_init(&robot, &p, d);
}

/* Release the cable of n segments from the straight chord and settle it to rest. */
static cdpr_status_t settle_release(const options_t *o, int n, result_t *res)
{
    cdpr_diag_t d;
    if (build(o, n, &d) != CDPR_OK) {
        fprintf(stderr, "cdpr-settle: invalid parameter %s: %s\n", d.field,
                cdpr_status_str(d.status));
        return d.status;
    }
    cdpr_cabin_motion_t m;
    memset(&m, 0, sizeof m);
    m.q.w = 1.0;
    const cdpr_status_t ps = cdpr_robot_place_straight(&robot, &m, y);
    if (ps != CDPR_OK) {
        fprintf(stderr, "cdpr-settle: the two end points coincide\n");
        return ps;
    }
    const int dim = cdpr_robot_state_dim(&robot);
    cdpr_rkf45_params_t sp;
    cdpr_rkf45_params_default(&sp);
    sp.step.rtol = 1e-7;
    sp.step.atol = 1e-9;
    cdpr_rkf45_t solver;
    if (cdpr_rkf45_init(&solver, &sp, work, (int)(sizeof work / sizeof work[0]),
                        CDPR_ROBOT_STATE_MAX, dim, &d) != CDPR_OK) {
        fprintf(stderr, "cdpr-settle: solver: %s (%s)\n", cdpr_status_str(d.status), d.field);
        return d.status;
    }
    cdpr_settle_t cfg;
    cdpr_settle_default(&cfg);
    cfg.acc_tol_m_per_s2 = 1e-6;
    const double t0 = cdpr_clock_now_s();
    const cdpr_status_t st = cdpr_settle_robot(&robot, &solver, y, scratch, &cfg);
    res->wall_s = cdpr_clock_now_s() - t0;
    if (st != CDPR_OK) {
        fprintf(stderr, "cdpr-settle: N=%d did not settle: %s (max acceleration %.3g m/s^2)\n", n,
                cdpr_status_str(st), cfg.max_acc_m_per_s2);
        return st;
    }
    res->n = n;
    res->steps = cfg.steps;
    res->resets = cfg.resets;
    res->sim_time_s = cfg.time_s;
    return CDPR_OK;
}

/* The settled shape against the catenary (deviations, CSV rows) and the mid-span sag. */
static void compare_shape(const options_t *o, int n, const cdpr_catenary_cable_t *cat, double H,
                          double va, result_t *res, FILE *csv)
{
    /* Node positions (A = node 0 at the origin, B = node n), arclengths and deviations. */
    const cdpr_cable_t *c = &robot.cable[0];
    const cdpr_real_t *pos = y + robot.offset[0] + 1;
    static double xs[CDPR_MAX_SEGMENTS + 1];
    static double zs[CDPR_MAX_SEGMENTS + 1];
    double s = 0.0;
    double max_dev = 0.0;
    const double l = o->span_m;
    const double h = o->height_m;
    for (int i = 0; i <= n; ++i) {
        xs[i] = (i == 0) ? 0.0 : (i == n) ? l : pos[3 * (i - 1)];
        zs[i] = (i == 0) ? 0.0 : (i == n) ? h : pos[3 * (i - 1) + 2];
        if (i > 0) {
            s += (i == n) ? y[robot.offset[0]] : c->lu_m[i - 1];
        }
        double xc;
        double zc;
        cdpr_catenary_point(cat, H, va, s, &xc, &zc);
        const double dev = hypot(xs[i] - xc, zs[i] - zc);
        max_dev = (dev > max_dev) ? dev : max_dev;
        if (csv != NULL) {
            fprintf(csv, "%d,%d,%.9f,%.9f,%.9f,%.9f,%.9f\n", n, i, s, xs[i], zs[i], xc, zc);
        }
    }
    /* Mid-span sag: quadratic (Lagrange) interpolation of z(x) through the three nodes
     * nearest x = l/2, so the interpolation error (O(Delta^3)) stays below the model's own
     * O(Delta^2) discretisation error. */
    int im = 1;
    for (int i = 1; i < n; ++i) {
        if (fabs(xs[i] - 0.5 * l) < fabs(xs[im] - 0.5 * l)) {
            im = i;
        }
    }
    if (n < 2) {
        im = 0;
    }
    double sag = (double)NAN;
    if (n >= 2) {
        const int a = (im > 0) ? im - 1 : 0;
        const double x0 = xs[a], x1 = xs[a + 1], x2 = xs[a + 2];
        const double xm = 0.5 * l;
        const double zi = zs[a] * (xm - x1) * (xm - x2) / ((x0 - x1) * (x0 - x2)) +
                          zs[a + 1] * (xm - x0) * (xm - x2) / ((x1 - x0) * (x1 - x2)) +
                          zs[a + 2] * (xm - x0) * (xm - x1) / ((x2 - x0) * (x2 - x1));
        sag = 0.5 * h - zi;
    }
    res->sag_m = sag;
    res->max_dev_m = max_dev;
}

/* Support forces at both ends of the settled cable. */
static void support_forces(const options_t *o, int n, result_t *res)
{
    const cdpr_cable_t *c = &robot.cable[0];
    const cdpr_real_t *pos = y + robot.offset[0] + 1;
    const double l = o->span_m;
    const double h = o->height_m;
    /* Support forces. At A the support carries segment 0's pull plus node 0's own weight
     * (that lumped mass rests on the support); at B likewise with node n. */
    cdpr_robot_out_t out;
    cdpr_robot_outputs(&robot, 0.0, y, &out);
    const double g = robot.p.g_m_per_s2;
    const double wa = 0.5 * c->p.rho_kg_per_m * c->lu_m[0] * g;
    const double wb = 0.5 * c->p.rho_kg_per_m * y[robot.offset[0]] * g;
    const cdpr_vec3_t fa = out.force_on_cabin_N[0];
    res->t_a_N = sqrt(fa.x * fa.x + fa.y * fa.y + (fa.z - wa) * (fa.z - wa));
    /* Winch end: T_{n-1} along the last segment, plus node n's weight. */
    {
        const double *pn = (n > 1) ? &pos[3 * (n - 2)] : NULL;
        const double ax = (pn != NULL) ? pn[0] : 0.0;
        const double az = (pn != NULL) ? pn[2] : 0.0;
        const double dx = l - ax;
        const double dz = h - az;
        const double len = hypot(dx, dz);
        const double T = out.tension_winch_N[0];
        const double fx = -T * dx / len;
        const double fz = -T * dz / len - wb;
        res->t_b_N = hypot(fx, fz);
    }
}

static cdpr_status_t run(const options_t *o, int n, const cdpr_catenary_cable_t *cat, double H,
                         double va, result_t *res, FILE *csv)
{
    const cdpr_status_t st = settle_release(o, n, res);
    if (st != CDPR_OK) {
        return st;
    }
    compare_shape(o, n, cat, H, va, res, csv);
    support_forces(o, n, res);
    return CDPR_OK;
}

/* Close nodes.csv: every fprintf into it left a failure in the stream's error flag; a full
 * device shows at the flush or the close. CDPR_OK, or CDPR_E_IO after "FILE: write failed:
 * why" on stderr. */
static cdpr_status_t close_csv(FILE *csv, const char *path)
{
    errno = 0;
    int e = (fflush(csv) != 0 || ferror(csv) != 0) ? ((errno != 0) ? errno : EIO) : 0;
    if (fclose(csv) != 0 && e == 0) {
        e = (errno != 0) ? errno : EIO;
    }
    if (e != 0) {
        fprintf(stderr, "cdpr-settle: %s: write failed: %s\n", path, strerror(e));
        return CDPR_E_IO;
    }
    return CDPR_OK;
}

int main(int argc, char **argv)
{
    options_t o = {100.0, 80.0, 10.0, 2.0e4, 0.14, "out/settle", {8, 16, 32, 64}, 4};
    if (parse(argc, argv, &o) != 0) {
        return cdpr_app_exit_code(CDPR_E_INVALID_ARG);
    }
    if (cdpr_fs_mkdir_p(o.out_dir) != CDPR_OK) {
        fprintf(stderr, "cdpr-settle: cannot create '%s': %s\n", o.out_dir, strerror(errno));
        return cdpr_app_exit_code(CDPR_E_IO);
    }
    /* The closed form: Irvine's elastic catenary through the same two points. */
    const cdpr_catenary_cable_t cat = {o.rho_kg_per_m * 9.80665, o.ea_N};
    cdpr_catenary_solver_t cs;
    cdpr_catenary_solver_default(&cs);
    cdpr_real_t H = 0.0;
    cdpr_real_t va = 0.0;
    const cdpr_status_t cst =
        cdpr_catenary_solve(&cat, o.span_m, o.height_m, o.length_m, &cs, &H, &va);
    if (cst != CDPR_OK) {
        fprintf(stderr, "cdpr-settle: catenary did not converge (residual %.3g m)\n",
                cs.residual_m);
        return cdpr_app_exit_code(cst);
    }
    const double vb = va + cat.w_N_per_m * o.length_m;
    const double ta = hypot(H, va);
    const double tb = hypot(H, vb);
    /* Mid-span sag of the closed form: find s with x(s) = l/2 by bisection (x is monotonic). */
    double lo = 0.0;
    double hi = o.length_m;
    for (int k = 0; k < 200; ++k) {
        const double mid = 0.5 * (lo + hi);
        double x;
        double z;
        cdpr_catenary_point(&cat, H, va, mid, &x, &z);
        if (x < 0.5 * o.span_m) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    double xm;
    double zm;
    cdpr_catenary_point(&cat, H, va, 0.5 * (lo + hi), &xm, &zm);
    const double sag_cat = 0.5 * o.height_m - zm;

    char path[600];
    FILE *csv = (cdpr_fs_path(path, sizeof path, o.out_dir, "nodes.csv") == CDPR_OK)
                    ? cdpr_fs_fopen(path, "w", NULL, 0)
                    : NULL;
    if (csv == NULL) {
        fprintf(stderr, "cdpr-settle: cannot write '%s': %s\n", path, strerror(errno));
        return cdpr_app_exit_code(CDPR_E_IO);
    }
    fprintf(csv, "segments,node,s_m,x_m,z_m,x_catenary_m,z_catenary_m\n");

    printf("cdpr-settle: %.1f m cable, span %.1f m, height %.1f m, EA %.3g N, rho %.3g kg/m\n",
           o.length_m, o.span_m, o.height_m, o.ea_N, o.rho_kg_per_m);
    printf("released from the straight chord at rest; settled by kinetic damping\n\n");
    printf("%8s %12s %12s %12s %12s %9s %9s %8s\n", "segments", "sag [m]", "T_A [N]", "T_B [N]",
           "max dev [m]", "steps", "sim [s]", "wall [s]");
    printf("%8s %12.6f %12.6f %12.6f %12s\n", "Irvine", sag_cat, ta, tb, "-");
    cdpr_status_t rc = CDPR_OK;
    result_t prev;
    memset(&prev, 0, sizeof prev);
    for (int k = 0; k < o.n_runs; ++k) {
        result_t r;
        rc = run(&o, o.segments[k], &cat, H, va, &r, csv);
        if (rc != CDPR_OK) {
            break;
        }
        printf("%8d %12.6f %12.6f %12.6f %12.3e %9ld %9.1f %8.2f\n", r.n, r.sag_m, r.t_a_N, r.t_b_N,
               r.max_dev_m, r.steps, r.sim_time_s, r.wall_s);
        prev = r;
    }
    const cdpr_status_t cs_rc = close_csv(csv, path);
    rc = (rc == CDPR_OK) ? cs_rc : rc;
    if (rc == CDPR_OK && prev.n > 0) {
        printf("\nfinest run (N=%d) vs closed form: sag %+.2e m (%.4f %%), T_A %+.2e N "
               "(%.4f %%), T_B %+.2e N (%.4f %%)\n",
               prev.n, prev.sag_m - sag_cat, 100.0 * (prev.sag_m - sag_cat) / sag_cat,
               prev.t_a_N - ta, 100.0 * (prev.t_a_N - ta) / ta, prev.t_b_N - tb,
               100.0 * (prev.t_b_N - tb) / tb);
        printf("node positions: %s\n", path);
    }
    return cdpr_app_exit_code(rc);
}
