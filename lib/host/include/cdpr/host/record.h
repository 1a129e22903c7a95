/* SPDX-License-Identifier: BSD-3-Clause */
/// @file record.h
/// Recorder of a tracking run: timeseries.csv (provenance comment lines, header and one row per
/// output period, columns in docs/scenarios.md, %.17g) and the error, tension and node
/// statistics of the summary (summary.h). Used by the batch runner (sim.h) and by the
/// controller node (tracker_node.h), so a run over LCM writes the same files.
///
/// Rows: one when the period's time reaches the next output instant (a multiple of
/// 1 / run.output_rate_hz: period k gets a row when k >= the next multiple of `every`, so a
/// recorder that does not see every period -- a tracker over LCM that skips superseded states --
/// still writes run.output_rate_hz rows per second; when every period is seen this is
/// k % every == 0), and the last. Rows are whole in the file even on a full device or a signal
/// (csv.h); after the first write error no further row is written and the error (errno) is kept
/// for the caller's message (cdpr_record_io_error).
///
/// Host library; no allocation, no printing.
#ifndef CDPR_HOST_RECORD_H
#define CDPR_HOST_RECORD_H

#include "cdpr/status.h"
#include "cdpr/host/csv.h"
#include "cdpr/host/scenario.h"
#include "cdpr/host/summary.h"
#include "cdpr/control/tracker.h"
#include "cdpr/control/trajectory.h"

/// One period's values for the recorder (inputs; arrays of the robot's cable count).
typedef struct {
    double t_s;                      ///< time t_k [s]
    const cdpr_traj_sample_t *des;   ///< desired state at t_k
    const cdpr_tracker_meas_t *meas; ///< measured cabin motion and lengths at t_k
    const double *tension_cabin_N;   ///< cabin-end tensions [N]
    const double *tension_winch_N;   ///< winch-end tensions [N]
    const double *l_ff_m;            ///< feed-forward lengths [m]
    const double *payout_m_per_s;    ///< payout rates [m/s]
    const int *segments;             ///< active segments per cable
} cdpr_record_row_t;

/// Recorder: timeseries.csv (every output period and the last) and the summary's statistics.
/// Fields are internal.
typedef struct {
    cdpr_csv_t csv;
    int csv_open;
    int n_cables;
    long every;
    double duration_s;
    double sum2_pos, sum2_rot, sum2_pos_late, sum2_pos_after;
    long n, n_late, n_after;
    cdpr_traj_t traj; ///< for the laps (cdpr_traj_lap)
    long lap;         ///< lap of the last period (-1: none)
    double lap_sum2_pos, lap_sum2_rot, lap_max;
    long lap_n;
    double transfer_s; ///< controller.transfer_s: rms_error_after_transfer_m counts t >= it
    cdpr_summary_t *sum;
    long prev_k; ///< period of the last recorded row (-1: none yet)
    int prev_segments[CDPR_MAX_CABLES];
    double prev_payout[CDPR_MAX_CABLES]; ///< payout rates of period prev_k [m/s]
    double du_limit[CDPR_MAX_CABLES];    ///< a_max T of each winch: its largest rate change [m/s]
    double u_limit[CDPR_MAX_CABLES];     ///< u_max of each winch [m/s]
    unsigned long seg_insertions, seg_removals; ///< node events seen in the segment counts
    long missed;         ///< periods between the first and the last recorded that were not recorded
    long next_row_k;     ///< first period of the next CSV row (the next output instant)
    long last_row_k;     ///< period of the last CSV row (-1: none)
    char csv_path[1100]; ///< out_dir/timeseries.csv ("" without outputs)
} cdpr_record_t;

/// Start recording into `sum` (zeroed by the caller) over the scenario's run.duration_s
/// (rows every run.output_rate_hz) and, when out_dir is not NULL, into out_dir/timeseries.csv
/// (the directory is created). Fills sum->prov (cdpr_summary_provenance_init: the scenario file
/// sc->path is hashed now; `pp` the plant's parameters, NULL when not known) and writes it as
/// the CSV's comment lines. Returns CDPR_OK, or CDPR_E_IO with `err` naming the directory or
/// file.
cdpr_status_t cdpr_record_open(cdpr_record_t *rec, const cdpr_scenario_t *sc,
                               const cdpr_plant_params_t *pp, const char *out_dir, int n_cables,
                               cdpr_summary_t *sum, cdpr_scenario_error_t *err);

/// Record period k (t_k = row->t_s); `last` forces a CSV row. Returns CDPR_OK, or CDPR_E_IO
/// when the CSV has failed (now or earlier; the statistics are still kept).
cdpr_status_t cdpr_record_period(cdpr_record_t *rec, long k, int last,
                                 const cdpr_record_row_t *row);

/// Node events as the recorded rows show them: per cable, a rise of the segment count from one
/// recorded period to the next is that many insertions, a fall that many removals (a node
/// event changes the count by one, and within one period a cable's winch moves one way, so
/// this equals the plant's own counts when every period is recorded -- lockstep, the batch
/// run). `missed` (may be NULL): periods not recorded between the first and the last recorded
/// one; the events in such a gap count by their net change. Events before the first recorded
/// period are not seen.
void cdpr_record_node_events(const cdpr_record_t *rec, unsigned long *insertions,
                             unsigned long *removals, long *missed);

/// The tracker's tension-awareness counts (slack demands per cable, the first one) into `sum`.
void cdpr_record_tracker_counts(const cdpr_tracker_t *tr, cdpr_summary_t *sum);

/// Finish the statistics (RMS values) and close the CSV (its buffered whole rows written).
/// Returns CDPR_OK, or CDPR_E_IO when a write or the close failed (then and later
/// cdpr_record_io_error describes it). Safe to call twice.
cdpr_status_t cdpr_record_close(cdpr_record_t *rec);

/// errno of the CSV's first failure (0: none).
int cdpr_record_errno(const cdpr_record_t *rec);

/// The CSV's failure as "DIR/timeseries.csv: write failed: REASON" (strerror of the kept errno)
/// into err->msg.
void cdpr_record_io_error(const cdpr_record_t *rec, cdpr_scenario_error_t *err);

#endif /* CDPR_HOST_RECORD_H */
