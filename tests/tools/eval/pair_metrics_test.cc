#include "tools/eval/pair_metrics.h"

#include <gtest/gtest.h>

#include <cmath>

namespace nadir {
namespace {

ground_truth_t truth(int64_t utime, double n, double e, double yaw) {
  ground_truth_t g{};
  g.utime = utime;
  g.kind = ground_truth_t::KIND_FRAME;
  g.position_ned[0] = n;
  g.position_ned[1] = e;
  g.yaw = yaw;
  return g;
}

vo_delta_t delta(int64_t prev, int64_t curr, double dx, double dy, double dyaw, int32_t quality) {
  vo_delta_t d{};
  d.prev_utime = prev;
  d.utime = curr;
  d.dx = dx;
  d.dy = dy;
  d.dyaw = dyaw;
  d.quality = quality;
  return d;
}

// Heading east (yaw 90 deg), 30 m east then a half turn; 10 m west.
TEST(PairMetrics, StepInThePreviousLevelFrame) {
  const std::vector<ground_truth_t> t = {truth(0, 0, 0, M_PI / 2), truth(5000000, 0, 30, M_PI / 2),
                                         truth(10000000, 0, 20, -M_PI / 2)};
  // Pair 1: 30 m forward estimated as 31 m forward and 1 m right: error hypot(1, 1).
  // Pair 2: heading east, the aircraft moved 10 m west: x = -10 in the frame of the previous frame.
  // Pair 3: too few features (unsolved).
  const std::vector<vo_delta_t> d = {delta(0, 5000000, 31, 1, 0, 0), delta(5000000, 10000000, -10, 0, M_PI, 64),
                                     delta(5000000, 10000000, 0, 0, 0, 1)};
  const PairMetrics m = evaluate_pairs(d, t, nullptr);
  ASSERT_EQ(m.pairs, 3);
  EXPECT_EQ(m.solved, 2);  // high residual counts as solved (flagged)
  EXPECT_NEAR(m.solved_pct, 200.0 / 3.0, 1e-9);
  ASSERT_EQ(m.samples.size(), 3u);
  EXPECT_NEAR(m.samples[0].step_m, 30.0, 1e-9);
  EXPECT_NEAR(m.samples[0].error_h_m, std::sqrt(2.0), 1e-9);
  EXPECT_NEAR(m.samples[0].error_pct, 100.0 * std::sqrt(2.0) / 30.0, 1e-9);
  EXPECT_NEAR(m.samples[1].error_h_m, 0.0, 1e-9);
  EXPECT_NEAR(std::fabs(m.samples[1].true_dyaw_deg), 180.0, 1e-9);
  EXPECT_NEAR(std::fabs(m.samples[1].dyaw_deg), 180.0, 1e-9);
  EXPECT_FALSE(m.samples[2].solved);
  EXPECT_EQ(m.measured, 2);
}

TEST(PairMetrics, PairsOutsideTheTruthAreNotCounted) {
  // (A pair starting 0.1 s before the truth: beyond what truth_at extrapolates.)
  const std::vector<ground_truth_t> t = {truth(1000, 0, 0, 0), truth(2000, 1, 0, 0)};
  const PairMetrics m = evaluate_pairs({delta(-100000, 2000, 1, 0, 0, 0), delta(1000, 2000, 1, 0, 0, 0)}, t, nullptr);
  EXPECT_EQ(m.pairs, 1);
  EXPECT_EQ(m.solved, 1);
  EXPECT_NEAR(m.error_pct_median, 0.0, 1e-12);
  EXPECT_FALSE(m.footprints);
  EXPECT_TRUE(std::isnan(m.samples[0].overlap_pct));
}

// 601 x 401 pixels, f = 500 px, camera x = body forward: at 100 m above
// level ground the footprint is 120 m along track by 80 m across.
TEST(PairMetrics, FootprintsTellPairsThatShareNoGround) {
  const CameraModel camera = CameraModel::pinhole(601, 401, 500);
  std::vector<ground_truth_t> t = {truth(0, 0, 0, 0), truth(1000000, 60, 0, 0), truth(2000000, 60, 0, M_PI),
                                   truth(3000000, 300, 0, M_PI)};
  for (ground_truth_t& g : t) {
    g.position_ned[2] = -100;
    g.height_agl_m = 100;
  }
  // Half a footprint ahead (solved), a half turn in place (solved), 240 m on
  // (footprints apart, unsolved: too few features).
  const PairMetrics m = evaluate_pairs(
      {delta(0, 1000000, 60, 0, 0, 0), delta(1000000, 2000000, 0, 0, M_PI, 0), delta(2000000, 3000000, 0, 0, 0, 1)},
      t, &camera);
  ASSERT_TRUE(m.footprints);
  ASSERT_EQ(m.samples.size(), 3u);
  EXPECT_NEAR(m.samples[0].overlap_pct, 50.0, 1e-3);
  EXPECT_NEAR(m.samples[1].overlap_pct, 100.0, 1e-3);
  EXPECT_NEAR(m.samples[2].overlap_pct, 0.0, 1e-9);
  EXPECT_EQ(m.apart, 1);
  EXPECT_EQ(m.overlapping_solved, 2);
  EXPECT_NEAR(m.overlapping_solved_pct, 100.0, 1e-9);
  EXPECT_NEAR(m.solved_pct, 200.0 / 3.0, 1e-9);
}

// A pair solved backwards (its dyaw half a turn from the INS's) carries
// QUALITY_HEADING_CONTRADICTS: not solved, counted under its bit, and not in
// the per-pair error. Under a mask without the bit (a replay configured so)
// it counts as solved, as yaw fusion then used it.
TEST(PairMetrics, HeadingContradictionIsNotSolved) {
  const std::vector<ground_truth_t> t = {truth(0, 0, 0, 0), truth(1000000, 20, 0, 0), truth(2000000, 40, 0, 0),
                                         truth(3000000, 60, 0, 0)};
  const int32_t contradicts = vo_delta_t::QUALITY_HEADING_CONTRADICTS;
  const std::vector<vo_delta_t> d = {delta(0, 1000000, 20, 0, 0, 0),
                                     delta(1000000, 2000000, -22, 0, M_PI, contradicts),
                                     delta(2000000, 3000000, 0, 0, 0, vo_delta_t::QUALITY_TOO_FEW_FEATURES)};
  const PairMetrics m = evaluate_pairs(d, t, nullptr);
  EXPECT_EQ(m.reject_quality_mask, kUnsolvedQualityMask);
  EXPECT_TRUE(kUnsolvedQualityMask & contradicts);
  EXPECT_EQ(m.solved, 1);
  EXPECT_FALSE(m.samples[1].solved);
  EXPECT_EQ(m.measured, 1);
  EXPECT_NEAR(m.error_pct_p90, 0.0, 1e-9) << "the backwards step is not in the per-pair error";
  EXPECT_EQ(m.not_solved_by_bit[kVoQualityBits - 1], 1);
  EXPECT_EQ(m.not_solved_by_bit[0], 1);
  EXPECT_EQ(format_not_solved(m), "1 too_few_features, 1 heading_contradicts");

  const PairMetrics old_mask = evaluate_pairs(d, t, nullptr, 1 | 2 | 8 | 16);
  EXPECT_EQ(old_mask.solved, 2);
  EXPECT_NEAR(old_mask.error_pct_p90, 210.0, 1e-9);  // 42 m off a 20 m step
  EXPECT_EQ(format_not_solved(old_mask), "1 too_few_features");
}

}  // namespace
}  // namespace nadir
