#pragma once
// Frame-pair figures: each VO_DELTA against the truth motion between its two
// frames. What a photo survey is judged on (share of consecutive pairs
// solved, per-pair horizontal error as % of the step), independent of how the
// pairs are chained into a trajectory.

#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "common/camera_model.h"
#include "common/vo_quality.h"
#include "nadir/ground_truth_t.hpp"
#include "nadir/vo_delta_t.hpp"

namespace nadir {

struct PairSample {
  int64_t utime = 0;
  int64_t prev_utime = 0;
  double step_m = 0;          // truth horizontal step
  double true_x = 0, true_y = 0;  // truth step in the level frame of the previous frame (x along its heading)
  double dx = 0, dy = 0;          // estimated step, same frame
  double true_dyaw_deg = 0;   // truth heading change
  double dyaw_deg = 0;        // estimated
  double error_h_m = 0;       // |estimated - truth| horizontal, in the level frame of the previous frame
  double error_pct = 0;       // error_h_m / step_m * 100
  int32_t quality = 0;
  int32_t inliers = 0;
  bool solved = false;
  // Share of the previous frame's ground footprint that this frame's covers
  // (truth poses, level ground at the truth height below the previous frame),
  // percent; NaN without a camera.
  double overlap_pct = std::nan("");
};

struct PairMetrics {
  int64_t pairs = 0;           // VO_DELTA with truth at both frames
  int64_t solved = 0;          // none of the unusable quality bits
  double solved_pct = 0;
  // Pairs not solved because of a quality bit of the reject mask, per bit
  // (a pair may count under several), and the mask used.
  int32_t reject_quality_mask = 0;
  std::array<int64_t, kVoQualityBits> not_solved_by_bit{};
  int64_t measured = 0;        // solved pairs with a step long enough to take a percentage of
  double error_pct_median = 0;  // over the measured pairs
  double error_pct_p90 = 0;
  double step_median_m = 0;
  // With a camera: pairs whose footprints share no ground (no tracker can
  // match them), and the share solved of the others.
  bool footprints = false;
  int64_t apart = 0;
  int64_t overlapping_solved = 0;
  double overlapping_solved_pct = 0;
  std::vector<PairSample> samples;
};

// VO_DELTA quality bits that leave a pair without a usable motion (too few
// features, no altimeter, not converged, no attitude) or with one that
// contradicts the INS heading change: yaw fusion's default reject mask
// (yaw_fusion.reject_quality_mask). HIGH_RESIDUAL, FRAME_GAP, STALE_ALTIMETER
// and DEPTH_LAYERS pairs count as solved (flagged).
constexpr int32_t kUnsolvedQualityMask = 1 | 2 | 8 | 16 | 256;

// Footprints overlapping by less than this (percent) share no ground.
constexpr double kApartOverlapPct = 0.1;

// `truth` sorted by utime. A pair with a bit of `reject_quality_mask` (the
// one yaw fusion ran with) is not solved. Steps under `min_step_m` are counted
// but not measured as a percentage. `camera` (may be null) gives each pair its
// footprint overlap.
PairMetrics evaluate_pairs(const std::vector<vo_delta_t>& deltas, const std::vector<ground_truth_t>& truth,
                           const CameraModel* camera, int32_t reject_quality_mask = kUnsolvedQualityMask,
                           double min_step_m = 0.5);

// "3 heading_contradicts, 1 too_few_features": the not-solved pairs per bit, most first.
std::string format_not_solved(const PairMetrics& metrics);

// One row per pair.
void write_pairs_csv(const PairMetrics& metrics, const std::string& path);

}  // namespace nadir
