// FoxgloveTranslator: the views of POSE (frames, covariance, geodetic
// origin), image decimation, and nothing decoded for unwanted topics.
#include "processes/foxglove/foxglove_translator.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>

#include "common/channels.h"
#include "common/message_guard.h"
#include "nadir/image_t.hpp"
#include "nadir/ins_t.hpp"
#include "nadir/pose_t.hpp"
#include "processes/foxglove/foxglove_options.h"
#include "processes/foxglove/foxglove_schemas.h"

namespace nadir {
namespace {

using nlohmann::json;

std::map<std::string, json> translate(FoxgloveTranslator& t, const std::string& channel,
                                      const std::vector<uint8_t>& bytes) {
  std::vector<FoxgloveMessage> out;
  std::string reason;
  EXPECT_TRUE(t.translate(channel, bytes.data(), bytes.size(), {}, &out, &reason)) << reason;
  std::map<std::string, json> by_topic;
  for (const auto& m : out) by_topic[t.topics()[m.topic].name] = json::parse(m.json);
  return by_topic;
}

pose_t pose_at(double north, double east, double down, double yaw) {
  pose_t p{};
  p.utime = 1'500'000;
  p.position_ned[0] = north;
  p.position_ned[1] = east;
  p.position_ned[2] = down;
  p.yaw = yaw;
  p.position_covariance[0][0] = 4.0;   // north
  p.position_covariance[1][1] = 9.0;   // east
  p.position_covariance[2][2] = 1.0;   // down
  p.position_covariance[0][1] = p.position_covariance[1][0] = 0.5;
  p.horizontal_protection_level_m = 12.0;
  p.flags = pose_t::FLAG_COASTING;
  return p;
}

TEST(FoxgloveTranslator, PoseViewsAreEastNorthUpWithTheCovarianceSwapped) {
  FoxgloveTranslatorOptions o;
  o.origin_from_ins = false;
  o.origin = {47.0, 8.0, 500.0};
  FoxgloveTranslator t(o);
  auto v = translate(t, channels::kPose, encode_message(pose_at(100.0, 50.0, -20.0, M_PI / 2)));
  ASSERT_EQ(v.size(), 4u);
  EXPECT_EQ(v["POSE/pose"]["frame_id"], "map");
  EXPECT_DOUBLE_EQ(v["POSE/pose"]["pose"]["position"]["x"].get<double>(), 50.0);   // east
  EXPECT_DOUBLE_EQ(v["POSE/pose"]["pose"]["position"]["y"].get<double>(), 100.0);  // north
  EXPECT_DOUBLE_EQ(v["POSE/pose"]["pose"]["position"]["z"].get<double>(), 20.0);   // up
  // Heading east (yaw 90 deg): the body's forward axis is ENU +x: a rotation of 0 about up.
  const json q = v["POSE/tf"]["rotation"];
  EXPECT_NEAR(std::abs(q["w"].get<double>()), 1.0, 1e-12);
  EXPECT_EQ(v["POSE/tf"]["child_frame_id"], "base_link");
  const json fix = v["POSE/fix"];
  EXPECT_GT(fix["latitude"].get<double>(), 47.0);
  EXPECT_GT(fix["longitude"].get<double>(), 8.0);
  EXPECT_NEAR(fix["altitude"].get<double>(), 520.0, 1e-9);
  const std::vector<double> cov = fix["position_covariance"];
  EXPECT_DOUBLE_EQ(cov[0], 9.0);  // east-east
  EXPECT_DOUBLE_EQ(cov[4], 4.0);  // north-north
  EXPECT_DOUBLE_EQ(cov[8], 1.0);  // up-up
  EXPECT_DOUBLE_EQ(cov[1], 0.5);
  EXPECT_EQ(fix["position_covariance_type"], 3);
  EXPECT_DOUBLE_EQ(v["POSE"]["sigma_east_m"].get<double>(), 3.0);
  EXPECT_EQ(v["POSE"]["flag_coasting"], 1);
  EXPECT_EQ(v["POSE"]["timestamp"]["sec"], 1);
  EXPECT_EQ(v["POSE"]["timestamp"]["nsec"], 500'000'000);
}

TEST(FoxgloveTranslator, HeadingNorthPointsTheBodyAlongEnuY) {
  FoxgloveTranslator t(FoxgloveTranslatorOptions{});
  auto v = translate(t, channels::kPose, encode_message(pose_at(0, 0, 0, 0.0)));
  const json q = v["POSE/pose"]["pose"]["orientation"];
  // 90 deg about up: (0, 0, sin 45, cos 45).
  EXPECT_NEAR(q["z"].get<double>(), std::sqrt(0.5), 1e-12);
  EXPECT_NEAR(q["w"].get<double>(), std::sqrt(0.5), 1e-12);
}

TEST(FoxgloveTranslator, OriginFromTheInsAtTheFirstPose) {
  FoxgloveTranslator t(FoxgloveTranslatorOptions{});  // origin_from_ins
  EXPECT_EQ(translate(t, channels::kPose, encode_message(pose_at(0, 0, 0, 0))).count("POSE/fix"), 0u);
  ins_t ins{};
  ins.utime = 1;
  ins.latitude_deg = 40.5;
  ins.longitude_deg = -80.0;
  ins.height_m = 300.0;
  translate(t, channels::kIns, encode_message(ins));
  auto v = translate(t, channels::kPose, encode_message(pose_at(0, 0, 0, 0)));
  ASSERT_EQ(v.count("POSE/fix"), 1u);
  EXPECT_DOUBLE_EQ(v["POSE/fix"]["latitude"].get<double>(), 40.5);
  EXPECT_DOUBLE_EQ(v["POSE/fix"]["longitude"].get<double>(), -80.0);
}

TEST(FoxgloveTranslator, ImagesAreDecimatedToTheConfiguredRate) {
  FoxgloveTranslatorOptions o;
  o.image_rate_hz = 2.0;
  FoxgloveTranslator t(o);
  image_t img{};
  img.width = 4;
  img.height = 2;
  img.stride = 4;
  img.pixel_format = image_t::PIXEL_MONO8;
  img.size = 8;
  img.data = {0, 1, 2, 3, 4, 5, 6, 7};
  int forwarded = 0;
  for (int i = 0; i < 140; ++i) {  // 10 s at 14 Hz
    img.utime = 1'000'000 + static_cast<int64_t>(i * 1e6 / 14.0);
    const auto v = translate(t, channels::kCameraImage, encode_message(img));
    if (v.count("CAMERA_IMAGE")) {
      ++forwarded;
      EXPECT_EQ(v.at("CAMERA_IMAGE")["data"], "AAECAwQFBgc=");  // base64 of 0..7
      EXPECT_EQ(v.at("CAMERA_IMAGE")["encoding"], "mono8");
    }
  }
  EXPECT_EQ(forwarded, 20);
  EXPECT_EQ(t.images_decimated(), 120);
}

TEST(FoxgloveTranslator, NothingIsDecodedForUnwantedTopicsAndBadBytesAreReported) {
  FoxgloveTranslator t(FoxgloveTranslatorOptions{});
  std::vector<FoxgloveMessage> out;
  std::string reason;
  const uint8_t garbage[5] = {1, 2, 3, 4, 5};
  EXPECT_TRUE(t.translate(channels::kVoDelta, garbage, sizeof garbage, [](int) { return false; }, &out, &reason));
  EXPECT_TRUE(out.empty());
  EXPECT_FALSE(t.translate(channels::kVoDelta, garbage, sizeof garbage, {}, &out, &reason));
  EXPECT_FALSE(reason.empty());
  EXPECT_TRUE(t.translate("SOMETHING_ELSE", garbage, sizeof garbage, {}, &out, &reason));
  EXPECT_TRUE(out.empty());
}

TEST(FoxgloveSchemas, EveryTopicHasAValidJsonSchema) {
  FoxgloveTranslator t(FoxgloveTranslatorOptions{});
  for (const FoxgloveTopic& topic : t.topics()) {
    const json s = json::parse(foxglove_schemas::schema_text(topic.schema_name));
    EXPECT_EQ(s["type"], "object") << topic.name;
    EXPECT_EQ(s["title"], topic.schema_name) << topic.name;
  }
  EXPECT_THROW(foxglove_schemas::schema_text("foxglove.Nope"), std::invalid_argument);
}

TEST(FoxgloveOptions, BadConfigNamesTheKey) {
  const Config c = Config::parse("foxglove:\n  port: 70000\n", "test.yaml");
  try {
    FoxgloveOptions::from_config(c);
    FAIL() << "no error";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("foxglove.port"), std::string::npos) << e.what();
  }
  EXPECT_THROW(FoxgloveOptions::from_config(Config::parse("foxglove:\n  prot: 1\n", "t")), ConfigError);
}

}  // namespace
}  // namespace nadir
