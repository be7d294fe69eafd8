#include "processes/tracker/tracker_options.h"

#include <gtest/gtest.h>

#include <string>

namespace nadir {
namespace {

std::string error_of(const std::string& yaml) {
  try {
    TrackerOptions::from_config(Config::parse(yaml, "test.yaml"));
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

TEST(TrackerOptions, DefaultConfigGivesTheIssueDefaults) {
  const TrackerOptions o = TrackerOptions::from_config(Config::load_file(NADIR_SOURCE_DIR "/config/default.yaml"));
  EXPECT_EQ(o.max_features(), 450);
  EXPECT_EQ(o.grid_cols, 3);
  EXPECT_EQ(o.grid_rows, 3);
  EXPECT_EQ(o.klt_window_px, 21);
  EXPECT_EQ(o.klt_pyramid_levels, 3);
  EXPECT_DOUBLE_EQ(o.fb_threshold_px, 1.0);
}

TEST(TrackerOptions, MissingSectionMeansDefaults) {
  const TrackerOptions o = TrackerOptions::from_config(Config::parse("camera: {}", "test.yaml"));
  EXPECT_EQ(o.features_per_cell, 50);
}

TEST(TrackerOptions, WindowWarpIsOnUnlessTurnedOff) {
  EXPECT_TRUE(TrackerOptions::from_config(Config::load_file(NADIR_SOURCE_DIR "/config/default.yaml")).klt_window_warp);
  EXPECT_TRUE(TrackerOptions::from_config(Config::parse("camera: {}", "t.yaml")).klt_window_warp);
  EXPECT_FALSE(TrackerOptions::from_config(Config::parse("tracker: {klt_window_warp: false}", "t.yaml")).klt_window_warp);
  const std::string bad = error_of("tracker: {klt_window_warp: sometimes}");
  EXPECT_NE(bad.find("klt_window_warp"), std::string::npos) << bad;
  EXPECT_FALSE(TrackerOptions::from_config(Config::load_file(NADIR_SOURCE_DIR "/config/default.yaml")).klt_local_warp);
  const std::string radius = error_of("tracker: {klt_local_warp: true, klt_local_warp_radius_px: 5}");
  EXPECT_NE(radius.find("tracker.klt_local_warp_radius_px"), std::string::npos) << radius;
  EXPECT_NE(radius.find("[10, 500]"), std::string::npos) << radius;
}

TEST(TrackerOptions, BadValuesNameTheKeyAndTheRange) {
  const std::string small = error_of("tracker: {klt_window_px: 4}");
  EXPECT_NE(small.find("test.yaml"), std::string::npos) << small;
  EXPECT_NE(small.find("tracker.klt_window_px"), std::string::npos) << small;
  EXPECT_NE(small.find("[5, 101]"), std::string::npos) << small;
  EXPECT_EQ(error_of("tracker: {klt_window_px: 24, fb_window_px: 8}"), "");  // even sizes are fine

  const std::string levels = error_of("tracker: {klt_pyramid_levels: 3, klt_predicted_levels: 4}");
  EXPECT_NE(levels.find("tracker.klt_predicted_levels"), std::string::npos) << levels;
  EXPECT_NE(levels.find("[1, 3]"), std::string::npos) << levels;

  const std::string range = error_of("tracker: {fb_threshold_px: -1}");
  EXPECT_NE(range.find("tracker.fb_threshold_px"), std::string::npos) << range;
  EXPECT_NE(range.find("out of range"), std::string::npos) << range;

  const std::string above = error_of("tracker: {features_per_cell: 40, replenish_below: 45}");
  EXPECT_NE(above.find("tracker.replenish_below"), std::string::npos) << above;
  EXPECT_NE(above.find("[1, 40]"), std::string::npos) << above;

  const std::string type = error_of("tracker: {grid_cols: many}");
  EXPECT_NE(type.find("tracker.grid_cols"), std::string::npos) << type;
  EXPECT_NE(type.find("wrong type"), std::string::npos) << type;
}

TEST(TrackerOptions, ModeAndDescriptorKeysAreCheckedByName) {
  const TrackerOptions o = TrackerOptions::from_config(Config::load_file(NADIR_SOURCE_DIR "/config/default.yaml"));
  // KLT, with descriptors only across what KLT cannot follow (featureless ground, a long step).
  EXPECT_EQ(o.mode, TrackerMode::kAuto);
  EXPECT_EQ(TrackerOptions{}.mode, TrackerMode::kKlt) << "without a config: KLT alone";
  EXPECT_EQ(o.descriptor.type, "sift");
  EXPECT_EQ(TrackerOptions::from_config(Config::parse("tracker: {mode: auto}", "t.yaml")).mode, TrackerMode::kAuto);
  const TrackerOptions d = TrackerOptions::from_config(
      Config::parse("tracker: {mode: descriptor, descriptor: {type: akaze, ratio: 0.7, geometry: fundamental}}", "t.yaml"));
  EXPECT_EQ(d.mode, TrackerMode::kDescriptor);
  EXPECT_EQ(d.descriptor.type, "akaze");
  EXPECT_DOUBLE_EQ(d.descriptor.ratio, 0.7);
  EXPECT_EQ(d.descriptor.geometry, "fundamental");

  const std::string mode = error_of("tracker: {mode: sometimes}");
  EXPECT_NE(mode.find("tracker.mode"), std::string::npos) << mode;
  EXPECT_NE(mode.find("klt | descriptor | auto"), std::string::npos) << mode;
  const std::string type = error_of("tracker: {descriptor: {type: surf}}");
  EXPECT_NE(type.find("tracker.descriptor.type"), std::string::npos) << type;
  EXPECT_NE(type.find("orb | akaze | sift"), std::string::npos) << type;
  const std::string ratio = error_of("tracker: {descriptor: {ratio: 1.5}}");
  EXPECT_NE(ratio.find("tracker.descriptor.ratio"), std::string::npos) << ratio;
  EXPECT_NE(ratio.find("[0.1, 1]"), std::string::npos) << ratio;
  EXPECT_NE(error_of("tracker: {descriptor: {min_matches: 4}}").find("tracker.descriptor.min_matches"), std::string::npos);
  EXPECT_NE(error_of("tracker: {descriptor: {geometry: affine}}").find("tracker.descriptor.geometry"), std::string::npos);
  EXPECT_NE(error_of("tracker: {auto_max_interval_s: -1}").find("tracker.auto_max_interval_s"), std::string::npos);
  EXPECT_NE(error_of("tracker: {descriptor: {cross_check: maybe}}").find("tracker.descriptor.cross_check"), std::string::npos);
}

}  // namespace
}  // namespace nadir
