// Paper section 6 (eq. 19-23) as a test. Over a long constant-altitude flight,
// INS roll/pitch noise enters each frame pair as the difference of the two
// frames' errors times the height, so with one attitude per frame (cached, as
// the node does) the sum telescopes: |e_x| <= 2 E_pitch h, |e_y| <= 2 E_roll h,
// whatever the distance. Yaw noise, used to register each translation in the
// world, is not telescoped and the error grows with distance.

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "common/geometry.h"
#include "processes/vo_solver/plane_model.h"
#include "processes/vo_solver/translation_solver.h"
#include "tests/processes/vo_solver/synthetic_scene.h"

namespace nadir::vo {
namespace {

struct Flight {
  // Per frame, in the vehicle's level heading frame: position error.
  std::vector<Eigen::Vector2d> error;
  double vertical_error = 0;  // sum of dz minus the true (zero) climb, at the end
  double max_roll_error = 0, max_pitch_error = 0;  // E_theta, E_psi of eq. (22-23)
};

enum class Noise { kRollPitchCached, kRollPitchPerPair, kYaw };

constexpr double kHeight = 300.0;      // constant height above level ground (paper Table 1, first flight)
constexpr double kStep = 30.0 / 14.0;  // 30 m/s at 14 Hz
constexpr int kFrames = 800;           // 1.7 km
constexpr double kHeading = 0.6;       // straight flight: world error = vehicle-frame error rotated

Flight fly(Noise noise, uint32_t seed, const SolverOptions& options = SolverOptions()) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> gauss(0.0, deg_to_rad(3.0));
  Flight flight;
  // True attitude: gentle oscillations, as a helicopter holding a line.
  auto roll = [](int k) { return deg_to_rad(2.0) * std::sin(0.05 * k); };
  auto pitch = [](int k) { return deg_to_rad(-1.5) + deg_to_rad(1.0) * std::cos(0.031 * k); };
  // The attitude the solver sees for each frame, drawn once per frame.
  std::vector<double> roll_seen(kFrames), pitch_seen(kFrames), yaw_seen(kFrames);
  for (int k = 0; k < kFrames; ++k) {
    const bool rp = noise != Noise::kYaw;
    const double er = rp ? gauss(rng) : 0.0, ep = rp ? gauss(rng) : 0.0;
    roll_seen[k] = roll(k) + er;
    pitch_seen[k] = pitch(k) + ep;
    yaw_seen[k] = kHeading + (noise == Noise::kYaw ? gauss(rng) : 0.0);
    flight.max_roll_error = std::max(flight.max_roll_error, std::abs(er));
    flight.max_pitch_error = std::max(flight.max_pitch_error, std::abs(ep));
  }
  Eigen::Vector2d estimated = Eigen::Vector2d::Zero(), truth = Eigen::Vector2d::Zero();
  flight.error.push_back(Eigen::Vector2d::Zero());
  for (int k = 1; k < kFrames; ++k) {
    testing::SceneSpec s;
    s.height_m = kHeight;
    s.prev_roll = roll(k - 1);
    s.prev_pitch = pitch(k - 1);
    s.curr_roll = roll(k);
    s.curr_pitch = pitch(k);
    s.prev_yaw = s.curr_yaw = kHeading;
    s.translation = Eigen::Vector3d(kStep, 0.0, 0.0);
    s.num_features = 60;
    s.seed = seed * 100000 + k;
    testing::Scene scene = testing::make_scene(s);
    scene.pair.prev_roll = roll_seen[k - 1];
    scene.pair.prev_pitch = pitch_seen[k - 1];
    scene.pair.curr_roll = roll_seen[k];
    scene.pair.curr_pitch = pitch_seen[k];
    if (noise == Noise::kRollPitchPerPair) {
      // What happens without the per-frame cache: frame k-1 is re-measured.
      scene.pair.prev_roll = roll(k - 1) + gauss(rng);
      scene.pair.prev_pitch = pitch(k - 1) + gauss(rng);
    }
    const Estimate est = solve(scene.pair, options);
    EXPECT_FALSE(est.quality & (kNotConverged | kTooFewFeatures)) << "frame " << k;
    // Register in the world with the yaw the navigation would use.
    estimated += rot_z(yaw_seen[k - 1]).topLeftCorner<2, 2>() * est.translation.head<2>();
    truth += rot_z(kHeading).topLeftCorner<2, 2>() * s.translation.head<2>();
    flight.error.push_back(rot_z(kHeading).topLeftCorner<2, 2>().transpose() * (estimated - truth));
    flight.vertical_error += est.translation.z() - s.translation.z();
  }
  return flight;
}

double rms_at(const std::vector<Flight>& flights, int k) {
  double sum = 0;
  for (const Flight& f : flights) sum += f.error[k].squaredNorm();
  return std::sqrt(sum / flights.size());
}

TEST(Telescoping, RollPitchNoiseStaysUnderThePaperBound) {
  std::vector<Flight> flights;
  for (uint32_t seed = 1; seed <= 4; ++seed) {
    flights.push_back(fly(Noise::kRollPitchCached, seed));
    const Flight& f = flights.back();
    const double bound_x = 2 * f.max_pitch_error * kHeight;  // eq. (22), constant h
    const double bound_y = 2 * f.max_roll_error * kHeight;   // eq. (23)
    for (int k = 0; k < kFrames; ++k) {
      ASSERT_LE(std::abs(f.error[k].x()), bound_x) << "seed " << seed << " frame " << k;
      ASSERT_LE(std::abs(f.error[k].y()), bound_y) << "seed " << seed << " frame " << k;
    }
  }
  // Bounded, not growing: the spread at the end is like the spread a quarter in.
  const double quarter = rms_at(flights, kFrames / 4), end = rms_at(flights, kFrames - 1);
  std::printf("roll/pitch 3 deg, cached per frame: rms error %.1f m at %.0f m, %.1f m at %.0f m\n", quarter,
              kFrames / 4 * kStep, end, (kFrames - 1) * kStep);
  EXPECT_LT(end, 1.6 * quarter);
}

// Vertically nothing telescopes: the relative levelling error delta of a pair,
// stood in for by a translation h * delta, meets the ground tilt seen in the
// curr frame (which carries that frame's own levelling error) in eq. (7) and
// leaves dz a one-signed bias of about h * sigma^2 per axis and frame. The
// time-reversed pair has the opposite bias; the mean of the two cancels it.
// At 3 deg levelling noise the one-plane model itself misses the image edges
// by 10-15 px (a rotation stood in for by a translation); the cancellation
// needs those features, so the outlier cap is lifted here (with the default
// 10 px cap: forward -2363 m, symmetric -471 m).
TEST(Telescoping, SymmetricDzCancelsTheVerticalBiasOfRollPitchNoise) {
  SolverOptions symmetric_options;
  symmetric_options.max_threshold_px = 1000;
  SolverOptions forward_only = symmetric_options;
  forward_only.symmetric_dz = false;
  double forward = 0, symmetric = 0;
  for (uint32_t seed = 1; seed <= 2; ++seed) {
    forward += fly(Noise::kRollPitchCached, seed, forward_only).vertical_error / 2;
    symmetric += fly(Noise::kRollPitchCached, seed, symmetric_options).vertical_error / 2;
  }
  const double per_frame_bias = 2 * kHeight * std::pow(deg_to_rad(3.0), 2);
  std::printf("roll/pitch 3 deg, vertical error after %.0f m: forward dz %.1f m, symmetric dz %.1f m "
              "(h sigma^2 per axis and frame: %.0f m)\n",
              (kFrames - 1) * kStep, forward, symmetric, per_frame_bias * (kFrames - 1));
  EXPECT_GT(std::abs(forward), 0.3 * per_frame_bias * (kFrames - 1));
  EXPECT_LT(std::abs(symmetric), 0.1 * std::abs(forward));  // second order: cancelled to ~7 % here
}

TEST(Telescoping, WithoutOneAttitudePerFrameTheErrorRandomWalks) {
  std::vector<Flight> flights;
  for (uint32_t seed = 1; seed <= 4; ++seed) flights.push_back(fly(Noise::kRollPitchPerPair, seed));
  const double quarter = rms_at(flights, kFrames / 4), end = rms_at(flights, kFrames - 1);
  std::printf("roll/pitch 3 deg, drawn per pair: rms error %.1f m at %.0f m, %.1f m at %.0f m\n", quarter,
              kFrames / 4 * kStep, end, (kFrames - 1) * kStep);
  // Every pair now carries an independent error of ~h * sigma * sqrt(2) = 22 m:
  // far beyond the telescoped flight with the same noise.
  std::vector<Flight> cached;
  for (uint32_t seed = 1; seed <= 4; ++seed) cached.push_back(fly(Noise::kRollPitchCached, seed));
  EXPECT_GT(end, 5.0 * rms_at(cached, kFrames - 1));
}

TEST(Telescoping, YawNoiseErrorGrowsWithDistance) {
  std::vector<Flight> flights;
  for (uint32_t seed = 1; seed <= 4; ++seed) flights.push_back(fly(Noise::kYaw, seed));
  const double quarter = rms_at(flights, kFrames / 4), end = rms_at(flights, kFrames - 1);
  std::printf("yaw 3 deg: rms error %.2f m at %.0f m, %.2f m at %.0f m\n", quarter, kFrames / 4 * kStep, end,
              (kFrames - 1) * kStep);
  // A random walk: sqrt(4) = 2x from a quarter of the way to the end.
  EXPECT_GT(end, 1.5 * quarter);
}

}  // namespace
}  // namespace nadir::vo
