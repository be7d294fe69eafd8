// Image time: trigger edge + delay + half exposure, and the camera-clock
// fallback through ClockSync.

#include "processes/camera_capture/image_time.h"

#include <gtest/gtest.h>

namespace nadir {
namespace {

TEST(ImageTime, TriggerTimeIsMidExposureAfterTheConfiguredDelay) {
  ImageTimingOptions o;
  o.trigger_delay_us = 35.0;
  EXPECT_EQ(utime_from_trigger(o, 1'000'000, 2000.0), 1'000'000 + 35 + 1000);
  EXPECT_EQ(utime_from_trigger(o, 1'000'000, 0.0), 1'000'035);
  EXPECT_EQ(mid_exposure_utime(500, 3.0), 502);  // rounds half up
}

TEST(ImageTime, CameraClockIsMappedByTheOffsetEstimator) {
  ClockSyncOptions sync_options;
  sync_options.window_s = 10;
  sync_options.block_s = 1;
  ClockSync clock(sync_options);
  // Camera clock 3 s behind the vehicle clock, transport delay 2..9 ms.
  const int64_t behind = 3'000'000;
  for (int i = 0; i < 14 * 6; ++i) {
    const int64_t camera = 10'000'000 + i * 71429;
    // Once per second (per ClockSync block) a frame gets through at the 2 ms minimum.
    const int64_t delay = 2000 + (i % 14 == 3 ? 0 : 500 + (i * 3779) % 6500);
    clock.add(camera, camera + behind + delay);
  }
  ASSERT_TRUE(clock.valid());
  ImageTimingOptions o;
  o.camera_stamp_to_exposure_start_us = -100;  // camera stamps 100 us after exposure starts
  const int64_t camera = 10'000'000 + 90 * 71429;
  const int64_t utime = utime_from_camera_clock(o, clock, camera, 4000);
  // The envelope of the delay is 2 ms (min_delay_us = 0 reports it as offset).
  EXPECT_NEAR(static_cast<double>(utime), static_cast<double>(camera + behind + 2000 - 100 + 2000), 5.0);
}

}  // namespace
}  // namespace nadir
