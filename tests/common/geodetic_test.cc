#include <gtest/gtest.h>

#include <cmath>

#include "common/geodetic.h"
#include "common/geometry.h"

namespace nadir {
namespace {

// Textbook radii of curvature, written independently of common/geodetic.cc:
// M = a (1 - e^2) / (1 - e^2 sin^2 phi)^(3/2), N = a / (1 - e^2 sin^2 phi)^(1/2).
double meridian_radius(double lat_deg) {
  const double s = std::sin(lat_deg * M_PI / 180.0);
  return 6378137.0 * (1.0 - 6.69437999014e-3) / std::pow(1.0 - 6.69437999014e-3 * s * s, 1.5);
}
double normal_radius(double lat_deg) {
  const double s = std::sin(lat_deg * M_PI / 180.0);
  return 6378137.0 / std::sqrt(1.0 - 6.69437999014e-3 * s * s);
}

TEST(Geodetic, RadiiOfCurvatureMatchTheTextbookFormulas) {
  // Equator: M = a (1 - e^2) = 6 335 439.327 m, N = a.
  const LocalTangentPlane equator({0.0, 0.0, 0.0});
  EXPECT_NEAR(equator.meridian_radius_m(), 6335439.327, 1e-3);
  EXPECT_NEAR(equator.normal_radius_m(), 6378137.0, 1e-9);
  for (double lat : {-60.0, 12.5, 45.0, 89.0}) {
    const LocalTangentPlane plane({lat, 0.0, 0.0});
    EXPECT_NEAR(plane.meridian_radius_m(), meridian_radius(lat), 1e-6) << lat;
    EXPECT_NEAR(plane.normal_radius_m(), normal_radius(lat), 1e-6) << lat;
  }
  // At 45 deg: M = 6 367 381.816 m (published figure for WGS84).
  EXPECT_NEAR(LocalTangentPlane({45.0, 0.0, 0.0}).meridian_radius_m(), 6367381.816, 1e-3);
}

TEST(Geodetic, OneKilometreNorthAt45DegreesFollowsTheMeridianRadius) {
  const LocalTangentPlane plane({45.0, 7.0, 0.0});
  const GeodeticPoint p = plane.geodetic(Eigen::Vector3d(1000.0, 0.0, 0.0));
  const double expected_dlat_deg = 1000.0 / meridian_radius(45.0) * 180.0 / M_PI;  // 0.0089982 deg
  EXPECT_NEAR(p.latitude_deg - 45.0, expected_dlat_deg, 1e-12);
  EXPECT_EQ(p.longitude_deg, 7.0);
  EXPECT_EQ(p.height_m, 0.0);
  EXPECT_NEAR(plane.ned(p).x(), 1000.0, 1e-7);
}

TEST(Geodetic, EastAtTheEquatorFollowsTheSemiMajorAxis) {
  const LocalTangentPlane plane({0.0, 100.0, 0.0});
  const GeodeticPoint p = plane.geodetic(Eigen::Vector3d(0.0, 1000.0, 0.0));
  EXPECT_NEAR(p.longitude_deg - 100.0, 1000.0 / 6378137.0 * 180.0 / M_PI, 1e-12);  // 0.0089832 deg
  EXPECT_EQ(p.latitude_deg, 0.0);
}

TEST(Geodetic, OriginHeightScalesTheRadiiAndSetsTheVertical) {
  const double h0 = 1500.0;
  const LocalTangentPlane plane({45.0, 7.0, h0});
  const GeodeticPoint p = plane.geodetic(Eigen::Vector3d(1000.0, 1000.0, -200.0));
  EXPECT_NEAR(p.latitude_deg - 45.0, rad_to_deg(1000.0 / (meridian_radius(45.0) + h0)), 1e-12);
  EXPECT_NEAR(p.longitude_deg - 7.0, rad_to_deg(1000.0 / ((normal_radius(45.0) + h0) * std::cos(M_PI / 4))), 1e-12);
  EXPECT_EQ(p.height_m, h0 + 200.0);  // down is negative above the origin
}

TEST(Geodetic, RoundTripsAreExactToANanodegree) {
  for (double lat0 : {-77.0, -33.9, 0.0, 45.0, 60.2}) {
    const LocalTangentPlane plane({lat0, -122.4, 35.0});
    for (const Eigen::Vector3d& ned : {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(5000, -3000, -120),
                                      Eigen::Vector3d(-20000, 15000, 40.5)}) {
      const GeodeticPoint p = plane.geodetic(ned);
      EXPECT_LT((plane.ned(p) - ned).norm(), 1e-6) << lat0;  // metres
      const GeodeticPoint q = plane.geodetic(plane.ned(p));
      EXPECT_NEAR(q.latitude_deg, p.latitude_deg, 1e-9) << lat0;
      EXPECT_NEAR(q.longitude_deg, p.longitude_deg, 1e-9) << lat0;
      EXPECT_NEAR(q.height_m, p.height_m, 1e-9) << lat0;
    }
  }
  const LocalTangentPlane plane({45.0, 7.0, 300.0});
  EXPECT_EQ(plane.ned({45.0, 7.0, 300.0}), Eigen::Vector3d::Zero());  // the origin maps to exactly zero
  EXPECT_EQ(plane.north_east(45.01, 7.02), plane.ned({45.01, 7.02, 0.0}).head<2>());
}

// The flat-earth model against the exact ellipsoid: a point 1 km north on the
// meridian by the arc length integral (Simpson) lands within a millimetre.
TEST(Geodetic, FlatEarthMatchesTheMeridianArcOverAKilometre) {
  const double lat0 = 45.0, dlat = 1000.0 / meridian_radius(lat0) * 180.0 / M_PI;
  const int n = 100;
  double arc = 0;
  for (int i = 0; i <= n; ++i) {
    const double w = (i == 0 || i == n) ? 1 : (i % 2 ? 4 : 2);
    arc += w * meridian_radius(lat0 + dlat * i / n);
  }
  arc *= deg_to_rad(dlat) / (3.0 * n);
  const LocalTangentPlane plane({lat0, 0.0, 0.0});
  EXPECT_NEAR(plane.ned({lat0 + dlat, 0.0, 0.0}).x(), arc, 1e-3);
}

}  // namespace
}  // namespace nadir
