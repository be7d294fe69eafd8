#pragma once
// When an image was taken, on the vehicle time base.
//
// utime = trigger edge + trigger_delay_us + exposure / 2: the middle of the
// exposure, which is the instant the image best describes for a moving
// aircraft. trigger_delay_us is the camera's documented (or measured) delay
// from the trigger input to the start of exposure.
//
// Without a trigger edge the camera's own buffer timestamp is used: mapped to
// the vehicle time base by ClockSync (camera time vs host arrival), then
// camera_stamp_to_exposure_start_us says when exposure started relative to
// the camera's stamp (most GigE cameras stamp the frame start: 0).

#include <cstdint>

#include "common/clock_sync.h"
#include "common/config.h"

namespace nadir {

struct ImageTimingOptions {
  double trigger_delay_us = 0.0;
  double camera_stamp_to_exposure_start_us = 0.0;
  static ImageTimingOptions FromConfig(const Config& section);
};

int64_t mid_exposure_utime(int64_t exposure_start_us, double exposure_us);
int64_t utime_from_trigger(const ImageTimingOptions& options, int64_t edge_vehicle_us, double exposure_us);
// Requires clock.valid().
int64_t utime_from_camera_clock(const ImageTimingOptions& options, const ClockSync& clock, int64_t camera_us,
                                double exposure_us);

}  // namespace nadir
