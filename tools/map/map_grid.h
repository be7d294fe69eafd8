#pragma once
// Where the simulated world lies on the Earth, and the north-up UTM grid a
// map of it is written on.
//
// The simulator's world is a plane of local north/east metres around the
// profile's reference point (the start, common/geodetic.h). The map puts a
// local point at the geodetic point one constant-heading (rhumb) step from the
// origin reaches -- GeodeticTrack's convention for a single step -- and writes
// it in the UTM zone of the origin (WGS84, EPSG 326zz north / 327zz south).
// The simulator's INS latitude/longitude follow the flown path step by step;
// the two agree exactly on a straight leg from the origin and, after turns,
// within 0.13 m along test2 and 0.43 m along test1 (6.1 km out; tested).

#include <Eigen/Core>
#include <array>

#include "common/geodetic.h"

namespace nadir::map {

class LocalProjection {
 public:
  explicit LocalProjection(const GeodeticPoint& origin);

  const GeodeticPoint& origin() const { return origin_; }
  int utm_zone() const { return zone_; }
  bool northern() const { return northern_; }
  int epsg() const { return (northern_ ? 32600 : 32700) + zone_; }

  // Local north/east (m) <-> the geodetic point (height: the origin's).
  GeodeticPoint geodetic(double north, double east) const;
  Eigen::Vector2d local(double latitude_deg, double longitude_deg) const;
  // Local north/east <-> UTM easting/northing (m) in this zone.
  Eigen::Vector2d utm(double north, double east) const;
  Eigen::Vector2d local_from_utm(double easting, double northing) const;

 private:
  GeodeticPoint origin_;
  int zone_ = 0;
  bool northern_ = true;
};

// A north-up raster on the projected grid: pixel (col, row) covers easting
// [x0 + col * gsd, x0 + (col + 1) * gsd) and northing (y0 - (row + 1) * gsd,
// y0 - row * gsd]; (x0, y0) is the top-left corner (GDAL's geotransform).
struct MapGrid {
  double x0 = 0.0, y0 = 0.0;
  double gsd_m = 1.0;
  int width = 0, height = 0;
  int epsg = 0;

  std::array<double, 6> geotransform() const { return {x0, gsd_m, 0.0, y0, 0.0, -gsd_m}; }
  // Projected coordinates of a fractional pixel position (col, row) = (0, 0)
  // at the top-left corner, (0.5, 0.5) at the first pixel's centre.
  Eigen::Vector2d projected(double col, double row) const { return {x0 + col * gsd_m, y0 - row * gsd_m}; }
};

// The smallest grid on multiples of gsd_m that holds every point in
// `projected` (easting, northing) widened by margin_m on every side.
MapGrid grid_around(const std::vector<Eigen::Vector2d>& projected, double margin_m, double gsd_m, int epsg);

}  // namespace nadir::map
