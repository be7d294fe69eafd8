// Two depth layers in view (30 % of the points on tree tops 20 % of h above a
// lawn): the outlier cut must not grow to let them in, and where they are too
// close to the plane's prediction to be cut, QUALITY_DEPTH_LAYERS must say so.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "common/config.h"
#include "common/geometry.h"
#include "processes/vo_solver/solver_support.h"
#include "processes/vo_solver/vo_solver_options.h"
#include "processes/vo_solver/translation_solver.h"
#include "tests/processes/vo_solver/synthetic_scene.h"

namespace nadir::vo {
namespace {

using testing::make_scene;
using testing::Scene;
using testing::SceneSpec;

// 40 m over a gentle slope, 0.5 px noise, 5 % gross outliers, 30 % of the
// points 8 m (20 % of h) above the plane; `step_m` forward between frames.
SceneSpec lawn_and_trees(double step_m, uint32_t seed) {
  SceneSpec s;
  s.height_m = 40.0;
  s.ground_roll = deg_to_rad(4.0);
  s.ground_pitch = deg_to_rad(-5.0);
  s.prev_roll = deg_to_rad(2.0);
  s.prev_pitch = deg_to_rad(-1.0);
  s.curr_roll = deg_to_rad(1.0);
  s.translation = Eigen::Vector3d(step_m, 0.2, -0.1);
  s.num_features = 200;
  s.noise_px = 0.5;
  s.outlier_fraction = 0.05;
  s.raised_fraction = 0.3;
  s.raised_height_m = 8.0;
  s.seed = seed;
  return s;
}

int raised_inliers(const Scene& scene, const Estimate& est) {
  int n = 0;
  for (size_t i = 0; i < scene.is_raised.size(); ++i) n += scene.is_raised[i] && est.weights[i] > 0;
  return n;
}

// A 4 m step: the tree tops are off the plane's prediction by ~25 % of their
// ~40 px flow, at the 10 px cap. Without the cap the robust sigma of a 30 %
// share of them lets them in (measured over these 10 seeds: ~44 of ~60 per
// pair, translation RMS 0.25 m against 0.02 m with the cap).
TEST(DepthLayers, ThresholdCapKeepsTreeTopsOut) {
  double capped_sq = 0, uncapped_sq = 0;
  for (uint32_t seed = 1; seed <= 10; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    const Scene scene = make_scene(lawn_and_trees(4.0, seed));
    const Estimate est = solve(scene.pair, SolverOptions{});
    EXPECT_EQ(est.quality, 0);
    EXPECT_LE(raised_inliers(scene, est), 4);
    EXPECT_LE((est.translation - scene.translation).norm(), 0.1);
    capped_sq += (est.translation - scene.translation).squaredNorm();
    SolverOptions uncapped;
    uncapped.max_threshold_px = 1000;
    uncapped_sq += (solve(scene.pair, uncapped).translation - scene.translation).squaredNorm();
  }
  EXPECT_GT(uncapped_sq, 25 * capped_sq) << "the cap is what keeps the estimate on the plane";
}

// A 2 m step: the tree tops are off by ~5 px, inside the cut, so they stay
// inliers; the residual stays under the 3 px flag (2.6 px), the layer flag
// fires (measured: 9 of 10 seeds).
TEST(DepthLayers, TwoLayersInsideTheCutAreFlagged) {
  int flagged = 0;
  for (uint32_t seed = 1; seed <= 10; ++seed) {
    const Scene scene = make_scene(lawn_and_trees(2.0, seed));
    const Estimate est = solve(scene.pair, SolverOptions{});
    EXPECT_GT(raised_inliers(scene, est), 30) << "seed " << seed;
    flagged += (est.quality & kDepthLayers) != 0;
  }
  EXPECT_GE(flagged, 9);
}

// One plane with 30 % gross outliers, from a 1 m to a 14 m step: never flagged.
TEST(DepthLayers, OnePlaneIsNotFlagged) {
  for (double step : {1.0, 3.0, 14.0}) {
    for (uint32_t seed = 1; seed <= 30; ++seed) {
      SceneSpec s = lawn_and_trees(step, seed);
      s.raised_fraction = 0;
      s.outlier_fraction = 0.3;
      const Estimate est = solve(make_scene(s).pair, SolverOptions{});
      EXPECT_EQ(est.quality & kDepthLayers, 0) << "step " << step << " seed " << seed;
    }
  }
}

// One plane seen with a levelling error of a few degrees (white INS roll/pitch
// noise of 1-3 deg): the model's own error spreads the reprojection errors so
// that the robust cut is wider than the cap, and the cap cuts a tail of corner
// features, not a layer. The cap is lifted: the estimate is the uncapped one
// (what the levelling error moves, h * (eps_prev - eps_curr), must be absorbed
// the same way in every pair, or the steps stop telescoping), and the fit
// converges.
TEST(DepthLayers, ACapCuttingTheTailOfOnePlaneIsLifted) {
  int in_regime = 0;
  double sum_sq = 0, sum_var = 0;
  for (uint32_t seed = 1; seed <= 10; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    SceneSpec s;
    s.height_m = 300.0;
    s.ground_roll = deg_to_rad(2.0);
    s.ground_pitch = deg_to_rad(-3.0);
    s.prev_roll = deg_to_rad(4.0);
    s.curr_roll = deg_to_rad(-2.0);
    s.prev_pitch = deg_to_rad(-3.0);
    s.curr_pitch = deg_to_rad(1.0);
    s.translation = Eigen::Vector3d(5.0, 0.3, -0.2);
    s.noise_px = 0.5;
    s.outlier_fraction = 0.05;
    s.seed = seed;
    Scene scene = make_scene(s);
    // The INS's levelling errors: 1.5 deg of roll and -1.5 deg of pitch between the frames.
    scene.pair.prev_roll += deg_to_rad(1.0);
    scene.pair.curr_roll -= deg_to_rad(0.5);
    scene.pair.prev_pitch -= deg_to_rad(0.5);
    scene.pair.curr_pitch += deg_to_rad(1.0);
    SolverOptions uncapped;
    uncapped.max_threshold_px = 1000;
    const Estimate reference = solve(scene.pair, uncapped);
    const Estimate est = solve(scene.pair, SolverOptions{});
    const std::vector<double> errors = estimate_reprojection_errors(scene.pair, reference, uncapped.focal_px);
    std::vector<double> sorted = errors;
    std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
    const double wide = 4.0 * 1.4826 * sorted[sorted.size() / 2];
    const auto tail = std::count_if(errors.begin(), errors.end(), [&](double e) { return e > 10.0 && e < wide; });
    in_regime += tail > 0 && tail < 0.15 * static_cast<double>(errors.size());
    EXPECT_EQ(est.quality & kNotConverged, 0);
    sum_sq += (est.translation - reference.translation).head<2>().squaredNorm();
    sum_var += reference.covariance(0, 0) + reference.covariance(1, 1);
  }
  EXPECT_GE(in_regime, 8) << "the scene must put a tail of features between the cap and the robust cut";
  // Two robust fits from different starts stop within their tolerance of
  // different points; capped for good, the gap was 0.79 sigma rms over these
  // seeds (lifted: 0.33).
  EXPECT_LE(std::sqrt(sum_sq / sum_var), 0.5);
}

TEST(DepthLayers, OptionsAreChecked) {
  SolverOptions options;
  options.max_threshold_px = options.min_threshold_px / 2;
  EXPECT_THROW(options.Check(), std::invalid_argument);
  options = SolverOptions{};
  options.layers.min_separation_sigma = 1.0;
  EXPECT_THROW(options.Check(), std::invalid_argument);
  options = SolverOptions{};
  options.layers.min_fraction = 0.7;
  EXPECT_THROW(options.Check(), std::invalid_argument);
  EXPECT_NO_THROW(SolverOptions{}.Check());
}

TEST(DepthLayers, ConfigKeysAreReadAndBadValuesNamed) {
  const char* camera = "camera: {width: 612, height: 512, fx: 398.79, fy: 398.79, cx: 305.5, cy: 255.5}\n";
  const VoSolverOptions read = VoSolverOptions::from_config(Config::parse(
      std::string(camera) + "vo_solver: {max_threshold_px: 7.5, layer_min_fraction: 0.2, layer_min_separation: 0.1,"
                            " layer_min_separation_sigma: 6}\n",
      "good.yaml"));
  EXPECT_EQ(read.solver.max_threshold_px, 7.5);
  EXPECT_EQ(read.solver.layers.min_fraction, 0.2);
  EXPECT_EQ(read.solver.layers.min_separation, 0.1);
  EXPECT_EQ(read.solver.layers.min_separation_sigma, 6.0);
  for (const char* bad : {"vo_solver: {max_threshold_px: 1.0}\n", "vo_solver: {layer_min_separation_sigma: 1}\n"}) {
    try {
      VoSolverOptions::from_config(Config::parse(std::string(camera) + bad, "bad.yaml"));
      ADD_FAILURE() << "expected ConfigError for " << bad;
    } catch (const ConfigError& e) {
      const std::string key = std::string(bad).find("max_threshold") != std::string::npos ? "max_threshold_px"
                                                                                         : "layer_min_separation_sigma";
      EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace nadir::vo
