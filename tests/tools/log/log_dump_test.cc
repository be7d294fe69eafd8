#include <gtest/gtest.h>

#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "common/channels.h"
#include "common/log_file.h"
#include "common/message_guard.h"
#include "nadir/ground_points_t.hpp"
#include "nadir/ins_t.hpp"
#include "nadir/tracks_t.hpp"
#include "nadir/trigger_t.hpp"
#include "nadir/vo_delta_t.hpp"
#include "tests/common/test_support.h"
#include "tools/log/log_dump.h"

namespace nadir {
namespace {

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

tracks_t two_tracks(int64_t utime) {
  tracks_t t{};
  t.utime = utime;
  t.prev_utime = utime - 5000000;
  t.frame_counter = 7;
  t.width = 600;
  t.height = 450;
  t.num_tracks = 2;
  t.track_id = {41, 42};
  t.age = {3, 1};
  t.prev_px = {{100.5f, 200.25f}, {300.0f, 50.0f}};
  t.curr_px = {{110.5f, 190.25f}, {290.0f, 60.0f}};
  t.prev_norm = {{-0.125, 0.0625}, {0.5, -0.25}};
  t.curr_norm = {{-0.1, 0.05}, {0.45, -0.2}};
  return t;
}

ins_t ins_at(int64_t utime, double lat) {
  ins_t m{};
  m.utime = utime;
  m.roll = 0.01;
  m.pitch = -0.02;
  m.yaw = 1.5;
  m.latitude_deg = lat;
  m.longitude_deg = -83.312345678912;
  m.height_m = 271.25;
  return m;
}

struct SampleLog {
  std::string path;
  std::vector<uint64_t> offsets;  // byte offset of each record, in write order
};

// TRACKS (2 tracks), VO_DELTA, three INS, a VO_DELTA whose payload is cut short,
// a CAMERA_TRIGGER (a type dump does not support) and a VO_GROUND of two points.
SampleLog write_sample(const testing::TempDir& dir) {
  SampleLog log{dir.file("sample.lcmlog"), {}};
  LogWriter writer(log.path);
  uint64_t offset = 0;
  auto put = [&](const std::string& channel, const std::vector<uint8_t>& bytes) {
    log.offsets.push_back(offset);
    writer.write(1000 + static_cast<int64_t>(log.offsets.size()), channel, bytes.data(), bytes.size());
    offset += 28 + channel.size() + bytes.size();
  };
  put(channels::kTracks, encode_message(two_tracks(10000000)));
  vo_delta_t d{};
  d.utime = 10000000;
  d.prev_utime = 5000000;
  d.dx = 31.5;
  d.dy = -2.25;
  d.dyaw = 0.1;
  d.covariance[0][0] = 4.0;
  d.covariance[5][5] = 0.01;
  d.altitude_m = 70.0;
  d.inliers = 55;
  d.variant = "level_ground";
  put(channels::kVoDelta, encode_message(d));
  for (int i = 0; i < 3; ++i) put(channels::kIns, encode_message(ins_at(5000000 + i * 10000, 41.031234567891 + i)));
  std::vector<uint8_t> cut = encode_message(d);
  cut.resize(cut.size() - 5);
  put(channels::kVoDelta, cut);
  trigger_t trig{};
  trig.utime = 1;
  put(channels::kCameraTrigger, encode_message(trig));
  ground_points_t g{};
  g.utime = 10000000;
  g.num_points = 2;
  g.track_id = {41, 43};
  g.position_m = {{12.5f, -3.25f, 150.5f}, {-40.0f, 8.0f, 149.75f}};
  g.depth_sigma_m = {0.5f, 1.25f};
  put(channels::kVoGround, encode_message(g));
  writer.flush();
  return log;
}

struct Dumped {
  DumpStats stats;
  std::vector<std::string> lines;
};

// Dumps one channel of the sample log (written to a fresh folder).
Dumped dump_sample(const std::string& channel, DumpFormat format) {
  testing::TempDir dir("log_dump");
  const SampleLog log = write_sample(dir);
  std::ostringstream out;
  Dumped d;
  d.stats = dump_channel(log.path, channel, format, out);
  d.lines = lines_of(out.str());
  return d;
}

TEST(LogDump, GroundPointsAreOneCsvRowPerPoint) {
  const Dumped d = dump_sample(channels::kVoGround, DumpFormat::kCsv);
  ASSERT_EQ(d.lines.size(), 3u);
  EXPECT_EQ(d.lines[0], "utime,track_id,x_m,y_m,z_m,depth_sigma_m");
  EXPECT_EQ(d.lines[1], "10000000,41,12.5,-3.25,150.5,0.5");
  EXPECT_EQ(d.lines[2], "10000000,43,-40,8,149.75,1.25");
}

TEST(LogDump, TracksAreOneCsvRowPerTrack) {
  const Dumped d = dump_sample(channels::kTracks, DumpFormat::kCsv);
  const DumpStats& s = d.stats;
  const auto& lines = d.lines;
  ASSERT_EQ(lines.size(), 3u);
  EXPECT_EQ(lines[0], "utime,prev_utime,frame_counter,flags,track_id,age,prev_px_x,prev_px_y,curr_px_x,curr_px_y,"
                      "prev_norm_x,prev_norm_y,curr_norm_x,curr_norm_y");
  EXPECT_EQ(lines[1], "10000000,5000000,7,0,41,3,100.5,200.25,110.5,190.25,-0.125,0.0625,-0.1,0.05");
  EXPECT_EQ(lines[2], "10000000,5000000,7,0,42,1,300,50,290,60,0.5,-0.25,0.45,-0.2");
  EXPECT_EQ(s.messages, 1);
  EXPECT_EQ(s.rows, 2);
  EXPECT_EQ(s.type, "nadir.tracks_t");
  EXPECT_EQ(s.corrupt_records, 0);
}

TEST(LogDump, VoDeltaScalarsAndUndecodableMessagesAreCounted) {
  const Dumped d = dump_sample(channels::kVoDelta, DumpFormat::kCsv);
  const DumpStats& s = d.stats;
  const auto& lines = d.lines;
  ASSERT_EQ(lines.size(), 2u);  // header + the good message; the cut one is skipped
  EXPECT_EQ(lines[0], "utime,prev_utime,dx,dy,dz,dyaw,ground_roll,ground_pitch,var_dx,var_dy,var_dz,var_dyaw,"
                      "var_ground_roll,var_ground_pitch,altitude_m,inliers,outliers,residual_rms_px,iterations,"
                      "quality,variant");
  EXPECT_EQ(lines[1], "10000000,5000000,31.5,-2.25,0,0.1,0,0,4,0,0,0,0,0.01,70,55,0,0,0,0,level_ground");
  EXPECT_EQ(s.messages, 1);
  EXPECT_EQ(s.undecodable, 1);
  EXPECT_FALSE(s.first_decode_error.empty());
}

TEST(LogDump, InsAsJsonLinesKeepsFullPrecision) {
  const Dumped d = dump_sample(channels::kIns, DumpFormat::kJsonLines);
  const DumpStats& s = d.stats;
  const auto& lines = d.lines;
  ASSERT_EQ(lines.size(), 3u);  // no header in JSON lines
  EXPECT_EQ(lines[0], "{\"utime\":5000000,\"device_utime\":0,\"roll\":0.01,\"pitch\":-0.02,\"yaw\":1.5,"
                      "\"latitude_deg\":41.031234567891,\"longitude_deg\":-83.312345678912,\"height_m\":271.25,"
                      "\"velocity_n\":0,\"velocity_e\":0,\"velocity_d\":0,\"ins_status\":0,\"flags\":0}");
  EXPECT_NE(lines[2].find("\"latitude_deg\":43.031234567891"), std::string::npos);
  EXPECT_EQ(s.rows, 3);
}

TEST(LogDump, CorruptRecordIsSkippedAndCounted) {
  testing::TempDir dir("log_dump");
  const SampleLog log = write_sample(dir);
  auto bytes = testing::read_file_bytes(log.path);
  bytes[log.offsets[3]] ^= 0xFF;  // break the sync word of the second INS record
  testing::write_file_bytes(dir.file("bad.lcmlog"), bytes);
  std::ostringstream out;
  const DumpStats s = dump_channel(dir.file("bad.lcmlog"), channels::kIns, DumpFormat::kCsv, out);
  const auto lines = lines_of(out.str());
  ASSERT_EQ(lines.size(), 3u);  // header + INS 1 and 3
  EXPECT_EQ(lines[1].rfind("5000000,", 0), 0u);
  EXPECT_EQ(lines[2].rfind("5020000,", 0), 0u);
  EXPECT_EQ(s.corrupt_records, 1);
  EXPECT_NE(s.damage_report.find("byte " + std::to_string(log.offsets[3])), std::string::npos);
}

void expect_error(const std::string& path, const std::string& channel, const std::vector<std::string>& parts) {
  std::ostringstream out;
  try {
    dump_channel(path, channel, DumpFormat::kCsv, out);
    FAIL() << "no error for " << channel;
  } catch (const std::runtime_error& e) {
    const std::string what = e.what();
    for (const std::string& p : parts) EXPECT_NE(what.find(p), std::string::npos) << what << " lacks " << p;
  }
  EXPECT_TRUE(out.str().empty());
}

TEST(LogDump, ErrorsNameTheFileAndTheChannel) {
  testing::TempDir dir("log_dump");
  const SampleLog log = write_sample(dir);
  expect_error(log.path, "POSE", {log.path, "channel POSE", "no messages", "TRACKS"});
  expect_error(log.path, channels::kCameraTrigger,
               {log.path, "channel CAMERA_TRIGGER", "nadir.trigger_t", "nadir.vo_delta_t"});
  expect_error(dir.file("missing.lcmlog"), "TRACKS", {dir.file("missing.lcmlog"), "channel TRACKS"});
}

}  // namespace
}  // namespace nadir
