#pragma once
// A multi-frame flight over non-planar ground with persistent tracks, for the
// feature_depth variant: fixed world points (track id = point index) seen by
// a downward camera along a straight path. The ground under the path (where
// the altimeter looks) is level; beside it the points stand on blocks and in
// pits of different heights, so one plane through the altimeter spot does not
// hold them. Built from world poses and plain projection, not from the
// solver's model code.

#include <Eigen/Core>

#include <cstdint>
#include <functional>
#include <vector>

#include "processes/vo_solver/translation_solver.h"

namespace nadir::vo::testing {

struct TerrainSpec {
  double height_m = 150.0;          // camera above the level corridor at frame 0
  double climb_per_frame_m = 0.05;  // upward
  double step_m = 1.5;              // along the path per frame
  double heading = 0.3;             // path heading, rad
  double yaw_rate = 0.0;            // rad per frame, for the vehicle's heading (the path stays straight)
  double corridor_half_width_m = 45.0;  // level ground either side of the path
  double relief_m = 25.0;           // block heights beside the corridor up to this (and pits down to -relief/2)
  // Smooth ridges across the path, everywhere (the corridor too, so under the
  // altimeter): the ground rises by ridge_amplitude_m * (cos p + cos(2 p) / 2), p = 2 pi along /
  // ridge_wavelength_m: crests sharper than the valleys.
  double ridge_amplitude_m = 0.0;
  double ridge_wavelength_m = 160.0;
  // Instead: crests that are kinks (the ground rises by ridge_amplitude_m *
  // (1 - 2 |sin(p / 2)|)), which no smooth surface holds, over smooth valleys.
  bool sharp_crests = false;
  int num_points = 6000;
  double noise_px = 0.0;
  uint32_t seed = 1;
  double fx = 398.79, cx = 305.5, cy = 255.5;
  int width = 612, height = 512;
};

struct FramePose {
  Eigen::Vector3d position;  // NED, camera centre
  double roll = 0, pitch = 0, yaw = 0;
};

struct SequencePair {
  FramePair pair;
  std::vector<int64_t> ids;
  Eigen::Vector3d translation;  // truth, level frame of prev
  double dyaw = 0;
  std::vector<double> curr_depth_m;  // truth: vertical depth of each point below the curr camera
};

class TerrainSequence {
 public:
  explicit TerrainSequence(const TerrainSpec& spec);
  FramePose pose(int k) const;
  // The pair (k-1, k) with every point seen in both frames.
  SequencePair pair(int k) const;
  // The pair (j, k): a frame skipped between them when k - j = 2.
  SequencePair pair(int j, int k) const;
  // World points may be changed between frames (moving objects, cliff edges).
  std::vector<Eigen::Vector3d>& points() { return points_; }
  // Moving points: point i is at points()[i] + motion(i, k) in frame k.
  std::function<Eigen::Vector3d(size_t, int)> point_motion;
  // Overrides the pose of frame k (hover, custom motion).
  std::function<FramePose(int)> pose_override;
  // The altimeter's range (along body z) from a camera at `pose`: any time,
  // not only a frame's (a range sampled between frames).
  double range_at(const FramePose& pose) const;

 private:
  // Height of the ridges above the level corridor at a north-east position.
  double ridge_up(double north, double east) const;
  // Range from the camera at `position` along `beam` (unit) to the ground under the path.
  double range_to_corridor(const Eigen::Vector3d& position, const Eigen::Vector3d& beam) const;

  TerrainSpec spec_;
  std::vector<Eigen::Vector3d> points_;
};

}  // namespace nadir::vo::testing
