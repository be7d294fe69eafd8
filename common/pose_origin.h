#pragma once
// Where POSE's local north-east-down frame lies on the Earth: the INS position
// (the GNSS-aided solution at the start) at the sensor time of the first
// POSE, moved back by that pose's own position (normally zero). Every process
// that ties POSE to the globe (the map matcher's fixes) must use this point:
// an origin read at a later pose carries that pose's error, and everything
// placed with it is shifted by it for the rest of the flight.
//
// The INS sample after the first pose usually comes after the pose (a
// lockstep replay, a live run), so the origin is known once an INS sample at
// or after the pose's time has been seen: the position is interpolated
// between the samples around the pose, or moved along the nearest sample's
// velocity when the INS starts within max_extrapolation_s after the pose. A
// pose the INS cannot place (no sample within that time on one side) is
// passed over and the next one is tried; such a pose is counted.

#include <cstdint>
#include <deque>
#include <optional>

#include "common/geodetic.h"
#include "nadir/ins_t.hpp"
#include "nadir/pose_t.hpp"

namespace nadir {

class PoseOrigin {
 public:
  // Throws std::invalid_argument unless 0 <= max_extrapolation_s <= 1.
  explicit PoseOrigin(double max_extrapolation_s = 0.05);

  // Messages in the order they arrive; each may make the origin known.
  void add_ins(const ins_t& ins);
  void add_pose(const pose_t& pose);

  bool known() const { return origin_.has_value(); }
  // The geodetic point of POSE's (0, 0, 0); only when known().
  const GeodeticPoint& origin() const { return *origin_; }
  // The sensor time of the pose the origin was read at (0 until known).
  int64_t anchored_utime() const { return anchored_utime_; }
  // Poses passed over because the INS could not place them.
  int64_t poses_passed_over() const { return passed_over_; }

 private:
  struct PendingPose {
    int64_t utime;
    Eigen::Vector3d position_ned;
  };
  void resolve();
  void anchor(const PendingPose& pose, const GeodeticPoint& ins_at_pose);

  int64_t max_extrapolation_us_;
  std::deque<ins_t> ins_;           // recent INS samples, time order
  std::deque<PendingPose> poses_;   // poses not placed yet, the first first
  std::optional<GeodeticPoint> origin_;
  int64_t anchored_utime_ = 0;
  int64_t passed_over_ = 0;
};

}  // namespace nadir
