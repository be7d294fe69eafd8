#include "processes/yaw_fusion/coasting.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "common/robust_stats.h"

namespace nadir {

namespace {
void check(bool ok, const std::string& key, const std::string& what) {
  require_option(ok, "config", "yaw_fusion.coast." + key, what);
}
}  // namespace

CoastOptions CoastOptions::from_config(const Config& c) {
  CoastOptions o;
  o.enabled = c.get<bool>("enabled", o.enabled);
  o.quality_mask = c.get_in_range("quality_mask", o.quality_mask, 0, 0x7fffffff);
  o.max_duration_s = c.get_in_range("max_duration_s", o.max_duration_s, 0.0, 3600.0);
  o.max_range_age_s = c.get_in_range("max_range_age_s", o.max_range_age_s, 0.0, 60.0);
  o.velocity_stddev_mps = c.get_in_range("velocity_stddev_mps", o.velocity_stddev_mps, 0.0, 100.0);
  o.velocity_random_walk = c.get_in_range("velocity_random_walk", o.velocity_random_walk, 0.0, 100.0);
  o.vertical_velocity_stddev_mps =
      c.get_in_range("vertical_velocity_stddev_mps", o.vertical_velocity_stddev_mps, 0.0, 100.0);
  o.inlier_drop_fraction = c.get_in_range("inlier_drop_fraction", o.inlier_drop_fraction, 0.0, 1.0);
  o.inlier_median_window = c.get_in_range("inlier_median_window", o.inlier_median_window, 1, 100000);
  o.vertical_gate_m = c.get_in_range("vertical_gate_m", o.vertical_gate_m, 0.0, 1e6);
  o.vertical_gate_slope = c.get_in_range("vertical_gate_slope", o.vertical_gate_slope, 0.0, 100.0);
  o.vertical_gate_sigmas = c.get_in_range("vertical_gate_sigmas", o.vertical_gate_sigmas, 0.0, 100.0);
  o.high_residual_window = c.get_in_range("high_residual_window", o.high_residual_window, 1, 100000);
  o.high_residual_fraction = c.get_in_range("high_residual_fraction", o.high_residual_fraction, 0.0, 1.0);
  o.resume_good_deltas = c.get_in_range("resume_good_deltas", o.resume_good_deltas, 1, 100000);
  o.vo_direction = c.get<bool>("vo_direction", o.vo_direction);
  o.speed_window_s = c.get_in_range("speed_window_s", o.speed_window_s, 0.0, 60.0);
  o.max_climb_ratio = c.get_in_range("max_climb_ratio", o.max_climb_ratio, 0.0, 10.0);
  o.Check();
  return o;
}

void CoastOptions::Check() const {
  check(quality_mask >= 0, "quality_mask", "must be >= 0");
  check(max_duration_s >= 0.0, "max_duration_s", "must be >= 0");
  check(max_range_age_s >= 0.0, "max_range_age_s", "must be >= 0");
  check(velocity_stddev_mps >= 0.0, "velocity_stddev_mps", "must be >= 0");
  check(velocity_random_walk >= 0.0, "velocity_random_walk", "must be >= 0");
  check(vertical_velocity_stddev_mps >= 0.0, "vertical_velocity_stddev_mps", "must be >= 0");
  check(inlier_drop_fraction >= 0.0 && inlier_drop_fraction <= 1.0, "inlier_drop_fraction", "must be in [0, 1]");
  check(inlier_median_window >= 1, "inlier_median_window", "must be >= 1");
  check(vertical_gate_m >= 0.0, "vertical_gate_m", "must be >= 0");
  check(vertical_gate_slope >= 0.0, "vertical_gate_slope", "must be >= 0");
  check(vertical_gate_sigmas >= 0.0, "vertical_gate_sigmas", "must be >= 0");
  check(high_residual_window >= 1, "high_residual_window", "must be >= 1");
  check(high_residual_fraction >= 0.0 && high_residual_fraction <= 1.0, "high_residual_fraction",
        "must be in [0, 1]");
  check(resume_good_deltas >= 1, "resume_good_deltas", "must be >= 1");
  check(max_climb_ratio >= 0.0, "max_climb_ratio", "must be >= 0");
  check(speed_window_s >= 0.0, "speed_window_s", "must be >= 0");
}

double coast_position_variance(double sigma_v, double q, double t) {
  if (!(t > 0.0)) return 0.0;
  return sigma_v * sigma_v * t * t + q * q * t * t * t / 3.0;
}

const char* coast_reason_name(int bit) {
  static const char* const kNames[kCoastReasons] = {"quality", "inlier_drop", "vertical", "high_residual",
                                                    "resuming"};
  return bit >= 0 && bit < kCoastReasons ? kNames[bit] : "unknown";
}

double CoastDetector::inlier_median() const {
  if (static_cast<int>(inliers_.size()) < options_.inlier_median_window) {
    return std::numeric_limits<double>::quiet_NaN();
  }
  std::vector<int> sorted(inliers_.begin(), inliers_.end());
  const auto mid = sorted.begin() + static_cast<std::ptrdiff_t>(sorted.size() / 2);
  std::nth_element(sorted.begin(), mid, sorted.end());
  return *mid;
}

int32_t CoastDetector::classify(const vo_delta_t& delta, int32_t coast_bits, double height_change_m, bool coasting) {
  const bool high = (delta.quality & vo_delta_t::QUALITY_HIGH_RESIDUAL) != 0;
  high_residual_.push_back(high);
  high_residual_count_ += high ? 1 : 0;
  while (static_cast<int>(high_residual_.size()) > options_.high_residual_window) {
    high_residual_count_ -= high_residual_.front() ? 1 : 0;
    high_residual_.pop_front();
  }

  int32_t reason = 0;
  if (coast_bits != 0) reason |= kCoastQuality;
  const double median = inlier_median();
  if (std::isfinite(median) && delta.inliers < options_.inlier_drop_fraction * median) reason |= kCoastInlierDrop;
  last_ground_step_ = std::numeric_limits<double>::quiet_NaN();
  if (std::isfinite(height_change_m)) {
    // Down coordinate of the ground: g = down + h, so the ground moved by dz + dh.
    const double ground_step = delta.dz + height_change_m;
    last_ground_step_ = ground_step;
    if (std::abs(ground_step) > vertical_gate(std::hypot(delta.dx, delta.dy))) reason |= kCoastVertical;
  }
  if (static_cast<int>(high_residual_.size()) >= options_.high_residual_window &&
      high_residual_count_ > options_.high_residual_fraction * static_cast<double>(high_residual_.size())) {
    reason |= kCoastHighResidual;
  }
  if (reason != 0) {
    good_streak_ = 0;
    return reason;
  }
  ++good_streak_;
  if (coasting && good_streak_ < options_.resume_good_deltas) return kCoastResuming;
  return 0;
}

double CoastDetector::vertical_gate(double horizontal_m) const {
  double gate = options_.vertical_gate_m;
  // Ten steps already give a usable robust spread (the start of a flight,
  // where the fixed gate alone fires most with a noisy altimeter).
  constexpr int kMinGroundSteps = 10;
  if (options_.vertical_gate_sigmas > 0 && static_cast<int>(ground_steps_.size()) >= kMinGroundSteps) {
    const std::vector<double> steps(ground_steps_.begin(), ground_steps_.end());
    gate = std::max(gate, options_.vertical_gate_sigmas * abs_sigma(steps));
  }
  return gate + options_.vertical_gate_slope * horizontal_m;
}

void CoastDetector::note_integrated(const vo_delta_t& delta) {
  inliers_.push_back(delta.inliers);
  while (static_cast<int>(inliers_.size()) > options_.inlier_median_window) inliers_.pop_front();
  // The delta integrated is the one classified last.
  if (std::isfinite(last_ground_step_)) ground_steps_.push_back(last_ground_step_);
  last_ground_step_ = std::numeric_limits<double>::quiet_NaN();
  while (static_cast<int>(ground_steps_.size()) > options_.inlier_median_window) ground_steps_.pop_front();
}

}  // namespace nadir
