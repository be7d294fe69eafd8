#include "common/geodetic.h"

#include <cmath>

#include "common/geometry.h"

namespace nadir {

// The operation order below is the simulator's since its first log: every
// cached simulator log (and Table 1) depends on the INS latitude/longitude
// bits, so do not reorder or "simplify" these expressions.
LocalTangentPlane::LocalTangentPlane(const GeodeticPoint& origin) : origin_(origin) {
  const double a = Wgs84::kSemiMajorAxisM, e2 = Wgs84::kFirstEccentricitySquared;
  const double lat0 = deg_to_rad(origin.latitude_deg);
  const double sin_lat = std::sin(lat0);
  const double w = 1.0 - e2 * sin_lat * sin_lat;
  normal_m_ = a / std::sqrt(w);
  meridian_m_ = a * (1.0 - e2) / (w * std::sqrt(w));
  cos_lat0_ = std::cos(lat0);
  north_radius_m_ = meridian_m_ + origin.height_m;
  east_radius_m_ = (normal_m_ + origin.height_m) * cos_lat0_;
}

Eigen::Vector2d LocalTangentPlane::north_east(double latitude_deg, double longitude_deg) const {
  // Differences in degrees first: exact for nearby angles (Sterbenz), so a
  // point at the origin maps to exactly zero.
  return {deg_to_rad(latitude_deg - origin_.latitude_deg) * north_radius_m_,
          deg_to_rad(longitude_deg - origin_.longitude_deg) * east_radius_m_};
}

Eigen::Vector3d LocalTangentPlane::ned(const GeodeticPoint& p) const {
  const Eigen::Vector2d ne = north_east(p.latitude_deg, p.longitude_deg);
  return {ne.x(), ne.y(), origin_.height_m - p.height_m};
}

GeodeticPoint LocalTangentPlane::geodetic(const Eigen::Vector3d& ned) const {
  GeodeticPoint p;
  p.latitude_deg = origin_.latitude_deg + rad_to_deg(ned.x() / north_radius_m_);
  p.longitude_deg = origin_.longitude_deg + rad_to_deg(ned.y() / east_radius_m_);
  p.height_m = origin_.height_m - ned.z();
  return p;
}

}  // namespace nadir
