// Where a local north/east/down position lands on the WGS84 ellipsoid, by
// three conversions, at 1-100 km from the origin (45 N, 300 m): the linear
// radii-of-curvature formula nadir used before its path-following conversion
// (common/geodetic.cc; written out below), the exact tangent
// plane (GeographicLib::LocalCartesian, ECEF-based) and the constant-heading
// path (GeographicLib::Rhumb) that dead reckoning with the local north
// integrates for a straight leg. Prints the distances between them and the
// tangent plane's height above the origin's. Evidence for the choice of
// conversion (docs/research/2026-12-geodesy.md).
#include <GeographicLib/Geodesic.hpp>
#include <GeographicLib/LocalCartesian.hpp>
#include <GeographicLib/Rhumb.hpp>

#include <cmath>
#include <cstdio>
#include <cstring>

#include "common/geodetic.h"

int main(int argc, char** argv) {
  if (argc > 1 && (std::strcmp(argv[1], "--help") == 0 || std::strcmp(argv[1], "-h") == 0)) {
    std::printf("Usage: nadir_study_frames_at_range\n"
                "Local NED -> geodetic by the linear formula, the tangent plane and the constant-heading\n"
                "(rhumb) path at 1, 10, 50 and 100 km north and east of 45 N; distances between them.\n");
    return 0;
  }
  const nadir::GeodeticPoint origin{45.0, 7.0, 300.0};
  // The linear formula: WGS84 radii at the origin latitude plus the origin height.
  const nadir::CurvatureRadii radii = nadir::wgs84_radii(origin.latitude_deg);
  auto linear_geodetic = [&](double n, double e) {
    const double lat0 = origin.latitude_deg * M_PI / 180.0;
    return nadir::GeodeticPoint{origin.latitude_deg + n / (radii.meridian_m + origin.height_m) * 180.0 / M_PI,
                                origin.longitude_deg +
                                    e / ((radii.normal_m + origin.height_m) * std::cos(lat0)) * 180.0 / M_PI,
                                origin.height_m};
  };
  const GeographicLib::LocalCartesian tangent(origin.latitude_deg, origin.longitude_deg, origin.height_m);
  const GeographicLib::Geodesic& geodesic = GeographicLib::Geodesic::WGS84();
  const GeographicLib::Rhumb& rhumb = GeographicLib::Rhumb::WGS84();
  const double a = GeographicLib::Constants::WGS84_a();
  std::printf("%-14s %20s %14s %20s %20s\n", "leg", "linear-tangent (m)", "tangent up (m)", "rhumb-tangent (m)",
              "linear-rhumb (m)");
  for (double d : {1000.0, 10000.0, 50000.0, 100000.0}) {
    for (int east = 0; east < 2; ++east) {
      const double n = east ? 0 : d, e = east ? d : 0;
      const nadir::GeodeticPoint lin = linear_geodetic(n, e);
      double tp_lat, tp_lon, tp_h;
      tangent.Reverse(e, n, 0.0, tp_lat, tp_lon, tp_h);
      double rh_lat, rh_lon;  // the leg flown at 300 m: its ground track is shorter by a / (a + h)
      rhumb.Direct(origin.latitude_deg, origin.longitude_deg, east ? 90.0 : 0.0, d * a / (a + origin.height_m),
                   rh_lat, rh_lon);
      double lin_tp, rh_tp, lin_rh;
      geodesic.Inverse(lin.latitude_deg, lin.longitude_deg, tp_lat, tp_lon, lin_tp);
      geodesic.Inverse(rh_lat, rh_lon, tp_lat, tp_lon, rh_tp);
      geodesic.Inverse(lin.latitude_deg, lin.longitude_deg, rh_lat, rh_lon, lin_rh);
      std::printf("%6.0f km %-5s %20.3f %14.3f %20.3f %20.3f\n", d / 1000, east ? "east" : "north", lin_tp,
                  tp_h - origin.height_m, rh_tp, lin_rh);
    }
  }
  return 0;
}
