// Algorithm 1 and its variants on synthetic pairs from a known tilted plane.

#include <gtest/gtest.h>

#include <cmath>

#include "common/geometry.h"
#include "processes/vo_solver/translation_solver.h"
#include "tests/processes/vo_solver/synthetic_scene.h"

namespace nadir::vo {
namespace {

using testing::make_scene;
using testing::Scene;
using testing::SceneSpec;

// A demanding but realistic pair: banked, pitched, turning, climbing, over a
// slope, with the camera mount and altimeter beam a little off the body axes.
SceneSpec tilted_case() {
  SceneSpec s;
  s.height_m = 250.0;
  s.ground_roll = deg_to_rad(6.0);
  s.ground_pitch = deg_to_rad(-9.0);
  s.prev_roll = deg_to_rad(4.0);
  s.prev_pitch = deg_to_rad(-3.0);
  s.prev_yaw = deg_to_rad(170.0);
  s.curr_roll = deg_to_rad(5.5);
  s.curr_pitch = deg_to_rad(-2.0);
  s.curr_yaw = deg_to_rad(-177.0);  // a 13 deg turn across +-180
  s.translation = Eigen::Vector3d(2.3, -0.6, -0.4);
  s.body_from_camera = rotation_from_rpy(deg_to_rad(1.0), deg_to_rad(-2.0), deg_to_rad(0.5));
  s.beam_body = Eigen::Vector3d(0.02, -0.01, 1.0).normalized();
  return s;
}

void expect_exact(const Scene& scene, const Estimate& est, double rel, bool check_tilt = true) {
  const double t = scene.translation.norm();
  EXPECT_LE((est.translation - scene.translation).norm(), rel * t)
      << "estimated " << est.translation.transpose() << " truth " << scene.translation.transpose();
  EXPECT_LE(std::abs(est.dyaw - scene.dyaw), rel * std::max(std::abs(scene.dyaw), 0.01));
  if (check_tilt) {
    const double tilt = std::hypot(scene.ground_roll, scene.ground_pitch);
    EXPECT_LE(std::abs(est.ground_roll - scene.ground_roll), rel * std::max(tilt, 0.01));
    EXPECT_LE(std::abs(est.ground_pitch - scene.ground_pitch), rel * std::max(tilt, 0.01));
  }
  EXPECT_NEAR(est.altitude_m, scene.prev_altitude_m, rel * scene.prev_altitude_m);
}

TEST(PaperSolver, NoiseFreeTiltedPlaneIsRecoveredExactly) {
  const Scene scene = make_scene(tilted_case());
  SolverOptions options;
  const Estimate est = solve(scene.pair, options);
  EXPECT_EQ(est.quality, 0);
  EXPECT_EQ(est.inliers, 450);
  EXPECT_EQ(est.outliers, 0);
  EXPECT_GT(est.iterations, 0);
  EXPECT_LT(est.residual_rms_px, 1e-6);
  expect_exact(scene, est, 1e-6);
}

TEST(PaperSolver, NoiseFreeOverManyGeometries) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> angle(-1.0, 1.0);
  for (int trial = 0; trial < 30; ++trial) {
    SceneSpec s;
    s.seed = 100 + trial;
    s.height_m = 60.0 + 900.0 * (0.5 + 0.5 * angle(rng));
    s.ground_roll = deg_to_rad(15.0 * angle(rng));
    s.ground_pitch = deg_to_rad(15.0 * angle(rng));
    s.prev_roll = deg_to_rad(10.0 * angle(rng));
    s.prev_pitch = deg_to_rad(10.0 * angle(rng));
    s.prev_yaw = deg_to_rad(180.0 * angle(rng));
    s.curr_roll = s.prev_roll + deg_to_rad(2.0 * angle(rng));
    s.curr_pitch = s.prev_pitch + deg_to_rad(2.0 * angle(rng));
    s.curr_yaw = s.prev_yaw + deg_to_rad(5.0 * angle(rng));
    s.translation = Eigen::Vector3d(3.0 * angle(rng), 1.0 * angle(rng), 0.5 * angle(rng));
    s.num_features = 100;
    const Scene scene = make_scene(s);
    const Estimate est = solve(scene.pair, SolverOptions{});
    SCOPED_TRACE("trial " + std::to_string(trial));
    EXPECT_EQ(est.quality, 0);
    expect_exact(scene, est, 1e-6);
  }
}

}  // namespace
}  // namespace nadir::vo

namespace nadir::vo {
namespace {

TEST(PaperSolver, ExploreNoise) {
  double max_t = 0, max_dz = 0, max_yaw = 0, max_tilt = 0, max_z = 0;
  int max_iter = 0, nc = 0;
  for (int seed = 1; seed <= 50; ++seed) {
    SceneSpec s = tilted_case();
    s.noise_px = 0.5;
    s.outlier_fraction = 0.3;
    s.seed = seed;
    const Scene scene = make_scene(s);
    const Estimate est = solve(scene.pair, SolverOptions{});
    const Eigen::Vector3d err = est.translation - scene.translation;
    max_t = std::max(max_t, err.head<2>().cwiseAbs().maxCoeff());
    max_dz = std::max(max_dz, std::abs(err.z()));
    max_yaw = std::max(max_yaw, std::abs(est.dyaw - scene.dyaw));
    max_tilt = std::max({max_tilt, std::abs(est.ground_roll - scene.ground_roll), std::abs(est.ground_pitch - scene.ground_pitch)});
    max_z = std::max({max_z, std::abs(err.x()) / std::sqrt(est.covariance(0, 0)), std::abs(err.y()) / std::sqrt(est.covariance(1, 1)),
                      std::abs(err.z()) / std::sqrt(est.covariance(2, 2))});
    max_iter = std::max(max_iter, est.iterations);
    nc += est.quality != 0;
    int wrong = 0, rejected_inliers = 0;
    for (size_t i = 0; i < scene.is_outlier.size(); ++i) {
      if (scene.is_outlier[i] && est.weights[i] > 0) ++wrong;
      if (!scene.is_outlier[i] && est.weights[i] == 0) ++rejected_inliers;
    }
    if (seed <= 5) printf("seed %d q %d in %d out %d rms %.3f iter %d wrong %d rejin %d sd %.4f %.4f %.4f\n", seed, est.quality, est.inliers, est.outliers,
           est.residual_rms_px, est.iterations, wrong, rejected_inliers, std::sqrt(est.covariance(0,0)), std::sqrt(est.covariance(1,1)), std::sqrt(est.covariance(2,2)));
  }
  printf("max xy %.4f dz %.4f yaw %.6f tilt %.6f z %.2f iter %d flagged %d\n", max_t, max_dz, max_yaw, max_tilt, max_z, max_iter, nc);
}

}  // namespace
}  // namespace nadir::vo
