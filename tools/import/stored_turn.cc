#include "tools/import/stored_turn.h"

#include <opencv2/calib3d.hpp>
#include <opencv2/features2d.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "common/geometry.h"

namespace nadir::import {

void StoredTurnOptions::Check() const {
  auto require = [](bool ok, const char* field, const char* range) {
    if (!ok) throw std::invalid_argument(std::string("stored turn check: ") + field + " must be " + range);
  };
  require(max_side_px >= 160 && max_side_px <= 8000, "max_side_px", "in [160, 8000]");
  require(features >= 100 && features <= 100000, "features", "in [100, 100000]");
  require(min_inliers >= 8 && min_inliers <= 10000, "min_inliers", "in [8, 10000]");
  require(min_inlier_share > 0.0 && min_inlier_share <= 1.0, "min_inlier_share", "in (0, 1]");
  require(tolerance_deg > 0.0 && tolerance_deg < 45.0, "tolerance_deg", "in (0, 45) degrees");
}

StoredTurnCheck::StoredTurnCheck(const StoredTurnOptions& options) : options_(options) { options_.Check(); }

StoredTurnCheck::Features StoredTurnCheck::features_of(const cv::Mat& grey) const {
  Features f;
  const int side = std::max(grey.cols, grey.rows);
  cv::Mat small = grey;
  if (side > options_.max_side_px) {
    const double s = static_cast<double>(options_.max_side_px) / side;
    cv::resize(grey, small, cv::Size(), s, s, cv::INTER_AREA);
  }
  cv::Ptr<cv::ORB> orb = cv::ORB::create(options_.features);
  std::vector<cv::KeyPoint> keypoints;
  orb->detectAndCompute(small, cv::noArray(), keypoints, f.descriptors);
  const cv::Point2f centre(0.5f * static_cast<float>(small.cols - 1), 0.5f * static_cast<float>(small.rows - 1));
  f.points.reserve(keypoints.size());
  for (const cv::KeyPoint& k : keypoints) f.points.push_back(k.pt - centre);
  return f;
}

StoredTurnLink StoredTurnCheck::link(const Features& a, const Eigen::Matrix3d& world_from_a, const Features& b,
                                     const Eigen::Matrix3d& world_from_b) const {
  StoredTurnLink l;
  // Camera b in camera a's axes: a turn by phi about the optical axis moves
  // the ground's image by -phi (x columns, y rows: positive = clockwise on screen).
  const Eigen::Matrix3d a_from_b = world_from_a.transpose() * world_from_b;
  l.predicted_rotation_deg = rad_to_deg(-std::atan2(a_from_b(1, 0), a_from_b(0, 0)));
  if (a.descriptors.empty() || b.descriptors.empty()) return l;
  cv::BFMatcher matcher(cv::NORM_HAMMING, true);
  std::vector<cv::DMatch> matches;
  matcher.match(a.descriptors, b.descriptors, matches);
  if (static_cast<int>(matches.size()) < options_.min_inliers) return l;
  std::vector<cv::Point2f> pa, pb;
  for (const cv::DMatch& m : matches) {
    pa.push_back(a.points[static_cast<size_t>(m.queryIdx)]);
    pb.push_back(b.points[static_cast<size_t>(m.trainIdx)]);
  }
  std::vector<uchar> inlier;
  cv::setRNGSeed(1);  // the same verdict on every run
  const cv::Mat m = cv::estimateAffinePartial2D(pa, pb, inlier, cv::RANSAC, 3.0, 2000, 0.995, 10);
  if (m.empty()) return l;
  l.inliers = static_cast<int>(std::count(inlier.begin(), inlier.end(), 1));
  if (l.inliers < options_.min_inliers ||
      l.inliers < options_.min_inlier_share * static_cast<double>(matches.size())) {
    return l;
  }
  l.image_rotation_deg = rad_to_deg(std::atan2(m.at<double>(1, 0), m.at<double>(0, 0)));
  const double difference = l.image_rotation_deg - l.predicted_rotation_deg;
  const double quarters = std::round(difference / 90.0);
  if (std::fabs(difference - 90.0 * quarters) > options_.tolerance_deg) return l;  // no quarter turn: not trusted
  l.quarter_turns = ((static_cast<int>(quarters) % 4) + 4) % 4;
  l.found = true;
  return l;
}

void StoredTurnCheck::add(const cv::Mat& grey, const Eigen::Matrix3d& world_from_camera) {
  aspect_.push_back(grey.empty() ? 0 : (grey.cols > grey.rows) - (grey.cols < grey.rows));
  if (grey.empty()) {
    links_.push_back({});
    have_previous_ = false;
    return;
  }
  Features current = features_of(grey);
  links_.push_back(have_previous_ ? link(previous_, previous_attitude_, current, world_from_camera) : StoredTurnLink{});
  previous_ = std::move(current);
  previous_attitude_ = world_from_camera;
  have_previous_ = true;
}

std::vector<StoredTurn> StoredTurnCheck::verdicts() const {
  const size_t n = links_.size();
  std::vector<StoredTurn> out(n);
  // The flight's aspect: most photos'; a photo of the other one is stored turned by a quarter turn.
  int64_t aspect_sum = 0;
  for (int a : aspect_) aspect_sum += a;
  const int flight_aspect = (aspect_sum > 0) - (aspect_sum < 0);
  std::vector<bool> transposed(n);
  for (size_t i = 0; i < n; ++i) transposed[i] = aspect_[i] != 0 && flight_aspect != 0 && aspect_[i] != flight_aspect;
  size_t begin = 0;
  while (begin < n) {
    size_t end = begin + 1;  // a chain: photos [begin, end) joined by found links
    while (end < n && links_[end].found) ++end;
    // Each photo's turn against the chain's first photo.
    std::vector<int> turn(end - begin, 0);
    for (size_t i = begin + 1; i < end; ++i) turn[i - begin] = (turn[i - begin - 1] + links_[i].quarter_turns) % 4;
    // The flight's orientation: the one most of the chain's photos have and
    // no photo's size contradicts (a transposed size is an odd turn).
    int best = 0;
    int64_t best_score = std::numeric_limits<int64_t>::min();
    for (int r = 0; r < 4; ++r) {
      int64_t score = 0;
      for (size_t i = begin; i < end; ++i) {
        const int k = (turn[i - begin] - r + 4) % 4;
        if (k % 2 != static_cast<int>(transposed[i])) score -= 1000000;  // impossible
        if (k == 0) ++score;
      }
      if (score > best_score) best_score = score, best = r;
    }
    const bool linked = end - begin > 1;
    for (size_t i = begin; i < end; ++i) {
      out[i].linked = linked;
      out[i].size_transposed = transposed[i];
      out[i].quarter_turns = linked ? (turn[i - begin] - best + 4) % 4 : 0;
    }
    begin = end;
  }
  return out;
}

cv::Mat read_grey_reduced(const std::string& path, int min_side_px, int full_width, int full_height) {
  const int side = std::max(full_width, full_height);
  int flag = cv::IMREAD_GRAYSCALE;
  if (side >= 8 * min_side_px) {
    flag = cv::IMREAD_REDUCED_GRAYSCALE_8;
  } else if (side >= 4 * min_side_px) {
    flag = cv::IMREAD_REDUCED_GRAYSCALE_4;
  } else if (side >= 2 * min_side_px) {
    flag = cv::IMREAD_REDUCED_GRAYSCALE_2;
  }
  return cv::imread(path, flag | cv::IMREAD_IGNORE_ORIENTATION);
}

cv::Mat turn_back(const cv::Mat& image, int quarter_turns) {
  static constexpr std::array<int, 4> kCodes{-1, cv::ROTATE_90_COUNTERCLOCKWISE, cv::ROTATE_180, cv::ROTATE_90_CLOCKWISE};
  const int k = ((quarter_turns % 4) + 4) % 4;
  if (k == 0) return image;
  cv::Mat turned;
  cv::rotate(image, turned, kCodes[static_cast<size_t>(k)]);
  return turned;
}

}  // namespace nadir::import
