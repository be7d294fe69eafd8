// Nodes composed in one process (ComposedBus): delivered to each other in the
// publishing thread, every channel still out on the outside bus, channels the
// process produces never taken back from outside, errors counted per node.

#include <gtest/gtest.h>

#include "common/channels.h"
#include "common/composed_bus.h"
#include "common/lcm_bus.h"
#include "nadir/ins_t.hpp"
#include "nadir/pose_t.hpp"
#include "nadir/vo_delta_t.hpp"
#include "tests/common/test_nodes.h"

namespace nadir {
namespace {

LcmBusOptions memq() {
  LcmBusOptions options;
  options.url = "memq://";
  return options;
}

// INS -> ins_delta (port 1) -> VO_DELTA -> delta_integrator (port 2) -> POSE,
// composed in one process over a memq:// LCM.
struct Composed : public ::testing::Test {
  Composed() { composed.connect_inputs({channels::kVoDelta, channels::kPose}); }
  LcmBus outside{memq()};
  ComposedBus composed{outside};
  NodePort port1{composed}, port2{composed};
  Config config = Config::parse("ins_delta: {scale: 2.0}", "test");
  testing::InsDeltaNode stage1{config, port1};
  testing::DeltaIntegratorNode stage2{config, port2};
};

TEST_F(Composed, ChainRunsInOneDeliveryAndEveryChannelGoesOutside) {

  std::vector<pose_t> poses_outside;
  int deltas_outside = 0;
  outside.subscribe<pose_t>(channels::kPose, [&](const pose_t& p) { poses_outside.push_back(p); });
  outside.subscribe<vo_delta_t>(channels::kVoDelta, [&](const vo_delta_t&) { ++deltas_outside; });

  for (int i = 0; i < 20; ++i) {
    ins_t ins{};
    ins.utime = 1000000 + i * 100000;
    ins.yaw = 0.01 * i;
    ins.velocity_ned[0] = 10.0;
    outside.publish(channels::kIns, ins);
    for (int k = 0; k < 100 && stage1.status().received <= i; ++k) outside.handle(0);
    ASSERT_EQ(stage1.status().received, i + 1);
    // Stage 2 ran on stage 1's delta inside the same delivery of the INS.
    EXPECT_EQ(stage2.status().published, stage1.status().published) << "sample " << i;
  }
  for (int k = 0; k < 200 && poses_outside.size() < 19; ++k) outside.handle(0);
  ASSERT_EQ(poses_outside.size(), 19u);
  EXPECT_EQ(deltas_outside, 19);
  EXPECT_NEAR(poses_outside.back().position_ned[0], 19 * 0.1 * 10.0 * 2.0, 1e-9);
  EXPECT_EQ(stage2.status().received, 19) << "VO_DELTA is produced here: never taken back from outside";
}

// A handler that calls deliver_pending() after publishing has its message
// handed on (and everything published in response) before it continues; the
// order of delivery is the FIFO order either way, and a nested call inside a
// drain changes nothing.
TEST(LocalBusDeliverPending, HandsTheQueueOnBeforeThePublisherContinues) {
  LcmBus outside{memq()};
  ComposedBus composed{outside};
  NodePort first{composed}, second{composed};
  std::vector<std::string> events;
  first.subscribe_raw("IN", [&](const std::string&, const uint8_t*, size_t) {
    const uint8_t byte = 1;
    first.publish_raw("A", &byte, 1);
    first.publish_raw("B", &byte, 1);
    first.deliver_pending();
    events.push_back("first continues");
  });
  second.subscribe_raw("A", [&](const std::string&, const uint8_t*, size_t) {
    events.push_back("A");
    const uint8_t byte = 2;
    second.publish_raw("C", &byte, 1);
    second.deliver_pending();  // inside the drain: no effect, C stays queued behind B
    events.push_back("A done");
  });
  second.subscribe_raw("B", [&](const std::string&, const uint8_t*, size_t) { events.push_back("B"); });
  second.subscribe_raw("C", [&](const std::string&, const uint8_t*, size_t) { events.push_back("C"); });
  const uint8_t byte = 0;
  composed.deliver("IN", &byte, 1);
  EXPECT_EQ(events, (std::vector<std::string>{"A", "A done", "B", "C", "first continues"}));
  // Without the call the same messages come after the handler returns.
  events.clear();
  composed.deliver_pending();  // nothing pending: nothing happens
  EXPECT_TRUE(events.empty());
}

TEST_F(Composed, MalformedMessagesAndPublishLatencyArePerNode) {
  const uint8_t garbage[5] = {1, 2, 3, 4, 5};
  composed.deliver(channels::kVoDelta, garbage, sizeof(garbage));
  EXPECT_EQ(port2.error_counts().malformed, 1);
  EXPECT_EQ(port1.error_counts().malformed, 0);

  vo_delta_t delta{};
  delta.utime = 1;
  delta.variant = "test";
  port1.publish(channels::kVoDelta, delta);
  composed.deliver("UNSUBSCRIBED", garbage, 0);  // drains what was published outside a delivery
  EXPECT_EQ(stage2.status().received, 1);
  float p50 = 0, p99 = 0, max = 0;
  port1.latency().take(&p50, &p99, &max);
  EXPECT_GT(max, 0.0f) << "port 1 published one message";
  port2.latency().take(&p50, &p99, &max);
  EXPECT_GT(max, 0.0f) << "port 2 published the POSE";
}

}  // namespace
}  // namespace nadir
