#include "tools/track_truth/track_truth.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>

namespace nadir::track_truth {

const std::vector<std::array<int, 2>>& drift_age_bins() {
  static const std::vector<std::array<int, 2>> bins = {
      {1, 5}, {5, 10}, {10, 20}, {20, 40}, {40, 80}, {80, 160}, {160, 320}, {320, std::numeric_limits<int>::max()}};
  return bins;
}

void ExpansionFit::add(const Eigen::Vector2d& error, const Eigen::Vector2d& radius) {
  ++count_;
  sum_rx_ += radius.x();
  sum_ry_ += radius.y();
  sum_rr_ += radius.squaredNorm();
  sum_ex_ += error.x();
  sum_ey_ += error.y();
  sum_er_ += error.dot(radius);
}

double ExpansionFit::expansion() const {
  if (count_ < 3) return 0.0;
  const double n = static_cast<double>(count_);
  Eigen::Matrix3d a;
  a << n, 0, sum_rx_, 0, n, sum_ry_, sum_rx_, sum_ry_, sum_rr_;
  const Eigen::Vector3d solution = a.ldlt().solve(Eigen::Vector3d(sum_ex_, sum_ey_, sum_er_));
  return solution.allFinite() ? solution.z() : 0.0;
}

void TrackTruth::Accumulator::add(const Eigen::Vector2d& e) {
  ++count;
  sum_x += e.x();
  sum_y += e.y();
  sum_sq += e.squaredNorm();
  lengths.push_back(static_cast<float>(e.norm()));
}

ErrorStats TrackTruth::Accumulator::stats() {
  ErrorStats s;
  s.count = count;
  if (count == 0) return s;
  s.mean_x = sum_x / static_cast<double>(count);
  s.mean_y = sum_y / static_cast<double>(count);
  s.rms = std::sqrt(sum_sq / static_cast<double>(count));
  const auto mid = lengths.begin() + static_cast<std::ptrdiff_t>(lengths.size() / 2);
  std::nth_element(lengths.begin(), mid, lengths.end());
  s.median_abs = *mid;
  return s;
}

TrackTruth::TrackTruth(const SimScene& scene, const CameraModel& estimator_camera)
    : scene_(scene), estimator_camera_(estimator_camera), drift_(drift_age_bins().size()),
      drift_expansion_(drift_age_bins().size()),
      flow_expansion_by_age_(drift_age_bins().size()) {}

void TrackTruth::write_position(const Eigen::Vector2d& px, float* pixel, double* normalized) const {
  const std::vector<cv::Point2d> n =
      estimator_camera_.undistort({cv::Point2f(static_cast<float>(px.x()), static_cast<float>(px.y()))});
  pixel[0] = static_cast<float>(px.x());
  pixel[1] = static_cast<float>(px.y());
  normalized[0] = n[0].x;
  normalized[1] = n[0].y;
}

FrameFlow TrackTruth::process(tracks_t* tracks, Rewrite rewrite) {
  const int64_t index = counts_.messages++;
  FrameFlow frame;
  frame.utime = tracks->utime;
  CameraPose prev, curr;
  if (tracks->num_tracks == 0) return frame;
  if (!scene_.pose_at(tracks->prev_utime, &prev) || !scene_.pose_at(tracks->utime, &curr)) {
    ++counts_.messages_without_truth;
    return frame;
  }
  Accumulator frame_errors;
  ExpansionFit frame_expansion;
  const auto& bins = drift_age_bins();
  for (int i = 0; i < tracks->num_tracks; ++i) {
    ++counts_.tracks;
    const int64_t id = tracks->track_id[i];
    last_seen_[id] = index;
    const Eigen::Vector2d prev_px(tracks->prev_px[i][0], tracks->prev_px[i][1]);
    const Eigen::Vector2d curr_px(tracks->curr_px[i][0], tracks->curr_px[i][1]);
    Eigen::Vector3d under_prev;
    if (!scene_.ground_point(prev, prev_px, &under_prev)) {
      ++counts_.ray_misses;
      continue;
    }
    auto first = first_point_.find(id);
    if (first == first_point_.end()) first = first_point_.emplace(id, under_prev).first;
    Eigen::Vector2d step_px, first_prev_px, first_curr_px;
    const bool seen = scene_.visible(curr, under_prev);
    if (!seen) ++counts_.occluded;
    const bool step_known = seen && scene_.pixel_of(curr, under_prev, &step_px);
    if (step_known) {
      const Eigen::Vector2d error = curr_px - step_px;
      const Eigen::Vector2d radius = step_px - Eigen::Vector2d(scene_.camera().cx, scene_.camera().cy);
      flow_.add(error);
      expansion_.add(error, radius);
      frame_errors.add(error);
      frame_expansion.add(error, radius);
      const int age = std::max(1, static_cast<int>(tracks->age[i]));
      for (size_t b = 0; b < bins.size(); ++b)
        if (age >= bins[b][0] && age < bins[b][1]) flow_expansion_by_age_[b].add(error, radius);
    }
    const bool first_in_view = scene_.pixel_of(curr, first->second, &first_curr_px);
    if (first_in_view && scene_.visible(curr, first->second)) {
      const int age = std::max(1, static_cast<int>(tracks->age[i]));
      for (size_t b = 0; b < bins.size(); ++b) {
        if (age >= bins[b][0] && age < bins[b][1]) {
          drift_[b].add(curr_px - first_curr_px);
          drift_expansion_[b].add(curr_px - first_curr_px,
                                  first_curr_px - Eigen::Vector2d(scene_.camera().cx, scene_.camera().cy));
        }
      }
    }
    if (rewrite == Rewrite::kFlow && step_known)
      write_position(step_px, tracks->curr_px[i].data(), tracks->curr_norm[i].data());
    if (rewrite == Rewrite::kExact && first_in_view && scene_.pixel_of(prev, first->second, &first_prev_px)) {
      write_position(first_prev_px, tracks->prev_px[i].data(), tracks->prev_norm[i].data());
      write_position(first_curr_px, tracks->curr_px[i].data(), tracks->curr_norm[i].data());
    }
  }
  // Forget tracks not seen for a while (ids are never reused).
  if (index % 64 == 0) {
    for (auto it = last_seen_.begin(); it != last_seen_.end();) {
      if (index - it->second > 64) {
        first_point_.erase(it->first);
        it = last_seen_.erase(it);
      } else {
        ++it;
      }
    }
  }
  const ErrorStats stats = frame_errors.stats();
  frame.count = stats.count;
  frame.mean_x = stats.mean_x;
  frame.mean_y = stats.mean_y;
  frame.rms = stats.rms;
  frame.expansion = frame_expansion.expansion();
  return frame;
}

TrackTruthReport TrackTruth::report() const {
  TrackTruthReport r = counts_;
  Accumulator flow = flow_;
  r.flow = flow.stats();
  r.flow_expansion_per_frame = expansion_.expansion();
  const auto& bins = drift_age_bins();
  for (size_t b = 0; b < bins.size(); ++b) {
    Accumulator a = drift_[b];
    if (a.count == 0) continue;
    AgeBin bin;
    bin.from = bins[b][0];
    bin.to = bins[b][1];
    bin.drift = a.stats();
    bin.drift_expansion = drift_expansion_[b].expansion();
    bin.flow_expansion = flow_expansion_by_age_[b].expansion();
    r.drift_by_age.push_back(bin);
  }
  return r;
}

}  // namespace nadir::track_truth
