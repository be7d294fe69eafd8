#include "tools/map/reference_map.h"

#include "tools/map/gdal_support.h"

#include <GeographicLib/Geodesic.hpp>
#include <GeographicLib/LocalCartesian.hpp>
#include <gdal_priv.h>
#include <ogr_spatialref.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace nadir::map {
namespace {

OGRSpatialReference wgs84_lon_lat() {
  OGRSpatialReference s;
  s.SetWellKnownGeogCS("WGS84");
  s.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);  // x = longitude, y = latitude
  return s;
}

bool is_metres(const std::string& unit) {
  return unit.empty() || unit == "m" || unit == "metre" || unit == "meter" || unit == "metres" || unit == "meters";
}

// One band of values (grey or height) on its georeferenced grid.
struct Raster {
  RasterInfo info;
  double transform[6] = {0, 1, 0, 0, 0, 1};
  double inverse[6] = {0, 1, 0, 0, 0, 1};
  OGRSpatialReference srs;
  Transform from_wgs84;
  std::vector<float> values;
  bool has_nodata = false;
  float nodata = 0.0f;

  bool missing(float v) const { return std::isnan(v) || (has_nodata && v == nodata); }

  // Fractional pixel position (0, 0 = top-left corner) of projected (x, y).
  void pixel_of(double x, double y, double* col, double* row) const {
    *col = inverse[0] + inverse[1] * x + inverse[2] * y;
    *row = inverse[3] + inverse[4] * x + inverse[5] * y;
  }
  bool inside(double col, double row) const { return col >= 0 && row >= 0 && col <= info.width && row <= info.height; }

  // Fractional pixel position of WGS84 points, in place (x = lon -> col, y = lat -> row).
  void to_pixels(std::vector<double>* lon_col, std::vector<double>* lat_row) const {
    const size_t n = lon_col->size();
    std::vector<int> ok(n, 0);
    // The call is false when any point fails; the flags say which.
    if (n) from_wgs84->Transform(n, lon_col->data(), lat_row->data(), nullptr, ok.data());
    for (size_t i = 0; i < n; ++i) {
      if (!ok[i]) {
        (*lon_col)[i] = (*lat_row)[i] = -1e30;  // not transformable: outside
        continue;
      }
      pixel_of((*lon_col)[i], (*lat_row)[i], &(*lon_col)[i], &(*lat_row)[i]);
    }
  }
  bool pixel(double lat, double lon, double* col, double* row) const {
    std::vector<double> x{lon}, y{lat};
    to_pixels(&x, &y);
    *col = x[0];
    *row = y[0];
    return inside(*col, *row);
  }

  // Bilinear between pixel centres (clamped to the edge pixels); false when
  // a pixel it uses holds no data.
  bool bilinear(double col, double row, double* value) const {
    const double u = std::clamp(col - 0.5, 0.0, info.width - 1.0), v = std::clamp(row - 0.5, 0.0, info.height - 1.0);
    const int c0 = std::min(static_cast<int>(u), info.width - 1), r0 = std::min(static_cast<int>(v), info.height - 1);
    const int c1 = std::min(c0 + 1, info.width - 1), r1 = std::min(r0 + 1, info.height - 1);
    const double a = u - c0, b = v - r0;
    const float p00 = values[static_cast<size_t>(r0) * info.width + c0], p01 = values[static_cast<size_t>(r0) * info.width + c1];
    const float p10 = values[static_cast<size_t>(r1) * info.width + c0], p11 = values[static_cast<size_t>(r1) * info.width + c1];
    if (missing(p00) || missing(p01) || missing(p10) || missing(p11)) return false;
    *value = (1 - b) * ((1 - a) * p00 + a * p01) + b * ((1 - a) * p10 + a * p11);
    return true;
  }
};

std::string data_type_name(GDALDataType t) { return GDALGetDataTypeName(t) ? GDALGetDataTypeName(t) : "unknown"; }

void read_band(const std::string& path, GDALRasterBand* band, std::vector<float>* out) {
  const int w = band->GetXSize(), h = band->GetYSize();
  out->resize(static_cast<size_t>(w) * h);
  if (band->RasterIO(GF_Read, 0, 0, w, h, out->data(), w, h, GDT_Float32, 0, 0) != CE_None)
    throw MapError(path + ": read failed (" + CPLGetLastErrorMsg() + ")");
}

Raster load(const std::string& path, bool is_dem) {
  const QuietGdal quiet;
  GDALAllRegister();
  std::unique_ptr<GDALDataset, DatasetCloser> ds(GDALDataset::Open(path.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY));
  if (!ds) throw MapError(path + ": cannot open as a raster (" + CPLGetLastErrorMsg() + ")");
  Raster r;
  r.info.path = path;
  r.info.width = ds->GetRasterXSize();
  r.info.height = ds->GetRasterYSize();
  r.info.bands = ds->GetRasterCount();
  if (ds->GetGeoTransform(r.transform) != CE_None)
    throw MapError(path + ": no georeferencing (no geotransform); a map needs its pixels placed on the Earth");
  const OGRSpatialReference* srs = ds->GetSpatialRef();
  if (!srs || srs->IsEmpty()) throw MapError(path + ": no georeferencing (no coordinate reference system)");
  if (!GDALInvGeoTransform(r.transform, r.inverse)) throw MapError(path + ": degenerate geotransform (not invertible)");
  r.srs = *srs;
  r.info.crs_name = r.srs.GetName() ? r.srs.GetName() : "unnamed";
  if (is_dem && (r.srs.IsCompound() || r.srs.IsVertical()))
    throw MapError(path + ": CRS '" + r.info.crs_name + "' has a vertical datum of its own; heights above the WGS84 "
                   "ellipsoid are required (convert the DEM, e.g. gdalwarp to an ellipsoidal CRS)");
  r.srs.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
  const OGRSpatialReference wgs84 = wgs84_lon_lat();
  r.from_wgs84.reset(OGRCreateCoordinateTransformation(&wgs84, &r.srs));
  if (!r.from_wgs84) throw MapError(path + ": no transformation from WGS84 to its CRS '" + r.info.crs_name + "'");

  const int bands = r.info.bands;
  if (is_dem ? bands != 1 : !(bands == 1 || bands == 3 || bands == 4))
    throw MapError(path + ": " + std::to_string(bands) + " bands; " +
                   (is_dem ? "a DEM has one band of heights" : "an orthophoto has 1 (grey), 3 (RGB) or 4 (RGBA)"));
  GDALRasterBand* first = ds->GetRasterBand(1);
  const GDALDataType type = first->GetRasterDataType();
  if (is_dem) {
    if (type == GDT_Unknown || GDALDataTypeIsComplex(type) || type == GDT_Int64 || type == GDT_UInt64)
      throw MapError(path + ": unsupported band type " + data_type_name(type) +
                     " (heights as Byte, Int16/32, UInt16/32, Float32/64)");
    const std::string unit = first->GetUnitType() ? first->GetUnitType() : "";
    if (!is_metres(unit)) throw MapError(path + ": heights in '" + unit + "'; metres are required");
  } else {
    for (int b = 1; b <= bands; ++b)
      if (ds->GetRasterBand(b)->GetRasterDataType() != GDT_Byte)
        throw MapError(path + ": unsupported band type " + data_type_name(ds->GetRasterBand(b)->GetRasterDataType()) +
                       " in band " + std::to_string(b) + " (an orthophoto has 8-bit Byte bands)");
  }
  int has_nodata = 0;
  const double nodata = first->GetNoDataValue(&has_nodata);
  r.has_nodata = has_nodata != 0;
  r.nodata = static_cast<float>(nodata);
  read_band(path, first, &r.values);
  if (bands >= 3) {
    std::vector<float> g, b;
    read_band(path, ds->GetRasterBand(2), &g);
    read_band(path, ds->GetRasterBand(3), &b);
    for (size_t i = 0; i < r.values.size(); ++i)
      if (!r.missing(r.values[i])) r.values[i] = 0.299f * r.values[i] + 0.587f * g[i] + 0.114f * b[i];
  }
  for (float v : r.values) r.info.nodata_pixels += r.missing(v) ? 1 : 0;

  // Ground size of a pixel at the centre: from its neighbour's distance.
  const OGRSpatialReference wgs84_out = wgs84_lon_lat();
  Transform to_wgs84(OGRCreateCoordinateTransformation(&r.srs, &wgs84_out));
  double x[2], y[2];
  for (int k = 0; k < 2; ++k) {
    const double col = r.info.width / 2.0 + k, row = r.info.height / 2.0;
    x[k] = r.transform[0] + r.transform[1] * col + r.transform[2] * row;
    y[k] = r.transform[3] + r.transform[4] * col + r.transform[5] * row;
  }
  if (!to_wgs84 || !to_wgs84->Transform(2, x, y)) throw MapError(path + ": its CRS cannot be transformed to WGS84");
  double distance = 0.0;
  GeographicLib::Geodesic::WGS84().Inverse(y[0], x[0], y[1], x[1], distance);
  r.info.pixel_size_m = distance;
  return r;
}

}  // namespace

struct ReferenceMap::Impl {
  Raster orthophoto;
  Raster dem;
};

ReferenceMap::ReferenceMap(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
ReferenceMap::~ReferenceMap() = default;
ReferenceMap::ReferenceMap(ReferenceMap&&) noexcept = default;
ReferenceMap& ReferenceMap::operator=(ReferenceMap&&) noexcept = default;

ReferenceMap ReferenceMap::open(const std::string& orthophoto_path, const std::string& dem_path) {
  auto impl = std::make_unique<Impl>();
  impl->orthophoto = load(orthophoto_path, false);
  impl->dem = load(dem_path, true);
  return ReferenceMap(std::move(impl));
}

const RasterInfo& ReferenceMap::orthophoto_info() const { return impl_->orthophoto.info; }
const RasterInfo& ReferenceMap::dem_info() const { return impl_->dem.info; }
bool ReferenceMap::dem_crs_differs() const { return !impl_->orthophoto.srs.IsSame(&impl_->dem.srs); }

bool ReferenceMap::covers(double latitude_deg, double longitude_deg) const {
  double col, row;
  return impl_->orthophoto.pixel(latitude_deg, longitude_deg, &col, &row);
}

bool ReferenceMap::orthophoto_pixel(double latitude_deg, double longitude_deg, double* col, double* row) const {
  return impl_->orthophoto.pixel(latitude_deg, longitude_deg, col, row);
}

bool ReferenceMap::dem_covers(double latitude_deg, double longitude_deg) const {
  double col, row;
  return impl_->dem.pixel(latitude_deg, longitude_deg, &col, &row);
}

namespace {

// Bilinear value at a WGS84 point; `raster_name` and `value_name` word the errors.
double lookup(const Raster& r, double lat, double lon, const char* raster_name, const char* value_name) {
  double col, row, value;
  if (!r.pixel(lat, lon, &col, &row))
    throw MapCoverageError(r.info.path + ": point " + point_text(lat, lon) + " outside the " + raster_name);
  if (!r.bilinear(col, row, &value))
    throw MapNoDataError(r.info.path + ": no " + value_name + " (NoData or NaN) at " + point_text(lat, lon));
  return value;
}

}  // namespace

double ReferenceMap::sample(double latitude_deg, double longitude_deg) const {
  return lookup(impl_->orthophoto, latitude_deg, longitude_deg, "map", "data");
}

double ReferenceMap::height(double latitude_deg, double longitude_deg) const {
  return lookup(impl_->dem, latitude_deg, longitude_deg, "DEM", "height");
}

MapWindow ReferenceMap::window(double latitude_deg, double longitude_deg, int size, double gsd_m) const {
  const Raster& r = impl_->orthophoto;
  if (size < 1 || size > 8192 || !(gsd_m > 0.0))
    throw MapError(r.info.path + ": window of " + std::to_string(size) + " pixels at " + std::to_string(gsd_m) +
                   " m: size must be in [1, 8192] and gsd > 0");
  const int k = std::max(1, static_cast<int>(std::ceil(gsd_m / r.info.pixel_size_m - 1e-6)));
  const GeographicLib::LocalCartesian level(latitude_deg, longitude_deg, 0.0);
  const size_t n = static_cast<size_t>(size) * size * k * k;
  std::vector<double> x(n), y(n);
  size_t index = 0;
  for (int row = 0; row < size; ++row)
    for (int col = 0; col < size; ++col)
      for (int i = 0; i < k; ++i)
        for (int j = 0; j < k; ++j, ++index) {
          const double north = (size / 2.0 - row - (i + 0.5) / k) * gsd_m;
          const double east = (col - size / 2.0 + (j + 0.5) / k) * gsd_m;
          double lat, lon, h;
          level.Reverse(east, north, 0.0, lat, lon, h);
          x[index] = lon;
          y[index] = lat;
        }
  r.to_pixels(&x, &y);
  MapWindow w;
  w.gsd_m = gsd_m;
  w.grey = cv::Mat::zeros(size, size, CV_32F);
  w.valid = cv::Mat::zeros(size, size, CV_8U);
  index = 0;
  for (int row = 0; row < size; ++row)
    for (int col = 0; col < size; ++col) {
      double sum = 0.0;
      bool valid = true;
      for (int s = 0; s < k * k; ++s, ++index) {
        if (!r.inside(x[index], y[index]))
          throw MapCoverageError(r.info.path + ": window of " + std::to_string(size) + " x " + std::to_string(gsd_m) +
                                 " m around " + point_text(latitude_deg, longitude_deg) + " reaches outside the map");
        double v = 0.0;
        if (r.bilinear(x[index], y[index], &v)) sum += v;
        else valid = false;
      }
      if (valid) {
        w.grey.at<float>(row, col) = static_cast<float>(sum / (k * k));
        w.valid.at<uint8_t>(row, col) = 255;
      } else {
        ++w.nodata_pixels;
      }
    }
  return w;
}

}  // namespace nadir::map
