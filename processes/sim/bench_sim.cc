// Rendered frames per second at 612x512 on one core, along the test profiles
// and the rough ones (successive frames at 14 Hz, so texture tiles are
// generated as in a run).
#include <benchmark/benchmark.h>
#include <opencv2/core.hpp>

#include "common/config.h"
#include "processes/sim/flight_profile.h"
#include "processes/sim/renderer.h"
#include "processes/sim/sim_camera.h"

namespace {

// relief_scale < 0: the profile's own relief.
void render_along(benchmark::State& state, const char* profile_name, double relief_scale = -1.0) {
  cv::setNumThreads(1);
  const std::string root = NADIR_SOURCE_DIR;
  const auto camera = nadir::sim::SimCamera::from_config(nadir::Config::load_file(root + "/config/default.yaml"));
  const auto profile = nadir::sim::FlightProfile::load(root + "/config/profiles/" + profile_name + ".yaml");
  nadir::sim::TerrainOptions terrain_options = profile.terrain;
  terrain_options.seed = 7;
  if (relief_scale >= 0.0) terrain_options.relief_scale = relief_scale;
  const nadir::sim::Terrain terrain(terrain_options);
  const nadir::sim::Trajectory trajectory(profile, 7);
  nadir::sim::Renderer renderer(camera, terrain, nadir::sim::RendererOptions{});
  std::vector<uint8_t> image;
  // The first frame generates every texture tile in view (~1 s, once per
  // run); the benchmark measures the steady state along the flight.
  {
    const nadir::sim::TruthState s0 = trajectory.at(0.0);
    renderer.render(s0.position_ned, s0.world_from_body() * camera.body_from_camera, 0, &image);
  }
  const int64_t tiles0 = renderer.texture().tiles_generated();
  int64_t k = 1;
  int64_t marched = 0, full = 0, local = 0;
  for (auto _ : state) {
    const double t = std::fmod(k / camera.rate_hz, trajectory.duration_s());
    const nadir::sim::TruthState s = trajectory.at(t);
    renderer.render(s.position_ned, s.world_from_body() * camera.body_from_camera, static_cast<uint64_t>(k), &image);
    marched += renderer.last_stats().marched_pixels;
    full += renderer.last_stats().full_solves;
    local += renderer.last_stats().local_bound_pixels;
    benchmark::DoNotOptimize(image.data());
    ++k;
  }
  state.SetItemsProcessed(state.iterations());
  state.counters["frames_per_s"] = benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
  state.counters["full_solves_per_frame"] = static_cast<double>(full) / std::max<int64_t>(1, k - 1);
  state.counters["tiles_per_frame"] =
      static_cast<double>(renderer.texture().tiles_generated() - tiles0) / std::max<int64_t>(1, k - 1);
  state.counters["marched_px_per_frame"] = static_cast<double>(marched) / std::max<int64_t>(1, k - 1);
  state.counters["local_bound_px_per_frame"] = static_cast<double>(local) / std::max<int64_t>(1, k - 1);
}

void BM_RenderTest1(benchmark::State& state) { render_along(state, "test1"); }
// Same pose every frame: the per-pixel cost without texture generation.
void BM_RenderStatic(benchmark::State& state) {
  cv::setNumThreads(1);
  const std::string root = NADIR_SOURCE_DIR;
  const auto camera = nadir::sim::SimCamera::from_config(nadir::Config::load_file(root + "/config/default.yaml"));
  const auto profile = nadir::sim::FlightProfile::load(root + "/config/profiles/test1.yaml");
  nadir::sim::TerrainOptions terrain_options = profile.terrain;
  const nadir::sim::Terrain terrain(terrain_options);
  const nadir::sim::Trajectory trajectory(profile, 7);
  nadir::sim::Renderer renderer(camera, terrain, nadir::sim::RendererOptions{});
  std::vector<uint8_t> image;
  const nadir::sim::TruthState s = trajectory.at(0.0);
  for (auto _ : state) {
    renderer.render(s.position_ned, s.world_from_body() * camera.body_from_camera, 1, &image);
    benchmark::DoNotOptimize(image.data());
  }
  state.counters["frames_per_s"] = benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_RenderStatic)->Unit(benchmark::kMillisecond);
void BM_RenderTest2(benchmark::State& state) { render_along(state, "test2"); }
BENCHMARK(BM_RenderTest1)->Unit(benchmark::kMillisecond)->MinTime(5.0);
BENCHMARK(BM_RenderTest2)->Unit(benchmark::kMillisecond)->MinTime(5.0);
// The rough profiles over their own relief and over flat ground
// (the same flight); the renderer should cost about the same on both.
void BM_RenderRough120Flat(benchmark::State& state) { render_along(state, "rough_120", 0.0); }
void BM_RenderRough120Relief3(benchmark::State& state) { render_along(state, "rough_120", 3.0); }
void BM_RenderRough250Flat(benchmark::State& state) { render_along(state, "rough_250", 0.0); }
void BM_RenderRough250Relief(benchmark::State& state) { render_along(state, "rough_250"); }
BENCHMARK(BM_RenderRough120Flat)->Unit(benchmark::kMillisecond)->MinTime(5.0);
BENCHMARK(BM_RenderRough120Relief3)->Unit(benchmark::kMillisecond)->MinTime(5.0);
BENCHMARK(BM_RenderRough250Flat)->Unit(benchmark::kMillisecond)->MinTime(5.0);
BENCHMARK(BM_RenderRough250Relief)->Unit(benchmark::kMillisecond)->MinTime(5.0);

}  // namespace
