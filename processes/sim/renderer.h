#pragma once
// Renders the camera's 8-bit mono image of the terrain: a per-pixel ray from
// the precomputed undistorted ray table (cv::undistortPoints), rotated into the
// world by the camera pose, intersected with the height field (occlusion
// included), shaded by slope, textured by footprint (trilinear mip sampling =
// anti-aliasing), plus Gaussian-like pixel noise.

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "processes/sim/sim_camera.h"
#include "processes/sim/terrain.h"
#include "processes/sim/texture_cache.h"

namespace nadir::sim {

struct RendererOptions {
  double pixel_noise_dn = 2.0;  // sigma of the additive pixel noise, digital numbers
  double gain = 1.0;            // albedo -> DN
  int coarse_step_px = 16;      // spacing of the exact-solve grid that seeds per-pixel Newton
  void Check() const;
};

// A bright disc painted on the ground, for projection tests.
struct GroundMarker {
  double north = 0, east = 0, radius_m = 1.0;
  float value = 255.0f;
};

struct RenderStats {
  int64_t marched_pixels = 0;  // pixels that took the occlusion-safe path
  int64_t local_bound_pixels = 0;  // oblique pixels found monotone by their block's local slope bound
  int64_t sky_pixels = 0;      // rays that missed the ground
  int64_t full_solves = 0;     // pixels whose one-step Newton seed was not good enough
};

class Renderer {
 public:
  Renderer(const SimCamera& camera, const Terrain& terrain, const RendererOptions& options);

  // Renders into `image` (width*height bytes, stride = width).
  // camera_position_ned: projection centre; world_from_camera: rotation camera -> NED.
  // noise_key selects the pixel noise realisation (deterministic).
  void render(const Eigen::Vector3d& camera_position_ned, const Eigen::Matrix3d& world_from_camera,
              uint64_t noise_key, std::vector<uint8_t>* image);

  void set_markers(std::vector<GroundMarker> markers) { markers_ = std::move(markers); }
  // When set, each render() also writes every pixel's hit distance along its
  // unit ray (m; -1 where the ray misses the ground): true depth for tests.
  void set_depth_output(std::vector<float>* depth) { depth_out_ = depth; }
  const RenderStats& last_stats() const { return stats_; }
  const SimCamera& camera() const { return camera_; }
  // Unit ray of pixel (u, v) in the camera frame.
  Eigen::Vector3d pixel_ray(int u, int v) const;
  const TextureCache& texture() const { return texture_; }

 private:
  SimCamera camera_;
  const Terrain& terrain_;
  RendererOptions options_;
  TextureCache texture_;
  std::vector<float> ray_x_, ray_y_, ray_z_, pixel_angle_;  // per pixel
  std::vector<GroundMarker> markers_;
  std::vector<float>* depth_out_ = nullptr;
  RenderStats stats_;
  // Slope bound over the ground the rays of one coarse block can cross
  // (computed on demand; < 0: not yet this frame).
  double block_slope(int gx, int gy, int gw, const Eigen::Vector3d& origin);
  std::vector<double> coarse_t_;
  std::vector<Eigen::Vector3d> coarse_dir_;  // world direction of each coarse-grid ray
  std::vector<double> block_slope_;
  int64_t frame_ = 0;
};

}  // namespace nadir::sim
