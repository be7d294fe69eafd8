#include "common/sensor_calibration.h"

#include <cmath>
#include <string>
#include <vector>

#include "common/geometry.h"

namespace nadir {

namespace {
constexpr double kDegToRad = M_PI / 180.0;

// An optional list of `n` numbers under `key`; `fallback` when absent.
Eigen::VectorXd get_numbers(const Config& section, const std::string& key, const Eigen::VectorXd& fallback) {
  if (!section.has(key)) return fallback;
  const auto v = section.get<std::vector<double>>(key);
  if (static_cast<Eigen::Index>(v.size()) != fallback.size()) {
    throw section.error(key, "must list " + std::to_string(fallback.size()) + " numbers, has " +
                                 std::to_string(v.size()));
  }
  Eigen::VectorXd out(fallback.size());
  for (Eigen::Index i = 0; i < out.size(); ++i) out[i] = v[static_cast<size_t>(i)];
  return out;
}
}  // namespace

const std::vector<std::string>& SensorCalibration::camera_keys() {
  static const std::vector<std::string> keys{"width",         "height",      "fx",        "fy",
                                             "cx",            "cy",          "distortion", "mount_rpy_deg",
                                             "rate_hz",       "lever_arm_m", "time_offset_us"};
  return keys;
}

const std::vector<std::string>& SensorCalibration::altimeter_keys() {
  static const std::vector<std::string> keys{"beam_body", "lever_arm_m", "beam_misalignment_deg", "range_scale",
                                             "range_bias_m"};
  return keys;
}

SensorCalibration SensorCalibration::from_config(const Config& root) {
  SensorCalibration c;
  const Config camera = root.section_or_empty("camera");
  camera.require_known_keys(camera_keys());
  root.section_or_empty("altimeter").require_known_keys(altimeter_keys());
  c.camera_time_offset_us = camera.get<int64_t>("time_offset_us", c.camera_time_offset_us);  // integer us
  c.camera_lever_arm_m = get_numbers(camera, "lever_arm_m", c.camera_lever_arm_m);
  const Config altimeter = root.section_or_empty("altimeter");
  c.altimeter_range_scale = altimeter.get<double>("range_scale", c.altimeter_range_scale);
  c.altimeter_range_bias_m = altimeter.get<double>("range_bias_m", c.altimeter_range_bias_m);
  c.altimeter_beam_misalignment_rad =
      get_numbers(altimeter, "beam_misalignment_deg", Eigen::Vector2d::Zero()) * kDegToRad;
  c.altimeter_lever_arm_m = get_numbers(altimeter, "lever_arm_m", c.altimeter_lever_arm_m);
  c.Check(root.source());
  return c;
}

void SensorCalibration::Check(const std::string& source) const {
  require_option(camera_time_offset_us > -1000000 && camera_time_offset_us < 1000000, source,
                 "camera.time_offset_us", "must be in (-1e6, 1e6) us (|offset| < 1 s)");
  require_option(altimeter_range_scale > 0.5 && altimeter_range_scale < 2.0, source, "altimeter.range_scale",
                 "must be in (0.5, 2)");
  require_option(std::fabs(altimeter_range_bias_m) < 100.0, source, "altimeter.range_bias_m",
                 "must be in (-100, 100) m");
  require_option(altimeter_beam_misalignment_rad.allFinite() &&
                     altimeter_beam_misalignment_rad.cwiseAbs().maxCoeff() <= 10.0 * kDegToRad,
                 source, "altimeter.beam_misalignment_deg", "must be within [-10, 10] deg per axis");
  require_option(altimeter_lever_arm_m.allFinite() && altimeter_lever_arm_m.cwiseAbs().maxCoeff() <= 20.0, source,
                 "altimeter.lever_arm_m", "must be within [-20, 20] m per axis");
  require_option(camera_lever_arm_m.allFinite() && camera_lever_arm_m.cwiseAbs().maxCoeff() <= 20.0, source,
                 "camera.lever_arm_m", "must be within [-20, 20] m per axis");
}

Eigen::Vector3d SensorCalibration::true_beam(const Eigen::Vector3d& reported_beam_body) const {
  if (altimeter_beam_misalignment_rad.isZero(0.0)) return reported_beam_body.normalized();
  return rotation_from_rpy(altimeter_beam_misalignment_rad.x(), altimeter_beam_misalignment_rad.y(), 0.0) *
         reported_beam_body.normalized();
}

bool SensorCalibration::moves_altimeter_ray() const {
  return !altimeter_beam_misalignment_rad.isZero(0.0) || !altimeter_lever_arm_m.isZero(0.0) ||
         !camera_lever_arm_m.isZero(0.0);
}

AltimeterRay SensorCalibration::ray_from(const Eigen::Vector3d& origin_body, double measured_range_m,
                                         const Eigen::Vector3d& reported_beam_body) const {
  AltimeterRay ray;
  ray.range_m = true_range(measured_range_m);
  ray.beam_body = reported_beam_body;
  if (altimeter_beam_misalignment_rad.isZero(0.0) && altimeter_lever_arm_m == origin_body) return ray;
  const Eigen::Vector3d ground_point = altimeter_lever_arm_m - origin_body + ray.range_m * true_beam(reported_beam_body);
  ray.range_m = ground_point.norm();
  ray.beam_body = ground_point / ray.range_m;
  return ray;
}

}  // namespace nadir
