#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <thread>

#include "common/channels.h"
#include "common/lcm_bus.h"
#include "common/udp_drops.h"
#include "nadir/ins_t.hpp"
#include "nadir/pose_t.hpp"
#include "tests/common/test_nodes.h"
#include "tests/common/test_support.h"

namespace nadir {
namespace {

ins_t make_ins(int64_t utime, double yaw) {
  ins_t msg{};
  msg.utime = utime;
  msg.yaw = yaw;
  msg.velocity_ned[0] = 10.0;
  return msg;
}

// Two nodes in two LcmBus instances (as two processes would be) exchange
// messages over `url`: INS -> ins_delta -> VO_DELTA -> delta_integrator -> POSE.
void run_two_node_exchange(const std::string& url) {
  LcmBusOptions options;
  options.url = url;
  LcmBus bus_a(options);
  LcmBus bus_b(options);
  LcmBus bus_src(options);
  const Config config = Config::parse("ins_delta: {scale: 2.0}", "test");
  testing::InsDeltaNode stage1(config, bus_a);
  testing::DeltaIntegratorNode stage2(config, bus_b);
  std::vector<pose_t> poses;
  bus_src.subscribe<pose_t>(channels::kPose, [&](const pose_t& p) { poses.push_back(p); });

  const int n = 20;
  for (int i = 0; i < n; ++i) {
    bus_src.publish(channels::kIns, make_ins(1000000 + i * 100000, 0.01 * i));
    // Each hop is handled by its own bus; pump all three.
    for (int k = 0; k < 50 && poses.size() < static_cast<size_t>(i); ++k) {
      bus_a.handle(5);
      bus_b.handle(5);
      bus_src.handle(5);
    }
  }
  for (int k = 0; k < 200 && poses.size() < static_cast<size_t>(n - 1); ++k) {
    bus_a.handle(5);
    bus_b.handle(5);
    bus_src.handle(5);
  }
  ASSERT_EQ(poses.size(), static_cast<size_t>(n - 1));
  // 19 steps of 0.1 s at 10 m/s, scaled by 2 from config.
  EXPECT_NEAR(poses.back().position_ned[0], 19 * 0.1 * 10.0 * 2.0, 1e-9);
  EXPECT_NEAR(poses.back().yaw, 0.01 * 19, 1e-12);
  EXPECT_EQ(poses.back().frames, n - 1);
  EXPECT_EQ(stage1.status().received, n);
  EXPECT_EQ(stage2.status().published, n - 1);
}

TEST(LcmBus, TwoNodesExchangeOverMemq) {
  // memq:// is one in-process queue per LCM instance, so the chain runs on a
  // single bus there.
  LcmBusOptions options;
  options.url = "memq://";
  LcmBus bus(options);
  const Config config = Config::parse("ins_delta: {scale: 2.0}", "test");
  testing::InsDeltaNode stage1(config, bus);
  testing::DeltaIntegratorNode stage2(config, bus);
  std::vector<pose_t> poses;
  bus.subscribe<pose_t>(channels::kPose, [&](const pose_t& p) { poses.push_back(p); });
  for (int i = 0; i < 20; ++i) bus.publish(channels::kIns, make_ins(1000000 + i * 100000, 0.01 * i));
  for (int k = 0; k < 200 && poses.size() < 19; ++k) bus.handle(0);
  ASSERT_EQ(poses.size(), 19u);
  EXPECT_NEAR(poses.back().position_ned[0], 19 * 0.1 * 10.0 * 2.0, 1e-9);
  EXPECT_EQ(stage1.status().received, 20);
}

TEST(LcmBus, TwoNodesExchangeOverUdpmInPrivateNamespace) {
  if (!testing::in_private_netns()) GTEST_SKIP() << "udpm runs only inside test.sh's private network namespace";
  run_two_node_exchange("udpm://239.255.76.67:7667?ttl=0");
}

TEST(LcmBus, ReceivePortIsTheUrlsPort) {
  EXPECT_EQ(lcm_receive_port("udpm://239.255.76.67:7667?ttl=0&recv_buf_size=4194304"), 7667);
  EXPECT_EQ(lcm_receive_port("udpm://239.255.76.67:7668?ttl=0"), 7668);
  EXPECT_EQ(lcm_receive_port("udpm://239.255.76.67"), 7667);  // LCM's default
  EXPECT_EQ(lcm_receive_port("udpm://239.255.76.67?ttl=0"), 7667);
  EXPECT_EQ(lcm_receive_port("memq://"), 0);
  EXPECT_EQ(lcm_receive_port("file:///tmp/capture.lcmlog?mode=r"), 0);
}

// A process's other UDP sockets (camera_capture's GigE Vision stream, which
// the camera goes on filling after acquisition stops) overflow without a bus
// message lost: the bus's STATUS counts its own socket's drops only.
TEST(LcmBus, KernelDropsOfTheProcessesOtherUdpSocketsAreNotTheBuses) {
  if (!testing::in_private_netns()) GTEST_SKIP() << "udpm runs only inside test.sh's private network namespace";
  LcmBusOptions options;
  options.url = "udpm://239.255.76.67:7667?ttl=0";
  LcmBus bus(options);
  int stream_port = 0;
  const int stream = testing::overflowed_udp_socket(300, &stream_port);
  ASSERT_GT(own_udp_receive_drops(), 0) << "the stream socket did not overflow";
  status_t msg{};
  bus.add_transport_counters(&msg);
  const auto at = std::find(msg.counter_names.begin(), msg.counter_names.end(), "udp_rx_drops");
  ASSERT_NE(at, msg.counter_names.end());
  EXPECT_EQ(msg.counter_values[static_cast<size_t>(at - msg.counter_names.begin())], 0.0);
  close(stream);
}

TEST(LcmBus, MalformedMessageIsCountedAndSurvived) {
  LcmBusOptions options;
  options.url = "memq://";
  LcmBus bus(options);
  int delivered = 0;
  bus.subscribe<ins_t>(channels::kIns, [&](const ins_t&) { ++delivered; });
  const uint8_t garbage[] = {1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16, 17};
  bus.publish_raw(channels::kIns, garbage, sizeof(garbage));
  bus.publish(channels::kIns, make_ins(5, 0.0));
  for (int k = 0; k < 10; ++k) bus.handle(0);
  EXPECT_EQ(delivered, 1);
  EXPECT_EQ(bus.error_counts().malformed, 1);
  EXPECT_NE(bus.error_counts().last_error.find("INS"), std::string::npos);
}

TEST(LcmBus, ThrowingHandlerIsCountedAndSurvived) {
  LcmBusOptions options;
  options.url = "memq://";
  LcmBus bus(options);
  int delivered = 0;
  bus.subscribe<ins_t>(channels::kIns, [&](const ins_t& m) {
    if (m.utime == 1) throw std::runtime_error("bad sample");
    ++delivered;
  });
  bus.publish(channels::kIns, make_ins(1, 0.0));
  bus.publish(channels::kIns, make_ins(2, 0.0));
  for (int k = 0; k < 10; ++k) bus.handle(0);
  EXPECT_EQ(delivered, 1);
  EXPECT_EQ(bus.error_counts().handler_errors, 1);
  EXPECT_NE(bus.error_counts().last_error.find("bad sample"), std::string::npos);
}

TEST(LcmBus, BadUrlFailsWithTheUrlNamed) {
  LcmBusOptions options;
  options.url = "nonsense://nowhere";
  try {
    LcmBus bus(options);
    FAIL() << "expected an error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("nonsense://nowhere"), std::string::npos);
  }
}

TEST(EncodedUtime, ReadsTheFirstField) {
  ins_t msg = make_ins(123456789012345, 0.0);
  std::vector<uint8_t> buf(msg.getEncodedSize());
  msg.encode(buf.data(), 0, static_cast<int>(buf.size()));
  int64_t utime = 0;
  ASSERT_TRUE(encoded_utime(buf.data(), buf.size(), &utime));
  EXPECT_EQ(utime, 123456789012345);
  EXPECT_FALSE(encoded_utime(buf.data(), 10, &utime));
}

}  // namespace
}  // namespace nadir
