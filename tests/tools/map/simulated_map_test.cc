// nadir_map simulate's map read back through the reader: georeferencing,
// heights against the simulator's Terrain, the orthophoto against the
// albedo, determinism.
#include <GeographicLib/UTMUPS.hpp>
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <memory>
#include <string>

#include "processes/sim/terrain.h"
#include "tests/common/test_support.h"
#include "tools/map/geotiff_writer.h"
#include "tools/map/map_record.h"
#include "tools/map/reference_map.h"
#include "tools/map/simulated_map.h"

namespace nadir::map {
namespace {

constexpr uint64_t kSeed = 3;

sim::FlightProfile test_profile() {
  sim::FlightProfile p = sim::FlightProfile::load(std::string(NADIR_SOURCE_DIR) + "/config/profiles/survey.yaml");
  p.override_relief_scale(1.0);  // the full relief: heights and hillshade matter
  return p;
}

SimulatedMapOptions test_options() {
  SimulatedMapOptions o;
  o.margin_m = 120.0;
  return o;
}

void write_map(const std::string& dir, const sim::FlightProfile& profile, uint64_t seed,
               const SimulatedMapOptions& options, SimulatedMap* out = nullptr) {
  const SimulatedMap map = simulate_map(profile, seed, options);
  write_geotiff_byte(dir + "/orthophoto.tif", map.grid, map.orthophoto);
  write_geotiff_float(dir + "/dem.tif", map.grid, map.dem, -9999.0);
  std::ofstream(dir + "/map.json", std::ios::binary) << map_record_json(profile, seed, options, map);
  if (out) *out = map;
}

class SimulatedMapTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new nadir::testing::TempDir("simulated_map");
    map_ = new SimulatedMap;
    write_map(dir_->path(), test_profile(), kSeed, test_options(), map_);
  }
  static void TearDownTestSuite() {
    delete map_;
    delete dir_;
  }
  static ReferenceMap open() { return ReferenceMap::open(dir_->file("orthophoto.tif"), dir_->file("dem.tif")); }
  static nadir::testing::TempDir* dir_;
  static SimulatedMap* map_;
};
nadir::testing::TempDir* SimulatedMapTest::dir_ = nullptr;
SimulatedMap* SimulatedMapTest::map_ = nullptr;

TEST_F(SimulatedMapTest, ReferencePointIsLocalOriginWithinHalfAPixel) {
  const sim::FlightProfile profile = test_profile();
  const ReferenceMap map = open();
  EXPECT_EQ(map.orthophoto_info().crs_name, "WGS 84 / UTM zone 17N");
  EXPECT_NEAR(map.orthophoto_info().pixel_size_m, 1.0, 0.01);  // UTM scale near the central meridian
  double col = 0, row = 0;
  // The reader goes through GDAL/PROJ; the writer placed pixels with GeographicLib.
  ASSERT_TRUE(map.orthophoto_pixel(profile.reference_latitude_deg, profile.reference_longitude_deg, &col, &row));
  const LocalProjection projection(
      {profile.reference_latitude_deg, profile.reference_longitude_deg, profile.reference_height_m});
  const Eigen::Vector2d utm = map_->grid.projected(col, row);
  const Eigen::Vector2d local = projection.local_from_utm(utm.x(), utm.y());
  EXPECT_LT(local.norm(), 0.5 * map_->grid.gsd_m) << local.transpose();
  // And the other way round: local (0, 0)'s UTM coordinates from the writer's
  // projection are those PROJ gives the reference point.
  const Eigen::Vector2d origin_utm = projection.utm(0.0, 0.0);
  EXPECT_NEAR(map_->grid.x0 + col * map_->grid.gsd_m, origin_utm.x(), 0.01);
  EXPECT_NEAR(map_->grid.y0 - row * map_->grid.gsd_m, origin_utm.y(), 0.01);
}

TEST_F(SimulatedMapTest, TrajectoryInsideCoverageAndDemMatchesTerrain) {
  const sim::FlightProfile profile = test_profile();
  const ReferenceMap map = open();
  EXPECT_FALSE(map.dem_crs_differs());
  EXPECT_EQ(map.dem_info().nodata_pixels, 0);
  const LocalProjection projection(
      {profile.reference_latitude_deg, profile.reference_longitude_deg, profile.reference_height_m});
  sim::TerrainOptions t = profile.terrain;
  t.seed = kSeed;
  const sim::Terrain terrain(t);
  double worst = 0.0, relief_lo = 1e9, relief_hi = -1e9;
  int points = 0;
  for (const Eigen::Vector2d& p : flight_track(profile, kSeed, 1.0)) {
    const GeodeticPoint g = projection.geodetic(p.x(), p.y());
    ASSERT_TRUE(map.covers(g.latitude_deg, g.longitude_deg)) << p.transpose();
    ASSERT_TRUE(map.dem_covers(g.latitude_deg, g.longitude_deg)) << p.transpose();
    const double truth = profile.reference_height_m + terrain.height(p.x(), p.y());
    worst = std::max(worst, std::fabs(map.height(g.latitude_deg, g.longitude_deg) - truth));
    relief_lo = std::min(relief_lo, truth);
    relief_hi = std::max(relief_hi, truth);
    ++points;
  }
  EXPECT_GT(points, 80);
  EXPECT_GT(relief_hi - relief_lo, 3.0);  // there is relief to get wrong
  // Bilinear on the map's 1 m grid of a surface that is bilinear on its own 1 m grid.
  EXPECT_LT(worst, 0.05);
}

// The footprint-averaged albedo of the world at pixel (col, row), without
// patches or season, against the map's pixel there.
TEST_F(SimulatedMapTest, OrthophotoCorrelatesWithAlbedoButIsNotIt) {
  const sim::FlightProfile profile = test_profile();
  const ReferenceMap map = open();
  const LocalProjection projection(
      {profile.reference_latitude_deg, profile.reference_longitude_deg, profile.reference_height_m});
  sim::TerrainOptions t = profile.terrain;
  t.seed = kSeed;
  const sim::Terrain terrain(t);
  const MapGrid& g = map_->grid;
  double n = 0, sx = 0, sy = 0, sxx = 0, syy = 0, sxy = 0, abs_diff = 0;
  for (int row = 5; row < g.height - 5; row += 7)
    for (int col = 5; col < g.width - 5; col += 7) {
      const Eigen::Vector2d utm = g.projected(col + 0.5, row + 0.5);
      double lat, lon;
      GeographicLib::UTMUPS::Reverse(projection.utm_zone(), true, utm.x(), utm.y(), lat, lon);
      const Eigen::Vector2d c = projection.local(lat, lon);
      double albedo = 0.0;
      for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) albedo += terrain.albedo(c.x() + (i - 1.5) * 0.25, c.y() + (j - 1.5) * 0.25);
      albedo /= 16.0;
      const double pixel = map.sample(lat, lon);
      n += 1;
      sx += albedo;
      sy += pixel;
      sxx += albedo * albedo;
      syy += pixel * pixel;
      sxy += albedo * pixel;
      abs_diff += std::fabs(pixel - albedo);
    }
  const double correlation = (n * sxy - sx * sy) / std::sqrt((n * sxx - sx * sx) * (n * syy - sy * sy));
  EXPECT_GT(correlation, 0.6);   // the same world ...
  EXPECT_LT(correlation, 0.97);  // ... seen in another season and light
  EXPECT_GT(abs_diff / n, 8.0);  // grey levels apart on average
  EXPECT_GT(map_->albedo_correlation, 0.6);
  EXPECT_LT(map_->albedo_correlation, 0.97);
}

// A window is north-up around its point: pixel (row, col) is the map at
// local north (size/2 - row - 0.5) * gsd, east (col - size/2 + 0.5) * gsd.
TEST_F(SimulatedMapTest, WindowIsNorthUpAroundItsPoint) {
  const sim::FlightProfile profile = test_profile();
  const ReferenceMap map = open();
  const LocalProjection projection(
      {profile.reference_latitude_deg, profile.reference_longitude_deg, profile.reference_height_m});
  const Eigen::Vector2d centre(40.0, -25.0);  // local north/east of the window's point
  const GeodeticPoint g = projection.geodetic(centre.x(), centre.y());
  const int size = 64;
  const MapWindow w = map.window(g.latitude_deg, g.longitude_deg, size, 1.0);
  EXPECT_EQ(w.nodata_pixels, 0);
  double worst = 0.0;
  for (int row = 1; row < size; row += 9)
    for (int col = 2; col < size; col += 7) {
      const double north = centre.x() + (size / 2.0 - row - 0.5), east = centre.y() + (col - size / 2.0 + 0.5);
      const GeodeticPoint p = projection.geodetic(north, east);
      worst = std::max(worst, std::fabs(w.grey.at<float>(row, col) - map.sample(p.latitude_deg, p.longitude_deg)));
    }
  EXPECT_LT(worst, 0.5);  // grey levels: the tangent plane and the rhumb step agree to well under a millimetre here
  // At 2 m, each pixel is the mean of the map over its footprint: smoother.
  const MapWindow coarse = map.window(g.latitude_deg, g.longitude_deg, size / 2, 2.0);
  cv::Mat fine_sd, coarse_sd, mean;
  cv::meanStdDev(w.grey, mean, fine_sd);
  cv::meanStdDev(coarse.grey, mean, coarse_sd);
  EXPECT_LT(coarse_sd.at<double>(0), fine_sd.at<double>(0));
}

TEST_F(SimulatedMapTest, ChangedPatchesCoverAFewPercent) {
  double area = 0.0;
  for (const ChangedPatch& p : map_->patches) area += p.area_m2();
  const double map_area = (map_->north_max - map_->north_min) * (map_->east_max - map_->east_min);
  EXPECT_GE(area / map_area, 0.02);
  EXPECT_LT(area / map_area, 0.03);
  EXPECT_GE(map_->patches.size(), 2u);

  // The same map without patches differs only at them, and at most of them.
  const sim::FlightProfile profile = test_profile();
  SimulatedMapOptions options = test_options();
  options.changed_fraction = 0.0;
  const SimulatedMap unchanged = simulate_map(profile, kSeed, options);
  ASSERT_EQ(unchanged.orthophoto.size(), map_->orthophoto.size());
  const LocalProjection projection(
      {profile.reference_latitude_deg, profile.reference_longitude_deg, profile.reference_height_m});
  const MapGrid& g = map_->grid;
  long long differing = 0, away_from_patches = 0;
  for (int row = 0; row < g.height; ++row)
    for (int col = 0; col < g.width; ++col) {
      const size_t i = static_cast<size_t>(row) * g.width + col;
      if (unchanged.orthophoto[i] == map_->orthophoto[i]) continue;
      ++differing;
      const Eigen::Vector2d utm = g.projected(col + 0.5, row + 0.5);
      const Eigen::Vector2d c = projection.local_from_utm(utm.x(), utm.y());
      bool near = false;
      for (const ChangedPatch& p : map_->patches)  // within a pixel of the patch's box
        near |= std::fabs(c.x() - p.north) < p.half_north + 1.5 && std::fabs(c.y() - p.east) < p.half_east + 1.5;
      away_from_patches += near ? 0 : 1;
    }
  EXPECT_EQ(away_from_patches, 0);
  EXPECT_GT(differing, 0.5 * area / (g.gsd_m * g.gsd_m));
}

// The simulator's INS reports latitude/longitude along the flown path (a
// GeodeticTrack stepped at the INS rate); the map places local points one
// step from the origin. Over the paper's longest flight the two agree within
// half a 1 m pixel.
TEST(MapPlacementTest, SimulatorLatLonWithinHalfAPixel) {
  for (const char* name : {"test1", "test2"}) {
    const sim::FlightProfile profile =
        sim::FlightProfile::load(std::string(NADIR_SOURCE_DIR) + "/config/profiles/" + name + ".yaml");
    const GeodeticPoint origin{profile.reference_latitude_deg, profile.reference_longitude_deg,
                               profile.reference_height_m};
    const LocalProjection projection(origin);
    const sim::Trajectory trajectory(profile, 1);
    GeodeticTrack path(origin);
    double worst = 0.0, farthest = 0.0;
    for (double t = 0.0; t <= trajectory.duration_s(); t += 0.01) {
      const Eigen::Vector3d ned = trajectory.at(t).position_ned;
      const GeodeticPoint flown = path.geodetic(ned);
      const Eigen::Vector2d placed = projection.local(flown.latitude_deg, flown.longitude_deg);
      worst = std::max(worst, (placed - ned.head<2>()).norm());
      farthest = std::max(farthest, ned.head<2>().norm());
    }
    EXPECT_LT(worst, 0.5) << name;  // measured: test1 0.43 m (6.1 km out), test2 0.13 m
  }
}

TEST(SeasonTransformTest, ShiftsClassesAndMovesTheLight) {
  const SeasonTransform s;
  EXPECT_EQ(s.land_cover(40).name, "dark");
  EXPECT_EQ(s.land_cover(120).name, "field");
  EXPECT_EQ(s.land_cover(230).name, "bright");
  EXPECT_GT(s.apply(40, 0, 0), 40);    // bare winter trees: lighter
  EXPECT_LT(s.apply(230, 0, 0), 230);  // wet roads and rocks: darker
  // 10 degree slopes: facing the map's sun (south-west) lit, facing away
  // (north-east) shaded; the renderer's sun (south-east) lights a slope facing
  // it, which the map's sun only grazes.
  const double g = std::tan(10.0 * M_PI / 180.0) / std::sqrt(2.0);
  const int flat = s.apply(120, 0, 0);
  EXPECT_GT(s.apply(120, g, g), flat);     // higher to the north-east: faces south-west
  EXPECT_LT(s.apply(120, -g, -g), flat);   // faces north-east
  SeasonTransform bad;
  bad.classes[1].gamma = 0.0;
  EXPECT_THROW(bad.Check(), std::invalid_argument);
}

TEST(SimulatedMapOptionsTest, RangesChecked) {
  SimulatedMapOptions o;
  o.gsd_m = 0.3;
  EXPECT_THROW(o.Check(), std::invalid_argument);
  o.gsd_m = 2.5;
  EXPECT_THROW(o.Check(), std::invalid_argument);
  o.gsd_m = 2.0;
  o.margin_m = -1.0;
  EXPECT_THROW(o.Check(), std::invalid_argument);
}

TEST(SimulatedMapDeterminismTest, SameInputsSameBytesOtherSeedOtherMap) {
  nadir::testing::TempDir a("simulated_map_a"), b("simulated_map_b"), c("simulated_map_c");
  sim::FlightProfile profile = test_profile();
  SimulatedMapOptions options = test_options();
  options.margin_m = 20.0;
  options.gsd_m = 2.0;
  write_map(a.path(), profile, 5, options);
  write_map(b.path(), profile, 5, options);
  write_map(c.path(), profile, 6, options);
  for (const char* f : {"orthophoto.tif", "dem.tif", "map.json"}) {
    EXPECT_EQ(nadir::testing::file_digest(a.file(f)), nadir::testing::file_digest(b.file(f))) << f;
    EXPECT_NE(nadir::testing::file_digest(a.file(f)), nadir::testing::file_digest(c.file(f))) << f;
  }
}

}  // namespace
}  // namespace nadir::map

namespace nadir::map {
namespace {

// A pixel budget coarsens the map in 0.25 m steps, and a flight too large
// for it even at max_gsd_m is refused naming the budget.
TEST(SimulatedMapBudgetTest, CoarsensToFitOrRefuses) {
  const sim::FlightProfile profile = test_profile();
  SimulatedMapOptions options = test_options();
  options.changed_fraction = 0.0;
  const SimulatedMap full = simulate_map(profile, kSeed, options);
  const double megapixels = double(full.grid.width) * full.grid.height / 1e6;
  options.max_megapixels = megapixels / 3.0;
  const SimulatedMap coarse = simulate_map(profile, kSeed, options);
  EXPECT_DOUBLE_EQ(coarse.grid.gsd_m, 1.75);  // sqrt(3) = 1.73: the next 0.25 m step
  EXPECT_LE(double(coarse.grid.width) * coarse.grid.height / 1e6, options.max_megapixels);
  options.max_megapixels = megapixels / 100.0;  // would need 10 m
  try {
    simulate_map(profile, kSeed, options);
    ADD_FAILURE() << "a map over budget at 2 m was made";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("max_megapixels"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace nadir::map
