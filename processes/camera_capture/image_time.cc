#include "processes/camera_capture/image_time.h"

#include <cmath>

namespace nadir {

ImageTimingOptions ImageTimingOptions::FromConfig(const Config& c) {
  ImageTimingOptions o;
  c.require_known_keys({"trigger_delay_us", "camera_stamp_to_exposure_start_us"});
  o.trigger_delay_us = c.get_in_range<double>("trigger_delay_us", o.trigger_delay_us, 0.0, 1e6);
  o.camera_stamp_to_exposure_start_us =
      c.get_in_range<double>("camera_stamp_to_exposure_start_us", o.camera_stamp_to_exposure_start_us, -1e6, 1e6);
  return o;
}

int64_t mid_exposure_utime(int64_t exposure_start_us, double exposure_us) {
  return exposure_start_us + static_cast<int64_t>(std::llround(exposure_us / 2.0));
}

int64_t utime_from_trigger(const ImageTimingOptions& options, int64_t edge_vehicle_us, double exposure_us) {
  return mid_exposure_utime(edge_vehicle_us + static_cast<int64_t>(std::llround(options.trigger_delay_us)),
                            exposure_us);
}

int64_t utime_from_camera_clock(const ImageTimingOptions& options, const ClockSync& clock, int64_t camera_us,
                                double exposure_us) {
  const int64_t stamp_vehicle = clock.to_vehicle(camera_us);
  return mid_exposure_utime(
      stamp_vehicle + static_cast<int64_t>(std::llround(options.camera_stamp_to_exposure_start_us)), exposure_us);
}

}  // namespace nadir
