#include "tools/map/geotiff_writer.h"

#include <gdal_priv.h>
#include <ogr_spatialref.h>

#include <array>
#include <memory>
#include <stdexcept>

namespace nadir::map {
namespace {

struct DatasetCloser {
  void operator()(GDALDataset* d) const { GDALClose(d); }
};

void write_band(const std::string& path, const MapGrid& grid, GDALDataType type, const void* pixels,
                std::optional<double> nodata) {
  if (static_cast<size_t>(grid.width) * grid.height == 0) throw std::runtime_error(path + ": empty grid");
  GDALAllRegister();
  GDALDriver* driver = GetGDALDriverManager()->GetDriverByName("GTiff");
  if (!driver) throw std::runtime_error(path + ": GDAL has no GTiff driver");
  char** create_options = nullptr;
  create_options = CSLSetNameValue(create_options, "COMPRESS", "DEFLATE");
  create_options = CSLSetNameValue(create_options, "TILED", "YES");
  // Heights: the floating-point predictor makes DEFLATE worth it (under half the size).
  if (type == GDT_Float32) create_options = CSLSetNameValue(create_options, "PREDICTOR", "3");
  std::unique_ptr<GDALDataset, DatasetCloser> dataset(
      driver->Create(path.c_str(), grid.width, grid.height, 1, type, create_options));
  CSLDestroy(create_options);
  if (!dataset) throw std::runtime_error(path + ": cannot create (" + CPLGetLastErrorMsg() + ")");
  std::array<double, 6> transform = grid.geotransform();
  OGRSpatialReference srs;
  if (srs.importFromEPSG(grid.epsg) != OGRERR_NONE)
    throw std::runtime_error(path + ": unknown CRS EPSG:" + std::to_string(grid.epsg));
  if (dataset->SetGeoTransform(transform.data()) != CE_None || dataset->SetSpatialRef(&srs) != CE_None)
    throw std::runtime_error(path + ": cannot write the georeferencing (" + CPLGetLastErrorMsg() + ")");
  GDALRasterBand* band = dataset->GetRasterBand(1);
  if (nodata && band->SetNoDataValue(*nodata) != CE_None)
    throw std::runtime_error(path + ": cannot set the NoData value");
  if (band->RasterIO(GF_Write, 0, 0, grid.width, grid.height, const_cast<void*>(pixels), grid.width, grid.height, type,
                     0, 0) != CE_None)
    throw std::runtime_error(path + ": write failed (" + CPLGetLastErrorMsg() + ")");
  CPLErrorReset();
  dataset.reset();  // closing flushes the last blocks
  if (CPLGetLastErrorType() >= CE_Failure)
    throw std::runtime_error(path + ": write failed on close (" + CPLGetLastErrorMsg() + ")");
}

}  // namespace

void write_geotiff_byte(const std::string& path, const MapGrid& grid, const std::vector<uint8_t>& pixels) {
  write_band(path, grid, GDT_Byte, pixels.data(), std::nullopt);
}

void write_geotiff_float(const std::string& path, const MapGrid& grid, const std::vector<float>& pixels,
                         std::optional<double> nodata) {
  write_band(path, grid, GDT_Float32, pixels.data(), nodata);
}

}  // namespace nadir::map
