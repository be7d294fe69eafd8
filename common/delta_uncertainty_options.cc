#include "common/delta_uncertainty_options.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "common/geometry.h"

namespace nadir {

const OptionsSchema<DeltaUncertaintyOptions>& DeltaUncertaintyOptions::schema() {
  using O = DeltaUncertaintyOptions;
  static const OptionsSchema<O> schema = [] {
    OptionsSchema<O> s("vo_solver.uncertainty",
                       "Errors of the INS/altimeter inputs every solve takes as exact, propagated into VO_DELTA's "
                       "covariance (read by vo_solver and yaw_fusion).");
    s.flag("enabled", "false: VO_DELTA carries the image covariance only", &O::enabled)
        .number("roll_pitch_stddev_deg", 0.0, 10.0, "deg", "INS roll/pitch white noise per sample",
                &O::roll_pitch_stddev_deg)
        .number("roll_pitch_correlated_stddev_deg", 0.0, 10.0, "deg",
                "INS roll/pitch error correlated between samples (not averaged where a frame's attitude is made "
                "from two samples)",
                &O::roll_pitch_correlated_stddev_deg)
        .number("yaw_stddev_deg", 0.0, 30.0, "deg", "INS yaw white noise (the flow variant's dyaw only)",
                &O::yaw_stddev_deg)
        .number("altimeter_stddev_m", 0.0, 100.0, "m", "altimeter range noise, constant part",
                &O::altimeter_stddev_m)
        .number("altimeter_stddev_fraction", 0.0, 0.5, "", "altimeter range noise, fraction of the range",
                &O::altimeter_stddev_fraction)
        .number("range_scale_stddev", 0.0, 0.5, "", "systematic altimeter scale error (fraction, 1 sigma)",
                &O::range_scale_stddev)
        .number("relief_walk_along_m_per_sqrt_m", 0.0, 10.0, "m/sqrt(m)",
                "relief model error of the one-plane variants along the step, random walk in the distance flown",
                &O::relief_walk_along_m_per_sqrt_m)
        .number("relief_walk_across_m_per_sqrt_m", 0.0, 10.0, "m/sqrt(m)",
                "relief model error of the one-plane variants across the step, random walk in the distance flown",
                &O::relief_walk_across_m_per_sqrt_m)
        .number("feature_depth_walk_along_m_per_sqrt_m", 0.0, 10.0, "m/sqrt(m)",
                "feature_depth variant's model error along the step, random walk in the distance flown",
                &O::feature_depth_walk_along_m_per_sqrt_m)
        .number("feature_depth_walk_across_m_per_sqrt_m", 0.0, 10.0, "m/sqrt(m)",
                "feature_depth variant's model error across the step, random walk in the distance flown",
                &O::feature_depth_walk_across_m_per_sqrt_m)
        .number("feature_depth_relief_heights", 0.0, 100.0, "heights",
                "feature_depth: along-step variance per metre added over relief, the altimeter anchor's model "
                "variance (relative) x height x this; 0 = off",
                &O::feature_depth_relief_heights)
        .number("dyaw_model_stddev_deg", 0.0, 10.0, "deg", "model error of each heading change",
                &O::dyaw_model_stddev_deg)
        .number("heading_drift_deg_per_s_per_deg", 0.0, 10.0, "deg/s per deg",
                "heading drift rate stddev per degree of roll_pitch_stddev_deg", &O::heading_drift_deg_per_s_per_deg)
        .number("heading_drift_time_s", 0.01, 1e6, "s", "correlation time of the heading drift (Gauss-Markov)",
                &O::heading_drift_time_s);
    return s;
  }();
  return schema;
}

DeltaUncertaintyOptions DeltaUncertaintyOptions::from_config(const Config& vo_solver_section) {
  return schema().read(vo_solver_section.section_or_empty("uncertainty"));
}

void DeltaUncertaintyOptions::Check() const {
  try {
    schema().check(*this);
  } catch (const ConfigError& e) {
    throw std::invalid_argument(e.what());
  }
}

double DeltaUncertaintyOptions::heading_drift_stddev_rad_s() const {
  return enabled ? deg_to_rad(heading_drift_deg_per_s_per_deg * roll_pitch_stddev_deg) : 0.0;
}

double DeltaUncertaintyOptions::frame_roll_pitch_stddev_rad(double white_noise_share) const {
  const double white = deg_to_rad(roll_pitch_stddev_deg), correlated = deg_to_rad(roll_pitch_correlated_stddev_deg);
  return std::sqrt(white * white * std::max(0.0, white_noise_share) + correlated * correlated);
}

double levelling_variance_m2(double height_m, double roll_pitch_stddev_rad) {
  const double shift = height_m * roll_pitch_stddev_rad;
  return shift * shift;
}

double levelling_yaw_variance_rad2(double pitch_rad, double roll_pitch_stddev_rad) {
  if (!std::isfinite(pitch_rad)) return 0.0;
  const double turn = std::sin(pitch_rad) * roll_pitch_stddev_rad;
  return turn * turn;
}

void frame_levelling_variances(double prev_altitude_m, double dz, double prev_roll_pitch_stddev_rad,
                               double curr_roll_pitch_stddev_rad, double* prev_m2, double* curr_m2) {
  *prev_m2 = *curr_m2 = 0.0;
  if (!std::isfinite(prev_altitude_m) || !(prev_altitude_m > 0.0) || !std::isfinite(dz)) return;
  *prev_m2 = levelling_variance_m2(prev_altitude_m, prev_roll_pitch_stddev_rad);
  *curr_m2 = levelling_variance_m2(std::max(0.0, prev_altitude_m - dz), curr_roll_pitch_stddev_rad);
}

}  // namespace nadir
