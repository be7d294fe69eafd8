// Consistency of yaw fusion's reported position covariance when the VO
// deltas share errors (delta_integration.h), and the protection level
// (protection_level.h).

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <utility>
#include <vector>

#include "common/geometry.h"
#include "nadir/pose_t.hpp"
#include "processes/vo_solver/delta_uncertainty.h"
#include "processes/yaw_fusion/delta_integration.h"
#include "processes/yaw_fusion/pose_filter.h"
#include "processes/yaw_fusion/protection_level.h"

namespace nadir {
namespace {

// A straight level flight north at `height` whose deltas carry each frame's
// levelling error with opposite signs in consecutive deltas (one attitude per
// frame), a range scale error common to the flight, and independent image
// noise. Each delta's covariance is what vo_solver publishes: the marginal of
// all three. Returns the final horizontal error and the reported covariance.
struct Flight {
  Eigen::Vector2d error;
  Eigen::Matrix2d reported;
};

Flight fly(int frames, double height, double step, const YawFusionOptions& options, double image_sigma, uint32_t seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> unit(0.0, 1.0);
  const double level_sigma = deg_to_rad(options.sensor_uncertainty.roll_pitch_stddev_deg);
  const double scale = options.sensor_uncertainty.range_scale_stddev * unit(rng);
  PoseFilter filter;
  filter.initialise(0.0, 1e-12);
  Eigen::Vector2d prev_eps(level_sigma * unit(rng), level_sigma * unit(rng));
  Eigen::Vector2d truth = Eigen::Vector2d::Zero();
  for (int k = 1; k <= frames; ++k) {
    const Eigen::Vector2d eps(level_sigma * unit(rng), level_sigma * unit(rng));
    const Eigen::Vector2d noise(image_sigma * unit(rng), image_sigma * unit(rng));
    const Eigen::Vector2d true_step(step, 0.0);
    const Eigen::Vector2d measured = true_step * (1.0 + scale) + height * (prev_eps - eps) + noise;
    truth += true_step;
    prev_eps = eps;
    vo_delta_t d{};
    d.utime = k * 71'429;
    d.prev_utime = (k - 1) * 71'429;
    d.dx = measured.x();
    d.dy = measured.y();
    d.altitude_m = height;
    Eigen::Matrix4d cov = Eigen::Matrix4d::Zero();
    cov(0, 0) = cov(1, 1) = 2 * vo::levelling_variance_m2(height, level_sigma) + image_sigma * image_sigma;
    cov(0, 0) += std::pow(options.sensor_uncertainty.range_scale_stddev * step, 2);
    cov(3, 3) = 1e-12;
    integrate_delta(&filter, d, cov, FrameAttitudeNoise{}, FrameAttitudeNoise{}, options);
  }
  return {filter.position().head<2>() - truth, filter.reported_position_covariance().topLeftCorner<2, 2>()};
}

TEST(DeltaIntegration, SharedLevellingAndScaleErrorsGiveAConsistentCovariance) {
  YawFusionOptions options;
  options.ins_yaw_bias_walk_deg_per_sqrt_s = 0.0;  // this test's subject: levelling and scale
  options.sensor_uncertainty.heading_drift_deg_per_s_per_deg = 0.0;
  options.sensor_uncertainty.roll_pitch_stddev_deg = 0.05;
  options.sensor_uncertainty.range_scale_stddev = 0.002;
  const int runs = 400;
  Eigen::Matrix2d sample = Eigen::Matrix2d::Zero();
  Eigen::Matrix2d reported = Eigen::Matrix2d::Zero();
  for (int i = 0; i < runs; ++i) {
    const Flight r = fly(800, 300.0, 2.14, options, 0.02, 100 + i);
    sample += r.error * r.error.transpose() / runs;
    reported = r.reported;
  }
  // Per axis: origin and last frame's levelling (2 h^2 sigma^2), the image
  // noise summed (800 s^2), along track the scale times 1712 m.
  const double levelling = 2 * std::pow(300.0 * deg_to_rad(0.05), 2);
  // (Plus a little of the yaw variance swinging the track; the scale acts on
  // the measured displacement.)
  EXPECT_NEAR(reported(1, 1), levelling + 800 * 0.02 * 0.02, 0.002 * reported(1, 1));
  EXPECT_NEAR(reported(0, 0), reported(1, 1) + std::pow(0.002 * 800 * 2.14, 2), 0.01 * reported(0, 0));
  // The sample covariance of 400 flights agrees within +-20 % (the sample
  // variance of 400 is good to ~7 % at 1 sigma; the seed is fixed). Treated as
  // independent per delta it would be 800 times the levelling: ~30x too large.
  EXPECT_NEAR(sample(0, 0) / reported(0, 0), 1.0, 0.2);
  EXPECT_NEAR(sample(1, 1) / reported(1, 1), 1.0, 0.2);
}

// A flight north then (after a 90 deg turn half way) east with exact
// translations, the heading change of each delta with the model's small
// noise, and after each frame an INS yaw that carries a bias random walk
// and an offset (constant, or first-order Gauss-Markov when the options give
// it a correlation time) plus white noise, fused as yaw_fusion does. The fused yaw
// follows the INS heading within ~20 frames, so it carries the bias, and every
// translation is registered with it: the position error across the track is
// the bias summed over the steps. Returns the final horizontal error and the
// reported covariance.
Flight fly_with_yaw_bias(int frames, double step, const YawFusionOptions& options, double ins_white_deg,
                         uint32_t seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> unit(0.0, 1.0);
  const double dt = 0.071429;
  const double walk = deg_to_rad(options.ins_yaw_bias_walk_deg_per_sqrt_s) * std::sqrt(dt);
  const double dyaw_sigma = deg_to_rad(options.sensor_uncertainty.dyaw_model_stddev_deg);
  const double white = deg_to_rad(ins_white_deg);
  const double offset_sigma = deg_to_rad(options.ins_yaw_bias_stddev_deg);
  const double tau = options.ins_yaw_bias_correlation_s;
  const double decay = tau > 0.0 ? std::exp(-dt / tau) : 1.0;
  double offset = offset_sigma * unit(rng);
  double bias = 0.0;  // the walk's part
  PoseFilter filter;
  filter.initialise(offset + white * unit(rng), white * white);
  double true_yaw = 0.0;
  Eigen::Vector2d truth = Eigen::Vector2d::Zero();
  for (int k = 1; k <= frames; ++k) {
    const double true_dyaw = (k == frames / 2) ? M_PI / 2 : 0.0;
    truth += step * Eigen::Vector2d(std::cos(true_yaw), std::sin(true_yaw));
    true_yaw += true_dyaw;
    bias += walk * unit(rng);
    offset = decay * offset + offset_sigma * std::sqrt(1.0 - decay * decay) * unit(rng);
    vo_delta_t d{};
    d.utime = static_cast<int64_t>(k * dt * 1e6);
    d.prev_utime = static_cast<int64_t>((k - 1) * dt * 1e6);
    d.dx = step;
    d.dyaw = true_dyaw + dyaw_sigma * unit(rng);
    d.altitude_m = 0.0;  // no levelling part in this test
    Eigen::Matrix4d cov = Eigen::Matrix4d::Zero();
    cov(0, 0) = cov(1, 1) = cov(2, 2) = 1e-12;
    cov(3, 3) = dyaw_sigma * dyaw_sigma;
    integrate_delta(&filter, d, cov, FrameAttitudeNoise{}, FrameAttitudeNoise{}, options);
    filter.update_yaw(true_yaw + bias + offset + white * unit(rng), white * white, 1e9);
  }
  return {filter.position().head<2>() - truth, filter.reported_position_covariance().topLeftCorner<2, 2>()};
}

// 400 such flights of 800 frames, 2 m apart (seeds first_seed...): the sample
// covariance of their final errors and the (same for all) reported one.
std::pair<Eigen::Matrix2d, Eigen::Matrix2d> fly_400_with_yaw_bias(const YawFusionOptions& options, double ins_white_deg,
                                                                  uint32_t first_seed) {
  const int runs = 400;
  Eigen::Matrix2d sample = Eigen::Matrix2d::Zero();
  Eigen::Matrix2d reported = Eigen::Matrix2d::Zero();
  for (int i = 0; i < runs; ++i) {
    const Flight r = fly_with_yaw_bias(800, 2.0, options, ins_white_deg, first_seed + static_cast<uint32_t>(i));
    sample += r.error * r.error.transpose() / runs;
    reported = r.reported;
  }
  return {sample, reported};
}

TEST(DeltaIntegration, InsYawBiasIsCarriedIntoThePositionCovariance) {
  YawFusionOptions options;
  options.sensor_uncertainty.dyaw_model_stddev_deg = 0.005;
  options.sensor_uncertainty.heading_drift_deg_per_s_per_deg = 0.0;
  options.ins_yaw_bias_walk_deg_per_sqrt_s = 0.004;
  options.ins_yaw_bias_stddev_deg = 0.02;
  const auto [sample, reported] = fly_400_with_yaw_bias(options, 0.1, 700);
  // 800 m north, then 800 m east: the bias gives both axes ~0.3-0.4 m, the
  // filter's own yaw variance (INS white noise, dyaw noise) much less.
  EXPECT_GT(reported(0, 0), 0.05);
  EXPECT_GT(reported(1, 1), 0.05);
  // Within +-25 % (400 flights: the sample variance is good to ~7 % at 1
  // sigma; the fused yaw lags the INS by ~20 frames, so it holds slightly
  // less than the whole bias). Without the bias term the reported variance
  // would be ~10x too small.
  EXPECT_NEAR(sample(0, 0) / reported(0, 0), 1.0, 0.25);
  EXPECT_NEAR(sample(1, 1) / reported(1, 1), 1.0, 0.25);
  YawFusionOptions without = options;
  without.ins_yaw_bias_walk_deg_per_sqrt_s = 0.0;
  without.ins_yaw_bias_stddev_deg = 0.0;
  const Flight plain = fly_with_yaw_bias(800, 2.0, without, 0.1, 700);
  EXPECT_LT(plain.reported(1, 1), 0.2 * reported(1, 1));
}

// An aided INS's heading error: Gauss-Markov, 0.04 deg stationary, 10 s
// correlation (the flight lasts 57 s, so it decorrelates ~6 times), beside a
// small walk. Carried with its correlation time, the reported covariance
// matches 400 flights; taken as a constant offset of the same sigma it is
// several times too large.
TEST(DeltaIntegration, InsYawGaussMarkovBiasIsCarriedWithItsCorrelationTime) {
  YawFusionOptions options;
  options.sensor_uncertainty.dyaw_model_stddev_deg = 0.005;
  options.sensor_uncertainty.heading_drift_deg_per_s_per_deg = 0.0;
  options.ins_yaw_bias_walk_deg_per_sqrt_s = 0.001;
  options.ins_yaw_bias_stddev_deg = 0.04;
  options.ins_yaw_bias_correlation_s = 10.0;
  const auto [sample, reported] = fly_400_with_yaw_bias(options, 0.01, 1700);
  EXPECT_GT(reported(0, 0), 0.01);
  EXPECT_GT(reported(1, 1), 0.01);
  EXPECT_NEAR(sample(0, 0) / reported(0, 0), 1.0, 0.25);
  EXPECT_NEAR(sample(1, 1) / reported(1, 1), 1.0, 0.25);
  YawFusionOptions constant = options;
  constant.ins_yaw_bias_correlation_s = 0.0;
  const Flight held = fly_with_yaw_bias(800, 2.0, constant, 0.01, 1700);
  EXPECT_GT(held.reported(1, 1), 2.0 * reported(1, 1));
  EXPECT_GT(held.reported(0, 0), 2.0 * reported(0, 0));
}

// A flight whose frames are levelled with a roll error each (0.3 deg, white)
// at a pitch of 1-5 deg, so each frame's levelled heading is off by
// -sin(pitch) * roll error (vo::levelling_yaw_variance_rad2) and each delta's
// dyaw carries curr's term minus prev's, plus a little image noise; its
// published variance is the marginal of both frames' terms and the noise, as
// vo_solver publishes it. After each frame an INS yaw with white noise is
// fused as yaw_fusion does. `pitch_known`: integrate_delta is given the
// frames' pitch (else NaN: every delta's variance taken as independent).
// Returns the final yaw error and the reported yaw variance.
std::pair<double, double> fly_with_heading_levelling(int frames, const YawFusionOptions& options, bool pitch_known,
                                                     uint32_t seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> unit(0.0, 1.0);
  const double rp = deg_to_rad(options.sensor_uncertainty.roll_pitch_stddev_deg);
  const double image = deg_to_rad(0.003);
  const double ins = deg_to_rad(0.3);
  auto pitch_of = [](int k) { return deg_to_rad(3.0 + 2.0 * std::sin(0.01 * k)); };
  PoseFilter filter;
  filter.initialise(ins * unit(rng), ins * ins);
  double prev_term = -std::sin(pitch_of(0)) * rp * unit(rng);
  for (int k = 1; k <= frames; ++k) {
    const double term = -std::sin(pitch_of(k)) * rp * unit(rng);
    vo_delta_t d{};
    d.utime = k * 71'429;
    d.prev_utime = (k - 1) * 71'429;
    d.dx = 2.0;
    d.dyaw = term - prev_term + image * unit(rng);
    prev_term = term;
    Eigen::Matrix4d cov = Eigen::Matrix4d::Identity() * 1e-12;
    cov(3, 3) = vo::levelling_yaw_variance_rad2(pitch_of(k - 1), rp) + vo::levelling_yaw_variance_rad2(pitch_of(k), rp) +
                image * image;
    FrameAttitudeNoise prev, curr;  // pitch NaN: not known
    if (pitch_known) {
      prev.pitch = pitch_of(k - 1);
      curr.pitch = pitch_of(k);
    }
    integrate_delta(&filter, d, cov, prev, curr, options);
    filter.update_yaw(ins * unit(rng), ins * ins, 1e9);  // the true yaw stays 0
  }
  return {filter.yaw(), filter.reported_yaw_variance()};
}

TEST(DeltaIntegration, LevellingHeadingErrorsTelescopeThroughInsYawUpdates) {
  YawFusionOptions options;
  options.ins_yaw_bias_walk_deg_per_sqrt_s = 0.0;  // this test's subject: the levelling heading term
  options.sensor_uncertainty.heading_drift_deg_per_s_per_deg = 0.0;
  options.sensor_uncertainty.roll_pitch_stddev_deg = 0.3;
  const int runs = 400;
  double nees = 0.0, nees_independent = 0.0;
  for (int i = 0; i < runs; ++i) {
    const auto [error, variance] = fly_with_heading_levelling(300, options, true, 900 + i);
    nees += error * error / variance / runs;
    const auto [error2, variance2] = fly_with_heading_levelling(300, options, false, 900 + i);
    nees_independent += error2 * error2 / variance2 / runs;
  }
  // Mean NEES of 400 flights: 1 within +-20 % (its standard error is 7 %).
  EXPECT_NEAR(nees, 1.0, 0.2);
  // Taken as independent per delta, the reported yaw variance is about twice
  // the error's (0.54 here): the chain's heading error does not grow.
  EXPECT_LT(nees_independent, 0.65) << "with the state: " << nees;
}

// A straight flight whose chained heading drifts: each delta's dyaw carries
// a rate that is a first-order Gauss-Markov process (0.03 deg/s, 20 s) times
// its duration, plus white noise, and the published variance only the
// white part, as vo_solver publishes it. After each frame an INS yaw with
// 0.3 deg white noise. `drift_model`: yaw fusion's heading drift stddev
// (deg/s per deg of roll/pitch noise; 0: none). Returns the yaw error at
// every 50th frame and the reported variance there.
std::vector<std::pair<double, double>> fly_with_heading_drift(double drift_model, uint32_t seed) {
  YawFusionOptions options;
  options.ins_yaw_bias_walk_deg_per_sqrt_s = 0.0;
  options.sensor_uncertainty.roll_pitch_stddev_deg = 0.3;
  options.sensor_uncertainty.heading_drift_deg_per_s_per_deg = drift_model;
  options.sensor_uncertainty.heading_drift_time_s = 20.0;
  std::mt19937 rng(seed);
  std::normal_distribution<double> unit(0.0, 1.0);
  const double dt = 0.071429, time_s = 20.0;
  const double drift_sigma = deg_to_rad(0.03), white = deg_to_rad(0.005), ins = deg_to_rad(0.3);
  const double decay = std::exp(-dt / time_s);
  double drift = drift_sigma * unit(rng), true_yaw = 0.0;
  PoseFilter filter;
  filter.initialise(ins * unit(rng), ins * ins);
  std::vector<std::pair<double, double>> out;
  for (int k = 1; k <= 840; ++k) {
    vo_delta_t d{};
    d.utime = static_cast<int64_t>(k * dt * 1e6);
    d.prev_utime = static_cast<int64_t>((k - 1) * dt * 1e6);
    d.dx = 2.0;
    d.dyaw = drift * dt + white * unit(rng);
    drift = decay * drift + drift_sigma * std::sqrt(1.0 - decay * decay) * unit(rng);
    Eigen::Matrix4d cov = Eigen::Matrix4d::Identity() * 1e-12;
    cov(3, 3) = white * white;
    integrate_delta(&filter, d, cov, FrameAttitudeNoise{}, FrameAttitudeNoise{}, options);
    filter.update_yaw(true_yaw + ins * unit(rng), ins * ins, 1e9);
    if (k % 50 == 0) out.emplace_back(angle_difference(filter.yaw(), true_yaw), filter.reported_yaw_variance());
  }
  return out;
}

TEST(DeltaIntegration, HeadingDriftIsEstimatedByTheInsYawUpdates) {
  const int runs = 300;
  double nees = 0.0, nees_without = 0.0, square_error = 0.0, square_error_without = 0.0;
  int n = 0;
  for (int i = 0; i < runs; ++i) {
    const auto with = fly_with_heading_drift(0.1, 1300 + i);
    const auto without = fly_with_heading_drift(0.0, 1300 + i);
    for (size_t j = 2; j < with.size(); ++j) {  // from 100 frames on
      nees += with[j].first * with[j].first / with[j].second;
      square_error += with[j].first * with[j].first;
      nees_without += without[j].first * without[j].first / without[j].second;
      square_error_without += without[j].first * without[j].first;
      ++n;
    }
  }
  // With the drift state: consistent (the model is the truth here, 0.1 x
  // 0.3 = 0.03 deg/s), 1 within +-15 % (samples along a flight are correlated).
  EXPECT_NEAR(nees / n, 1.0, 0.15);
  // Without it the filter trusts the chain: several times over-confident, and
  // the yaw error is larger because the drift is not taken out.
  EXPECT_GT(nees_without / n, 3.0);
  EXPECT_LT(square_error, 0.8 * square_error_without);
}

TEST(DeltaIntegration, WithoutAnAltitudeNothingIsTakenApart) {
  YawFusionOptions options;
  PoseFilter filter;
  filter.initialise(0.0, 1e-6);
  vo_delta_t d{};
  d.utime = 71'429;
  d.dx = 2.0;
  d.altitude_m = 0.0;  // unknown
  Eigen::Matrix4d cov = Eigen::Matrix4d::Identity() * 0.01;
  integrate_delta(&filter, d, cov, FrameAttitudeNoise{}, FrameAttitudeNoise{}, options);
  // The delta's variance (plus the initial yaw variance swinging 2 m: 4e-6).
  EXPECT_NEAR(filter.reported_position_covariance()(1, 1), 0.01 + 4e-6, 1e-9);
}

TEST(ProtectionLevel, NinetyNinePercentOfTheLargestSigma) {
  ProtectionLevelOptions o;
  EXPECT_NEAR(o.sigma_factor(), 3.0349, 1e-4);
  Eigen::Matrix2d cov;
  cov << 4.0, 0.0, 0.0, 1.0;  // sigma 2 m north, 1 m east
  EXPECT_NEAR(horizontal_protection_level(cov, 0, o), 3.0349 * 2.0, 1e-3);
  // Rotated: the largest eigenvalue, not a diagonal entry.
  Eigen::Matrix2d rotated;
  rotated << 2.5, 1.5, 1.5, 2.5;  // eigenvalues 4 and 1
  EXPECT_NEAR(horizontal_protection_level(rotated, 0, o), 3.0349 * 2.0, 1e-3);
  // A Gaussian with this covariance exceeds it at most 1 % of the time.
  std::mt19937 rng(5);
  std::normal_distribution<double> unit(0.0, 1.0);
  int exceeded = 0;
  const int n = 200000;
  for (int i = 0; i < n; ++i) {
    if (std::hypot(2.0 * unit(rng), 1.0 * unit(rng)) > horizontal_protection_level(cov, 0, o)) ++exceeded;
  }
  EXPECT_LT(exceeded, n / 100);
  EXPECT_GT(exceeded, n / 1000);  // not absurdly loose either: ~0.4 % here
}

TEST(ProtectionLevel, FlagsInflateOrMakeItUnavailable) {
  ProtectionLevelOptions o;
  const Eigen::Matrix2d cov = Eigen::Matrix2d::Identity();
  const double base = horizontal_protection_level(cov, 0, o);
  EXPECT_NEAR(horizontal_protection_level(cov, pose_t::FLAG_VO_GAP, o), 2 * base, 1e-12);
  EXPECT_NEAR(horizontal_protection_level(cov, pose_t::FLAG_NO_ALTIMETER, o), 2 * base, 1e-12);
  EXPECT_NEAR(horizontal_protection_level(cov, 16 /* FLAG_COASTING */, o), 2 * base, 1e-12);
  EXPECT_NEAR(horizontal_protection_level(cov, pose_t::FLAG_INS_YAW_REJECTED, o), base, 1e-12);
  EXPECT_EQ(horizontal_protection_level(cov, pose_t::FLAG_INITIALIZING, o), -1.0);
  Eigen::Matrix2d bad = cov;
  bad(0, 0) = std::nan("");
  EXPECT_EQ(horizontal_protection_level(bad, 0, o), -1.0);
}

}  // namespace
}  // namespace nadir
