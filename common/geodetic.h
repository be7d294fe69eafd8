#pragma once
// Local north-east-down <-> geodetic (WGS84) about an origin, flat-earth:
// the WGS84 radii of curvature at the origin latitude, taken at the origin
// height, scale angles to metres. Good to a few centimetres over the
// kilometres of one flight; not a full ECEF conversion.
//
// Angles in degrees, heights in metres above the ellipsoid (or whatever datum
// the caller's origin height uses: down = origin height - height).

#include <Eigen/Core>

namespace nadir {

struct Wgs84 {
  static constexpr double kSemiMajorAxisM = 6378137.0;
  static constexpr double kFirstEccentricitySquared = 6.69437999014e-3;
};

struct GeodeticPoint {
  double latitude_deg = 0;
  double longitude_deg = 0;
  double height_m = 0;
};

class LocalTangentPlane {
 public:
  // Radii at origin.latitude_deg, each plus origin.height_m. Callers that want
  // the radii on the ellipsoid surface pass a height of 0 and do their own
  // vertical.
  explicit LocalTangentPlane(const GeodeticPoint& origin);

  const GeodeticPoint& origin() const { return origin_; }
  // Meridian radius of curvature M and prime-vertical (normal) radius N at the
  // origin latitude, on the ellipsoid surface (without the origin height).
  double meridian_radius_m() const { return meridian_m_; }
  double normal_radius_m() const { return normal_m_; }

  // Geodetic -> local NED (metres).
  Eigen::Vector3d ned(const GeodeticPoint& p) const;
  // The horizontal part of ned(): north, east (m).
  Eigen::Vector2d north_east(double latitude_deg, double longitude_deg) const;
  // Local NED (metres) -> geodetic; the exact inverse of ned() up to rounding.
  GeodeticPoint geodetic(const Eigen::Vector3d& ned) const;

 private:
  GeodeticPoint origin_;
  double meridian_m_ = 0, normal_m_ = 0;
  double cos_lat0_ = 1;
  double north_radius_m_ = 0;  // meridian_m_ + origin height
  double east_radius_m_ = 0;   // (normal_m_ + origin height) * cos(origin latitude)
};

}  // namespace nadir
