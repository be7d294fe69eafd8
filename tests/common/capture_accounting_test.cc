#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "common/capture_accounting.h"
#include "common/channels.h"
#include "common/lcm_bus.h"
#include "common/message_guard.h"
#include "nadir/ins_t.hpp"
#include "nadir/status_t.hpp"

namespace nadir {
namespace {

// Records for an accountant; the bytes live as long as the feed.
class Feed {
 public:
  explicit Feed(CaptureAccountant* accountant) : accountant_(accountant) {}

  void records(const std::string& channel, int n) {
    const uint8_t byte = 0;
    for (int i = 0; i < n; ++i) add(channel, std::vector<uint8_t>(1, byte));
  }
  void status(const std::string& name, int32_t pid, const std::vector<std::pair<std::string, double>>& counters) {
    status_t msg{};
    msg.name = name;
    msg.pid = pid;
    for (const auto& [key, value] : counters) {
      msg.counter_names.push_back(key);
      msg.counter_values.push_back(value);
    }
    msg.num_counters = static_cast<int32_t>(counters.size());
    status(msg);
  }
  void status(const status_t& msg) { add(channels::kStatus, encode_message(msg)); }

 private:
  void add(const std::string& channel, std::vector<uint8_t> bytes) {
    LogEvent e;
    e.channel = channel;
    e.data = bytes.data();
    e.size = bytes.size();
    accountant_->add(e);
  }
  CaptureAccountant* accountant_;
};

const ChannelAccount* find(const CaptureAccounting& a, const std::string& channel) {
  for (const ChannelAccount& c : a.channels) {
    if (c.channel == channel) return &c;
  }
  return nullptr;
}

TEST(CaptureAccounting, CountsWhatThePublishersStatusSaysIsMissingFromTheCapture) {
  CaptureAccountant accountant;
  Feed feed(&accountant);
  feed.records(channels::kIns, 10);
  feed.status("sim", 5, {{"tx.INS", 12}, {"tx.ALTIMETER", 2}});
  feed.records(channels::kIns, 3);
  feed.records(channels::kAltimeter, 6);  // 2 from the sim + 4 from a publisher without STATUS
  feed.status("sim", 5, {{"tx.INS", 15}, {"tx.ALTIMETER", 2}});
  feed.records(channels::kIns, 4);  // after the last STATUS: not judged
  const CaptureAccounting a = accountant.result();
  const ChannelAccount* ins = find(a, channels::kIns);
  ASSERT_NE(ins, nullptr);
  EXPECT_EQ(ins->published, 15);
  EXPECT_EQ(ins->captured, 13);
  EXPECT_EQ(ins->missing(), 2);
  EXPECT_EQ(ins->publishers, "sim");
  const ChannelAccount* alt = find(a, channels::kAltimeter);
  ASSERT_NE(alt, nullptr);
  EXPECT_EQ(alt->missing(), 0);
  EXPECT_EQ(alt->unaccounted(), 4);
  EXPECT_EQ(a.missing_total(), 2);
  const std::string text = format_capture_accounting(a);
  EXPECT_NE(text.find("INS: 2 of 15 published by sim missing from the capture"), std::string::npos) << text;
  EXPECT_NE(text.find("ALTIMETER: 4 record(s) more than sim published"), std::string::npos) << text;
}

TEST(CaptureAccounting, AddsUpARestartedPublisherAndReceiverDrops) {
  CaptureAccountant accountant;
  Feed feed(&accountant);
  feed.records(channels::kPose, 20);
  feed.status("yaw_fusion", 7, {{"tx.POSE", 20}, {"udp_rx_drops", 30}});
  feed.records(channels::kPose, 5);  // killed before its next STATUS
  feed.records(channels::kPose, 8);  // the restarted process
  feed.status("yaw_fusion", 8, {{"tx.POSE", 10}, {"udp_rx_drops", 5}});
  const CaptureAccounting a = accountant.result();
  const ChannelAccount* pose = find(a, channels::kPose);
  ASSERT_NE(pose, nullptr);
  EXPECT_EQ(pose->published, 30);
  EXPECT_EQ(pose->captured, 33);
  EXPECT_EQ(pose->missing(), 0);
  EXPECT_EQ(a.udp_rx_drops.at("yaw_fusion"), 35);
  EXPECT_EQ(a.udp_rx_drops_total(), 35);
}

TEST(CaptureAccounting, LcmBusStatusCountsPublishedAndDeliveredMessagesPerChannel) {
  LcmBusOptions options;
  options.url = "memq://";
  LcmBus bus(options);
  int delivered = 0;
  bus.subscribe<ins_t>(channels::kIns, [&](const ins_t&) { ++delivered; });
  ins_t ins{};
  for (int i = 0; i < 7; ++i) {
    ins.utime = 1000 + i;
    bus.publish(channels::kIns, ins);
  }
  while (bus.handle(0) > 0) {
  }
  ASSERT_EQ(delivered, 7);
  status_t msg{};
  bus.add_transport_counters(&msg);
  ASSERT_EQ(msg.num_counters, static_cast<int32_t>(msg.counter_names.size()));
  double tx = -1;
  double rx = -1;
  for (size_t i = 0; i < msg.counter_names.size(); ++i) {
    if (msg.counter_names[i] == "tx.INS") tx = msg.counter_values[i];
    if (msg.counter_names[i] == "rx.INS") rx = msg.counter_values[i];
    EXPECT_NE(msg.counter_names[i], "tx.STATUS");
  }
  EXPECT_EQ(tx, 7);
  EXPECT_EQ(rx, 7);
}

// The sim_mavlink set: the simulator publishes INS and images on a bus of its
// own; a feeder turns its INS into MAVLink (the bridge publishes INS on the
// captured bus) and relays its images and its STATUS onto the captured bus.
// The simulator's counts are of its own bus: relayed relabelled, they are
// not held against the capture, and nothing is missing.
TEST(CaptureAccounting, AStatusRelayedFromAnotherBusIsNotCheckedAgainstTheCapture) {
  LcmBusOptions options;
  options.url = "memq://";
  LcmBus sim_bus(options), feeder_bus(options), bridge_bus(options);
  ins_t ins{};
  for (int i = 0; i < 10; ++i) sim_bus.publish(channels::kIns, ins);
  const uint8_t image_bytes[16] = {};
  for (int i = 0; i < 4; ++i) {
    sim_bus.publish_raw(channels::kCameraImage, image_bytes, sizeof image_bytes);
    feeder_bus.publish_raw(channels::kCameraImage, image_bytes, sizeof image_bytes);
  }
  for (int i = 0; i < 10; ++i) bridge_bus.publish(channels::kIns, ins);
  const status_t sim_status = sim_bus.status_message("sim", StatusReport{});
  status_t relayed = sim_status;
  relabel_relayed_transport_counters(&relayed);
  for (const std::string& name : relayed.counter_names) {
    EXPECT_TRUE(name.rfind("tx.", 0) != 0 && name.rfind("rx.", 0) != 0) << name;
  }
  EXPECT_NE(std::find(relayed.counter_names.begin(), relayed.counter_names.end(), "origin_bus.tx.INS"),
            relayed.counter_names.end());

  auto capture = [&](const status_t& sim) {
    CaptureAccountant accountant;
    Feed feed(&accountant);
    feed.records(channels::kIns, 10);          // the bridge's
    feed.records(channels::kCameraImage, 4);   // the feeder's relay
    feed.status(sim);
    feed.status(feeder_bus.status_message("sim_mavlink", StatusReport{}));
    feed.status(bridge_bus.status_message("mavlink_bridge", StatusReport{}));
    return accountant.result();
  };
  const CaptureAccounting as_relayed = capture(relayed);
  EXPECT_EQ(as_relayed.missing_total(), 0) << format_capture_accounting(as_relayed);
  const ChannelAccount* images = find(as_relayed, channels::kCameraImage);
  ASSERT_NE(images, nullptr);
  EXPECT_EQ(images->publishers, "sim_mavlink");
  EXPECT_EQ(images->published, 4);
  EXPECT_EQ(find(as_relayed, channels::kIns)->publishers, "mavlink_bridge");
  // Relayed unchanged, the simulator's own-bus counts double every channel.
  EXPECT_EQ(capture(sim_status).missing_total(), 10 + 4);
}

}  // namespace
}  // namespace nadir
