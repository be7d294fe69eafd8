#include "processes/map_matcher/map_matcher.h"

#include <opencv2/imgproc.hpp>

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <utility>

#include "common/geometry.h"
#include "processes/map_matcher/frame_ortho.h"
#include "processes/map_matcher/map_fix_covariance.h"
#include "processes/map_matcher/map_registration.h"

namespace nadir {

const char* fix_refusal_name(FixRefusal refusal) {
  switch (refusal) {
    case FixRefusal::kNone: return "accepted";
    case FixRefusal::kNoHeight: return "no_height";
    case FixRefusal::kTilted: return "tilted";
    case FixRefusal::kPriorUncertain: return "prior_uncertain";
    case FixRefusal::kTemplateSmall: return "template_small";
    case FixRefusal::kOutsideMap: return "outside_map";
    case FixRefusal::kMapNoData: return "map_no_data";
    case FixRefusal::kFramePartial: return "frame_partial";
    case FixRefusal::kFeatureless: return "featureless";
    case FixRefusal::kLowScore: return "low_score";
    case FixRefusal::kAmbiguous: return "ambiguous";
    case FixRefusal::kPeakAtEdge: return "peak_at_edge";
    case FixRefusal::kRepetitive: return "repetitive";
    case FixRefusal::kFrameDropped: return "frame_dropped";
  }
  return "unknown";
}

namespace {

std::string format(const char* pattern, double a, double b) {
  char text[160];
  std::snprintf(text, sizeof(text), pattern, a, b);
  return text;
}

FixAttempt refused(FixAttempt attempt, FixRefusal why, std::string text) {
  attempt.refusal = why;
  attempt.why = std::move(text);
  return attempt;
}

// The DEM's heights under a size x size grid (north-up, gsd) around a point,
// relative to the height there: sampled every `step` pixels and interpolated.
cv::Mat relief_around(const map::ReferenceMap& map, const map::LocalProjection& origin, double north, double east,
                      double centre_height, int size, double gsd_m) {
  const int step = 8;
  const int coarse = size / step + 2;
  cv::Mat samples(coarse, coarse, CV_32F);
  const double span = (coarse - 1) * step * gsd_m;
  for (int r = 0; r < coarse; ++r) {
    for (int c = 0; c < coarse; ++c) {
      const double dn = 0.5 * span - r * step * gsd_m, de = c * step * gsd_m - 0.5 * span;
      const GeodeticPoint p = origin.geodetic(north + dn, east + de);
      samples.at<float>(r, c) = static_cast<float>(map.height(p.latitude_deg, p.longitude_deg) - centre_height);
    }
  }
  // Sample (r, c) lies at output pixel coordinate (r * step + o) with the grid
  // centred on the output's centre.
  const double offset = 0.5 * (size - 1) - 0.5 * (coarse - 1) * step;
  cv::Mat to_coarse(size, size, CV_32FC2);
  for (int r = 0; r < size; ++r)
    for (int c = 0; c < size; ++c)
      to_coarse.at<cv::Vec2f>(r, c) = {static_cast<float>((c - offset) / step), static_cast<float>((r - offset) / step)};
  cv::Mat relief;
  cv::remap(samples, relief, to_coarse, cv::noArray(), cv::INTER_LINEAR, cv::BORDER_REPLICATE);
  return relief;
}

}  // namespace

MapMatcher::MapMatcher(const MapMatcherOptions& options, const CameraModel& camera, map::ReferenceMap map,
                       const Eigen::Vector3d& camera_lever_arm_m)
    : options_(options), camera_(camera), map_(std::move(map)), camera_lever_arm_m_(camera_lever_arm_m) {
  options_.Check();
}

FixAttempt MapMatcher::attempt(const image_t& image, const pose_t& pose, const map::LocalProjection& origin) const {
  FixAttempt a;
  map_fix_t& fix = a.fix;
  fix.utime = image.utime;
  fix.prior_ne[0] = pose.position_ned[0];
  fix.prior_ne[1] = pose.position_ned[1];
  fix.gsd_m = options_.gsd_m;
  fix.ground_down_variance = -1.0;
  const double h = pose.height_agl_m;
  if (!(h > 0.0)) return refused(a, FixRefusal::kNoHeight, "the pose has no height above ground");
  const Eigen::Matrix3d world_from_body = rotation_from_rpy(pose.roll, pose.pitch, pose.yaw);
  const Eigen::Vector3d axis = world_from_body * camera_.body_from_camera * Eigen::Vector3d::UnitZ();
  const double tilt_deg = rad_to_deg(std::acos(std::clamp(axis.z(), -1.0, 1.0)));
  // The camera centre lies camera.lever_arm_m from the INS reference point the
  // pose is of: the frame is orthorectified about the camera, and the fix
  // taken back to the reference point.
  const Eigen::Vector3d lever = world_from_body * camera_lever_arm_m_;
  const double camera_height = h - lever.z();
  if (tilt_deg > options_.max_tilt_deg) {
    return refused(a, FixRefusal::kTilted, format("camera %.1f deg from nadir (max_tilt_deg %.1f)", tilt_deg,
                                                  options_.max_tilt_deg));
  }
  Eigen::Matrix2d prior;
  prior << pose.position_covariance[0][0], pose.position_covariance[0][1], pose.position_covariance[1][0],
      pose.position_covariance[1][1];
  const double prior_sigma = std::sqrt(std::max(0.0, Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(prior)
                                                          .eigenvalues()
                                                          .maxCoeff()));
  const double radius_m = std::max(options_.min_search_radius_m, options_.search_sigmas * prior_sigma);
  fix.search_radius_m = radius_m;
  if (!(radius_m <= options_.max_search_radius_m)) {
    return refused(a, FixRefusal::kPriorUncertain, format("search radius %.1f m over max_search_radius_m %.1f",
                                                          radius_m, options_.max_search_radius_m));
  }
  const int t =
      static_cast<int>(options_.template_fraction * nadir_square_side_m(camera_, camera_height) / options_.gsd_m);
  if (t < options_.min_template_px) {
    return refused(a, FixRefusal::kTemplateSmall,
                   format("template %.0f px under min_template_px %.0f", t, options_.min_template_px));
  }
  const int radius_px = static_cast<int>(std::ceil(radius_m / options_.gsd_m));
  const int w = t + 2 * radius_px;
  const double north = pose.position_ned[0] + lever.x(), east = pose.position_ned[1] + lever.y();
  const GeodeticPoint centre = origin.geodetic(north, east);

  OrthoFrame frame;
  map::MapWindow window;
  try {
    const double ground = map_.height(centre.latitude_deg, centre.longitude_deg);
    FrameOrthoInput input;
    input.image = cv::Mat(image.height, image.width, CV_8UC1, const_cast<uint8_t*>(image.data.data()), image.stride);
    input.world_from_body = world_from_body;
    input.camera_height_m = camera_height;
    input.relief_m = relief_around(map_, origin, north, east, ground, t, options_.gsd_m);
    frame = orthorectify_frame(camera_, input, t, options_.gsd_m);
    window = map_.window(centre.latitude_deg, centre.longitude_deg, w, options_.gsd_m);
  } catch (const map::MapCoverageError& e) {
    return refused(a, FixRefusal::kOutsideMap, e.what());
  } catch (const map::MapNoDataError& e) {
    return refused(a, FixRefusal::kMapNoData, e.what());
  }
  const int unseen = t * t - cv::countNonZero(frame.valid);
  if (unseen > 0) {
    return refused(a, FixRefusal::kFramePartial, format("the frame misses %.0f of %.0f template pixels", unseen,
                                                        double(t) * t));
  }
  if (window.nodata_pixels > 0 || cv::countNonZero(window.valid) < w * w) {
    return refused(a, FixRefusal::kMapNoData, format("%.0f NoData pixels in the %.0f px map window",
                                                     double(w * w - cv::countNonZero(window.valid)), w));
  }
  const double map_texture = texture_stddev(window.grey), frame_texture = texture_stddev(frame.grey);
  fix.texture = map_texture;
  if (map_texture < options_.min_texture || frame_texture < options_.min_texture) {
    return refused(a, FixRefusal::kFeatureless,
                   format("grey stddev map %.1f, frame %.1f", map_texture, frame_texture) +
                       format(" (min_texture %.1f)%.0s", options_.min_texture, 0.0));
  }
  const cv::Mat map_edges = edge_strength(window.grey), frame_edges = edge_strength(frame.grey);
  a.map_edge_strength = mean_edge_strength(map_edges);
  a.frame_edge_strength = mean_edge_strength(frame_edges);
  if (a.map_edge_strength < options_.min_edge_strength || a.frame_edge_strength < options_.min_edge_strength) {
    return refused(a, FixRefusal::kFeatureless,
                   format("mean edge strength map %.2f, frame %.2f", a.map_edge_strength, a.frame_edge_strength) +
                       format(" grey levels/px (min_edge_strength %.2f)%.0s", options_.min_edge_strength, 0.0));
  }
  const Registration reg = register_template(map_edges, frame_edges);
  fix.score = reg.score;
  fix.peak_ratio = reg.peak_ratio;
  if (!reg.found || reg.score < options_.min_score) {
    return refused(a, FixRefusal::kLowScore, format("peak %.3f under min_score %.3f", reg.score, options_.min_score));
  }
  if (reg.at_edge) return refused(a, FixRefusal::kPeakAtEdge, "the best shift is on the border of the search");
  if (reg.peak_ratio < options_.min_peak_ratio) {
    return refused(a, FixRefusal::kAmbiguous, format("peak ratio %.3f under min_peak_ratio %.3f", reg.peak_ratio,
                                                     options_.min_peak_ratio));
  }
  a.map_self_similarity = map_self_similarity(map_edges, reg.peak_px, t);
  if (a.map_self_similarity > options_.max_map_self_similarity) {
    return refused(a, FixRefusal::kRepetitive,
                   format("the map's ground at the fix fits elsewhere in the search at %.3f "
                          "(max_map_self_similarity %.3f)",
                          a.map_self_similarity, options_.max_map_self_similarity));
  }
  Eigen::Matrix2d covariance;
  if (!map_fix_covariance(options_, reg, t * t, camera_height, &covariance)) {
    return refused(a, FixRefusal::kAmbiguous, "the correlation peak is not a maximum (flat along a direction)");
  }
  const double fix_sigma =
      std::sqrt(Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(covariance).eigenvalues().maxCoeff());
  if (fix_sigma > options_.max_fix_stddev_m) {
    return refused(a, FixRefusal::kAmbiguous, format("the peak is flat: sigma %.1f m over max_fix_stddev_m %.1f",
                                                     fix_sigma, options_.max_fix_stddev_m));
  }
  const double fix_north = north - reg.shift_px.y() * options_.gsd_m - lever.x();
  const double fix_east = east + reg.shift_px.x() * options_.gsd_m - lever.y();
  const GeodeticPoint at = origin.geodetic(fix_north, fix_east);
  fix.latitude_deg = at.latitude_deg;
  fix.longitude_deg = at.longitude_deg;
  fix.position_ne[0] = fix_north;
  fix.position_ne[1] = fix_east;
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 2; ++j) fix.covariance_ne[i][j] = covariance(i, j);
  set_ground(origin, &fix);
  return a;
}

void MapMatcher::set_ground(const map::LocalProjection& origin, map_fix_t* fix) const {
  const double north = fix->position_ne[0], east = fix->position_ne[1];
  const auto height_at = [&](double n, double e) {
    const GeodeticPoint p = origin.geodetic(n, e);
    return map_.height(p.latitude_deg, p.longitude_deg);
  };
  try {
    // The slope over one comparison pixel each side: the scale the fix's
    // position is known at.
    const double step = options_.gsd_m;
    const double up_north = (height_at(north + step, east) - height_at(north - step, east)) / (2.0 * step);
    const double up_east = (height_at(north, east + step) - height_at(north, east - step)) / (2.0 * step);
    fix->ground_down_m = origin.origin().height_m - height_at(north, east);
    fix->ground_gradient_ne[0] = -up_north;
    fix->ground_gradient_ne[1] = -up_east;
    fix->ground_down_variance = options_.dem_stddev_m * options_.dem_stddev_m;
  } catch (const map::MapError&) {
    // The DEM ends (or has NoData) right there: nothing was written, the fix
    // stays horizontal (attempt() set the variance to -1).
  }
}

}  // namespace nadir
