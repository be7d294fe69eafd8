#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "common/clock_sync.h"
#include "common/config.h"

namespace nadir {
namespace {

// Device clock with offset and drift; arrival delayed by 1 ms + exponential jitter.
struct Simulated {
  double offset_us = 3.5e6;
  double drift_ppm = 40.0;
  int64_t vehicle_of(int64_t device_us) const {
    return device_us + static_cast<int64_t>(offset_us + drift_ppm * 1e-6 * static_cast<double>(device_us));
  }
};

TEST(ClockSync, TracksOffsetAndDriftUnderJitter) {
  ClockSyncOptions options;
  options.min_delay_us = 1000;
  ClockSync sync(options);
  Simulated clock;
  std::mt19937 rng(7);
  std::exponential_distribution<double> jitter(1.0 / 2000.0);  // mean 2 ms
  double worst = 0;
  for (int i = 0; i < 100 * 120; ++i) {  // 100 Hz for 120 s
    const int64_t device = 1000000 + i * 10000;
    const int64_t arrival = clock.vehicle_of(device) + 1000 + static_cast<int64_t>(jitter(rng));
    ASSERT_TRUE(sync.add(device, arrival));
    if (i > 100 * 10) worst = std::max(worst, std::fabs(double(sync.to_vehicle(device) - clock.vehicle_of(device))));
  }
  EXPECT_LT(worst, 200.0);  // 0.2 ms against 2 ms mean jitter
  EXPECT_NEAR(sync.state().drift_ppm, 40.0, 5.0);
  EXPECT_EQ(sync.state().jumps, 0);
  std::printf("clock sync: worst error after 10 s = %.1f us, drift %.2f ppm\n", worst, sync.state().drift_ppm);
}

TEST(ClockSync, DetectsAStepAndRecovers) {
  ClockSync sync(ClockSyncOptions{});
  for (int i = 0; i < 1000; ++i) sync.add(i * 10000, i * 10000 + 500000 + (i % 7) * 100);
  EXPECT_EQ(sync.state().jumps, 0);
  // The device clock steps back by 1 s (e.g. a reset).
  for (int i = 1000; i < 3000; ++i) sync.add(i * 10000 - 1000000 + 20000, i * 10000 + 500000 + (i % 7) * 100);
  EXPECT_GE(sync.state().jumps, 1);
  EXPECT_FALSE(sync.state().last_jump.empty());
  EXPECT_NEAR(static_cast<double>(sync.to_vehicle(2999 * 10000 - 980000)), 2999 * 10000 + 500000.0, 1000.0);
}

TEST(ClockSync, BadOptionsAreNamed) {
  ClockSyncOptions options;
  options.block_s = 100;
  try {
    ClockSync sync(options);
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("block_s"), std::string::npos);
  }
}

}  // namespace
}  // namespace nadir
