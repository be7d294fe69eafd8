// The map matcher against a simulated world and its simulated map (another
// season, coarser, changed patches): a frame rendered by the simulator's
// renderer at a known pose, a prior off by metres -> the fix lands on the
// truth within its covariance; maps and frames it must not trust are refused.
#include <gtest/gtest.h>

#include <Eigen/LU>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <memory>
#include <string>

#include "common/camera_model.h"
#include "common/config.h"
#include "common/geometry.h"
#include "common/paths.h"
#include "common/channels.h"
#include "common/lcm_bus.h"
#include "nadir/ins_t.hpp"
#include "processes/map_matcher/map_matcher.h"
#include "processes/map_matcher/map_matcher_node.h"
#include "processes/sim/sim_camera.h"
#include "processes/sim/terrain.h"
#include "tests/common/test_support.h"
#include "tests/processes/map_matcher/matcher_scene.h"
#include "tools/map/geotiff_writer.h"
#include "tools/map/simulated_map.h"

namespace nadir {
namespace {

constexpr uint64_t kSeed = 7;
constexpr double kHeight = 200.0;

const char* kProfile = R"(
name: matcher_test
distance_m: 600
speed_mps: 20
altitude_agl_m: 200
initial_heading_deg: 30
reference: {latitude_deg: 40.4406, longitude_deg: -79.9959, height_m: 300.0}
terrain: {relief_scale: 1.0}
legs:
  - {type: straight}
)";

struct World {
  sim::FlightProfile profile = sim::FlightProfile::parse(kProfile, "matcher_test");
  std::unique_ptr<sim::Terrain> terrain;
  Config config = Config::load_file(std::string(NADIR_SOURCE_DIR) + "/config/default.yaml");
};

class MapMatcherTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    world_ = new World;
    sim::TerrainOptions t = world_->profile.terrain;
    t.seed = kSeed;
    world_->terrain = std::make_unique<sim::Terrain>(t);
    dir_ = new testing::TempDir("map_matcher");
    test::write_simulated_map(dir_->path(), world_->profile, kSeed, 250.0);
    other_dir_ = new testing::TempDir("map_matcher_other");
    test::write_simulated_map(other_dir_->path(), world_->profile, kSeed + 1, 250.0);  // the same flight over another world
  }
  static void TearDownTestSuite() {
    delete dir_;
    delete other_dir_;
    delete world_;
  }

  static MapMatcher matcher(const std::string& dir, MapMatcherOptions options = {}) {
    return MapMatcher(options, CameraModel::from_config(world_->config),
                      map::ReferenceMap::open(dir + "/orthophoto.tif", dir + "/dem.tif"));
  }
  static map::LocalProjection origin() {
    GeodeticPoint p;
    p.latitude_deg = world_->profile.reference_latitude_deg;
    p.longitude_deg = world_->profile.reference_longitude_deg;
    return map::LocalProjection(p);
  }

  // The frame the simulator's camera takes at (north, east), kHeight above
  // the ground there, with this attitude; and the POSE of it with the
  // horizontal position off by (dn, de) and a prior sigma.
  static image_t render(double north, double east, const Eigen::Vector3d& rpy_deg) {
    return test::rendered_frame(sim::SimCamera::from_config(world_->config), *world_->terrain, north, east, kHeight,
                                rpy_deg * M_PI / 180.0, 11, 1'000'000);
  }
  static pose_t pose(double north, double east, const Eigen::Vector3d& rpy_deg, double dn, double de, double sigma) {
    return test::prior_pose(north + dn, east + de, rpy_deg * M_PI / 180.0, kHeight, sigma, 1'000'000);
  }

  static World* world_;
  static testing::TempDir* dir_;
  static testing::TempDir* other_dir_;
};
World* MapMatcherTest::world_ = nullptr;
testing::TempDir* MapMatcherTest::dir_ = nullptr;
testing::TempDir* MapMatcherTest::other_dir_ = nullptr;

TEST_F(MapMatcherTest, FixLandsOnTheTruthWithinItsCovariance) {
  const MapMatcher m = matcher(dir_->path());
  const struct {
    double north, east, dn, de;
    Eigen::Vector3d rpy;
  } cases[] = {
      {150.0, 80.0, 6.0, -4.0, {1.0, -2.0, 30.0}},
      {300.0, 200.0, -9.0, 3.0, {-2.0, 1.5, 210.0}},
      {420.0, 260.0, 2.0, 8.0, {0.5, 0.5, 95.0}},
  };
  for (const auto& c : cases) {
    const FixAttempt a = m.attempt(render(c.north, c.east, c.rpy), pose(c.north, c.east, c.rpy, c.dn, c.de, 5.0),
                                   origin());
    ASSERT_EQ(a.refusal, FixRefusal::kNone) << a.why;
    const Eigen::Vector2d error(a.fix.position_ne[0] - c.north, a.fix.position_ne[1] - c.east);
    Eigen::Matrix2d cov;
    cov << a.fix.covariance_ne[0][0], a.fix.covariance_ne[0][1], a.fix.covariance_ne[1][0], a.fix.covariance_ne[1][1];
    EXPECT_LT(error.norm(), 1.5) << "at " << c.north << ", " << c.east;
    EXPECT_LT(std::sqrt(error.dot(cov.inverse() * error)), 3.0) << "error " << error.transpose();
    EXPECT_GT(a.fix.score, 0.35);
    EXPECT_NEAR(a.fix.search_radius_m, 25.0, 1e-9);  // 5 sigma
  }
}

// The attitude term of a fix's covariance is the INS's roll/pitch sigma as
// vo_solver.uncertainty describes it when that is above
// map_matcher.attitude_stddev_deg: a noisy INS described once is not
// forgotten by the matcher (its fixes were 2-5x their sigma otherwise).
TEST_F(MapMatcherTest, FixCarriesTheAttitudeErrorTheConfigGivesTheIns) {
  auto options_with = [](const std::string& override_text) {
    Config config = Config::load_file(std::string(NADIR_SOURCE_DIR) + "/config/default.yaml");
    if (!override_text.empty()) config.apply_override(override_text);
    return MapMatcherOptions::from_config(config);
  };
  const MapMatcherOptions standard = options_with("");
  const MapMatcherOptions noisy = options_with("vo_solver.uncertainty.roll_pitch_stddev_deg=0.3");
  const MapMatcherOptions correlated = options_with("vo_solver.uncertainty.roll_pitch_correlated_stddev_deg=0.4");
  EXPECT_NEAR(standard.ins_attitude_stddev_deg, 0.05, 1e-12);  // the standard INS: the matcher's own 0.05 deg
  EXPECT_NEAR(noisy.ins_attitude_stddev_deg, 0.3, 1e-12);
  EXPECT_NEAR(correlated.ins_attitude_stddev_deg, std::hypot(0.05, 0.4), 1e-12);
  const Eigen::Vector3d rpy(1.0, -2.0, 30.0);
  const image_t frame = render(150.0, 80.0, rpy);
  const pose_t prior = pose(150.0, 80.0, rpy, 6.0, -4.0, 5.0);
  const FixAttempt a = matcher(dir_->path(), standard).attempt(frame, prior, origin());
  const FixAttempt b = matcher(dir_->path(), noisy).attempt(frame, prior, origin());
  ASSERT_EQ(a.refusal, FixRefusal::kNone) << a.why;
  ASSERT_EQ(b.refusal, FixRefusal::kNone) << b.why;
  // The same match, the covariance larger by the attitude term's difference on each axis.
  EXPECT_EQ(a.fix.position_ne[0], b.fix.position_ne[0]);
  EXPECT_EQ(a.fix.position_ne[1], b.fix.position_ne[1]);
  const double added = std::pow(prior.height_agl_m * 0.3 * M_PI / 180.0, 2) -
                       std::pow(prior.height_agl_m * 0.05 * M_PI / 180.0, 2);
  EXPECT_NEAR(b.fix.covariance_ne[0][0] - a.fix.covariance_ne[0][0], added, 1e-9);
  EXPECT_NEAR(b.fix.covariance_ne[1][1] - a.fix.covariance_ne[1][1], added, 1e-9);
  EXPECT_NEAR(b.fix.covariance_ne[0][1], a.fix.covariance_ne[0][1], 1e-12);
}

// The fix is of the INS reference point the pose is of, not of the camera
// 1.5 m ahead of it (camera.lever_arm_m), and it carries the DEM's ground
// under it on POSE's down axis with the slope there.
TEST_F(MapMatcherTest, FixIsOfThePosesPointWithTheGroundUnderIt) {
  const Eigen::Vector3d lever_body(1.5, 0.4, 0.3);
  const MapMatcher with_lever(MapMatcherOptions{}, CameraModel::from_config(world_->config),
                              map::ReferenceMap::open(dir_->path() + "/orthophoto.tif", dir_->path() + "/dem.tif"),
                              lever_body);
  const MapMatcher without_lever = matcher(dir_->path());
  // POSE's down 0 lies 200 m above the datum (the profile's reference height 300 m).
  GeodeticPoint at_origin;
  at_origin.latitude_deg = world_->profile.reference_latitude_deg;
  at_origin.longitude_deg = world_->profile.reference_longitude_deg;
  at_origin.height_m = world_->profile.reference_height_m + 200.0;
  const map::LocalProjection origin_200(at_origin);
  const struct {
    double north, east;
    Eigen::Vector3d rpy;
  } cases[] = {{150.0, 80.0, {1.0, -2.0, 30.0}}, {300.0, 200.0, {-2.0, 1.5, 210.0}}, {420.0, 260.0, {0.5, 0.5, 95.0}}};
  for (const auto& c : cases) {
    const Eigen::Vector3d rpy = c.rpy * M_PI / 180.0;
    const Eigen::Vector3d lever = rotation_from_rpy(rpy.x(), rpy.y(), rpy.z()) * lever_body;
    const image_t frame = test::rendered_frame(sim::SimCamera::from_config(world_->config), *world_->terrain,
                                               c.north + lever.x(), c.east + lever.y(), kHeight - lever.z(), rpy, 11,
                                               1'000'000);
    const pose_t prior = pose(c.north, c.east, c.rpy, 3.0, -2.0, 3.0);
    const FixAttempt a = with_lever.attempt(frame, prior, origin_200);
    ASSERT_EQ(a.refusal, FixRefusal::kNone) << a.why;
    const Eigen::Vector2d error(a.fix.position_ne[0] - c.north, a.fix.position_ne[1] - c.east);
    EXPECT_LT(error.norm(), 0.6) << "at " << c.north << ", " << c.east;
    const FixAttempt b = without_lever.attempt(frame, prior, origin_200);
    ASSERT_EQ(b.refusal, FixRefusal::kNone) << b.why;
    const Eigen::Vector2d camera_error(b.fix.position_ne[0] - c.north, b.fix.position_ne[1] - c.east);
    EXPECT_GT((camera_error - error).norm(), 1.2) << "the lever arm moves the fix by " << lever.head<2>().norm();

    // The ground: the simulated DEM is the terrain at 1 m, read at the fix.
    double up_north = 0.0, up_east = 0.0;
    const double ground =
        world_->terrain->height(a.fix.position_ne[0], a.fix.position_ne[1], &up_north, &up_east);
    EXPECT_NEAR(a.fix.ground_down_m, 200.0 - ground, 0.05);
    EXPECT_NEAR(a.fix.ground_gradient_ne[0], -up_north, 0.02);
    EXPECT_NEAR(a.fix.ground_gradient_ne[1], -up_east, 0.02);
    EXPECT_DOUBLE_EQ(a.fix.ground_down_variance, 0.25);  // dem_stddev_m 0.5
  }
}

TEST_F(MapMatcherTest, MapOfAnotherWorldIsRefused) {
  const MapMatcher m = matcher(other_dir_->path());
  const Eigen::Vector3d rpy(1.0, -2.0, 30.0);
  for (const double north : {120.0, 250.0, 380.0}) {
    const FixAttempt a = m.attempt(render(north, 100.0, rpy), pose(north, 100.0, rpy, 0.0, 0.0, 5.0), origin());
    EXPECT_NE(a.refusal, FixRefusal::kNone) << "score " << a.fix.score << " ratio " << a.fix.peak_ratio;
  }
}

TEST_F(MapMatcherTest, RefusesWhatItCannotTrust) {
  const MapMatcher m = matcher(dir_->path());
  const Eigen::Vector3d rpy(1.0, -2.0, 30.0);
  const image_t frame = render(200.0, 100.0, rpy);
  // A prior too uncertain for the search.
  EXPECT_EQ(m.attempt(frame, pose(200.0, 100.0, rpy, 0, 0, 100.0), origin()).refusal, FixRefusal::kPriorUncertain);
  // Beyond the map.
  EXPECT_EQ(m.attempt(frame, pose(200.0, 100.0, rpy, 5000.0, 0, 5.0), origin()).refusal, FixRefusal::kOutsideMap);
  // No height.
  pose_t no_height = pose(200.0, 100.0, rpy, 0, 0, 5.0);
  no_height.height_agl_m = -1.0;
  EXPECT_EQ(m.attempt(frame, no_height, origin()).refusal, FixRefusal::kNoHeight);
  // Tilted far from nadir.
  const Eigen::Vector3d banked(35.0, 0.0, 30.0);
  EXPECT_EQ(m.attempt(frame, pose(200.0, 100.0, banked, 0, 0, 5.0), origin()).refusal, FixRefusal::kTilted);
  // A featureless frame (fog, a lens cap).
  image_t grey = frame;
  std::fill(grey.data.begin(), grey.data.end(), uint8_t{90});
  const FixAttempt a = m.attempt(grey, pose(200.0, 100.0, rpy, 0, 0, 5.0), origin());
  EXPECT_EQ(a.refusal, FixRefusal::kFeatureless);
  EXPECT_NE(a.why.find("min_texture"), std::string::npos) << a.why;  // Only smooth shading, as of relief under snow: grey levels spread over
  // 40 levels but hardly an edge.
  image_t smooth = frame;
  for (int v = 0; v < smooth.height; ++v)
    for (int u = 0; u < smooth.width; ++u)
      smooth.data[static_cast<size_t>(v) * smooth.stride + u] =
          static_cast<uint8_t>(std::lround(128 + 20 * std::sin(2 * M_PI * (u + 0.3 * v) / 900.0)));
  const FixAttempt s = m.attempt(smooth, pose(200.0, 100.0, rpy, 0, 0, 5.0), origin());
  EXPECT_EQ(s.refusal, FixRefusal::kFeatureless) << s.why;
  EXPECT_NE(s.why.find("min_edge_strength"), std::string::npos) << s.why;
  EXPECT_LT(s.frame_edge_strength, m.options().min_edge_strength);
  EXPECT_GT(s.map_edge_strength, m.options().min_edge_strength);
}

TEST_F(MapMatcherTest, MapHolesAreRefusedNeverMatched) {
  // The map with a NaN hole in the DEM under the frame and NoData in the orthophoto.
  testing::TempDir holes("map_matcher_holes");
  map::SimulatedMapOptions options;
  options.margin_m = 250.0;
  map::SimulatedMap m = map::simulate_map(world_->profile, kSeed, options);
  const Eigen::Vector2d at = map::LocalProjection({world_->profile.reference_latitude_deg,
                                                   world_->profile.reference_longitude_deg, 0.0})
                                 .utm(200.0, 100.0);
  const int row = static_cast<int>((m.grid.y0 - at.y()) / m.grid.gsd_m);
  const int col = static_cast<int>((at.x() - m.grid.x0) / m.grid.gsd_m);
  for (int r = row - 20; r < row + 20; ++r)
    for (int c = col - 20; c < col + 20; ++c) m.dem[static_cast<size_t>(r) * m.grid.width + c] = std::nanf("");
  map::write_geotiff_byte(holes.file("orthophoto.tif"), m.grid, m.orthophoto);
  map::write_geotiff_float(holes.file("dem.tif"), m.grid, m.dem, -9999.0);
  const MapMatcher matcher_with_holes(MapMatcherOptions{}, CameraModel::from_config(world_->config),
                                      map::ReferenceMap::open(holes.file("orthophoto.tif"), holes.file("dem.tif")));
  const Eigen::Vector3d rpy(0.5, 0.5, 60.0);
  const FixAttempt a = matcher_with_holes.attempt(render(200.0, 100.0, rpy), pose(200.0, 100.0, rpy, 2.0, 2.0, 3.0),
                                                  origin());
  EXPECT_EQ(a.refusal, FixRefusal::kMapNoData) << a.why;
}

// The process logic on a bus: INS places the local frame, a frame and its
// POSE give a MAP_FIX; a malformed POSE is counted, not used; a config
// without a map or with a file that is not a map is refused by name.
TEST_F(MapMatcherTest, NodePublishesFixesAndRefusesBadInput) {
  // (Config copies share their YAML tree: each gets its own load.)
  auto fresh = []() { return Config::load_file(std::string(NADIR_SOURCE_DIR) + "/config/default.yaml"); };
  Config config = fresh();
  config.apply_override("map_matcher.orthophoto=" + dir_->file("orthophoto.tif"));
  config.apply_override("map_matcher.dem=" + dir_->file("dem.tif"));
  LcmBusOptions bus_options;
  bus_options.url = "memq://";
  LcmBus bus(bus_options);
  auto pump = [&bus]() {
    while (bus.handle(0) > 0) {
    }
  };
  std::vector<map_fix_t> fixes;
  bus.subscribe<map_fix_t>(channels::kMapFix, [&](const map_fix_t& f) { fixes.push_back(f); });
  const std::unique_ptr<Node> node = make_map_matcher_node(config, bus);
  // A pose 300 ms before the INS starts: too early to be placed, passed over
  // (the next one, at the origin, becomes it) and counted in STATUS.
  pose_t too_early = pose(0.0, 0.0, Eigen::Vector3d(1.0, -1.0, 130.0), 0.0, 0.0, 0.0);
  too_early.utime = 100'000;
  bus.publish(channels::kPose, too_early);
  pump();
  // The INS around the first pose: the reference point (the local origin).
  for (int64_t t : {400'000, 1'400'000}) {
    ins_t ins{};
    ins.utime = t;
    ins.latitude_deg = world_->profile.reference_latitude_deg;
    ins.longitude_deg = world_->profile.reference_longitude_deg;
    ins.flags = ins_t::FLAG_ALIGNED | ins_t::FLAG_SOLUTION_GOOD;
    bus.publish(channels::kIns, ins);
    pump();
  }
  const Eigen::Vector3d rpy(1.0, -1.0, 130.0);
  pose_t first = pose(0.0, 0.0, rpy, 0.0, 0.0, 0.0);
  first.utime = 500'000;
  bus.publish(channels::kPose, first);
  pump();
  pose_t bad = pose(0.0, 0.0, rpy, 0.0, 0.0, 0.0);
  bad.utime = 600'000;
  bad.position_ned[0] = std::nan("");
  bus.publish(channels::kPose, bad);
  pump();
  bus.publish(channels::kCameraImage, render(250.0, 150.0, rpy));  // utime 1 s
  pump();
  bus.publish(channels::kPose, pose(250.0, 150.0, rpy, 4.0, -3.0, 4.0));
  pump();
  ASSERT_EQ(fixes.size(), 1u) << node->status().detail;
  EXPECT_NEAR(fixes[0].position_ne[0], 250.0, 1.5);
  EXPECT_NEAR(fixes[0].position_ne[1], 150.0, 1.5);
  const StatusReport status = node->status();
  EXPECT_EQ(status.published, 1);
  EXPECT_EQ(status.errors, 1);  // the NaN pose
  EXPECT_EQ(status.counter("origin_poses_passed_over"), 1.0);

  Config no_map = fresh();
  try {
    make_map_matcher_node(no_map, bus);
    ADD_FAILURE() << "a config without a map was taken";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("map_matcher.orthophoto"), std::string::npos) << e.what();
  }
  // A file that is not a georeferenced raster.
  testing::TempDir bare("map_matcher_bare");
  std::ofstream(bare.file("orthophoto.tif")) << "not a GeoTIFF";
  Config not_a_map = fresh();
  not_a_map.apply_override("map_matcher.orthophoto=" + bare.file("orthophoto.tif"));
  not_a_map.apply_override("map_matcher.dem=" + dir_->file("dem.tif"));
  try {
    make_map_matcher_node(not_a_map, bus);
    ADD_FAILURE() << "a file that is not a map was taken";
  } catch (const map::MapError& e) {
    EXPECT_NE(std::string(e.what()).find(bare.file("orthophoto.tif")), std::string::npos) << e.what();
  }
}

TEST_F(MapMatcherTest, OptionsChecked) {
  MapMatcherOptions o;
  o.min_search_radius_m = 50.0;
  o.max_search_radius_m = 20.0;
  EXPECT_THROW(matcher(dir_->path(), o), ConfigError);
}

}  // namespace
}  // namespace nadir
