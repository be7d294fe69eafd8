#include "tools/map/map_grid.h"

#include <GeographicLib/UTMUPS.hpp>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

namespace nadir::map {

LocalProjection::LocalProjection(const GeodeticPoint& origin) : origin_(origin) {
  zone_ = GeographicLib::UTMUPS::StandardZone(origin.latitude_deg, origin.longitude_deg);
  if (zone_ == GeographicLib::UTMUPS::UPS)
    throw std::invalid_argument("reference point beyond the UTM latitudes (polar): no UTM zone for the map");
  northern_ = origin.latitude_deg >= 0.0;
}

GeodeticPoint LocalProjection::geodetic(double north, double east) const {
  GeodeticTrack track(origin_);  // one step from the origin
  return track.geodetic(Eigen::Vector3d(north, east, 0.0));
}

Eigen::Vector2d LocalProjection::local(double latitude_deg, double longitude_deg) const {
  GeodeticTrack track(origin_);
  const Eigen::Vector3d ned = track.ned({latitude_deg, longitude_deg, origin_.height_m});
  return {ned.x(), ned.y()};
}

Eigen::Vector2d LocalProjection::utm(double north, double east) const {
  const GeodeticPoint p = geodetic(north, east);
  int zone = 0;
  bool northp = true;
  double x = 0.0, y = 0.0;
  GeographicLib::UTMUPS::Forward(p.latitude_deg, p.longitude_deg, zone, northp, x, y, zone_);
  // Forward gives northings of the hemisphere the point is in; keep the zone's.
  if (northp != northern_) y += northern_ ? -GeographicLib::UTMUPS::UTMShift() : GeographicLib::UTMUPS::UTMShift();
  return {x, y};
}

Eigen::Vector2d LocalProjection::local_from_utm(double easting, double northing) const {
  double lat = 0.0, lon = 0.0;
  GeographicLib::UTMUPS::Reverse(zone_, northern_, easting, northing, lat, lon);
  return local(lat, lon);
}

MapGrid grid_around(const std::vector<Eigen::Vector2d>& projected, double margin_m, double gsd_m, int epsg) {
  if (projected.empty()) throw std::invalid_argument("map extent: no points to cover");
  Eigen::Vector2d lo = projected.front(), hi = projected.front();
  for (const Eigen::Vector2d& p : projected) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  MapGrid g;
  g.gsd_m = gsd_m;
  g.epsg = epsg;
  g.x0 = std::floor((lo.x() - margin_m) / gsd_m) * gsd_m;
  g.y0 = std::ceil((hi.y() + margin_m) / gsd_m) * gsd_m;
  g.width = static_cast<int>(std::ceil((hi.x() + margin_m - g.x0) / gsd_m));
  g.height = static_cast<int>(std::ceil((g.y0 - (lo.y() - margin_m)) / gsd_m));
  return g;
}

}  // namespace nadir::map
