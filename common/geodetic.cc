#include "common/geodetic.h"

#include <GeographicLib/Rhumb.hpp>

#include <cmath>

#include "common/geometry.h"

namespace nadir {
namespace {

constexpr double kSemiMajorAxisM = 6378137.0;
constexpr double kFirstEccentricitySquared = 6.69437999014e-3;

const GeographicLib::Rhumb& rhumb() { return GeographicLib::Rhumb::WGS84(); }

// A step of `north`, `east` metres flown at height `height_m` covers the same
// latitude and longitude as `north * M / (M + h)`, `east * N / (N + h)` on the
// ellipsoid surface (radii at the step's start latitude; the steps are metres,
// so the change of the radii along one is below a micrometre).
Eigen::Vector2d scale_to_surface(const CurvatureRadii& r, double height_m) {
  return {r.meridian_m / (r.meridian_m + height_m), r.normal_m / (r.normal_m + height_m)};
}

}  // namespace

CurvatureRadii wgs84_radii(double latitude_deg) {
  const double sin_lat = std::sin(deg_to_rad(latitude_deg));
  const double w = 1.0 - kFirstEccentricitySquared * sin_lat * sin_lat;
  CurvatureRadii r;
  r.normal_m = kSemiMajorAxisM / std::sqrt(w);
  r.meridian_m = kSemiMajorAxisM * (1.0 - kFirstEccentricitySquared) / (w * std::sqrt(w));
  return r;
}

GeodeticTrack::GeodeticTrack(const GeodeticPoint& origin) : origin_(origin), last_geodetic_(origin) {}

void GeodeticTrack::restart() {
  last_geodetic_ = origin_;
  last_ned_.setZero();
}

GeodeticPoint GeodeticTrack::geodetic(const Eigen::Vector3d& ned) {
  GeodeticPoint p;
  p.height_m = origin_.height_m - ned.z();
  const Eigen::Vector2d step = (ned - last_ned_).head<2>();
  if (step.isZero()) {
    p.latitude_deg = last_geodetic_.latitude_deg;
    p.longitude_deg = last_geodetic_.longitude_deg;
  } else {
    const double mean_height = 0.5 * (last_geodetic_.height_m + p.height_m);
    const Eigen::Vector2d surface =
        step.cwiseProduct(scale_to_surface(wgs84_radii(last_geodetic_.latitude_deg), mean_height));
    rhumb().Direct(last_geodetic_.latitude_deg, last_geodetic_.longitude_deg,
                   rad_to_deg(std::atan2(surface.y(), surface.x())), surface.norm(), p.latitude_deg,
                   p.longitude_deg);
  }
  last_geodetic_ = p;
  last_ned_ = ned;
  return p;
}

Eigen::Vector3d GeodeticTrack::ned(const GeodeticPoint& p) {
  Eigen::Vector3d n;
  n.z() = origin_.height_m - p.height_m;
  double distance_m = 0, azimuth_deg = 0;
  rhumb().Inverse(last_geodetic_.latitude_deg, last_geodetic_.longitude_deg, p.latitude_deg, p.longitude_deg,
                  distance_m, azimuth_deg);
  const double mean_height = 0.5 * (last_geodetic_.height_m + p.height_m);
  const Eigen::Vector2d surface(distance_m * std::cos(deg_to_rad(azimuth_deg)),
                                distance_m * std::sin(deg_to_rad(azimuth_deg)));
  const Eigen::Vector2d step =
      surface.cwiseQuotient(scale_to_surface(wgs84_radii(last_geodetic_.latitude_deg), mean_height));
  n.head<2>() = last_ned_.head<2>() + step;
  last_geodetic_ = p;
  last_ned_ = n;
  return n;
}

}  // namespace nadir
