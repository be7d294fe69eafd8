#include "tests/tools/map/map_test_rasters.h"

#include <gdal_priv.h>
#include <ogr_spatialref.h>

#include <stdexcept>
#include <vector>

namespace nadir::map::testing {

void write_test_raster(const std::string& path, const TestRaster& r) {
  GDALAllRegister();
  GDALDriver* driver = GetGDALDriverManager()->GetDriverByName("GTiff");
  GDALDataset* ds = driver->Create(path.c_str(), r.width, r.height, r.bands, static_cast<GDALDataType>(r.gdal_type),
                                   nullptr);
  if (!ds) throw std::runtime_error(path + ": cannot create");
  if (r.geotransform) {
    std::array<double, 6> t = *r.geotransform;
    ds->SetGeoTransform(t.data());
  }
  if (!r.crs.empty()) {
    OGRSpatialReference srs;
    if (srs.SetFromUserInput(r.crs.c_str()) != OGRERR_NONE) throw std::runtime_error("unknown CRS " + r.crs);
    ds->SetSpatialRef(&srs);
  }
  std::vector<double> values(static_cast<size_t>(r.width) * r.height);
  for (int row = 0; row < r.height; ++row)
    for (int col = 0; col < r.width; ++col) values[static_cast<size_t>(row) * r.width + col] = r.value(col, row);
  for (int b = 1; b <= r.bands; ++b) {
    GDALRasterBand* band = ds->GetRasterBand(b);
    if (r.nodata) band->SetNoDataValue(*r.nodata);
    if (band->RasterIO(GF_Write, 0, 0, r.width, r.height, values.data(), r.width, r.height, GDT_Float64, 0, 0) !=
        CE_None)
      throw std::runtime_error(path + ": write failed");
  }
  GDALClose(ds);
}

}  // namespace nadir::map::testing
