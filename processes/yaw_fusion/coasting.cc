#include "processes/yaw_fusion/coasting.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "common/geometry.h"
#include "common/robust_stats.h"

namespace nadir {

const OptionsSchema<CoastOptions>& CoastOptions::schema() {
  using O = CoastOptions;
  static const OptionsSchema<O> schema = [] {
    OptionsSchema<O> s("yaw_fusion.coast", "Coasting over deltas whose translation is not trusted (coasting.h).");
    s.flag("enabled", "false: no coasting", &O::enabled)
        .number("quality_mask", 0, 0x7fffffff, "bits", "VO_DELTA quality bits that make a delta coast",
                &O::quality_mask)
        .number("max_duration_s", 0.0, 3600.0, "s", "beyond, the VO-gap behaviour (hold, FLAG_VO_GAP)",
                &O::max_duration_s)
        .number("max_range_age_s", 0.0, 60.0, "s", "altimeter range older than this is not used while coasting",
                &O::max_range_age_s)
        .number("velocity_stddev_mps", 0.0, 100.0, "m/s", "error of the held velocity", &O::velocity_stddev_mps)
        .number("velocity_random_walk", 0.0, 100.0, "m/s/sqrt(s)", "random walk of the held velocity",
                &O::velocity_random_walk)
        .number("vertical_velocity_stddev_mps", 0.0, 100.0, "m/s", "the same for down",
                &O::vertical_velocity_stddev_mps)
        .number("inlier_drop_fraction", 0.0, 1.0, "", "inliers below this fraction of the running median: coast",
                &O::inlier_drop_fraction)
        .number("inlier_median_window", 1, 100000, "deltas", "integrated deltas in the running median",
                &O::inlier_median_window)
        .number("vertical_gate_m", 0.0, 1e6, "m", "vertical gate, constant part", &O::vertical_gate_m)
        .number("vertical_gate_slope", 0.0, 100.0, "", "vertical gate, per metre of horizontal step",
                &O::vertical_gate_slope)
        .number("vertical_gate_sigmas", 0.0, 100.0, "", "vertical gate in sigmas of the delta's dz",
                &O::vertical_gate_sigmas)
        .number("high_residual_window", 1, 100000, "deltas", "window of the HIGH_RESIDUAL share",
                &O::high_residual_window)
        .number("high_residual_fraction", 0.0, 1.0, "", "more HIGH_RESIDUAL than this share in the window: coast",
                &O::high_residual_fraction)
        .number("resume_good_deltas", 1, 100000, "deltas", "clean deltas in a row before integrating again",
                &O::resume_good_deltas)
        .flag("vo_direction", "a stale-range delta coasts along its own direction at the held speed",
              &O::vo_direction)
        .number("speed_window_s", 0.0, 60.0, "s", "window of the held velocity (displacement, mean heading)",
                &O::speed_window_s)
        .number("max_climb_ratio", 0.0, 10.0, "", "vo_direction: |dz| at most this share of the horizontal step",
                &O::max_climb_ratio)
        .flag("follow_altimeter", "while coasting, down = the last frames' ground plane minus the levelled range",
              &O::follow_altimeter)
        .number("terrain_window_s", 0.0, 60.0, "s",
                "integrated frames whose ground points and patch tilts make that plane", &O::terrain_window_s)
        .number("terrain_slope_stddev", 0.0, 1.0, "m/m",
                "error of that plane's slope over the coast: weighs it against the held climb rate",
                &O::terrain_slope_stddev)
        .flag("follow_seen_ground",
              "while coasting over ground the last frames' VO_GROUND points cover, each range measures down (that "
              "ground minus the levelled range) and, with it, the climb held beyond it",
              &O::follow_seen_ground)
        .number("seen_ground_window_s", 0.0, 60.0, "s",
                "integrated frames whose VO_GROUND points are kept (each track's newest)", &O::seen_ground_window_s)
        .number("seen_ground_radius_of_height", 0.001, 10.0, "",
                "points within this share of the height (at least 10 m) make the ground below",
                &O::seen_ground_radius_of_height)
        .number("seen_ground_min_points", 1, 100000, "points", "fewer within the radius: that ground was not seen",
                &O::seen_ground_min_points)
        .number("seen_ground_steady_climb_stddev_mps", 0.0, 100.0, "m/s",
                "over seen ground, the steady climb model: error of the held climb", &O::seen_ground_steady_climb_stddev_mps)
        .number("seen_ground_steady_random_walk", 0.0, 100.0, "m/s/sqrt(s)",
                "... and its random walk (the changing model: vertical_velocity_stddev_mps, velocity_random_walk)",
                &O::seen_ground_steady_random_walk)
        .number("seen_ground_changing_probability", 0.0, 1.0, "",
                "chance at the coast's start that the climb is changing", &O::seen_ground_changing_probability)
        .number("seen_ground_switch_rate", 0.0, 100.0, "1/s", "rate of switching between the two climb models",
                &O::seen_ground_switch_rate)
        .flag("bridge",
              "a delta from the last integrated frame over the whole coast (the tracker matched across it) ends "
              "the coast with its climb (bridge_horizontal, bridge_heading_from_ins: the rest)",
              &O::bridge)
        .choice<BridgeHorizontal>("bridge_horizontal",
                                  {{"coast", BridgeHorizontal::kCoast},
                                   {"pair", BridgeHorizontal::kPair},
                                   {"pair_direction", BridgeHorizontal::kPairDirection}},
                                  "the bridged horizontal: the coast's, the pair's, or the pair's direction with "
                                  "the coast's length",
                                  &O::bridge_horizontal)
        .flag("bridge_heading_from_ins",
              "the bridging pair's heading change replaced by the INS's over its span (and what the pair solved "
              "with it moved along, by its covariance)",
              &O::bridge_heading_from_ins);
    return s;
  }();
  return schema;
}

CoastOptions CoastOptions::from_config(const Config& c) { return schema().read(c); }

void CoastOptions::Check() const { schema().check(*this); }

std::optional<Eigen::Vector3d> held_level_velocity(const std::deque<CoastSample>& window) {
  if (window.size() < 2) return std::nullopt;
  const CoastSample& first = window.front();
  const CoastSample& last = window.back();
  const double duration_s = static_cast<double>(last.utime - first.utime) * 1e-6;
  if (!(duration_s > 0.0)) return std::nullopt;
  // The mean heading as offsets from the first sample's (a window across 180 deg averages right).
  double offset_sum = 0.0;
  for (size_t i = 0; i + 1 < window.size(); ++i) offset_sum += wrap_angle(window[i].yaw - first.yaw);
  const double heading = first.yaw + offset_sum / static_cast<double>(window.size() - 1);
  const Eigen::Vector3d world = (last.position - first.position) / duration_s;
  return rotation_from_rpy(0.0, 0.0, -heading) * world;
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
