#include "tools/map/raster_ground.h"

#include "tools/map/gdal_support.h"

#include <GeographicLib/LocalCartesian.hpp>
#include <gdal_priv.h>
#include <ogr_spatialref.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace nadir::map {
namespace {

template <typename... Args>
std::string format(const char* pattern, Args... args) {
  char text[200];
  std::snprintf(text, sizeof text, pattern, args...);
  return text;
}

std::string local_text(double north, double east) { return format("local north %.1f m, east %.1f m", north, east); }

// Smallest singular value of the 2 x 2 map [a b; c d].
double smallest_singular_value(double a, double b, double c, double d) {
  const double p = a * a + c * c, q = a * b + c * d, r = b * b + d * d;  // J^T J = [p q; q r]
  const double tr = p + r, det = p * r - q * q;
  return std::sqrt(std::max(0.0, 0.5 * (tr - std::sqrt(std::max(0.0, tr * tr - 4.0 * det)))));
}

}  // namespace

DemBounds read_dem_bounds(const std::string& path) {
  const QuietGdal quiet;
  GDALAllRegister();
  std::unique_ptr<GDALDataset, DatasetCloser> ds(GDALDataset::Open(path.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY));
  if (!ds) throw MapError(path + ": cannot open as a raster (" + CPLGetLastErrorMsg() + ")");
  double gt[6];
  const OGRSpatialReference* crs = ds->GetSpatialRef();
  if (ds->GetGeoTransform(gt) != CE_None || !crs || crs->IsEmpty())
    throw MapError(path + ": no georeferencing (geotransform and CRS)");
  GDALRasterBand* band = ds->GetRasterBand(1);
  const int w = ds->GetRasterXSize(), h = ds->GetRasterYSize();
  int has_nodata = 0;
  const float nodata = static_cast<float>(band->GetNoDataValue(&has_nodata));
  auto missing = [&](float v) { return std::isnan(v) || (has_nodata && v == nodata); };

  // Heights and the largest steps between valid neighbours, a row at a time.
  double lo = std::numeric_limits<double>::infinity(), hi = -lo, du = 0.0, dv = 0.0;
  std::vector<float> previous(static_cast<size_t>(w)), row(static_cast<size_t>(w));
  for (int r = 0; r < h; ++r) {
    if (band->RasterIO(GF_Read, 0, r, w, 1, row.data(), w, 1, GDT_Float32, 0, 0) != CE_None)
      throw MapError(path + ": read failed (" + CPLGetLastErrorMsg() + ")");
    for (int c = 0; c < w; ++c) {
      const float v = row[static_cast<size_t>(c)];
      if (missing(v)) continue;
      lo = std::min(lo, static_cast<double>(v));
      hi = std::max(hi, static_cast<double>(v));
      if (c + 1 < w && !missing(row[static_cast<size_t>(c) + 1]))
        du = std::max(du, std::fabs(static_cast<double>(row[static_cast<size_t>(c) + 1]) - v));
      if (r > 0 && !missing(previous[static_cast<size_t>(c)]))
        dv = std::max(dv, std::fabs(static_cast<double>(previous[static_cast<size_t>(c)]) - v));
    }
    std::swap(previous, row);
  }
  if (!(lo <= hi)) throw MapError(path + ": no heights (every pixel is NoData or NaN)");

  // The smallest ground size of a pixel step: the pixel-to-ground map's
  // smaller singular value on a 9 x 9 lattice over the raster (edges included).
  OGRSpatialReference source = *crs;
  source.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
  OGRSpatialReference wgs84;
  wgs84.SetWellKnownGeogCS("WGS84");
  wgs84.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
  Transform to_wgs84(
      OGRCreateCoordinateTransformation(&source, &wgs84));
  if (!to_wgs84) throw MapError(path + ": its CRS cannot be transformed to WGS84");
  double smallest = std::numeric_limits<double>::infinity();
  for (int i = 0; i <= 8; ++i)
    for (int j = 0; j <= 8; ++j) {
      const double c = 0.5 + (w - 1) * i / 8.0, r = 0.5 + (h - 1) * j / 8.0;
      double x[3], y[3];
      const double cols[3] = {c, c + 1.0, c}, rows[3] = {r, r, r + 1.0};
      for (int k = 0; k < 3; ++k) {
        x[k] = gt[0] + gt[1] * cols[k] + gt[2] * rows[k];
        y[k] = gt[3] + gt[4] * cols[k] + gt[5] * rows[k];
      }
      if (!to_wgs84->Transform(3, x, y)) throw MapError(path + ": its CRS cannot be transformed to WGS84");
      const GeographicLib::LocalCartesian level(y[0], x[0], 0.0);
      double e1, n1, e2, n2, z;
      level.Forward(y[1], x[1], 0.0, e1, n1, z);
      level.Forward(y[2], x[2], 0.0, e2, n2, z);
      smallest = std::min(smallest, smallest_singular_value(e1, e2, n1, n2));
    }
  if (!(smallest > 0.0)) throw MapError(path + ": degenerate pixel size (zero on the ground)");
  DemBounds b;
  b.min_height = lo;
  b.max_height = hi;
  b.max_slope = std::hypot(du, dv) / smallest * 1.05;
  return b;
}

RasterGround::RasterGround(ReferenceMap map, const DemBounds& dem, double latitude_deg, double longitude_deg,
                           const LocalBox& box)
    : map_(std::move(map)), box_(box) {
  const std::string& dem_path = map_.dem_info().path;
  if (!map_.dem_covers(latitude_deg, longitude_deg))
    throw MapCoverageError(dem_path + ": the reference point " + point_text(latitude_deg, longitude_deg) +
                           " lies outside the DEM");
  datum_ = map_.height(latitude_deg, longitude_deg);
  bounds_.min_height = dem.min_height - datum_;
  bounds_.max_height = dem.max_height - datum_;
  bounds_.max_slope = dem.max_slope;

  // The node lattice: at most ~4 million nodes.
  const double span_n = std::max(box_.north_max - box_.north_min, 1.0);
  const double span_e = std::max(box_.east_max - box_.east_min, 1.0);
  while ((span_n / step_ + 2.0) * (span_e / step_ + 2.0) > 4e6) step_ *= 2.0;
  nodes_n_ = static_cast<int>(std::ceil(span_n / step_)) + 1;
  nodes_e_ = static_cast<int>(std::ceil(span_e / step_)) + 1;
  const LocalProjection projection({latitude_deg, longitude_deg, datum_});
  nodes_.resize(static_cast<size_t>(nodes_n_) * nodes_e_);
  for (int i = 0; i < nodes_n_; ++i)
    for (int j = 0; j < nodes_e_; ++j) {
      const GeodeticPoint g = projection.geodetic(box_.north_min + i * step_, box_.east_min + j * step_);
      nodes_[static_cast<size_t>(i) * nodes_e_ + j] = {g.latitude_deg, g.longitude_deg};
    }

  // The box inside both rasters: its edge every 20 m or less (a raster's
  // footprint on the local plane is convex up to a negligible bow).
  const std::string& ortho_path = map_.orthophoto_info().path;
  auto check = [&](double north, double east) {
    double lat, lon;
    geodetic(north, east, &lat, &lon);
    const bool ortho = map_.covers(lat, lon), height = map_.dem_covers(lat, lon);
    if (ortho && height) return;
    throw MapCoverageError((ortho ? dem_path : ortho_path) + ": the flight's area (north " +
                           format("%.0f .. %.0f m", box_.north_min, box_.north_max) + ", east " +
                           format("%.0f .. %.0f m", box_.east_min, box_.east_max) +
                           " around the reference point) reaches outside it at " + local_text(north, east) + " (" +
                           point_text(lat, lon) + ")");
  };
  const int steps_n = static_cast<int>(std::ceil(span_n / 20.0)), steps_e = static_cast<int>(std::ceil(span_e / 20.0));
  for (int i = 0; i <= steps_n; ++i) {
    const double north = box_.north_min + (box_.north_max - box_.north_min) * i / steps_n;
    check(north, box_.east_min);
    check(north, box_.east_max);
  }
  for (int j = 0; j <= steps_e; ++j) {
    const double east = box_.east_min + (box_.east_max - box_.east_min) * j / steps_e;
    check(box_.north_min, east);
    check(box_.north_max, east);
  }
}

void RasterGround::geodetic(double north, double east, double* latitude_deg, double* longitude_deg) const {
  const double fn = (std::clamp(north, box_.north_min, box_.north_max) - box_.north_min) / step_;
  const double fe = (std::clamp(east, box_.east_min, box_.east_max) - box_.east_min) / step_;
  const int i = std::min(nodes_n_ - 2, static_cast<int>(fn)), j = std::min(nodes_e_ - 2, static_cast<int>(fe));
  const double a = fn - i, b = fe - j;
  const Eigen::Vector2d* p = &nodes_[static_cast<size_t>(i) * nodes_e_ + j];
  const Eigen::Vector2d g = (1 - a) * ((1 - b) * p[0] + b * p[1]) + a * ((1 - b) * p[nodes_e_] + b * p[nodes_e_ + 1]);
  *latitude_deg = g.x();
  *longitude_deg = g.y();
}

double RasterGround::height(double north, double east) const {
  double lat, lon;
  geodetic(north, east, &lat, &lon);
  try {
    return map_.height(lat, lon) - datum_;
  } catch (const MapNoDataError& e) {
    throw MapNoDataError(std::string(e.what()) + " (" + local_text(north, east) + ")");
  } catch (const MapCoverageError& e) {
    throw MapCoverageError(std::string(e.what()) + " (" + local_text(north, east) + ")");
  }
}

float RasterGround::albedo(double north, double east) const {
  double lat, lon;
  geodetic(north, east, &lat, &lon);
  try {
    return static_cast<float>(map_.sample(lat, lon));
  } catch (const MapNoDataError& e) {
    throw MapNoDataError(std::string(e.what()) + " (" + local_text(north, east) + ")");
  } catch (const MapCoverageError& e) {
    throw MapCoverageError(std::string(e.what()) + " (" + local_text(north, east) + ")");
  }
}

std::string RasterGround::describe() const {
  return "orthophoto " + map_.orthophoto_info().path + ", DEM " + map_.dem_info().path;
}

double view_margin_m(double height_above_ground_m) { return 1.5 * std::max(0.0, height_above_ground_m) + 100.0; }

void attach_raster_world(sim::FlightProfile* profile, uint64_t seed) {
  if (!profile->has_world()) return;
  ReferenceMap map = ReferenceMap::open(profile->world_orthophoto, profile->world_dem);
  const std::string& ortho_path = map.orthophoto_info().path;
  const std::string& dem_path = map.dem_info().path;
  const double lat0 = profile->reference_latitude_deg, lon0 = profile->reference_longitude_deg;
  if (!map.dem_covers(lat0, lon0))
    throw MapCoverageError(dem_path + ": the profile's reference point " + point_text(lat0, lon0) +
                           " lies outside the DEM");
  if (!map.covers(lat0, lon0))
    throw MapCoverageError(ortho_path + ": the profile's reference point " + point_text(lat0, lon0) +
                           " lies outside the orthophoto");
  const double datum = map.height(lat0, lon0);
  const DemBounds dem = read_dem_bounds(dem_path);
  const double lowest = profile->terrain.relief_scale * (dem.min_height - datum);  // <= 0, local

  // Every 0.5 s of the flight: data under the aircraft, and its view inside both rasters.
  const LocalProjection projection({lat0, lon0, datum});
  const sim::Trajectory trajectory(*profile, seed);
  LocalBox box{1e300, -1e300, 1e300, -1e300};
  for (double t = 0.0;; t += 0.5) {
    const double tt = std::min(t, trajectory.duration_s());
    const Eigen::Vector3d p = trajectory.at(tt).position_ned;
    const double margin = view_margin_m(-p.z() - lowest);
    auto where = [&](double north, double east, const GeodeticPoint& g) {
      return format("at t = %.1f s (", tt) + local_text(north, east) + "; " +
             point_text(g.latitude_deg, g.longitude_deg) + ")";
    };
    const GeodeticPoint under = projection.geodetic(p.x(), p.y());
    try {
      map.height(under.latitude_deg, under.longitude_deg);
      map.sample(under.latitude_deg, under.longitude_deg);
    } catch (const MapError& e) {
      throw MapError(std::string(e.what()) + ": the flight crosses it " + where(p.x(), p.y(), under));
    }
    for (const double dn : {-margin, margin})
      for (const double de : {-margin, margin}) {
        const GeodeticPoint g = projection.geodetic(p.x() + dn, p.y() + de);
        const bool ortho = map.covers(g.latitude_deg, g.longitude_deg);
        if (ortho && map.dem_covers(g.latitude_deg, g.longitude_deg)) continue;
        throw MapCoverageError((ortho ? dem_path : ortho_path) + ": the flight leaves it: " +
                               format("the view (%.0f m around the aircraft) reaches outside it ", margin) +
                               where(p.x() + dn, p.y() + de, g));
      }
    box.north_min = std::min(box.north_min, p.x() - margin);
    box.north_max = std::max(box.north_max, p.x() + margin);
    box.east_min = std::min(box.east_min, p.y() - margin);
    box.east_max = std::max(box.east_max, p.y() + margin);
    if (tt >= trajectory.duration_s()) break;
  }
  auto ground = std::make_shared<const RasterGround>(std::move(map), dem, lat0, lon0, box);
  profile->reference_height_m = ground->datum_height_m();
  profile->terrain.ground = ground;
}

}  // namespace nadir::map
