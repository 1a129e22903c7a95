/* SPDX-License-Identifier: BSD-3-Clause */
/// @file design.h
/// The linear design of a scenario's feedback loop (docs/validation.md §8, "Feedback design"):
/// the loop linearised about a held pose, and its analysis -- the closed-loop eigenvalues,
/// the loop broken at the rate commands, one per cable (loop-at-a-time margins, α = min σ(I + L))
/// and the convergence of the learning over laps -- with the definitions of
/// scripts/feedback_design.py, on LAPACK.
///
/// Library cdpr_design (component `design`, target cdpr::design, pkg-config cdpr-design):
/// host only, links cdpr_host and LAPACK/BLAS (Debian liblapack-dev, BSD). Everything here
/// allocates (heap, at load) and frees what it allocated before returning; every failure is
/// a status, never an abort (NaN/Inf in a matrix: CDPR_E_NOT_FINITE, a LAPACK failure:
/// CDPR_E_NO_CONVERGENCE or CDPR_E_SINGULAR, no memory: CDPR_E_CAPACITY), with the reason
/// in the error's text.
#ifndef CDPR_DESIGN_DESIGN_H
#define CDPR_DESIGN_DESIGN_H

#include <stddef.h>
#include <stdio.h>

#include "cdpr/status.h"

#include "cdpr/host/correction.h"
#include "cdpr/host/plant.h"
#include "cdpr/host/scenario.h"
#include "cdpr/control/tracker.h"

/// Sizes of the model of a robot of m cables (cdpr_design_model_t.nu, .nz, .nm): m rate commands
/// (payout rates), 33 + 4 m states of the tracker (err_f1, err_f: 12 each; ten_f: one per
/// cable; integ: 6; mass_est_kg: 1; the feed-forward's l_ff_m and t_ff_N it keeps from one
/// period to the next: m each; the weight residual's two filter stages; the tension washout's
/// ten_w: one per cable), 12 + m linearised outputs
/// (p, θ, v, ω, the m lengths). The most a build holds:
#define CDPR_DESIGN_NU_MAX        CDPR_MAX_CABLES
#define CDPR_DESIGN_NZ(m)         (33 + (4 * (m))) ///< the tracker's states of m cables
#define CDPR_DESIGN_NZ_MAX        CDPR_DESIGN_NZ(CDPR_MAX_CABLES)
#define CDPR_DESIGN_NM_MAX        (12 + CDPR_MAX_CABLES)
#define CDPR_DESIGN_GOAL_GM_DB    6.0  ///< goal: loop-at-a-time gain margin [dB]
#define CDPR_DESIGN_GOAL_PM_DEG   30.0 ///< goal: loop-at-a-time phase margin [deg]
#define CDPR_DESIGN_GROWTH_TOL    1e-5 ///< growth [1/s] below which the loop counts as not growing
#define CDPR_DESIGN_MAX_HARMONICS 256  ///< lap harmonics reported (knots / 2 at most)

/// Why a call failed (or, for cdpr_design_check_scenario, the verdict's text).
typedef struct {
    char msg[1024];
} cdpr_design_error_t;

/// The operating point: the scenario with its trajectory replaced by a hold at the
/// trajectory's pose, the plant settled there and the controller built to hold it.
typedef struct {
    cdpr_scenario_t sc; ///< the scenario as held (trajectory: hold; no transfer), its robot
                        ///< the plant's (scaled by plant_scale)
    cdpr_rig_scale_t plant_scale; ///< the plant's variation from the scenario's robot
    cdpr_robot_params_t model;    ///< the controller's model (cdpr_host_controller_params)
    cdpr_plant_t plant;           ///< settled at the held pose
    cdpr_tracker_t tr0;           ///< the tracker holding it, before its first step
    cdpr_tracker_t tr;            ///< scratch copy (internal)
    double pose[6];               ///< the held pose (x, y, z, roll, pitch, yaw as the trajectory's)
    double lap_s;                 ///< lap of the scenario's own trajectory (0: not periodic)
    double learn_knots;           ///< the tracker's knots for that lap
} cdpr_design_point_t;

/// The linear model (row-major doubles, as cdpr-design's .bin files; see apps/cdpr-design).
typedef struct {
    int n;           ///< plant states
    int nu;          ///< rate commands: the robot's cables m (1..CDPR_DESIGN_NU_MAX)
    int nz;          ///< the tracker's states: 33 + 4 nu
    int nm;          ///< outputs: 12 + nu
    double period_s; ///< control period T
    double *A;       ///< n x n    ∂f/∂y of cdpr_robot_rhs
    double *B;       ///< n x nu   ∂f/∂u (payout rates)
    double *Kx;      ///< nu x n   u_k = Kx x_k + Kz z_k + Ku u_{k-1}
    double *Kz;      ///< nu x nz
    double *Zx;      ///< nz x n   z_{k+1} = Zx x_k + Zz z_k + Zu u_{k-1}
    double *Zz;      ///< nz x nz
    double *Ku;      ///< nu x nu
    double *Zu;      ///< nz x nu
    double *Cm;      ///< nm x n   outputs (pose, v, ω, lengths)
    double J[6 * CDPR_DESIGN_NU_MAX]; ///< nu x 6 straight-cable length Jacobian at the pose
    double lap_s;                     ///< lap of the trajectory (0: none)
    double learn_knots;
    double k_length_per_s;
    double learning_gain;
    double learning_lead_s;
    double learning_cutoff_hz;
} cdpr_design_model_t;

/// The analysis (feedback_design.py's design.json names in brackets).
typedef struct {
    double max_abs_eig;  ///< largest |λ| of the closed loop [closed_loop_max_abs_eig]
    double growth_per_s; ///< ln|λ|/T of it [closed_loop_max_growth_per_s]
    double growth_hz;    ///< |arg λ|/(2πT) [closed_loop_worst_hz]
    int grows;           ///< growth_per_s > CDPR_DESIGN_GROWTH_TOL
    int n_freq;          ///< points of the frequency grid
    double alpha;        ///< min σ_min(I + L) [sigma_min_I_plus_L]
    double alpha_hz;     ///< where [sigma_min_at_hz]
    int active;          ///< the loop has any gain (else no margins)
    int n_channels;      ///< rate commands analysed (the model's nu)
    double
        gm_db[CDPR_DESIGN_NU_MAX]; ///< per channel: gain margin [dB] (HUGE_VAL: no -180° crossing)
    double gm_hz[CDPR_DESIGN_NU_MAX];  ///< its frequency (NaN: none)
    double pm_deg[CDPR_DESIGN_NU_MAX]; ///< phase margin [deg] (HUGE_VAL: no crossover)
    double pm_hz[CDPR_DESIGN_NU_MAX];  ///< its frequency (NaN: none)
    double gm_min_db;                  ///< min_j |gm_db[j]| [loop_at_a_time_min.gm_db]
    double gm_min_hz;                  ///< the frequency of that channel's margin
    double pm_min_deg;                 ///< min_j pm_deg[j] [loop_at_a_time_min.pm_deg]
    double pm_min_hz;                  ///< the frequency of that channel's margin
    int learning;                      ///< the learning is analysed (periodic trajectory, γ > 0)
    double band_top_hz;                ///< top of the band Q >= 0.01 [learning.band_top_hz]
    int n_harmonics; ///< lap harmonics in that band (at most CDPR_DESIGN_MAX_HARMONICS)
    double harmonic_hz[CDPR_DESIGN_MAX_HARMONICS]; ///< k / T_lap
    double harmonic_q[CDPR_DESIGN_MAX_HARMONICS];  ///< Q there
    double rho[CDPR_DESIGN_MAX_HARMONICS];         ///< ρ(M) there
    double sigma_max[CDPR_DESIGN_MAX_HARMONICS];   ///< σ_max(M) there
    double max_rho;                     ///< max ρ at the harmonics [learning.max_rho_at_harmonics]
    int worst_harmonic;                 ///< the harmonic (1-based) where ρ is largest (0: none)
    int first_diverging;                ///< the first harmonic with ρ >= 1 (0: none)
    double g0_diag[CDPR_DESIGN_NU_MAX]; ///< Re diag G(1e-4 Hz) [learning.G_at_0_diag]
} cdpr_design_report_t;

/// Settle scenario `sc` at its trajectory's pose at `at_s` (NaN: where it stops, or its start
/// when it never stops) held, and build the controller holding it. The plant is the scenario's
/// robot scaled by `plant` (NULL: as written; the robustness set's variations); the
/// controller's model is the robot scaled by the scenario's own controller.model, whatever
/// `plant` says (a controller that does not know the variation). Allocates *pt (free with
/// cdpr_design_point_free). CDPR_OK, or the status of the plant / tracker init (err: why).
cdpr_status_t cdpr_design_point_new(const cdpr_scenario_t *sc, double at_s,
                                    const cdpr_rig_scale_t *plant, cdpr_design_point_t **pt,
                                    cdpr_design_error_t *err);
void cdpr_design_point_free(cdpr_design_point_t *pt);

/// The 12 + m outputs (p, rotation vector of q q0^-1, v, ω world, the m measured lengths) of
/// the measurement at plant state y (pt->plant.robot.dim values), q0 the held attitude.
void cdpr_design_outputs(cdpr_design_point_t *pt, const double *y, double o[CDPR_DESIGN_NM_MAX]);

/// Linearise the loop at `pt` (central differences of cdpr_robot_rhs and of one real
/// cdpr_tracker_step). Allocates the model's matrices (free with cdpr_design_model_free).
cdpr_status_t cdpr_design_linearise(cdpr_design_point_t *pt, cdpr_design_model_t *m,
                                    cdpr_design_error_t *err);
void cdpr_design_model_free(cdpr_design_model_t *m);

/// Zero-order hold: Phi (n x n) and Gam (n x nu), row-major, the blocks of
/// exp([[A, B], [0, 0]] T) (scaling and squaring, Padé degree 13). Caller's buffers.
cdpr_status_t cdpr_design_discretise(const cdpr_design_model_t *m, double *Phi, double *Gam,
                                     cdpr_design_error_t *err);

/// Analyse model `m` (feedback_design.py's closed_loop, Loop, channel_loops, margins and,
/// with learn != 0, learning_report at the lap harmonics).
cdpr_status_t cdpr_design_analyse(const cdpr_design_model_t *m, int learn, cdpr_design_report_t *r,
                                  cdpr_design_error_t *err);

/// The robustness set (docs/validation.md §8, "The robustness set"): the loop linearised with
/// the trajectory's pose held at its start, middle and end (poses that coincide, as a hold's,
/// count once), each with the plant as the scenario gives it and with one of EA, cabin mass
/// (with its inertia) and rope mass CDPR_DESIGN_ROBUST_STEP higher and lower; the
/// controller's model is the scenario's (controller.model) in every case.
#define CDPR_DESIGN_ROBUST_POSES    3
#define CDPR_DESIGN_ROBUST_VARIANTS 7
#define CDPR_DESIGN_ROBUST_CASES    (CDPR_DESIGN_ROBUST_POSES * CDPR_DESIGN_ROBUST_VARIANTS)
#define CDPR_DESIGN_ROBUST_STEP     0.2 ///< the plant variation: ±20 %

/// One case of the set and its analysis (a cdpr_design_report_t's summary).
typedef struct {
    char name[96];          ///< e.g. "middle (t = 5 s), cabin mass +20 %"
    double at_s;            ///< the held pose's trajectory time [s]
    cdpr_rig_scale_t plant; ///< the plant's factors
    double growth_per_s;    ///< as cdpr_design_report_t
    double growth_hz;
    int grows;
    int active;
    double gm_min_db;
    double pm_min_deg;
    double alpha;
    int learning;
    double max_rho;
    int worst_harmonic;
    int first_diverging;
} cdpr_design_case_t;

/// The set's results.
typedef struct {
    int n_cases;                                    ///< cases analysed
    cdpr_design_case_t c[CDPR_DESIGN_ROBUST_CASES]; ///< in order: pose, then variation
    int refused;     ///< first case that grows or whose learning diverges (-1: none)
    int n_grow;      ///< cases whose closed loop grows
    int n_diverge;   ///< cases whose learning has ρ >= 1 at a lap harmonic
    int worst_gm;    ///< case of the smallest gain margin (-1: no active loop)
    int worst_pm;    ///< case of the smallest phase margin
    int worst_alpha; ///< case of the smallest α
    int worst_rho;   ///< case of the largest ρ (-1: no learning)
} cdpr_design_robust_t;

/// The held poses' times of the set for `sc`: 0, the middle and the end of its trajectory
/// (where it stops; run.duration_s for one that never stops). Returns how many distinct
/// poses (1..3) went into t.
int cdpr_design_robust_times(const cdpr_scenario_t *sc, double t[CDPR_DESIGN_ROBUST_POSES]);

/// Linearise and analyse the cases of the set in order (pose, then variation): all of them, or
/// with `stop_at_refusal` != 0 up to the first that grows or whose learning diverges (out->
/// n_cases then counts the cases analysed). CDPR_OK, or the status of the first case that
/// could not be built or analysed (err names it).
cdpr_status_t cdpr_design_robust(const cdpr_scenario_t *sc, int stop_at_refusal,
                                 cdpr_design_robust_t *out, cdpr_design_error_t *err);

/// The check at load: when sc's controller has feedback or learning (cdpr_tracker_has_feedback),
/// run the robustness set (cdpr_design_robust), stopping at the first refused case. Returns
/// CDPR_OK when accepted (*warn set when a case is below the goal margins: err->msg names the
/// cases and the margins), CDPR_E_OUT_OF_RANGE when refused (a case's closed loop grows, or
/// its ρ(M) >= 1 at a lap harmonic; err->msg names the keys, the case and the margin, prefixed
/// by `path`), another status when the check itself failed. No feedback: CDPR_OK at once
/// (*checked 0). `robust` (may be NULL) receives the set's results (the cases analysed).
cdpr_status_t cdpr_design_check_scenario(const cdpr_scenario_t *sc, const char *path, int *checked,
                                         int *warn, cdpr_design_robust_t *robust,
                                         cdpr_design_error_t *err);

/// Offline pre-compensation of a known trajectory (issue 22 item 1; docs/validation.md §8,
/// "Pre-compensation"; cdpr-precomp). The correction c_j(t) of the tracker's step 4c, a cubic
/// B-spline with knot spacing h from t = 0 (cdpr_tracker_correction_t), iterated against the
/// nonlinear model of the scenario (cdpr_sim_run: the plant as written, the controller with
/// its own model and gains) so the cabin follows the trajectory:
///  1. the lift: the closed loop linearised with the trajectory's pose held at `poses` times
///     evenly along its motion (cdpr_design_point_new, cdpr_design_linearise, zero-order
///     hold), each driven by one basis function on each cable in turn (the input the tracker
///     adds, (c(t + Δ) - c(t)) / Δ + k_L c(t)); the pose response of basis i is the response at
///     the pose nearest its centre, delayed to its start (the held loop is time-invariant),
///     which gives the matrix G from the m n coefficients to the pose error over the run (6
///     rows per period: position [m] and attitude [rad] times rot_weight_m);
///  2. run 0: the model without correction, its pose error e_0 over the run;
///  3. each later run: the regularised Gauss-Newton step
///       Δa = (G^T G + λ' I)^-1 G^T e_k,  λ' = lambda · tr(G^T G) / (m n),
///     a_{k+1} = a_k + α Δa, the model run with it; kept when its pose error's sum of squares
///     is below the best's and its smallest cable-end tension (either end, every period) is at
///     least floor_N, else α halved (at most twice) and run again; the iteration stops at
///     max_runs model runs or when no step is kept, with the best iterate.
/// Robust (robust_mass, robust_ea > 0): the cost is the sum over V models, the plant as written
/// and with its cabin mass (and inertia) or every rope's EA times 1 ± x, the controller's model
/// nominal in each (a controller that does not know the variation); each model v has its own
/// lift G_v (step 1 with the plant varied) and error e_v, the step becomes
///       Δa = (Σ_v G_v^T G_v + λ' I)^-1 Σ_v G_v^T e_v,  λ' = lambda · tr(Σ_v G_v^T G_v) / (m n),
/// and a step is kept when the summed cost falls and every model keeps floor_N. A correction
/// that cancels the nominal plant's sway exactly excites a plant of another mass; the sum
/// trades a little nominal error for much less on the others (docs/validation.md §8).
/// Deterministic (same binary, scenario and options: the same coefficients). Work per model:
/// `poses` linearisations (a design check's case each), `poses` m closed-loop simulations of
/// the run's periods at the linearised size, up to max_runs nonlinear runs of the scenario; one
/// Cholesky factorisation of an m n square matrix. Memory: the G_v, 6 K m n V doubles (K
/// periods); refused above CDPR_PRECOMP_MAX_LIFT_BYTES.
typedef struct {
    int poses;           ///< linearisation poses along the motion (>= 1; default 5)
    double spacing_s;    ///< knot spacing h [s] (a whole number of control periods; default 0.3)
    int max_runs;        ///< most model runs, the first without correction (>= 1; default 8)
    double floor_N;      ///< smallest cable-end tension an iterate may reach [N] (default 20)
    double lambda;       ///< regularisation, relative to G^T G's mean diagonal (> 0; 1e-3)
    double rot_weight_m; ///< weight of the attitude error in the pose error [m/rad] (default 1)
    double robust_mass;  ///< cost over the plant's cabin mass x (1 ± this) too (0: off; <= 0.3)
    double robust_ea;    ///< cost over the plant's EA x (1 ± this) too (0: off; <= 0.3)
    FILE *log;           ///< a line per model run (NULL: none)
} cdpr_precomp_opts_t;

#define CDPR_PRECOMP_MAX_MODELS     5   ///< the plant as written and four variations
#define CDPR_PRECOMP_MAX_VARIATION  0.3 ///< largest robust_mass / robust_ea
#define CDPR_PRECOMP_MAX_LIFT_BYTES (768.0 * 1024.0 * 1024.0) ///< largest G [bytes]

/// The defaults above.
void cdpr_precomp_opts_default(cdpr_precomp_opts_t *o);

/// Iterate the pre-compensation of scenario `sc` (its own controller.precompensation is not
/// used) into `hc` (cdpr_correction_init for sc: hashes, period; coefficients; report). CDPR_OK,
/// or: CDPR_E_OUT_OF_RANGE (options; a trajectory that does not move; the lift too large),
/// the first run's status when the scenario cannot run (err says why), a linearisation's or
/// LAPACK's status.
cdpr_status_t cdpr_design_precompensate(const cdpr_scenario_t *sc, const cdpr_precomp_opts_t *o,
                                        cdpr_host_correction_t *hc, cdpr_design_error_t *err);

#endif /* CDPR_DESIGN_DESIGN_H */
