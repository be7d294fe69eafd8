// The yaw_fusion node over real buses: LCM memq:// and the lockstep ReplayBus
// give byte-identical POSE for different arrival orders of the same messages;
// malformed messages are counted and survived; the executable has --help.

#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <string>

#include "common/channels.h"
#include "common/lcm_bus.h"
#include "common/replay.h"
#include "nadir/pose_t.hpp"
#include "processes/yaw_fusion/yaw_fusion_node.h"
#include "synthetic_flight.h"

namespace nadir {
namespace {

using Bytes = std::vector<uint8_t>;

Config test_config() { return Config::parse("camera: {rate_hz: 14.0}\nyaw_fusion: {}\n", "node_test.yaml"); }

test::SyntheticFlight flight_with_gap() {
  test::FlightSpec spec;
  spec.frames = 200;
  spec.ins_yaw_stddev_deg = 0.3;
  spec.dyaw_stddev_deg = 0.05;
  spec.translation_stddev_m = 0.05;
  test::SyntheticFlight flight = test::make_flight(spec);
  flight.deltas.erase(flight.deltas.begin() + 80, flight.deltas.begin() + 90);
  return flight;
}

// Publishes every message on a memq:// LCM bus, handling after each, and
// returns the POSE bytes that came back.
std::vector<Bytes> run_on_lcm(const std::vector<test::TimedMessage>& messages, StatusReport* report = nullptr,
                              BusErrorCounts* errors = nullptr, bool add_garbage = false) {
  LcmBusOptions options;
  options.url = "memq://";
  options.queue_capacity = 100000;
  LcmBus bus(options);
  auto node = make_yaw_fusion_node(test_config(), bus);
  std::vector<Bytes> poses;
  bus.subscribe_raw(channels::kPose, [&](const std::string&, const uint8_t* data, size_t size) {
    poses.emplace_back(data, data + size);
  });
  size_t index = 0;
  for (const auto& m : messages) {
    bus.publish_raw(m.channel, m.bytes.data(), m.bytes.size());
    if (add_garbage && index % 50 == 0) {
      const Bytes garbage(37, static_cast<uint8_t>(index));
      bus.publish_raw(channels::kVoDelta, garbage.data(), garbage.size());
      bus.publish_raw(channels::kVoGround, garbage.data(), garbage.size());
      bus.publish_raw(channels::kIns, m.bytes.data(), m.bytes.size() / 2);  // truncated
    }
    ++index;
    while (bus.handle(0) > 0) {
    }
  }
  while (bus.handle(0) > 0) {
  }
  if (report != nullptr) *report = node->status();
  if (errors != nullptr) *errors = bus.error_counts();
  return poses;
}

std::vector<Bytes> run_on_replay_bus(const std::vector<test::TimedMessage>& messages) {
  ReplayBus bus(nullptr);
  auto node = make_yaw_fusion_node(test_config(), bus);
  std::vector<Bytes> poses;
  bus.subscribe_raw(channels::kPose, [&](const std::string&, const uint8_t* data, size_t size) {
    poses.emplace_back(data, data + size);
  });
  for (const auto& m : messages) bus.deliver(m.channel, m.bytes.data(), m.bytes.size());
  return poses;
}

TEST(YawFusionNode, LcmAndReplayGiveIdenticalPoseBytesForDifferentArrivalOrders) {
  const test::SyntheticFlight flight = flight_with_gap();
  const auto live_order = test::arrival_order(flight, 90'000, 3'000, 8'000, 5, 40'000);
  const auto other_order = test::arrival_order(flight, 0, 350'000, 100'000);
  const auto lcm_poses = run_on_lcm(live_order);
  const auto replay_poses = run_on_replay_bus(other_order);
  ASSERT_EQ(lcm_poses.size(), flight.truth.size());  // one per frame, gap frames included
  ASSERT_EQ(lcm_poses.size(), replay_poses.size());
  for (size_t i = 0; i < lcm_poses.size(); ++i) EXPECT_EQ(lcm_poses[i], replay_poses[i]) << "pose " << i;
  pose_t last;
  ASSERT_EQ(last.decode(lcm_poses.back().data(), 0, static_cast<int>(lcm_poses.back().size())),
            static_cast<int>(lcm_poses.back().size()));
  EXPECT_EQ(last.utime, flight.truth.back().utime);
}

TEST(YawFusionNode, MalformedMessagesAreCountedAndSurvived) {
  const test::SyntheticFlight flight = flight_with_gap();
  const auto order = test::arrival_order(flight, 90'000, 3'000, 8'000);
  StatusReport report;
  BusErrorCounts errors;
  const auto poses = run_on_lcm(order, &report, &errors, /*add_garbage=*/true);
  const auto clean = run_on_lcm(order);
  EXPECT_GT(errors.malformed, 0);
  EXPECT_NE(errors.last_error.find("malformed message on"), std::string::npos) << errors.last_error;
  EXPECT_EQ(poses, clean);  // garbage changed nothing
  EXPECT_EQ(report.state, status_t::STATE_OK);
  EXPECT_EQ(report.published, static_cast<int64_t>(poses.size()));
  EXPECT_EQ(report.counter("gap_poses"), 10.0);  // frames 81..89 at the camera rate, and frame 90
  const status_t msg = make_status_message("yaw_fusion", 0, 0, report, errors);
  EXPECT_EQ(msg.malformed, errors.malformed);
}

TEST(YawFusionNode, RegistryAndExecutableHelp) {
  NodeRegistry registry;
  register_yaw_fusion_node(registry);
  ASSERT_NE(registry.find("yaw_fusion"), nullptr);
  ReplayBus bus(nullptr);
  auto node = (*registry.find("yaw_fusion"))(test_config(), bus);
  EXPECT_EQ(node->name(), "yaw_fusion");
  EXPECT_EQ(node->output_channels(), std::vector<std::string>{channels::kPose});
  EXPECT_EQ(node->status().state, status_t::STATE_STARTING);

  const char* bin_dir = std::getenv("NADIR_BIN_DIR");
  ASSERT_NE(bin_dir, nullptr);
  const std::string command = std::string(bin_dir) + "/nadir_yaw_fusion --help";
  FILE* pipe = popen(command.c_str(), "r");
  ASSERT_NE(pipe, nullptr);
  std::string text;
  char buffer[256];
  while (fgets(buffer, sizeof(buffer), pipe) != nullptr) text += buffer;
  EXPECT_EQ(pclose(pipe), 0);
  EXPECT_NE(text.find("Kalman filter"), std::string::npos) << text;
  EXPECT_NE(text.find("--config"), std::string::npos);
}

}  // namespace
}  // namespace nadir
