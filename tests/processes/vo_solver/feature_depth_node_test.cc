// The feature_depth variant through the node on a memq:// bus: per-track
// depths keyed by TRACKS' track ids give the exact motion over non-planar
// ground. A dropped frame (the tracks go on over two frame periods) keeps
// them: they belong to the pair's prev frame. A time gap beyond
// sync.max_frame_interval clears them (that pair is the paper's). A range
// sampled before its frame is moved to the frame (range_at_frame.h).

#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <string>
#include <vector>

#include "common/channels.h"
#include "common/config.h"
#include "common/lcm_bus.h"
#include "nadir/altimeter_t.hpp"
#include "nadir/ground_points_t.hpp"
#include "nadir/ins_t.hpp"
#include "nadir/tracks_t.hpp"
#include "nadir/vo_delta_t.hpp"
#include "processes/vo_solver/vo_solver_node.h"
#include "tests/processes/vo_solver/terrain_sequence.h"

namespace nadir {
namespace {

constexpr int64_t kStart = 1700000000000000;
constexpr int64_t kPeriod = 71429;

// Noise-free tracks and attitudes: the depth filter and the INS tilt filter
// told so (the tilt taken as the INS says).
std::string config(const std::string& variant, double max_frame_interval_ms, bool move_ranges) {
  return R"(
camera: {width: 612, height: 512, fx: 398.79, fy: 398.79, cx: 305.5, cy: 255.5, mount_rpy_deg: [0, 0, 0]}
altimeter: {beam_body: [0, 0, 1]}
vo_solver:
  variant: )" + variant + R"(
  feature_depth: {triangulation_noise_px: 0.001, patch_feature_weight: 0, ins_tilt_sigma_deg: 0, range_from_sample_position: )" +
         std::string(move_ranges ? "true" : "false") + R"(}
  sync: {max_frame_interval_ms: )" + std::to_string(max_frame_interval_ms) + R"(}
)";
}

struct NodeRun {
  std::map<int64_t, vo_delta_t> deltas;
  std::map<int64_t, ground_points_t> ground;
  std::vector<std::pair<std::string, int64_t>> order;  // (channel, utime) as received
  StatusReport status;
};

// How the altimeter is sampled: at the frame times (so the node's lookup
// returns them exactly), or range_lag_us before each frame, from where the
// camera was then (moved to the frame by the node unless move_ranges is off).
struct AltimeterTiming {
  int64_t range_lag_us = 0;
  bool move_ranges = true;
};

// INS samples exactly at the frame times, TRACKS with the points' indices as
// ids. Frame dropped_frame never comes: the next TRACKS spans two periods,
// flagged FLAG_FRAME_GAP as the tracker does.
NodeRun run_node(const std::string& variant, int frames, int dropped_frame, double max_frame_interval_ms = 250,
                 const vo::testing::TerrainSpec& spec = {}, const AltimeterTiming& altimeter = {}) {
  vo::testing::TerrainSequence seq{spec};
  LcmBusOptions options;
  options.url = "memq://";
  LcmBus bus(options);
  std::unique_ptr<Node> node = make_vo_solver_node(
      Config::parse(config(variant, max_frame_interval_ms, altimeter.move_ranges), "feature depth node test"), bus);
  NodeRun result;
  bus.subscribe<vo_delta_t>(channels::kVoDelta, [&](const vo_delta_t& m) {
    result.deltas[m.utime] = m;
    result.order.emplace_back(channels::kVoDelta, m.utime);
  });
  bus.subscribe<ground_points_t>(channels::kVoGround, [&](const ground_points_t& m) {
    result.ground[m.utime] = m;
    result.order.emplace_back(channels::kVoGround, m.utime);
  });
  auto deliver = [&] {
    while (bus.handle(0) > 0) {
    }
  };
  for (int k = 0; k <= frames + 3; ++k) {
    const int64_t t = kStart + k * kPeriod;
    const vo::testing::FramePose pose = seq.pose(k);
    ins_t ins{};
    ins.utime = t;
    ins.roll = pose.roll;
    ins.pitch = pose.pitch;
    ins.yaw = pose.yaw;
    bus.publish(channels::kIns, ins);
    altimeter_t alt{};
    alt.utime = t - altimeter.range_lag_us;
    // The camera then: between frames k-1 and k, linear (the INS gives the node the same attitude within 1e-6 rad).
    const double back = static_cast<double>(altimeter.range_lag_us) / kPeriod;
    const vo::testing::FramePose before = seq.pose(k - 1);
    vo::testing::FramePose then = pose;
    then.position = (1 - back) * pose.position + back * before.position;
    then.roll = (1 - back) * pose.roll + back * before.roll;
    then.pitch = (1 - back) * pose.pitch + back * before.pitch;
    then.yaw = (1 - back) * pose.yaw + back * before.yaw;
    alt.range_m = seq.range_at(then);
    alt.beam_body[2] = 1.0;
    alt.signal_quality = 1.0f;
    alt.validity = altimeter_t::VALID_OK;
    bus.publish(channels::kAltimeter, alt);
    deliver();
  }
  for (int k = 0; k <= frames; ++k) {
    if (k == dropped_frame) continue;
    const bool after_drop = k == dropped_frame + 1;
    const int prev = after_drop ? k - 2 : k - 1;
    tracks_t m{};
    m.utime = kStart + k * kPeriod;
    m.prev_utime = k == 0 ? 0 : kStart + prev * kPeriod;
    m.frame_counter = k;
    m.width = 612;
    m.height = 512;
    m.flags = k == 0 ? tracks_t::FLAG_FIRST_FRAME : (after_drop ? tracks_t::FLAG_FRAME_GAP : 0);
    if (k > 0) {
      const vo::testing::SequencePair sp = seq.pair(prev, k);
      m.num_tracks = static_cast<int32_t>(sp.ids.size());
      for (size_t i = 0; i < sp.ids.size(); ++i) {
        m.track_id.push_back(sp.ids[i]);
        m.age.push_back(1);
        m.prev_px.push_back({0.f, 0.f});
        m.curr_px.push_back({0.f, 0.f});
        m.prev_norm.push_back({sp.pair.prev_norm[i].x(), sp.pair.prev_norm[i].y()});
        m.curr_norm.push_back({sp.pair.curr_norm[i].x(), sp.pair.curr_norm[i].y()});
      }
    }
    bus.publish(channels::kTracks, m);
    deliver();
  }
  while (bus.handle(10) > 0) {
  }
  result.status = node->status();
  return result;
}

// Frames from..to (skipping `dropped`): exact within 1e-5 m and rad.
void expect_exact(const NodeRun& run, const vo::testing::TerrainSequence& seq, int from, int to, int dropped) {
  for (int k = from; k <= to; ++k) {
    if (k == dropped) continue;
    const vo_delta_t& d = run.deltas.at(kStart + k * kPeriod);
    const vo::testing::SequencePair truth = seq.pair(k == dropped + 1 ? k - 2 : k - 1, k);
    EXPECT_EQ(d.variant, "feature_depth");
    EXPECT_EQ(d.quality & ~vo_delta_t::QUALITY_FRAME_GAP, 0) << "frame " << k;
    // Within 1e-5 m through the node. It was ~1e-4 m until the node moved
    // each range to its frame: altimeter_mode latest takes the newest sample
    // before the frame, here the previous frame's, 71 ms old while climbing.
    EXPECT_NEAR(d.dx, truth.translation.x(), 1e-5) << "frame " << k;
    EXPECT_NEAR(d.dy, truth.translation.y(), 1e-5) << "frame " << k;
    EXPECT_NEAR(d.dz, truth.translation.z(), 1e-5) << "frame " << k;
    EXPECT_NEAR(d.dyaw, truth.dyaw, 1e-5) << "frame " << k;
  }
}

// The depths have converged by then (feature_depth_test.cc); frame 205's pair is (203, 205).
constexpr int kDropped = 204;
constexpr int kFrames = 220;

TEST(FeatureDepthNode, ExactOverReliefAndKeptOverADroppedFrame) {
  vo::testing::TerrainSequence seq{vo::testing::TerrainSpec{}};
  const NodeRun depth = run_node("feature_depth", kFrames, kDropped);
  const NodeRun paper = run_node("paper", kFrames, kDropped);
  ASSERT_EQ(depth.deltas.size(), static_cast<size_t>(kFrames));
  expect_exact(depth, seq, 180, kDropped - 1, kDropped);
  expect_exact(depth, seq, kDropped + 2, kFrames, kDropped);
  double worst_paper = 0;
  for (int k = 180; k < kDropped; ++k) {
    const vo::testing::SequencePair truth = seq.pair(k);
    const vo_delta_t& p = paper.deltas.at(kStart + k * kPeriod);
    worst_paper = std::max(worst_paper, std::hypot(p.dx - truth.translation.x(), p.dy - truth.translation.y()));
  }
  EXPECT_GT(worst_paper, 1e-2);
  // The pair over the dropped frame: flagged, solved with the own depths (the
  // paper's patch is centimetres off here), and the map was never cleared.
  const vo_delta_t& over_drop = depth.deltas.at(kStart + (kDropped + 1) * kPeriod);
  const vo_delta_t& paper_over_drop = paper.deltas.at(kStart + (kDropped + 1) * kPeriod);
  EXPECT_TRUE(over_drop.quality & vo_delta_t::QUALITY_FRAME_GAP);
  EXPECT_EQ(over_drop.prev_utime, kStart + (kDropped - 1) * kPeriod);
  const vo::testing::SequencePair truth = seq.pair(kDropped - 1, kDropped + 1);
  // Twice the baseline: 1.6 mm off here against the paper's centimetres.
  EXPECT_LT((Eigen::Vector3d(over_drop.dx, over_drop.dy, over_drop.dz) - truth.translation).norm(), 5e-3);
  EXPECT_GT(std::hypot(paper_over_drop.dx - truth.translation.x(), paper_over_drop.dy - truth.translation.y()), 1e-2);
  EXPECT_EQ(depth.status.counter("own_depth_resets"), 0);
  EXPECT_GT(depth.status.counter("own_depths"), 100);
}

// VO_GROUND: each solved frame's trusted points, published just before its
// VO_DELTA, are the world's points seen from the frame's level frame.
TEST(FeatureDepthNode, GroundPointsAreTheWorldPointsInTheFramesLevelFrame) {
  vo::testing::TerrainSequence seq{vo::testing::TerrainSpec{}};
  const NodeRun run = run_node("feature_depth", kFrames, kDropped);
  const auto& world = seq.points();
  for (int k = 190; k <= 200; k += 5) {
    const int64_t t = kStart + k * kPeriod;
    ASSERT_TRUE(run.ground.count(t)) << "frame " << k;
    const ground_points_t& g = run.ground.at(t);
    EXPECT_GT(g.num_points, 100) << "frame " << k;
    const auto delta_at = std::find(run.order.begin(), run.order.end(), std::make_pair(std::string(channels::kVoDelta), t));
    ASSERT_NE(delta_at, run.order.begin());
    EXPECT_EQ(*std::prev(delta_at), std::make_pair(std::string(channels::kVoGround), t)) << "frame " << k;
    const vo::testing::FramePose pose = seq.pose(k);
    const double c = std::cos(pose.yaw), s = std::sin(pose.yaw);
    double worst = 0.0;
    for (int i = 0; i < g.num_points; ++i) {
      const Eigen::Vector3d local(g.position_m[i][0], g.position_m[i][1], g.position_m[i][2]);
      const Eigen::Vector3d placed = pose.position + Eigen::Vector3d(c * local.x() - s * local.y(),
                                                                     s * local.x() + c * local.y(), local.z());
      double nearest = 1e9;
      for (const Eigen::Vector3d& w : world) nearest = std::min(nearest, (w - placed).norm());
      worst = std::max(worst, nearest);
      EXPECT_GE(g.depth_sigma_m[i], 0.0f);
    }
    EXPECT_LT(worst, 0.01) << "frame " << k;  // the depth filter: ~7 mm at 150 m
  }
  EXPECT_GT(run.status.counter("ground_frames_published"), 100);
  // The paper variant has no own depths: no VO_GROUND.
  EXPECT_TRUE(run_node("paper", 20, -1).ground.empty());
}

TEST(FeatureDepthNode, ClearedByATimeGap) {
  // The same drop, but 143 ms is beyond this max_frame_interval: a time gap.
  // No own depth crosses it: that pair is the paper's own solve.
  vo::testing::TerrainSequence seq{vo::testing::TerrainSpec{}};
  const NodeRun depth = run_node("feature_depth", kFrames, kDropped, 100);
  const NodeRun paper = run_node("paper", kFrames, kDropped, 100);
  const vo_delta_t& at_gap = depth.deltas.at(kStart + (kDropped + 1) * kPeriod);
  const vo_delta_t& paper_gap = paper.deltas.at(kStart + (kDropped + 1) * kPeriod);
  EXPECT_TRUE(at_gap.quality & vo_delta_t::QUALITY_FRAME_GAP);
  EXPECT_EQ(at_gap.dx, paper_gap.dx);
  EXPECT_EQ(at_gap.dy, paper_gap.dy);
  EXPECT_EQ(at_gap.dz, paper_gap.dz);
  EXPECT_GE(depth.status.counter("own_depth_resets"), 1);
  EXPECT_GT(depth.status.counter("own_depths"), 100);  // rebuilt after the gap
}

TEST(FeatureDepthNode, ARangeSampledBeforeItsFrameIsMovedToTheFrame) {
  // Climbing 7 m/s (18 degrees); each range sampled 40 ms before its frame
  // (altimeter_mode latest takes the newest before the frame), 0.28 m shorter
  // than at the frame. Moved to the frame with the pairs' velocity, it gives
  // the exact motion; as sampled, every pair's scale is short by the 0.28 m
  // over the range. The level corridor is widened so that the altimeter
  // anchor's radius stays on it as the camera climbs to 260 m.
  vo::testing::TerrainSpec climb;
  climb.climb_per_frame_m = 0.5;
  climb.corridor_half_width_m = 200.0;
  vo::testing::TerrainSequence seq{climb};
  const NodeRun moved = run_node("feature_depth", kFrames, -1, 250, climb, {40000, true});
  const NodeRun as_sampled = run_node("feature_depth", kFrames, -1, 250, climb, {40000, false});
  expect_exact(moved, seq, 180, kFrames, -1);
  double along = 0, along_as_sampled = 0, travelled = 0;
  for (int k = 180; k <= kFrames; ++k) {
    const Eigen::Vector3d truth = seq.pair(k).translation;
    const vo_delta_t& m = moved.deltas.at(kStart + k * kPeriod);
    const vo_delta_t& a = as_sampled.deltas.at(kStart + k * kPeriod);
    along += Eigen::Vector3d(m.dx, m.dy, m.dz).dot(truth.normalized()) - truth.norm();
    along_as_sampled += Eigen::Vector3d(a.dx, a.dy, a.dz).dot(truth.normalized()) - truth.norm();
    travelled += truth.norm();
  }
  EXPECT_LT(std::abs(along) / travelled, 1e-6);
  EXPECT_LT(along_as_sampled / travelled, -5e-4) << "as sampled: the scale of a lower camera";
}

}  // namespace
}  // namespace nadir
