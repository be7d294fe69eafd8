#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "common/channels.h"
#include "common/log_holes.h"
#include "common/message_guard.h"
#include "nadir/config_t.hpp"
#include "nadir/status_t.hpp"

namespace nadir {
namespace {

void add_status(LogHoleFinder* finder, const std::string& name, int64_t logged_us) {
  status_t s{};
  s.utime = logged_us;
  s.name = name;
  const std::vector<uint8_t> bytes = encode_message(s);
  LogEvent e;
  e.channel = channels::kStatus;
  e.timestamp = logged_us;
  e.data = bytes.data();
  e.size = bytes.size();
  finder->add(e);
}

// Six processes send STATUS at 1 Hz within 0.15 s of each other (0.85 s
// between bursts, more than 5 mean intervals of the channel): no hole. One of
// them stopped for 8 s is one (a 1 Hz stream's hole is longer than 5 of its
// intervals), named after it; an undecodable STATUS is
// nobody's heartbeat.
TEST(LogHoles, StatusIsJudgedPerProcess) {
  const std::vector<std::string> names = {"sim", "sim_mavlink", "mavlink_bridge", "tracker", "vo_solver", "yaw_fusion"};
  LogHoleFinder finder;
  const int64_t t0 = 1767225600000000;
  for (int second = 0; second < 60; ++second) {
    for (size_t k = 0; k < names.size(); ++k) {
      if (names[k] == "vo_solver" && second >= 30 && second < 38) continue;
      add_status(&finder, names[k], t0 + second * 1000000 + static_cast<int64_t>(k) * 30000);
    }
    const uint8_t garbage[12] = {1, 2, 3};
    LogEvent e;
    e.channel = channels::kStatus;
    e.timestamp = t0 + second * 1000000 + 500000;
    e.data = garbage;
    e.size = sizeof garbage;
    if (second % 10 == 0) finder.add(e);
  }
  const std::vector<LogHole> holes = finder.holes();
  ASSERT_EQ(holes.size(), 1u) << format_log_holes(holes);
  EXPECT_EQ(holes[0].channel, "STATUS from vo_solver");
  EXPECT_NEAR(holes[0].seconds(), 9.0, 1e-9);
  EXPECT_EQ(holes[0].expected_messages, 6);  // at the mean interval, which the hole lengthens
}

// VO_GROUND silent for 10 s of featureless ground, beside VO_DELTA every
// frame: not a hole (vo_solver publishes it only for frames it has points
// for). VO_DELTA silent as long is one.
TEST(LogHoles, GroundPointsAreNeverJudged) {
  LogHoleFinder finder;
  const int64_t t0 = 1767225600000000;
  const uint8_t bytes[4] = {0, 0, 0, 0};
  for (int frame = 0; frame < 14 * 60; ++frame) {
    const int64_t t = t0 + frame * 71429;
    const bool featureless = frame >= 14 * 20 && frame < 14 * 30;
    for (const char* channel : {channels::kVoGround, channels::kVoDelta}) {
      if (featureless) continue;
      LogEvent e;
      e.channel = channel;
      e.timestamp = t;
      e.data = bytes;
      e.size = sizeof bytes;
      finder.add(e);
    }
  }
  const std::vector<LogHole> holes = finder.holes();
  ASSERT_EQ(holes.size(), 1u) << format_log_holes(holes);
  EXPECT_EQ(holes[0].channel, channels::kVoDelta);
}

void add_config(LogHoleFinder* finder, const std::string& name, const std::string& yaml, int64_t logged_us) {
  config_t c{};
  c.utime = logged_us;
  c.name = name;
  c.yaml = yaml;
  const std::vector<uint8_t> bytes = encode_message(c);
  LogEvent e;
  e.channel = channels::kConfig;
  e.timestamp = logged_us;
  e.data = bytes.data();
  e.size = bytes.size();
  finder->add(e);
}

void add_image_time(LogHoleFinder* finder, int64_t logged_us) {
  const uint8_t payload[8] = {};
  LogEvent e;
  e.channel = channels::kCameraImage;
  e.timestamp = logged_us;
  e.data = payload;
  e.size = sizeof payload;
  finder->add(e);
}

// 40 photos 2 s apart, with pauses of 15 s after photos 10 and 25 (over 5
// mean intervals, 2.6 s). Without the import's CONFIG those are two holes;
// from a photo import they are one summary line.
void add_photo_times(LogHoleFinder* finder, int64_t t0) {
  int64_t t = t0;
  for (int k = 0; k < 40; ++k) {
    add_image_time(finder, t);
    t += (k == 10 || k == 25) ? 15000000 : 2000000;
  }
}

TEST(LogHoles, PhotoImportIntervalsAreSummarisedNotHoles) {
  const int64_t t0 = 1767225600000000;
  LogHoleFinder live;
  add_photo_times(&live, t0);
  EXPECT_FALSE(live.photo_intervals());
  EXPECT_EQ(live.holes().size(), 2u) << format_log_holes(live.holes());
  EXPECT_TRUE(live.irregular_channels().empty());

  LogHoleFinder photos;
  add_config(&photos, "import", "mode: photos\nsource: survey\n", t0 - 2000);
  add_photo_times(&photos, t0);
  EXPECT_TRUE(photos.photo_intervals());
  EXPECT_TRUE(photos.holes().empty()) << format_log_holes(photos.holes());
  const std::vector<ChannelIntervals> intervals = photos.irregular_channels();
  ASSERT_EQ(intervals.size(), 1u);
  EXPECT_EQ(intervals[0].channel, channels::kCameraImage);
  EXPECT_EQ(intervals[0].intervals, 39);
  EXPECT_NEAR(intervals[0].median_s, 2.0, 1e-9);
  EXPECT_NEAR(intervals[0].max_s, 15.0, 1e-9);
  EXPECT_EQ(intervals[0].gaps, 2);
  EXPECT_NEAR(intervals[0].gap_limit_s, 4.0, 1e-9);  // twice the median
  EXPECT_EQ(format_channel_intervals(intervals),
            "CAMERA_IMAGE: 39 intervals, median 2.0 s, max 15.0 s, 2 gaps over 4.0 s\n");
}

TEST(LogHoles, VideoImportAndOtherConfigsKeepTheirHoles) {
  const int64_t t0 = 1767225600000000;
  LogHoleFinder video;
  add_config(&video, "import", "mode: video\n", t0 - 2000);
  add_config(&video, "tracker", "mode: photos\n", t0 - 1000);  // not the import's
  add_photo_times(&video, t0);
  EXPECT_FALSE(video.photo_intervals());
  EXPECT_EQ(video.holes().size(), 2u);
}

}  // namespace
}  // namespace nadir
