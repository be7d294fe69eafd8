#pragma once
// Small GeoTIFFs written with GDAL for the reader's tests: any band type,
// with or without a geotransform and a CRS.

#include <array>
#include <functional>
#include <optional>
#include <string>

namespace nadir::map::testing {

struct TestRaster {
  int width = 64, height = 64, bands = 1;
  int gdal_type = 1;  // GDALDataType; 1 = Byte, 6 = Float32
  std::optional<std::array<double, 6>> geotransform;
  std::string crs;  // "EPSG:32617", "EPSG:4326", ...; empty: none
  std::optional<double> nodata;
  std::function<double(int col, int row)> value = [](int, int) { return 100.0; };
};

void write_test_raster(const std::string& path, const TestRaster& raster);

}  // namespace nadir::map::testing
