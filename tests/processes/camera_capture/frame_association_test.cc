// Association of frames with trigger edges on scripted edge/frame sequences:
// a healthy stream and each fault the capture must survive.

#include "processes/camera_capture/frame_association.h"

#include <gtest/gtest.h>

#include <vector>

namespace nadir {
namespace {

// A 14 Hz triggered camera: the camera stamps each frame 150 us after the
// edge on its own clock (5 s ahead of vehicle time); the frame arrives 12 ms
// after the edge.
constexpr int64_t kPeriod = 71429;
constexpr int64_t kT0 = 1'700'000'000'000'000;
constexpr int64_t kCameraAhead = 5'000'000;
constexpr int64_t kStampDelay = 150;
constexpr int64_t kArrival = 12'000;

struct Script {
  FrameAssociator associator{AssociationOptions{}};
  int64_t next_sequence = 0;
  std::vector<AssociationDecision> decisions;

  TriggerEdge edge_at(int64_t t) {
    TriggerEdge e;
    e.sequence = next_sequence++;
    e.device_us = t;
    e.vehicle_us = t;
    return e;
  }
  bool edge(int64_t t) { return associator.add_edge(edge_at(t)); }
  void frame(int64_t counter, int64_t edge_time, int64_t arrival_delay = kArrival) {
    FrameStamp f;
    f.token = static_cast<uint64_t>(counter);
    f.frame_counter = counter;
    f.camera_us = edge_time + kCameraAhead + kStampDelay;
    f.arrival_us = edge_time + arrival_delay;
    associator.add_frame(f);
  }
  void decide(int64_t now) {
    for (const auto& d : associator.decide(now)) decisions.push_back(d);
  }
  // Edge and frame for trigger k, then decisions well after arrival.
  void healthy(int64_t k, int64_t counter) {
    const int64_t t = kT0 + k * kPeriod;
    edge(t);
    frame(counter, t);
    decide(t + kArrival + 40000);
  }
};

TEST(FrameAssociation, HealthyStreamMatchesEveryFrameToItsEdge) {
  Script s;
  for (int k = 0; k < 20; ++k) s.healthy(k, 100 + k);
  ASSERT_EQ(s.decisions.size(), 20u);
  for (int k = 0; k < 20; ++k) {
    EXPECT_EQ(s.decisions[k].result, AssociationResult::kMatched);
    EXPECT_EQ(s.decisions[k].edge.sequence, k);
    EXPECT_EQ(s.decisions[k].edge_estimate_us, kT0 + k * kPeriod);
  }
  const auto& c = s.associator.counters();
  EXPECT_EQ(c.frames_matched, 20);
  EXPECT_EQ(c.locks, 1);
  EXPECT_EQ(c.sequence_slips, 0);
  EXPECT_EQ(c.edges_without_frame, 0);
  EXPECT_TRUE(s.associator.locked());
  EXPECT_DOUBLE_EQ(s.associator.locked_offset_us(), double(kCameraAhead + kStampDelay));
}

TEST(FrameAssociation, MissingEdgeIsTimedFromTheLockedOffsetNotMistimed) {
  Script s;
  for (int k = 0; k < 5; ++k) s.healthy(k, k);
  // Trigger 5 fires the camera but the GPIO edge is lost.
  const int64_t t5 = kT0 + 5 * kPeriod;
  s.frame(5, t5);
  s.decide(t5 + kArrival + 1000);  // still waiting for the edge
  EXPECT_EQ(s.decisions.size(), 5u);
  s.decide(t5 + kArrival + 40000);
  ASSERT_EQ(s.decisions.size(), 6u);
  EXPECT_EQ(s.decisions[5].result, AssociationResult::kEstimatedFromLock);
  EXPECT_EQ(s.decisions[5].edge_estimate_us, t5);  // exact: the camera clock carries it
  for (int k = 6; k < 10; ++k) s.healthy(k, k);
  ASSERT_EQ(s.decisions.size(), 10u);
  for (int k = 6; k < 10; ++k) {
    EXPECT_EQ(s.decisions[k].result, AssociationResult::kMatched);
    EXPECT_EQ(s.decisions[k].edge_estimate_us, kT0 + k * kPeriod);
  }
  const auto& c = s.associator.counters();
  EXPECT_EQ(c.frames_estimated, 1);
  EXPECT_EQ(c.sequence_slips, 1);  // edge sequence now runs one behind the frame counter
}

TEST(FrameAssociation, SpuriousAndDoubleEdgesAreFlaggedAndNeverMatched) {
  Script s;
  for (int k = 0; k < 3; ++k) s.healthy(k, k);
  const int64_t t3 = kT0 + 3 * kPeriod;
  EXPECT_TRUE(s.edge(t3));
  EXPECT_FALSE(s.edge(t3 + 800));       // contact bounce: double edge
  EXPECT_TRUE(s.edge(t3 + kPeriod / 2));  // stray pulse half a period later
  s.frame(3, t3);
  s.decide(t3 + kArrival + 40000);
  for (int k = 4; k < 8; ++k) s.healthy(k, k);
  ASSERT_EQ(s.decisions.size(), 8u);
  for (int k = 0; k < 8; ++k) {
    EXPECT_EQ(s.decisions[k].result, AssociationResult::kMatched) << k;
    EXPECT_EQ(s.decisions[k].edge_estimate_us, kT0 + k * kPeriod) << k;
  }
  const auto& c = s.associator.counters();
  EXPECT_EQ(c.edges_spurious, 1);
  EXPECT_EQ(c.edges_without_frame, 1);  // the stray pulse, expired when frame 4 matched
  EXPECT_GE(c.sequence_slips, 1);
}

TEST(FrameAssociation, DroppedFrameLeavesItsEdgeUnmatchedAndShowsAsCounterGap) {
  Script s;
  for (int k = 0; k < 4; ++k) s.healthy(k, k);
  const int64_t t4 = kT0 + 4 * kPeriod;
  s.edge(t4);  // frame 4 is lost in transport
  for (int k = 5; k < 9; ++k) s.healthy(k, k);
  ASSERT_EQ(s.decisions.size(), 8u);
  EXPECT_EQ(s.decisions[4].frame.frame_counter, 5);
  EXPECT_EQ(s.decisions[4].edge.sequence, 5);
  EXPECT_EQ(s.decisions[4].edge_estimate_us, kT0 + 5 * kPeriod);
  const auto& c = s.associator.counters();
  EXPECT_EQ(c.frame_counter_gaps, 1);
  EXPECT_EQ(c.edges_without_frame, 1);
  EXPECT_EQ(c.sequence_slips, 0);
}

TEST(FrameAssociation, BufferUnderrunBurstIsMatchedByCameraTimeNotArrival) {
  Script s;
  for (int k = 0; k < 4; ++k) s.healthy(k, k);
  // The host stalls: frames 4..7 arrive together 400 ms late, frame 5 was
  // lost to a buffer underrun (no free buffer).
  std::vector<int64_t> t;
  for (int k = 4; k < 8; ++k) {
    t.push_back(kT0 + k * kPeriod);
    s.edge(t.back());
  }
  const int64_t burst = t.back() + 400000;
  for (int k : {4, 6, 7}) s.frame(k, kT0 + k * kPeriod, burst - (kT0 + k * kPeriod));
  s.decide(burst + 1000);
  ASSERT_EQ(s.decisions.size(), 7u);
  EXPECT_EQ(s.decisions[4].edge_estimate_us, kT0 + 4 * kPeriod);
  EXPECT_EQ(s.decisions[5].edge_estimate_us, kT0 + 6 * kPeriod);
  EXPECT_EQ(s.decisions[6].edge_estimate_us, kT0 + 7 * kPeriod);
  for (const auto& d : s.decisions) EXPECT_EQ(d.result, AssociationResult::kMatched);
  EXPECT_EQ(s.associator.counters().frame_counter_gaps, 1);
  EXPECT_EQ(s.associator.counters().edges_without_frame, 1);
}

TEST(FrameAssociation, CounterResetAfterReconnectRelocksByArrivalWindow) {
  Script s;
  for (int k = 0; k < 5; ++k) s.healthy(k, 1000 + k);
  // The camera power-cycles: frame counter and camera clock restart.
  const int64_t t5 = kT0 + 5 * kPeriod + 3'000'000;
  s.edge(t5);
  FrameStamp f;
  f.token = 99;
  f.frame_counter = 0;
  f.camera_us = 20'000;  // camera clock restarted near zero
  f.arrival_us = t5 + kArrival;
  s.associator.add_frame(f);
  s.decide(t5 + kArrival + 40000);
  ASSERT_EQ(s.decisions.size(), 6u);
  EXPECT_EQ(s.decisions[5].result, AssociationResult::kMatched);
  EXPECT_EQ(s.decisions[5].edge_estimate_us, t5);
  const auto& c = s.associator.counters();
  EXPECT_EQ(c.frame_counter_resets, 1);
  EXPECT_EQ(c.lock_losses, 1);
  EXPECT_EQ(c.locks, 2);
  EXPECT_DOUBLE_EQ(s.associator.locked_offset_us(), double(20'000 - t5));
}

TEST(FrameAssociation, FrameWithoutEdgeBeforeLockIsUnmatched) {
  Script s;
  const int64_t t0 = kT0;
  s.frame(0, t0);
  s.decide(t0 + kArrival + 40000);
  ASSERT_EQ(s.decisions.size(), 1u);
  EXPECT_EQ(s.decisions[0].result, AssociationResult::kUnmatched);
  EXPECT_EQ(s.associator.counters().frames_unmatched, 1);
  EXPECT_FALSE(s.associator.locked());
}

TEST(FrameAssociation, AmbiguousWindowBeforeLockIsNotGuessed) {
  AssociationOptions wide;
  wide.max_latency_us = 200000;  // wider than a trigger period
  Script s;
  s.associator = FrameAssociator(wide);
  s.edge(kT0);
  s.edge(kT0 + kPeriod);
  s.frame(0, kT0 + kPeriod, kArrival);
  s.decide(kT0 + kPeriod + kArrival + 40000);
  ASSERT_EQ(s.decisions.size(), 1u);
  EXPECT_EQ(s.decisions[0].result, AssociationResult::kUnmatched);
  EXPECT_EQ(s.associator.counters().frames_ambiguous, 1);
}

TEST(FrameAssociation, RepeatedMissesDropTheLock) {
  Script s;
  for (int k = 0; k < 3; ++k) s.healthy(k, k);
  for (int k = 3; k < 6; ++k) {
    const int64_t t = kT0 + k * kPeriod;
    s.frame(k, t);
    s.decide(t + kArrival + 40000);
  }
  EXPECT_FALSE(s.associator.locked());
  EXPECT_EQ(s.associator.counters().frames_estimated, 3);
  EXPECT_EQ(s.associator.counters().lock_losses, 1);
  for (int k = 6; k < 9; ++k) s.healthy(k, k);
  EXPECT_TRUE(s.associator.locked());
  EXPECT_EQ(s.decisions.back().edge_estimate_us, kT0 + 8 * kPeriod);
}

TEST(FrameAssociation, SixteenBitCounterWrapIsNotAReset) {
  Script s;
  for (int k = 0; k < 3; ++k) s.healthy(k, 65533 + k);
  s.healthy(3, 1);  // GigE Vision 1.x block ids skip 0 when they wrap
  EXPECT_EQ(s.associator.counters().frame_counter_resets, 0);
  EXPECT_TRUE(s.associator.locked());
  EXPECT_EQ(s.decisions.back().result, AssociationResult::kMatched);
}

TEST(FrameAssociation, StaleEdgesExpire) {
  Script s;
  s.edge(kT0);
  s.decide(kT0 + 2'000'000);
  EXPECT_EQ(s.associator.pending_edges(), 0u);
  EXPECT_EQ(s.associator.counters().edges_without_frame, 1);
}

TEST(FrameAssociation, OptionsFromConfigRejectOutOfRangeValues) {
  const Config bad = Config::parse("max_latency_us: -5\n", "test.yaml");
  try {
    AssociationOptions::FromConfig(bad);
    FAIL() << "accepted a negative max_latency_us";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("max_latency_us"), std::string::npos) << e.what();
  }
  const AssociationOptions o = AssociationOptions::FromConfig(Config::parse("frame_wait_us: 5000\n", "t.yaml"));
  EXPECT_EQ(o.frame_wait_us, 5000);
}

}  // namespace
}  // namespace nadir

namespace nadir {
namespace {

TEST(FrameAssociation, ChangedCameraDelayRelocksOnTheArrivalWindow) {
  Script s;
  s.healthy(0, 0);  // first frame: the camera took 45 ms longer to stamp it
  const int64_t first_offset = static_cast<int64_t>(s.associator.locked_offset_us());
  for (int k = 1; k < 6; ++k) {
    const int64_t t = kT0 + k * kPeriod;
    s.edge(t);
    FrameStamp f;
    f.token = static_cast<uint64_t>(k);
    f.frame_counter = k;
    f.camera_us = t + first_offset - 45000;
    f.arrival_us = t + kArrival;
    s.associator.add_frame(f);
    s.decide(t + kArrival + 40000);
  }
  ASSERT_EQ(s.decisions.size(), 6u);
  for (int k = 0; k < 6; ++k) {
    EXPECT_EQ(s.decisions[k].result, AssociationResult::kMatched) << k;
    EXPECT_EQ(s.decisions[k].edge_estimate_us, kT0 + k * kPeriod) << k;
  }
  EXPECT_EQ(s.associator.counters().lock_losses, 1);
  EXPECT_EQ(s.associator.counters().locks, 2);
  EXPECT_EQ(s.associator.counters().frames_estimated, 0);
}

}  // namespace
}  // namespace nadir
