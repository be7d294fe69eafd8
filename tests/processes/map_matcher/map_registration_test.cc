// Template registration and orthorectification on synthetic images with known answers.
#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include <cmath>

#include "common/camera_model.h"
#include "common/geometry.h"
#include "processes/map_matcher/frame_ortho.h"
#include "processes/map_matcher/map_registration.h"

namespace nadir {
namespace {

// Smooth random texture: white noise blurred, stretched to 0..255.
cv::Mat texture(int size, uint64_t seed, double blur = 2.0) {
  cv::Mat noise(size, size, CV_32F);
  cv::RNG rng(seed);
  rng.fill(noise, cv::RNG::NORMAL, 0.0, 1.0);
  cv::GaussianBlur(noise, noise, cv::Size(), blur);
  cv::normalize(noise, noise, 0, 255, cv::NORM_MINMAX);
  return noise;
}

TEST(MapRegistration, IntegerShiftRecoveredExactly) {
  const cv::Mat window = texture(161, 1);
  const int t = 101, r = 30;
  for (const cv::Point shift : {cv::Point(0, 0), cv::Point(7, -3), cv::Point(-12, 21), cv::Point(29, 29)}) {
    const cv::Mat templ = window(cv::Rect(r + shift.x, r + shift.y, t, t)).clone();
    const Registration reg = register_template(window, templ);
    ASSERT_TRUE(reg.found);
    EXPECT_NEAR(reg.shift_px.x(), shift.x, 0.01);  // the parabola through an asymmetric peak: a hair off
    EXPECT_NEAR(reg.shift_px.y(), shift.y, 0.01);
    EXPECT_GT(reg.score, 0.9999);
    EXPECT_GT(reg.peak_ratio, 2.0);
    EXPECT_FALSE(reg.at_edge);
    EXPECT_LT(reg.hessian(0, 0), 0.0);
    EXPECT_LT(reg.hessian(1, 1), 0.0);
  }
}

TEST(MapRegistration, SubpixelShiftWithinAFifthOfAPixel) {
  const cv::Mat big = texture(201, 2, 3.0);
  const int t = 101;
  for (const cv::Point2d shift : {cv::Point2d(0.3, -0.4), cv::Point2d(-5.25, 3.5), cv::Point2d(10.7, 0.1)}) {
    // The template is the window's centre moved by `shift`: sample it there.
    cv::Mat templ;
    const cv::Matx23d move(1, 0, 50 + shift.x, 0, 1, 50 + shift.y);
    cv::warpAffine(big, templ, move, cv::Size(t, t), cv::INTER_CUBIC | cv::WARP_INVERSE_MAP);
    const Registration reg = register_template(big, templ);
    ASSERT_TRUE(reg.found);
    EXPECT_NEAR(reg.shift_px.x(), shift.x, 0.2);
    EXPECT_NEAR(reg.shift_px.y(), shift.y, 0.2);
  }
}

TEST(MapRegistration, RepetitiveGroundIsAmbiguous) {
  // Stripes with a 16 px period plus a little noise: every 16 px fits as well.
  cv::Mat window(161, 161, CV_32F);
  for (int r = 0; r < window.rows; ++r)
    for (int c = 0; c < window.cols; ++c)
      window.at<float>(r, c) = static_cast<float>(128 + 60 * std::sin(2 * M_PI * (c + 0.5 * r) / 16.0));
  window += texture(161, 3) * 0.05;
  const cv::Mat templ = window(cv::Rect(30, 30, 101, 101)).clone();
  const Registration reg = register_template(window, templ);
  ASSERT_TRUE(reg.found);
  EXPECT_LT(reg.peak_ratio, 1.1);
}

TEST(MapRegistration, MapSelfSimilarityFindsRepeatsWithinTheWindow) {
  // Unique ground: the square at any place fits nowhere else.
  const cv::Mat unique = edge_strength(texture(161, 4));
  EXPECT_LT(map_self_similarity(unique, cv::Point(30, 30), 101), 0.5);
  EXPECT_LT(map_self_similarity(unique, cv::Point(10, 45), 101), 0.5);
  // A window tiled with a 20 px period: the square fits one period away as
  // well as where it is.
  const cv::Mat tile = texture(20, 5, 1.5);
  cv::Mat tiled(161, 161, CV_32F);
  for (int r = 0; r < tiled.rows; ++r)
    for (int c = 0; c < tiled.cols; ++c) tiled.at<float>(r, c) = tile.at<float>(r % 20, c % 20);
  EXPECT_GT(map_self_similarity(edge_strength(tiled), cv::Point(30, 30), 101), 0.99);
  // A copy of one square pasted elsewhere in unique ground.
  cv::Mat copied = texture(201, 6);
  copied(cv::Rect(10, 10, 60, 60)).copyTo(copied(cv::Rect(120, 100, 60, 60)));
  EXPECT_GT(map_self_similarity(edge_strength(copied), cv::Point(10, 10), 60), 0.9);  // edges differ on the paste's border
  // A square that does not fit in the window.
  EXPECT_EQ(map_self_similarity(unique, cv::Point(100, 100), 101), -1.0);
}

TEST(MapRegistration, EdgeStrengthOfWeakAndSmoothGround) {
  // Strong edges: a step of 100 grey levels every 20 px.
  cv::Mat steps(100, 100, CV_32F);
  for (int r = 0; r < steps.rows; ++r)
    for (int c = 0; c < steps.cols; ++c) steps.at<float>(r, c) = (c / 20) % 2 ? 200.0f : 100.0f;
  // Smooth shading: a 30 grey-level sinusoid over 400 px, a larger grey-level
  // stddev than a weak texture has but hardly any edge.
  cv::Mat shading(100, 100, CV_32F);
  for (int r = 0; r < shading.rows; ++r)
    for (int c = 0; c < shading.cols; ++c)
      shading.at<float>(r, c) = static_cast<float>(128 + 30 * std::sin(2 * M_PI * (c + r) / 400.0));
  const double strong = mean_edge_strength(edge_strength(steps));
  const double smooth = mean_edge_strength(edge_strength(shading));
  EXPECT_GT(strong, 3.0);  // 100 grey levels over 4 steps per 100 px
  EXPECT_GT(texture_stddev(shading), 6.0);
  EXPECT_LT(smooth, 0.6);  // at most 30 x 2 pi / 400 x sqrt(2) = 0.67, 0.43 on average
  // Level ground: no edge at all.
  EXPECT_NEAR(mean_edge_strength(edge_strength(cv::Mat(50, 50, CV_32F, cv::Scalar(90)))), 0.0, 1e-6);
}

TEST(MapRegistration, TextureStddevOverValidPixelsOnly) {
  cv::Mat grey(10, 10, CV_32F, cv::Scalar(100));
  grey(cv::Rect(0, 0, 5, 10)) = 200;
  cv::Mat valid = cv::Mat::zeros(10, 10, CV_8U);
  valid(cv::Rect(5, 0, 5, 10)) = 255;
  EXPECT_NEAR(texture_stddev(grey), 50.0, 1e-9);
  EXPECT_NEAR(texture_stddev(grey, valid), 0.0, 1e-9);
}

// A level ground of known pattern seen by a pinhole camera at a known
// attitude: the frame is made by projecting the pattern, orthorectifying it
// gives the pattern back.
TEST(FrameOrtho, LevelGroundComesBackNorthUp) {
  const CameraModel camera = CameraModel::pinhole(612, 512, 398.79);
  const double height = 150.0, gsd = 1.0;
  auto ground = [](double north, double east) {
    return 128.0 + 50.0 * std::sin(north / 9.0) * std::cos(east / 13.0) + 30.0 * std::sin((north + east) / 23.0);
  };
  const Eigen::Matrix3d world_from_body = rotation_from_rpy(deg_to_rad(2.0), deg_to_rad(-3.0), deg_to_rad(35.0));
  const Eigen::Matrix3d world_from_camera = world_from_body * camera.body_from_camera;
  cv::Mat image(camera.height, camera.width, CV_8UC1);
  for (int v = 0; v < image.rows; ++v)
    for (int u = 0; u < image.cols; ++u) {
      const Eigen::Vector3d ray = world_from_camera * Eigen::Vector3d((u - camera.cx) / camera.fx,
                                                                      (v - camera.cy) / camera.fy, 1.0);
      const double s = height / ray.z();
      image.at<uint8_t>(v, u) = cv::saturate_cast<uint8_t>(ground(s * ray.x(), s * ray.y()));
    }
  FrameOrthoInput input;
  input.image = image;
  input.world_from_body = world_from_body;
  input.camera_height_m = height;
  const int size = static_cast<int>(nadir_square_side_m(camera, height) * 0.9 / gsd);
  ASSERT_GT(size, 100);
  const OrthoFrame ortho = orthorectify_frame(camera, input, size, gsd);
  EXPECT_EQ(cv::countNonZero(ortho.valid), size * size);
  double worst = 0.0;
  for (int r = 2; r < size - 2; ++r)
    for (int c = 2; c < size - 2; ++c) {
      const double north = (size / 2.0 - r - 0.5) * gsd, east = (c - size / 2.0 + 0.5) * gsd;
      worst = std::max(worst, std::abs(ortho.grey.at<float>(r, c) - ground(north, east)));
    }
  // Quantisation and bilinear sampling of a blurred frame: a few grey levels.
  EXPECT_LT(worst, 6.0);
}

TEST(FrameOrtho, BadInputsRefused) {
  const CameraModel camera = CameraModel::pinhole(64, 48, 50.0);
  FrameOrthoInput input;
  input.world_from_body = Eigen::Matrix3d::Identity();
  input.camera_height_m = 10.0;
  EXPECT_THROW(orthorectify_frame(camera, input, 8, 1.0), std::invalid_argument);  // no image
  input.image = cv::Mat(48, 64, CV_8UC1, cv::Scalar(9));
  EXPECT_THROW(orthorectify_frame(camera, input, 8, 0.0), std::invalid_argument);
  input.relief_m = cv::Mat(4, 4, CV_32F);
  EXPECT_THROW(orthorectify_frame(camera, input, 8, 1.0), std::invalid_argument);
}

}  // namespace
}  // namespace nadir
