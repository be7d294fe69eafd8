// PoseFilter: registration with the previous frame's yaw, covariance
// propagation against a numerical Jacobian, INS yaw gating, terrain updates.

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

#include "common/geometry.h"
#include "processes/yaw_fusion/pose_filter.h"

namespace nadir {
namespace {

TEST(PoseFilter, RegistersTranslationWithPreviousYawThenTurns) {
  PoseFilter f;
  f.initialise(deg_to_rad(90.0), 1e-6);  // heading east
  const Eigen::Vector3d world = f.predict_with_delta({10.0, 2.0, -1.0}, deg_to_rad(90.0), Eigen::Matrix4d::Identity() * 1e-4);
  // Forward 10 m is east, right 2 m is south (down 1 m negative = climb).
  EXPECT_NEAR(world.x(), -2.0, 1e-12);
  EXPECT_NEAR(world.y(), 10.0, 1e-12);
  EXPECT_NEAR(world.z(), -1.0, 1e-12);
  EXPECT_NEAR(f.yaw(), M_PI, 1e-12);
  // The next delta uses the new yaw (south).
  f.predict_with_delta({5.0, 0.0, 0.0}, 0.0, Eigen::Matrix4d::Identity() * 1e-4);
  EXPECT_NEAR(f.position().x(), -7.0, 1e-12);
  EXPECT_NEAR(f.position().y(), 10.0, 1e-9);
}

TEST(PoseFilter, YawWrapsAcrossPlusMinusPi) {
  PoseFilter f;
  f.initialise(deg_to_rad(179.0), 1e-6);
  f.predict_with_delta({1.0, 0.0, 0.0}, deg_to_rad(3.0), Eigen::Matrix4d::Identity() * 1e-6);
  EXPECT_NEAR(f.yaw(), deg_to_rad(-178.0), 1e-12);
  // An INS yaw of +179.5 is 2.5 deg away, not 357.5: accepted.
  EXPECT_EQ(f.update_yaw(deg_to_rad(179.5), 1e-3, 3.0), PoseFilter::UpdateResult::kAccepted);
  EXPECT_GT(std::abs(f.yaw()), deg_to_rad(178.0));
}

// Propagates mean and covariance of (n, e, d, yaw) through one delta by
// sampling and compares with the linearised covariance.
TEST(PoseFilter, CovarianceMatchesMonteCarloForSmallNoise) {
  PoseFilter f;
  f.initialise(0.7, std::pow(deg_to_rad(1.0), 2));
  Eigen::Matrix4d cov = Eigen::Matrix4d::Zero();
  cov.diagonal() << 0.04, 0.09, 0.01, std::pow(deg_to_rad(0.2), 2);
  cov(0, 3) = cov(3, 0) = 0.5 * std::sqrt(cov(0, 0) * cov(3, 3));
  const Eigen::Vector3d d(20.0, -3.0, 0.5);
  f.predict_with_delta(d, 0.01, cov);

  std::mt19937 rng(3);
  std::normal_distribution<double> normal;
  const Eigen::Matrix4d l = cov.llt().matrixL();
  const int n = 200000;
  Eigen::Matrix<double, 4, Eigen::Dynamic> samples(4, n);
  for (int i = 0; i < n; ++i) {
    const double yaw0 = 0.7 + deg_to_rad(1.0) * normal(rng);
    Eigen::Vector4d e;
    for (int j = 0; j < 4; ++j) e(j) = normal(rng);
    const Eigen::Vector4d delta = Eigen::Vector4d(d.x(), d.y(), d.z(), 0.01) + l * e;
    samples(0, i) = std::cos(yaw0) * delta(0) - std::sin(yaw0) * delta(1);
    samples(1, i) = std::sin(yaw0) * delta(0) + std::cos(yaw0) * delta(1);
    samples(2, i) = delta(2);
    samples(3, i) = yaw0 + delta(3);
  }
  const Eigen::Vector4d mean = samples.rowwise().mean();
  const Eigen::MatrixXd centred = samples.colwise() - mean;
  const Eigen::Matrix4d sample_cov = centred * centred.transpose() / (n - 1);
  const Eigen::Matrix4d predicted = f.covariance().topLeftCorner<4, 4>();
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) {
      const double scale = std::sqrt(sample_cov(r, r) * sample_cov(c, c));
      EXPECT_NEAR(predicted(r, c), sample_cov(r, c), 0.02 * scale) << "entry " << r << "," << c;
    }
  }
}

TEST(PoseFilter, YawUpdateIsTheScalarKalmanUpdateAndGatesOutliers) {
  PoseFilter f;
  f.initialise(0.0, 4e-4);
  ASSERT_EQ(f.update_yaw(0.01, 1e-4, 3.0), PoseFilter::UpdateResult::kAccepted);
  EXPECT_NEAR(f.yaw(), 0.01 * 4e-4 / 5e-4, 1e-15);
  EXPECT_NEAR(f.yaw_variance(), 4e-4 * 1e-4 / 5e-4, 1e-15);
  const double yaw_before = f.yaw();
  const double var_before = f.yaw_variance();
  // 3 sigma of the innovation is 3 * sqrt(0.8e-4 + 1e-4) = 0.04 rad: 0.1 rad away is an outlier.
  EXPECT_EQ(f.update_yaw(yaw_before + 0.1, 1e-4, 3.0), PoseFilter::UpdateResult::kRejected);
  EXPECT_EQ(f.yaw(), yaw_before);
  EXPECT_EQ(f.yaw_variance(), var_before);
  EXPECT_NEAR(f.last_yaw_innovation(), 0.1, 1e-12);
}

TEST(PoseFilter, YawUpdateLeavesPositionButShrinksCrossCovariance) {
  PoseFilter f;
  f.initialise(0.0, std::pow(deg_to_rad(2.0), 2));
  f.predict_with_delta({100.0, 0.0, 0.0}, 0.0, Eigen::Matrix4d::Identity() * 1e-6);
  const Eigen::Vector3d p = f.position();
  const double cross = f.covariance()(PoseFilter::kEast, PoseFilter::kYaw);
  EXPECT_GT(cross, 0.0);  // an eastward yaw error moved the point east
  f.update_yaw(0.01, std::pow(deg_to_rad(0.5), 2), 3.0);
  EXPECT_EQ(f.position(), p);
  EXPECT_LT(std::abs(f.covariance()(PoseFilter::kEast, PoseFilter::kYaw)), std::abs(cross));
  // The position covariance keeps the error already made by the old yaw.
  EXPECT_NEAR(f.position_covariance()(1, 1), 1e-6 + 100.0 * 100.0 * std::pow(deg_to_rad(2.0), 2), 1e-6);
  const Eigen::SelfAdjointEigenSolver<PoseFilter::Matrix> eig(f.covariance());
  EXPECT_GE(eig.eigenvalues().minCoeff(), -1e-12);
}

TEST(PoseFilter, LevelTerrainHeightCorrectsDownAndStepsAreGated) {
  PoseFilter f;
  f.initialise(0.0, 1e-4);
  f.anchor_terrain(300.0, 0.04);
  // 50 deltas with a +0.1 m bias each in dz: down drifts 5 m, the altimeter says it did not.
  Eigen::Matrix4d cov = Eigen::Matrix4d::Identity() * 1e-4;
  cov(2, 2) = 0.01;
  for (int i = 0; i < 50; ++i) {
    f.predict_with_delta({2.0, 0.0, 0.1}, 0.0, cov);
    ASSERT_EQ(f.update_height_agl(300.0, 0.04, 3.0), PoseFilter::UpdateResult::kAccepted);
  }
  EXPECT_LT(std::abs(f.position().z()), 1.5);
  // A 40 m cliff is not a 40 m climb.
  f.predict_with_delta({2.0, 0.0, 0.0}, 0.0, cov);
  EXPECT_EQ(f.update_height_agl(260.0, 0.04, 3.0), PoseFilter::UpdateResult::kRejected);
}

}  // namespace
}  // namespace nadir
