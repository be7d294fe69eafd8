// The image scale and the heading offset against GNSS
// (tools/calibrate/gps_scale.h): exact on noise-free steps, the median holds
// against mismatched pairs, flagged and short pairs are not used.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "common/config.h"
#include "tools/calibrate/calibration.h"
#include "tools/calibrate/gps_scale.h"

namespace nadir::calibrate {
namespace {

constexpr int32_t kUnsolved = 1 | 2 | 8 | 16;

// A flight along a curve sampled at 1 Hz; a VO step per second whose length
// is the true one times `vo_scale` (a focal length or height error).
struct Track {
  std::vector<PositionSample> positions;
  std::vector<VoStep> steps;
};

// The recorded yaw of each position is the steps' true heading minus
// `heading_offset` (rad): image heading = recorded yaw + offset.
Track curved_flight(int n, double vo_scale, double heading_offset = 0.0) {
  Track t;
  for (int i = 0; i <= n; ++i) {
    const double s = i * 20.0;  // 20 m/s
    t.positions.push_back({static_cast<int64_t>(i) * 1000000, Eigen::Vector3d(200.0 * std::sin(s / 200.0),
                                                                              200.0 * (1.0 - std::cos(s / 200.0)),
                                                                              -100.0 - 0.1 * i),
                           0.3 * i - heading_offset});
  }
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3d d = t.positions[i + 1].position_ned - t.positions[i].position_ned;
    // The level frame of the previous frame: any rotation of (dx, dy) about z keeps the length.
    const double heading = 0.3 * i;
    const double dx = std::cos(heading) * d.x() + std::sin(heading) * d.y();
    const double dy = -std::sin(heading) * d.x() + std::cos(heading) * d.y();
    t.steps.push_back({t.positions[i].utime, t.positions[i + 1].utime, vo_scale * dx, vo_scale * dy, 0});
  }
  return t;
}

TEST(GpsScale, ExactOnNoiseFreeSteps) {
  const Track t = curved_flight(50, 1.2);
  const GpsScaleFit fit = fit_gps_scale(t.steps, t.positions, kUnsolved, 2.0, 4.0);
  EXPECT_EQ(fit.pairs, 50);
  EXPECT_EQ(fit.rejected, 0);
  EXPECT_NEAR(fit.scale, 1.0 / 1.2, 1e-12);
  EXPECT_NEAR(fit.sigma, 0.0, 1e-12);
}

TEST(GpsScale, StepsBetweenPositionSamplesAreInterpolated) {
  const Track t = curved_flight(50, 0.9);
  // Steps from mid-second to mid-second: the positions are interpolated.
  std::vector<VoStep> steps;
  for (size_t i = 0; i + 2 < t.positions.size(); ++i) {
    const Eigen::Vector3d a = 0.5 * (t.positions[i].position_ned + t.positions[i + 1].position_ned);
    const Eigen::Vector3d b = 0.5 * (t.positions[i + 1].position_ned + t.positions[i + 2].position_ned);
    steps.push_back({t.positions[i].utime + 500000, t.positions[i + 1].utime + 500000, 0.9 * (b - a).x(),
                     0.9 * (b - a).y(), 0});
  }
  const GpsScaleFit fit = fit_gps_scale(steps, t.positions, kUnsolved, 2.0, 4.0);
  EXPECT_EQ(fit.pairs, static_cast<int64_t>(steps.size()));
  EXPECT_NEAR(fit.scale, 1.0 / 0.9, 1e-12);
}

TEST(GpsScale, NoisyStepsWithMismatchesStayWithinThreeSigma) {
  Track t = curved_flight(200, 1.1);
  std::mt19937_64 rng(5);
  std::normal_distribution<double> noise(0.0, 0.5);  // 0.5 m per axis on 20 m steps
  for (size_t i = 0; i < t.steps.size(); ++i) {
    t.steps[i].dx += noise(rng);
    t.steps[i].dy += noise(rng);
    if (i % 10 == 3) t.steps[i].dx *= 3.0;  // a mismatched pair: far off
  }
  const GpsScaleFit fit = fit_gps_scale(t.steps, t.positions, kUnsolved, 2.0, 4.0);
  EXPECT_GT(fit.sigma, 0.0);
  EXPECT_LT(fit.sigma, 0.01);
  EXPECT_NEAR(fit.scale, 1.0 / 1.1, 3.0 * fit.sigma);
  EXPECT_GE(fit.rejected, 15);  // the 20 mismatched pairs, most of them dropped as outliers
}

TEST(GpsScale, FlaggedShortAndUncoveredPairsAreNotUsed) {
  Track t = curved_flight(30, 1.0);
  t.steps[0].quality = 8;                 // not converged: unsolved
  t.steps[1].quality = 64;                // high residual: solved (flagged), used
  t.steps[2].dx = t.steps[2].dy = 0.0;    // no VO motion: rejected
  t.steps[3].prev_utime = -5000000;       // before the GNSS span
  t.steps[4].dx = std::nan("");           // non-finite: rejected
  const GpsScaleFit fit = fit_gps_scale(t.steps, t.positions, kUnsolved, 2.0, 4.0);
  EXPECT_EQ(fit.pairs, 26);
  EXPECT_EQ(fit.rejected, 2);
  EXPECT_NEAR(fit.scale, 1.0, 1e-12);
  const GpsScaleFit none = fit_gps_scale({}, t.positions, kUnsolved, 2.0, 4.0);
  EXPECT_EQ(none.pairs, 0);
  // Baselines under the minimum carry mostly GNSS noise.
  const GpsScaleFit long_only = fit_gps_scale(t.steps, t.positions, kUnsolved, 25.0, 4.0);
  EXPECT_EQ(long_only.pairs, 0);
}

TEST(HeadingOffset, ExactOnNoiseFreeStepsAndAcrossTheHalfTurn) {
  for (double offset_deg : {0.0, 11.5, -7.25, 179.0, -179.5}) {
    const double offset = offset_deg * M_PI / 180.0;
    const Track t = curved_flight(50, 1.2, offset);
    const HeadingOffsetFit fit = fit_heading_offset(t.steps, t.positions, kUnsolved, 2.0, 4.0);
    EXPECT_EQ(fit.pairs, 50) << offset_deg;
    EXPECT_NEAR(std::remainder(fit.offset_rad - offset, 2.0 * M_PI), 0.0, 1e-12) << offset_deg;
    EXPECT_NEAR(fit.sigma_rad, 0.0, 1e-12) << offset_deg;
  }
}

TEST(HeadingOffset, NoisyStepsWithMismatchesStayWithinThreeSigma) {
  const double offset = 11.5 * M_PI / 180.0;
  Track t = curved_flight(200, 1.0, offset);
  std::mt19937_64 rng(9);
  std::normal_distribution<double> noise(0.0, 0.5);  // 0.5 m per axis on 20 m steps: ~1.4 deg
  for (size_t i = 0; i < t.steps.size(); ++i) {
    t.steps[i].dx += noise(rng);
    t.steps[i].dy += noise(rng);
    if (i % 10 == 3) std::swap(t.steps[i].dx, t.steps[i].dy);  // a pair solved in a wrong direction
  }
  const HeadingOffsetFit fit = fit_heading_offset(t.steps, t.positions, kUnsolved, 2.0, 4.0);
  EXPECT_GT(fit.sigma_rad, 0.0);
  EXPECT_LT(fit.sigma_rad, 0.005);
  EXPECT_NEAR(fit.offset_rad, offset, 3.0 * fit.sigma_rad);
  EXPECT_GE(fit.rejected, 15);
}

TEST(HeadingOffset, FlaggedAndShortPairsAreNotUsed) {
  Track t = curved_flight(30, 1.0, 0.1);
  t.steps[0].quality = 8;             // not converged
  t.steps[2].dx = t.steps[2].dy = 0.0;
  const HeadingOffsetFit fit = fit_heading_offset(t.steps, t.positions, kUnsolved, 2.0, 4.0);
  EXPECT_EQ(fit.pairs, 28);
  EXPECT_EQ(fit.rejected, 1);
  EXPECT_NEAR(fit.offset_rad, 0.1, 1e-12);
  EXPECT_EQ(fit_heading_offset({}, t.positions, kUnsolved, 2.0, 4.0).pairs, 0);
}

// The error for a segment with too few pairs counts them (a photo survey's
// first seconds): it once printed a double through %lld.
TEST(GpsScale, TooFewPairsAreCountedInTheError) {
  const Track t = curved_flight(30, 1.0);
  FlightData data;
  for (const PositionSample& p : t.positions) {
    data.ins.push_back({p.utime, 0.0, 0.0, p.yaw, false, Eigen::Vector3d::Zero(), p.position_ned});
  }
  data.vo_steps.assign(t.steps.begin(), t.steps.begin() + 8);
  CalibrationOptions options;
  options.gps_scale_target = CalibrationOptions::GpsScaleTarget::kFocal;
  options.gps_scale_only = true;
  options.estimate_focal = false;  // the focal length comes from the GNSS scale
  const Config config = Config::load_file(std::string(NADIR_SOURCE_DIR) + "/config/default.yaml");
  try {
    calibrate(data, config, options);
    FAIL() << "a GNSS scale from 8 pairs";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("GNSS scale: 8 solved frame pair(s)"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("10 needed"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace nadir::calibrate
