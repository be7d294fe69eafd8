#include "processes/tracker/feature_tracker.h"

#include <opencv2/video/tracking.hpp>

#include <cmath>
#include <stdexcept>
#include <utility>

namespace nadir {

FeatureTracker::FeatureTracker(const TrackerOptions& options)
    : options_(options),
      detector_(options),
      win_(options.klt_window_px, options.klt_window_px),
      max_level_(options.klt_pyramid_levels - 1),
      criteria_(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, options.klt_max_iterations, options.klt_epsilon_px) {
  options_.Check();
}

void FeatureTracker::reset() {
  features_.clear();
  prev_pyramid_.clear();
}

TrackStepResult FeatureTracker::process(const cv::Mat& image) {
  if (image.empty() || image.type() != CV_8UC1) {
    throw std::invalid_argument("FeatureTracker::process needs a non-empty 8-bit single-channel image");
  }
  TrackStepResult result;
  if (has_reference() && image.size() != image_size_) reset();
  image_size_ = image.size();

  // One pyramid per frame, with derivatives, copied (never referencing the
  // caller's buffer, which may be an LCM message that goes away).
  cv::buildOpticalFlowPyramid(image, curr_pyramid_, win_, max_level_, true, cv::BORDER_REFLECT_101,
                              cv::BORDER_CONSTANT, false);
  if (!has_reference()) {
    result.first_frame = true;
    features_.clear();
  } else {
    track(result);
  }
  replenish(image, result);
  std::swap(prev_pyramid_, curr_pyramid_);
  result.features_after = static_cast<int>(features_.size());
  return result;
}

void FeatureTracker::track(TrackStepResult& result) {
  result.attempted = static_cast<int>(features_.size());
  if (features_.empty()) return;
  prev_pts_.clear();
  for (const Feature& f : features_) prev_pts_.push_back(f.px);

  cv::calcOpticalFlowPyrLK(prev_pyramid_, curr_pyramid_, prev_pts_, curr_pts_, status_fwd_, err_, win_, max_level_,
                           criteria_, 0, options_.klt_min_eig_threshold);
  // Backward pass starts from the original positions: a consistent track
  // returns there in a few iterations.
  back_pts_ = prev_pts_;
  cv::calcOpticalFlowPyrLK(curr_pyramid_, prev_pyramid_, curr_pts_, back_pts_, status_bwd_, err_, win_, max_level_,
                           criteria_, cv::OPTFLOW_USE_INITIAL_FLOW, options_.klt_min_eig_threshold);

  const float w = static_cast<float>(image_size_.width), h = static_cast<float>(image_size_.height);
  const double fb_sq = options_.fb_threshold_px * options_.fb_threshold_px;
  std::vector<Feature> survivors;
  survivors.reserve(features_.size());
  for (size_t i = 0; i < features_.size(); ++i) {
    if (!status_fwd_[i] || !status_bwd_[i]) {
      ++result.klt_lost;
      continue;
    }
    const cv::Point2f& c = curr_pts_[i];
    if (!(c.x >= 0.0f && c.y >= 0.0f && c.x <= w - 1.0f && c.y <= h - 1.0f)) {
      ++result.out_of_image;
      continue;
    }
    const double dx = back_pts_[i].x - prev_pts_[i].x, dy = back_pts_[i].y - prev_pts_[i].y;
    if (!(dx * dx + dy * dy <= fb_sq)) {
      ++result.fb_rejected;
      continue;
    }
    Feature f = features_[i];
    f.age += 1;
    f.px = c;
    survivors.push_back(f);
    result.tracks.push_back({f.id, f.age, prev_pts_[i], c});
  }
  features_ = std::move(survivors);
}

void FeatureTracker::replenish(const cv::Mat& image, TrackStepResult& result) {
  const int cells = options_.grid_cols * options_.grid_rows;
  std::vector<int> per_cell(static_cast<size_t>(cells), 0);
  for (const Feature& f : features_) ++per_cell[static_cast<size_t>(detector_.cell_index(image.size(), f.px))];
  bool any = false;
  for (int n : per_cell) any = any || n < options_.replenish_below;
  if (!any) return;

  SpacingGrid spacing(image.size(), options_.min_distance_px);
  for (const Feature& f : features_) spacing.add(f.px);
  std::vector<cv::Point2f> fresh;
  for (int cell = 0; cell < cells; ++cell) {
    if (per_cell[static_cast<size_t>(cell)] >= options_.replenish_below) continue;
    ++result.cells_replenished;
    detector_.detect(image, cell, options_.features_per_cell - per_cell[static_cast<size_t>(cell)], spacing, fresh);
  }
  for (const cv::Point2f& p : fresh) features_.push_back({next_id_++, 1, p});
  result.replenished = static_cast<int>(fresh.size());
}

}  // namespace nadir
