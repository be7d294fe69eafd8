#pragma once
// Per-track depth for the feature_depth variant (DERIVATION.md section 13):
// each track's depth in the level frame of the last solved frame, with its
// standard deviation, refined at every frame by triangulating the pair's two
// rays with the solved motion and INS attitude (inverse-variance fusion with
// the previous depth carried over by that motion and re-anchored on the
// altimeter). Nothing survives a frame that was not solved: a gap, a tracker
// reset, a time jump or a failed estimate clears the map, so no stale depth
// is used across it.

#include <Eigen/Core>

#include <cstdint>
#include <unordered_map>
#include <vector>

#include "processes/vo_solver/translation_solver.h"

namespace nadir::vo {

class FeatureDepthMap {
 public:
  explicit FeatureDepthMap(const SolverOptions& options) : options_(options) {}

  void reset();
  // Fills pair->prev_depth_m / prev_depth_sigma_m (NaN: unknown) for the
  // tracks `ids` (parallel to the pair's points), and pair->prev_tilt /
  // prev_tilt_variance (the frame's INS tilt error as estimated), and
  // pair->earlier_ground_spots (anchor_spots track). The stored depths are for
  // the frame at the utime they were stored at: if that is not prev_utime
  // (a frame was skipped), the map is cleared first.
  void fill(const std::vector<int64_t>& ids, int64_t prev_utime, FramePair* pair);
  // After `pair` (filled by `fill`) was solved into `est`: stores each
  // track's depth in the level frame of curr (curr_utime). A failed estimate
  // clears the map.
  void update(const std::vector<int64_t>& ids, int64_t curr_utime, const FramePair& pair, const Estimate& est);

  // Tracks with a depth (tracked without parallax yet: not counted).
  size_t size() const;
  int64_t resets() const { return resets_; }
  // Tracks whose own depth was used and rejected by the fit (a cliff edge, a
  // moving object): the depth is dropped, not fused.
  int64_t rejected_depths() const { return rejected_; }
  // Tracks off their epipolar line under the solved motion: no depth.
  int64_t off_epipolar() const { return off_epipolar_; }

  // A track's point in the level frame of the map's frame (camera at the
  // origin) and the standard deviation of its depth.
  struct GroundPoint {
    int64_t track_id;
    Eigen::Vector3d position;
    double depth_sigma;
  };
  // The tracks whose depth sigma is below max_relative_sigma of the depth, by
  // track id (the points the fit itself would trust).
  std::vector<GroundPoint> trusted_points(double max_relative_sigma) const;

 private:
  // A track: its first ray (origin and direction, from the camera that first
  // saw it) and its depth, all in the level frame of the map's frame. Depth
  // NaN: no parallax yet (hover); the track is kept so that it can grow one.
  struct Entry {
    Eigen::Vector3d origin = Eigen::Vector3d::Zero(), ray = Eigen::Vector3d::UnitZ();
    double depth = 0, sigma = 0;  // vertical depth below the camera, metres
    Eigen::Vector3d point = Eigen::Vector3d::Zero();  // the track's point (depth finite)
  };
  // Prev's altimeter spot and every earlier one, moved into curr's level
  // frame by the solved motion (to_curr (X - t)).
  void move_spots(const FramePair& pair, const Eigen::Matrix3d& to_curr, const Eigen::Vector3d& t);

  SolverOptions options_;
  std::unordered_map<int64_t, Entry> depths_;
  int64_t utime_ = INT64_MIN;
  // anchor_spots track: the altimeter's ground spots of the frames up to the
  // map's frame, newest first, in its level frame (FramePair::earlier_ground_spots).
  std::vector<Eigen::Vector3d> spots_;
  // The map frame's INS roll/pitch error as estimated (FramePair::prev_tilt).
  Eigen::Vector2d tilt_ = Eigen::Vector2d::Zero(), tilt_variance_ = Eigen::Vector2d::Zero();
  // Pairs in a row that kept the depths' scale without an anchor (0: the
  // last was anchored; -1: no anchored scale, FramePair::carried_scale_pairs).
  int carried_scale_pairs_ = -1;
  double scale_variance_ = 0;  // FramePair::prev_scale_variance
  int64_t resets_ = 0, rejected_ = 0, off_epipolar_ = 0;
};

}  // namespace nadir::vo
