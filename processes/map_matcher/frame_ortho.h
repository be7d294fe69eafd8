#pragma once
// A camera frame re-projected onto the ground, north-up: the picture the
// frame would give of the ground around a point if it had been taken straight
// down, at a given ground sample distance -- comparable pixel for pixel with
// an orthophoto window of the same grid (reference_map.h's MapWindow:
// pixel (row, col) centre at north = (size/2 - row - 0.5) * gsd,
// east = (col - size/2 + 0.5) * gsd from the centre point).
//
// Each output pixel's ground point (its north/east offset from the centre,
// its height from `relief`) is projected through the pinhole + distortion
// camera at the camera's position (`camera_height_m` above the ground at the
// centre, straight above it) and attitude, and the frame is sampled there
// (bilinear, after a Gaussian blur that brings the frame's ground resolution
// down to the output's). Pixels the frame does not see are marked invalid.

#include <opencv2/core.hpp>

#include <Eigen/Core>

#include "common/camera_model.h"

namespace nadir {

struct FrameOrthoInput {
  cv::Mat image;                      // CV_8UC1, the frame as captured (distorted)
  Eigen::Matrix3d world_from_body;    // NED <- body at the frame's exposure
  double camera_height_m = 0.0;       // above the ground at the centre point
  // Height (m, up) of the ground at each output pixel relative to the ground
  // at the centre point: CV_32F size x size, or empty for level ground.
  cv::Mat relief_m;
};

struct OrthoFrame {
  cv::Mat grey;   // CV_32F size x size, 0..255
  cv::Mat valid;  // CV_8U, 255 where the frame saw the ground point
};

// Throws std::invalid_argument for an empty or non-8-bit image, size < 2,
// gsd <= 0, a camera height <= 0 or a relief of the wrong size.
OrthoFrame orthorectify_frame(const CameraModel& camera, const FrameOrthoInput& input, int size, double gsd_m);

// The largest side (m) of a north-up square centred below the camera that a
// frame taken straight down from `camera_height_m` holds at any heading.
double nadir_square_side_m(const CameraModel& camera, double camera_height_m);

}  // namespace nadir
