#pragma once
// Turning an image_t into an 8-bit grey cv::Mat, and judging whether it is
// worth tracking in. Both return a reason in words for STATUS instead of
// throwing, because a bad image is an expected event in flight.

#include <opencv2/core.hpp>

#include <string>

#include "nadir/image_t.hpp"
#include "processes/tracker/tracker_options.h"

namespace nadir {

struct ImageFormatCheck {
  bool ok = false;
  std::string reason;  // empty when ok
};

// Checks pixel format, size against the camera config, stride and data size.
ImageFormatCheck check_image_format(const image_t& msg, int expected_width, int expected_height);

// 8-bit view or copy of a checked image: Mono8 is wrapped without copying
// (valid while `msg` lives); Mono16 (little-endian, as GenICam sends it)
// keeps the top 8 of `significant_bits`. `buffer` holds converted pixels.
cv::Mat to_gray8(const image_t& msg, int significant_bits, cv::Mat& buffer);

enum class ImageQuality { kGood, kBlack, kSaturated, kFeatureless };

struct ImageQualityCheck {
  ImageQuality quality = ImageQuality::kGood;
  double mean = 0.0;
  double stddev = 0.0;
  double dark_fraction = 0.0;
  double saturated_fraction = 0.0;
  std::string reason;  // empty when good
};

// Black, saturated or featureless (grey-level spread too small)?
ImageQualityCheck check_image_quality(const cv::Mat& gray8, const TrackerOptions& options);

}  // namespace nadir
