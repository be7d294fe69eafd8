// Cost of one fix attempt (orthorectify, map window, edge pictures, search,
// covariance) on a frame the simulator renders over its simulated map, at
// two heights and two prior sigmas; the CPU share at one attempt per second
// (map_matcher.interval_s) is the CPU time per attempt over 1 s. For scale, the same run times cv::matchTemplate of
// the template alone over the same search (the search's share of the attempt).
#include <benchmark/benchmark.h>
#include <opencv2/imgproc.hpp>

#include <memory>
#include <string>

#include "common/camera_model.h"
#include "common/config.h"
#include "processes/map_matcher/map_matcher.h"
#include "processes/sim/sim_camera.h"
#include "processes/sim/terrain.h"
#include "tests/common/test_support.h"
#include "tests/processes/map_matcher/matcher_scene.h"

namespace {

using namespace nadir;

const char* kProfile = R"(
name: bench
distance_m: 800
speed_mps: 20
altitude_agl_m: 300
initial_heading_deg: 0
reference: {latitude_deg: 40.4406, longitude_deg: -79.9959, height_m: 300.0}
terrain: {relief_scale: 1.0}
legs:
  - {type: straight}
)";

struct Bench {
  Config config = Config::load_file(std::string(NADIR_SOURCE_DIR) + "/config/default.yaml");
  sim::FlightProfile profile = sim::FlightProfile::parse(kProfile, "bench");
  testing::TempDir dir{"bench_map_matcher"};
  std::unique_ptr<sim::Terrain> terrain;
  std::unique_ptr<MapMatcher> matcher;
  Bench() {
    sim::TerrainOptions t = profile.terrain;
    t.seed = 3;
    terrain = std::make_unique<sim::Terrain>(t);
    test::write_simulated_map(dir.path(), profile, 3, 400.0);
    matcher = std::make_unique<MapMatcher>(MapMatcherOptions::from_config(config), CameraModel::from_config(config),
                                           map::ReferenceMap::open(dir.file("orthophoto.tif"), dir.file("dem.tif")));
  }
  map::LocalProjection origin() const {
    return map::LocalProjection({profile.reference_latitude_deg, profile.reference_longitude_deg, 0.0});
  }
  image_t frame(double height) const {
    return test::rendered_frame(sim::SimCamera::from_config(config), *terrain, 400.0, 50.0, height, {0.01, -0.02, 0.5},
                                1, 0);
  }
  pose_t pose(double height, double sigma) const {
    return test::prior_pose(403.0, 48.0, {0.01, -0.02, 0.5}, height, sigma, 0);
  }
};

Bench& bench() {
  static Bench b;
  return b;
}

void BM_FixAttempt(benchmark::State& state) {
  const double height = static_cast<double>(state.range(0)), sigma = static_cast<double>(state.range(1));
  const image_t image = bench().frame(height);
  const pose_t pose = bench().pose(height, sigma);
  const map::LocalProjection origin = bench().origin();
  bool accepted = false;
  for (auto _ : state) {
    const FixAttempt a = bench().matcher->attempt(image, pose, origin);
    accepted = a.refusal == FixRefusal::kNone;
    benchmark::DoNotOptimize(a);
  }
  state.counters["accepted"] = accepted ? 1.0 : 0.0;
}
BENCHMARK(BM_FixAttempt)->Args({150, 5})->Args({300, 5})->Args({300, 30})->Unit(benchmark::kMillisecond);

// The search alone: cv::matchTemplate of a template the size the attempt
// uses at 300 m over the window a 5 m prior gives.
void BM_MatchTemplateAlone(benchmark::State& state) {
  const int t = state.range(0), w = t + 2 * state.range(1);
  cv::Mat window(w, w, CV_32F), templ(t, t, CV_32F), out;
  cv::randu(window, 0, 255);
  cv::randu(templ, 0, 255);
  for (auto _ : state) {
    cv::matchTemplate(window, templ, out, cv::TM_CCOEFF_NORMED);
    benchmark::DoNotOptimize(out.data);
  }
}
BENCHMARK(BM_MatchTemplateAlone)->Args({245, 15})->Unit(benchmark::kMillisecond);

}  // namespace
