#include "processes/tracker/image_input.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <sstream>

namespace nadir {

ImageFormatCheck check_image_format(const image_t& msg, int expected_width, int expected_height) {
  ImageFormatCheck check;
  std::ostringstream why;
  int bytes_per_pixel = 0;
  if (msg.pixel_format == image_t::PIXEL_MONO8) {
    bytes_per_pixel = 1;
  } else if (msg.pixel_format == image_t::PIXEL_MONO16) {
    bytes_per_pixel = 2;
  } else {
    why << "pixel_format " << static_cast<int>(msg.pixel_format) << " is neither MONO8 (1) nor MONO16 (2)";
    check.reason = why.str();
    return check;
  }
  if (msg.width != expected_width || msg.height != expected_height) {
    why << "image is " << msg.width << "x" << msg.height << ", camera config says " << expected_width << "x"
        << expected_height;
    check.reason = why.str();
    return check;
  }
  const int64_t row_bytes = static_cast<int64_t>(msg.width) * bytes_per_pixel;
  if (msg.stride < row_bytes) {
    why << "stride " << msg.stride << " is shorter than a row (" << row_bytes << " bytes)";
    check.reason = why.str();
    return check;
  }
  const int64_t needed = static_cast<int64_t>(msg.stride) * (msg.height - 1) + row_bytes;
  if (msg.size < needed || static_cast<int64_t>(msg.data.size()) < needed) {
    why << "data holds " << msg.data.size() << " bytes, " << needed << " needed for " << msg.height
        << " rows of stride " << msg.stride;
    check.reason = why.str();
    return check;
  }
  check.ok = true;
  return check;
}

cv::Mat to_gray8(const image_t& msg, int significant_bits, cv::Mat& buffer) {
  uint8_t* data = const_cast<uint8_t*>(msg.data.data());  // cv::Mat wants non-const; never written
  if (msg.pixel_format == image_t::PIXEL_MONO8) {
    return cv::Mat(msg.height, msg.width, CV_8UC1, data, static_cast<size_t>(msg.stride));
  }
  const int shift = significant_bits - 8;
  buffer.create(msg.height, msg.width, CV_8UC1);
  for (int y = 0; y < msg.height; ++y) {
    const uint8_t* src = data + static_cast<size_t>(y) * static_cast<size_t>(msg.stride);
    uint8_t* dst = buffer.ptr<uint8_t>(y);
    for (int x = 0; x < msg.width; ++x) {
      const unsigned value = static_cast<unsigned>(src[2 * x]) | (static_cast<unsigned>(src[2 * x + 1]) << 8);
      const unsigned scaled = value >> shift;
      dst[x] = static_cast<uint8_t>(scaled > 255 ? 255 : scaled);
    }
  }
  return buffer;
}

ImageQualityCheck check_image_quality(const cv::Mat& gray8, const TrackerOptions& options) {
  ImageQualityCheck check;
  // One pass: histogram; mean, spread and clipped shares follow from it.
  // Four interleaved partial counts, so that runs of equal pixels do not wait
  // on each other's increment (same counts, a fraction of the time).
  int64_t partial[4][256] = {};
  for (int y = 0; y < gray8.rows; ++y) {
    const uint8_t* row = gray8.ptr<uint8_t>(y);
    int x = 0;
    for (; x + 4 <= gray8.cols; x += 4) {
      ++partial[0][row[x]];
      ++partial[1][row[x + 1]];
      ++partial[2][row[x + 2]];
      ++partial[3][row[x + 3]];
    }
    for (; x < gray8.cols; ++x) ++partial[0][row[x]];
  }
  int64_t histogram[256];
  for (int v = 0; v < 256; ++v) histogram[v] = partial[0][v] + partial[1][v] + partial[2][v] + partial[3][v];
  const double n = static_cast<double>(gray8.total());
  double sum = 0.0, sum_sq = 0.0;
  int64_t dark = 0, bright = 0;
  for (int v = 0; v < 256; ++v) {
    sum += static_cast<double>(v) * histogram[v];
    sum_sq += static_cast<double>(v) * v * histogram[v];
    if (v <= options.dark_level) dark += histogram[v];
    if (v >= options.saturated_level) bright += histogram[v];
  }
  check.mean = sum / n;
  check.stddev = std::sqrt(std::max(0.0, sum_sq / n - check.mean * check.mean));
  check.dark_fraction = static_cast<double>(dark) / n;
  check.saturated_fraction = static_cast<double>(bright) / n;
  std::ostringstream why;
  if (check.dark_fraction >= options.bad_pixel_fraction) {
    check.quality = ImageQuality::kBlack;
    why << "black image: " << static_cast<int>(100 * check.dark_fraction) << "% of pixels <= " << options.dark_level;
  } else if (check.saturated_fraction >= options.bad_pixel_fraction) {
    check.quality = ImageQuality::kSaturated;
    why << "saturated image: " << static_cast<int>(100 * check.saturated_fraction) << "% of pixels >= "
        << options.saturated_level;
  } else if (check.stddev < options.min_stddev) {
    check.quality = ImageQuality::kFeatureless;
    why << "featureless image: grey-level std " << check.stddev << " < " << options.min_stddev;
  }
  check.reason = why.str();
  return check;
}

}  // namespace nadir
