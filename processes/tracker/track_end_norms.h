#pragma once
// Undistorted (normalized) coordinates of the last published frame's track
// ends, kept by track id. A track's prev_px is bit for bit the curr_px it was
// published with one frame earlier, so its undistortion - after KLT the
// tracker node's costliest step - need not be repeated. A point whose id or
// pixel does not match exactly (a new corner, a restart) is undistorted
// afresh; undistortion works point by point, so the result is identical.

#include <opencv2/core.hpp>

#include <cstdint>
#include <vector>

#include "common/camera_model.h"

namespace nadir {

class TrackEndNorms {
 public:
  // Normalized coordinates of `px`; ids ascending, one per point.
  std::vector<cv::Point2d> undistort_prev(const std::vector<int64_t>& ids, const std::vector<cv::Point2f>& px,
                                          const CameraModel& camera) const;
  // Replaces what is kept with this frame's track ends (ids ascending).
  void remember(const std::vector<int64_t>& ids, const std::vector<cv::Point2f>& px,
                const std::vector<cv::Point2d>& norm);

 private:
  struct End {
    int64_t id;
    cv::Point2f px;
    cv::Point2d norm;
  };
  std::vector<End> ends_;  // ascending id
};

}  // namespace nadir
