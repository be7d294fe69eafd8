#pragma once
// Frame-to-frame matching with feature descriptors (OpenCV features2d: ORB,
// AKAZE or SIFT) for what KLT cannot follow: photo surveys seconds apart,
// any heading change up to 180 degrees, 30-100 % overlap. Per frame:
// keypoints spread over a grid, candidates by ratio test and mutual cross
// check, then RANSAC on the undistorted normalized coordinates (homography
// or fundamental matrix). The inliers are the tracks. A keypoint matched
// again in the next pair keeps its id, and its age counts the frames.
//
// Deterministic: keypoints are sorted by response, position, size and angle
// before they are selected (the detectors' own order can depend on threads),
// brute-force matching has no randomness, and OpenCV's RANSAC seeds its
// generator on every call.

#include <opencv2/core.hpp>
#include <opencv2/features2d.hpp>

#include <cstdint>
#include <vector>

#include "common/camera_model.h"
#include "processes/tracker/feature_tracker.h"
#include "processes/tracker/tracker_options.h"

namespace nadir {

// One frame's keypoints, ready to match.
struct DescribedFrame {
  std::vector<cv::Point2f> px;      // distorted pixels
  std::vector<cv::Point2d> norm;    // camera_.undistort(px)
  cv::Mat descriptors;              // one row per keypoint
  std::vector<int64_t> ids;
  std::vector<int32_t> ages;
};

// A candidate correspondence: keypoint `prev` of the reference frame and
// `curr` of the new one.
struct DescriptorMatch {
  int prev = 0;
  int curr = 0;
};

struct DescriptorStepStats {
  int keypoints = 0;       // in the current frame
  int candidates = 0;      // after ratio test and cross check
  int inliers = 0;         // after the geometric check (= tracks)
  bool geometry_failed = false;  // too few candidates or no model found
};

class DescriptorMatcher {
 public:
  // Throws ConfigError for bad options.
  DescriptorMatcher(const DescriptorOptions& options, const CameraModel& camera);

  // Matches `image` (CV_8UC1) against the reference frame and makes it the
  // new reference. The first call (or after reset) only describes.
  // result.tracks ascend by id; features_after is the number of keypoints.
  TrackStepResult process(const cv::Mat& image);
  // Makes `image` the reference without matching (new ids for everything).
  void set_reference(const cv::Mat& image);
  void reset();
  bool has_reference() const { return have_reference_; }

  // Ids are never reused; callers that run another tracker beside this one
  // share the count through these.
  int64_t next_id() const { return next_id_; }
  void set_next_id(int64_t id) { next_id_ = id; }

  const DescriptorStepStats& last_stats() const { return stats_; }
  const DescriptorOptions& options() const { return options_; }

  // The steps, public for the tests.
  DescribedFrame describe(const cv::Mat& image) const;
  std::vector<DescriptorMatch> candidates(const DescribedFrame& prev, const DescribedFrame& curr) const;
  // The candidates consistent with one homography (or fundamental matrix)
  // between the normalized coordinates; empty when none is found.
  std::vector<DescriptorMatch> geometric_inliers(const std::vector<cv::Point2d>& prev_norm,
                                                 const std::vector<cv::Point2d>& curr_norm,
                                                 const std::vector<DescriptorMatch>& matches) const;

 private:
  DescriptorOptions options_;
  CameraModel camera_;
  cv::Ptr<cv::Feature2D> detector_;
  int norm_type_;
  bool have_reference_ = false;
  cv::Size image_size_;
  DescribedFrame reference_;
  int64_t next_id_ = 1;
  DescriptorStepStats stats_;
};

}  // namespace nadir
