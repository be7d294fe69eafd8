// Occlusion by relief: for oblique rays over steep terrain the caster must
// return the FIRST intersection. Checked against a brute-force 2 cm march.
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include "processes/sim/ray_caster.h"
#include "processes/sim/renderer.h"
#include "sim_test_support.h"

namespace nadir::sim {
namespace {

double brute_force_first_hit(const Terrain& terrain, const Eigen::Vector3d& o, const Eigen::Vector3d& d, double t_max) {
  const double step = 0.02;
  double prev_t = 0.0;
  double prev_f = -o.z() - terrain.height(o.x(), o.y());
  for (double t = step; t < t_max; t += step) {
    const Eigen::Vector3d p = o + t * d;
    const double f = -p.z() - terrain.height(p.x(), p.y());
    if (f <= 0) return prev_t + step * prev_f / (prev_f - f);  // linear within 2 cm
    prev_t = t;
    prev_f = f;
  }
  return -1.0;
}

// The roughest relief: slopes oblique rays can graze.
Terrain steep_terrain(uint64_t seed) {
  TerrainOptions options;
  options.seed = seed;
  options.relief_scale = 3.0;
  return Terrain(options);
}

RendererOptions noiseless() {
  RendererOptions options;
  options.pixel_noise_dn = 0.0;
  return options;
}

TEST(Occlusion, ObliqueRaysHitTheFirstSurface) {
  const Terrain terrain = steep_terrain(17);
  int marched = 0, checked = 0;
  for (int i = 0; i < 40; ++i) {
    const double azimuth = i * 0.61, elevation_from_nadir = 0.9 + 0.015 * i;  // 52..86 degrees off nadir
    const Eigen::Vector3d d(std::sin(elevation_from_nadir) * std::cos(azimuth),
                            std::sin(elevation_from_nadir) * std::sin(azimuth), std::cos(elevation_from_nadir));
    const Eigen::Vector3d origin(100.0 * i, -37.0 * i, -(terrain.height(100.0 * i, -37.0 * i) + 25.0));
    RayHit hit;
    const bool found = cast_ray(terrain, origin, d, -1.0, &hit);
    const double reference = brute_force_first_hit(terrain, origin, d, 3000.0);
    if (reference < 0) {
      EXPECT_FALSE(found && hit.t < 3000.0) << "ray " << i;
      continue;
    }
    ASSERT_TRUE(found) << "ray " << i;
    EXPECT_NEAR(hit.t, reference, 0.01) << "ray " << i;
    marched += hit.marched;
    ++checked;
  }
  EXPECT_GT(checked, 30);
  EXPECT_GT(marched, 20);  // the occlusion-safe path really ran
}

TEST(Occlusion, RendererUsesTheSafePathForGrazingViews) {
  SimCamera camera = testing::default_camera();
  camera.body_from_camera = (Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitY())).toRotationMatrix();  // looking forward-down
  const Terrain terrain = steep_terrain(17);
  Renderer renderer(camera, terrain, noiseless());
  const Eigen::Vector3d origin(0, 0, -60.0);
  std::vector<uint8_t> image;
  renderer.render(origin, camera.body_from_camera, 1, &image);
  EXPECT_GT(renderer.last_stats().marched_pixels, 1000);
  // Spot-check pixels against the brute-force march.
  for (int v = 20; v < camera.height; v += 97)
    for (int u = 15; u < camera.width; u += 113) {
      const Eigen::Vector3d d = camera.body_from_camera * renderer.pixel_ray(u, v);
      RayHit hit;
      const double reference = brute_force_first_hit(terrain, origin, d.normalized(), 3000.0);
      if (reference < 0) continue;
      ASSERT_TRUE(cast_ray(terrain, origin, d.normalized(), -1.0, &hit));
      EXPECT_NEAR(hit.t, reference, 0.01) << u << "," << v;
    }
}

// The renderer's oblique pixels (banked over the roughest relief) take the
// locally monotone Newton path where their block's slope bound allows, the
// march elsewhere: every depth it rendered is the first hit.
TEST(Occlusion, LocalSlopeBoundsKeepTheFirstHit) {
  const SimCamera camera = testing::default_camera();
  const Terrain terrain = steep_terrain(5);
  Renderer renderer(camera, terrain, noiseless());
  std::vector<float> depth;
  renderer.set_depth_output(&depth);
  // 120 m above the ground, banked 14 degrees and pitched 4 degrees down.
  const Eigen::Matrix3d world_from_camera =
      (Eigen::AngleAxisd(0.6, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(-0.07, Eigen::Vector3d::UnitY()) *
       Eigen::AngleAxisd(0.244, Eigen::Vector3d::UnitX()))
          .toRotationMatrix();
  const Eigen::Vector3d origin(310.0, -420.0, -(terrain.height(310.0, -420.0) + 120.0));
  std::vector<uint8_t> image;
  renderer.render(origin, world_from_camera, 1, &image);
  EXPECT_GT(renderer.last_stats().local_bound_pixels, 20000);
  int checked = 0;
  for (int v = 3; v < camera.height; v += 23)
    for (int u = 5; u < camera.width; u += 29) {
      const Eigen::Vector3d d = (world_from_camera * renderer.pixel_ray(u, v)).normalized();
      if (terrain.max_slope() * std::hypot(d.x(), d.y()) < d.z()) continue;  // globally monotone: not new
      const double reference = brute_force_first_hit(terrain, origin, d, 1500.0);
      ASSERT_GT(reference, 0.0) << u << "," << v;
      // Float depth output: ~1e-5 relative.
      EXPECT_NEAR(depth[static_cast<size_t>(v) * camera.width + u], reference, 0.01) << u << "," << v;
      ++checked;
    }
  EXPECT_GT(checked, 100);
}

// The per-tile bounds hold for the surface everyone samples.
TEST(Occlusion, TileBoundsHoldTheSampledSurface) {
  const Terrain terrain = steep_terrain(9);
  const HeightBounds b = terrain.bounds(-100.0, 90.0, 30.0, 200.0);  // 4 x 4 tiles
  EXPECT_LE(b.max_slope, terrain.max_slope());
  EXPECT_LT(b.max_slope, 0.8 * terrain.max_slope());  // tighter than the analytic bound: why it pays
  EXPECT_GE(b.min_height, terrain.min_height());
  EXPECT_LE(b.max_height, terrain.max_height());
  double lo = 1e9, hi = -1e9;
  for (double n = -128.0; n < 128.0; n += 0.37)
    for (double e = 0.0; e < 256.0; e += 0.41) {
      double gn, ge;
      const double h = terrain.height(n, e, &gn, &ge);
      lo = std::min(lo, h);
      hi = std::max(hi, h);
      ASSERT_GE(h, b.min_height - 1e-9);
      ASSERT_LE(h, b.max_height + 1e-9);
      ASSERT_LE(std::hypot(gn, ge), b.max_slope);
    }
  // The bounds are the samples' own extremes, not loose.
  EXPECT_NEAR(lo, b.min_height, 0.5);
  EXPECT_NEAR(hi, b.max_height, 0.5);
}

}  // namespace
}  // namespace nadir::sim
