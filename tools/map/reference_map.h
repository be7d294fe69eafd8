#pragma once
// A reference map for position fixes: an orthophoto and a DEM, GeoTIFFs (or
// any raster GDAL reads) in any CRS GDAL knows, each with its own grid.
//
// Requirements (each refused with an error naming the file):
//   - both georeferenced: a geotransform (north-up or rotated) and a CRS;
//   - orthophoto: 8-bit (Byte) bands; one band is the grey value, three or
//     four (RGB[A]) are turned grey (0.299 R + 0.587 G + 0.114 B);
//   - DEM: one band of heights in metres above the WGS84 ellipsoid (Byte,
//     Int16/32, UInt16/32, Float32/64); a CRS with a vertical datum of its own
//     (a compound CRS, e.g. heights above a geoid) is refused: the heights
//     would be off by the geoid undulation, tens of metres.
// The DEM may use another horizontal CRS (or datum) than the orthophoto:
// every point is transformed into each raster's CRS on its own (GDAL/PROJ),
// which is a reprojection at lookup time; dem_crs_differs() says so.
// NoData (the band's NoData value, or NaN) is never read as a value: a
// lookup touching it throws MapNoDataError, a window marks it in its mask.
// A point or window outside a raster throws MapCoverageError.

#include <memory>
#include <opencv2/core.hpp>
#include <stdexcept>
#include <string>
#include <vector>

namespace nadir::map {

// Base of every error of the reader; what() names the file.
struct MapError : std::runtime_error {
  using std::runtime_error::runtime_error;
};
struct MapCoverageError : MapError {
  using MapError::MapError;
};
struct MapNoDataError : MapError {
  using MapError::MapError;
};

struct RasterInfo {
  std::string path;
  std::string crs_name;   // e.g. "WGS 84 / UTM zone 17N"
  int width = 0, height = 0, bands = 0;
  double pixel_size_m = 0.0;  // ground size of a pixel at the raster's centre (geographic CRS: metres too)
  long long nodata_pixels = 0;  // NoData or NaN
};

// A window around a geodetic point, north-up in the local level frame of
// that point: pixel (row, col) centre at north = (rows/2 - row - 0.5) * gsd,
// east = (col - cols/2 + 0.5) * gsd from it.
struct MapWindow {
  cv::Mat grey;  // CV_32F, 0..255; 0 where invalid
  cv::Mat valid;  // CV_8U, 255 where every orthophoto pixel used was data
  double gsd_m = 0.0;
  long long nodata_pixels = 0;
};

class ReferenceMap {
 public:
  // Opens and reads both rasters; throws MapError naming the file.
  static ReferenceMap open(const std::string& orthophoto_path, const std::string& dem_path);
  ~ReferenceMap();
  ReferenceMap(ReferenceMap&&) noexcept;
  ReferenceMap& operator=(ReferenceMap&&) noexcept;

  const RasterInfo& orthophoto_info() const;
  const RasterInfo& dem_info() const;
  bool dem_crs_differs() const;

  // Grey value (bilinear) at a WGS84 point.
  double sample(double latitude_deg, double longitude_deg) const;
  // Height above the WGS84 ellipsoid (bilinear) at a WGS84 point.
  double height(double latitude_deg, double longitude_deg) const;
  // True when the point lies inside the orthophoto (resp. the DEM).
  bool covers(double latitude_deg, double longitude_deg) const;
  bool dem_covers(double latitude_deg, double longitude_deg) const;
  // The orthophoto's fractional pixel position of a WGS84 point ((0, 0) the
  // top-left corner of the first pixel); false when outside it.
  bool orthophoto_pixel(double latitude_deg, double longitude_deg, double* col, double* row) const;
  // A size x size window of `gsd_m` pixels around a WGS84 point; each pixel
  // the mean of the orthophoto over its footprint (ceil(gsd / map pixel)^2
  // bilinear subsamples). Throws MapCoverageError when any of it lies outside
  // the orthophoto.
  MapWindow window(double latitude_deg, double longitude_deg, int size, double gsd_m) const;

 private:
  struct Impl;
  explicit ReferenceMap(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace nadir::map
