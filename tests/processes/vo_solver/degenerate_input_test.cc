// Degenerate and adversarial frame pairs through every solver variant: all
// features on a line, at one point, zero baseline (hover), a handful of
// features, near-zero, negative and huge ranges, attitudes at the edge of the
// physical range, and random mixtures. Whatever comes in, every published
// field must be finite, and an estimate that is not good must say so in its
// quality bits ("nothing non-finite is ever published").
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>

#include "processes/vo_solver/translation_solver.h"
#include "tests/processes/vo_solver/synthetic_scene.h"

namespace nadir::vo {
namespace {

std::string first_non_finite(const Estimate& e) {
  if (!e.translation.allFinite()) return "translation";
  if (!std::isfinite(e.dyaw)) return "dyaw";
  if (!std::isfinite(e.ground_roll) || !std::isfinite(e.ground_pitch)) return "ground attitude";
  if (!std::isfinite(e.altitude_m)) return "altitude_m";
  if (!e.covariance.allFinite()) return "covariance";
  if (!std::isfinite(e.residual_rms_px)) return "residual_rms_px";
  return "";
}

const Variant kVariants[] = {Variant::kPaper, Variant::kLevelGround, Variant::kHomography, Variant::kFlow};

void expect_finite_everywhere(const FramePair& pair, const std::string& what, bool must_be_flagged) {
  for (const Variant v : kVariants) {
    SolverOptions options;
    options.variant = v;
    const Estimate e = solve(pair, options);
    const std::string bad = first_non_finite(e);
    EXPECT_TRUE(bad.empty()) << what << " (" << variant_name(v) << "): non-finite " << bad;
    if (must_be_flagged) {
      EXPECT_NE(e.quality, 0) << what << " (" << variant_name(v) << "): not flagged";
    }
  }
}

FramePair good_pair() {
  testing::SceneSpec spec;
  spec.num_features = 200;
  return testing::make_scene(spec).pair;
}

TEST(DegenerateInput, FeaturesOnOneLine) {
  FramePair pair = good_pair();
  for (size_t i = 0; i < pair.prev_norm.size(); ++i) {
    const double s = -0.5 + static_cast<double>(i) / static_cast<double>(pair.prev_norm.size());
    pair.prev_norm[i] = Eigen::Vector2d(s, 0.2 * s);
    pair.curr_norm[i] = Eigen::Vector2d(s - 0.01, 0.2 * s);
  }
  expect_finite_everywhere(pair, "collinear features", false);
}

TEST(DegenerateInput, FeaturesAtOnePoint) {
  FramePair pair = good_pair();
  for (size_t i = 0; i < pair.prev_norm.size(); ++i) {
    pair.prev_norm[i] = Eigen::Vector2d(0.1, -0.05);
    pair.curr_norm[i] = Eigen::Vector2d(0.09, -0.05);
  }
  expect_finite_everywhere(pair, "one point", false);
}

TEST(DegenerateInput, ZeroBaselineHover) {
  FramePair pair = good_pair();
  pair.curr_norm = pair.prev_norm;
  expect_finite_everywhere(pair, "zero baseline", false);
}

TEST(DegenerateInput, NearFeaturelessIsFlagged) {
  for (const int n : {0, 1, 2, 3, 5, 7}) {
    FramePair pair = good_pair();
    pair.prev_norm.resize(static_cast<size_t>(n));
    pair.curr_norm.resize(static_cast<size_t>(n));
    expect_finite_everywhere(pair, std::to_string(n) + " features", true);
  }
}

TEST(DegenerateInput, RangesAndAttitudesAtTheEdges) {
  const double ranges[] = {0.0, -5.0, 1e-9, 1e-3, 1e6, 1e12};
  for (const double r : ranges) {
    FramePair pair = good_pair();
    pair.prev_range_m = r;
    pair.curr_range_m = r;
    expect_finite_everywhere(pair, "range " + std::to_string(r), false);
  }
  const double angles[] = {M_PI_2, -M_PI_2, M_PI, 1.5, -1.5};
  for (const double a : angles) {
    FramePair pair = good_pair();
    pair.curr_pitch = a;
    pair.prev_roll = a;
    expect_finite_everywhere(pair, "attitude " + std::to_string(a), false);
  }
  FramePair pair = good_pair();
  pair.curr_beam_body = Eigen::Vector3d::Zero();
  expect_finite_everywhere(pair, "zero beam", false);
  pair = good_pair();
  pair.prev_beam_body = Eigen::Vector3d(1, 0, 0);  // horizontal: never meets level ground
  expect_finite_everywhere(pair, "horizontal beam", false);
}

// Random mixtures of the above with finite but extreme coordinates.
TEST(DegenerateInput, RandomPairsGiveFiniteEstimates) {
  std::mt19937 rng(23);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::uniform_int_distribution<int> count(0, 60);
  const double scales[] = {1e-9, 1e-3, 0.5, 10.0, 1e4};
  for (int trial = 0; trial < 300; ++trial) {
    FramePair pair;
    const int n = count(rng);
    const double scale = scales[trial % 5];
    for (int i = 0; i < n; ++i) {
      pair.prev_norm.emplace_back(scale * unit(rng), scale * unit(rng));
      const Eigen::Vector2d step = trial % 3 == 0 ? Eigen::Vector2d::Zero() : Eigen::Vector2d(unit(rng), unit(rng));
      pair.curr_norm.push_back(pair.prev_norm.back() + 0.01 * scale * step);
    }
    pair.prev_range_m = std::pow(10.0, 4.0 * unit(rng) + 1.0);
    pair.curr_range_m = trial % 7 == 0 ? 0.0 : pair.prev_range_m * (1.0 + 0.5 * unit(rng));
    pair.prev_roll = 0.5 * unit(rng);
    pair.curr_pitch = 0.5 * unit(rng);
    pair.curr_yaw = M_PI * unit(rng);
    expect_finite_everywhere(pair, "random pair " + std::to_string(trial), false);
    if (::testing::Test::HasFailure()) break;  // one report is enough
  }
}

}  // namespace
}  // namespace nadir::vo
