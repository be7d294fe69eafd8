#pragma once
// Generated ground texture for tracker tests and benchmarks: a large seeded
// image (smoothed noise at several scales plus field-like patches), viewed by
// a virtual camera that shifts and rotates over it. Because every frame is an
// exact affine view of the same texture, where each pixel must go is known.

#include <opencv2/core.hpp>

#include <cstdint>

#include "nadir/image_t.hpp"

namespace nadir::testing {

// Pose of a frame over the ground texture: the image centre sits at
// `centre` (texture pixels) and the image is rotated by `angle_rad`.
struct ViewPose {
  cv::Point2d centre;
  double angle_rad = 0.0;
};

class SyntheticScene {
 public:
  // A deterministic texture of `size` from `seed`.
  SyntheticScene(cv::Size size, uint64_t seed);

  // The view at `pose` (CV_8UC1, frame_size), with Gaussian pixel noise of
  // `noise_sigma` grey levels drawn from `noise_seed`.
  cv::Mat render(const ViewPose& pose, cv::Size frame_size, double noise_sigma = 0.0, uint64_t noise_seed = 1) const;

  // Where frame pixel `p` seen at `from` appears in the frame at `to`.
  static cv::Point2d map_point(const cv::Point2d& p, const ViewPose& from, const ViewPose& to, cv::Size frame_size);

  const cv::Mat& texture() const { return texture_; }

 private:
  cv::Mat texture_;
};

// A Mono8 image_t for `pixels` (CV_8UC1).
image_t make_image_msg(const cv::Mat& pixels, int64_t utime, int64_t frame_counter);

}  // namespace nadir::testing
