// Rendered frames per second at 612x512 on one core, along the test profiles
// (successive frames at 14 Hz, so texture tiles are generated as in a run).
#include <benchmark/benchmark.h>
#include <opencv2/core.hpp>

#include "common/config.h"
#include "processes/sim/flight_profile.h"
#include "processes/sim/renderer.h"
#include "processes/sim/sim_camera.h"

namespace {

void render_along(benchmark::State& state, const char* profile_name) {
  cv::setNumThreads(1);
  const std::string root = NADIR_SOURCE_DIR;
  const auto camera = nadir::sim::SimCamera::from_config(nadir::Config::load_file(root + "/config/default.yaml"));
  const auto profile = nadir::sim::FlightProfile::load(root + "/config/profiles/" + profile_name + ".yaml");
  nadir::sim::TerrainOptions terrain_options = profile.terrain;
  terrain_options.seed = 7;
  const nadir::sim::Terrain terrain(terrain_options);
  const nadir::sim::Trajectory trajectory(profile, 7);
  nadir::sim::Renderer renderer(camera, terrain, nadir::sim::RendererOptions{});
  std::vector<uint8_t> image;
  int64_t k = 0;
  int64_t marched = 0;
  for (auto _ : state) {
    const double t = std::fmod(k / camera.rate_hz, trajectory.duration_s());
    const nadir::sim::TruthState s = trajectory.at(t);
    renderer.render(s.position_ned, s.world_from_body() * camera.body_from_camera, static_cast<uint64_t>(k), &image);
    marched += renderer.last_stats().marched_pixels;
    benchmark::DoNotOptimize(image.data());
    ++k;
  }
  state.SetItemsProcessed(state.iterations());
  state.counters["frames_per_s"] = benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
  state.counters["marched_px_per_frame"] = static_cast<double>(marched) / std::max<int64_t>(1, k);
}

void BM_RenderTest1(benchmark::State& state) { render_along(state, "test1"); }
void BM_RenderTest2(benchmark::State& state) { render_along(state, "test2"); }
BENCHMARK(BM_RenderTest1)->Unit(benchmark::kMillisecond)->MinTime(5.0);
BENCHMARK(BM_RenderTest2)->Unit(benchmark::kMillisecond)->MinTime(5.0);

}  // namespace
