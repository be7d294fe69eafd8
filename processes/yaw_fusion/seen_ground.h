#pragma once
// The ground the last integrated frame saw, for a coast. vo_solver's
// feature_depth variant triangulates its feature tracks and publishes the
// points it trusts (VO_GROUND, in the level frame of the frame); a frame's
// image covers the ground ahead of the vehicle as well as below it (about
// 0.75 x the height ahead with the default camera), so over the first part of
// a coast the altimeter's range is measured over ground whose height is
// known: the vehicle's down is that ground's minus the levelled range, with
// no climb rate to hold and no terrain shape to guess.
//
// No bus, no filter: the estimator places a frame's points in the world with
// the frame's pose and asks for the ground's down coordinate below a
// horizontal position.

#include <Eigen/Core>

#include <optional>
#include <vector>

#include "nadir/ground_points_t.hpp"

namespace nadir {

struct SeenGroundOptions {
  double radius_m = 25.0;  // points within this horizontal distance make the local ground
  int min_points = 5;      // fewer: the ground there was not seen
  // The points' weighted centroid farther than this share of the radius from
  // the position: it is at the edge of what was seen (a fit would be extrapolated).
  double max_centroid_offset = 0.3;
};

class SeenGround {
 public:
  // The frame's points (ground_points_t, level frame of the frame: x forward,
  // y right, z down from the INS reference point) placed with its position
  // (NED) and yaw; replaces the previous frame's.
  void note_frame(const ground_points_t& points, const Eigen::Vector3d& position, double yaw);
  void clear() { points_.clear(); }
  size_t size() const { return points_.size(); }

  struct Height {
    double down = 0.0;      // the ground's down coordinate below the position
    double variance = 0.0;  // m^2: the local fit's, plus the ground's own roughness about it
    int points = 0;
  };
  // The ground below `horizontal` (north, east): a plane fitted (weighted by
  // the points' depth variances) to the points within options.radius_m,
  // evaluated there; their weighted mean when they do not span a plane.
  // nullopt with fewer than options.min_points, or at the edge of the points.
  std::optional<Height> ground_down(const Eigen::Vector2d& horizontal, const SeenGroundOptions& options) const;

 private:
  struct Point {
    Eigen::Vector2d horizontal;
    double down;
    double variance;
  };
  std::vector<Point> points_;
};

}  // namespace nadir
