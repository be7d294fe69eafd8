#include "processes/tracker/tracker_options.h"

#include <sstream>
#include <vector>

namespace nadir {

namespace {

template <class T>
void check_range(const std::string& source, const std::string& key, T value, T lo, T hi) {
  if (value >= lo && value <= hi) return;
  std::ostringstream what;
  what << "= " << value << " is out of range [" << lo << ", " << hi << "]";
  require_option(false, source, "tracker." + key, what.str());
}

void check_choice(const std::string& source, const std::string& key, const std::string& value,
                  const std::vector<std::string>& allowed) {
  std::string list;
  for (const std::string& a : allowed) {
    if (value == a) return;
    list += (list.empty() ? "" : " | ") + a;
  }
  require_option(false, source, "tracker." + key, "= '" + value + "' is not one of " + list);
}

const char* mode_name(TrackerMode mode) {
  switch (mode) {
    case TrackerMode::kDescriptor:
      return "descriptor";
    case TrackerMode::kAuto:
      return "auto";
    case TrackerMode::kKlt:
      break;
  }
  return "klt";
}

TrackerMode parse_mode(const std::string& source, const std::string& text) {
  check_choice(source, "mode", text, {"klt", "descriptor", "auto"});
  if (text == "descriptor") return TrackerMode::kDescriptor;
  if (text == "auto") return TrackerMode::kAuto;
  return TrackerMode::kKlt;
}

}  // namespace

TrackerOptions TrackerOptions::from_config(const Config& root) {
  const Config c = root.section_or_empty("tracker");
  TrackerOptions o;
  o.mode = parse_mode(c.source(), c.get<std::string>("mode", mode_name(o.mode)));
  o.auto_max_interval_s = c.get<double>("auto_max_interval_s", o.auto_max_interval_s);
  o.auto_min_tracks = c.get<int>("auto_min_tracks", o.auto_min_tracks);
  const Config d = c.section_or_empty("descriptor");
  DescriptorOptions& q = o.descriptor;
  q.type = d.get<std::string>("type", q.type);
  q.max_features = d.get<int>("max_features", q.max_features);
  q.grid_cols = d.get<int>("grid_cols", q.grid_cols);
  q.grid_rows = d.get<int>("grid_rows", q.grid_rows);
  q.border_px = d.get<int>("border_px", q.border_px);
  q.orb_fast_threshold = d.get<int>("orb_fast_threshold", q.orb_fast_threshold);
  q.orb_levels = d.get<int>("orb_levels", q.orb_levels);
  q.akaze_threshold = d.get<double>("akaze_threshold", q.akaze_threshold);
  q.sift_contrast_threshold = d.get<double>("sift_contrast_threshold", q.sift_contrast_threshold);
  q.ratio = d.get<double>("ratio", q.ratio);
  q.cross_check = d.get<bool>("cross_check", q.cross_check);
  q.geometry = d.get<std::string>("geometry", q.geometry);
  q.ransac_threshold_px = d.get<double>("ransac_threshold_px", q.ransac_threshold_px);
  q.ransac_confidence = d.get<double>("ransac_confidence", q.ransac_confidence);
  q.ransac_max_iterations = d.get<int>("ransac_max_iterations", q.ransac_max_iterations);
  q.min_matches = d.get<int>("min_matches", q.min_matches);
  o.grid_cols = c.get<int>("grid_cols", o.grid_cols);
  o.grid_rows = c.get<int>("grid_rows", o.grid_rows);
  o.features_per_cell = c.get<int>("features_per_cell", o.features_per_cell);
  o.replenish_below = c.get<int>("replenish_below", o.replenish_below);
  o.min_distance_px = c.get<double>("min_distance_px", o.min_distance_px);
  o.border_px = c.get<int>("border_px", o.border_px);
  o.harris_block_size = c.get<int>("harris_block_size", o.harris_block_size);
  o.harris_k = c.get<double>("harris_k", o.harris_k);
  o.quality_level = c.get<double>("quality_level", o.quality_level);
  o.min_harris_response = c.get<double>("min_harris_response", o.min_harris_response);
  o.klt_window_px = c.get<int>("klt_window_px", o.klt_window_px);
  o.klt_pyramid_levels = c.get<int>("klt_pyramid_levels", o.klt_pyramid_levels);
  o.klt_max_iterations = c.get<int>("klt_max_iterations", o.klt_max_iterations);
  o.klt_epsilon_px = c.get<double>("klt_epsilon_px", o.klt_epsilon_px);
  o.klt_min_eig_threshold = c.get<double>("klt_min_eig_threshold", o.klt_min_eig_threshold);
  o.klt_scout_features = c.get<int>("klt_scout_features", o.klt_scout_features);
  o.klt_predicted_levels = c.get<int>("klt_predicted_levels", o.klt_predicted_levels);
  o.klt_window_warp = c.get<bool>("klt_window_warp", o.klt_window_warp);
  o.klt_local_warp = c.get<bool>("klt_local_warp", o.klt_local_warp);
  o.klt_local_warp_radius_px = c.get<double>("klt_local_warp_radius_px", o.klt_local_warp_radius_px);
  o.fb_threshold_px = c.get<double>("fb_threshold_px", o.fb_threshold_px);
  o.fb_pyramid_levels = c.get<int>("fb_pyramid_levels", o.fb_pyramid_levels);
  o.fb_window_px = c.get<int>("fb_window_px", o.fb_window_px);
  o.patch_error_factor = c.get<double>("patch_error_factor", o.patch_error_factor);
  o.patch_error_floor = c.get<double>("patch_error_floor", o.patch_error_floor);
  o.min_tracks = c.get<int>("min_tracks", o.min_tracks);
  o.dark_level = c.get<int>("dark_level", o.dark_level);
  o.saturated_level = c.get<int>("saturated_level", o.saturated_level);
  o.bad_pixel_fraction = c.get<double>("bad_pixel_fraction", o.bad_pixel_fraction);
  o.min_stddev = c.get<double>("min_stddev", o.min_stddev);
  o.mono16_significant_bits = c.get<int>("mono16_significant_bits", o.mono16_significant_bits);
  o.gap_factor = c.get<double>("gap_factor", o.gap_factor);
  o.max_gap_s = c.get<double>("max_gap_s", o.max_gap_s);
  o.Check(c.source());
  return o;
}

void TrackerOptions::Check(const std::string& source) const {
  parse_mode(source, mode_name(mode));
  check_range(source, "auto_max_interval_s", auto_max_interval_s, 0.0, 3600.0);
  check_range(source, "auto_min_tracks", auto_min_tracks, 0, 100000);
  descriptor.Check(source);
  check_range(source, "grid_cols", grid_cols, 1, 16);
  check_range(source, "grid_rows", grid_rows, 1, 16);
  check_range(source, "features_per_cell", features_per_cell, 1, 1000);
  check_range(source, "replenish_below", replenish_below, 1, features_per_cell);
  check_range(source, "min_distance_px", min_distance_px, 1.0, 200.0);
  check_range(source, "border_px", border_px, 0, 200);
  check_range(source, "harris_block_size", harris_block_size, 2, 15);
  check_range(source, "harris_k", harris_k, 0.01, 0.25);
  check_range(source, "quality_level", quality_level, 0.0, 1.0);
  check_range(source, "min_harris_response", min_harris_response, 0.0, 1.0);
  check_range(source, "klt_window_px", klt_window_px, 5, 101);
  check_range(source, "klt_pyramid_levels", klt_pyramid_levels, 1, 8);
  check_range(source, "klt_max_iterations", klt_max_iterations, 1, 1000);
  check_range(source, "klt_epsilon_px", klt_epsilon_px, 1e-6, 1.0);
  check_range(source, "klt_min_eig_threshold", klt_min_eig_threshold, 0.0, 1.0);
  check_range(source, "klt_scout_features", klt_scout_features, 6, 100000);
  check_range(source, "klt_predicted_levels", klt_predicted_levels, 1, klt_pyramid_levels);
  check_range(source, "fb_threshold_px", fb_threshold_px, 0.01, 1e6);
  check_range(source, "fb_pyramid_levels", fb_pyramid_levels, 1, klt_pyramid_levels);
  check_range(source, "fb_window_px", fb_window_px, 5, klt_window_px);
  check_range(source, "klt_local_warp_radius_px", klt_local_warp_radius_px, 10.0, 500.0);
  check_range(source, "patch_error_factor", patch_error_factor, 1.0, 1e6);
  check_range(source, "patch_error_floor", patch_error_floor, 0.0, 255.0);
  check_range(source, "min_tracks", min_tracks, 0, max_features());
  check_range(source, "dark_level", dark_level, 0, 254);
  check_range(source, "saturated_level", saturated_level, dark_level + 1, 255);
  check_range(source, "bad_pixel_fraction", bad_pixel_fraction, 0.01, 1.0);
  check_range(source, "min_stddev", min_stddev, 0.0, 128.0);
  check_range(source, "mono16_significant_bits", mono16_significant_bits, 8, 16);
  check_range(source, "gap_factor", gap_factor, 1.01, 100.0);
  check_range(source, "max_gap_s", max_gap_s, 0.001, 3600.0);
}

void DescriptorOptions::Check(const std::string& source) const {
  check_choice(source, "descriptor.type", type, {"orb", "akaze", "sift"});
  check_range(source, "descriptor.max_features", max_features, 10, 100000);
  check_range(source, "descriptor.grid_cols", grid_cols, 1, 32);
  check_range(source, "descriptor.grid_rows", grid_rows, 1, 32);
  check_range(source, "descriptor.border_px", border_px, 0, 200);
  check_range(source, "descriptor.orb_fast_threshold", orb_fast_threshold, 1, 255);
  check_range(source, "descriptor.orb_levels", orb_levels, 1, 16);
  check_range(source, "descriptor.akaze_threshold", akaze_threshold, 1e-6, 0.1);
  check_range(source, "descriptor.sift_contrast_threshold", sift_contrast_threshold, 1e-4, 0.5);
  check_range(source, "descriptor.ratio", ratio, 0.1, 1.0);
  check_choice(source, "descriptor.geometry", geometry, {"homography", "fundamental"});
  check_range(source, "descriptor.ransac_threshold_px", ransac_threshold_px, 0.1, 100.0);
  check_range(source, "descriptor.ransac_confidence", ransac_confidence, 0.5, 0.999999);
  check_range(source, "descriptor.ransac_max_iterations", ransac_max_iterations, 10, 1000000);
  check_range(source, "descriptor.min_matches", min_matches, 8, 100000);
}

}  // namespace nadir
