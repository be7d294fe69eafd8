#pragma once
// The downward camera as the estimator sees it: pinhole intrinsics, OpenCV
// radial-tangential distortion and the body <- camera mounting rotation, all
// from the `camera:` section of the config. Points are undistorted one by one
// (cv::undistortPoints), never whole images.

#include <opencv2/core.hpp>

#include <Eigen/Core>
#include <vector>

#include "common/config.h"

namespace nadir {

struct CameraModel {
  int width = 0;
  int height = 0;
  double fx = 0, fy = 0, cx = 0, cy = 0;
  std::vector<double> distortion;  // k1, k2, p1, p2[, k3]
  Eigen::Matrix3d body_from_camera = Eigen::Matrix3d::Identity();
  double rate_hz = 14.0;

  // Reads and checks the `camera:` section; throws ConfigError naming the key.
  static CameraModel from_config(const Config& root);
  // An ideal camera: focal length `focal_px` on both axes, the principal point
  // at the image centre, no distortion, mounted looking down with its x axis
  // forward.
  static CameraModel pinhole(int width, int height, double focal_px);
  void Check(const std::string& source) const;

  cv::Matx33d camera_matrix() const;
  cv::Mat distortion_coefficients() const;
  double horizontal_fov_rad() const;

  // Distorted pixels -> undistorted normalized coordinates (x/z, y/z).
  std::vector<cv::Point2d> undistort(const std::vector<cv::Point2f>& pixels) const;
  // Normalized coordinates -> distorted pixels.
  std::vector<cv::Point2f> distort(const std::vector<cv::Point2d>& normalized) const;
  // d pixel / d normalized at `normalized`: the lens's local magnification
  // (the derivative of distort(), analytic).
  cv::Matx22d pixel_jacobian(const cv::Point2d& normalized) const;
};

}  // namespace nadir
