// The feature_depth variant over non-planar ground (DERIVATION.md section 13):
// exact recovery where the paper's one-patch model is biased, bounded error
// with noise, and the degenerate cases: hover, a moving object, a cliff edge
// and a frame gap; and a covariance that matches the errors.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <random>
#include <vector>

#include "processes/vo_solver/feature_depth_map.h"
#include "processes/vo_solver/plane_model.h"
#include "processes/vo_solver/translation_solver.h"
#include "tests/processes/vo_solver/terrain_sequence.h"

namespace nadir::vo {
namespace {

using testing::SequencePair;
using testing::TerrainSequence;
using testing::TerrainSpec;

constexpr int64_t kPeriod = 71429;

SolverOptions variant_options(Variant variant) {
  SolverOptions o;
  o.variant = variant;
  return o;
}

// Runs frames 1..last through the map and the solver as the node does.
struct SequenceRun {
  std::vector<Estimate> estimates;  // index k: pair (k-1, k)
  std::vector<SequencePair> pairs;
};

// `adjust` changes pair k as the solver sees it (INS errors).
SequenceRun run(TerrainSequence& seq, int last, const SolverOptions& options, FeatureDepthMap* map,
        const std::function<void(int, TerrainSequence&)>& before_frame = nullptr,
        const std::function<void(int, FramePair&)>& adjust = nullptr) {
  SequenceRun r;
  r.estimates.resize(last + 1);
  r.pairs.resize(last + 1);
  for (int k = 1; k <= last; ++k) {
    if (before_frame) before_frame(k, seq);
    SequencePair sp = seq.pair(k);
    if (adjust) adjust(k, sp.pair);
    if (map) map->fill(sp.ids, (k - 1) * kPeriod, &sp.pair);
    r.estimates[k] = solve(sp.pair, options);
    if (map) map->update(sp.ids, k * kPeriod, sp.pair, r.estimates[k]);
    r.pairs[k] = sp;
  }
  return r;
}

// Noise-free data: the depth filter told so (each pair's triangulation is
// then exact and outweighs the carried depth), as is the INS tilt filter (the
// attitudes are exact), and the young features' patch depths, wrong here by
// construction, given no weight once own depths exist.
SolverOptions exact_options() {
  SolverOptions o = variant_options(Variant::kFeatureDepth);
  o.feature_depth.triangulation_noise_px = 1e-3;
  o.feature_depth.ins_tilt_sigma_deg = 0.0;
  o.feature_depth.patch_feature_weight = 0.0;
  return o;
}

int own_used(const Estimate& e) {
  int n = 0;
  for (char c : e.used_own_depth) n += c != 0;
  return n;
}

TEST(FeatureDepth, ExactOverNonPlanarGroundWherePaperIsBiased) {
  // Each track's depth comes from its first ray and the motion solved since:
  // the first tracks' origins carry the motion of the start, solved on the
  // patch (centimetres off here), so the error decays as the tracks of the
  // start leave the image and later ones, seen from solved motion, replace
  // them: 1e-4 m at frame 20, 1e-6 m by frame 160.
  TerrainSequence seq{TerrainSpec{}};
  const SolverOptions fd = exact_options();
  FeatureDepthMap map(fd);
  constexpr int kLast = 240;
  const SequenceRun depth = run(seq, kLast, fd, &map);
  const SequenceRun paper = run(seq, kLast, variant_options(Variant::kPaper), nullptr);
  auto error = [&](int k) { return (depth.estimates[k].translation - depth.pairs[k].translation).norm(); };
  EXPECT_LT(error(100), 0.5 * error(20));
  EXPECT_LT(error(kLast), 0.05 * error(20));
  double worst_paper = 0;
  for (int k = 200; k <= kLast; ++k) {
    const Estimate& e = depth.estimates[k];
    const SequencePair& truth = depth.pairs[k];
    EXPECT_EQ(e.quality, 0) << "frame " << k;
    EXPECT_GT(own_used(e), 100) << "frame " << k;
    EXPECT_NEAR(error(k), 0.0, 3e-6) << "frame " << k;
    EXPECT_NEAR(e.dyaw, truth.dyaw, 2e-7) << "frame " << k;
    worst_paper = std::max(worst_paper, (paper.estimates[k].translation - truth.translation).norm());
  }
  // The one-patch model is off by centimetres per 1.5 m step here.
  EXPECT_GT(worst_paper, 1e-2);
  // Depths are the true ones.
  const SequencePair last = seq.pair(kLast + 1);
  FramePair probe = last.pair;
  map.fill(last.ids, kLast * kPeriod, &probe);
  const SequencePair at_last = seq.pair(kLast);
  int checked = 0;
  for (size_t i = 0; i < at_last.ids.size(); ++i) {
    for (size_t j = 0; j < last.ids.size(); ++j) {
      if (last.ids[j] != at_last.ids[i] || !std::isfinite(probe.prev_depth_m[j])) continue;
      EXPECT_NEAR(probe.prev_depth_m[j] / at_last.curr_depth_m[i], 1.0, 3e-5);
      ++checked;
    }
  }
  EXPECT_GT(checked, 100);
}

TEST(FeatureDepth, FirstPairsAreThePapersOwn) {
  // No depth known yet: the variant is exactly the paper's solve.
  TerrainSequence seq{TerrainSpec{}};
  const SolverOptions fd = variant_options(Variant::kFeatureDepth);
  FeatureDepthMap map(fd);
  SequencePair sp = seq.pair(1);
  map.fill(sp.ids, 0, &sp.pair);
  const Estimate a = solve(sp.pair, fd);
  const Estimate b = solve(sp.pair, variant_options(Variant::kPaper));
  EXPECT_EQ(a.translation, b.translation);
  EXPECT_EQ(a.dyaw, b.dyaw);
  EXPECT_EQ(a.covariance, b.covariance);
}

TEST(FeatureDepth, BoundedErrorWithNoiseAndBetterThanThePatch) {
  TerrainSpec spec;
  spec.noise_px = 0.3;
  TerrainSequence seq{spec};
  const SolverOptions fd = variant_options(Variant::kFeatureDepth);
  FeatureDepthMap map(fd);
  const SequenceRun depth = run(seq, 120, fd, &map);
  const SequenceRun paper = run(seq, 120, variant_options(Variant::kPaper), nullptr);
  Eigen::Vector3d sum_depth = Eigen::Vector3d::Zero(), sum_paper = Eigen::Vector3d::Zero();
  double step = 0;
  for (int k = 40; k <= 120; ++k) {
    EXPECT_EQ(depth.estimates[k].quality & (kNotConverged | kTooFewFeatures), 0) << "frame " << k;
    sum_depth += depth.estimates[k].translation - depth.pairs[k].translation;
    sum_paper += paper.estimates[k].translation - depth.pairs[k].translation;
    step += depth.pairs[k].translation.norm();
    // The INS is exact here, but the solver assumes it 0.05 deg off per
    // frame: the filtered tilt errors move each step sideways by up to
    // 0.13 m (0.04 m with the INS tilt taken as it is); that telescopes, and
    // the summed drift below is the same (0.32 % against 0.31 %).
    EXPECT_LT((depth.estimates[k].translation - depth.pairs[k].translation).norm(), 0.2) << "frame " << k;
  }
  // Accumulated over 81 frames (~120 m): the drift of each.
  EXPECT_LT(sum_depth.norm() / step, 0.012) << "paper: " << sum_paper.norm() / step;
  EXPECT_LT(sum_depth.norm(), 0.5 * sum_paper.norm()) << "paper: " << sum_paper.norm() / step;
}

TEST(FeatureDepth, UnbiasedWithNoiseOnOwnDepthsAlone) {
  // Flat ground, 0.5 px noise, the young features given no weight: the scale
  // and the vertical come from the own depths alone. A depth fused pair by
  // pair with each pair's own sigma came out +5 % (the near draws weigh
  // most) and the translation +2 %; from each track's whole baseline both
  // are unbiased within noise.
  TerrainSpec spec;
  spec.noise_px = 0.5;
  spec.relief_m = 0.0;
  TerrainSequence seq{spec};
  SolverOptions fd = variant_options(Variant::kFeatureDepth);
  fd.feature_depth.patch_feature_weight = 0.0;
  FeatureDepthMap map(fd);
  constexpr int kLast = 300;
  const SequenceRun r = run(seq, kLast, fd, &map);
  double along = 0, distance = 0, vertical = 0;
  for (int k = 40; k <= kLast; ++k) {
    const Eigen::Vector3d truth = r.pairs[k].translation;
    const Eigen::Vector3d e = r.estimates[k].translation - truth;
    EXPECT_GT(own_used(r.estimates[k]), 100) << "frame " << k;
    along += e.head<2>().dot(truth.head<2>().normalized());
    distance += truth.head<2>().norm();
    vertical += e.z();
  }
  EXPECT_LT(std::abs(along / distance), 0.002);  // measured 0.00002
  EXPECT_LT(std::abs(vertical), 3.0);             // metres over 390 m; measured -0.9
  // The usable depths (sigma under 3 %) at the last frame against the truth.
  const SequencePair next = seq.pair(kLast + 1), at_last = seq.pair(kLast);
  FramePair probe = next.pair;
  map.fill(next.ids, kLast * kPeriod, &probe);
  double sum = 0;
  int usable = 0;
  for (size_t j = 0; j < next.ids.size(); ++j) {
    if (!(probe.prev_depth_sigma_m[j] < 0.03 * probe.prev_depth_m[j])) continue;
    for (size_t i = 0; i < at_last.ids.size(); ++i) {
      if (at_last.ids[i] != next.ids[j]) continue;
      sum += probe.prev_depth_m[j] / at_last.curr_depth_m[i] - 1.0;
      ++usable;
    }
  }
  ASSERT_GT(usable, 100);
  EXPECT_LT(std::abs(sum / usable), 0.01);  // measured -0.002
}

double largest_young_weight(const Estimate& e) {
  double w = 0;
  for (size_t i = 0; i < e.weights.size(); ++i) {
    if (!e.used_own_depth[i]) w = std::max(w, e.weights[i]);
  }
  return w;
}

TEST(FeatureDepth, YoungFeaturesCountFullyWhereTheGroundIsThePatch) {
  // Level ground, noise-free: the patch holds every own depth (misfit 0), so
  // the young features keep patch_feature_weight (1: as much as a feature
  // with its own depth) and carry the curr altimeter's range into dz.
  TerrainSpec spec;
  spec.relief_m = 0.0;
  TerrainSequence seq{spec};
  SolverOptions fd = variant_options(Variant::kFeatureDepth);
  fd.feature_depth.triangulation_noise_px = 1e-3;
  ASSERT_EQ(fd.feature_depth.patch_feature_weight, 1.0);
  FeatureDepthMap map(fd);
  const SequenceRun r = run(seq, 240, fd, &map);
  int young = 0;
  for (int k = 120; k <= 240; ++k) {
    const Estimate& e = r.estimates[k];
    EXPECT_GT(own_used(e), 100) << "frame " << k;
    EXPECT_LT(e.patch_misfit, 1.0) << "frame " << k;
    const int young_here = static_cast<int>(e.weights.size()) - own_used(e);
    if (young_here > 0) {
      EXPECT_GT(largest_young_weight(e), 0.99) << "frame " << k;
    }
    young += young_here;
    EXPECT_NEAR((e.translation - r.pairs[k].translation).norm(), 0.0, 1e-9) << "frame " << k;
  }
  EXPECT_GT(young, 500);
}

TEST(FeatureDepth, YoungFeaturesWeighLittleOverRidges) {
  // Ridges under the whole view, noise-free: the plane puts the young
  // features at depths wrong by metres, and the patch misses the own depths
  // by several of their sigmas (measured 7 to 54). Each young feature's
  // weight is at most patch_feature_weight / misfit^2, and the motion is the
  // own depths' (the same run with the young features given no weight).
  TerrainSpec spec;
  spec.relief_m = 0.0;
  spec.ridge_amplitude_m = 6.0;
  TerrainSequence seq{spec};
  SolverOptions fd = variant_options(Variant::kFeatureDepth);
  fd.feature_depth.triangulation_noise_px = 1e-3;
  FeatureDepthMap map(fd);
  const SequenceRun r = run(seq, 240, fd, &map);
  const SolverOptions own_only = exact_options();
  FeatureDepthMap own_map(own_only);
  const SequenceRun o = run(seq, 240, own_only, &own_map);
  double largest_difference = 0;
  for (int k = 120; k <= 240; ++k) {
    const Estimate& e = r.estimates[k];
    EXPECT_GT(e.patch_misfit, 5.0) << "frame " << k;
    EXPECT_LE(largest_young_weight(e), 1.0 / (e.patch_misfit * e.patch_misfit)) << "frame " << k;
    largest_difference = std::max(largest_difference, (e.translation - o.estimates[k].translation).norm());
  }
  EXPECT_LT(largest_difference, 1e-3);
}

// Along-track drift (share of the distance) and the worst step's error over
// frames 120-240, the own depths exact (noise-free, exact_options) and used
// by every pair.
double anchored_drift(const TerrainSpec& spec, const SolverOptions& options, double* worst_step) {
  TerrainSequence seq{spec};
  FeatureDepthMap map(options);
  const SequenceRun r = run(seq, 240, options, &map);
  double along = 0, distance = 0;
  *worst_step = 0;
  for (int k = 120; k <= 240; ++k) {
    const Eigen::Vector3d truth = r.pairs[k].translation;
    const Eigen::Vector3d e = r.estimates[k].translation - truth;
    EXPECT_GT(own_used(r.estimates[k]), 100) << "frame " << k;
    along += e.head<2>().dot(truth.head<2>().normalized());
    distance += truth.head<2>().norm();
    *worst_step = std::max(*worst_step, e.norm() / truth.norm());
  }
  return along / distance;
}

TEST(FeatureDepth, QuadraticAnchorFollowsRidgesUnderTheAltimeter) {
  // Ridges 160 m apart (crests 13.5 m above the valleys, sharper than them)
  // across the path and under the altimeter, noise-free. The own depths are
  // exact, so the scale is only as good as the surface the beam meets: a
  // plane through the own depths within 37 m of the spot cuts below a crest
  // and above a valley, and each step's scale follows the ground's curvature
  // (measured: worst step 1.6 % off); the quadratic surface holds a crest and
  // a valley (0.33 %). Over whole ridges the plane's errors largely cancel
  // (drift -0.058 % against -0.022 %): smooth curvature integrates to zero.
  TerrainSpec spec;
  spec.ridge_amplitude_m = 6.0;
  spec.relief_m = 0.0;
  auto drift = [&](AnchorSurfaceModel model, double* worst_step) {
    SolverOptions fd = exact_options();
    fd.feature_depth.anchor_surface = model;
    return anchored_drift(spec, fd, worst_step);
  };
  double plane_step = 0, quadratic_step = 0;
  const double plane = drift(AnchorSurfaceModel::kPlane, &plane_step);
  const double quadratic = drift(AnchorSurfaceModel::kQuadratic, &quadratic_step);
  EXPECT_GT(plane_step, 5e-3);
  EXPECT_LT(quadratic_step, 0.3 * plane_step) << "plane " << plane_step;
  EXPECT_LT(std::abs(quadratic), 5e-4) << "plane " << plane;
  EXPECT_LT(std::abs(quadratic), std::abs(plane));
}

// Crests that are kinks, 12 m above smooth valleys, 120 m apart, across the
// path and under the altimeter; nothing else off the plane.
TerrainSpec kinked_crests() {
  TerrainSpec spec;
  spec.relief_m = 0.0;
  spec.ridge_amplitude_m = 6.0;
  spec.ridge_wavelength_m = 120.0;
  spec.sharp_crests = true;
  return spec;
}

TEST(FeatureDepth, TrackAnchorFollowsSharpCrests) {
  // Crests that are kinks (12 m above smooth valleys, 120 m apart) across the
  // path and under the altimeter, noise-free. A quadratic fitted around the
  // beam passes below a kinked crest in inverse depth, and each pair there
  // comes out short (measured: worst step 1.4 % off, drift -0.080 %). Anchored
  // on the spots along the track, each weighted as the fit weighs the own
  // depths across the track there, the misfit averages out over the spots
  // (0.47 %, -0.027 %). Not zero: the fit's residuals average to zero over
  // the ~50 own depths it holds, the spots sample the ground densely. Over
  // crests 90 m apart (less than the anchor's 2 x 37 m) the drift is not
  // smaller (+0.07 % against -0.04 %), the worst step is (0.61 % against 2.0 %).
  const TerrainSpec spec = kinked_crests();
  SolverOptions beam = exact_options();
  SolverOptions track = beam;
  track.feature_depth.anchor_spots = AnchorSpots::kTrack;
  double beam_step = 0, track_step = 0;
  const double beam_drift = anchored_drift(spec, beam, &beam_step);
  const double track_drift = anchored_drift(spec, track, &track_step);
  EXPECT_GT(beam_step, 0.01);
  EXPECT_LT(track_step, 0.4 * beam_step) << "beam " << beam_step;
  EXPECT_LT(beam_drift, -5e-4);
  EXPECT_LT(std::abs(track_drift), 0.5 * std::abs(beam_drift)) << "beam " << beam_drift;
  // Until the spots reach 2 x anchor_radius back (75 m here, 50 frames), the
  // beam alone: the same estimates bit for bit.
  TerrainSequence seq{spec};
  FeatureDepthMap beam_map(beam), track_map(track);
  const SequenceRun b = run(seq, 45, beam, &beam_map);
  const SequenceRun t = run(seq, 45, track, &track_map);
  for (int k = 1; k <= 45; ++k) EXPECT_EQ(b.estimates[k].translation, t.estimates[k].translation) << "frame " << k;
}

TEST(FeatureDepth, AnchorModelVarianceIsTheReliefTheSurfaceMisses) {
  // Noise-free. Over smooth ridges the quadratic around the beam holds the
  // own depths: no model variance. Over kinked crests it cannot, and the
  // pairs whose scale the crests put off carry the misfit: the steps more
  // than 0.5 % off all have a model variance, and its root is of the size of
  // their error (measured: largest root 0.70 %, worst step 1.40 % off).
  auto run_spec = [](const TerrainSpec& spec, std::vector<double>* variance, std::vector<double>* step_error) {
    const SolverOptions options = exact_options();
    TerrainSequence seq{spec};
    FeatureDepthMap map(options);
    const SequenceRun r = run(seq, 240, options, &map);
    for (int k = 120; k <= 240; ++k) {
      const Eigen::Vector3d truth = r.pairs[k].translation;
      variance->push_back(r.estimates[k].anchor_model_variance);
      step_error->push_back((r.estimates[k].translation - truth).norm() / truth.norm());
    }
  };
  TerrainSpec smooth;
  smooth.relief_m = 0.0;
  smooth.ridge_amplitude_m = 2.0;
  smooth.ridge_wavelength_m = 400.0;
  std::vector<double> smooth_variance, smooth_error, kinked_variance, kinked_error;
  run_spec(smooth, &smooth_variance, &smooth_error);
  run_spec(kinked_crests(), &kinked_variance, &kinked_error);
  for (double v : smooth_variance) EXPECT_LT(v, 1e-8);
  double worst_error = 0, largest_sigma = 0;
  for (size_t i = 0; i < kinked_variance.size(); ++i) {
    if (kinked_error[i] > 0.005) {
      EXPECT_GT(kinked_variance[i], 1e-6) << "pair " << i << " " << kinked_error[i];
    }
    worst_error = std::max(worst_error, kinked_error[i]);
    largest_sigma = std::max(largest_sigma, std::sqrt(kinked_variance[i]));
  }
  EXPECT_GT(worst_error, 0.01);
  EXPECT_GT(largest_sigma, 0.3 * worst_error);
  EXPECT_LT(largest_sigma, 3.0 * worst_error);
}

TEST(FeatureDepth, ScaleFilterDiscountsAnchorsTheSurfaceCannotHold) {
  // The kinked crests of TrackAnchorFollowsSharpCrests, noise-free. Each
  // pair's altimeter scale fused with the one the own depths carry, by their
  // variances: near a crest the own depths miss the quadratic beyond their
  // sigmas, so the anchor there counts little and the scale anchored over the
  // smooth valleys carries across it (measured: drift -0.080 % -> -0.008 %,
  // worst step 1.4 % -> 0.08 %).
  const TerrainSpec spec = kinked_crests();
  SolverOptions beam = exact_options();
  SolverOptions filter = beam;
  filter.feature_depth.scale_filter = true;
  filter.feature_depth.scale_process_noise = 1e-4;
  double beam_step = 0, filter_step = 0;
  const double beam_drift = anchored_drift(spec, beam, &beam_step);
  const double filter_drift = anchored_drift(spec, filter, &filter_step);
  EXPECT_LT(beam_drift, -5e-4);
  EXPECT_LT(std::abs(filter_drift), 0.2 * std::abs(beam_drift)) << "beam " << beam_drift;
  EXPECT_LT(filter_step, 0.2 * beam_step) << "beam " << beam_step;
}

TEST(FeatureDepth, ScaleFilterAveragesTheAltimetersNoise) {
  // Level ground, exact tracks, the altimeter's range off by 0.3 m (1 sigma)
  // at each frame and its sigma given: anchored pair by pair, each step's
  // scale carries its range's error; fused, the scale averages the ranges
  // over many pairs. Exact ranges: the filter is as exact as the anchor.
  TerrainSpec spec;
  spec.relief_m = 0.0;
  SolverOptions beam = exact_options();
  SolverOptions filter = beam;
  filter.feature_depth.scale_filter = true;
  filter.feature_depth.scale_process_noise = 1e-4;
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, 0.3);
  std::vector<double> range_error(241);
  for (double& e : range_error) e = noise(rng);
  auto rms_step_error = [&](const SolverOptions& o, bool noisy) {
    TerrainSequence seq{spec};
    FeatureDepthMap map(o);
    const SequenceRun r = run(seq, 240, o, &map, nullptr, [&](int k, FramePair& pair) {
      if (!noisy) return;
      pair.prev_range_m += range_error[k - 1];
      pair.curr_range_m += range_error[k];
      pair.prev_range_sigma_m = 0.3;
    });
    double sum = 0;
    for (int k = 120; k <= 240; ++k) {
      EXPECT_GT(own_used(r.estimates[k]), 100) << "frame " << k;
      sum += (r.estimates[k].translation - r.pairs[k].translation).squaredNorm() / r.pairs[k].translation.squaredNorm();
    }
    return std::sqrt(sum / 121);
  };
  const double beam_exact = rms_step_error(beam, false), filter_exact = rms_step_error(filter, false);
  const double beam_noisy = rms_step_error(beam, true), filter_noisy = rms_step_error(filter, true);
  EXPECT_LT(beam_exact, 1e-4);
  EXPECT_LT(filter_exact, 1e-4);
  EXPECT_GT(beam_noisy, 1e-3);
  EXPECT_LT(filter_noisy, 0.3 * beam_noisy) << "anchored pair by pair " << beam_noisy;
}

TEST(FeatureDepth, QuadraticAnchorWithTooFewDepthsFallsBackToThePlane) {
  // A small anchor radius (21 m on the ground here) holds about twelve own
  // depths: on some pairs fewer than the quadratic's twelve. There the anchor
  // is the plane's, never the paper's solve (which it was at first: on the
  // simulator's rough_120 seed 2 that nearly doubled the error, README
  // section Rough ground).
  TerrainSpec spec;
  spec.relief_m = 0.0;
  spec.ridge_amplitude_m = 6.0;
  TerrainSequence seq{spec};
  SolverOptions plane = exact_options();
  plane.feature_depth.anchor_radius = 0.14;
  plane.feature_depth.anchor_surface = AnchorSurfaceModel::kPlane;
  SolverOptions quadratic = plane;
  quadratic.feature_depth.anchor_surface = AnchorSurfaceModel::kQuadratic;
  FeatureDepthMap map(plane);
  int as_plane = 0, own = 0;
  for (int k = 1; k <= 160; ++k) {
    SequencePair sp = seq.pair(k);
    map.fill(sp.ids, (k - 1) * kPeriod, &sp.pair);
    const Estimate by_plane = solve(sp.pair, plane);
    if (k > 60) {
      const Estimate by_quadratic = solve(sp.pair, quadratic);
      const Estimate by_paper = solve(sp.pair, variant_options(Variant::kPaper));
      if (by_plane.translation != by_paper.translation) {  // the plane anchor held
        EXPECT_NE(by_quadratic.translation, by_paper.translation) << "frame " << k;
        as_plane += by_quadratic.translation == by_plane.translation;
        ++own;
      }
    }
    map.update(sp.ids, k * kPeriod, sp.pair, by_plane);
  }
  EXPECT_GT(own, 60);
  EXPECT_GT(as_plane, 0);    // some pairs with too few for the quadratic ...
  EXPECT_LT(as_plane, own);  // ... and some with enough
}

TEST(FeatureDepth, TooFewDepthsNearTheBeamCarryTheScaleForAFewPairs) {
  // Low over a crest the image holds less ground, and the tracks near the
  // beam can all be young: too few own depths within anchor_radius of it for
  // even the plane. The pair then keeps the own depths at the scale the pair
  // before left them, up to scale_carry_pairs pairs after the last anchored
  // one, rather than the paper's one plane, which over blocks and pits is
  // steps off (on the simulator's rough_120 seed 2, with exact tracks, 31
  // such pairs made a third of the relief's along-track error; README
  // section Rough ground). Noise-free: the carried scale is exact.
  TerrainSpec spec;
  TerrainSequence seq{spec};
  SolverOptions carry = exact_options();
  carry.feature_depth.scale_carry_pairs = 14;
  SolverOptions never = carry;
  never.feature_depth.scale_carry_pairs = 0;
  const SolverOptions paper = variant_options(Variant::kPaper);
  FeatureDepthMap carry_map(carry), never_map(never);
  // Frames 101..140: every own depth within 1.2 anchor radii of the beam taken away.
  auto hole = [&](int k, FramePair* pair) {
    if (k <= 100 || k > 140) return;
    const Eigen::Vector2d beam = pair->prev_beam_body.head<2>() / pair->prev_beam_body.z();
    int kept = 0;
    for (size_t i = 0; i < pair->prev_norm.size(); ++i) {
      if ((pair->prev_norm[i] - beam).norm() < 1.2 * carry.feature_depth.anchor_radius) {
        pair->prev_depth_m[i] = std::numeric_limits<double>::quiet_NaN();
      } else {
        kept += std::isfinite(pair->prev_depth_m[i]);
      }
    }
    ASSERT_GE(kept, carry.feature_depth.min_own_depth_features) << "frame " << k;
  };
  double anchored_error = 0, carried_error = 0, paper_error = 0;
  for (int k = 1; k <= 160; ++k) {
    SequencePair a = seq.pair(k), b = a;
    carry_map.fill(a.ids, (k - 1) * kPeriod, &a.pair);
    never_map.fill(b.ids, (k - 1) * kPeriod, &b.pair);
    hole(k, &a.pair);
    hole(k, &b.pair);
    const Estimate by_carry = solve(a.pair, carry);
    const Estimate by_never = solve(b.pair, never);
    const double error = (by_carry.translation - a.translation).norm() / a.translation.norm();
    if (k > 60 && k <= 100) {  // own depths exact and anchored
      EXPECT_TRUE(by_carry.own_depths_used && !by_carry.scale_carried) << "frame " << k;
      anchored_error = std::max(anchored_error, error);
    } else if (k > 100 && k <= 114) {  // carried, 14 pairs
      EXPECT_EQ(a.pair.carried_scale_pairs, k - 101) << "frame " << k;
      EXPECT_TRUE(by_carry.own_depths_used && by_carry.scale_carried) << "frame " << k;
      carried_error = std::max(carried_error, error);
      EXPECT_FALSE(by_never.own_depths_used) << "frame " << k;
      EXPECT_EQ(by_never.translation, solve(b.pair, paper).translation) << "frame " << k;
      paper_error = std::max(paper_error, (by_never.translation - b.translation).norm() / b.translation.norm());
    } else if (k > 114 && k <= 140) {  // then the paper's model alone, until an anchor holds again
      EXPECT_FALSE(by_carry.own_depths_used) << "frame " << k;
      EXPECT_EQ(by_carry.translation, solve(a.pair, paper).translation) << "frame " << k;
    } else if (k > 150) {
      EXPECT_TRUE(by_carry.own_depths_used && !by_carry.scale_carried) << "frame " << k;
    }
    carry_map.update(a.ids, k * kPeriod, a.pair, by_carry);
    never_map.update(b.ids, k * kPeriod, b.pair, by_never);
  }
  // Still the patch-solved start's last tracks here (exact by frame 160).
  EXPECT_LT(anchored_error, 1e-4);
  EXPECT_LT(carried_error, 2 * anchored_error) << "anchored " << anchored_error;
  EXPECT_GT(paper_error, 100 * carried_error) << "carried " << carried_error;
}

TEST(FeatureDepth, HoverHasNoDepthAndFallsBackToThePatch) {
  TerrainSequence seq{TerrainSpec{}};
  seq.pose_override = [](int k) {
    testing::FramePose p;
    p.position = Eigen::Vector3d(0, 0, -150.0);
    p.roll = 0.04 * std::sin(0.3 * k);
    p.pitch = -0.03 + 0.02 * std::cos(0.2 * k);
    p.yaw = 0.3 + 0.002 * k;
    return p;
  };
  const SolverOptions fd = variant_options(Variant::kFeatureDepth);
  FeatureDepthMap map(fd);
  const SequenceRun depth = run(seq, 30, fd, &map);
  EXPECT_EQ(map.size(), 0u);  // no parallax: no depth is observable
  for (int k = 1; k <= 30; ++k) {
    const Estimate paper = solve(depth.pairs[k].pair, variant_options(Variant::kPaper));
    EXPECT_EQ(depth.estimates[k].translation, paper.translation) << "frame " << k;
    EXPECT_EQ(own_used(depth.estimates[k]), 0);
    EXPECT_NEAR(depth.estimates[k].translation.norm(), 0.0, 1e-6);
  }
}

TEST(FeatureDepth, MovingObjectIsAnOutlier) {
  TerrainSequence seq{TerrainSpec{}};
  const SolverOptions fd = exact_options();
  FeatureDepthMap map(fd);
  // From frame 200 (the depths converged, see above), the points within 20 m
  // of a car beside the path (clear of the altimeter spot) move 4 m per frame.
  std::vector<size_t> car;
  const SequenceRun r = run(seq, 220, fd, &map, [&](int k, TerrainSequence& s) {
    if (k == 200) {
      const testing::FramePose p = s.pose(200);
      for (size_t i = 0; i < s.points().size(); ++i) {
        const Eigen::Vector3d d = s.points()[i] - p.position;
        if (std::hypot(d.x() - 30.0, d.y() + 10.0) < 20.0) car.push_back(i);
      }
    }
    if (k == 200) {
      // Parked until frame 199, then 4 m per frame sideways.
      s.point_motion = [&car](size_t i, int frame) {
        const bool on_car = std::find(car.begin(), car.end(), i) != car.end();
        return Eigen::Vector3d(0.0, on_car ? 4.0 * std::max(0, frame - 199) : 0.0, 0.0);
      };
    }
  });
  ASSERT_GT(car.size(), 10u);
  for (int k = 200; k <= 220; ++k) {
    const Estimate& e = r.estimates[k];
    EXPECT_NEAR((e.translation - r.pairs[k].translation).norm(), 0.0, 3e-6) << "frame " << k;
    for (size_t j = 0; j < r.pairs[k].ids.size(); ++j) {
      const bool on_car = std::find(car.begin(), car.end(), static_cast<size_t>(r.pairs[k].ids[j])) != car.end();
      if (on_car) {
        EXPECT_EQ(e.weights[j], 0.0) << "frame " << k;
      }
    }
  }
  EXPECT_GT(map.off_epipolar(), 0);
}

TEST(FeatureDepth, CliffEdgeDropsTheDepthInsteadOfBlendingIt) {
  TerrainSequence seq{TerrainSpec{}};
  const SolverOptions fd = exact_options();
  FeatureDepthMap map(fd);
  // At frame 205 (the depths converged) the tracked points beside the
  // corridor slip down a 30 m cliff: same track, same image point in frame
  // 204, a new depth.
  std::vector<size_t> slipped;
  int64_t rejected_before = 0;
  int checked = 0;
  const SequenceRun r = run(seq, 330, fd, &map, [&](int k, TerrainSequence& s) {
    if (k == 241) {
      const SequencePair at240 = s.pair(240), next = s.pair(241);
      FramePair probe = next.pair;
      map.fill(next.ids, 240 * kPeriod, &probe);
      for (size_t j = 0; j < next.ids.size(); ++j) {
        if (std::find(slipped.begin(), slipped.end(), static_cast<size_t>(next.ids[j])) == slipped.end()) continue;
        if (!std::isfinite(probe.prev_depth_m[j])) continue;
        for (size_t i = 0; i < at240.ids.size(); ++i) {
          if (at240.ids[i] != next.ids[j]) continue;
          EXPECT_NEAR(probe.prev_depth_m[j] / at240.curr_depth_m[i], 1.0, 5e-3);
          ++checked;
        }
      }
    }
    if (k != 205) return;
    rejected_before = map.rejected_depths();
    const testing::FramePose p44 = s.pose(204);
    const SequencePair at44 = s.pair(204);
    for (size_t j = 0; j < at44.ids.size() && slipped.size() < 40; ++j) {
      const size_t i = static_cast<size_t>(at44.ids[j]);
      Eigen::Vector3d& x = s.points()[i];
      if (x.z() > -1.0) continue;  // on a block beside the corridor
      // Along the ray from the camera at 204: same image point, 30 m deeper.
      const Eigen::Vector3d ray = x - p44.position;
      x = p44.position + ray * (ray.z() + 30.0) / ray.z();
      slipped.push_back(i);
    }
  });
  ASSERT_EQ(slipped.size(), 40u);
  // At the cliff frame the 30 m depth error of a tenth of the features moves
  // them by under a pixel in this pair (below the robust threshold): the
  // motion is off by centimetres there, once; the map sees the jump against
  // this pair's triangulation and drops those depths (no blend with the old
  // ones survives). That pair's error stays in the baseline of every track
  // alive then, so the sequence converges back to exact as those tracks are
  // replaced: 3 mm 35 frames on, 0.2 mm 125 frames on.
  auto error = [&](int k) { return (r.estimates[k].translation - r.pairs[k].translation).norm(); };
  EXPECT_LT(error(205), 0.05);
  EXPECT_LT(error(206), 0.01);
  EXPECT_LT(error(240), 5e-3);
  EXPECT_LT(error(270), 0.5 * error(240));
  EXPECT_LT(error(330), 3e-4);
  EXPECT_GE(map.rejected_depths() - rejected_before, 40);
  // The slipped tracks hold their new depth (30 m deeper: 20 %) to 0.5 %,
  // 35 frames on (checked before frame 241).
  EXPECT_GT(checked, 20);
}

TEST(FeatureDepth, NoStaleDepthAcrossAFrameGap) {
  TerrainSequence seq{TerrainSpec{}};
  const SolverOptions fd = variant_options(Variant::kFeatureDepth);
  FeatureDepthMap map(fd);
  run(seq, 30, fd, &map);
  ASSERT_GT(map.size(), 100u);
  // Frame 31 is lost: the next pair is (31, 32), whose prev is not the frame the depths belong to.
  SequencePair sp = seq.pair(32);
  map.fill(sp.ids, 31 * kPeriod, &sp.pair);
  EXPECT_EQ(map.size(), 0u);
  EXPECT_EQ(map.resets(), 1);
  for (double d : sp.pair.prev_depth_m) EXPECT_TRUE(std::isnan(d));
  const Estimate e = solve(sp.pair, fd);
  EXPECT_EQ(own_used(e), 0);
  EXPECT_EQ(e.translation, solve(sp.pair, variant_options(Variant::kPaper)).translation);
  // A failed estimate clears the map too.
  run(seq, 10, fd, &map);
  Estimate failed;
  failed.quality = kNoAltimeter;
  SequencePair next = seq.pair(11);
  map.update(next.ids, 11 * kPeriod, next.pair, failed);
  EXPECT_EQ(map.size(), 0u);
}

// White INS roll/pitch errors, the same for a frame in both its pairs, as
// the node hands them on: per frame, the error of (roll, pitch).
std::vector<Eigen::Vector2d> white_attitude_errors(int frames, double sigma_deg, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, sigma_deg * M_PI / 180.0);
  std::vector<Eigen::Vector2d> errors(frames);
  for (Eigen::Vector2d& e : errors) e = Eigen::Vector2d(noise(rng), noise(rng));
  return errors;
}

// The `adjust` of run() that hands the solver each frame's INS attitude with its error.
std::function<void(int, FramePair&)> adding_ins_errors(const std::vector<Eigen::Vector2d>& ins_error) {
  return [&ins_error](int k, FramePair& pair) {
    pair.prev_roll += ins_error[k - 1].x();
    pair.prev_pitch += ins_error[k - 1].y();
    pair.curr_roll += ins_error[k].x();
    pair.curr_pitch += ins_error[k].y();
  };
}

// A pair's true translation in the level frame of prev as the INS levels it
// (prev's error `prev_error`): rays the INS levels are perceived =
// levelled-by-INS x (levelled-by-truth)^-1 x true.
Eigen::Vector3d truth_as_the_ins_levels(const SequencePair& sp, const Eigen::Vector2d& prev_error) {
  const Eigen::Matrix3d prev_perceived =
      level_from_camera(sp.pair.prev_roll, sp.pair.prev_pitch, Eigen::Matrix3d::Identity()) *
      level_from_camera(sp.pair.prev_roll - prev_error.x(), sp.pair.prev_pitch - prev_error.y(),
                        Eigen::Matrix3d::Identity())
          .transpose();
  return prev_perceived * sp.translation;
}

TEST(FeatureDepth, TheInsTiltBetweenTwoFramesIsFittedToTheImages) {
  // Noise-free images; the INS roll and pitch 0.2 deg off, independently in
  // every frame. Taken as the INS says, the image motion of each pair's
  // relative tilt is read as translation: across the image (h x tilt, which
  // telescopes) and, to second order, as a climb in every pair, which does
  // not. Fitted, each pair's tilt is the INS's error between its frames, and
  // filtered it is the difference of the two frames' estimated errors: the
  // summed translation neither drifts sideways nor climbs.
  TerrainSpec spec;
  spec.relief_m = 0.0;
  TerrainSequence seq{spec};
  constexpr int kLast = 600;
  const std::vector<Eigen::Vector2d> ins_error = white_attitude_errors(kLast + 1, 0.2, 7);
  const auto with_ins_error = adding_ins_errors(ins_error);
  SolverOptions fitted = exact_options();
  fitted.feature_depth.ins_tilt_sigma_deg = 0.2;
  SolverOptions as_ins = fitted;
  as_ins.feature_depth.ins_tilt_sigma_deg = 0.0;
  FeatureDepthMap fitted_map(fitted), as_ins_map(as_ins);
  const SequenceRun f = run(seq, kLast, fitted, &fitted_map, nullptr, with_ins_error);
  const SequenceRun a = run(seq, kLast, as_ins, &as_ins_map, nullptr, with_ins_error);
  double worst_tilt = 0, worst_chain = 0;
  Eigen::Vector3d fitted_sum = Eigen::Vector3d::Zero(), as_ins_sum = Eigen::Vector3d::Zero();
  for (int k = 500; k <= kLast; ++k) {
    const SequencePair& sp = f.pairs[k];
    ASSERT_GT(own_used(f.estimates[k]), 100) << "frame " << k;
    const Eigen::Vector3d truth = truth_as_the_ins_levels(sp, ins_error[k - 1]);
    fitted_sum += f.estimates[k].translation - truth;
    as_ins_sum += a.estimates[k].translation - truth;
    const Eigen::Vector2d relative = ins_error[k] - ins_error[k - 1];
    worst_tilt = std::max(worst_tilt, (f.estimates[k].relative_tilt - relative).cwiseAbs().maxCoeff());
    worst_chain = std::max(worst_chain, (f.estimates[k].relative_tilt -
                                         (f.estimates[k].curr_tilt - f.estimates[k - 1].curr_tilt))
                                            .cwiseAbs()
                                            .maxCoeff());
    EXPECT_EQ(a.estimates[k].relative_tilt, Eigen::Vector2d::Zero());
  }
  // Frames 500-600 (150 m), once the tracks of the start (solved by the
  // patch, every tilt read as translation) are replaced.
  EXPECT_LT(worst_tilt, 5e-5);  // rad, against INS errors ~5e-3 between frames; measured 2.4e-5
  EXPECT_LT(worst_chain, 1e-15);  // each pair's tilt is the difference of its frames' errors
  EXPECT_LT(fitted_sum.head<2>().norm(), 0.03);  // metres; measured 0.011
  EXPECT_LT(std::abs(fitted_sum.z()), 0.02);     // measured +0.005
  // As the INS says: measured 8.0 m sideways and -2.4 m (a climb). Noise-free,
  // each pair's triangulation outweighs the carried depth here, so each
  // tilt goes into the depths as well.
  EXPECT_GT(as_ins_sum.head<2>().norm(), 1.0);
  EXPECT_LT(as_ins_sum.z(), -1.0);
}

TEST(FeatureDepth, CovarianceMatchesTheErrors) {
  // Over ridges and blocks, 0.5 px noise, the INS roll and pitch off by the
  // sigma the solver assumes (0.05 deg, independently in every frame): each
  // pair's error in dx, dy, dz and dyaw over its own reported sigma. The
  // covariance is the pair's weight downstream (yaw fusion, the position's
  // sigma), so it must be neither overconfident nor far too cautious.
  TerrainSpec spec;
  spec.noise_px = 0.5;
  spec.ridge_amplitude_m = 6.0;
  TerrainSequence seq{spec};
  constexpr int kLast = 200;
  const std::vector<Eigen::Vector2d> ins_error = white_attitude_errors(kLast + 1, 0.05, 11);
  const auto with_ins_error = adding_ins_errors(ins_error);
  const SolverOptions fd = variant_options(Variant::kFeatureDepth);
  ASSERT_EQ(fd.feature_depth.ins_tilt_sigma_deg, 0.05);
  FeatureDepthMap map(fd);
  const SequenceRun r = run(seq, kLast, fd, &map, nullptr, with_ins_error);
  Eigen::Vector4d sum = Eigen::Vector4d::Zero();
  int n = 0;
  for (int k = 40; k <= kLast; ++k) {
    const Estimate& e = r.estimates[k];
    const SequencePair& sp = r.pairs[k];
    ASSERT_GT(own_used(e), 100) << "frame " << k;
    Eigen::Vector4d error;
    error.head<3>() = e.translation - truth_as_the_ins_levels(sp, ins_error[k - 1]);
    error(3) = e.dyaw - sp.dyaw;
    for (int c = 0; c < 4; ++c) sum(c) += error(c) * error(c) / e.covariance(c, c);
    ++n;
  }
  const Eigen::Vector4d normalized_rms = (sum / n).cwiseSqrt();
  // Measured 1.07 / 1.09 / 0.76 / 0.74 (with the INS exact, about 0.45 / 0.45 /
  // 0.7 / 0.7: the assumed tilt sigma then only widens the sigmas).
  for (int c = 0; c < 2; ++c) {
    EXPECT_GT(normalized_rms(c), 0.8) << "component " << c;
    EXPECT_LT(normalized_rms(c), 1.3) << "component " << c;
  }
  for (int c = 2; c < 4; ++c) {
    EXPECT_GT(normalized_rms(c), 0.5) << "component " << c;
    EXPECT_LT(normalized_rms(c), 1.3) << "component " << c;
  }
}

TEST(FeatureDepth, OptionsAreChecked) {
  SolverOptions o;
  o.feature_depth.max_relative_sigma = 0;
  EXPECT_THROW(o.Check(), std::invalid_argument);
  o = SolverOptions();
  o.feature_depth.min_anchor_features = 2;
  EXPECT_THROW(o.Check(), std::invalid_argument);
  o = SolverOptions();
  o.feature_depth.scale_carry_pairs = -1;
  EXPECT_THROW(o.Check(), std::invalid_argument);
  o = SolverOptions();
  o.feature_depth.ins_tilt_sigma_deg = -0.1;
  EXPECT_THROW(o.Check(), std::invalid_argument);
  o = SolverOptions();
  o.feature_depth.scale_process_noise = 0;
  EXPECT_THROW(o.Check(), std::invalid_argument);
  EXPECT_FALSE(SolverOptions().feature_depth.scale_filter);
  EXPECT_EQ(SolverOptions().feature_depth.anchor_surface, AnchorSurfaceModel::kQuadratic);
  EXPECT_EQ(variant_from_name("feature_depth"), Variant::kFeatureDepth);
  EXPECT_EQ(variant_name(Variant::kFeatureDepth), "feature_depth");
}

}  // namespace
}  // namespace nadir::vo
