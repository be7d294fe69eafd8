#pragma once
// Installation calibration applied where sensor data enters the estimators
// (issue 17; the values come from nadir_calibrate, tools/calibrate/README.md):
//
//   camera.time_offset_us    exposure time = image stamp + offset: the INS
//                            attitude and the altimeter range for a frame are
//                            looked up at the exposure time. The frame keeps
//                            its stamp (TRACKS, VO_DELTA and POSE utimes are
//                            unchanged).
//   altimeter.range_scale    measured range = scale * true + bias, so every
//   altimeter.range_bias_m   consumer uses true = (measured - bias) / scale.
//
// The defaults (0, 1, 0) change nothing, bit for bit.

#include <cstdint>
#include <string>

#include "common/config.h"

namespace nadir {

struct SensorCalibration {
  int64_t camera_time_offset_us = 0;
  double altimeter_range_scale = 1.0;
  double altimeter_range_bias_m = 0.0;

  // Reads camera.time_offset_us, altimeter.range_scale and
  // altimeter.range_bias_m from the config root (each optional) and checks
  // them; throws ConfigError naming the key.
  static SensorCalibration from_config(const Config& root);
  // Throws ConfigError naming the key and its allowed range: |time offset| <
  // 1 s, scale in (0.5, 2), |bias| < 100 m.
  // `source` names the config in the error.
  void Check(const std::string& source = "config") const;

  // Sensor time at which a frame stamped `image_utime` was exposed.
  int64_t exposure_utime(int64_t image_utime) const { return image_utime + camera_time_offset_us; }
  // The true range of a measured one.
  double true_range(double measured_m) const {
    return (measured_m - altimeter_range_bias_m) / altimeter_range_scale;
  }
};

}  // namespace nadir
