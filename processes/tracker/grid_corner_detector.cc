#include "processes/tracker/grid_corner_detector.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>

namespace nadir {

SpacingGrid::SpacingGrid(cv::Size image_size, double min_distance)
    : min_distance_sq_(min_distance * min_distance), bucket_size_(std::max(1.0, min_distance)) {
  cols_ = static_cast<int>(std::ceil(image_size.width / bucket_size_)) + 1;
  rows_ = static_cast<int>(std::ceil(image_size.height / bucket_size_)) + 1;
  buckets_.resize(static_cast<size_t>(cols_ * rows_));
}

void SpacingGrid::add(const cv::Point2f& p) {
  const int c = std::clamp(static_cast<int>(p.x / bucket_size_), 0, cols_ - 1);
  const int r = std::clamp(static_cast<int>(p.y / bucket_size_), 0, rows_ - 1);
  buckets_[static_cast<size_t>(r * cols_ + c)].push_back(p);
}

bool SpacingGrid::is_free(const cv::Point2f& p) const {
  const int c0 = std::clamp(static_cast<int>(p.x / bucket_size_), 0, cols_ - 1);
  const int r0 = std::clamp(static_cast<int>(p.y / bucket_size_), 0, rows_ - 1);
  for (int r = std::max(0, r0 - 1); r <= std::min(rows_ - 1, r0 + 1); ++r) {
    for (int c = std::max(0, c0 - 1); c <= std::min(cols_ - 1, c0 + 1); ++c) {
      for (const cv::Point2f& q : buckets_[static_cast<size_t>(r * cols_ + c)]) {
        const double dx = p.x - q.x, dy = p.y - q.y;
        if (dx * dx + dy * dy < min_distance_sq_) return false;
      }
    }
  }
  return true;
}

cv::Rect GridCornerDetector::cell_rect(cv::Size size, int col, int row) const {
  const int x0 = size.width * col / options_.grid_cols;
  const int x1 = size.width * (col + 1) / options_.grid_cols;
  const int y0 = size.height * row / options_.grid_rows;
  const int y1 = size.height * (row + 1) / options_.grid_rows;
  return {x0, y0, x1 - x0, y1 - y0};
}

int GridCornerDetector::cell_index(cv::Size size, const cv::Point2f& p) const {
  // The inverse of cell_rect's integer split: column c starts at
  // floor(width * c / cols), so pixel x is in column floor((cols * (x + 1) - 1) / width).
  const int x = std::clamp(static_cast<int>(std::floor(p.x)), 0, size.width - 1);
  const int y = std::clamp(static_cast<int>(std::floor(p.y)), 0, size.height - 1);
  const int col = (options_.grid_cols * (x + 1) - 1) / size.width;
  const int row = (options_.grid_rows * (y + 1) - 1) / size.height;
  return row * options_.grid_cols + col;
}

int GridCornerDetector::detect(const cv::Mat& image, int cell, int wanted, SpacingGrid& spacing,
                               std::vector<cv::Point2f>& out) {
  if (wanted <= 0) return 0;
  const cv::Rect cell_box = cell_rect(image.size(), cell % options_.grid_cols, cell / options_.grid_cols);
  // Corners must keep border_px from the image edge; the cell box is clipped.
  const int b = options_.border_px;
  const cv::Rect inner = cell_box & cv::Rect(b, b, image.cols - 2 * b, image.rows - 2 * b);
  if (inner.width < 3 || inner.height < 3) return 0;

  // Harris on the cell. The filters read pixels just outside the ROI from the
  // parent image, so corners on cell borders are not damped.
  cv::cornerHarris(image(inner), response_, options_.harris_block_size, 3, options_.harris_k, cv::BORDER_REFLECT_101);
  double max_response = 0.0;
  cv::minMaxLoc(response_, nullptr, &max_response);
  const double threshold = std::max(options_.min_harris_response, options_.quality_level * max_response);
  if (max_response < threshold) return 0;
  // Non-maximum suppression over 3x3 neighbourhoods.
  cv::dilate(response_, dilated_, cv::Mat());

  struct Candidate {
    float response;
    int y, x;
  };
  std::vector<Candidate> candidates;
  for (int y = 0; y < response_.rows; ++y) {
    const float* r = response_.ptr<float>(y);
    const float* d = dilated_.ptr<float>(y);
    for (int x = 0; x < response_.cols; ++x) {
      if (r[x] >= threshold && r[x] == d[x]) candidates.push_back({r[x], y, x});
    }
  }
  std::sort(candidates.begin(), candidates.end(), [](const Candidate& a, const Candidate& c) {
    if (a.response != c.response) return a.response > c.response;
    if (a.y != c.y) return a.y < c.y;
    return a.x < c.x;
  });

  int added = 0;
  for (const Candidate& c : candidates) {
    const cv::Point2f p(static_cast<float>(inner.x + c.x), static_cast<float>(inner.y + c.y));
    if (!spacing.is_free(p)) continue;
    spacing.add(p);
    out.push_back(p);
    if (++added == wanted) break;
  }
  return added;
}

}  // namespace nadir
