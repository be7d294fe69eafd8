#pragma once
// Harris corners for one grid cell, spaced away from features that already
// exist. Deterministic: candidates are ordered by response, then row, then
// column, so the same image and the same existing features give the same
// corners on every run and every machine thread count.

#include <opencv2/core.hpp>

#include <vector>

#include "processes/tracker/tracker_options.h"

namespace nadir {

// Points on a coarse grid so "is anything within min_distance?" is a look at
// 3x3 buckets instead of a scan over every feature.
class SpacingGrid {
 public:
  SpacingGrid(cv::Size image_size, double min_distance);
  void add(const cv::Point2f& p);
  bool is_free(const cv::Point2f& p) const;

 private:
  double min_distance_sq_;
  double bucket_size_;
  int cols_, rows_;
  std::vector<std::vector<cv::Point2f>> buckets_;
};

class GridCornerDetector {
 public:
  explicit GridCornerDetector(const TrackerOptions& options) : options_(options) {}

  // The rectangle of cell (col,row) in an image of `size`.
  cv::Rect cell_rect(cv::Size size, int col, int row) const;
  // Which cell a point falls in (index row * grid_cols + col).
  int cell_index(cv::Size size, const cv::Point2f& p) const;

  // Up to `wanted` corners in cell `cell` of `image` (CV_8UC1), each at least
  // min_distance from every point already in `spacing` (which the accepted
  // corners are added to). Appends to `out`; returns how many were added.
  int detect(const cv::Mat& image, int cell, int wanted, SpacingGrid& spacing, std::vector<cv::Point2f>& out);

 private:
  TrackerOptions options_;
  cv::Mat response_;   // reused buffers: no allocation per frame
  cv::Mat dilated_;
};

}  // namespace nadir
