// OptionsSchema: one declaration per key reads, refuses unknown keys with the
// nearest known one, checks ranges and choices, and describes itself.
#include "common/options_schema.h"

#include <gtest/gtest.h>

#include <array>
#include <string>

namespace nadir {
namespace {

enum class Mode { kFast, kSlow };

struct Inner {
  double radius = 0.25;
};

struct Demo {
  double gain = 1.5;
  int count = 8;
  bool enabled = true;
  Mode mode = Mode::kFast;
  std::string name = "x";
  int64_t wait_us = 9000;
  std::array<double, 3> arm{0.0, 0.0, 0.0};
  Inner inner;
};

const OptionsSchema<Demo>& schema() {
  static const OptionsSchema<Demo> s = [] {
    OptionsSchema<Demo> d("demo", "A demo section.");
    d.number("gain", 0.0, 10.0, "", "a gain", &Demo::gain)
        .number("min_features", 5, 100, "", "a count", &Demo::count)
        .flag("enabled", "on or off", &Demo::enabled)
        .choice<Mode>("mode", {{"fast", Mode::kFast}, {"slow", Mode::kSlow}}, "how fast", &Demo::mode)
        .text("name", "a name", &Demo::name)
        .scaled("wait_ms", 1e3, 0.0, 1000.0, "ms", "a wait", &Demo::wait_us)
        .numbers<3>("arm_m", -20.0, 20.0, "m", "a lever arm", &Demo::arm)
        .number("inner.radius", 1e-3, 2.0, "", "nested", &Demo::inner, &Inner::radius)
        .rule("gain", [](const Demo& o) { return o.gain < o.count; }, "must be below min_features");
    return d;
  }();
  return s;
}

std::string error_of(const std::string& yaml) {
  try {
    schema().read(Config::parse(yaml, "test.yaml").section_or_empty("demo"));
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

TEST(OptionsSchema, ReadsEveryKindOfKey) {
  const Demo d = schema().read(Config::parse(
      "demo: {gain: 2, min_features: 9, enabled: false, mode: slow, name: y, wait_ms: 1.5, arm_m: [1, 2, 3],"
      " inner: {radius: 0.5}}",
      "test.yaml").section("demo"));
  EXPECT_EQ(d.gain, 2.0);
  EXPECT_EQ(d.count, 9);
  EXPECT_FALSE(d.enabled);
  EXPECT_EQ(d.mode, Mode::kSlow);
  EXPECT_EQ(d.name, "y");
  EXPECT_EQ(d.wait_us, 1500);
  EXPECT_EQ(d.arm[2], 3.0);
  EXPECT_EQ(d.inner.radius, 0.5);
}

TEST(OptionsSchema, AbsentKeysKeepTheDefaults) {
  const Demo d = schema().read(Config::parse("other: 1", "test.yaml").section_or_empty("demo"));
  EXPECT_EQ(d.gain, 1.5);
  EXPECT_EQ(d.count, 8);
  EXPECT_EQ(d.wait_us, 9000);
}

TEST(OptionsSchema, ReadingNestedKeysLeavesTheConfigAsItWas) {
  const Config c = Config::parse("demo: {gain: 2, inner: {radius: 0.5}, wait_ms: 3}\nother: {a: 1}\n", "t.yaml");
  const std::string before = c.dump();
  EXPECT_EQ(schema().read(c.section("demo")).inner.radius, 0.5);
  EXPECT_EQ(c.dump(), before);
}

TEST(Config, AssignmentRebindsAndLeavesTheOtherTreeAlone) {
  const Config a = Config::parse("x: {k: 1}\n", "a.yaml");
  const Config b = Config::parse("y: {k: 2}\n", "b.yaml");
  const std::string a_text = a.dump();
  Config c = a;
  c = b;
  EXPECT_EQ(a.dump(), a_text);
  EXPECT_EQ(c.source(), "b.yaml");
  EXPECT_TRUE(c.has("y"));
}

TEST(OptionsSchema, MisspeltKeyNamesFileLinePathAndSuggestion) {
  const std::string e = error_of("demo:\n  gain: 2\n  min_featurs: 3\n");
  EXPECT_NE(e.find("test.yaml"), std::string::npos) << e;
  EXPECT_NE(e.find("'demo.min_featurs'"), std::string::npos) << e;
  EXPECT_NE(e.find("line 3"), std::string::npos) << e;
  EXPECT_NE(e.find("did you mean demo.min_features?"), std::string::npos) << e;
}

TEST(OptionsSchema, MisspeltNestedKeyAndKeyAtTheWrongLevel) {
  std::string e = error_of("demo: {inner: {radis: 0.3}}");
  EXPECT_NE(e.find("'demo.inner.radis'"), std::string::npos) << e;
  EXPECT_NE(e.find("did you mean demo.inner.radius?"), std::string::npos) << e;
  e = error_of("demo: {radius: 0.3}");
  EXPECT_NE(e.find("did you mean demo.inner.radius?"), std::string::npos) << e;
  e = error_of("demo: {completely_unrelated_key: 1}");
  EXPECT_NE(e.find("is not a known key"), std::string::npos) << e;
  EXPECT_EQ(e.find("did you mean"), std::string::npos) << e;
}

TEST(OptionsSchema, OverrideOfAMisspeltKeyIsRefused) {
  Config c = Config::parse("demo: {gain: 2}", "default.yaml");
  c.apply_override("demo.min_featurs=3");
  try {
    schema().read(c.section("demo"));
    FAIL() << "no error";
  } catch (const ConfigError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("demo.min_featurs=3"), std::string::npos) << what;  // the source names the --set
    EXPECT_NE(what.find("did you mean demo.min_features?"), std::string::npos) << what;
  }
}

TEST(OptionsSchema, RangesChoicesListsAndRules) {
  EXPECT_NE(error_of("demo: {gain: 11}").find("'demo.gain' = 11 is out of range [0, 10]"), std::string::npos);
  EXPECT_NE(error_of("demo: {min_features: 3}").find("= 3 is out of range [5, 100]"), std::string::npos);
  EXPECT_NE(error_of("demo: {mode: medium}").find("= 'medium' is not one of fast | slow"), std::string::npos);
  EXPECT_NE(error_of("demo: {wait_ms: 2000}").find("'demo.wait_ms'"), std::string::npos);
  EXPECT_NE(error_of("demo: {arm_m: [1, 2]}").find("must have 3 numbers"), std::string::npos);
  EXPECT_NE(error_of("demo: {arm_m: [1, 2, 30]}").find("'demo.arm_m' = 30 is out of range"), std::string::npos);
  EXPECT_NE(error_of("demo: {gain: 9, min_features: 5}").find("'demo.gain' must be below min_features"),
            std::string::npos);
  EXPECT_NE(error_of("demo: {gain: fast}").find("wrong type"), std::string::npos);
  Demo d;
  d.gain = -1;
  EXPECT_THROW(schema().check(d), ConfigError);
}

TEST(OptionsSchema, DescribesEveryKeyWithItsDefault) {
  const SectionDoc doc = schema().describe();
  ASSERT_EQ(doc.keys.size(), 8u);
  EXPECT_EQ(doc.path, "demo");
  EXPECT_EQ(doc.keys[0].default_value, "1.5");
  EXPECT_EQ(doc.keys[1].type, "integer");
  EXPECT_EQ(doc.keys[1].allowed, "[5, 100]");
  EXPECT_EQ(doc.keys[3].allowed, "fast | slow");
  EXPECT_EQ(doc.keys[5].default_value, "9");  // wait_ms: in the config's unit
  EXPECT_EQ(doc.keys[6].default_value, "[0, 0, 0]");
  EXPECT_EQ(doc.keys[7].key, "inner.radius");
  const std::string md = render_reference({doc});
  EXPECT_NE(md.find("## `demo`"), std::string::npos) << md;
  EXPECT_NE(md.find("| `min_features` | integer |  | `8` | [5, 100] | a count |"), std::string::npos) << md;
  EXPECT_NE(md.find("fast \\| slow"), std::string::npos) << md;
}

TEST(OptionsSchema, NearestKey) {
  EXPECT_EQ(nearest_key("min_featurs", {"min_features", "max_features"}), "min_features");
  EXPECT_EQ(nearest_key("klt_windw_px", {"klt_window_px", "fb_window_px"}), "klt_window_px");
  EXPECT_EQ(nearest_key("zzz", {"min_features"}), "");
}

TEST(Config, RequireKnownKeysSuggestsTheNearest) {
  const Config c = Config::parse("rate_hz: 1\nnoise_mm: 2\n", "sensors.yaml");
  try {
    c.require_known_keys({"rate_hz", "noise_m", "noise_pct"});
    FAIL() << "no error";
  } catch (const ConfigError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("sensors.yaml: key 'noise_mm' is not a known key (line 2); did you mean noise_m?"),
              std::string::npos)
        << what;
  }
}

}  // namespace
}  // namespace nadir
