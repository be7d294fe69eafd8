// The per-feature model: plane depth against a direct ray/plane intersection,
// eq. (9) zero for a perfect measurement, analytic Jacobian vs finite differences.

#include <gtest/gtest.h>

#include <random>

#include "common/geometry.h"
#include "processes/vo_solver/plane_model.h"
#include "processes/vo_solver/solver_support.h"

namespace nadir::vo {
namespace {

TEST(PlaneModel, TiltConventionMatchesZyxAttitude) {
  // The ground normal of a patch with roll r, pitch p is the body z axis of a
  // vehicle sitting on it with that roll and pitch.
  const double roll = 0.2, pitch = -0.3;
  EXPECT_TRUE(normal_from_tilt(roll, pitch).isApprox(rotation_from_rpy(roll, pitch, 0.0).col(2), 1e-15));
  double r = 0, p = 0;
  tilt_from_normal(normal_from_tilt(roll, pitch), &r, &p);
  EXPECT_NEAR(r, roll, 1e-15);
  EXPECT_NEAR(p, pitch, 1e-15);
  // Positive ground pitch: the ground rises ahead (smaller depth at +x).
  PlaneGeometry plane;
  plane.range_m = 100;
  Eigen::Vector3d ahead, behind;
  ASSERT_TRUE(ground_point(plane, normal_from_tilt(0, 0.1), Eigen::Vector3d(0.5, 0, 1), &ahead));
  ASSERT_TRUE(ground_point(plane, normal_from_tilt(0, 0.1), Eigen::Vector3d(-0.5, 0, 1), &behind));
  EXPECT_LT(ahead.z(), behind.z());
}

TEST(PlaneModel, GroundPointLiesOnPlaneThroughAltimeterPoint) {
  PlaneGeometry plane;
  plane.range_m = 312.0;
  plane.beam = Eigen::Vector3d(0.05, -0.03, 1.0).normalized();
  plane.relevel = rotation_from_rpy(0.1, -0.05, 0.3);
  const Eigen::Vector3d n = ground_normal(plane, 0.02, -0.04);
  const Eigen::Vector3d a = plane.range_m * plane.beam;
  Eigen::Vector3d x;
  ASSERT_TRUE(ground_point(plane, n, Eigen::Vector3d(0.4, -0.3, 1.0), &x));
  EXPECT_NEAR(n.dot(x - a), 0.0, 1e-9);
  EXPECT_NEAR(x.x() / x.z(), 0.4, 1e-15);
  EXPECT_NEAR(x.y() / x.z(), -0.3, 1e-15);
}

TEST(PlaneModel, AnalyticJacobianMatchesFiniteDifferences) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> uni(-1.0, 1.0);
  for (int trial = 0; trial < 200; ++trial) {
    PlaneGeometry plane;
    plane.range_m = 100 + 400 * (uni(rng) + 1);
    plane.beam = Eigen::Vector3d(0.1 * uni(rng), 0.1 * uni(rng), 1.0).normalized();
    plane.relevel = rotation_from_rpy(0.2 * uni(rng), 0.2 * uni(rng), 0.0);
    LevelFeature f{Eigen::Vector3d(0.7 * uni(rng), 0.6 * uni(rng), 1.0),
                   Eigen::Vector3d(0.7 * uni(rng), 0.6 * uni(rng), 1.0)};
    Params p;
    p << 3 * uni(rng), 3 * uni(rng), 0.2 * uni(rng), 0.1 * uni(rng), 0.1 * uni(rng);
    if (trial % 2 == 0) p(3) = p(4) = 0;  // where the solver evaluates it (just re-levelled)
    JacobianRow analytic;
    const double r0 = plane_residual(f, plane, p, &analytic);
    EXPECT_EQ(r0, plane_residual(f, plane, p, nullptr));
    for (int k = 0; k < 5; ++k) {
      const double h = k < 2 ? 1e-5 : 1e-7;
      Params plus = p, minus = p;
      plus(k) += h;
      minus(k) -= h;
      const double numeric =
          (plane_residual(f, plane, plus, nullptr) - plane_residual(f, plane, minus, nullptr)) / (2 * h);
      EXPECT_NEAR(analytic(k), numeric, 1e-6 * std::max(1.0, std::abs(numeric)))
          << "trial " << trial << " parameter " << k;
    }
  }
}

TEST(PlaneModel, ReLevellingComposesTheTilt) {
  // Folding an increment into the virtual camera and restarting it at zero
  // must not move the plane: the solver's re-levelling step is exact.
  PlaneGeometry plane;
  plane.relevel = rotation_from_rpy(0.05, -0.08, 0.0);
  const Eigen::Vector3d before = ground_normal(plane, 0.03, 0.02);
  plane.relevel = ground_relevel(plane, 0.03, 0.02);
  EXPECT_TRUE(ground_normal(plane, 0, 0).isApprox(before, 1e-15));
}

}  // namespace
}  // namespace nadir::vo
