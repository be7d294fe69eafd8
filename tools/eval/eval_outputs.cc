#include "tools/eval/eval_outputs.h"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <stdexcept>

#include "common/geodetic.h"

namespace nadir {
namespace {

std::ofstream open_out(const std::string& path) {
  std::ofstream out(path);
  if (!out) throw std::runtime_error(path + ": cannot write");
  out.precision(10);
  return out;
}

// Calls f(lon, lat, alt) for every sample of one track (at most ~2000 points).
// Latitude/longitude along the track's path from the reference fix, on the
// ellipsoid surface (every sample moves the path; every step-th is written);
// altitude relative to the first pose.
void for_track(const EvalResult& r, bool estimate, const std::function<void(double, double, double)>& f) {
  GeodeticTrack track({r.reference_lat_deg, r.reference_lon_deg, 0.0});
  const size_t step = std::max<size_t>(1, r.samples.size() / 2000);
  for (size_t i = 0; i < r.samples.size(); ++i) {
    const auto& ned = estimate ? r.samples[i].estimate : r.samples[i].truth;
    const GeodeticPoint geo = track.geodetic(Eigen::Vector3d(ned[0], ned[1], 0.0));
    if (i % step == 0) f(geo.longitude_deg, geo.latitude_deg, -ned[2]);
  }
}

}  // namespace

void write_series_csv(const EvalResult& r, const std::string& path) {
  std::ofstream out = open_out(path);
  out << "t_s,distance_m,est_n,est_e,est_d,true_n,true_e,true_d,error_h_m,error_v_m,vel_err_n,vel_err_e,vel_err_d,"
         "yaw_error_deg,flags,sigma_h_m,sigma_n_m,sigma_e_m,sigma_yaw_deg,nees_h,nees_yaw,protection_level_m,sigma_d_m,cov_ne_m2\n";
  for (const EvalSample& s : r.samples) {
    out << s.t_s << "," << s.distance_m << "," << s.estimate[0] << "," << s.estimate[1] << "," << s.estimate[2] << ","
        << s.truth[0] << "," << s.truth[1] << "," << s.truth[2] << "," << s.error_h_m << "," << s.error_v_m << ","
        << s.velocity_error[0] << "," << s.velocity_error[1] << "," << s.velocity_error[2] << "," << s.yaw_error_deg
        << "," << s.flags << "," << s.sigma_h_m << "," << s.sigma_n_m << "," << s.sigma_e_m << "," << s.sigma_yaw_deg
        << "," << s.nees_h << "," << s.nees_yaw << "," << s.protection_level_m << "," << s.sigma_d_m << "," << s.cov_ne_m2 << "\n";
  }
}

void write_geojson(const EvalResult& r, const std::string& path) {
  std::ofstream out = open_out(path);
  out << "{\"type\":\"FeatureCollection\",\"features\":[";
  for (int track = 0; track < 2; ++track) {
    const bool estimate = track == 0;
    out << (track ? "," : "") << "{\"type\":\"Feature\",\"properties\":{\"name\":\""
        << (estimate ? "nadir estimate" : "ground truth") << "\"},\"geometry\":{\"type\":\"LineString\","
        << "\"coordinates\":[";
    bool first = true;
    for_track(r, estimate, [&](double lon, double lat, double alt) {
      out << (first ? "" : ",") << "[" << lon << "," << lat << "," << alt << "]";
      first = false;
    });
    out << "]}}";
  }
  out << "]}\n";
}

void write_kml(const EvalResult& r, const std::string& path) {
  std::ofstream out = open_out(path);
  out << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<kml xmlns=\"http://www.opengis.net/kml/2.2\"><Document>\n"
      << "<Style id=\"estimate\"><LineStyle><color>ffff0000</color><width>3</width></LineStyle></Style>\n"
      << "<Style id=\"truth\"><LineStyle><color>ff0000ff</color><width>3</width></LineStyle></Style>\n";
  for (int track = 0; track < 2; ++track) {
    const bool estimate = track == 0;
    out << "<Placemark><name>" << (estimate ? "nadir estimate" : "ground truth") << "</name><styleUrl>#"
        << (estimate ? "estimate" : "truth") << "</styleUrl><LineString><tessellate>1</tessellate>"
        << "<altitudeMode>relativeToGround</altitudeMode><coordinates>\n";
    for_track(r, estimate, [&](double lon, double lat, double alt) { out << lon << "," << lat << "," << alt << " "; });
    out << "\n</coordinates></LineString></Placemark>\n";
  }
  out << "</Document></kml>\n";
}

}  // namespace nadir
