#pragma once
// Local north-east-down <-> geodetic (WGS84) along the path a vehicle flies.
//
// nadir's position is dead-reckoned: each step is measured in the local level
// frame of that moment, with its heading to the local north, and the vertical
// follows the local vertical (the altimeter ties it to the ground). Over the
// curved Earth such a sum is not a function of the end point alone (50 km east
// then 50 km north ends ~400 m from 50 km north then 50 km east), so the
// conversion follows the path: every step from the previous position is laid
// on the ellipsoid as a constant-heading (rhumb) segment flown at its height,
// with GeographicLib. For a straight leg this is exact at any length; for a
// vehicle's steps (metres each) it is exact for any path. A conversion that
// has seen no previous position starts at the origin.
//
// Angles in degrees, heights in metres above the ellipsoid, or above whatever
// datum the caller's origin height uses (down = origin height - height; the
// step's height above the ellipsoid scales it by ~1e-7 per metre, so a datum
// offset of tens of metres moves a 100 km leg by centimetres).

#include <Eigen/Core>

namespace nadir {

struct GeodeticPoint {
  double latitude_deg = 0;
  double longitude_deg = 0;
  double height_m = 0;
};

// The WGS84 radii of curvature (m) at a latitude, on the ellipsoid surface.
struct CurvatureRadii {
  double meridian_m = 0;  // M: north-south
  double normal_m = 0;    // N: prime vertical (east-west, times cos(latitude) for a parallel)
};
CurvatureRadii wgs84_radii(double latitude_deg);

class GeodeticTrack {
 public:
  explicit GeodeticTrack(const GeodeticPoint& origin);

  const GeodeticPoint& origin() const { return origin_; }

  // The geodetic point of local position `ned` (metres from the origin),
  // reached from the previous position by one step.
  GeodeticPoint geodetic(const Eigen::Vector3d& ned);
  // The local position of geodetic point `p`, reached from the previous
  // position by one step: the inverse of geodetic() along the same path.
  Eigen::Vector3d ned(const GeodeticPoint& p);

  // Forget the path: the next conversion starts at the origin again.
  void restart();

 private:
  GeodeticPoint origin_;
  GeodeticPoint last_geodetic_;
  Eigen::Vector3d last_ned_ = Eigen::Vector3d::Zero();
};

}  // namespace nadir
