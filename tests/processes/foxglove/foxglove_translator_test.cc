// FoxgloveTranslator: the views of POSE (frames, covariance, geodetic
// origin), VO_GROUND's points placed by POSE's level frame, image decimation,
// and nothing decoded for unwanted topics.
#include "processes/foxglove/foxglove_translator.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <Eigen/Geometry>

#include <cmath>
#include <cstring>

#include "common/channels.h"
#include "common/message_guard.h"
#include "nadir/ground_points_t.hpp"
#include "nadir/ground_truth_t.hpp"
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
  ASSERT_EQ(v.size(), 5u);
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
  // The INS before the first POSE (1.5 s), then the first POSE: the origin
  // waits for the INS sample after it.
  ins_t ins{};
  ins.utime = 1'490'000;
  ins.latitude_deg = 40.5;
  ins.longitude_deg = -80.0;
  ins.height_m = 300.0;
  translate(t, channels::kIns, encode_message(ins));
  EXPECT_EQ(translate(t, channels::kPose, encode_message(pose_at(0, 0, 0, 0))).count("POSE/fix"), 0u);
  ins.utime = 1'510'000;
  ins.latitude_deg = 40.5002;  // north at ~2.2 km/s between the two samples: the pose lies half-way
  translate(t, channels::kIns, encode_message(ins));
  auto v = translate(t, channels::kPose, encode_message(pose_at(0, 0, 0, 0)));
  ASSERT_EQ(v.count("POSE/fix"), 1u);
  EXPECT_NEAR(v["POSE/fix"]["latitude"].get<double>(), 40.5001, 1e-9);
  EXPECT_NEAR(v["POSE/fix"]["longitude"].get<double>(), -80.0, 1e-9);
}

std::vector<uint8_t> base64_decode(const std::string& text) {
  const std::string table = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::vector<uint8_t> out;
  uint32_t bits = 0;
  int count = 0;
  for (char c : text) {
    if (c == '=') break;
    bits = (bits << 6) | static_cast<uint32_t>(table.find(c));
    count += 6;
    if (count >= 8) {
      count -= 8;
      out.push_back(static_cast<uint8_t>((bits >> count) & 0xff));
    }
  }
  return out;
}

Eigen::Vector3d vec(const json& j) { return {j["x"].get<double>(), j["y"].get<double>(), j["z"].get<double>()}; }
Eigen::Quaterniond rotation(const json& j) {
  return Eigen::Quaterniond(j["w"].get<double>(), j["x"].get<double>(), j["y"].get<double>(), j["z"].get<double>());
}

TEST(FoxgloveTranslator, GroundPointsLandWhereThePoseLevelFramePutsThem) {
  FoxgloveTranslator t(FoxgloveTranslatorOptions{});
  const double yaw = 30.0 * M_PI / 180.0;
  pose_t pose = pose_at(100.0, 50.0, -20.0, yaw);
  pose.roll = 0.1;  // the level frame ignores roll and pitch
  pose.pitch = -0.05;
  ground_points_t g{};
  g.utime = pose.utime;
  g.num_points = 2;
  g.track_id = {7, 9};
  g.position_m = {{10.0f, 5.0f, 150.0f}, {-40.0f, -12.5f, 149.25f}};  // forward, right, down
  g.depth_sigma_m = {0.25f, 1.5f};
  auto p = translate(t, channels::kPose, encode_message(pose));
  auto v = translate(t, channels::kVoGround, encode_message(g));
  ASSERT_EQ(v.count("VO_GROUND"), 1u);
  const json cloud = v["VO_GROUND"];
  const json level = p["POSE/level_tf"];
  EXPECT_EQ(cloud["frame_id"], level["child_frame_id"]);
  EXPECT_EQ(level["child_frame_id"], "base_link_level");
  EXPECT_EQ(cloud["timestamp"], level["timestamp"]);
  ASSERT_EQ(cloud["point_stride"], 16);
  ASSERT_EQ(cloud["fields"].size(), 4u);
  EXPECT_EQ(cloud["fields"][3]["name"], "depth_sigma");
  EXPECT_EQ(cloud["fields"][3]["offset"], 12);
  const std::vector<uint8_t> bytes = base64_decode(cloud["data"]);
  ASSERT_EQ(bytes.size(), 32u);
  for (int i = 0; i < 2; ++i) {
    float f[4];
    std::memcpy(f, bytes.data() + 16 * i, sizeof f);
    // The point in map (ENU) through the transform, against the NED sum by hand.
    const Eigen::Vector3d enu = rotation(level["rotation"]) * Eigen::Vector3d(f[0], f[1], f[2]) + vec(level["translation"]);
    const double x = g.position_m[i][0], y = g.position_m[i][1], z = g.position_m[i][2];
    const double north = 100.0 + x * std::cos(yaw) - y * std::sin(yaw);
    const double east = 50.0 + x * std::sin(yaw) + y * std::cos(yaw);
    EXPECT_NEAR(enu.x(), east, 1e-9) << i;
    EXPECT_NEAR(enu.y(), north, 1e-9) << i;
    EXPECT_NEAR(enu.z(), -(-20.0 + z), 1e-9) << i;
    EXPECT_EQ(f[3], g.depth_sigma_m[i]);
  }
}

TEST(FoxgloveTranslator, TruthStartsAtTheFirstPoseWhereTheTruthWasThen) {
  FoxgloveTranslator t(FoxgloveTranslatorOptions{});
  auto truth = [](int64_t utime, double north) {
    ground_truth_t g{};
    g.utime = utime;
    g.kind = ground_truth_t::KIND_INS;
    g.position_ned[0] = north;
    g.position_ned[2] = -200.0;  // the simulator's origin is on the ground below the start
    return encode_message(g);
  };
  auto before = translate(t, channels::kGroundTruth, truth(1'000'000, 0.0));
  EXPECT_EQ(before.count("GROUND_TRUTH"), 1u);  // the plain view as it is
  EXPECT_EQ(before.count("GROUND_TRUTH/pose"), 0u);
  translate(t, channels::kGroundTruth, truth(1'100'000, 2.0));
  pose_t first = pose_at(0.0, 0.0, 0.0, 0.0);  // POSE's origin: the first frame
  first.utime = 1'050'000;
  translate(t, channels::kPose, encode_message(first));
  auto v = translate(t, channels::kGroundTruth, truth(1'200'000, 4.0));
  ASSERT_EQ(v.count("GROUND_TRUTH/pose"), 1u);
  const json position = v["GROUND_TRUTH/pose"]["pose"]["position"];
  EXPECT_NEAR(position["y"].get<double>(), 3.0, 1e-12);  // north: 4 less 1 (the truth at the first POSE)
  EXPECT_NEAR(position["x"].get<double>(), 0.0, 1e-12);
  EXPECT_NEAR(position["z"].get<double>(), 0.0, 1e-12);  // at the height of POSE's origin, not 200 m up
  EXPECT_EQ(v["GROUND_TRUTH"]["down_m"], -200.0);
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
