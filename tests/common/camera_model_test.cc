#include <gtest/gtest.h>

#include <cmath>

#include "common/camera_model.h"
#include "common/geometry.h"

namespace nadir {
namespace {

CameraModel load_default() {
  return CameraModel::from_config(Config::load_file(std::string(NADIR_SOURCE_DIR) + "/config/default.yaml"));
}

TEST(CameraModel, UndistortRoundTripsWithDistort) {
  const CameraModel camera = load_default();
  std::vector<cv::Point2f> pixels;
  for (int v = 0; v < camera.height; v += 37)
    for (int u = 0; u < camera.width; u += 41) pixels.emplace_back(u + 0.25f, v + 0.75f);
  const auto normalized = camera.undistort(pixels);
  const auto back = camera.distort(normalized);
  ASSERT_EQ(back.size(), pixels.size());
  for (size_t i = 0; i < pixels.size(); ++i) {
    EXPECT_NEAR(back[i].x, pixels[i].x, 1e-3);
    EXPECT_NEAR(back[i].y, pixels[i].y, 1e-3);
  }
}

TEST(CameraModel, DistortMatchesTheHandComputedModel) {
  const CameraModel camera = load_default();
  const double x = 0.3, y = -0.2;
  const auto& d = camera.distortion;
  const double r2 = x * x + y * y;
  const double radial = 1 + d[0] * r2 + d[1] * r2 * r2 + d[4] * r2 * r2 * r2;
  const double xd = x * radial + 2 * d[2] * x * y + d[3] * (r2 + 2 * x * x);
  const double yd = y * radial + d[2] * (r2 + 2 * y * y) + 2 * d[3] * x * y;
  const auto px = camera.distort({cv::Point2d(x, y)});
  EXPECT_NEAR(px[0].x, camera.fx * xd + camera.cx, 1e-3);
  EXPECT_NEAR(px[0].y, camera.fy * yd + camera.cy, 1e-3);
}

TEST(CameraModel, PixelJacobianIsTheDerivativeOfTheLens) {
  CameraModel camera = load_default();
  camera.distortion = {-0.12, 0.05, 0.004, -0.003, 0.02};  // every term, tangential included
  camera.fy = camera.fx * 1.01;
  auto pixel = [&](double x, double y) {  // the model in double, as DistortMatchesTheHandComputedModel
    const auto& d = camera.distortion;
    const double r2 = x * x + y * y;
    const double radial = 1 + d[0] * r2 + d[1] * r2 * r2 + d[4] * r2 * r2 * r2;
    return cv::Vec2d(camera.fx * (x * radial + 2 * d[2] * x * y + d[3] * (r2 + 2 * x * x)) + camera.cx,
                     camera.fy * (y * radial + d[2] * (r2 + 2 * y * y) + 2 * d[3] * x * y) + camera.cy);
  };
  const double h = 1e-6;
  for (const cv::Point2d n : {cv::Point2d(0, 0), cv::Point2d(0.45, -0.3), cv::Point2d(-0.7, 0.55), cv::Point2d(0.1, 0.6)}) {
    const cv::Matx22d j = camera.pixel_jacobian(n);
    const cv::Vec2d dx = (pixel(n.x + h, n.y) - pixel(n.x - h, n.y)) / (2 * h);
    const cv::Vec2d dy = (pixel(n.x, n.y + h) - pixel(n.x, n.y - h)) / (2 * h);
    EXPECT_NEAR(j(0, 0), dx[0], 1e-4) << n;
    EXPECT_NEAR(j(1, 0), dx[1], 1e-4) << n;
    EXPECT_NEAR(j(0, 1), dy[0], 1e-4) << n;
    EXPECT_NEAR(j(1, 1), dy[1], 1e-4) << n;
  }
  // At the centre without tangential terms it is the focal length.
  camera.distortion = {-0.12, 0.05, 0, 0, 0.02};
  const cv::Matx22d centre = camera.pixel_jacobian(cv::Point2d(0, 0));
  EXPECT_DOUBLE_EQ(centre(0, 0), camera.fx);
  EXPECT_DOUBLE_EQ(centre(1, 1), camera.fy);
  EXPECT_DOUBLE_EQ(centre(0, 1), 0.0);
}

TEST(Geometry, RpyRoundTripAndConvention) {
  const Eigen::Matrix3d r = rotation_from_rpy(0.1, -0.2, 2.5);
  const Eigen::Vector3d rpy = rpy_from_rotation(r);
  EXPECT_NEAR(rpy[0], 0.1, 1e-12);
  EXPECT_NEAR(rpy[1], -0.2, 1e-12);
  EXPECT_NEAR(rpy[2], 2.5, 1e-12);
  // Yaw 90 deg: body forward points east in NED.
  const Eigen::Vector3d fwd = rotation_from_rpy(0, 0, M_PI / 2) * Eigen::Vector3d::UnitX();
  EXPECT_NEAR(fwd.y(), 1.0, 1e-12);
  // Pitch up: forward gains a negative down component.
  EXPECT_LT((rotation_from_rpy(0, 0.1, 0) * Eigen::Vector3d::UnitX()).z(), 0.0);
  EXPECT_NEAR(angle_difference(-3.1, 3.1), 2 * M_PI - 6.2, 1e-12);
}

}  // namespace
}  // namespace nadir
