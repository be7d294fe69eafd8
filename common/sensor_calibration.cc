#include "common/sensor_calibration.h"

#include <cmath>
#include <string>

namespace nadir {

SensorCalibration SensorCalibration::from_config(const Config& root) {
  SensorCalibration c;
  const Config camera = root.section_or_empty("camera");
  c.camera_time_offset_us = camera.get<int64_t>("time_offset_us", c.camera_time_offset_us);  // integer us
  const Config altimeter = root.section_or_empty("altimeter");
  c.altimeter_range_scale = altimeter.get<double>("range_scale", c.altimeter_range_scale);
  c.altimeter_range_bias_m = altimeter.get<double>("range_bias_m", c.altimeter_range_bias_m);
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
}

}  // namespace nadir
