#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "common/channels.h"
#include "common/config.h"
#include "common/input_checks.h"

namespace nadir {
namespace {

constexpr int64_t kStart = 1000000000;
constexpr int64_t kInsPeriod = 10000;  // 100 Hz

ins_t ins_at(int64_t utime, double roll = 0.01, double yaw = 1.0) {
  ins_t m{};
  m.utime = utime;
  m.roll = roll;
  m.pitch = -0.02;
  m.yaw = yaw;
  return m;
}

altimeter_t range_at(int64_t utime, double range) {
  altimeter_t m{};
  m.utime = utime;
  m.range_m = range;
  m.beam_body[2] = 1.0;
  m.validity = altimeter_t::VALID_OK;
  return m;
}

tracks_t tracks_at(int64_t utime, double x) {
  tracks_t m{};
  m.utime = utime;
  m.prev_utime = utime - 71428;
  m.width = 612;
  m.height = 512;
  m.num_tracks = 1;
  m.track_id = {1};
  m.age = {2};
  m.prev_px = {{100.0f, 100.0f}};
  m.curr_px = {{101.0f, 100.0f}};
  m.prev_norm = {{x, 0.1}};
  m.curr_norm = {{x, 0.1}};
  return m;
}

TEST(InputGate, ImpossibleInsValuesAreRejectedAndCountedByReason) {
  InputGate gate{InputCheckOptions()};
  ASSERT_TRUE(gate.admit(channels::kIns, ins_at(kStart)));
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(gate.admit(channels::kIns, ins_at(kStart + kInsPeriod, nan)));
  EXPECT_FALSE(gate.admit(channels::kIns, ins_at(kStart + kInsPeriod, INFINITY)));
  EXPECT_FALSE(gate.admit(channels::kIns, ins_at(kStart + kInsPeriod, 1e9)));
  EXPECT_FALSE(gate.admit(channels::kIns, ins_at(kStart + kInsPeriod, 0.5)));  // 0.49 rad in 10 ms
  ins_t spinning = ins_at(kStart + kInsPeriod);
  spinning.has_rates = true;
  spinning.angular_rate[2] = 50.0;
  EXPECT_FALSE(gate.admit(channels::kIns, spinning));
  EXPECT_TRUE(gate.admit(channels::kIns, ins_at(kStart + kInsPeriod)));
  EXPECT_EQ(gate.rejected(), 5);
  StatusReport report;
  gate.add_counters(&report);
  EXPECT_EQ(report.counter("rejected.INS.attitude"), 3);
  EXPECT_EQ(report.counter("rejected.INS.attitude_step"), 1);
  EXPECT_EQ(report.counter("rejected.INS.rates"), 1);
  EXPECT_EQ(report.counter("rejected_inputs"), 5);
}

TEST(InputGate, GroundPointsWithBadSizesOrValuesAreRejectedAndCounted) {
  InputGate gate{InputCheckOptions()};
  ground_points_t g{};
  g.utime = kStart;
  g.num_points = 2;
  g.track_id = {11, 12};
  g.position_m = {{1.0f, 2.0f, 150.0f}, {-3.0f, 4.0f, 149.0f}};
  g.depth_sigma_m = {0.5f, 0.7f};
  EXPECT_TRUE(gate.admit(channels::kVoGround, g));
  ground_points_t short_arrays = g;
  short_arrays.utime = kStart + 71429;
  short_arrays.num_points = 3;  // says three, carries two
  EXPECT_FALSE(gate.admit(channels::kVoGround, short_arrays));
  ground_points_t nan_point = short_arrays;
  nan_point.num_points = 2;
  nan_point.position_m[1][2] = std::numeric_limits<float>::quiet_NaN();
  EXPECT_FALSE(gate.admit(channels::kVoGround, nan_point));
  ground_points_t negative_sigma = short_arrays;
  negative_sigma.num_points = 2;
  negative_sigma.depth_sigma_m[0] = -1.0f;
  EXPECT_FALSE(gate.admit(channels::kVoGround, negative_sigma));
  ground_points_t empty{};
  empty.utime = kStart + 71429;
  EXPECT_TRUE(gate.admit(channels::kVoGround, empty));  // nothing seen: nothing wrong
  StatusReport report;
  gate.add_counters(&report);
  EXPECT_EQ(report.counter("rejected.VO_GROUND.size"), 1);
  EXPECT_EQ(report.counter("rejected.VO_GROUND.non_finite"), 2);
}

// An INS that reports 3 deg of white roll/pitch noise per sample (the
// paper's Fig. 8b) moves 4.2 deg sigma from sample to sample: its steps pass
// within six sigmas of the two samples' noise; a step the noise cannot explain
// does not, and without a reported stddev the rate alone decides.
TEST(InputGate, AnAttitudeStepWithinTheReportedNoiseIsPlausible) {
  const double sigma = 3.0 * M_PI / 180.0;
  const auto noisy = [&](int64_t utime, double roll) {
    ins_t m = ins_at(utime, roll);
    m.has_stddev = true;
    m.attitude_stddev[0] = m.attitude_stddev[1] = sigma;
    m.attitude_stddev[2] = 0.001;
    return m;
  };
  InputGate gate{InputCheckOptions()};
  ASSERT_TRUE(gate.admit(channels::kIns, noisy(kStart, 0.0)));
  const double limit = 6.0 * 0.01 + 6.0 * std::sqrt(2.0) * sigma;  // 0.504 rad in 10 ms
  const double three_sigma = 3.0 * std::sqrt(2.0) * sigma;
  EXPECT_TRUE(gate.admit(channels::kIns, noisy(kStart + kInsPeriod, three_sigma)));
  EXPECT_TRUE(gate.admit(channels::kIns, noisy(kStart + 2 * kInsPeriod, three_sigma - (limit - 0.01))));
  EXPECT_FALSE(gate.admit(channels::kIns, noisy(kStart + 3 * kInsPeriod, three_sigma - (limit - 0.01) + (limit + 0.01))));
  InputGate quiet{InputCheckOptions()};
  ASSERT_TRUE(quiet.admit(channels::kIns, ins_at(kStart, 0.0)));
  EXPECT_FALSE(quiet.admit(channels::kIns, ins_at(kStart + kInsPeriod, 3.0 * std::sqrt(2.0) * sigma)));
  InputCheckOptions off;
  off.attitude_step_noise_sigmas = 0.0;
  InputGate strict{off};
  ASSERT_TRUE(strict.admit(channels::kIns, noisy(kStart, 0.0)));
  EXPECT_FALSE(strict.admit(channels::kIns, noisy(kStart + kInsPeriod, 3.0 * std::sqrt(2.0) * sigma)));
}

TEST(InputGate, AFutureSampleNeverBecomesTheReference) {
  InputGate gate{InputCheckOptions()};
  int64_t t = kStart;
  for (int i = 0; i < 10; ++i, t += kInsPeriod) ASSERT_TRUE(gate.admit(channels::kIns, ins_at(t)));
  EXPECT_FALSE(gate.admit(channels::kIns, ins_at(t + 10000000)));  // +10 s
  for (int i = 0; i < 100; ++i, t += kInsPeriod) EXPECT_TRUE(gate.admit(channels::kIns, ins_at(t))) << i;
  // Other channels are judged against the newest accepted time of the gate.
  EXPECT_FALSE(gate.admit(channels::kAltimeter, range_at(t + 10000000, 100.0)));
  EXPECT_TRUE(gate.admit(channels::kAltimeter, range_at(t, 100.0)));
  EXPECT_FALSE(gate.admit(channels::kAltimeter, range_at(t - 20000000, 100.0)));  // 20 s in the past
  EXPECT_FALSE(gate.admit(channels::kAltimeter, range_at(t, 100.0)));             // duplicate time
  EXPECT_EQ(gate.time_rejected(), 4);
  EXPECT_NE(gate.last_rejection().find("ALTIMETER utime"), std::string::npos);
}

TEST(InputGate, AStreamThatReallyMovedIsFollowedAfterAgreeingMessages) {
  InputCheckOptions options;
  options.relock_messages = 5;
  InputGate gate{options};
  int64_t t = kStart;
  for (int i = 0; i < 10; ++i, t += kInsPeriod) ASSERT_TRUE(gate.admit(channels::kIns, ins_at(t)));
  // The device came back with a clock 30 s behind: four samples are
  // rejected, the fifth that agrees with them re-anchors the channel.
  t -= 30000000;
  for (int i = 0; i < 4; ++i, t += kInsPeriod) EXPECT_FALSE(gate.admit(channels::kIns, ins_at(t)));
  for (int i = 0; i < 10; ++i, t += kInsPeriod) EXPECT_TRUE(gate.admit(channels::kIns, ins_at(t)));
  // Samples whose driver does not trust their time are not used.
  ins_t untrusted = ins_at(t);
  untrusted.flags = ins_t::FLAG_TIME_JUMP;
  EXPECT_FALSE(gate.admit(channels::kIns, untrusted));
  EXPECT_TRUE(gate.admit(channels::kIns, ins_at(t)));
}

TEST(InputGate, AnInsStreamAfterAStrayFirstSampleIsFollowed) {
  InputGate gate{InputCheckOptions()};
  ASSERT_TRUE(gate.admit(channels::kIns, ins_at(kStart, 0.8)));  // a stray with a wrong roll
  int64_t t = kStart + kInsPeriod;
  int accepted = 0;
  for (int i = 0; i < 20; ++i, t += kInsPeriod) accepted += gate.admit(channels::kIns, ins_at(t)) ? 1 : 0;
  EXPECT_EQ(accepted, 20 - 4);
}

TEST(InputGate, AltimeterTracksAndDeltasOutsideTheirLimitsAreRejected) {
  InputGate gate{InputCheckOptions()};
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(gate.admit(channels::kAltimeter, range_at(kStart, nan)));
  EXPECT_FALSE(gate.admit(channels::kAltimeter, range_at(kStart, 0.0)));
  EXPECT_FALSE(gate.admit(channels::kAltimeter, range_at(kStart, -5.0)));
  altimeter_t no_return = range_at(kStart, nan);
  no_return.validity = altimeter_t::VALID_NO_RETURN;  // an honest dropout passes on
  EXPECT_TRUE(gate.admit(channels::kAltimeter, no_return));

  EXPECT_FALSE(gate.admit(channels::kTracks, tracks_at(kStart, nan)));
  EXPECT_FALSE(gate.admit(channels::kTracks, tracks_at(kStart, 1e30)));
  tracks_t off_image = tracks_at(kStart, 0.1);
  off_image.curr_px[0][0] = 5000.0f;
  EXPECT_FALSE(gate.admit(channels::kTracks, off_image));
  EXPECT_TRUE(gate.admit(channels::kTracks, tracks_at(kStart, 0.1)));
  EXPECT_FALSE(gate.admit(channels::kTracks, tracks_at(kStart - 10000000, 0.1)));  // 10 s in the past

  vo_delta_t delta{};
  delta.utime = kStart;
  delta.prev_utime = kStart - 71428;
  delta.dx = 2.0;
  EXPECT_TRUE(gate.admit(channels::kVoDelta, delta));
  delta.utime += 71428;
  delta.prev_utime += 71428;
  delta.covariance[2][2] = nan;
  EXPECT_FALSE(gate.admit(channels::kVoDelta, delta));
  delta.covariance[2][2] = 0.0;
  delta.dx = 500.0;  // 7000 m/s
  EXPECT_FALSE(gate.admit(channels::kVoDelta, delta));
}

// A step that a levelling error moved (h * (eps_prev - eps_curr), taken back
// by the next step) is plausible at the height the delta reports, not below.
TEST(InputGate, AStepMovedByTheLevellingErrorIsAllowedInProportionToTheHeight) {
  InputGate gate{InputCheckOptions()};
  const double interval_limit = 250.0 * 0.071428;  // 17.9 m at 250 m/s
  const double allowance = 300.0 * std::tan(25.0 * M_PI / 180.0);  // 139.9 m at 300 m
  vo_delta_t delta{};
  int64_t t = kStart;
  const auto admit = [&](double dx, double altitude) {
    t += 71428;
    delta.utime = t;
    delta.prev_utime = t - 71428;
    delta.dx = dx;
    delta.altitude_m = altitude;
    return gate.admit(channels::kVoDelta, delta);
  };
  // 3 deg white roll/pitch noise at 300 m: a 3-sigma difference moves a step by 67 m.
  EXPECT_TRUE(admit(5.0 + 67.0, 300.0));
  EXPECT_FALSE(admit(5.0 + 67.0, 0.0));
  EXPECT_TRUE(admit(interval_limit + allowance - 0.1, 300.0));
  EXPECT_FALSE(admit(interval_limit + allowance + 0.1, 300.0));
  // No height, or an impossible one: no more than the altimeter's range.
  EXPECT_FALSE(admit(5.0 + 67.0, std::numeric_limits<double>::quiet_NaN()));
  EXPECT_FALSE(admit(1e6, 1e9));
}

TEST(InputCheckOptions, BadValuesNameTheKey) {
  const Config bad = Config::parse("input_checks: {max_ahead_s: -1}", "test.yaml");
  try {
    InputCheckOptions::from_config(bad);
    FAIL() << "expected a ConfigError";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("input_checks.max_ahead_s"), std::string::npos) << e.what();
  }
  const Config defaults = Config::parse("{}", "test.yaml");
  EXPECT_EQ(InputCheckOptions::from_config(defaults).relock_messages, 5);
}

}  // namespace
}  // namespace nadir
