// INS and altimeter buffers: order-independent insertion, interpolation at
// frame time (angle-aware), limits on bracketing and age.

#include <gtest/gtest.h>

#include <cmath>

#include "common/geometry.h"
#include "processes/yaw_fusion/sensor_history.h"

namespace nadir {
namespace {

AttitudeSample sample(int64_t utime, double yaw_deg, double variance = 1e-4) {
  AttitudeSample s;
  s.utime = utime;
  s.roll = 0.001 * static_cast<double>(utime);
  s.pitch = -0.002 * static_cast<double>(utime);
  s.yaw = deg_to_rad(yaw_deg);
  s.yaw_variance = variance;
  return s;
}

TEST(InsHistory, InterpolatesAcrossTheYawWrap) {
  InsHistory h;
  ASSERT_TRUE(h.add(sample(100, 179.0)));
  ASSERT_TRUE(h.add(sample(200, -179.0)));
  const auto a = h.at(150, 1000);
  ASSERT_TRUE(a.has_value());
  EXPECT_NEAR(std::abs(a->yaw), M_PI, 1e-12);
  EXPECT_NEAR(a->roll, 0.15, 1e-12);
  const auto b = h.at(125, 1000);
  EXPECT_NEAR(b->yaw, deg_to_rad(179.5), 1e-12);
}

TEST(InsHistory, SameAnswerWhateverTheInsertionOrder) {
  InsHistory forward;
  InsHistory backward;
  for (int i = 0; i < 10; ++i) forward.add(sample(i * 10, i * 3.0));
  for (int i = 9; i >= 0; --i) backward.add(sample(i * 10, i * 3.0));
  EXPECT_FALSE(backward.add(sample(50, 0.0)));  // duplicate time
  for (int64_t t = 0; t <= 90; t += 7) {
    EXPECT_EQ(forward.at(t, 100)->yaw, backward.at(t, 100)->yaw) << t;
  }
  EXPECT_EQ(forward.newest_utime(), 90);
}

TEST(InsHistory, LimitsBracketAndMarksUnusableYaw) {
  InsHistory h;
  h.add(sample(0, 10.0));
  h.add(sample(1000, 20.0, -1.0));
  EXPECT_FALSE(h.at(500, 400).has_value());        // bracket too wide, both too far
  EXPECT_NEAR(h.at(100, 400)->yaw, deg_to_rad(10.0), 1e-12);  // nearest within reach
  EXPECT_LT(h.at(500, 2000)->yaw_variance, 0.0);   // one side unusable -> unusable
  h.add(sample(2000, 30.0));
  h.forget_before(1900);
  EXPECT_EQ(h.size(), 3u);  // keeps the two samples before 1900 (propagation without rates needs both)
  h.forget_before(2000);
  EXPECT_EQ(h.size(), 2u);
}

TEST(InsHistory, PropagateUsesOnlySamplesAtOrBeforeTheQuery) {
  // Yaw 10 deg/s without INS rates: the rate comes from the two newest
  // samples, so the attitude between them and the next sample is exact, and
  // it does not change when the next sample arrives.
  auto level = [](int64_t utime, double yaw_deg) {
    AttitudeSample s = sample(utime, yaw_deg);
    s.roll = s.pitch = 0.0;
    return s;
  };
  InsHistory h;
  h.add(level(0, 10.0));
  h.add(level(10000, 10.1));
  const auto early = h.at(14000, 500000, AttitudePolicy::kPropagate);
  ASSERT_TRUE(early.has_value());
  EXPECT_NEAR(early->yaw, deg_to_rad(10.14), 1e-12);
  EXPECT_TRUE(h.complete_at(14000)) << "the next sample (20 ms) cannot be at or before 14 ms";
  EXPECT_FALSE(h.complete_at(19000));
  h.add(level(20000, 10.3));  // not on the straight line: must not matter for 14 ms
  EXPECT_EQ(h.at(14000, 500000, AttitudePolicy::kPropagate)->yaw, early->yaw);
  EXPECT_NE(h.at(14000, 500000)->yaw, early->yaw) << "interpolation does use the later sample";
}

// The INS yaw variance is one sample's white noise; a frame's yaw made from
// two samples carries the share of it the attitude policy leaves
// (attitude_propagation.h), and yaw fusion weighs the INS yaw by that.
TEST(InsHistory, FrameYawVarianceIsTheWhiteNoiseLeftInTheFrameAttitude) {
  const double v = 4e-6;
  InsHistory with_rates, without_rates;
  for (int64_t t : {0, 10000}) {
    AttitudeSample s = sample(t, 10.0, v);
    without_rates.add(s);
    s.has_rate = true;
    with_rates.add(s);
  }
  const auto averaged = with_rates.at(14000, 500000, AttitudePolicy::kPropagate);
  ASSERT_TRUE(averaged.has_value());
  EXPECT_DOUBLE_EQ(averaged->white_noise_share, 0.5);
  EXPECT_DOUBLE_EQ(averaged->yaw_variance, 0.5 * v);
  const auto interpolated = with_rates.at(2500, 500000, AttitudePolicy::kInterpolate);
  EXPECT_DOUBLE_EQ(interpolated->yaw_variance, (0.75 * 0.75 + 0.25 * 0.25) * v);
  // Carried 0.4 sample intervals past the newest with the rate between the two: (1.4^2 + 0.4^2) v.
  const auto carried = without_rates.at(14000, 500000, AttitudePolicy::kPropagate);
  EXPECT_NEAR(carried->yaw_variance, (1.4 * 1.4 + 0.4 * 0.4) * v, 1e-18);
  const auto at_sample = without_rates.at(10000, 500000, AttitudePolicy::kPropagate);
  EXPECT_DOUBLE_EQ(at_sample->yaw_variance, v);
  EXPECT_DOUBLE_EQ(at_sample->white_noise_share, 1.0);
  // Unusable stays unusable.
  InsHistory unusable;
  for (int64_t t : {0, 10000}) {
    AttitudeSample s = sample(t, 10.0, -1.0);
    s.has_rate = true;
    unusable.add(s);
  }
  EXPECT_LT(unusable.at(14000, 500000, AttitudePolicy::kPropagate)->yaw_variance, 0.0);
}

TEST(AltimeterHistory, VerticalHeightFromTiltedBeamAndAge) {
  AltimeterHistory h;
  h.add({1000, 100.0, Eigen::Vector3d::UnitZ()});
  h.add({2000, 110.0, Eigen::Vector3d::UnitZ()});
  EXPECT_NEAR(*h.height_agl(1500, 1000, 0.0, 0.0), 105.0, 1e-12);
  // Pitched 10 deg: the beam's vertical component is cos(10 deg).
  EXPECT_NEAR(*h.height_agl(1000, 1000, 0.0, deg_to_rad(10.0)), 100.0 * std::cos(deg_to_rad(10.0)), 1e-9);
  EXPECT_FALSE(h.height_agl(5000, 1000, 0.0, 0.0).has_value());
  EXPECT_NEAR(*h.height_agl(2500, 1000, 0.0, 0.0), 110.0, 1e-12);
}

// Frame intervals tile the samples: each one in exactly one [from, to).
TEST(AltimeterHistory, SamplesBetweenTwoTimesTileTheHistory) {
  AltimeterHistory h;
  for (int64_t t = 1000; t <= 9000; t += 1000) h.add({t, static_cast<double>(t), Eigen::Vector3d::UnitZ()});
  auto times = [&](int64_t from, int64_t to) {
    std::vector<int64_t> out;
    for (const RangeSample& s : h.between(from, to)) out.push_back(s.utime);
    return out;
  };
  EXPECT_EQ(times(2000, 4000), (std::vector<int64_t>{2000, 3000}));
  EXPECT_EQ(times(1500, 2500), (std::vector<int64_t>{2000}));
  EXPECT_EQ(times(2500, 2900), std::vector<int64_t>{});
  EXPECT_EQ(times(0, 100000).size(), 9u);
  size_t total = 0;
  for (int64_t from = 0; from < 10000; from += 700) total += h.between(from, from + 700).size();
  EXPECT_EQ(total, 9u);
}

}  // namespace
}  // namespace nadir
