// Synchronisation by sensor time: attitude interpolation and caching, waiting
// for the INS after a frame, altimeter range with a staleness limit.

#include <gtest/gtest.h>

#include "common/geometry.h"
#include "processes/vo_solver/frame_sync.h"

namespace nadir::vo {
namespace {

ins_t ins_at(int64_t utime, double roll, double pitch, double yaw) {
  ins_t m{};
  m.utime = utime;
  m.roll = roll;
  m.pitch = pitch;
  m.yaw = yaw;
  return m;
}

SyncOptions interpolating() {
  SyncOptions options;
  options.attitude_policy = AttitudePolicy::kInterpolate;
  return options;
}

altimeter_t altimeter_at(int64_t utime, double range, int8_t validity = altimeter_t::VALID_OK) {
  altimeter_t m{};
  m.utime = utime;
  m.range_m = range;
  m.beam_body[2] = 1.0;
  m.validity = validity;
  return m;
}

TEST(FrameSync, InterpolatesAttitudeAcrossTheYawWrap) {
  FrameSync sync(interpolating(), Eigen::Vector3d::UnitZ());
  sync.add_ins(ins_at(1000000, 0.01, 0.02, deg_to_rad(179.0)));
  sync.add_ins(ins_at(1010000, 0.03, 0.04, deg_to_rad(-179.0)));
  sync.add_altimeter(altimeter_at(1010000, 200));
  ASSERT_TRUE(sync.ready(1005000));
  const FrameState& s = sync.frame_state(1005000);
  ASSERT_TRUE(s.has_attitude);
  EXPECT_NEAR(s.roll, 0.02, 1e-4);
  EXPECT_NEAR(s.pitch, 0.03, 1e-4);
  EXPECT_NEAR(std::abs(s.yaw), M_PI, 1e-4);
}

TEST(FrameSync, WaitsForTheInsSampleAfterTheFrame) {
  FrameSync sync(interpolating(), Eigen::Vector3d::UnitZ());
  sync.add_altimeter(altimeter_at(2000000, 150));
  sync.add_ins(ins_at(990000, 0, 0, 0));
  EXPECT_FALSE(sync.ready(1000000));
  sync.add_ins(ins_at(1000000, 0.1, 0, 0));
  EXPECT_TRUE(sync.ready(1000000));
  EXPECT_NEAR(sync.frame_state(1000000).roll, 0.1, 1e-12);
}

TEST(FrameSync, AFrameKeepsItsFirstAttitude) {
  // Both pairs a frame belongs to must use the same attitude (eq. 21-23),
  // even if a sample inside its bracket turns up later.
  FrameSync sync(interpolating(), Eigen::Vector3d::UnitZ());
  sync.add_altimeter(altimeter_at(2000000, 150));
  sync.add_ins(ins_at(1000000, 0.0, 0, 0));
  sync.add_ins(ins_at(1020000, 0.2, 0, 0));
  const double first = sync.frame_state(1010000).roll;
  EXPECT_NEAR(first, 0.1, 1e-9);
  sync.add_ins(ins_at(1010000, 0.5, 0, 0));
  EXPECT_EQ(sync.frame_state(1010000).roll, first);
}

TEST(FrameSync, WaitsForTheAltimeterThenGivesUp) {
  SyncOptions options;
  options.altimeter_interpolate = true;
  options.altimeter_wait_us = 300000;
  FrameSync sync(options, Eigen::Vector3d::UnitZ());
  sync.add_altimeter(altimeter_at(900000, 150));
  sync.add_ins(ins_at(1000000, 0, 0, 0));
  sync.add_ins(ins_at(1100000, 0, 0, 0));
  EXPECT_FALSE(sync.ready(1000000)) << "an altimeter sample after the frame may still come";
  sync.add_ins(ins_at(1300000, 0, 0, 0));
  EXPECT_TRUE(sync.ready(1000000));
}

TEST(FrameSync, LatestModeUsesOnlyEarlierRangesAndNeverWaits) {
  SyncOptions options;  // altimeter_mode: latest (default)
  FrameSync sync(options, Eigen::Vector3d::UnitZ());
  sync.add_altimeter(altimeter_at(900000, 150));
  sync.add_ins(ins_at(990000, 0, 0, 0));
  sync.add_ins(ins_at(1000000, 0, 0, 0));
  EXPECT_TRUE(sync.ready(1000000)) << "the INS sample at the frame is enough";
  // At the frame time: must not count either. The frame was ready before it
  // came, so whether it counted would depend on arrival order (live != replay).
  sync.add_altimeter(altimeter_at(1000000, 160));
  sync.add_altimeter(altimeter_at(1010000, 170));  // after the frame: must not count
  const FrameState s = sync.frame_state(1000000);
  EXPECT_TRUE(s.has_range);
  EXPECT_NEAR(s.range_m, 150, 1e-12);
  EXPECT_NEAR(sync.frame_state(995000).range_m, 150, 1e-12);
}

TEST(FrameSync, AltimeterRangeIsInterpolatedAndStalenessFlagged) {
  SyncOptions options;
  options.altimeter_interpolate = true;
  options.altimeter_staleness_us = 200000;
  FrameSync sync(options, Eigen::Vector3d::UnitZ());
  sync.add_altimeter(altimeter_at(1000000, 100));
  sync.add_altimeter(altimeter_at(1050000, 0, altimeter_t::VALID_NO_RETURN));  // ignored
  sync.add_altimeter(altimeter_at(1100000, 110));
  FrameState s = sync.frame_state(1025000);
  EXPECT_TRUE(s.has_range);
  EXPECT_FALSE(s.range_stale);
  EXPECT_NEAR(s.range_m, 102.5, 1e-9);
  s = sync.frame_state(1250000);  // 150 ms after the last valid: fresh enough
  EXPECT_FALSE(s.range_stale);
  EXPECT_NEAR(s.range_m, 110, 1e-9);
  s = sync.frame_state(1400000);  // 300 ms: stale, nearest used and flagged
  EXPECT_TRUE(s.has_range);
  EXPECT_TRUE(s.range_stale);
  EXPECT_EQ(sync.invalid_altimeter_samples(), 1);

  FrameSync none(options, Eigen::Vector3d::UnitZ());
  none.add_altimeter(altimeter_at(1000000, 0, altimeter_t::VALID_OUT_OF_RANGE));
  EXPECT_FALSE(none.frame_state(1000000).has_range);
}

TEST(FrameSync, InsGapMeansNoAttitude) {
  SyncOptions options;
  options.max_ins_gap_us = 100000;
  FrameSync sync(options, Eigen::Vector3d::UnitZ());
  sync.add_ins(ins_at(1000000, 0, 0, 0));
  sync.add_ins(ins_at(1500000, 0, 0, 0));
  EXPECT_FALSE(sync.frame_state(1250000).has_attitude);
  EXPECT_TRUE(sync.frame_state(1510000).has_attitude) << "10 ms past the last sample is within the extrapolation limit";
  EXPECT_FALSE(sync.frame_state(1600000).has_attitude);
}

TEST(FrameSync, OptionsAreChecked) {
  SyncOptions bad;
  bad.max_pending_frames = 0;
  EXPECT_THROW(bad.Check(), std::invalid_argument);
}

}  // namespace
}  // namespace nadir::vo
