#pragma once
// The simulated world a log was flown in, rebuilt from the simulator's CONFIG
// message: the terrain (seed and relief of the profile as flown), the camera
// as it really was (the configured one with the sensor set's errors) and where
// it sat on the aircraft, and the flight's frame poses from GROUND_TRUTH.
// Built from the simulator's own code (processes/sim), never from the
// estimator's geometry, so it is an independent witness.

#include <Eigen/Core>
#include <cstdint>
#include <map>
#include <memory>
#include <string>

#include "nadir/ground_truth_t.hpp"
#include "processes/sim/sim_camera.h"
#include "processes/sim/terrain.h"

namespace nadir::track_truth {

// A camera pose: centre (NED, m) and world <- camera rotation.
struct CameraPose {
  Eigen::Vector3d centre;
  Eigen::Matrix3d world_from_camera;
};

class SimScene {
 public:
  // `config_yaml`: the yaml of the simulator's CONFIG message (name "sim");
  // `source` names it in errors. Throws ConfigError naming the missing or
  // wrong key.
  SimScene(const std::string& config_yaml, const std::string& source);

  const sim::Terrain& terrain() const { return *terrain_; }
  const sim::SimCamera& camera() const { return camera_; }
  uint64_t seed() const { return seed_; }
  double relief_scale() const { return relief_scale_; }

  // Records a GROUND_TRUTH message; only frame truth (KIND_FRAME) is kept.
  void add_truth(const ground_truth_t& truth);
  size_t frames() const { return frames_.size(); }
  // The camera pose of the frame stamped `utime` (sensor time of the image):
  // the frame truth nearest its exposure (utime + the camera's exposure
  // delay), within a quarter of the frame period. False when none is.
  bool pose_at(int64_t utime, CameraPose* pose) const;

  // Ground point seen along the camera ray through distorted pixel `px`;
  // false when the ray misses the terrain.
  bool ground_point(const CameraPose& pose, const Eigen::Vector2d& px, Eigen::Vector3d* point) const;
  // Distorted pixel of `point`; false when it is behind the camera.
  bool pixel_of(const CameraPose& pose, const Eigen::Vector3d& point, Eigen::Vector2d* px) const;
  // True when nothing of the terrain lies between the camera and `point`.
  bool visible(const CameraPose& pose, const Eigen::Vector3d& point) const;

 private:
  uint64_t seed_ = 0;
  double relief_scale_ = 0;
  std::unique_ptr<const sim::Terrain> terrain_;
  sim::SimCamera camera_;
  Eigen::Vector3d lever_arm_body_ = Eigen::Vector3d::Zero();
  int64_t exposure_delay_us_ = 0;
  int64_t match_window_us_ = 0;
  std::map<int64_t, CameraPose> frames_;  // by exposure utime
};

}  // namespace nadir::track_truth
