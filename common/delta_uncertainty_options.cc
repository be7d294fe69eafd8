#include "common/delta_uncertainty_options.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "common/geometry.h"

namespace nadir {
namespace {

void require(bool ok, const std::string& field, const std::string& range) {
  if (!ok) throw std::invalid_argument("uncertainty." + field + " must be " + range);
}

}  // namespace

DeltaUncertaintyOptions DeltaUncertaintyOptions::from_config(const Config& vo_solver_section) {
  DeltaUncertaintyOptions o;
  const Config c = vo_solver_section.section_or_empty("uncertainty");
  o.enabled = c.get<bool>("enabled", o.enabled);
  o.roll_pitch_stddev_deg = c.get_in_range("roll_pitch_stddev_deg", o.roll_pitch_stddev_deg, 0.0, 10.0);
  o.yaw_stddev_deg = c.get_in_range("yaw_stddev_deg", o.yaw_stddev_deg, 0.0, 30.0);
  o.altimeter_stddev_m = c.get_in_range("altimeter_stddev_m", o.altimeter_stddev_m, 0.0, 100.0);
  o.altimeter_stddev_fraction = c.get_in_range("altimeter_stddev_fraction", o.altimeter_stddev_fraction, 0.0, 0.5);
  o.range_scale_stddev = c.get_in_range("range_scale_stddev", o.range_scale_stddev, 0.0, 0.5);
  o.relief_walk_along_m_per_sqrt_m =
      c.get_in_range("relief_walk_along_m_per_sqrt_m", o.relief_walk_along_m_per_sqrt_m, 0.0, 10.0);
  o.relief_walk_across_m_per_sqrt_m =
      c.get_in_range("relief_walk_across_m_per_sqrt_m", o.relief_walk_across_m_per_sqrt_m, 0.0, 10.0);
  o.dyaw_model_stddev_deg = c.get_in_range("dyaw_model_stddev_deg", o.dyaw_model_stddev_deg, 0.0, 10.0);
  o.heading_drift_deg_per_s_per_deg =
      c.get_in_range("heading_drift_deg_per_s_per_deg", o.heading_drift_deg_per_s_per_deg, 0.0, 10.0);
  o.heading_drift_time_s = c.get_in_range("heading_drift_time_s", o.heading_drift_time_s, 0.01, 1e6);
  try {
    o.Check();
  } catch (const std::invalid_argument& e) {
    throw c.error("", e.what());
  }
  return o;
}

void DeltaUncertaintyOptions::Check() const {
  require(roll_pitch_stddev_deg >= 0 && roll_pitch_stddev_deg <= 10, "roll_pitch_stddev_deg", "in [0, 10]");
  require(yaw_stddev_deg >= 0 && yaw_stddev_deg <= 30, "yaw_stddev_deg", "in [0, 30]");
  require(altimeter_stddev_m >= 0 && altimeter_stddev_m <= 100, "altimeter_stddev_m", "in [0, 100]");
  require(altimeter_stddev_fraction >= 0 && altimeter_stddev_fraction <= 0.5, "altimeter_stddev_fraction",
          "in [0, 0.5]");
  require(range_scale_stddev >= 0 && range_scale_stddev <= 0.5, "range_scale_stddev", "in [0, 0.5]");
  require(relief_walk_along_m_per_sqrt_m >= 0 && relief_walk_along_m_per_sqrt_m <= 10, "relief_walk_along_m_per_sqrt_m",
          "in [0, 10]");
  require(relief_walk_across_m_per_sqrt_m >= 0 && relief_walk_across_m_per_sqrt_m <= 10,
          "relief_walk_across_m_per_sqrt_m", "in [0, 10]");
  require(dyaw_model_stddev_deg >= 0 && dyaw_model_stddev_deg <= 10, "dyaw_model_stddev_deg", "in [0, 10]");
  require(heading_drift_deg_per_s_per_deg >= 0 && heading_drift_deg_per_s_per_deg <= 10,
          "heading_drift_deg_per_s_per_deg", "in [0, 10]");
  require(heading_drift_time_s >= 0.01 && heading_drift_time_s <= 1e6, "heading_drift_time_s", "in [0.01, 1e6]");
}

double DeltaUncertaintyOptions::heading_drift_stddev_rad_s() const {
  return enabled ? deg_to_rad(heading_drift_deg_per_s_per_deg * roll_pitch_stddev_deg) : 0.0;
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

void frame_levelling_variances(double prev_altitude_m, double dz, double roll_pitch_stddev_rad, double* prev_m2,
                               double* curr_m2) {
  *prev_m2 = *curr_m2 = 0.0;
  if (!std::isfinite(prev_altitude_m) || !(prev_altitude_m > 0.0) || !std::isfinite(dz)) return;
  *prev_m2 = levelling_variance_m2(prev_altitude_m, roll_pitch_stddev_rad);
  *curr_m2 = levelling_variance_m2(std::max(0.0, prev_altitude_m - dz), roll_pitch_stddev_rad);
}

}  // namespace nadir
