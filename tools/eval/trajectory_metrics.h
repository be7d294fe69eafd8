#pragma once
// Estimate vs truth, aligned by sensor time: the paper's Table 1 figures
// (distance flown, final error, error as % of distance), drift over time
// (Fig. 7a), velocity errors (Fig. 7b) and yaw error.

#include <array>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "tools/eval/coast_metrics.h"
#include "tools/eval/eval_data.h"
#include "tools/eval/map_fix_metrics.h"
#include "tools/eval/pair_metrics.h"

namespace nadir {

struct EvalSample {
  double t_s = 0;                      // since the first pose
  std::array<double, 3> estimate{};    // NED relative to the first pose
  std::array<double, 3> truth{};       // NED relative to truth at the first pose
  double distance_m = 0;               // flown so far (truth path length)
  double error_h_m = 0;                // horizontal position error
  double error_v_m = 0;                // vertical (down) position error, signed
  std::array<double, 3> velocity_error{};
  double yaw_error_deg = 0;
  int32_t flags = 0;
  double sigma_h_m = 0;                // reported: sqrt of the horizontal position variances
  double sigma_n_m = 0, sigma_e_m = 0;  // reported, per axis
  double sigma_d_m = 0;                // reported: sqrt of the down variance
  double cov_ne_m2 = 0;                // reported north-east covariance
  double sigma_yaw_deg = 0;            // reported: sqrt of the yaw variance
  double nees_h = -1;                  // horizontal NEES (chi-square, 2 dof); < 0: undefined
  double nees_yaw = -1;                // yaw NEES (1 dof)
  double protection_level_m = -1;      // reported horizontal protection level; < 0: unavailable
};

struct EvalMetrics {
  double duration_s = 0;
  double distance_m = 0;
  double final_error_h_m = 0;
  double final_error_v_m = 0;
  double final_error_3d_m = 0;
  double error_pct_h = 0;     // final horizontal error / distance * 100
  double error_pct_v = 0;
  double error_pct_3d = 0;    // the paper's "accuracy" column
  double max_error_h_m = 0;
  double p95_error_h_m = 0;    // 95th percentile of the horizontal error over every aligned pose
  MapFixMetrics map_fixes;     // the map matcher's fixes; fixes == 0 and applied == 0: none in the log
  double rms_error_h_m = 0;    // over every aligned pose: the whole flight, not only its end
  double rms_error_3d_m = 0;
  double rms_error_pct_3d = 0; // rms_error_3d_m as % of the distance flown
  double rms_velocity_error_h = 0;
  double max_velocity_error_h = 0;
  double rms_yaw_error_deg = 0;  // fused POSE yaw vs GROUND_TRUTH yaw at each pose's time
  // An imported flight: its truth is the flight's record (GPS, the photos'
  // recorded attitude, which is also the INS the estimator gets).
  bool imported = false;
  int64_t poses = 0;
  int64_t poses_flagged = 0;
  std::vector<CoastEpisode> coasts;  // POSE flagged COASTING (coast_metrics.h)
  double coast_s = 0;                // their durations summed
  int64_t images = 0;          // frames: images the tracker answered (tools/eval/pipeline_records.h)
  int64_t triggers = 0;
  int64_t frames_dropped = 0;  // triggers without such a frame
  // CAMERA_IMAGE, TRACKS and VO_DELTA records that are not the pipeline's: a
  // second publisher's, undecodable ones, images the tracker dropped.
  int64_t records_not_pipeline = 0;
  int64_t capture_corrupt_records = 0;
  bool capture_truncated = false;
  int64_t capture_holes = 0;         // stretches a regular channel has no messages for
  double capture_hole_seconds = 0.0; // the longest
  // Consistency of the reported covariance (tools/eval/consistency.h).
  int64_t nees_samples = 0;
  double nees_h_mean = 0, nees_h_within_95_pct = 0;      // consistent: ~2 and ~95
  double nees_yaw_mean = 0, nees_yaw_within_95_pct = 0;  // consistent: ~1 and ~95
  // Horizontal protection level: share of poses whose true error exceeded it
  // (its stated probability is 99 %: ~1 % expected), and poses without one.
  double pl_exceeded_pct = 0;
  int64_t pl_samples = 0, pl_unavailable = 0;
  int64_t capture_missing = 0;       // published (per the publishers' STATUS) but not in the capture
  int64_t capture_unaccounted = 0;   // in the capture but counted by no publisher (a second publisher?)
  std::map<std::string, int64_t> udp_rx_drops;  // per process: datagrams its kernel dropped
  // Per process, from its last STATUS: received, published, dropped, errors, malformed.
  std::map<std::string, std::array<int64_t, 5>> process_counts;
  int64_t tracks = 0;
  int64_t vo_deltas = 0;
  int64_t vo_deltas_flagged = 0;
  // Frame pairs (tools/eval/pair_metrics.h): VO_DELTA against the truth step.
  int64_t pairs = 0, pairs_solved = 0;
  double pairs_solved_pct = 0;
  int64_t pairs_not_solved_flagged = 0;     // a bit of the reject mask: not solved
  int64_t pairs_heading_contradicts = 0;    // of those, QUALITY_HEADING_CONTRADICTS
  std::string pairs_not_solved_why;         // per bit, pair_metrics.h format_not_solved
  double pair_error_pct_median = 0, pair_error_pct_p90 = 0;  // horizontal, % of the step, solved pairs
  double pair_step_median_m = 0;
  // With the estimator's camera (its CONFIG): pairs whose ground footprints do
  // not overlap, and the share solved of the pairs that do (-1: no camera).
  int64_t pairs_apart = 0;
  double pairs_overlapping_solved_pct = -1;
  std::string footprint_problem;  // why there are no footprints, when there are none
  // Latency is measured only in a live capture: a lockstep replay's and an
  // imported flight's log times are the input's, not when anything was computed.
  bool latency_measured = true;
  double latency_p50_ms = 0;   // logger receive time - sensor time of POSE
  double latency_p99_ms = 0;
  double latency_max_ms = 0;   // the worst frame
  double after_image_latency_p50_ms = 0;  // POSE logged - CAMERA_IMAGE logged, per frame
  double after_image_latency_p99_ms = 0;
  double after_image_latency_max_ms = 0;
};

struct EvalResult {
  EvalMetrics metrics;
  PairMetrics pairs;   // each VO_DELTA against the truth step
  std::vector<EvalSample> samples;
  double reference_lat_deg = 0;  // geographic reference of the first pose
  double reference_lon_deg = 0;
  bool has_reference = false;
};

// Throws std::runtime_error when poses and truth do not overlap in time.
EvalResult evaluate(const EvalData& data);
std::string metrics_json(const EvalMetrics& m);

}  // namespace nadir
