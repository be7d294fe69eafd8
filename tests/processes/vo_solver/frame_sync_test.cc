// Synchronisation by sensor time: attitude interpolation and caching, waiting
// for the INS after a frame, altimeter range with a staleness limit.

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <utility>

#include "common/geometry.h"
#include "processes/vo_solver/frame_sync.h"
#include "processes/vo_solver/vo_solver_options.h"

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

TEST(FrameSync, ALatestRangeCarriesItsAgeAndTheAttitudeItWasSampledAt) {
  // The range is 30 ms older than the frame: it was measured from where the
  // aircraft was then, along the beam as the body was turned then.
  FrameSync sync(interpolating(), Eigen::Vector3d::UnitZ());  // altimeter_mode latest
  sync.add_ins(ins_at(960000, 0.00, 0.10, 0));
  sync.add_ins(ins_at(980000, 0.04, 0.06, 0));
  sync.add_ins(ins_at(1000000, 0.08, 0.02, 0));
  sync.add_altimeter(altimeter_at(970000, 150));
  const FrameState s = sync.frame_state(1000000);
  EXPECT_EQ(s.range_age_us, 30000);
  EXPECT_NEAR(s.roll, 0.08, 1e-12);
  // Slerped between the INS samples at 960 and 980 ms: within 1e-4 of linear.
  EXPECT_NEAR(s.range_roll, 0.02, 1e-4);
  EXPECT_NEAR(s.range_pitch, 0.08, 1e-4);
  // Interpolated to the frame: no age, the frame's own attitude.
  SyncOptions interpolate = interpolating();
  interpolate.altimeter_interpolate = true;
  FrameSync at_frame(interpolate, Eigen::Vector3d::UnitZ());
  at_frame.add_ins(ins_at(980000, 0.04, 0.06, 0));
  at_frame.add_ins(ins_at(1000000, 0.08, 0.02, 0));
  at_frame.add_altimeter(altimeter_at(970000, 150));
  at_frame.add_altimeter(altimeter_at(1070000, 160));
  const FrameState t = at_frame.frame_state(1000000);
  EXPECT_NEAR(t.range_m, 153, 1e-9);
  EXPECT_EQ(t.range_age_us, 0);
  EXPECT_EQ(t.range_roll, t.roll);
  EXPECT_EQ(t.range_pitch, t.pitch);
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

// A camera stamping its frames `offset` before the exposure and an
// altimeter measuring scale * true + bias; with the calibration in the sync
// options the frame's attitude and range are the true ones at the exposure,
// exactly (noise-free, attitude and range linear in time).
TEST(FrameSync, CalibrationRemovesTimeOffsetAndAltimeterScaleAndBias) {
  const int64_t offset_us = 3000;
  const double scale = 1.01, bias_m = 0.3;
  auto roll_at = [](int64_t t) { return 0.1 * static_cast<double>(t) * 1e-6 - 0.05; };  // 0.1 rad/s
  auto range_at = [](int64_t t) { return 200.0 + 5.0 * static_cast<double>(t) * 1e-6; };
  SyncOptions calibrated = interpolating();
  calibrated.altimeter_interpolate = true;  // linear interpolation of a linear range is exact
  calibrated.calibration.camera_time_offset_us = offset_us;
  calibrated.calibration.altimeter_range_scale = scale;
  calibrated.calibration.altimeter_range_bias_m = bias_m;
  calibrated.Check();
  SyncOptions uncalibrated = calibrated;
  uncalibrated.calibration = SensorCalibration{};
  FrameSync sync(calibrated, Eigen::Vector3d::UnitZ());
  FrameSync plain(uncalibrated, Eigen::Vector3d::UnitZ());
  for (int64_t t = 0; t <= 3000000; t += 10000) {
    sync.add_ins(ins_at(t, roll_at(t), 0.0, 0.0));
    plain.add_ins(ins_at(t, roll_at(t), 0.0, 0.0));
  }
  for (int64_t t = 0; t <= 3000000; t += 50000) {
    sync.add_altimeter(altimeter_at(t, scale * range_at(t) + bias_m));
    plain.add_altimeter(altimeter_at(t, scale * range_at(t) + bias_m));
  }
  int frames = 0;
  for (int64_t exposure = 1000000; exposure < 2000000; exposure += 71429) {
    const int64_t stamp = exposure - offset_us;
    ASSERT_TRUE(sync.ready(stamp));
    const FrameState& s = sync.frame_state(stamp);
    ASSERT_TRUE(s.has_attitude && s.has_range);
    EXPECT_NEAR(s.roll, roll_at(exposure), 1e-12) << exposure;
    EXPECT_NEAR(s.range_m, range_at(exposure), 1e-9) << exposure;
    // Without the calibration: the attitude of 3 ms earlier, the raw range.
    const FrameState& p = plain.frame_state(stamp);
    EXPECT_NEAR(p.roll, roll_at(stamp), 1e-12);
    EXPECT_GT(std::abs(p.range_m - range_at(exposure)), 2.0);
    ++frames;
  }
  EXPECT_EQ(frames, 14);
}

TEST(FrameSync, DefaultCalibrationIsTheIdentityBitForBit) {
  const SensorCalibration none;
  for (double r : {0.0, 1e-300, 0.1, 123.456789012345, 4321.0 / 3.0, 1e9}) EXPECT_EQ(none.true_range(r), r);
  for (int64_t t : {int64_t{0}, int64_t{-5}, int64_t{1764000000123456}}) EXPECT_EQ(none.exposure_utime(t), t);
}

TEST(FrameSync, CalibrationKeysAreReadAndCheckedByName) {
  const SensorCalibration c = SensorCalibration::from_config(Config::parse(
      "camera: {time_offset_us: -2042, lever_arm_m: [1.5, 0, 0.3]}\n"
      "altimeter: {range_scale: 1.00762, range_bias_m: -1.242, lever_arm_m: [1.2, 0.2, 0.4],"
      " beam_misalignment_deg: [0.2, -0.15]}\n",
      "cal.yaml"));
  EXPECT_EQ(c.camera_time_offset_us, -2042);
  EXPECT_EQ(c.altimeter_range_scale, 1.00762);
  EXPECT_EQ(c.altimeter_range_bias_m, -1.242);
  EXPECT_EQ(c.camera_lever_arm_m, Eigen::Vector3d(1.5, 0.0, 0.3));
  EXPECT_EQ(c.altimeter_lever_arm_m, Eigen::Vector3d(1.2, 0.2, 0.4));
  EXPECT_NEAR(c.altimeter_beam_misalignment_rad.x(), deg_to_rad(0.2), 1e-15);
  EXPECT_NEAR(c.altimeter_beam_misalignment_rad.y(), deg_to_rad(-0.15), 1e-15);
  const std::pair<const char*, const char*> bad[] = {
      {"camera: {time_offset_us: 1000000}\n", "camera.time_offset_us"},
      {"camera: {time_offset_us: 2.5}\n", "camera.time_offset_us"},  // integer microseconds
      {"altimeter: {range_scale: 0.5}\n", "altimeter.range_scale"},
      {"altimeter: {range_scale: 2.5}\n", "altimeter.range_scale"},
      {"altimeter: {range_bias_m: -100}\n", "altimeter.range_bias_m"},
      {"altimeter: {range_bias_m: .nan}\n", "altimeter.range_bias_m"},
      {"camera: {lever_arm_m: [1.5, 0]}\n", "camera.lever_arm_m"},
      {"camera: {lever_arm_m: [25, 0, 0]}\n", "camera.lever_arm_m"},
      {"altimeter: {lever_arm_m: [0, .nan, 0]}\n", "altimeter.lever_arm_m"},
      {"altimeter: {beam_misalignment_deg: [11, 0]}\n", "altimeter.beam_misalignment_deg"},
      {"altimeter: {beam_misalignment_deg: [0.1, 0.1, 0.1]}\n", "altimeter.beam_misalignment_deg"},
  };
  for (const auto& [yaml, key] : bad) {
    try {
      SensorCalibration::from_config(Config::parse(yaml, "bad.yaml"));
      ADD_FAILURE() << "expected ConfigError for " << yaml;
    } catch (const ConfigError& e) {
      EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("bad.yaml"), std::string::npos) << e.what();
    }
  }
  SyncOptions options;
  options.calibration.altimeter_range_scale = 0.0;
  EXPECT_THROW(options.Check(), ConfigError);
  // The solver's options carry them into its FrameSync.
  const VoSolverOptions solver = VoSolverOptions::from_config(Config::parse(
      "camera: {width: 612, height: 512, fx: 398.79, fy: 398.79, cx: 305.5, cy: 255.5, time_offset_us: 3000}\n"
      "altimeter: {range_scale: 1.01, range_bias_m: 0.3}\n",
      "cal.yaml"));
  EXPECT_EQ(solver.sync.calibration.camera_time_offset_us, 3000);
  EXPECT_EQ(solver.sync.calibration.altimeter_range_scale, 1.01);
  EXPECT_EQ(solver.sync.calibration.altimeter_range_bias_m, 0.3);
}

}  // namespace
}  // namespace nadir::vo
