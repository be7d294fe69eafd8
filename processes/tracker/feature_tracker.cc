#include "processes/tracker/feature_tracker.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <utility>

namespace nadir {

namespace {

const TrackerOptions& checked(const TrackerOptions& options) {
  options.Check();
  return options;
}

LkOptions klt_options(const TrackerOptions& options, int window_px) {
  LkOptions o;
  o.window_px = window_px;
  o.max_iterations = options.klt_max_iterations;
  o.epsilon_px = options.klt_epsilon_px;
  o.min_eig_threshold = options.klt_min_eig_threshold;
  return o;
}

}  // namespace

FeatureTracker::FeatureTracker(const TrackerOptions& options, const CameraModel* lens)
    : options_(checked(options)),
      detector_(options),
      forward_klt_(klt_options(options, options.klt_window_px)),
      backward_klt_(klt_options(options, options.fb_window_px)),
      pyramid_border_(LucasKanade::border_for(std::max(options.klt_window_px, options.fb_window_px))),
      max_level_(options.klt_pyramid_levels - 1),
      fb_max_level_(options.fb_pyramid_levels - 1) {
  if (lens) {
    lens->Check("FeatureTracker lens");
    has_lens_ = true;
    lens_ = *lens;
  }
}

void FeatureTracker::reset() {
  have_last_motion_ = false;
  features_.clear();
  prev_pyramid_.clear();
}

TrackStepResult FeatureTracker::process(const cv::Mat& image) {
  TrackStepResult result = track_frame(image);
  prepare_next(image, result);
  return result;
}

TrackStepResult FeatureTracker::track_frame(const cv::Mat& image) {
  if (image.empty() || image.type() != CV_8UC1) {
    throw std::invalid_argument("FeatureTracker::process needs a non-empty 8-bit single-channel image");
  }
  TrackStepResult result;
  if (has_reference() && image.size() != image_size_) reset();
  image_size_ = image.size();

  // One pyramid per frame, copied as float (never referencing the caller's
  // buffer, which may be an LCM message that goes away).
  curr_pyramid_.build(image, max_level_ + 1, pyramid_border_);
  if (!has_reference()) {
    result.first_frame = true;
    features_.clear();
  } else {
    track(result);
  }
  return result;
}

void FeatureTracker::prepare_next(const cv::Mat& image, TrackStepResult& result) {
  replenish(image, result);
  prev_pyramid_.swap(curr_pyramid_);
  result.features_after = static_cast<int>(features_.size());
}

int FeatureTracker::usable_levels(const cv::Point2f& p) const {
  // A KLT window that runs off the image reads the pyramid's reflected
  // border, whose content moves against the scene; near the edge such a point
  // can lock onto its mirror image consistently in both directions, so the
  // forward-backward check does not catch it. Each level is used only where
  // its window (half_win pixels there, half_win * 2^L at full resolution)
  // stays inside the image.
  const float d = std::min(std::min(p.x, p.y), std::min(image_size_.width - 1 - p.x, image_size_.height - 1 - p.y));
  const float half_win = static_cast<float>(options_.klt_window_px / 2);
  int level = 0;
  while (level < max_level_ && d >= half_win * static_cast<float>(2 << level)) ++level;
  return level;
}

bool FeatureTracker::fit_motion(double fb_sq, cv::Matx23d* motion) const {
  // Least-squares affine prev -> curr over the tracks tracked so far that
  // pass the forward-backward check, refitted once without the points it
  // explains worst (moving objects, parallax). Plain sums: deterministic.
  std::vector<size_t> use;
  for (size_t i = 0; i < status_fwd_.size(); ++i)
    if (!failed(i, fb_sq)) use.push_back(i);
  cv::Matx23d fit;
  for (int round = 0; round < 2; ++round) {
    if (use.size() < 6) return false;
    cv::Matx33d ata = cv::Matx33d::zeros();
    cv::Vec3d atx(0, 0, 0), aty(0, 0, 0);
    for (size_t i : use) {
      const cv::Vec3d a(prev_pts_[i].x, prev_pts_[i].y, 1.0);
      ata += a * a.t();
      atx += a * static_cast<double>(curr_pts_[i].x);
      aty += a * static_cast<double>(curr_pts_[i].y);
    }
    cv::Vec3d row_x, row_y;
    if (!cv::solve(ata, atx, row_x, cv::DECOMP_CHOLESKY) || !cv::solve(ata, aty, row_y, cv::DECOMP_CHOLESKY)) return false;
    fit = cv::Matx23d(row_x[0], row_x[1], row_x[2], row_y[0], row_y[1], row_y[2]);
    if (round == 1) break;
    std::vector<size_t> kept;
    for (size_t i : use) {
      const cv::Point2f& p = prev_pts_[i];
      const double ex = fit(0, 0) * p.x + fit(0, 1) * p.y + fit(0, 2) - curr_pts_[i].x;
      const double ey = fit(1, 0) * p.x + fit(1, 1) * p.y + fit(1, 2) - curr_pts_[i].y;
      if (ex * ex + ey * ey <= 9.0) kept.push_back(i);  // within 3 px
    }
    use = std::move(kept);
  }
  *motion = fit;
  return true;
}

void FeatureTracker::window_warps(const std::vector<cv::Point2f>& predicted, const cv::Matx23d& motion) {
  // offsets in curr = J_lens(curr) * M * J_lens(prev)^-1 * offsets in prev,
  // M the motion's linear part in normalized coordinates (K^-1 L K).
  const cv::Matx22d linear(motion(0, 0), motion(0, 1), motion(1, 0), motion(1, 1));
  cv::Matx22d normalized_motion = linear;
  std::vector<cv::Point2d> curr_norm;
  if (has_lens_) {
    const cv::Matx22d k(lens_.fx, 0, 0, lens_.fy), k_inv(1.0 / lens_.fx, 0, 0, 1.0 / lens_.fy);
    normalized_motion = k_inv * linear * k;
    curr_norm = lens_.undistort(predicted);
  }
  for (size_t g = 0; g < group_index_.size(); ++g) {
    const size_t i = group_index_[g];
    if (options_.klt_local_warp && features_[i].has_local_warp) {
      has_warp_[i] = true;
      warp_[i] = features_[i].local_warp;
      continue;
    }
    const cv::Matx22d a = has_lens_ ? lens_.pixel_jacobian(curr_norm[g]) * normalized_motion * prev_lens_inverse_[i]
                                    : normalized_motion;
    has_warp_[i] = LucasKanade::warp_within(a, 0.5 * LucasKanade::kMaxWarpDeviation);
    if (has_warp_[i]) warp_[i] = cv::Matx22f(a);
  }
}

void FeatureTracker::track_group(int max_level, const cv::Matx23d* motion) {
  const int back_level = std::min(max_level, fb_max_level_);
  const cv::Matx23d& m = motion ? *motion : cv::Matx23d(1, 0, 0, 0, 1, 0);
  std::vector<cv::Point2f> predicted;
  predicted.reserve(group_index_.size());
  for (size_t i : group_index_) {
    const cv::Point2f p = features_[i].px;
    predicted.emplace_back(static_cast<float>(m(0, 0) * p.x + m(0, 1) * p.y + m(0, 2)),
                           static_cast<float>(m(1, 0) * p.x + m(1, 1) * p.y + m(1, 2)));
  }
  if (options_.klt_window_warp) window_warps(predicted, m);
  for (size_t g = 0; g < group_index_.size(); ++g) {
    const size_t i = group_index_[g];
    const cv::Point2f p = features_[i].px;
    cv::Point2f c = predicted[g];
    float error = 0.f;
    const bool warped = options_.klt_window_warp && has_warp_[i];
    const bool forward =
        forward_klt_.track(prev_pyramid_, curr_pyramid_, p, &c, max_level, &error, warped ? &warp_[i] : nullptr);
    // Backward from the original position: a consistent track returns there
    // in a few iterations. A track lost forward is not followed back. The
    // backward pass only gates (forward-backward error against a 1 px
    // threshold), so its template is not warped: the deformation it leaves
    // is hundredths of a pixel, and the resampling would double the warp's cost.
    cv::Point2f back = p;
    const bool backward = forward && backward_klt_.track(curr_pyramid_, prev_pyramid_, c, &back, back_level, nullptr);
    prev_pts_[i] = p;
    curr_pts_[i] = c;
    back_pts_[i] = back;
    status_fwd_[i] = forward;
    status_bwd_[i] = backward;
    patch_error_[i] = error;
    level_used_[i] = max_level;
  }
}

bool FeatureTracker::failed(size_t i, double fb_sq) const {
  if (!status_fwd_[i] || !status_bwd_[i]) return true;
  const double dx = back_pts_[i].x - prev_pts_[i].x, dy = back_pts_[i].y - prev_pts_[i].y;
  return !(dx * dx + dy * dy <= fb_sq);
}

void FeatureTracker::track(TrackStepResult& result) {
  const size_t n = features_.size();
  result.attempted = static_cast<int>(n);
  if (n == 0) return;
  prev_pts_.resize(n);
  curr_pts_.resize(n);
  back_pts_.resize(n);
  status_fwd_.assign(n, 0);
  status_bwd_.assign(n, 0);
  patch_error_.assign(n, 0.0f);
  level_used_.assign(n, -1);
  usable_level_.resize(n);
  if (options_.klt_window_warp) {
    warp_.resize(n);
    has_warp_.assign(n, 0);
    prev_lens_inverse_.resize(n);
    if (has_lens_) {
      std::vector<cv::Point2f> prev_px(n);
      for (size_t i = 0; i < n; ++i) prev_px[i] = features_[i].px;
      const std::vector<cv::Point2d> prev_norm = lens_.undistort(prev_px);
      for (size_t i = 0; i < n; ++i) prev_lens_inverse_[i] = lens_.pixel_jacobian(prev_norm[i]).inv();
    }
  }
  size_t full_reach = 0;
  for (size_t i = 0; i < n; ++i) {
    usable_level_[i] = usable_levels(features_[i].px);
    if (usable_level_[i] == max_level_) ++full_reach;
  }

  const double fb_sq = options_.fb_threshold_px * options_.fb_threshold_px;
  bool have_motion = have_last_motion_;
  cv::Matx23d motion = last_motion_;
  bool fitted = false;
  // Scouts: an even spread of the features that can use the full pyramid,
  // tracked with its full reach from the previous pair's motion (constant
  // velocity). The affine motion fitted to them is this pair's.
  const int predicted_max_level = options_.klt_predicted_levels - 1;
  const bool scouting = predicted_max_level < max_level_;
  if (scouting) {
    const size_t stride = std::max<size_t>(1, full_reach / static_cast<size_t>(options_.klt_scout_features));
    group_index_.clear();
    for (size_t i = 0, k = 0; i < n; ++i)
      if (usable_level_[i] == max_level_ && k++ % stride == 0) group_index_.push_back(i);
    if (!group_index_.empty()) {
      track_group(max_level_, have_motion ? &motion : nullptr);
      fitted = fit_motion(fb_sq, &motion);
      have_motion = have_motion || fitted;
    }
  }
  // The rest, grouped by the levels they may use: all their window allows
  // (edge features: a few, refining a good first guess), at most
  // klt_predicted_levels once this pair's motion is known. Without scouts
  // the full-pyramid group goes first and its fit predicts the others.
  for (int level = max_level_; level >= 0; --level) {
    group_index_.clear();
    for (size_t i = 0; i < n; ++i) {
      if (level_used_[i] >= 0) continue;
      const int use = fitted && scouting ? std::min(usable_level_[i], predicted_max_level) : usable_level_[i];
      if (use == level) group_index_.push_back(i);
    }
    if (group_index_.empty()) continue;
    track_group(level, have_motion ? &motion : nullptr);
    if (!fitted && fit_motion(fb_sq, &motion)) {
      fitted = true;
      have_motion = true;
    }
  }
  // A feature that failed with fewer levels than it may use gets the rest:
  // the prediction was off by more than the short reach (a moving object,
  // strong relief), or the match is wrong. Occluded ones fail again.
  for (int level = max_level_; level > 0; --level) {
    group_index_.clear();
    for (size_t i = 0; i < n; ++i)
      if (usable_level_[i] == level && level_used_[i] < level && failed(i, fb_sq)) group_index_.push_back(i);
    if (!group_index_.empty()) track_group(level, have_motion ? &motion : nullptr);
  }
  have_last_motion_ = fitted;
  last_motion_ = motion;

  // Tracks must end where new corners may start: at least border_px inside,
  // so their level-0 window is (almost) all real pixels.
  const float b = static_cast<float>(options_.border_px);
  const float x_max = static_cast<float>(image_size_.width - 1) - b;
  const float y_max = static_cast<float>(image_size_.height - 1) - b;
  // Photometric check: a track whose final patch differs from the original
  // far more than is typical in this frame (noise, exposure change) has
  // latched onto something else - an occluder, a moving object.
  patch_errors_sorted_.clear();
  for (size_t i = 0; i < n; ++i)
    if (status_fwd_[i]) patch_errors_sorted_.push_back(patch_error_[i]);
  float patch_limit = std::numeric_limits<float>::infinity();
  if (!patch_errors_sorted_.empty()) {
    const auto mid = patch_errors_sorted_.begin() + static_cast<long>(patch_errors_sorted_.size() / 2);
    std::nth_element(patch_errors_sorted_.begin(), mid, patch_errors_sorted_.end());
    patch_limit = static_cast<float>(std::max(options_.patch_error_floor, options_.patch_error_factor * *mid));
  }
  std::vector<Feature> survivors;
  std::vector<size_t> track_index;  // survivors' indices into prev_pts_ / curr_pts_
  survivors.reserve(n);
  for (size_t i = 0; i < n; ++i) {
    if (!status_fwd_[i] || !status_bwd_[i]) {
      ++result.klt_lost;
      continue;
    }
    const cv::Point2f& c = curr_pts_[i];
    if (!(c.x >= b && c.y >= b && c.x <= x_max && c.y <= y_max)) {
      ++result.out_of_image;
      continue;
    }
    const double dx = back_pts_[i].x - prev_pts_[i].x, dy = back_pts_[i].y - prev_pts_[i].y;
    if (!(dx * dx + dy * dy <= fb_sq)) {
      ++result.fb_rejected;
      continue;
    }
    if (!(patch_error_[i] <= patch_limit)) {
      ++result.patch_rejected;
      continue;
    }
    Feature f = features_[i];
    f.age += 1;
    f.px = c;
    survivors.push_back(f);
    track_index.push_back(i);
    result.tracks.push_back({f.id, f.age, prev_pts_[i], c});
  }
  if (options_.klt_window_warp && options_.klt_local_warp) fit_local_warps(survivors, track_index);
  features_ = std::move(survivors);
}

void FeatureTracker::fit_local_warps(std::vector<Feature>& survivors, const std::vector<size_t>& track_index) const {
  // Per survivor: G minimising sum w |(c_j - c_s) - G (p_j - p_s)|^2 over the
  // neighbours j within the radius (prev positions), weighted (1 - d^2/r^2)^2
  // (no libm call: the same bits on every machine); a neighbour moving more
  // than 3 px unlike it (another object) is left out. Plain sums in index
  // order: deterministic.
  const double radius = options_.klt_local_warp_radius_px;
  const double radius_sq = radius * radius;
  for (size_t s = 0; s < survivors.size(); ++s) {
    const cv::Point2f ps = prev_pts_[track_index[s]], cs = curr_pts_[track_index[s]];
    cv::Matx22d cp = cv::Matx22d::zeros(), pp = cv::Matx22d::zeros();
    int used = 0;
    for (size_t j = 0; j < survivors.size(); ++j) {
      if (j == s) continue;
      const cv::Point2f pj = prev_pts_[track_index[j]], cj = curr_pts_[track_index[j]];
      const double dx = pj.x - ps.x, dy = pj.y - ps.y, d2 = dx * dx + dy * dy;
      if (d2 > radius_sq) continue;
      const double qx = cj.x - cs.x, qy = cj.y - cs.y;  // its curr offset; (dx, dy) the prev one
      const double ex = qx - dx, ey = qy - dy;            // how much more it moved than s
      if (ex * ex + ey * ey > 9.0) continue;
      const double taper = 1.0 - d2 / radius_sq;
      const double w = taper * taper;
      cp += w * cv::Matx22d(qx * dx, qx * dy, qy * dx, qy * dy);
      pp += w * cv::Matx22d(dx * dx, dx * dy, dy * dx, dy * dy);
      ++used;
    }
    Feature& f = survivors[s];
    f.has_local_warp = false;
    if (used < 8) continue;
    const double det = pp(0, 0) * pp(1, 1) - pp(0, 1) * pp(1, 0);
    if (!(det > 1e-6 * (pp(0, 0) + pp(1, 1)) * (pp(0, 0) + pp(1, 1)))) continue;
    const cv::Matx22d g = cp * pp.inv();
    if (!LucasKanade::warp_within(g, 0.5 * LucasKanade::kMaxWarpDeviation)) continue;
    f.has_local_warp = true;
    f.local_warp = cv::Matx22f(g);
  }
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
