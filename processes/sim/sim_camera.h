#pragma once
// The simulated camera's parameters, read from the `camera:` section of the
// config by the simulator itself (not through common/camera_model: the
// simulator must stay independent of the estimator's geometry code).

#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "common/config.h"

namespace nadir::sim {

struct SimCamera {
  int width = 612;
  int height = 512;
  double fx = 398.79, fy = 398.79, cx = 305.5, cy = 255.5;
  std::vector<double> distortion{0, 0, 0, 0, 0};  // OpenCV k1, k2, p1, p2, k3
  // body <- camera: Rz(yaw) Ry(pitch) Rx(roll) of mount_rpy_deg applied to the
  // nominal downward mount (camera x = body forward, camera z = body down,
  // hence camera y = body right: the nominal mount is the identity).
  Eigen::Matrix3d body_from_camera = Eigen::Matrix3d::Identity();
  double rate_hz = 14.0;

  // Reads `camera:` of a config root; throws ConfigError naming the key.
  static SimCamera from_config(const Config& root);

  cv::Matx33d camera_matrix() const;
  cv::Mat distortion_coefficients() const;
  // Optical axis (camera z) in the body frame.
  Eigen::Vector3d optical_axis_body() const { return body_from_camera.col(2); }

  // Pixels -> undistorted normalized coordinates (cv::undistortPoints with a
  // tight termination so the round trip through cv::projectPoints is exact).
  std::vector<cv::Point2d> undistort(const std::vector<cv::Point2d>& pixels) const;
  // Camera-frame points -> distorted pixels (cv::projectPoints).
  std::vector<cv::Point2d> project(const std::vector<cv::Point3d>& points_camera) const;
};

}  // namespace nadir::sim
