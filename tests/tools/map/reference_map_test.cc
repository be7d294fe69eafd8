// The reader against bad inputs: no georeferencing, unsupported bands,
// points outside, NoData/NaN holes, a DEM in another CRS or with its own
// vertical datum. Every error names the file.
#include <GeographicLib/UTMUPS.hpp>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "tests/common/test_support.h"
#include "tests/tools/map/map_test_rasters.h"
#include "tools/map/reference_map.h"

namespace nadir::map {
namespace {

using testing::TestRaster;
using testing::write_test_raster;

// A 200 x 200 m patch of UTM zone 17N at 1 m, around (40.44 N, 80.0 W).
constexpr double kLat = 40.44, kLon = -80.0;
constexpr int kSize = 200;

std::array<double, 6> utm_transform() {
  int zone;
  bool north;
  double x, y;
  GeographicLib::UTMUPS::Forward(kLat, kLon, zone, north, x, y);
  return {std::floor(x) - kSize / 2, 1.0, 0.0, std::floor(y) + kSize / 2, 0.0, -1.0};
}

TestRaster utm_orthophoto() {
  TestRaster r;
  r.width = r.height = kSize;
  r.geotransform = utm_transform();
  r.crs = "EPSG:32617";
  r.value = [](int col, int row) { return (col * 7 + row * 3) % 256; };
  return r;
}

TestRaster utm_dem() {
  TestRaster r = utm_orthophoto();
  r.gdal_type = 6;  // Float32
  r.nodata = -9999.0;
  r.value = [](int col, int row) { return 300.0 + 0.1 * col - 0.05 * row; };
  return r;
}

// The message of the MapError `f` throws (fails the test when none).
template <class Error, class F>
std::string error_of(F f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  ADD_FAILURE() << "no error thrown";
  return "";
}

class ReferenceMapTest : public ::testing::Test {
 protected:
  nadir::testing::TempDir dir_{"reference_map"};
  std::string ortho_ = dir_.file("ortho.tif"), dem_ = dir_.file("dem.tif");
  void SetUp() override {
    write_test_raster(ortho_, utm_orthophoto());
    write_test_raster(dem_, utm_dem());
  }
};

TEST_F(ReferenceMapTest, GoodPairReadsBack) {
  const ReferenceMap map = ReferenceMap::open(ortho_, dem_);
  EXPECT_FALSE(map.dem_crs_differs());
  double col, row;
  ASSERT_TRUE(map.orthophoto_pixel(kLat, kLon, &col, &row));
  // Pixel centres read back exactly; heights interpolate the linear DEM.
  const int c = static_cast<int>(col), r = static_cast<int>(row);
  const std::array<double, 6> t = utm_transform();
  double lat, lon;
  GeographicLib::UTMUPS::Reverse(17, true, t[0] + c + 0.5, t[3] - r - 0.5, lat, lon);
  EXPECT_NEAR(map.sample(lat, lon), (c * 7 + r * 3) % 256, 1e-3);
  EXPECT_NEAR(map.height(lat, lon), 300.0 + 0.1 * c - 0.05 * r, 1e-3);
  const MapWindow w = map.window(kLat, kLon, 32, 2.0);
  EXPECT_EQ(w.nodata_pixels, 0);
  EXPECT_EQ(cv::countNonZero(w.valid), 32 * 32);
}

TEST_F(ReferenceMapTest, NoGeoreferencingIsRefused) {
  TestRaster bare = utm_orthophoto();
  bare.geotransform.reset();
  bare.crs.clear();
  const std::string path = dir_.file("bare.tif");
  write_test_raster(path, bare);
  std::string why = error_of<MapError>([&] { ReferenceMap::open(path, dem_); });
  EXPECT_NE(why.find(path), std::string::npos) << why;
  EXPECT_NE(why.find("no georeferencing"), std::string::npos) << why;

  TestRaster no_crs = utm_orthophoto();
  no_crs.crs.clear();
  write_test_raster(path, no_crs);
  why = error_of<MapError>([&] { ReferenceMap::open(ortho_, path); });
  EXPECT_NE(why.find(path), std::string::npos) << why;
  EXPECT_NE(why.find("coordinate reference system"), std::string::npos) << why;
}

TEST_F(ReferenceMapTest, UnsupportedBandTypeIsRefused) {
  TestRaster floats = utm_orthophoto();
  floats.gdal_type = 6;
  const std::string path = dir_.file("float_ortho.tif");
  write_test_raster(path, floats);
  const std::string why = error_of<MapError>([&] { ReferenceMap::open(path, dem_); });
  EXPECT_NE(why.find(path), std::string::npos) << why;
  EXPECT_NE(why.find("unsupported band type Float32"), std::string::npos) << why;
}

TEST_F(ReferenceMapTest, PointsOutsideAreCoverageErrors) {
  const ReferenceMap map = ReferenceMap::open(ortho_, dem_);
  EXPECT_FALSE(map.covers(kLat + 0.01, kLon));  // 1.1 km north of a 200 m map
  std::string why = error_of<MapCoverageError>([&] { map.sample(kLat + 0.01, kLon); });
  EXPECT_NE(why.find(ortho_), std::string::npos) << why;
  EXPECT_NE(why.find("outside"), std::string::npos) << why;
  why = error_of<MapCoverageError>([&] { map.height(kLat, kLon + 0.01); });
  EXPECT_NE(why.find(dem_), std::string::npos) << why;
  // A window of 300 m around a point of a 200 m map reaches outside.
  why = error_of<MapCoverageError>([&] { map.window(kLat, kLon, 150, 2.0); });
  EXPECT_NE(why.find("reaches outside"), std::string::npos) << why;
}

TEST_F(ReferenceMapTest, DemHolesAreReportedNeverZero) {
  TestRaster holes = utm_dem();
  const auto good = holes.value;
  // NaN in columns 50-59, the NoData value in rows 120-129.
  holes.value = [good](int col, int row) {
    if (col >= 50 && col < 60) return std::numeric_limits<double>::quiet_NaN();
    if (row >= 120 && row < 130) return -9999.0;
    return good(col, row);
  };
  write_test_raster(dem_, holes);
  const ReferenceMap map = ReferenceMap::open(ortho_, dem_);
  EXPECT_EQ(map.dem_info().nodata_pixels, 10 * kSize + 10 * kSize - 100);
  const std::array<double, 6> t = utm_transform();
  double lat, lon;
  GeographicLib::UTMUPS::Reverse(17, true, t[0] + 55.5, t[3] - 10.5, lat, lon);  // in the NaN columns
  std::string why = error_of<MapNoDataError>([&] { map.height(lat, lon); });
  EXPECT_NE(why.find(dem_), std::string::npos) << why;
  EXPECT_NE(why.find("no height"), std::string::npos) << why;
  GeographicLib::UTMUPS::Reverse(17, true, t[0] + 10.5, t[3] - 125.5, lat, lon);  // in the NoData rows
  EXPECT_THROW(map.height(lat, lon), MapNoDataError);
  GeographicLib::UTMUPS::Reverse(17, true, t[0] + 10.5, t[3] - 10.5, lat, lon);  // clear of both
  EXPECT_NEAR(map.height(lat, lon), 300.0 + 0.1 * 10 - 0.05 * 10, 1e-3);
}

TEST_F(ReferenceMapTest, OrthophotoNoDataMaskedInWindows) {
  TestRaster ortho = utm_orthophoto();
  ortho.nodata = 0.0;
  ortho.value = [](int col, int) { return col < kSize / 2 ? 0.0 : 90.0; };  // west half: no data
  write_test_raster(ortho_, ortho);
  const ReferenceMap map = ReferenceMap::open(ortho_, dem_);
  const MapWindow w = map.window(kLat, kLon, 40, 1.0);
  EXPECT_GT(w.nodata_pixels, 40 * 15);
  EXPECT_LT(w.nodata_pixels, 40 * 25);
  EXPECT_EQ(w.valid.at<uint8_t>(20, 0), 0);
  EXPECT_EQ(w.valid.at<uint8_t>(20, 39), 255);
  EXPECT_FLOAT_EQ(w.grey.at<float>(20, 39), 90.0f);
}

TEST_F(ReferenceMapTest, DemInAnotherCrsIsReprojectedAtLookup) {
  // A geographic (EPSG:4326) DEM over the same ground: height linear in
  // latitude and longitude, so bilinear reading is exact.
  TestRaster geo;
  geo.width = geo.height = 100;
  geo.gdal_type = 6;
  const double step = 0.00005;  // ~5.5 m
  geo.geotransform = std::array<double, 6>{kLon - 50 * step, step, 0.0, kLat + 50 * step, 0.0, -step};
  geo.crs = "EPSG:4326";
  geo.value = [step](int col, int row) {
    const double lon = kLon - 50 * step + (col + 0.5) * step, lat = kLat + 50 * step - (row + 0.5) * step;
    return 310.0 + 20000.0 * (lat - kLat) - 10000.0 * (lon - kLon);
  };
  write_test_raster(dem_, geo);
  const ReferenceMap map = ReferenceMap::open(ortho_, dem_);
  EXPECT_TRUE(map.dem_crs_differs());
  for (double dlat : {-0.0005, 0.0, 0.0007})
    for (double dlon : {-0.0009, 0.0003}) {
      const double expected = 310.0 + 20000.0 * dlat - 10000.0 * dlon;
      EXPECT_NEAR(map.height(kLat + dlat, kLon + dlon), expected, 1e-3);
    }
}

TEST_F(ReferenceMapTest, DemWithItsOwnVerticalDatumIsRefused) {
  TestRaster geoid = utm_dem();
  geoid.crs = "EPSG:32617+5773";  // UTM 17N + EGM96 height: above the geoid, not the ellipsoid
  write_test_raster(dem_, geoid);
  const std::string why = error_of<MapError>([&] { ReferenceMap::open(ortho_, dem_); });
  EXPECT_NE(why.find(dem_), std::string::npos) << why;
  EXPECT_NE(why.find("vertical datum"), std::string::npos) << why;
}

TEST_F(ReferenceMapTest, MissingFileNamed) {
  const std::string path = dir_.file("absent.tif");
  const std::string why = error_of<MapError>([&] { ReferenceMap::open(path, dem_); });
  EXPECT_NE(why.find(path), std::string::npos) << why;
}

}  // namespace
}  // namespace nadir::map
