#pragma once
// Frames and priors for the map matcher's tests, benchmark and study: a
// frame the simulator's renderer takes over its terrain at a known pose, the
// POSE that is its prior, and a simulated map written as GeoTIFFs.

#include <Eigen/Core>

#include <cstdint>
#include <string>
#include <vector>

#include "nadir/image_t.hpp"
#include "nadir/pose_t.hpp"
#include "processes/sim/flight_profile.h"
#include "processes/sim/sim_camera.h"
#include "processes/sim/terrain.h"

namespace nadir::test {

// A MONO8 frame of these pixels (stride = width).
image_t mono8_frame(std::vector<uint8_t> pixels, int width, int height, int64_t utime);

// The frame at (north, east), `height_agl` above the terrain there, with
// this attitude (rad), rendered with pixel noise `noise_key`.
image_t rendered_frame(const sim::SimCamera& camera, const sim::Terrain& terrain, double north, double east,
                       double height_agl, const Eigen::Vector3d& rpy, uint64_t noise_key, int64_t utime);

// A POSE at (north, east) with this attitude (rad) and height above ground,
// horizontal sigma `sigma` on both axes (the position already off by whatever
// the caller added).
pose_t prior_pose(double north, double east, const Eigen::Vector3d& rpy, double height_agl, double sigma,
                  int64_t utime);

// nadir_map simulate's orthophoto.tif and dem.tif of `profile` with `seed` into `dir`.
void write_simulated_map(const std::string& dir, const sim::FlightProfile& profile, uint64_t seed, double margin_m);

}  // namespace nadir::test
