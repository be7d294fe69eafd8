// nadir_bench_vo_solver: one frame pair of 450 features (612x512 camera) per
// iteration, for each variant; the goal for `paper` and `feature_depth` is
// <= 0.5 ms per frame on one core. Run: build/bin/nadir_bench_vo_solver (pin
// with taskset -c 0).
// this machine under load (load average ~3), back to back:
// Paper_Noise05px_Outliers30 748-828 us CPU before (main's build), 525-560 us
// after (LM reuses the trial's normal equations, lower-triangle accumulation,
// inlined eq. (9), forward covariance once, -O3 for the solver library; the
// outputs are bit-identical). Instructions per solve (callgrind, the same 16
// pairs): 8.31 M -> 5.30 M. FeatureDepth_Noise05px_Outliers30: 581-615 us.
// 2026-11-29, a slower machine of the kind (2 x 2.6 GHz, quiet,
// --benchmark_repetitions=5 medians): FeatureDepth 580 us -> 481 us with the
// Jacobian as the projection's rows over dY/dm (outputs change by rounding
// only: translation by < 2e-11 m over 272 solves) -> 453 us with J^T w J's
// lower triangle in fixed-size column blocks (bit-identical); Paper 423 us.

#include <benchmark/benchmark.h>

#include <cmath>
#include <random>
#include <vector>

#include "common/geometry.h"
#include "processes/vo_solver/delta_uncertainty.h"
#include "processes/vo_solver/feature_depth_map.h"
#include "processes/vo_solver/translation_solver.h"
#include "tests/processes/vo_solver/synthetic_scene.h"
#include "tests/processes/vo_solver/terrain_sequence.h"

namespace {

using nadir::deg_to_rad;
using namespace nadir::vo;

// `turn_deg`: heading change between the frames (a photo survey's half turn: 180).
std::vector<FramePair> make_pairs(double noise_px, double outliers, double turn_deg = 1.0) {
  std::vector<FramePair> pairs;
  for (uint32_t seed = 1; seed <= 16; ++seed) {
    testing::SceneSpec s;
    s.height_m = 250.0;
    s.ground_roll = deg_to_rad(6.0);
    s.ground_pitch = deg_to_rad(-9.0);
    s.prev_roll = deg_to_rad(4.0);
    s.prev_pitch = deg_to_rad(-3.0);
    s.prev_yaw = deg_to_rad(30.0);
    s.curr_roll = deg_to_rad(5.0);
    s.curr_pitch = deg_to_rad(-2.5);
    s.curr_yaw = deg_to_rad(30.0 + turn_deg);
    s.translation = Eigen::Vector3d(2.1, -0.3, -0.2);
    s.num_features = 450;
    s.noise_px = noise_px;
    s.outlier_fraction = outliers;
    s.seed = seed;
    pairs.push_back(testing::make_scene(s).pair);
  }
  return pairs;
}

void run(benchmark::State& state, Variant variant, double noise_px, double outliers, bool symmetric_dz = true,
         double turn_deg = 1.0) {
  const std::vector<FramePair> pairs = make_pairs(noise_px, outliers, turn_deg);
  SolverOptions options;
  options.variant = variant;
  options.symmetric_dz = symmetric_dz;
  size_t i = 0;
  int64_t iterations = 0, frames = 0;
  for (auto _ : state) {
    const Estimate est = solve(pairs[i++ % pairs.size()], options);
    benchmark::DoNotOptimize(est.translation);
    iterations += est.iterations;
    ++frames;
  }
  state.counters["lm_iterations"] = static_cast<double>(iterations) / std::max<int64_t>(1, frames);
}

// The node's per-frame hook after the solve: VO_DELTA's INS/altimeter covariance.
void BM_SensorUncertainty(benchmark::State& state) {
  const std::vector<FramePair> pairs = make_pairs(0.5, 0.3);
  const SolverOptions options;
  std::vector<Estimate> estimates;
  for (const FramePair& p : pairs) estimates.push_back(solve(p, options));
  const UncertaintyOptions uncertainty;
  size_t i = 0;
  for (auto _ : state) {
    const size_t k = i++ % pairs.size();
    benchmark::DoNotOptimize(sensor_covariance(pairs[k], estimates[k], options, uncertainty));
  }
}

// A flight over blocks and pits (450 features, 0.5 px noise, 30 % of the
// tracks outliers displaced 10-50 px at every frame) through the depth map,
// as the node runs it: the map as it stands after frame 120 (kSteady), the
// next pair as the tracker gives it, and the pairs 121-136 the map filled,
// whose tracks carry their own depths.
constexpr int kSteady = 120;
struct SteadyFlight {
  SolverOptions options;
  FeatureDepthMap map_at_steady;
  FramePair next_unfilled;  // pair kSteady + 1 before the map's fill
  std::vector<int64_t> next_ids;  // its tracks
  std::vector<FramePair> pairs;  // filled from the map, frames kSteady + 1...
};

SteadyFlight steady_flight(AnchorSpots anchor_spots) {
  testing::TerrainSpec spec;
  spec.noise_px = 0.5;
  spec.num_points = 7500;
  testing::TerrainSequence seq(spec);
  SolverOptions options;
  options.variant = Variant::kFeatureDepth;
  options.feature_depth.anchor_spots = anchor_spots;
  SteadyFlight flight{options, FeatureDepthMap(options), {}, {}, {}};
  FeatureDepthMap map(options);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int k = 1; k <= kSteady + 16; ++k) {
    testing::SequencePair sp = seq.pair(k);
    for (size_t i = 0; i < sp.pair.curr_norm.size(); ++i) {
      // 30 % of the tracks are bad ones (mismatched at every frame).
      if (static_cast<uint64_t>(sp.ids[i]) * 2654435761u % 100 >= 30) continue;
      const double angle = 2 * M_PI * unit(rng), size = (10.0 + 40.0 * unit(rng)) / spec.fx;
      sp.pair.curr_norm[i] += size * Eigen::Vector2d(std::cos(angle), std::sin(angle));
    }
    if (k == kSteady + 1) {
      flight.next_unfilled = sp.pair;
      flight.next_ids = sp.ids;
    }
    map.fill(sp.ids, (k - 1) * 71429, &sp.pair);
    map.update(sp.ids, k * 71429, sp.pair, solve(sp.pair, options));
    if (k == kSteady) flight.map_at_steady = map;
    if (k > kSteady) flight.pairs.push_back(sp.pair);
  }
  return flight;
}

// feature_depth's solve in the steady state (the map's update runs outside
// the timed solve, as it is not part of the solver). With the anchor on the
// spots along the track (anchor_spots track), or on the beam alone.
void feature_depth_steady_state(benchmark::State& state, AnchorSpots anchor_spots) {
  const SteadyFlight flight = steady_flight(anchor_spots);
  const std::vector<FramePair>& pairs = flight.pairs;
  size_t i = 0;
  int64_t iterations = 0, frames = 0, features = 0, own = 0;
  for (auto _ : state) {
    const FramePair& pair = pairs[i++ % pairs.size()];
    const Estimate est = solve(pair, flight.options);
    benchmark::DoNotOptimize(est.translation);
    iterations += est.iterations;
    features += static_cast<int64_t>(pair.prev_norm.size());
    for (char c : est.used_own_depth) own += c != 0;
    ++frames;
  }
  state.counters["lm_iterations"] = static_cast<double>(iterations) / std::max<int64_t>(1, frames);
  state.counters["features"] = static_cast<double>(features) / std::max<int64_t>(1, frames);
  state.counters["own_depths"] = static_cast<double>(own) / std::max<int64_t>(1, frames);
}

// The node's other per-frame work for feature_depth, beside the solve: the
// depth map's fill (the pair's own depths) and update (each track's depth
// triangulated and fused) for frame kSteady + 1, the map copied outside the
// timed part.
void BM_FeatureDepthMap_FillUpdate(benchmark::State& state) {
  const SteadyFlight flight = steady_flight(AnchorSpots::kBeam);
  const Estimate est = solve(flight.pairs.front(), flight.options);
  const std::vector<int64_t>& ids = flight.next_ids;
  int64_t depths = 0, frames = 0;
  for (auto _ : state) {
    state.PauseTiming();
    FeatureDepthMap map = flight.map_at_steady;
    FramePair pair = flight.next_unfilled;
    state.ResumeTiming();
    map.fill(ids, kSteady * 71429, &pair);
    map.update(ids, (kSteady + 1) * 71429, pair, est);
    benchmark::DoNotOptimize(map.size());
    depths += static_cast<int64_t>(map.size());
    ++frames;
  }
  state.counters["tracks"] = static_cast<double>(ids.size());
  state.counters["depths"] = static_cast<double>(depths) / std::max<int64_t>(1, frames);
}

void BM_FeatureDepth_Noise05px_Outliers30(benchmark::State& s) { feature_depth_steady_state(s, AnchorSpots::kBeam); }
void BM_FeatureDepth_TrackAnchor_Noise05px_Outliers30(benchmark::State& s) {
  feature_depth_steady_state(s, AnchorSpots::kTrack);
}
void BM_Paper_NoiseFree(benchmark::State& s) { run(s, Variant::kPaper, 0.0, 0.0); }
void BM_Paper_Noise05px_Outliers30(benchmark::State& s) { run(s, Variant::kPaper, 0.5, 0.3); }
// Without the time-reversed solve of the symmetric dz: what it costs.
void BM_Paper_Noise05px_Outliers30_ForwardDz(benchmark::State& s) { run(s, Variant::kPaper, 0.5, 0.3, false); }
// A half turn between the frames, started at the INS heading change.
void BM_Paper_Noise05px_Outliers30_HalfTurn(benchmark::State& s) { run(s, Variant::kPaper, 0.5, 0.3, true, 180.0); }
void BM_LevelGround_Noise05px_Outliers30(benchmark::State& s) { run(s, Variant::kLevelGround, 0.5, 0.3); }
void BM_Homography_Noise05px_Outliers30(benchmark::State& s) { run(s, Variant::kHomography, 0.5, 0.3); }
void BM_Flow_Noise05px_Outliers30(benchmark::State& s) { run(s, Variant::kFlow, 0.5, 0.3); }

BENCHMARK(BM_SensorUncertainty)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Paper_NoiseFree)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Paper_Noise05px_Outliers30)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Paper_Noise05px_Outliers30_ForwardDz)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Paper_Noise05px_Outliers30_HalfTurn)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_LevelGround_Noise05px_Outliers30)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Homography_Noise05px_Outliers30)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Flow_Noise05px_Outliers30)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_FeatureDepth_Noise05px_Outliers30)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_FeatureDepth_TrackAnchor_Noise05px_Outliers30)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_FeatureDepthMap_FillUpdate)->Unit(benchmark::kMicrosecond);

}  // namespace
