#include "processes/tracker/track_end_norms.h"

namespace nadir {

std::vector<cv::Point2d> TrackEndNorms::undistort_prev(const std::vector<int64_t>& ids,
                                                       const std::vector<cv::Point2f>& px,
                                                       const CameraModel& camera) const {
  std::vector<cv::Point2d> norm(px.size());
  std::vector<size_t> missing;
  std::vector<cv::Point2f> missing_px;
  size_t k = 0;  // both lists ascend by id: one merge walk
  for (size_t i = 0; i < px.size(); ++i) {
    while (k < ends_.size() && ends_[k].id < ids[i]) ++k;
    const bool same = k < ends_.size() && ends_[k].id == ids[i] && ends_[k].px.x == px[i].x && ends_[k].px.y == px[i].y;
    if (same) {
      norm[i] = ends_[k].norm;
    } else {
      missing.push_back(i);
      missing_px.push_back(px[i]);
    }
  }
  const std::vector<cv::Point2d> fresh = camera.undistort(missing_px);
  for (size_t m = 0; m < missing.size(); ++m) norm[missing[m]] = fresh[m];
  return norm;
}

void TrackEndNorms::remember(const std::vector<int64_t>& ids, const std::vector<cv::Point2f>& px,
                             const std::vector<cv::Point2d>& norm) {
  ends_.resize(ids.size());
  for (size_t i = 0; i < ids.size(); ++i) ends_[i] = {ids[i], px[i], norm[i]};
}

}  // namespace nadir
