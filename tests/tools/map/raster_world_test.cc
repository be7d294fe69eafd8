// Worlds from real places: a small synthetic orthophoto + DEM (UTM) named by
// a profile is the simulator's ground -- heights, albedo, rendered frames,
// the altimeter's range, refusals naming the file -- and the default
// procedural world is untouched.
#include <GeographicLib/UTMUPS.hpp>
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <string>
#include <vector>

#include "common/config.h"
#include "processes/sim/flight_profile.h"
#include "processes/sim/ray_caster.h"
#include "processes/sim/renderer.h"
#include "processes/sim/terrain.h"
#include "tests/common/test_support.h"
#include "tests/processes/sim/sim_test_support.h"
#include "tests/tools/map/map_test_rasters.h"
#include "tools/map/map_grid.h"
#include "tools/map/raster_ground.h"
#include "tools/map/simulated_map.h"

namespace nadir::map {
namespace {

constexpr double kLat = 40.0, kLon = -80.0;  // UTM zone 17N
constexpr double kPixel = 2.0;               // m, both rasters
constexpr int kSize = 1000;                  // pixels a side: 2 km
constexpr double kSquare = 15.0;             // half side (m) of the bright square at the start

// The rasters: a DEM rising 2 % to the east, an orthophoto ramp in grey
// with a bright square (grey 230) around the reference point.
class RasterWorld : public ::testing::Test {
 protected:
  void SetUp() override {
    int zone = 0;
    bool northp = true;
    GeographicLib::UTMUPS::Forward(kLat, kLon, zone, northp, x_ref_, y_ref_);
    x0_ = std::floor(x_ref_) - kSize * kPixel / 2;
    y0_ = std::floor(y_ref_) + kSize * kPixel / 2;
    testing::TestRaster dem;
    dem.width = dem.height = kSize;
    dem.gdal_type = 6;  // Float32
    dem.geotransform = std::array<double, 6>{x0_, kPixel, 0.0, y0_, 0.0, -kPixel};
    dem.crs = "EPSG:32617";
    dem.value = [this](int col, int) { return dem_height(x0_ + (col + 0.5) * kPixel); };
    testing::write_test_raster(dir_.file("dem.tif"), dem);
    testing::TestRaster ortho = dem;
    ortho.gdal_type = 1;
    ortho.value = [this](int col, int row) {
      const double x = x0_ + (col + 0.5) * kPixel, y = y0_ - (row + 0.5) * kPixel;
      if (std::fabs(x - x_ref_) < kSquare && std::fabs(y - y_ref_) < kSquare) return 230.0;
      return ramp_grey(col + 0.5, row + 0.5);
    };
    testing::write_test_raster(dir_.file("orthophoto.tif"), ortho);
  }

  double dem_height(double easting) const { return 250.0 + 0.02 * (easting - x0_); }
  // Grey of the ramp at a fractional pixel position; the orthophoto holds
  // it rounded to bytes at pixel centres.
  static double ramp_grey(double col, double row) { return 20.0 + 0.08 * col + 0.04 * row; }
  // What a bilinear read of the stored bytes gives at (col, row).
  static double stored_grey(double col, double row) {
    const double u = col - 0.5, v = row - 0.5;
    const int c = static_cast<int>(std::floor(u)), r = static_cast<int>(std::floor(v));
    const double a = u - c, b = v - r;
    auto at = [](int cc, int rr) { return std::round(ramp_grey(cc + 0.5, rr + 0.5)); };
    return (1 - b) * ((1 - a) * at(c, r) + a * at(c + 1, r)) + b * ((1 - a) * at(c, r + 1) + a * at(c + 1, r + 1));
  }

  // A profile flying `north_m` due north at 100 m over the world.
  std::string write_profile(double north_m, const std::string& extra = "") {
    std::ofstream f(dir_.file("profile.yaml"));
    f << "name: raster_world_test\n"
      << "distance_m: " << north_m << "\n"
      << "speed_mps: 20\naltitude_agl_m: 100\n"
      << "reference: {latitude_deg: " << kLat << ", longitude_deg: " << kLon << extra << "}\n"
      << "world: {orthophoto: orthophoto.tif, dem: dem.tif}\n"
      << "legs:\n  - {type: straight}\n";
    return dir_.file("profile.yaml");
  }

  sim::FlightProfile world_profile(double north_m = 300.0) {
    sim::FlightProfile p = sim::FlightProfile::load(write_profile(north_m));
    attach_raster_world(&p, 1);
    return p;
  }

  nadir::testing::TempDir dir_{"raster_world"};
  double x_ref_ = 0, y_ref_ = 0, x0_ = 0, y0_ = 0;
};

TEST_F(RasterWorld, ProfileNamesTheWorldRelativeToItsFolder) {
  const sim::FlightProfile p = sim::FlightProfile::load(write_profile(300.0));
  EXPECT_TRUE(p.has_world());
  EXPECT_EQ(p.world_orthophoto, dir_.file("orthophoto.tif"));
  EXPECT_EQ(p.world_dem, dir_.file("dem.tif"));
  EXPECT_FALSE(p.terrain.ground);  // the profile alone reads no raster
  // The datum is the DEM's: an explicit reference height is refused, by name.
  try {
    sim::FlightProfile::load(write_profile(300.0, ", height_m: 250"));
    FAIL() << "reference.height_m with world: accepted";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("reference.height_m"), std::string::npos) << e.what();
  }
  const std::string no_latitude =
      "name: x\ndistance_m: 100\nreference: {longitude_deg: -80}\nworld: {orthophoto: a.tif, dem: b.tif}\n"
      "legs:\n  - {type: straight}\n";
  try {
    sim::FlightProfile::parse(no_latitude, "/some/where/p.yaml");
    FAIL() << "world: without reference.latitude_deg accepted";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("reference.latitude_deg"), std::string::npos) << e.what();
  }
  // Without world: the procedural world, as before.
  EXPECT_FALSE(sim::testing::profile("survey").has_world());
}

TEST_F(RasterWorld, TerrainHasTheDemHeightsAndTheOrthophotoGrey) {
  const sim::FlightProfile p = world_profile();
  ASSERT_TRUE(p.terrain.ground);
  // The datum: the DEM at the reference point (its heights are linear, so bilinear is exact).
  EXPECT_NEAR(p.reference_height_m, dem_height(x_ref_), 1e-3);
  const sim::Terrain terrain(p.terrain);
  EXPECT_EQ(terrain.height(0.0, 0.0), 0.0);
  const LocalProjection projection({kLat, kLon, p.reference_height_m});
  const ReferenceMap map = ReferenceMap::open(dir_.file("orthophoto.tif"), dir_.file("dem.tif"));
  for (const auto& ne : std::vector<Eigen::Vector2d>{{0, 200}, {150, -230}, {420, 90}, {-120, 250}, {300.4, 17.7}}) {
    const Eigen::Vector2d utm = projection.utm(ne.x(), ne.y());
    // Height above the datum: the DEM's, through an independent path (UTM).
    EXPECT_NEAR(terrain.height(ne.x(), ne.y()), dem_height(utm.x()) - p.reference_height_m, 2e-3) << ne.transpose();
    const GeodeticPoint g = projection.geodetic(ne.x(), ne.y());
    EXPECT_NEAR(terrain.height(ne.x(), ne.y()), map.height(g.latitude_deg, g.longitude_deg) - p.reference_height_m,
                2e-3);
    // Albedo: the orthophoto's grey at that place.
    const double col = (utm.x() - x0_) / kPixel, row = (y0_ - utm.y()) / kPixel;
    EXPECT_NEAR(terrain.albedo(ne.x(), ne.y()), stored_grey(col, row), 0.02) << ne.transpose();
  }
  // The bright square (30 m in UTM, turned by the grid convergence of
  // ~0.6 degrees here): its edges where the orthophoto puts them.
  EXPECT_NEAR(terrain.albedo(0.0, 0.0), 230.0, 1e-3);
  for (const auto& edge : std::vector<Eigen::Vector2d>{{0, 1}, {0, -1}, {1, 0}, {-1, 0}}) {
    const Eigen::Vector2d inside = edge * (kSquare - 2.5), outside = edge * (kSquare + 2.5);
    EXPECT_NEAR(terrain.albedo(inside.x(), inside.y()), 230.0, 1e-3) << edge.transpose();
    EXPECT_LT(terrain.albedo(outside.x(), outside.y()), 120.0) << edge.transpose();
  }
  // Bounds the ray caster relies on hold for the sampled surface.
  EXPECT_GE(terrain.max_slope(), 0.02);
  EXPECT_LT(terrain.max_slope(), 0.1);
  for (double n = -300; n <= 600; n += 37)
    for (double e = -300; e <= 300; e += 41) {
      const double h = terrain.height(n, e);
      EXPECT_LE(h, terrain.max_height());
      EXPECT_GE(h, terrain.min_height());
    }
}

TEST_F(RasterWorld, RenderedFrameShowsTheSquareUnderTheCamera) {
  const sim::FlightProfile p = world_profile();
  const sim::Terrain terrain(p.terrain);
  const sim::SimCamera camera = sim::testing::default_camera();
  sim::RendererOptions options;
  options.pixel_noise_dn = 0.0;
  sim::Renderer renderer(camera, terrain, options);
  std::vector<uint8_t> image;
  // Level, heading north, 100 m above the start: the camera looks straight down.
  renderer.render(Eigen::Vector3d(0, 0, -100), camera.body_from_camera, 1, &image);
  const int w = camera.width, h = camera.height;
  auto mean = [&](int cx, int cy, int half) {
    double sum = 0;
    int n = 0;
    for (int y = cy - half; y <= cy + half; ++y)
      for (int x = cx - half; x <= cx + half; ++x, ++n) sum += image[static_cast<size_t>(y) * w + x];
    return sum / n;
  };
  // The 30 m square spans ~1/5 of the 150 m wide view: its middle is bright,
  // the ramp around it (grey ~60) is not.
  const double centre = mean(w / 2, h / 2, 15);
  EXPECT_GT(centre, 180.0);
  EXPECT_LT(mean(40, 40, 15), 110.0);
  EXPECT_LT(mean(w - 40, h - 40, 15), 110.0);
  // The square's edge lies 15 m from the middle: bright at 10 m, dark at 20 m.
  const double px_per_m = camera.fx / 100.0;
  EXPECT_GT(mean(w / 2 + static_cast<int>(10 * px_per_m), h / 2, 3), 180.0);
  EXPECT_LT(mean(w / 2 + static_cast<int>(20 * px_per_m), h / 2, 3), 110.0);
}

TEST_F(RasterWorld, AltimeterRangesTheDem) {
  const sim::FlightProfile p = world_profile();
  const sim::Terrain terrain(p.terrain);
  const LocalProjection projection({kLat, kLon, p.reference_height_m});
  for (const auto& ne : std::vector<Eigen::Vector2d>{{0, 0}, {100, 250}, {400, -200}}) {
    sim::RayHit hit;
    ASSERT_TRUE(sim::cast_ray(terrain, Eigen::Vector3d(ne.x(), ne.y(), -120.0), Eigen::Vector3d(0, 0, 1), -1.0, &hit));
    const double dem = dem_height(projection.utm(ne.x(), ne.y()).x());  // ellipsoidal
    EXPECT_NEAR(hit.t, 120.0 - (dem - p.reference_height_m), 5e-3) << ne.transpose();
  }
}

TEST_F(RasterWorld, FlightLeavingTheRastersIsRefusedNamingTheFile) {
  // 2 km north from the middle of a 2 km raster: it leaves after ~1 km
  // (less the view margin).
  sim::FlightProfile p = sim::FlightProfile::load(write_profile(2000.0));
  try {
    attach_raster_world(&p, 1);
    FAIL() << "a flight leaving the rasters was accepted";
  } catch (const MapCoverageError& e) {
    const std::string what = e.what();
    EXPECT_TRUE(what.find("orthophoto.tif") != std::string::npos || what.find("dem.tif") != std::string::npos) << what;
    EXPECT_NE(what.find("leaves"), std::string::npos) << what;
    EXPECT_NE(what.find("t = "), std::string::npos) << what;
  }
  EXPECT_FALSE(p.terrain.ground);
  // A reference point off the rasters.
  std::string text = "name: x\ndistance_m: 100\nreference: {latitude_deg: 41, longitude_deg: -80}\n"
                     "world: {orthophoto: orthophoto.tif, dem: dem.tif}\nlegs:\n  - {type: straight}\n";
  sim::FlightProfile off = sim::FlightProfile::parse(text, dir_.file("off.yaml"));
  try {
    attach_raster_world(&off, 1);
    FAIL() << "a reference point off the DEM was accepted";
  } catch (const MapCoverageError& e) {
    EXPECT_NE(std::string(e.what()).find("dem.tif"), std::string::npos) << e.what();
  }
}

TEST_F(RasterWorld, NoDataUnderTheFlightIsRefused) {
  testing::TestRaster dem;
  dem.width = dem.height = kSize;
  dem.gdal_type = 6;
  dem.geotransform = std::array<double, 6>{x0_, kPixel, 0.0, y0_, 0.0, -kPixel};
  dem.crs = "EPSG:32617";
  dem.nodata = -9999.0;
  const double hole_row = (y0_ - (y_ref_ + 200.0)) / kPixel;  // 200 m north of the start
  dem.value = [&](int, int row) { return std::fabs(row - hole_row) < 3 ? -9999.0 : 250.0; };
  testing::write_test_raster(dir_.file("dem.tif"), dem);
  sim::FlightProfile p = sim::FlightProfile::load(write_profile(300.0));
  try {
    attach_raster_world(&p, 1);
    FAIL() << "NoData under the flight was accepted";
  } catch (const MapError& e) {
    EXPECT_NE(std::string(e.what()).find("dem.tif"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("NoData"), std::string::npos) << e.what();
  }
}

TEST_F(RasterWorld, SimulatedMapIsThatPlace) {
  const sim::FlightProfile p = world_profile();
  SimulatedMapOptions options;
  options.margin_m = 100.0;
  options.changed_fraction = 0.0;
  const SimulatedMap m = simulate_map(p, 1, options);
  // The map's DEM is the world's: ellipsoidal heights linear in easting.
  for (int row = 0; row < m.grid.height; row += 97)
    for (int col = 0; col < m.grid.width; col += 89) {
      const Eigen::Vector2d xy = m.grid.projected(col + 0.5, row + 0.5);
      EXPECT_NEAR(m.dem[static_cast<size_t>(row) * m.grid.width + col], dem_height(xy.x()), 0.01);
    }
  // It covers the flight's view: the world's box lies inside the map's.
  const auto* ground = dynamic_cast<const RasterGround*>(p.terrain.ground.get());
  ASSERT_NE(ground, nullptr);
  EXPECT_LE(m.north_min, 0.0);
  EXPECT_GE(m.north_max, 300.0);
}

TEST(ProceduralWorld, UnchangedWithoutAWorld) {
  // No ground source: the procedural field, bit for bit (values pinned from
  // before worlds existed; digest tests in tests/processes/sim cover whole logs).
  sim::TerrainOptions options;
  options.seed = 7;
  EXPECT_FALSE(options.ground);
  const sim::Terrain terrain(options);
  EXPECT_EQ(terrain.height(123.4, -56.7), -2.2259019279479983);
  EXPECT_EQ(terrain.height(-1234.5, 987.25), -5.4519034028053284);
  EXPECT_EQ(terrain.albedo(33.3, 44.4), 89.785202f);
  EXPECT_EQ(terrain.max_slope(), 0.54817235377994722);
  EXPECT_EQ(terrain.height(0.0, 0.0), 0.0);
}

}  // namespace
}  // namespace nadir::map
