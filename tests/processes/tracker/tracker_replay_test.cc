// The tracker in lockstep replay (common/replay.h): a log of images, some
// bad and one late, replayed twice gives byte-identical output logs.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "common/channels.h"
#include "common/log_file.h"
#include "common/replay.h"
#include "nadir/tracks_t.hpp"
#include "processes/tracker/tracker_node.h"
#include "synthetic_scene.h"

namespace nadir {
namespace {

namespace fs = std::filesystem;
using testing::make_image_msg;
using testing::SyntheticScene;
using testing::ViewPose;

std::vector<char> file_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

class TrackerReplay : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::path(NADIR_BINARY_DIR) / "test_tmp" / ("tracker_replay_" + std::to_string(getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  fs::path dir_;
};

TEST_F(TrackerReplay, ReplayingTwiceGivesIdenticalLogs) {
  const SyntheticScene scene(cv::Size(1200, 1200), 3);
  const int64_t start = 1700000000000000, period = 71429;
  {
    LogWriter writer(path("in.lcmlog"));
    auto write = [&](const image_t& msg) {
      std::vector<uint8_t> bytes(static_cast<size_t>(msg.getEncodedSize()));
      msg.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
      writer.write(msg.utime + 3000, channels::kCameraImage, bytes.data(), bytes.size());
    };
    for (int k = 0; k < 10; ++k) {
      const cv::Mat pixels = k == 4 ? cv::Mat(512, 612, CV_8UC1, cv::Scalar(0))
                                    : scene.render(ViewPose{{600 + 3.0 * k, 600 + 1.0 * k}, 0.002 * k},
                                                   cv::Size(612, 512), 1.0, k);
      write(make_image_msg(pixels, start + k * period, k));
      if (k == 6) write(make_image_msg(pixels, start + 2 * period, 2));  // a late duplicate of frame 2
    }
    writer.flush();
  }

  NodeRegistry registry;
  register_tracker_node(registry);
  auto replay = [&](const std::string& out) {
    ReplayOptions options;
    options.in_path = path("in.lcmlog");
    options.out_path = path(out);
    options.nodes = {"tracker"};
    options.config_path = NADIR_SOURCE_DIR "/config/default.yaml";
    return run_replay(options, registry);
  };
  const ReplaySummary first = replay("out1.lcmlog");
  const ReplaySummary second = replay("out2.lcmlog");
  EXPECT_EQ(file_bytes(path("out1.lcmlog")), file_bytes(path("out2.lcmlog")));
  EXPECT_EQ(first.published_per_channel.at(channels::kTracks), 10);
  EXPECT_EQ(second.published_per_channel.at(channels::kTracks), 10);
  ASSERT_EQ(first.final_status.size(), 1u);
  EXPECT_EQ(first.final_status[0].received, 11);
  EXPECT_EQ(first.final_status[0].dropped, 1);

  // The output log holds the tracks, in order, with the black frame flagged.
  LogReader reader(path("out1.lcmlog"));
  LogEvent event;
  std::vector<tracks_t> tracks;
  while (reader.next(&event)) {
    if (event.channel != channels::kTracks) continue;
    tracks_t msg;
    ASSERT_EQ(msg.decode(event.data, 0, static_cast<int>(event.size)), static_cast<int>(event.size));
    tracks.push_back(msg);
  }
  ASSERT_EQ(tracks.size(), 10u);
  EXPECT_TRUE(tracks[4].flags & tracks_t::FLAG_BAD_IMAGE);
  EXPECT_EQ(tracks[5].flags, tracks_t::FLAG_FRAME_GAP);
  EXPECT_EQ(tracks[5].prev_utime, start + 3 * period);
  EXPECT_GT(tracks[9].num_tracks, 300);
}

}  // namespace
}  // namespace nadir
