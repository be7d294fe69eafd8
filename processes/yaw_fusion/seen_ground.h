#pragma once
// The ground the last integrated frames saw, for a coast. vo_solver's
// feature_depth variant triangulates its feature tracks and publishes the
// points it trusts (VO_GROUND, in the level frame of the frame); a frame's
// image covers the ground ahead of the vehicle as well as below it (about
// 0.75 x the height ahead with the default camera), so over the first part of
// a coast the altimeter's range is measured over ground whose height is
// known: the vehicle's down is that ground's minus the levelled range, with
// no climb rate to hold and no terrain shape to guess.
//
// The points of the integrated frames of the last window are kept, each
// track's from the newest frame that had it (its depth filtered over the
// longest baseline): a frame whose image was already fading (the first
// frames of featureless ground) adds little, and the ground the frames before
// it saw ahead stays.
//
// No bus, no filter: the estimator places a frame's points in the world with
// the frame's pose and asks for the ground's down coordinate below a
// horizontal position.

#include <Eigen/Core>

#include <cstdint>
#include <optional>
#include <unordered_map>

#include "nadir/ground_points_t.hpp"

namespace nadir {

struct SeenGroundOptions {
  double radius_m = 25.0;  // points within this horizontal distance make the local ground
  int min_points = 8;      // fewer: the ground there was not seen
  // The points' centroid farther than this share of the radius from the
  // position: it is at the edge of what was seen (the plane would be
  // extrapolated; a half disc's centroid is at 0.42 of its radius).
  double max_centroid_offset = 0.4;
};

class SeenGround {
 public:
  explicit SeenGround(double window_s) : window_us_(static_cast<int64_t>(window_s * 1e6)) {}

  // An integrated frame's points (ground_points_t, level frame of the frame:
  // x forward, y right, z down from the INS reference point) placed with its
  // position (NED) and yaw; each replaces its track's older point, and points
  // last seen more than the window before it are dropped.
  void note_frame(const ground_points_t& points, const Eigen::Vector3d& position, double yaw);
  // An integrated frame without points: the window moves on.
  void note_frame_without_points(int64_t utime);
  void clear() { points_.clear(); }
  size_t size() const { return points_.size(); }
  // The positions the points were placed with were corrected by `shift` (a map fix).
  void move_with_position(const Eigen::Vector3d& shift) {
    for (auto& entry : points_) {
      entry.second.horizontal += shift.head<2>();
      entry.second.down += shift.z();
    }
  }

  struct Height {
    double down = 0.0;      // the ground's down coordinate below the position
    double variance = 0.0;  // m^2: the local fit's, plus the ground's own roughness about it
    int points = 0;
  };
  // The ground below `horizontal` (north, east): a plane fitted (weighted by
  // the points' depth variances) to the points within options.radius_m,
  // evaluated there. nullopt with fewer than options.min_points (at least
  // 3), points that do not span a plane (one line of them), or at the edge
  // of what was seen.
  std::optional<Height> ground_down(const Eigen::Vector2d& horizontal, const SeenGroundOptions& options) const;

 private:
  struct Point {
    Eigen::Vector2d horizontal;
    double down;
    double variance;
    int64_t utime;  // of the frame that placed it
  };
  int64_t window_us_;
  std::unordered_map<int64_t, Point> points_;  // by track id
};

}  // namespace nadir
