#include "processes/tracker/tracker_options.h"

namespace nadir {

namespace {
// Checks a struct built in code, errors naming `source` and tracker.<key>.
template <class T>
void check_with(const OptionsSchema<T>& schema, const T& value, const std::string& source, const std::string& path) {
  schema.check(value, Config(YAML::Node(YAML::NodeType::Map), source, path));
}
}  // namespace

const OptionsSchema<DescriptorOptions>& DescriptorOptions::schema() {
  using O = DescriptorOptions;
  static const OptionsSchema<O> schema = [] {
    OptionsSchema<O> s("tracker.descriptor", "Descriptor matching (modes descriptor and auto): photo surveys.");
    s.choice<std::string>("type", {{"orb", "orb"}, {"akaze", "akaze"}, {"sift", "sift"}}, "keypoint detector",
                          &O::type)
        .number("max_features", 10, 100000, "", "keypoints kept per frame", &O::max_features)
        .number("grid_cols", 1, 32, "", "keypoints spread over this grid (columns)", &O::grid_cols)
        .number("grid_rows", 1, 32, "", "... (rows)", &O::grid_rows)
        .number("border_px", 0, 200, "px", "no keypoints closer to the image edge", &O::border_px)
        .number("orb_fast_threshold", 1, 255, "", "ORB: FAST threshold", &O::orb_fast_threshold)
        .number("orb_levels", 1, 16, "", "ORB: pyramid levels", &O::orb_levels)
        .number("akaze_threshold", 1e-6, 0.1, "", "AKAZE: detector response threshold", &O::akaze_threshold)
        .number("sift_contrast_threshold", 1e-4, 0.5, "", "SIFT: contrast threshold", &O::sift_contrast_threshold)
        .number("ratio", 0.1, 1.0, "", "Lowe's ratio test", &O::ratio)
        .flag("cross_check", "keep only mutual best matches", &O::cross_check)
        .choice<std::string>("geometry", {{"homography", "homography"}, {"fundamental", "fundamental"}},
                             "RANSAC model that confirms the matches", &O::geometry)
        .number("ransac_threshold_px", 0.1, 100.0, "px", "RANSAC inlier threshold", &O::ransac_threshold_px)
        .number("ransac_confidence", 0.5, 0.999999, "", "RANSAC confidence", &O::ransac_confidence)
        .number("ransac_max_iterations", 10, 1000000, "", "RANSAC iterations at most", &O::ransac_max_iterations)
        .number("min_matches", 8, 100000, "", "fewer confirmed matches: no tracks from the pair", &O::min_matches);
    return s;
  }();
  return schema;
}

const OptionsSchema<TrackerOptions>& TrackerOptions::schema() {
  using O = TrackerOptions;
  static const OptionsSchema<O> schema = [] {
    OptionsSchema<O> s("tracker", "Feature tracker: Harris corners on a grid, pyramidal KLT with a forward-backward "
                                  "check, per-cell replenishment; descriptor matching for photo surveys.");
    s.choice<TrackerMode>("mode",
                          {{"klt", TrackerMode::kKlt}, {"descriptor", TrackerMode::kDescriptor}, {"auto", TrackerMode::kAuto}},
                          "pairing: KLT (live camera), descriptors (photo surveys) or auto", &O::mode)
        .number("auto_max_interval_s", 0.0, 3600.0, "s", "auto: descriptors for a pair farther apart than this",
                &O::auto_max_interval_s)
        .number("auto_min_tracks", 0, 100000, "", "auto: ... or where KLT keeps fewer tracks", &O::auto_min_tracks)
        .include("descriptor", DescriptorOptions::schema(), &O::descriptor)
        .number("grid_cols", 1, 16, "", "cells across the image", &O::grid_cols)
        .number("grid_rows", 1, 16, "", "cells down the image", &O::grid_rows)
        .number("features_per_cell", 1, 1000, "", "target number of tracks per cell", &O::features_per_cell)
        .number("replenish_below", 1, 1000, "", "detect in a cell only when it holds fewer tracks",
                &O::replenish_below)
        .number("min_distance_px", 1.0, 200.0, "px", "spacing between any two features", &O::min_distance_px)
        .number("border_px", 0, 200, "px", "no corners or tracks closer to the image edge", &O::border_px)
        .number("harris_block_size", 2, 15, "px", "neighbourhood of the structure tensor", &O::harris_block_size)
        .number("harris_k", 0.01, 0.25, "", "Harris detector free parameter", &O::harris_k)
        .number("quality_level", 0.0, 1.0, "", "corner response relative to the strongest in the cell",
                &O::quality_level)
        .number("min_harris_response", 0.0, 1.0, "", "absolute floor: featureless cells give nothing",
                &O::min_harris_response)
        .number("klt_window_px", 5, 101, "px", "KLT window", &O::klt_window_px)
        .number("klt_pyramid_levels", 1, 8, "", "KLT pyramid levels including full resolution",
                &O::klt_pyramid_levels)
        .number("klt_max_iterations", 1, 1000, "", "KLT iterations per level", &O::klt_max_iterations)
        .number("klt_epsilon_px", 1e-6, 1.0, "px", "KLT convergence", &O::klt_epsilon_px)
        .number("klt_min_eig_threshold", 0.0, 1.0, "", "cv::calcOpticalFlowPyrLK minEigThreshold",
                &O::klt_min_eig_threshold)
        .number("klt_scout_features", 6, 100000, "", "tracked through the full pyramid first to predict the rest",
                &O::klt_scout_features)
        .number("klt_predicted_levels", 1, 8, "", "levels the predicted features need (at most klt_pyramid_levels)",
                &O::klt_predicted_levels)
        .flag("klt_window_warp", "resample each template through its window's expected deformation",
              &O::klt_window_warp)
        .flag("klt_local_warp", "... through the last pair's linear map around each feature", &O::klt_local_warp)
        .number("klt_local_warp_radius_px", 10.0, 500.0, "px", "... fitted to the neighbours within this radius",
                &O::klt_local_warp_radius_px)
        .number("fb_threshold_px", 0.01, 1e6, "px", "forward-backward consistency", &O::fb_threshold_px)
        .number("fb_pyramid_levels", 1, 8, "", "levels of the backward pass (at most klt_pyramid_levels)",
                &O::fb_pyramid_levels)
        .number("fb_window_px", 5, 101, "px", "backward-pass window (at most klt_window_px)", &O::fb_window_px)
        .number("patch_error_factor", 1.0, 1e6, "", "drop tracks whose patch error > max(floor, factor x median)",
                &O::patch_error_factor)
        .number("patch_error_floor", 0.0, 255.0, "grey levels", "... floor of that limit", &O::patch_error_floor)
        .number("min_tracks", 0, 256000, "", "fewer published tracks: FLAG_FEW_FEATURES", &O::min_tracks)
        .number("dark_level", 0, 254, "grey level", "pixel values <= this count as black", &O::dark_level)
        .number("saturated_level", 1, 255, "grey level", "pixel values >= this count as saturated",
                &O::saturated_level)
        .number("bad_pixel_fraction", 0.01, 1.0, "", "this share black (or saturated): bad image",
                &O::bad_pixel_fraction)
        .number("min_stddev", 0.0, 128.0, "grey levels", "grey-level std below this: featureless", &O::min_stddev)
        .number("mono16_significant_bits", 8, 16, "bits", "Mono16 -> 8 bit keeps the top 8 of these bits",
                &O::mono16_significant_bits)
        .number("gap_factor", 1.01, 100.0, "", "FLAG_FRAME_GAP beyond this many camera periods",
                &O::gap_factor)
        .number("max_gap_s", 0.001, 3600.0, "s", "beyond this the tracker restarts from the new frame",
                &O::max_gap_s)
        .at_most<int>("replenish_below", 1, [](const O& o) { return o.replenish_below; },
                      [](const O& o) { return o.features_per_cell; })
        .at_most<int>("klt_predicted_levels", 1, [](const O& o) { return o.klt_predicted_levels; },
                      [](const O& o) { return o.klt_pyramid_levels; })
        .at_most<int>("fb_pyramid_levels", 1, [](const O& o) { return o.fb_pyramid_levels; },
                      [](const O& o) { return o.klt_pyramid_levels; })
        .at_most<int>("fb_window_px", 5, [](const O& o) { return o.fb_window_px; },
                      [](const O& o) { return o.klt_window_px; })
        .at_most<int>("min_tracks", 0, [](const O& o) { return o.min_tracks; },
                      [](const O& o) { return o.max_features(); })
        .rule("saturated_level", [](const O& o) { return o.saturated_level > o.dark_level; },
              "must be > dark_level");
    return s;
  }();
  return schema;
}

TrackerOptions TrackerOptions::from_config(const Config& root) {
  return schema().read(root.section_or_empty("tracker"));
}

void TrackerOptions::Check(const std::string& source) const { check_with(schema(), *this, source, "tracker"); }

void DescriptorOptions::Check(const std::string& source) const {
  check_with(schema(), *this, source, "tracker.descriptor");
}

}  // namespace nadir
