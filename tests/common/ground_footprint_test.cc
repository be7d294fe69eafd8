#include "common/ground_footprint.h"

#include <gtest/gtest.h>

#include <cmath>

#include "common/geometry.h"

namespace nadir {
namespace {

// 601 x 401 pixels, f = 500 px, no distortion, camera x = body forward.
CameraModel pinhole() { return CameraModel::pinhole(601, 401, 500); }

TEST(GroundFootprint, LevelCameraSeesItsFieldOfViewTimesTheHeight) {
  const auto f = ground_footprint(pinhole(), {10, 20, -100}, Eigen::Matrix3d::Identity(), 0.0);
  ASSERT_EQ(f.size(), 8u);
  // Corner (0, 0): 300 px behind and 200 px left of the centre at 100 m.
  EXPECT_NEAR(f[0].x(), 10 - 60, 1e-6);
  EXPECT_NEAR(f[0].y(), 20 - 40, 1e-6);
  EXPECT_NEAR(f[4].x(), 10 + 60, 1e-6);
  EXPECT_NEAR(f[4].y(), 20 + 40, 1e-6);
}

TEST(GroundFootprint, HeadingTurnsTheFootprint) {
  const auto f = ground_footprint(pinhole(), {0, 0, -100}, rotation_from_rpy(0, 0, M_PI / 2), 0.0);
  ASSERT_EQ(f.size(), 8u);
  // Flying east, the image's forward edge (camera x) lies east.
  EXPECT_NEAR(f[4].y(), 60, 1e-6);
  EXPECT_NEAR(f[4].x(), -40, 1e-6);
}

TEST(GroundFootprint, PointsAboveTheHorizonAreLeftOut) {
  // Pitched up 80 deg, the forward half of the image looks above the horizon.
  const auto f = ground_footprint(pinhole(), {0, 0, -100}, rotation_from_rpy(0, deg_to_rad(80), 0), 0.0);
  EXPECT_LT(f.size(), 8u);
  for (const auto& p : f) EXPECT_GT(p.x(), 0);  // what remains lies ahead of the aircraft
}

TEST(GroundFootprint, OverlapOfStepsAlongTrackAndOfATurnInPlace) {
  const CameraModel camera = pinhole();
  const auto a = ground_footprint(camera, {0, 0, -100}, Eigen::Matrix3d::Identity(), 0.0);
  const auto half = ground_footprint(camera, {60, 0, -100}, Eigen::Matrix3d::Identity(), 0.0);
  const auto apart = ground_footprint(camera, {121, 0, -100}, Eigen::Matrix3d::Identity(), 0.0);
  const auto turned = ground_footprint(camera, {0, 0, -100}, rotation_from_rpy(0, 0, M_PI), 0.0);
  EXPECT_NEAR(footprint_overlap(a, half), 0.5, 1e-5);
  EXPECT_NEAR(footprint_overlap(a, apart), 0.0, 1e-9);
  EXPECT_NEAR(footprint_overlap(a, turned), 1.0, 1e-5);
}

TEST(FootprintOverlap, SquaresShiftedByAQuarter) {
  const std::vector<Eigen::Vector2d> a{{0, 0}, {4, 0}, {4, 4}, {0, 4}};
  const std::vector<Eigen::Vector2d> b{{1, 0}, {5, 0}, {5, 4}, {1, 4}};
  EXPECT_NEAR(footprint_overlap(a, b), 0.75, 1e-6);
  EXPECT_NEAR(footprint_overlap(a, {{10, 10}, {11, 10}, {11, 11}}), 0.0, 1e-9);
  EXPECT_NEAR(footprint_overlap(a, {{1, 1}}), 0.0, 1e-9);  // fewer than three points
}

}  // namespace
}  // namespace nadir
