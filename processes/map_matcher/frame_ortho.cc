#include "processes/map_matcher/frame_ortho.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

namespace nadir {

double nadir_square_side_m(const CameraModel& camera, double camera_height_m) {
  // The footprint of a nadir frame is a rectangle around the nadir point
  // (the principal point, pinhole); the north-up square must fit inside it at
  // any heading, i.e. inside its inscribed circle around the nadir point.
  const double left = camera.cx / camera.fx, right = (camera.width - camera.cx) / camera.fx;
  const double top = camera.cy / camera.fy, bottom = (camera.height - camera.cy) / camera.fy;
  const double radius = camera_height_m * std::min(std::min(left, right), std::min(top, bottom));
  return radius * std::sqrt(2.0);
}

OrthoFrame orthorectify_frame(const CameraModel& camera, const FrameOrthoInput& input, int size, double gsd_m) {
  if (input.image.empty() || input.image.type() != CV_8UC1) {
    throw std::invalid_argument("orthorectify_frame: the frame must be a non-empty 8-bit grey image");
  }
  if (size < 2 || !(gsd_m > 0.0) || !(input.camera_height_m > 0.0)) {
    throw std::invalid_argument("orthorectify_frame: size >= 2, gsd > 0 and a camera height > 0 are needed");
  }
  if (!input.relief_m.empty() &&
      (input.relief_m.rows != size || input.relief_m.cols != size || input.relief_m.type() != CV_32F)) {
    throw std::invalid_argument("orthorectify_frame: relief must be CV_32F, size x size");
  }
  // Blur the frame down to the output's ground resolution (anti-aliasing).
  const double ground_px_m = input.camera_height_m / std::max(camera.fx, camera.fy);
  const double blur_px = 0.5 * gsd_m / ground_px_m;
  cv::Mat source;
  input.image.convertTo(source, CV_32F);
  if (blur_px > 0.5) cv::GaussianBlur(source, source, cv::Size(), blur_px, blur_px, cv::BORDER_REFLECT);

  const Eigen::Matrix3d camera_from_world = (input.world_from_body * camera.body_from_camera).transpose();
  // Points far outside the field of view are not sent through the distortion
  // polynomial, which can fold them back into the image.
  const double corner_x = std::max(camera.cx, camera.width - camera.cx) / camera.fx;
  const double corner_y = std::max(camera.cy, camera.height - camera.cy) / camera.fy;
  const double max_radius2 = 2.25 * (corner_x * corner_x + corner_y * corner_y);
  const int n = size * size;
  std::vector<cv::Point2d> normalized(static_cast<size_t>(n));
  std::vector<uint8_t> in_front(static_cast<size_t>(n), 0);
  for (int r = 0; r < size; ++r) {
    const double north = (size / 2.0 - r - 0.5) * gsd_m;
    const float* relief = input.relief_m.empty() ? nullptr : input.relief_m.ptr<float>(r);
    for (int c = 0; c < size; ++c) {
      const double east = (c - size / 2.0 + 0.5) * gsd_m;
      const double down = input.camera_height_m - (relief ? relief[c] : 0.0);
      const Eigen::Vector3d v = camera_from_world * Eigen::Vector3d(north, east, down);
      const size_t i = static_cast<size_t>(r * size + c);
      if (v.z() > 1e-6) {
        const cv::Point2d xy(v.x() / v.z(), v.y() / v.z());
        if (xy.x * xy.x + xy.y * xy.y <= max_radius2) {
          normalized[i] = xy;
          in_front[i] = 1;
        }
      }
    }
  }
  const std::vector<cv::Point2f> pixels = camera.distort(normalized);
  cv::Mat map_x(size, size, CV_32F), map_y(size, size, CV_32F);
  OrthoFrame out;
  out.valid = cv::Mat::zeros(size, size, CV_8U);
  const float max_x = static_cast<float>(input.image.cols - 1), max_y = static_cast<float>(input.image.rows - 1);
  for (int r = 0; r < size; ++r) {
    for (int c = 0; c < size; ++c) {
      const size_t i = static_cast<size_t>(r * size + c);
      const cv::Point2f p = pixels[i];
      const bool seen = in_front[i] && p.x >= 0.f && p.y >= 0.f && p.x <= max_x && p.y <= max_y;
      map_x.at<float>(r, c) = seen ? p.x : -1.f;
      map_y.at<float>(r, c) = seen ? p.y : -1.f;
      if (seen) out.valid.at<uint8_t>(r, c) = 255;
    }
  }
  cv::remap(source, out.grey, map_x, map_y, cv::INTER_LINEAR, cv::BORDER_CONSTANT, cv::Scalar(0));
  return out;
}

}  // namespace nadir
