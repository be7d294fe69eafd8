#pragma once
// Installation calibration applied where sensor data enters the estimators
// (the values come from nadir_calibrate, docs/calibration.md,
// and, for the lever arms, from the installation drawing):
//
//   camera.time_offset_us    exposure time = image stamp + offset: the INS
//                            attitude and the altimeter range for a frame are
//                            looked up at the exposure time. The frame keeps
//                            its stamp (TRACKS, VO_DELTA and POSE utimes are
//                            unchanged).
//   altimeter.range_scale    measured range = scale * true + bias, so every
//   altimeter.range_bias_m   consumer uses true = (measured - bias) / scale.
//   altimeter.beam_misalignment_deg [roll, pitch]
//                            the beam's true direction is the reported one
//                            (ALTIMETER.beam_body) turned by R(roll, pitch, 0).
//   altimeter.lever_arm_m [x, y, z]
//                            the beam's origin from the INS reference point,
//                            body frame (forward, right, down), metres.
//   camera.lever_arm_m [x, y, z]
//                            the camera centre from the INS reference point,
//                            body frame, metres. VO_DELTA and POSE refer to
//                            the INS reference point (the ground truth's).
//
// The defaults (0, 1, 0, zeros) change nothing, bit for bit.

#include <Eigen/Core>

#include <cstdint>
#include <string>

#include "common/config.h"

namespace nadir {

// An altimeter measurement as a ray: the ground point it hit lies at
// range_m * beam_body from the ray's origin (body frame).
struct AltimeterRay {
  double range_m = 0.0;
  Eigen::Vector3d beam_body = Eigen::Vector3d::UnitZ();
};

struct SensorCalibration {
  int64_t camera_time_offset_us = 0;
  double altimeter_range_scale = 1.0;
  double altimeter_range_bias_m = 0.0;
  Eigen::Vector2d altimeter_beam_misalignment_rad = Eigen::Vector2d::Zero();
  Eigen::Vector3d altimeter_lever_arm_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d camera_lever_arm_m = Eigen::Vector3d::Zero();

  // Reads the keys above from the config root (each optional) and checks
  // them; throws ConfigError naming the key.
  static SensorCalibration from_config(const Config& root);
  // Every key of the shared `camera:` and `altimeter:` sections, whichever
  // process reads which (camera model, calibration, rate, beam): the readers
  // refuse any other key there.
  static const std::vector<std::string>& camera_keys();
  static const std::vector<std::string>& altimeter_keys();
  // Throws ConfigError naming the key and its allowed range: |time offset| <
  // 1 s, scale in (0.5, 2), |bias| < 100 m, misalignment within 10 deg, lever
  // arms within 20 m per axis. `source` names the config in the error.
  void Check(const std::string& source = "config") const;

  // Sensor time at which a frame stamped `image_utime` was exposed.
  int64_t exposure_utime(int64_t image_utime) const { return image_utime + camera_time_offset_us; }
  // The true range of a measured one.
  double true_range(double measured_m) const {
    return (measured_m - altimeter_range_bias_m) / altimeter_range_scale;
  }
  // The beam's true direction (unit) of a reported one.
  Eigen::Vector3d true_beam(const Eigen::Vector3d& reported_beam_body) const;
  // True when the beam misalignment or a lever arm is set.
  bool moves_altimeter_ray() const;
  // The measured range along the reported beam as the ray from `origin_body`
  // (a point given from the INS reference, body frame) to the same ground
  // point: the true range along the true beam, from the altimeter's lever
  // arm. With no misalignment and no lever arms, exactly {true range, beam}.
  AltimeterRay ray_from(const Eigen::Vector3d& origin_body, double measured_range_m,
                        const Eigen::Vector3d& reported_beam_body) const;
};

}  // namespace nadir
