// VO_DELTA's sensor covariance (processes/vo_solver/delta_uncertainty.h):
// the model's Jacobian against finite differences of the real solver, and the
// propagated variance against a Monte Carlo of the real solver with perturbed
// attitudes and ranges on a synthetic pair.

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <random>
#include <stdexcept>
#include <vector>

#include "common/geometry.h"
#include "processes/vo_solver/delta_uncertainty.h"
#include "processes/vo_solver/translation_solver.h"
#include "tests/processes/vo_solver/synthetic_scene.h"

namespace nadir::vo {
namespace {

testing::SceneSpec pair_spec() {
  testing::SceneSpec s;
  s.height_m = 300.0;
  s.prev_roll = deg_to_rad(1.5);
  s.prev_pitch = deg_to_rad(-2.0);
  s.curr_roll = deg_to_rad(1.2);
  s.curr_pitch = deg_to_rad(-1.7);
  s.prev_yaw = 0.3;
  s.curr_yaw = 0.3 + deg_to_rad(0.4);
  s.translation = Eigen::Vector3d(2.1, 0.3, -0.2);
  s.num_features = 200;
  s.noise_px = 0.0;
  return s;
}

// Sets one sensor input of a pair.
void set_input(FramePair* pair, int k, double value) {
  switch (k) {
    case kPrevRoll: pair->prev_roll = value; break;
    case kPrevPitch: pair->prev_pitch = value; break;
    case kCurrRoll: pair->curr_roll = value; break;
    case kCurrPitch: pair->curr_pitch = value; break;
    case kPrevRange: pair->prev_range_m = value; break;
    case kCurrRange: pair->curr_range_m = value; break;
    default: throw std::invalid_argument("no such input");
  }
}

Eigen::Vector4d as_vector(const Estimate& e) {
  return Eigen::Vector4d(e.translation.x(), e.translation.y(), e.translation.z(), e.dyaw);
}

TEST(DeltaUncertainty, ModelJacobianMatchesFiniteDifferencesOfTheModel) {
  const testing::Scene scene = testing::make_scene(pair_spec());
  const Estimate est = solve(scene.pair, SolverOptions());
  ASSERT_EQ(est.quality & kNotConverged, 0);
  const SensorJacobian j = sensor_jacobian(scene.pair, est, true);
  ASSERT_TRUE(j.allFinite());
  // A coarser, one-sided difference of the model agrees with the central one.
  const SensorVector x0 = measured_inputs(scene.pair);
  for (int k = 0; k < kSensorInputs; ++k) {
    const double step = (k == kPrevRange || k == kCurrRange) ? 0.05 : 2e-4;
    SensorVector x = x0;
    x(k) += step;
    const Eigen::Vector4d fd =
        (delta_model(scene.pair, est, true, x) - delta_model(scene.pair, est, true, x0)) / step;
    for (int r = 0; r < 4; ++r) {
      EXPECT_NEAR(fd(r), j(r, k), 0.02 * j.col(k).cwiseAbs().maxCoeff() + 1e-9) << "row " << r << " input " << k;
    }
  }
  // Levelling: a pitch error of either frame moves dx by about the height.
  EXPECT_NEAR(std::abs(j(0, kPrevPitch)), 300.0, 45.0);
  EXPECT_NEAR(std::abs(j(0, kCurrPitch)), 300.0, 45.0);
  EXPECT_NEAR(std::abs(j(1, kPrevRoll)), 300.0, 45.0);
  // Range scale: the translation scales with the range.
  EXPECT_NEAR(j(0, kRangeScale), est.translation.x(), 0.05 * std::abs(est.translation.x()));
}

TEST(DeltaUncertainty, ModelJacobianMatchesTheSolversResponse) {
  const testing::Scene scene = testing::make_scene(pair_spec());
  const SolverOptions options;
  const Estimate est = solve(scene.pair, options);
  const SensorJacobian j = sensor_jacobian(scene.pair, est, options.symmetric_dz);
  const SensorVector x0 = measured_inputs(scene.pair);
  // dx, dy against the two frames' pitch and roll; all four against the ranges.
  for (int k = 0; k < kRangeScale; ++k) {
    const double step = (k == kPrevRange || k == kCurrRange) ? 0.5 : deg_to_rad(0.05);
    FramePair plus = scene.pair, minus = scene.pair;
    set_input(&plus, k, x0(k) + step);
    set_input(&minus, k, x0(k) - step);
    const Eigen::Vector4d solver_d = (as_vector(solve(plus, options)) - as_vector(solve(minus, options))) / (2 * step);
    // Horizontal: within 3 % of the larger of the two (300 m/rad levelling, metres per metre of range).
    const double scale = std::max(j.col(k).head<2>().cwiseAbs().maxCoeff(), solver_d.head<2>().cwiseAbs().maxCoeff());
    for (int r = 0; r < 2; ++r) EXPECT_NEAR(j(r, k), solver_d(r), 0.03 * scale) << "row " << r << " input " << k;
    // dz against the ranges (against the attitudes the solver's own forward/reverse gap stands in).
    if (k == kPrevRange || k == kCurrRange) {
      EXPECT_NEAR(j(2, k), solver_d(2), 0.05 * std::abs(solver_d(2)));
    }
  }
}

// The solver's heading change against each frame's roll and pitch is the
// turn of that frame's levelled frame, -sin(pitch) per radian of roll error
// (levelling_yaw_variance_rad2), at any bank: prev's with one sign, curr's
// with the other, so it telescopes over consecutive deltas.
TEST(DeltaUncertainty, DyawAgainstTheAttitudesIsTheTurnOfTheLevelledFrame) {
  const std::vector<std::array<double, 2>> roll_pitch_deg = {{0, 3}, {1.5, -2}, {10, 3}, {20, 2}, {-15, 5}};
  for (const auto& [roll, pitch] : roll_pitch_deg) {
    testing::SceneSpec spec = pair_spec();
    spec.prev_roll = deg_to_rad(roll);
    spec.prev_pitch = deg_to_rad(pitch);
    spec.curr_roll = deg_to_rad(roll + 0.3);
    spec.curr_pitch = deg_to_rad(pitch - 0.4);
    const testing::Scene scene = testing::make_scene(spec);
    const SolverOptions options;
    const SensorVector x0 = measured_inputs(scene.pair);
    Eigen::Vector4d response;
    for (int k = kPrevRoll; k <= kCurrPitch; ++k) {
      const double step = deg_to_rad(0.05);
      FramePair plus = scene.pair, minus = scene.pair;
      set_input(&plus, k, x0(k) + step);
      set_input(&minus, k, x0(k) - step);
      response(k) = (solve(plus, options).dyaw - solve(minus, options).dyaw) / (2 * step);
    }
    const double prev_turn = -std::sin(scene.pair.prev_pitch), curr_turn = std::sin(scene.pair.curr_pitch);
    EXPECT_NEAR(response(kPrevRoll), prev_turn, 0.02 * std::abs(prev_turn)) << roll << " " << pitch;
    EXPECT_NEAR(response(kCurrRoll), curr_turn, 0.02 * std::abs(curr_turn)) << roll << " " << pitch;
    EXPECT_NEAR(response(kPrevPitch), 0.0, 1e-3) << roll << " " << pitch;
    EXPECT_NEAR(response(kCurrPitch), 0.0, 1e-3) << roll << " " << pitch;
  }
}

// Mean dyaw error of the solver (rad) over `runs` copies of a pair over ground
// sloping by `ground_roll` (rad), with white roll/pitch noise (`sigma`, rad)
// on both frames, after taking out each copy's first-order heading term.
double mean_dyaw_beyond_first_order(double ground_roll, double sigma, int runs, double* standard_error) {
  testing::SceneSpec spec = pair_spec();
  spec.prev_roll = spec.curr_roll = deg_to_rad(0.5);
  spec.prev_pitch = spec.curr_pitch = deg_to_rad(3.0);
  spec.ground_roll = ground_roll;
  const testing::Scene scene = testing::make_scene(spec);
  const SolverOptions options;
  const double clean = solve(scene.pair, options).dyaw;
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, sigma);
  double sum = 0, sum2 = 0;
  for (int i = 0; i < runs; ++i) {
    FramePair p = scene.pair;
    const double prev_roll_error = noise(rng), curr_roll_error = noise(rng);
    p.prev_roll += prev_roll_error;
    p.prev_pitch += noise(rng);
    p.curr_roll += curr_roll_error;
    p.curr_pitch += noise(rng);
    const double first_order = std::sin(p.curr_pitch) * curr_roll_error - std::sin(p.prev_pitch) * prev_roll_error;
    const double e = solve(p, options).dyaw - clean - first_order;
    sum += e;
    sum2 += e * e;
  }
  *standard_error = std::sqrt(sum2 / runs) / std::sqrt(runs);
  return sum / runs;
}

// What the heading drift of the uncertainty model stands for
// (UncertaintyOptions::heading_drift_deg_per_s_per_deg): with noisy levelling
// the solver's dyaw is biased over sloping ground, in proportion to the slope,
// and not over level ground.
TEST(DeltaUncertainty, LevellingNoiseBiasesDyawOverSlopingGround) {
  double se = 0;
  const double level = mean_dyaw_beyond_first_order(0.0, deg_to_rad(0.3), 1000, &se);
  EXPECT_LT(std::abs(level), std::max(3 * se, deg_to_rad(0.0005)));
  const double sloped = mean_dyaw_beyond_first_order(0.05, deg_to_rad(0.3), 1000, &se);
  EXPECT_GT(sloped, 10 * se);  // +0.008 deg per pair
  EXPECT_NEAR(rad_to_deg(sloped), 0.008, 0.002);
  const double steeper = mean_dyaw_beyond_first_order(0.10, deg_to_rad(0.3), 1000, &se);
  EXPECT_NEAR(steeper / sloped, 2.0, 0.3);
}

// Sample covariance of the solver's (dx, dy, dz, dyaw) over `runs` perturbed
// copies of the pair: attitudes by roll_pitch_stddev, ranges by range_stddev.
Eigen::Matrix4d monte_carlo(const FramePair& pair, const SolverOptions& options, const UncertaintyOptions& u,
                            bool perturb_attitude, int runs) {
  const Estimate est = solve(pair, options);
  std::mt19937 rng(7);
  std::normal_distribution<double> angle(0.0, deg_to_rad(u.roll_pitch_stddev_deg));
  std::normal_distribution<double> unit(0.0, 1.0);
  Eigen::Matrix4d sum = Eigen::Matrix4d::Zero();
  for (int i = 0; i < runs; ++i) {
    FramePair p = pair;
    if (perturb_attitude) {
      p.prev_roll += angle(rng);
      p.prev_pitch += angle(rng);
      p.curr_roll += angle(rng);
      p.curr_pitch += angle(rng);
    }
    p.prev_range_m += u.range_stddev(p.prev_range_m) * unit(rng);
    p.curr_range_m += u.range_stddev(p.curr_range_m) * unit(rng);
    const Eigen::Vector4d e = as_vector(solve(p, options)) - as_vector(est);
    sum += e * e.transpose();
  }
  return sum / runs;
}

TEST(DeltaUncertainty, VarianceMatchesMonteCarloOfTheSolver) {
  const testing::Scene scene = testing::make_scene(pair_spec());
  const SolverOptions options;
  UncertaintyOptions u;  // the standard set: 0.05 deg, 0.1 m + 0.1 %; no model error terms
  u.relief_walk_along_m_per_sqrt_m = u.relief_walk_across_m_per_sqrt_m = 0.0;
  u.dyaw_model_stddev_deg = 0.0;
  const Estimate est = solve(scene.pair, options);
  const Eigen::Matrix4d predicted = sensor_covariance(scene.pair, est, options, u);
  // dx, dy: levelling and ranges. Within +-10 % (400 runs: the sample variance
  // itself is good to ~7 % at 1 sigma; the seed is fixed).
  const Eigen::Matrix4d measured = monte_carlo(scene.pair, options, u, true, 400);
  for (int r = 0; r < 2; ++r) EXPECT_NEAR(predicted(r, r) / measured(r, r), 1.0, 0.10) << "row " << r;
  // dyaw: the two frames' heading terms (and the ranges' small part); within
  // +-15 % (2 standard errors of the sample variance; 0.90 with this seed).
  // The grid model's own response gave a third of it here.
  EXPECT_NEAR(predicted(3, 3) / measured(3, 3), 1.0, 0.15);
  // dz against the ranges alone (its response to levelling is a known gap, delta_uncertainty.cc).
  u.roll_pitch_stddev_deg = 0.0;
  const Eigen::Matrix4d range_only = monte_carlo(scene.pair, options, u, false, 400);
  EXPECT_NEAR(sensor_covariance(scene.pair, est, options, u)(2, 2) / range_only(2, 2), 1.0, 0.10);
}

TEST(DeltaUncertainty, NothingAddedToAFailedSolveOrWhenDisabled) {
  const testing::Scene scene = testing::make_scene(pair_spec());
  Estimate failed;
  failed.translation = Eigen::Vector3d(std::nan(""), 0, 0);
  EXPECT_TRUE(sensor_covariance(scene.pair, failed, SolverOptions(), UncertaintyOptions()).isZero());
  UncertaintyOptions off;
  off.enabled = false;
  const Estimate est = solve(scene.pair, SolverOptions());
  EXPECT_TRUE(sensor_covariance(scene.pair, est, SolverOptions(), off).isZero());
  const Eigen::Matrix4d on = sensor_covariance(scene.pair, est, SolverOptions(), UncertaintyOptions());
  EXPECT_GT(on(0, 0), 0.0);
  EXPECT_TRUE(on.allFinite());
}

TEST(DeltaUncertainty, ModelErrorTermsAlongTheStepAndOnTheHeading) {
  const testing::Scene scene = testing::make_scene(pair_spec());
  const SolverOptions options;
  const Estimate est = solve(scene.pair, options);
  UncertaintyOptions without, with;
  without.relief_walk_along_m_per_sqrt_m = without.relief_walk_across_m_per_sqrt_m = 0.0;
  without.dyaw_model_stddev_deg = 0.0;
  with.relief_walk_along_m_per_sqrt_m = 0.05;
  with.relief_walk_across_m_per_sqrt_m = 0.01;
  with.dyaw_model_stddev_deg = 0.005;
  const Eigen::Matrix4d added =
      sensor_covariance(scene.pair, est, options, with) - sensor_covariance(scene.pair, est, options, without);
  // Along the horizontal step: 0.05^2 per metre of it; across: 0.01^2 per metre.
  const Eigen::Vector2d step = est.translation.head<2>();
  const Eigen::Vector2d along = step.normalized();
  const Eigen::Vector2d across(-along.y(), along.x());
  EXPECT_NEAR(along.dot(added.topLeftCorner<2, 2>() * along), 0.05 * 0.05 * step.norm(), 1e-12);
  EXPECT_NEAR(across.dot(added.topLeftCorner<2, 2>() * across), 0.01 * 0.01 * step.norm(), 1e-12);
  EXPECT_NEAR(across.dot(added.topLeftCorner<2, 2>() * along), 0.0, 1e-12);
  EXPECT_NEAR(added(2, 2), 0.0, 1e-15);
  EXPECT_NEAR(added(3, 3), std::pow(deg_to_rad(0.005), 2), 1e-15);
  // Summed over the deltas of a straight line it is a random walk in the
  // distance: n steps of s metres give walk^2 * n * s whatever the frame rate.
  EXPECT_NEAR(10 * relief_walk_covariance(Eigen::Vector2d(2.0, 0.0), Variant::kPaper, with)(0, 0),
              20 * relief_walk_covariance(Eigen::Vector2d(1.0, 0.0), Variant::kPaper, with)(0, 0), 1e-15);
  EXPECT_TRUE(relief_walk_covariance(Eigen::Vector2d::Zero(), Variant::kPaper, with).isZero());
}

// feature_depth carries its own walks; the one-plane variants' do not touch it.
TEST(DeltaUncertainty, FeatureDepthHasItsOwnModelError) {
  UncertaintyOptions u;
  u.relief_walk_along_m_per_sqrt_m = 0.05;
  u.relief_walk_across_m_per_sqrt_m = 0.01;
  u.feature_depth_walk_along_m_per_sqrt_m = 0.004;
  u.feature_depth_walk_across_m_per_sqrt_m = 0.002;
  const Eigen::Vector2d step(3.0, 4.0);  // 5 m
  const Eigen::Vector2d along = step.normalized(), across(-along.y(), along.x());
  for (const Variant v : {Variant::kPaper, Variant::kLevelGround, Variant::kHomography, Variant::kFlow}) {
    const Eigen::Matrix2d c = relief_walk_covariance(step, v, u);
    EXPECT_NEAR(along.dot(c * along), 0.05 * 0.05 * 5.0, 1e-15) << variant_name(v);
    EXPECT_NEAR(across.dot(c * across), 0.01 * 0.01 * 5.0, 1e-15) << variant_name(v);
  }
  const Eigen::Matrix2d own = relief_walk_covariance(step, Variant::kFeatureDepth, u);
  EXPECT_NEAR(along.dot(own * along), 0.004 * 0.004 * 5.0, 1e-15);
  EXPECT_NEAR(across.dot(own * across), 0.002 * 0.002 * 5.0, 1e-15);
  EXPECT_NEAR(across.dot(own * along), 0.0, 1e-15);

  // The relief part: the anchor's model variance x height x heights, along the step only.
  Estimate est;
  est.anchor_model_variance = 4e-5;
  est.altitude_m = 120.0;
  u.feature_depth_relief_heights = 0.0;
  EXPECT_EQ(relief_along_variance_per_m(est, Variant::kFeatureDepth, u), 0.0);  // off
  u.feature_depth_relief_heights = 0.5;
  const double relief = relief_along_variance_per_m(est, Variant::kFeatureDepth, u);
  EXPECT_NEAR(relief, 0.5 * 4e-5 * 120.0, 1e-15);
  EXPECT_EQ(relief_along_variance_per_m(est, Variant::kPaper, u), 0.0);
  const Eigen::Matrix2d rough = relief_walk_covariance(step, Variant::kFeatureDepth, u, relief);
  EXPECT_NEAR(along.dot(rough * along), (0.004 * 0.004 + relief) * 5.0, 1e-15);
  EXPECT_NEAR(across.dot(rough * across), 0.002 * 0.002 * 5.0, 1e-15);
  est.altitude_m = std::nan("");
  EXPECT_EQ(relief_along_variance_per_m(est, Variant::kFeatureDepth, u), 0.0);
}

// A feature_depth pair that its own depths did not solve (no depths yet: the
// paper's model alone) carries the one-plane walk; one they solved carries
// feature_depth's own, with the relief part from its anchor.
TEST(DeltaUncertainty, FeatureDepthPairSolvedByThePaperAloneCarriesThePapersWalk) {
  const testing::Scene scene = testing::make_scene(pair_spec());
  SolverOptions options;
  options.variant = Variant::kFeatureDepth;
  Estimate est = solve(scene.pair, options);
  ASSERT_FALSE(est.own_depths_used);  // a single pair: no track has a depth
  UncertaintyOptions u;
  u.relief_walk_along_m_per_sqrt_m = 0.05;
  u.relief_walk_across_m_per_sqrt_m = 0.01;
  u.feature_depth_walk_along_m_per_sqrt_m = 0.004;
  u.feature_depth_walk_across_m_per_sqrt_m = 0.002;
  u.feature_depth_relief_heights = 0.5;
  est.anchor_model_variance = 1e-5;  // not the paper's: left out
  const Eigen::Matrix4d paper_alone = sensor_covariance(scene.pair, est, options, u);
  est.own_depths_used = true;
  const Eigen::Matrix4d own = sensor_covariance(scene.pair, est, options, u);
  const Eigen::Vector2d step = est.translation.head<2>();
  const Eigen::Vector2d along = step.normalized(), across(-along.y(), along.x());
  const Eigen::Matrix2d difference = (paper_alone - own).topLeftCorner<2, 2>();
  const double relief = 0.5 * 1e-5 * est.altitude_m;
  EXPECT_NEAR(along.dot(difference * along), (0.05 * 0.05 - 0.004 * 0.004 - relief) * step.norm(), 1e-12);
  EXPECT_NEAR(across.dot(difference * across), (0.01 * 0.01 - 0.002 * 0.002) * step.norm(), 1e-12);
  const Eigen::Matrix2d rest = (paper_alone - own).bottomRightCorner<2, 2>();
  EXPECT_NEAR(rest.norm(), 0.0, 1e-15);
}

// Each frame's levelling term is its attitude's error: the white noise scaled
// by the share the attitude policy left in that frame (half where two INS
// samples were averaged), the correlated part whole.
TEST(DeltaUncertainty, EachFramesLevellingTermCarriesItsShareOfTheWhiteNoise) {
  const testing::Scene scene = testing::make_scene(pair_spec());
  const SolverOptions options;
  const Estimate est = solve(scene.pair, options);
  UncertaintyOptions u;
  u.roll_pitch_stddev_deg = 0.3;
  u.roll_pitch_correlated_stddev_deg = 0.1;
  FramePair halved = scene.pair;
  halved.prev_attitude_noise_share = 0.5;
  const Eigen::Matrix4d whole = sensor_covariance(scene.pair, est, options, u);
  const Eigen::Matrix4d less = sensor_covariance(halved, est, options, u);
  const double white = deg_to_rad(0.3), correlated = deg_to_rad(0.1);
  EXPECT_NEAR(u.frame_roll_pitch_stddev_rad(0.5), std::sqrt(0.5 * white * white + correlated * correlated), 1e-15);
  EXPECT_NEAR(u.frame_roll_pitch_stddev_rad(1.0), std::hypot(white, correlated), 1e-15);
  // prev's footprint term (height est.altitude_m) loses half the white variance, on dx and dy alike.
  const double lost = est.altitude_m * est.altitude_m * 0.5 * white * white;
  EXPECT_NEAR(whole(0, 0) - less(0, 0), lost, 1e-9 * lost);
  EXPECT_NEAR(whole(1, 1) - less(1, 1), lost, 1e-9 * lost);
  // prev's heading term: sin(prev pitch)^2 times the same.
  const double lost_heading = std::pow(std::sin(scene.pair.prev_pitch), 2) * 0.5 * white * white;
  EXPECT_NEAR(whole(3, 3) - less(3, 3), lost_heading, 1e-6 * lost_heading);
  // The time-reversed pair swaps the two frames' shares with their attitudes.
  const FramePair reversed = reversed_in_time(halved);
  EXPECT_EQ(reversed.curr_attitude_noise_share, 0.5);
  EXPECT_EQ(reversed.prev_attitude_noise_share, 1.0);
}

TEST(DeltaUncertainty, FlowVariantCarriesTheInsHeadingNoise) {
  const testing::Scene scene = testing::make_scene(pair_spec());
  SolverOptions flow;
  flow.variant = Variant::kFlow;
  const Estimate est = solve(scene.pair, flow);
  UncertaintyOptions u;
  u.yaw_stddev_deg = 0.2;
  const Eigen::Matrix4d cov = sensor_covariance(scene.pair, est, flow, u);
  EXPECT_GE(cov(3, 3), 2 * std::pow(deg_to_rad(0.2), 2) * 0.999);
}

TEST(DeltaUncertainty, CheckNamesTheField) {
  UncertaintyOptions u;
  u.roll_pitch_stddev_deg = -1;
  try {
    u.Check();
    FAIL() << "no throw";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("roll_pitch_stddev_deg"), std::string::npos);
  }
  u = UncertaintyOptions();
  u.range_scale_stddev = 0.9;
  EXPECT_THROW(u.Check(), std::invalid_argument);
}

}  // namespace
}  // namespace nadir::vo
