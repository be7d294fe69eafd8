#pragma once
// Noise-free (or noisy, on request) feature pairs from a known tilted ground
// plane, known motion and attitude. Built from world poses and plain ray/plane
// intersection, not from the solver's own model code, so a convention error in
// the solver cannot cancel itself here.

#include <Eigen/Core>

#include <cstdint>
#include <random>
#include <vector>

#include "processes/vo_solver/translation_solver.h"

namespace nadir::vo::testing {

struct SceneSpec {
  double height_m = 300.0;        // vertical height of the curr camera above the plane
  double ground_roll = 0.0;       // plane attitude in the level frame of curr
  double ground_pitch = 0.0;
  double prev_roll = 0, prev_pitch = 0, prev_yaw = 0;
  double curr_roll = 0, curr_pitch = 0, curr_yaw = 0;
  Eigen::Vector3d translation = Eigen::Vector3d(2.1, 0.0, 0.0);  // level frame of prev
  Eigen::Matrix3d body_from_camera = Eigen::Matrix3d::Identity();
  Eigen::Vector3d beam_body = Eigen::Vector3d::UnitZ();
  int num_features = 450;
  int width = 612, height = 512;
  double fx = 398.79, cx = 305.5, cy = 255.5;
  double noise_px = 0.0;          // Gaussian, each coordinate of both frames
  double outlier_fraction = 0.0;  // these get the curr point displaced by ...
  double outlier_min_px = 10.0, outlier_max_px = 50.0;  // ... this many pixels
  // These get their ground point on a second layer this far above the plane
  // (tree tops over a lawn); the altimeter still sees the plane.
  double raised_fraction = 0.0, raised_height_m = 0.0;
  uint32_t seed = 1;
};

struct Scene {
  FramePair pair;
  std::vector<bool> is_outlier;
  std::vector<bool> is_raised;
  // Truth.
  Eigen::Vector3d translation;
  double dyaw = 0;
  double ground_roll = 0, ground_pitch = 0;
  double prev_altitude_m = 0;  // vertical height of the prev camera above the plane
};

Scene make_scene(const SceneSpec& spec);

}  // namespace nadir::vo::testing
