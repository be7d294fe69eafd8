// Log mode end to end through the real binary: same profile + seed gives a
// byte-identical log; messages are in sensor-time order with the real
// drivers' fields; dropped frames leave a trigger without an image.
#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <map>
#include <opencv2/imgproc.hpp>
#include <sstream>
#include <vector>

#include "common/channels.h"
#include "common/bus.h"
#include "common/log_file.h"
#include "nadir/altimeter_t.hpp"
#include "nadir/config_t.hpp"
#include "nadir/ground_truth_t.hpp"
#include "nadir/image_t.hpp"
#include "nadir/ins_t.hpp"
#include "nadir/trigger_t.hpp"
#include "processes/sim/simulator.h"
#include "sim_test_support.h"
#include "tests/common/test_support.h"

namespace nadir::sim {
namespace {

std::string sim_binary() {
  const char* dir = std::getenv("NADIR_BIN_DIR");
  return std::string(dir ? dir : NADIR_BINARY_DIR "/bin") + "/nadir_sim";
}

int run(const std::string& args, const std::string& stderr_file) {
  const std::string cmd = sim_binary() + " " + args + " 2>" + stderr_file;
  return WEXITSTATUS(std::system(cmd.c_str()));
}

std::string slurp(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST(LogMode, SameSeedGivesByteIdenticalLog) {
  nadir::testing::TempDir dir("sim_determinism");
  const std::string common = "--profile demo --duration 1.5 ";
  ASSERT_EQ(run(common + "--seed 5 --out " + dir.file("a.lcmlog"), dir.file("a.err")), 0) << slurp(dir.file("a.err"));
  ASSERT_EQ(run(common + "--seed 5 --out " + dir.file("b.lcmlog"), dir.file("b.err")), 0) << slurp(dir.file("b.err"));
  ASSERT_EQ(run(common + "--seed 6 --out " + dir.file("c.lcmlog"), dir.file("c.err")), 0) << slurp(dir.file("c.err"));
  const std::string a = nadir::testing::file_digest(dir.file("a.lcmlog"));
  EXPECT_EQ(a, nadir::testing::file_digest(dir.file("b.lcmlog")));
  EXPECT_NE(a, nadir::testing::file_digest(dir.file("c.lcmlog")));

  // Contents: CONFIG first, nondecreasing utime = log timestamp, real fields.
  LogReader reader(dir.file("a.lcmlog"));
  LogEvent e;
  std::map<std::string, int> count;
  int64_t last = INT64_MIN;
  int64_t last_frame = -1;
  bool first = true;
  while (reader.next(&e)) {
    int64_t utime = 0;
    ASSERT_TRUE(encoded_utime(e.data, e.size, &utime));
    EXPECT_EQ(e.timestamp, utime);
    EXPECT_GE(utime, last);
    last = utime;
    ++count[e.channel];
    if (first) {
      ASSERT_EQ(e.channel, channels::kConfig);
      config_t c;
      ASSERT_GT(c.decode(e.data, 0, static_cast<int>(e.size)), 0);
      EXPECT_EQ(c.name, "sim");
      EXPECT_EQ(c.utime, kLogEpochUs);
      EXPECT_NE(c.yaml.find("seed: 5"), std::string::npos);
      EXPECT_NE(c.yaml.find("roll_pitch_noise_deg"), std::string::npos);
      EXPECT_NE(c.yaml.find("fx:"), std::string::npos);
      first = false;
    }
    if (e.channel == channels::kCameraImage) {
      image_t img;
      ASSERT_GT(img.decode(e.data, 0, static_cast<int>(e.size)), 0);
      EXPECT_EQ(img.width, 612);
      EXPECT_EQ(img.height, 512);
      EXPECT_EQ(img.stride, 612);
      EXPECT_EQ(img.size, 612 * 512);
      EXPECT_EQ(img.pixel_format, image_t::PIXEL_MONO8);
      EXPECT_EQ(img.time_quality, image_t::TIME_SIMULATED);
      EXPECT_EQ(img.trigger_utime, img.utime);
      EXPECT_GT(img.frame_counter, last_frame);
      EXPECT_EQ(img.trigger_sequence, img.frame_counter);
      last_frame = img.frame_counter;
    }
  }
  EXPECT_EQ(reader.corrupt_records(), 0);
  EXPECT_EQ(count[channels::kConfig], 1);
  EXPECT_EQ(count[channels::kCameraTrigger], 22);  // 14 Hz over [0, 1.5] s
  EXPECT_GE(count[channels::kCameraImage], 20);
  EXPECT_EQ(count[channels::kIns], 151);
  EXPECT_EQ(count[channels::kAltimeter], 16);
  EXPECT_EQ(count[channels::kGroundTruth], 151 + 22);
  EXPECT_NE(slurp(dir.file("a.err")).find("rendered frames/s"), std::string::npos);
}

// The first message of a log.
config_t first_config(const std::string& log) {
  LogReader reader(log);
  LogEvent e;
  config_t c;
  if (reader.next(&e) && e.channel == channels::kConfig) c.decode(e.data, 0, static_cast<int>(e.size));
  return c;
}

// Every payload of one channel, in order.
std::vector<std::string> channel_payloads(const std::string& log, const std::string& channel) {
  LogReader reader(log);
  LogEvent e;
  std::vector<std::string> out;
  while (reader.next(&e))
    if (e.channel == channel) out.emplace_back(reinterpret_cast<const char*>(e.data), e.size);
  return out;
}

// --relief-scale: the same flight (INS, triggers) over other ground, and
// CONFIG says what was flown and that it was overridden.
TEST(LogMode, ReliefScaleOverrideFliesTheSameFlightOverOtherGround) {
  nadir::testing::TempDir dir("sim_relief_override");
  const std::string common = "--profile rough_120 --duration 0.5 --seed 3 ";
  ASSERT_EQ(run(common + "--out " + dir.file("rough.lcmlog"), dir.file("rough.err")), 0) << slurp(dir.file("rough.err"));
  ASSERT_EQ(run(common + "--relief-scale 0 --out " + dir.file("flat.lcmlog"), dir.file("flat.err")), 0)
      << slurp(dir.file("flat.err"));
  const config_t rough = first_config(dir.file("rough.lcmlog")), flat = first_config(dir.file("flat.lcmlog"));
  EXPECT_NE(rough.yaml.find("relief_scale: 3.0"), std::string::npos) << rough.yaml;
  EXPECT_EQ(rough.yaml.find("profile_overrides"), std::string::npos) << rough.yaml;
  EXPECT_NE(flat.yaml.find("relief_scale: 0"), std::string::npos) << flat.yaml;
  EXPECT_NE(flat.yaml.find("profile_overrides:\n  - terrain.relief_scale"), std::string::npos) << flat.yaml;
  for (const std::string& channel : {std::string(channels::kIns), std::string(channels::kCameraTrigger)}) {
    const auto a = channel_payloads(dir.file("rough.lcmlog"), channel);
    EXPECT_FALSE(a.empty()) << channel;
    EXPECT_TRUE(a == channel_payloads(dir.file("flat.lcmlog"), channel)) << channel;
  }
  // The images are not: relief is there.
  EXPECT_FALSE(channel_payloads(dir.file("rough.lcmlog"), channels::kCameraImage) ==
               channel_payloads(dir.file("flat.lcmlog"), channels::kCameraImage));
  EXPECT_EQ(run(common + "--relief-scale 3.5 --out " + dir.file("bad.lcmlog"), dir.file("bad.err")), 2);
  EXPECT_NE(slurp(dir.file("bad.err")).find("terrain.relief_scale"), std::string::npos) << slurp(dir.file("bad.err"));
}

TEST(LogMode, BadProfileIsRejectedNamingTheKey) {
  nadir::testing::TempDir dir("sim_bad_profile");
  {
    std::ofstream out(dir.file("bad.yaml"));
    out << "name: bad\ndistance_m: 2000\nspeed_mps: 20\naltitude_agl_m: 150\n"
           "legs:\n  - {type: straight}\n  - {type: turn, angle_deg: 90, bank_deg: 89}\n";
  }
  EXPECT_EQ(run("--profile " + dir.file("bad.yaml") + " --seed 1 --out " + dir.file("x.lcmlog"), dir.file("err")), 2);
  const std::string err = slurp(dir.file("err"));
  EXPECT_NE(err.find("legs[1].bank_deg"), std::string::npos) << err;
  EXPECT_NE(err.find("bad.yaml"), std::string::npos) << err;
  EXPECT_EQ(run("--help", dir.file("help")), 0);
}

TEST(Frames, DroppedFrameLeavesTriggerWithoutImageAndTruthIsAtTrueTime) {
  SensorOptions sensors = testing::sensor_set("standard");
  sensors.camera.frame_drop_probability = 0.3;
  sensors.camera.trigger_jitter_us = 500.0;
  SimulatorOptions options;
  options.seed = 8;
  options.duration_s = 1.2;
  Simulator sim(testing::profile("test2"), testing::default_camera(), sensors, options);
  std::map<int64_t, trigger_t> triggers;
  std::map<int64_t, image_t> images;
  std::vector<ground_truth_t> frame_truth;
  SimEvent e;
  while (sim.next(&e)) {
    if (e.channel == channels::kCameraTrigger) {
      trigger_t t;
      t.decode(e.data.data(), 0, static_cast<int>(e.data.size()));
      triggers[t.sequence] = t;
    } else if (e.channel == channels::kCameraImage) {
      image_t i;
      i.decode(e.data.data(), 0, static_cast<int>(e.data.size()));
      images[i.trigger_sequence] = i;
    } else if (e.channel == channels::kGroundTruth) {
      ground_truth_t g;
      g.decode(e.data.data(), 0, static_cast<int>(e.data.size()));
      if (g.kind == ground_truth_t::KIND_FRAME) frame_truth.push_back(g);
    }
  }
  ASSERT_EQ(triggers.size(), 17u);
  ASSERT_EQ(frame_truth.size(), triggers.size());
  EXPECT_LT(images.size(), triggers.size());
  EXPECT_GT(images.size(), 4u);
  EXPECT_EQ(static_cast<int64_t>(triggers.size() - images.size()), sim.counts().dropped_frames);
  for (const auto& [seq, img] : images) {
    ASSERT_TRUE(triggers.count(seq));
    EXPECT_EQ(img.utime, triggers[seq].utime);
  }
  for (size_t k = 0; k < frame_truth.size(); ++k) {
    // Truth at the exact exposure time k / 14 s; the trigger is that plus jitter.
    EXPECT_EQ(frame_truth[k].utime, kLogEpochUs + std::llround(k * 1e6 / 14.0));
    EXPECT_LT(std::llabs(triggers[static_cast<int64_t>(k)].utime - frame_truth[k].utime), 5 * 500);
    EXPECT_NEAR(frame_truth[k].height_agl_m, -frame_truth[k].position_ned[2] - frame_truth[k].terrain_height_m, 1e-9);
  }
}

// The texture gives trackable corners at the paper's heights, spread over the image.
TEST(Texture, GivesCornersAcrossTheImageAt150And300m) {
  for (const char* name : {"test1", "test2"}) {
    SimulatorOptions options;
    options.seed = 2;
    Simulator sim(testing::profile(name), testing::default_camera(), testing::sensor_set("standard"), options);
    std::vector<uint8_t> image;
    const TruthState s = sim.trajectory().at(20.0);
    sim.renderer().render(s.position_ned, s.world_from_body() * sim.camera().body_from_camera, 1, &image);
    const cv::Mat view(512, 612, CV_8UC1, image.data());
    std::vector<cv::Point2f> corners;
    cv::goodFeaturesToTrack(view, corners, 400, 0.01, 10, cv::noArray(), 3, true, 0.04);
    EXPECT_GT(corners.size(), 250u) << name;
    int cells[4][4] = {};
    for (const auto& c : corners) ++cells[std::min(3, static_cast<int>(c.y / 128))][std::min(3, static_cast<int>(c.x / 153))];
    int populated = 0;
    for (auto& row : cells)
      for (int c : row) populated += c >= 5;
    EXPECT_GE(populated, 14) << name;
  }
}

}  // namespace
}  // namespace nadir::sim
