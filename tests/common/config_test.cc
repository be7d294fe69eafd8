#include <gtest/gtest.h>

#include "common/camera_model.h"
#include "common/config.h"
#include "common/paths.h"
#include "tests/common/test_support.h"

namespace nadir {
namespace {

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

TEST(Config, OutOfRangeValueNamesFileKeyAndRange) {
  const Config c = Config::parse("tracker:\n  max_features: 99999\n", "my.yaml");
  const std::string what = error_of([&] { c.section("tracker").get_in_range<int>("max_features", 450, 10, 5000); });
  EXPECT_NE(what.find("my.yaml"), std::string::npos) << what;
  EXPECT_NE(what.find("tracker.max_features"), std::string::npos) << what;
  EXPECT_NE(what.find("[10, 5000]"), std::string::npos) << what;
}

TEST(Config, UnknownKeyIsNamedWithItsLine) {
  const Config c = Config::parse("cam:\n  fx: 1\n  fz: 2\n", "k.yaml");
  EXPECT_NO_THROW(c.section("cam").require_known_keys({"fx", "fz"}));
  const std::string what = error_of([&] { c.section("cam").require_known_keys({"fx", "fy"}); });
  EXPECT_NE(what.find("k.yaml"), std::string::npos) << what;
  EXPECT_NE(what.find("cam.fz"), std::string::npos) << what;
  EXPECT_NE(what.find("line 3"), std::string::npos) << what;
  EXPECT_NE(what.find("did you mean cam.fx?"), std::string::npos) << what;  // the nearest known key
}

TEST(Config, WrongTypeNamesKeyAndLine) {
  const Config c = Config::parse("a:\n  b: hello\n", "x.yaml");
  const std::string what = error_of([&] { c.section("a").get<double>("b"); });
  EXPECT_NE(what.find("a.b"), std::string::npos) << what;
  EXPECT_NE(what.find("line 2"), std::string::npos) << what;
}

TEST(Config, MissingKeyAndSyntaxErrorAreNamed) {
  const Config c = Config::parse("a: {}\n", "x.yaml");
  EXPECT_NE(error_of([&] { c.section("a").get<int>("n"); }).find("'a.n' is missing"), std::string::npos);
  EXPECT_NE(error_of([&] { Config::parse("a: [1, 2\n", "y.yaml"); }).find("y.yaml: YAML syntax error"),
            std::string::npos);
  EXPECT_NE(error_of([&] { Config::load_file("/nonexistent.yaml"); }).find("/nonexistent.yaml"), std::string::npos);
}

TEST(Config, OverridesEditNestedKeysAndAreNamedInErrors) {
  Config c = Config::parse("vo_solver:\n  variant: paper\n  iterations: 10\n", "x.yaml");
  c.apply_override("vo_solver.variant=flow");
  c.apply_override("tracker.klt.levels=4");
  EXPECT_EQ(c.section("vo_solver").get<std::string>("variant"), "flow");
  EXPECT_EQ(c.section("vo_solver").get<int>("iterations"), 10);
  EXPECT_EQ(c.section("tracker").section("klt").get<int>("levels"), 4);
  EXPECT_NE(c.source().find("vo_solver.variant=flow"), std::string::npos);
  EXPECT_NE(error_of([&] { c.apply_override("novalue"); }).find("novalue"), std::string::npos);
  EXPECT_NE(error_of([&] { c.apply_override("vo_solver.variant.x=1"); }).find("not a section"), std::string::npos);
}

TEST(Config, AnOverlayMergesAFragmentKeyByKey) {
  // nadir_calibrate's fragment (docs/calibration.md) over a config.
  Config c = Config::parse(
      "camera: {fx: 398.79, fy: 398.79, cx: 305.5, mount_rpy_deg: [0, 0, 0]}\naltimeter: {beam_body: [0, 0, 1]}\n",
      "x.yaml");
  c.apply_overlay(Config::parse(
      "# comment\ncamera:\n  mount_rpy_deg: [0.2831, 0.0219, 0.4143]\n  fx: 401.429\n  time_offset_us: 2042\n"
      "altimeter:\n  range_scale: 1.00762\n  range_bias_m: -1.242\n",
      "cal.yaml"));
  const Config camera = c.section("camera");
  EXPECT_EQ(camera.get<std::vector<double>>("mount_rpy_deg"), (std::vector<double>{0.2831, 0.0219, 0.4143}));
  EXPECT_EQ(camera.get<double>("fx"), 401.429);
  EXPECT_EQ(camera.get<double>("fy"), 398.79);  // not in the fragment: kept
  EXPECT_EQ(camera.get<double>("cx"), 305.5);
  EXPECT_EQ(camera.get<int64_t>("time_offset_us"), 2042);
  EXPECT_EQ(c.section("altimeter").get<double>("range_scale"), 1.00762);
  EXPECT_EQ(c.section("altimeter").get<double>("range_bias_m"), -1.242);
  EXPECT_EQ(c.section("altimeter").get<std::vector<double>>("beam_body"), (std::vector<double>{0, 0, 1}));
  EXPECT_NE(c.source().find("camera.fx=401.429"), std::string::npos) << c.source();
  // A fragment key where the config has a value, not a section, is named.
  const Config bad = Config::parse("camera: {fx: {a: 1}}\n", "bad.yaml");
  EXPECT_NE(error_of([&] { c.apply_overlay(bad); }).find("not a section"), std::string::npos);
}

TEST(Config, DefaultsApplyWhenAbsent) {
  const Config c = Config::parse("a: {}\n", "x.yaml");
  EXPECT_EQ(c.section_or_empty("b").get<int>("n", 7), 7);
}

TEST(Config, ShippedDefaultConfigLoadsAndHasTheCamera) {
  const Config c = Config::load_file(std::string(NADIR_SOURCE_DIR) + "/config/default.yaml");
  const CameraModel camera = CameraModel::from_config(c);
  EXPECT_EQ(camera.width, 612);
  EXPECT_EQ(camera.height, 512);
  EXPECT_NEAR(camera.horizontal_fov_rad() * 180.0 / M_PI, 75.0, 0.05);
}

TEST(Config, BadCameraValueFailsWithTheKey) {
  const Config c = Config::parse(
      "camera: {width: 612, height: 512, fx: 400, fy: 400, cx: 306, cy: 256, distortion: [0, 0, 0]}\n", "cam.yaml");
  EXPECT_NE(error_of([&] { CameraModel::from_config(c); }).find("camera.distortion"), std::string::npos);
}

}  // namespace
}  // namespace nadir
