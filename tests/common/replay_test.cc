#include <gtest/gtest.h>

#include <cmath>

#include "common/channels.h"
#include "common/log_file.h"
#include "common/replay.h"
#include "nadir/config_t.hpp"
#include "nadir/ins_t.hpp"
#include "nadir/pose_t.hpp"
#include "nadir/status_t.hpp"
#include "tests/common/test_nodes.h"
#include "tests/common/test_support.h"

namespace nadir {
namespace {

void write_input_log(const std::string& path, int n) {
  LogWriter writer(path);
  for (int i = 0; i < n; ++i) {
    ins_t msg{};
    msg.utime = 1700000000000000 + i * 10000;
    msg.yaw = 0.001 * i * i;
    msg.velocity_ned[0] = 20.0 + std::sin(i * 0.1);
    msg.velocity_ned[1] = 3.0;
    std::vector<uint8_t> buf(msg.getEncodedSize());
    msg.encode(buf.data(), 0, static_cast<int>(buf.size()));
    writer.write(msg.utime, channels::kIns, buf.data(), buf.size());
    if (i % 50 == 7) {  // something no node listens to must pass through
      writer.write(msg.utime, "UNRELATED", buf.data(), buf.size());
    }
  }
  writer.flush();
}

std::string write_config(const testing::TempDir& dir, double scale) {
  const std::string path = dir.file("config.yaml");
  const std::string text = "ins_delta:\n  scale: " + std::to_string(scale) + "\n";
  testing::write_file_bytes(path, std::vector<uint8_t>(text.begin(), text.end()));
  return path;
}

ReplayOptions options_for(const testing::TempDir& dir, const std::string& out) {
  ReplayOptions options;
  options.in_path = dir.file("in.lcmlog");
  options.out_path = dir.file(out);
  options.nodes = {"ins_delta", "delta_integrator"};
  options.config_path = dir.file("config.yaml");
  return options;
}

TEST(Replay, TwiceGivesByteIdenticalOutput) {
  testing::TempDir dir("replay");
  write_input_log(dir.file("in.lcmlog"), 500);
  write_config(dir, 1.5);
  NodeRegistry registry;
  testing::register_test_nodes(registry);
  const ReplaySummary a = run_replay(options_for(dir, "a.lcmlog"), registry);
  const ReplaySummary b = run_replay(options_for(dir, "b.lcmlog"), registry);
  EXPECT_EQ(testing::file_digest(dir.file("a.lcmlog")), testing::file_digest(dir.file("b.lcmlog")));
  EXPECT_EQ(a.events_in, 510);
  EXPECT_EQ(a.passed_through, 510);
  EXPECT_EQ(a.published_per_channel.at(channels::kPose), 499);
  EXPECT_EQ(a.published_per_channel.at(channels::kVoDelta), 499);
  EXPECT_EQ(a.published, b.published);
}

TEST(Replay, OutputHoldsConfigAndResultsMatchTheInput) {
  testing::TempDir dir("replay");
  write_input_log(dir.file("in.lcmlog"), 200);
  write_config(dir, 2.0);
  NodeRegistry registry;
  testing::register_test_nodes(registry);
  run_replay(options_for(dir, "out.lcmlog"), registry);

  LogReader reader(dir.file("out.lcmlog"));
  LogEvent event;
  int configs = 0;
  pose_t last{};
  double expected_north = 0.0;
  ins_t prev{};
  bool have_prev = false;
  while (reader.next(&event)) {
    if (event.channel == channels::kConfig) {
      config_t c;
      ASSERT_GT(c.decode(event.data, 0, static_cast<int>(event.size)), 0);
      EXPECT_NE(c.yaml.find("scale: 2"), std::string::npos);
      ++configs;
    } else if (event.channel == channels::kPose) {
      ASSERT_GT(last.decode(event.data, 0, static_cast<int>(event.size)), 0);
    } else if (event.channel == channels::kIns) {
      ins_t m{};
      ASSERT_GT(m.decode(event.data, 0, static_cast<int>(event.size)), 0);
      if (have_prev) expected_north += 2.0 * m.velocity_ned[0] * 1e-6 * static_cast<double>(m.utime - prev.utime);
      prev = m;
      have_prev = true;
    }
  }
  EXPECT_EQ(configs, 2);
  EXPECT_EQ(last.frames, 199);
  EXPECT_NEAR(last.position_ned[0], expected_north, 1e-9);
}

TEST(Replay, ChannelsTheNodesProduceAreReplacedNotDuplicated) {
  testing::TempDir dir("replay");
  write_input_log(dir.file("in.lcmlog"), 100);
  write_config(dir, 1.0);
  NodeRegistry registry;
  testing::register_test_nodes(registry);
  run_replay(options_for(dir, "first.lcmlog"), registry);
  // Replaying the first output again: its POSE/VO_DELTA are replaced.
  ReplayOptions again = options_for(dir, "second.lcmlog");
  again.in_path = dir.file("first.lcmlog");
  const ReplaySummary s = run_replay(again, registry);
  EXPECT_EQ(s.published_per_channel.at(channels::kPose), 99);
  EXPECT_GE(s.replaced_input, 2 * 99);
}

TEST(Replay, CorruptInputIsSkippedAndReported) {
  testing::TempDir dir("replay");
  write_input_log(dir.file("good.lcmlog"), 100);
  auto bytes = testing::read_file_bytes(dir.file("good.lcmlog"));
  bytes[5000] ^= 0xFF;
  bytes.resize(bytes.size() - 10);
  testing::write_file_bytes(dir.file("in.lcmlog"), bytes);
  write_config(dir, 1.0);
  NodeRegistry registry;
  testing::register_test_nodes(registry);
  const ReplaySummary s = run_replay(options_for(dir, "out.lcmlog"), registry);
  EXPECT_GE(s.corrupt_records, 1);
  EXPECT_TRUE(s.truncated);
  EXPECT_NE(s.damage_report.find("in.lcmlog: byte"), std::string::npos);
  EXPECT_GT(s.events_in, 90);
}

TEST(Replay, UnknownNodeIsNamed) {
  testing::TempDir dir("replay");
  write_input_log(dir.file("in.lcmlog"), 10);
  write_config(dir, 1.0);
  NodeRegistry registry;
  testing::register_test_nodes(registry);
  ReplayOptions options = options_for(dir, "out.lcmlog");
  options.nodes = {"ins_delta", "warp_drive"};
  try {
    run_replay(options, registry);
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("warp_drive"), std::string::npos);
  }
}

TEST(Replay, AFileWithoutLcmEventsIsAnError) {
  testing::TempDir dir("replay");
  write_config(dir, 1.0);
  testing::write_file_bytes(dir.file("in.lcmlog"), std::vector<uint8_t>(5000, 0x42));
  NodeRegistry registry;
  testing::register_test_nodes(registry);
  try {
    run_replay(options_for(dir, "out.lcmlog"), registry);
    FAIL() << "a file without events replayed";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("in.lcmlog: no LCM events in 5000 bytes"), std::string::npos) << e.what();
  }
}

// A record whose payload declares a negative array length (here a STATUS
// with num_counters -1, which the replay itself decodes, and one on a node's
// input channel) is counted as malformed; the replay goes on.
TEST(Replay, HostileLengthFieldsInTheLogAreCountedNotFatal) {
  testing::TempDir dir("replay");
  write_input_log(dir.file("in.lcmlog"), 10);
  write_config(dir, 1.0);
  int64_t good_events = 0;
  {
    LogReader reader(dir.file("in.lcmlog"));
    LogEvent event;
    while (reader.next(&event)) ++good_events;
  }
  {
    status_t status{};
    status.name = "ins_delta";
    std::vector<uint8_t> bytes(static_cast<size_t>(status.getEncodedSize()));
    status.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
    // num_counters: the last int32 of a STATUS without counters.
    for (int i = 0; i < 4; ++i) bytes[bytes.size() - 4 + i] = 0xff;
    std::vector<uint8_t> log = testing::read_file_bytes(dir.file("in.lcmlog"));
    LogWriter extra(dir.file("extra.lcmlog"));
    extra.write(1000, channels::kStatus, bytes.data(), bytes.size());
    extra.write(1001, channels::kIns, bytes.data(), bytes.size());
    extra.flush();
    const std::vector<uint8_t> tail = testing::read_file_bytes(dir.file("extra.lcmlog"));
    log.insert(log.end(), tail.begin(), tail.end());
    testing::write_file_bytes(dir.file("in.lcmlog"), log);
  }
  NodeRegistry registry;
  testing::register_test_nodes(registry);
  const ReplaySummary s = run_replay(options_for(dir, "out.lcmlog"), registry);
  EXPECT_EQ(s.events_in, good_events + 2);
  bool counted = false;
  for (const status_t& st : s.final_status) counted = counted || st.malformed >= 1;
  EXPECT_TRUE(counted);
}

}  // namespace
}  // namespace nadir
