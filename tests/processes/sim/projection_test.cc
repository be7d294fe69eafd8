// The renderer is a correct perspective projection: ground markers land where
// cv::projectPoints puts them, computed here from the test's own pose algebra.
// Also the terrain itself: relief, texture, featureless areas and the
// profiles that fly over them.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <opencv2/calib3d.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>

#include "processes/sim/featureless_area.h"
#include "processes/sim/flight_profile.h"
#include "processes/sim/ray_caster.h"
#include "processes/sim/renderer.h"
#include "processes/sim/simulator.h"
#include "sim_test_support.h"

namespace nadir::sim {
namespace {

using testing::default_camera;

// R_world_body = Rz(yaw) Ry(pitch) Rx(roll), written with AngleAxis so it does
// not share code with the simulator's rotation helpers.
Eigen::Matrix3d rotation_zyx(double roll, double pitch, double yaw) {
  return (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

struct ProjectionCase {
  double roll_deg, pitch_deg, yaw_deg;
  double mount_roll_deg, mount_pitch_deg, mount_yaw_deg;
  double altitude_m;
};

// Centroid of a marker's coverage = (image with a white marker - image with a
// black marker) / 255, which removes the texture under it exactly.
cv::Point2d coverage_centroid(const std::vector<uint8_t>& white, const std::vector<uint8_t>& black, int width,
                              int height, cv::Point2d around, int radius) {
  double sum = 0, su = 0, sv = 0;
  for (int v = std::max(0, static_cast<int>(around.y) - radius); v <= std::min(height - 1, static_cast<int>(around.y) + radius); ++v)
    for (int u = std::max(0, static_cast<int>(around.x) - radius); u <= std::min(width - 1, static_cast<int>(around.x) + radius); ++u) {
      const size_t i = static_cast<size_t>(v) * width + u;
      const double w = (static_cast<double>(white[i]) - black[i]) / 255.0;
      if (w <= 0) continue;
      sum += w;
      su += w * u;
      sv += w * v;
    }
  return sum > 0 ? cv::Point2d(su / sum, sv / sum) : cv::Point2d(-1, -1);
}

class MarkerProjection : public ::testing::TestWithParam<ProjectionCase> {};

TEST_P(MarkerProjection, MarkersLandWhereProjectPointsSays) {
  const ProjectionCase c = GetParam();
  SimCamera camera = default_camera();
  camera.body_from_camera = rotation_zyx(c.mount_roll_deg * M_PI / 180, c.mount_pitch_deg * M_PI / 180,
                                         c.mount_yaw_deg * M_PI / 180);
  TerrainOptions terrain_options;
  terrain_options.seed = 11;
  const Terrain terrain(terrain_options);
  RendererOptions options;
  options.pixel_noise_dn = 0.0;
  Renderer renderer(camera, terrain, options);

  const Eigen::Vector3d origin(420.0, -310.0, -c.altitude_m);
  const Eigen::Matrix3d world_from_body =
      rotation_zyx(c.roll_deg * M_PI / 180, c.pitch_deg * M_PI / 180, c.yaw_deg * M_PI / 180);
  const Eigen::Matrix3d world_from_camera = world_from_body * camera.body_from_camera;

  // Ground points near chosen pixels (centre, edges, corners): the pixel's
  // OpenCV-undistorted ray meets a level plane at the terrain height below;
  // the marker then sits on the terrain at that (north, east), and its
  // expected pixel comes from cv::projectPoints, whatever the guess error.
  const std::vector<cv::Point2d> targets = {{306, 256}, {40, 40}, {570, 40}, {40, 470}, {575, 475},
                                            {306, 30},  {306, 490}, {30, 256}, {585, 256}, {150, 350}};
  std::vector<cv::Point2d> normalized;
  cv::undistortPoints(targets, normalized, camera.camera_matrix(), camera.distortion_coefficients());
  const double ground = terrain.height(origin.x(), origin.y());
  std::vector<GroundMarker> markers;
  std::vector<cv::Point3d> points_camera;
  for (const cv::Point2d& n : normalized) {
    const Eigen::Vector3d ray = world_from_camera * Eigen::Vector3d(n.x, n.y, 1.0);
    const double t = (-ground - origin.z()) / ray.z();
    const Eigen::Vector3d guess = origin + t * ray;
    GroundMarker m;
    m.north = guess.x();
    m.east = guess.y();
    m.radius_m = 2.0;
    markers.push_back(m);
    const Eigen::Vector3d p(m.north, m.east, -terrain.height(m.north, m.east));
    const Eigen::Vector3d pc = world_from_camera.transpose() * (p - origin);
    points_camera.emplace_back(pc.x(), pc.y(), pc.z());
  }
  std::vector<cv::Point2d> expected;
  cv::projectPoints(points_camera, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), camera.camera_matrix(),
                    camera.distortion_coefficients(), expected);

  std::vector<uint8_t> white, black;
  for (GroundMarker& m : markers) m.value = 255.0f;
  renderer.set_markers(markers);
  renderer.render(origin, world_from_camera, 1, &white);
  for (GroundMarker& m : markers) m.value = 0.0f;
  renderer.set_markers(markers);
  renderer.render(origin, world_from_camera, 1, &black);

  double worst = 0;
  for (size_t i = 0; i < markers.size(); ++i) {
    ASSERT_GT(expected[i].x, 8);
    ASSERT_LT(expected[i].x, camera.width - 9);
    ASSERT_GT(expected[i].y, 8);
    ASSERT_LT(expected[i].y, camera.height - 9);
    const cv::Point2d seen = coverage_centroid(white, black, camera.width, camera.height, expected[i], 10);
    const double error = std::hypot(seen.x - expected[i].x, seen.y - expected[i].y);
    EXPECT_LT(error, 0.5) << "marker " << i << " expected at " << expected[i] << " seen at " << seen;
    worst = std::max(worst, error);
  }
  RecordProperty("worst_marker_error_px", std::to_string(worst));
  std::printf("worst marker error: %.4f px\n", worst);
}

INSTANTIATE_TEST_SUITE_P(Poses, MarkerProjection,
                         ::testing::Values(ProjectionCase{0, 0, 0, 0, 0, 0, 250},
                                           ProjectionCase{4, -3, 30, 0, 0, 0, 250},
                                           ProjectionCase{-12, 5, -140, 2, -3, 5, 160},
                                           ProjectionCase{8, 2, 95, -1.5, 4, -90, 300}));

TEST(Distortion, RayTableRoundTripsThroughProjectPoints) {
  const SimCamera camera = default_camera();
  TerrainOptions terrain_options;
  const Terrain terrain(terrain_options);
  Renderer renderer(camera, terrain, RendererOptions{});
  std::vector<cv::Point3d> rays;
  std::vector<cv::Point2d> pixels;
  for (int v = 0; v < camera.height; v += 17)
    for (int u = 0; u < camera.width; u += 19) pixels.emplace_back(u, v);
  pixels.emplace_back(0, 0);
  pixels.emplace_back(camera.width - 1, camera.height - 1);
  pixels.emplace_back(camera.width - 1, 0);
  pixels.emplace_back(0, camera.height - 1);
  for (const cv::Point2d& p : pixels) {
    const Eigen::Vector3d r = renderer.pixel_ray(static_cast<int>(p.x), static_cast<int>(p.y));
    rays.emplace_back(r.x(), r.y(), r.z());
  }
  const std::vector<cv::Point2d> back = camera.project(rays);
  double worst = 0;
  for (size_t i = 0; i < pixels.size(); ++i) worst = std::max(worst, std::hypot(back[i].x - pixels[i].x, back[i].y - pixels[i].y));
  // The table is stored as floats: ~1e-7 rad, i.e. < 1e-3 px.
  EXPECT_LT(worst, 2e-3);
  // And the lens really is distorted there: the corner ray differs from the pinhole one.
  const Eigen::Vector3d corner = renderer.pixel_ray(0, 0);
  const double pinhole_x = (0 - camera.cx) / camera.fx;
  EXPECT_GT(std::fabs(corner.x() / corner.z() - pinhole_x), 0.02);
}

TEST(Altimeter, RangeIsTheRayCastDistanceAlongTheOpticalAxis) {
  SimulatorOptions options;
  options.seed = 4;
  options.render_images = false;
  SimCamera camera = default_camera();
  camera.body_from_camera = rotation_zyx(0.03, -0.05, 0.0);  // a tilted mount: beam leaves the body z axis
  const Simulator sim(testing::profile("test2"), camera, testing::sensor_set("standard"), options);
  for (double t = 0.0; t < sim.duration_s(); t += 7.3) {
    double range = 0;
    ASSERT_TRUE(sim.altimeter_truth_range(t, &range));
    const TruthState s = sim.trajectory().at(t);
    const Eigen::Vector3d beam =
        rotation_zyx(s.roll, s.pitch, s.yaw) * camera.body_from_camera * Eigen::Vector3d::UnitZ();
    const Eigen::Vector3d hit = s.position_ned + range * beam;
    EXPECT_NEAR(-hit.z(), sim.terrain().height(hit.x(), hit.y()), 1e-3) << "t = " << t;
    // The interpolated surface stays within centimetres of the analytic field.
    EXPECT_NEAR(-hit.z(), sim.terrain().exact_height(hit.x(), hit.y()), 0.02);
    // No earlier hit: every point before it is above the ground.
    for (int k = 1; k < 10; ++k) {
      const Eigen::Vector3d p = s.position_ned + 0.1 * k * range * beam;
      EXPECT_GT(-p.z(), sim.terrain().height(p.x(), p.y()));
    }
  }
}

TEST(Terrain, HasReliefAndTexturesWithoutLargeScaleRepetition) {
  TerrainOptions options;
  options.seed = 9;
  const Terrain terrain(options);
  EXPECT_DOUBLE_EQ(terrain.height(0, 0), 0.0);
  double max_slope_deg = 0, lo = 1e9, hi = -1e9;
  for (double n = -3000; n <= 3000; n += 7.0)
    for (double e = -3000; e <= 3000; e += 53.0) {
      double gn, ge;
      const double h = terrain.height(n, e, &gn, &ge);
      lo = std::min(lo, h);
      hi = std::max(hi, h);
      max_slope_deg = std::max(max_slope_deg, std::atan(std::hypot(gn, ge)) * 180 / M_PI);
      ASSERT_LE(std::hypot(gn, ge), terrain.max_slope());
    }
  EXPECT_GT(hi - lo, 20.0);        // hills
  EXPECT_GT(max_slope_deg, 8.0);   // sharper features
  EXPECT_LT(max_slope_deg, 25.0);  // but helicopter country, ~15 degrees
  // Albedo 1 km apart is uncorrelated: no tiling at any scale we fly.
  double sab = 0, saa = 0, sbb = 0, sa = 0, sb = 0;
  int n = 0;
  for (double x = 0; x < 500; x += 1.7)
    for (double y = 0; y < 100; y += 3.1) {
      const double a = terrain.albedo(x, y), b = terrain.albedo(x + 1024.0, y + 2048.0);
      sa += a;
      sb += b;
      sab += a * b;
      saa += a * a;
      sbb += b * b;
      ++n;
    }
  const double cov = sab / n - sa / n * sb / n;
  const double corr = cov / std::sqrt((saa / n - sa * sa / n / n) * (sbb / n - sb * sb / n / n));
  EXPECT_LT(std::fabs(corr), 0.3);
}

// Featureless areas: the albedo keeps `contrast` of its deviation from the
// area's level inside the box, blends back across the shore band, and is
// the ground's own, bit for bit, everywhere else; heights never change.
TEST(Terrain, FeaturelessAreaWeakensTheTextureAndNothingElse) {
  TerrainOptions plain_options;
  plain_options.seed = 9;
  TerrainOptions options = plain_options;
  FeaturelessArea area;
  area.north_min_m = 1000.0;
  area.north_max_m = 1600.0;
  area.east_min_m = -300.0;
  area.east_max_m = 900.0;
  area.contrast = 0.08;
  area.shore_m = 100.0;
  options.featureless.push_back(area);
  const Terrain plain(plain_options), with_area(options);

  // Outside the box and its shore band: identical albedo; heights identical everywhere.
  for (double n = 0.0; n <= 2800.0; n += 3.7)
    for (double e = -1500.0; e <= 2100.0; e += 41.3) {
      ASSERT_EQ(with_area.exact_height(n, e), plain.exact_height(n, e)) << n << ", " << e;
      if (n > 1000.0 - 100.0 && n < 1600.0 + 100.0 && e > -300.0 - 100.0 && e < 900.0 + 100.0) continue;
      ASSERT_EQ(with_area.albedo(n, e), plain.albedo(n, e)) << n << ", " << e;
    }

  // Inside: the standard deviation over a patch is `contrast` times the plain one's.
  auto stats = [](const Terrain& t, double n0, double e0, double* mean, double* sd) {
    double s = 0.0, ss = 0.0;
    int k = 0;
    for (double n = n0; n < n0 + 200.0; n += 0.7)
      for (double e = e0; e < e0 + 200.0; e += 0.7) {
        const double a = t.albedo(n, e);
        s += a;
        ss += a * a;
        ++k;
      }
    *mean = s / k;
    *sd = std::sqrt(std::max(0.0, ss / k - *mean * *mean));
  };
  double plain_mean, plain_sd, mean, sd;
  stats(plain, 1150.0, 100.0, &plain_mean, &plain_sd);
  stats(with_area, 1150.0, 100.0, &mean, &sd);
  EXPECT_GT(plain_sd, 20.0);  // the plain ground is textured there
  EXPECT_NEAR(sd, area.contrast * plain_sd, 0.01 * area.contrast * plain_sd);
  EXPECT_NEAR(mean, area.albedo + area.contrast * (plain_mean - area.albedo), 0.01);

  // The shore band: contrast rises from `contrast` at the box to 1 at shore_m, monotonically.
  double previous = area.contrast;
  EXPECT_DOUBLE_EQ(FeaturelessGround::contrast_at(area, 1600.0, 0.0), area.contrast);
  for (double d = 5.0; d <= 100.0; d += 5.0) {
    const double k = FeaturelessGround::contrast_at(area, 1600.0 + d, 0.0);
    EXPECT_GE(k, previous) << d;
    EXPECT_LE(k, 1.0) << d;
    previous = k;
  }
  EXPECT_DOUBLE_EQ(previous, 1.0);
  EXPECT_GT(FeaturelessGround::contrast_at(area, 1650.0, 0.0), 0.3);
  EXPECT_LT(FeaturelessGround::contrast_at(area, 1650.0, 0.0), 0.8);

  // No areas, or an area elsewhere: the terrain is the plain one here.
  TerrainOptions far_options = plain_options;
  area.north_min_m = -90000.0;
  area.north_max_m = -80000.0;
  far_options.featureless.push_back(area);
  const Terrain far(far_options);
  for (double n = 1000.0; n < 1600.0; n += 13.1)
    for (double e = -300.0; e < 900.0; e += 7.9) ASSERT_EQ(far.albedo(n, e), plain.albedo(n, e));
}

void expect_featureless_error(const std::string& area, const std::string& key) {
  const std::string yaml = "name: x\ndistance_m: 3000\nspeed_mps: 20\naltitude_agl_m: 150\n"
                           "terrain:\n  featureless:\n    - {north_m: [0, 100], east_m: [0, 100], contrast: 0.1}\n"
                           "    - " + area + "\nlegs:\n  - {type: straight}\n";
  try {
    FlightProfile::parse(yaml, "bad_profile.yaml");
    FAIL() << "accepted " << area;
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("bad_profile.yaml"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("'" + key + "'"), std::string::npos) << e.what();
  }
}

TEST(Terrain, FeaturelessAreaKeysAreCheckedAndNamed) {
  const std::string yaml = "name: x\ndistance_m: 3000\nspeed_mps: 20\naltitude_agl_m: 150\n"
                           "terrain: {relief_scale: 1.0, featureless: [{north_m: [-50, 250.5], east_m: [10, 20], "
                           "contrast: 0.05}, {north_m: [0, 1], east_m: [0, 1], contrast: 0, shore_m: 0, albedo: 60}]}\n"
                           "legs:\n  - {type: straight}\n";
  const FlightProfile p = FlightProfile::parse(yaml, "good.yaml");
  ASSERT_EQ(p.terrain.featureless.size(), 2u);
  EXPECT_EQ(p.terrain.featureless[0].north_min_m, -50.0);
  EXPECT_EQ(p.terrain.featureless[0].north_max_m, 250.5);
  EXPECT_EQ(p.terrain.featureless[0].east_min_m, 10.0);
  EXPECT_EQ(p.terrain.featureless[0].east_max_m, 20.0);
  EXPECT_EQ(p.terrain.featureless[0].contrast, 0.05);
  EXPECT_EQ(p.terrain.featureless[0].shore_m, 100.0);  // default
  EXPECT_EQ(p.terrain.featureless[1].shore_m, 0.0);
  EXPECT_EQ(p.terrain.featureless[1].albedo, 60.0);
  // The list survives a relief override's rewrite of the YAML.
  FlightProfile q = p;
  q.override_relief_scale(0.5);
  EXPECT_EQ(FlightProfile::parse(q.yaml, "override").terrain.featureless.size(), 2u);

  const std::string k = "terrain.featureless[1]";
  expect_featureless_error("{north_m: [0, 100], east_m: [0, 100], contrast: 1.5}", k + ".contrast");
  expect_featureless_error("{north_m: [0, 100], east_m: [0, 100], contrast: -0.1}", k + ".contrast");
  expect_featureless_error("{north_m: [0, 100], east_m: [0, 100]}", k + ".contrast");
  expect_featureless_error("{north_m: [100, 0], east_m: [0, 100], contrast: 0.1}", k + ".north_m");
  expect_featureless_error("{north_m: [0, 100, 200], east_m: [0, 100], contrast: 0.1}", k + ".north_m");
  expect_featureless_error("{north_m: [0, 100], east_m: [5, 5], contrast: 0.1}", k + ".east_m");
  expect_featureless_error("{north_m: [0, 100], contrast: 0.1}", k + ".east_m");
  expect_featureless_error("{north_m: [0, 100], east_m: [0, 100], contrast: 0.1, shore_m: -1}", k + ".shore_m");
  expect_featureless_error("{north_m: [0, 100], east_m: [0, 100], contrast: 0.1, albedo: 300}", k + ".albedo");
  expect_featureless_error("{north_m: [0, 100], east_m: [0, 100], contrst: 0.1}", k + ".contrst");

  // The same rules for options built in code.
  TerrainOptions options;
  options.featureless.resize(1);
  options.featureless[0].north_max_m = options.featureless[0].east_max_m = 10.0;
  options.featureless[0].contrast = 2.0;
  try {
    const Terrain terrain(options);
    FAIL() << "contrast 2 accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("terrain.featureless[0].contrast"), std::string::npos) << e.what();
  }
}

// featureless_crossing: the camera footprint of the middle 20 km of the track
// is inside the area's box, and the rest of the flight sees no part of the
// area or its shore; the aircraft keeps its height above the ground.
TEST(FeaturelessCrossing, MiddleTwentyKilometresSeeOnlyTheArea) {
  const FlightProfile p = testing::profile("featureless_crossing");
  ASSERT_EQ(p.terrain.featureless.size(), 1u);
  const FeaturelessArea& area = p.terrain.featureless[0];
  const double half_fov = 37.5 * M_PI / 180.0;  // 75 degree HFOV; the vertical one is narrower
  for (uint64_t seed : {1, 2, 3}) {
    const Trajectory traj(p, seed);
    TerrainOptions terrain_options = p.terrain;
    terrain_options.seed = seed;
    const Terrain terrain(terrain_options);
    EXPECT_NEAR(traj.duration_s() * p.speed_mps, 40000.0, 1.0);
    for (double t = 0.0; t <= traj.duration_s(); t += 0.5) {
      const TruthState s = traj.at(t);
      const double along = t * p.speed_mps;
      const double n = s.position_ned.x(), e = s.position_ned.y();
      const double agl = -s.position_ned.z() - terrain.height(n, e);
      ASSERT_GT(agl, 250.0) << "seed " << seed << " t " << t;
      // Half the footprint's diagonal, with room for the attitude oscillations and the pitch trim.
      const double half = agl * std::tan(half_fov + 5.0 * M_PI / 180.0);
      if (along >= 10000.0 && along <= 30000.0) {
        ASSERT_GT(n - half, area.north_min_m) << "t " << t;
        ASSERT_LT(n + half, area.north_max_m) << "t " << t;
        ASSERT_GT(e - half, area.east_min_m) << "t " << t;
        ASSERT_LT(e + half, area.east_max_m) << "t " << t;
      } else if (along < 9000.0 || along > 31000.0) {
        const double dn = std::max({area.north_min_m - n, 0.0, n - area.north_max_m});
        const double de = std::max({area.east_min_m - e, 0.0, e - area.east_max_m});
        ASSERT_GT(std::hypot(dn, de), area.shore_m + half) << "t " << t;
      }
    }
  }
}

// long_100km: 100 km at 300 m, relief and climbs really there, and at least
// 200 m above the ground with seeds 1-3.
TEST(LongProfile, HundredKilometresClearOfTheGround) {
  const FlightProfile p = testing::profile("long_100km");
  EXPECT_EQ(p.distance_m, 100000.0);
  EXPECT_EQ(p.altitude_agl_m, 300.0);
  EXPECT_GE(p.terrain.relief_scale, 1.5);
  EXPECT_TRUE(p.terrain.featureless.empty());
  int turns = 0, climbs = 0;
  for (const FlightLeg& leg : p.legs) {
    turns += leg.type == FlightLeg::kTurn;
    climbs += leg.type == FlightLeg::kClimb;
  }
  EXPECT_GE(turns, 3);
  EXPECT_GE(climbs, 3);
  for (uint64_t seed : {1, 2, 3}) {
    const Trajectory traj(p, seed);
    EXPECT_NEAR(traj.duration_s() * p.speed_mps, 100000.0, 1.0);
    TerrainOptions terrain_options = p.terrain;
    terrain_options.seed = seed;
    const Terrain terrain(terrain_options);
    double min_agl = 1e9, max_agl = -1e9;
    for (double t = 0.0; t <= traj.duration_s(); t += 0.2) {
      const TruthState s = traj.at(t);
      const double agl = -s.position_ned.z() - terrain.height(s.position_ned.x(), s.position_ned.y());
      min_agl = std::min(min_agl, agl);
      max_agl = std::max(max_agl, agl);
    }
    EXPECT_GE(min_agl, 200.0) << "seed " << seed;
    EXPECT_GT(max_agl - min_agl, 80.0) << "seed " << seed;
    std::printf("long_100km seed %d: %.1f to %.1f m above the ground\n", static_cast<int>(seed), min_agl, max_agl);
  }
}

}  // namespace
}  // namespace nadir::sim
