// The feature_depth variant through the node on a memq:// bus: per-track
// depths keyed by TRACKS' track ids give the exact motion over non-planar
// ground, and a TRACKS frame gap clears them (that pair is the paper's).

#include <gtest/gtest.h>

#include <map>
#include <string>
#include <vector>

#include "common/channels.h"
#include "common/config.h"
#include "common/lcm_bus.h"
#include "nadir/altimeter_t.hpp"
#include "nadir/ins_t.hpp"
#include "nadir/tracks_t.hpp"
#include "nadir/vo_delta_t.hpp"
#include "processes/vo_solver/vo_solver_node.h"
#include "tests/processes/vo_solver/terrain_sequence.h"

namespace nadir {
namespace {

constexpr int64_t kStart = 1700000000000000;
constexpr int64_t kPeriod = 71429;

std::string config(const std::string& variant) {
  return R"(
camera: {width: 612, height: 512, fx: 398.79, fy: 398.79, cx: 305.5, cy: 255.5, mount_rpy_deg: [0, 0, 0]}
altimeter: {beam_body: [0, 0, 1]}
vo_solver:
  variant: )" + variant + R"(
  feature_depth: {triangulation_noise_px: 0.001, patch_feature_weight: 0}
)";
}

struct NodeRun {
  std::map<int64_t, vo_delta_t> deltas;
  StatusReport status;
};

// INS and altimeter samples exactly at the frame times (so the node's
// interpolation returns them exactly), TRACKS with the points' indices as ids.
NodeRun run_node(const std::string& variant, int frames, int gap_frame) {
  vo::testing::TerrainSequence seq{vo::testing::TerrainSpec{}};
  LcmBusOptions options;
  options.url = "memq://";
  LcmBus bus(options);
  std::unique_ptr<Node> node = make_vo_solver_node(Config::parse(config(variant), "feature depth node test"), bus);
  NodeRun result;
  bus.subscribe<vo_delta_t>(channels::kVoDelta, [&](const vo_delta_t& m) { result.deltas[m.utime] = m; });
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
    alt.utime = t;
    alt.range_m = k > 0 ? seq.pair(k).pair.curr_range_m : seq.pair(1).pair.prev_range_m;
    alt.beam_body[2] = 1.0;
    alt.signal_quality = 1.0f;
    alt.validity = altimeter_t::VALID_OK;
    bus.publish(channels::kAltimeter, alt);
    deliver();
  }
  for (int k = 0; k <= frames; ++k) {
    tracks_t m{};
    m.utime = kStart + k * kPeriod;
    m.prev_utime = k == 0 ? 0 : m.utime - kPeriod;
    m.frame_counter = k;
    m.width = 612;
    m.height = 512;
    m.flags = k == 0 ? tracks_t::FLAG_FIRST_FRAME : (k == gap_frame ? tracks_t::FLAG_FRAME_GAP : 0);
    if (k > 0) {
      const vo::testing::SequencePair sp = seq.pair(k);
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

double counter(const StatusReport& r, const std::string& name) {
  for (const auto& [key, value] : r.counters) {
    if (key == name) return value;
  }
  ADD_FAILURE() << "no counter " << name;
  return -1;
}

TEST(FeatureDepthNode, ExactOverReliefAndClearedByAFrameGap) {
  vo::testing::TerrainSequence seq{vo::testing::TerrainSpec{}};
  constexpr int kGap = 45;
  const NodeRun depth = run_node("feature_depth", 50, kGap);
  const NodeRun paper = run_node("paper", 50, kGap);
  ASSERT_EQ(depth.deltas.size(), 51u);
  double worst_paper = 0;
  for (int k = 30; k < kGap; ++k) {
    const vo_delta_t& d = depth.deltas.at(kStart + k * kPeriod);
    const vo::testing::SequencePair truth = seq.pair(k);
    EXPECT_EQ(d.variant, "feature_depth");
    EXPECT_EQ(d.quality, 0) << "frame " << k;
    // Through the node it settles at ~1e-4 m, not the 1e-6 of the direct
    // solver+map run (feature_depth_test.cc): the paper variant's node output
    // differs from its direct solve of the same pair by as much (1.5e-4 m at
    // frame 30), so the node's synchronised inputs (INS/altimeter as fed
    // here) are not bit-identical to the pair's; not yet traced.
    EXPECT_NEAR(d.dx, truth.translation.x(), 1e-3) << "frame " << k;
    EXPECT_NEAR(d.dy, truth.translation.y(), 1e-3) << "frame " << k;
    EXPECT_NEAR(d.dz, truth.translation.z(), 1e-3) << "frame " << k;
    EXPECT_NEAR(d.dyaw, truth.dyaw, 1e-5) << "frame " << k;
    const vo_delta_t& p = paper.deltas.at(kStart + k * kPeriod);
    worst_paper = std::max(worst_paper, std::hypot(p.dx - truth.translation.x(), p.dy - truth.translation.y()));
  }
  EXPECT_GT(worst_paper, 1e-2);
  // The gap frame: flagged, no own depth used (the paper's own solve), map cleared.
  const vo_delta_t& at_gap = depth.deltas.at(kStart + kGap * kPeriod);
  const vo_delta_t& paper_gap = paper.deltas.at(kStart + kGap * kPeriod);
  EXPECT_TRUE(at_gap.quality & vo_delta_t::QUALITY_FRAME_GAP);
  EXPECT_EQ(at_gap.dx, paper_gap.dx);
  EXPECT_EQ(at_gap.dy, paper_gap.dy);
  EXPECT_GE(counter(depth.status, "own_depth_resets"), 1);
  EXPECT_GT(counter(depth.status, "own_depths"), 100);  // rebuilt after the gap
}

}  // namespace
}  // namespace nadir
