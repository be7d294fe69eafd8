// The map matcher against maps built to fool it, and against the true map:
// frames rendered by the simulator's renderer at random poses over a
// simulated world, each matched with a prior drawn from its own covariance
// against
//   true        the world's simulated map (another season, changed patches):
//               the control, where fixes must land within their covariance;
//   wrong_place the map of another world (another seed) under the same grid;
//   tiled       the true map made repetitive: every TILE metres around the
//               flight the same ground again (shifted copies of the truth
//               within the search);
//   shifted     the true map with a copy of the frame's own ground pasted at
//               a random offset inside the search (one decoy as good as the truth).
// An accepted fix is wrong when its error against the truth exceeds 3 sigma
// (Mahalanobis distance of its own covariance). Prints a JSON summary and
// writes one CSV row per attempt.
#include <CLI/CLI.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <random>
#include <string>
#include <vector>

#include <Eigen/LU>

#include "common/camera_model.h"
#include "common/config.h"
#include "common/geometry.h"
#include "common/json_writer.h"
#include "common/paths.h"
#include "common/progress.h"
#include "processes/map_matcher/map_matcher.h"
#include "processes/sim/renderer.h"
#include "processes/sim/sim_camera.h"
#include "processes/sim/terrain.h"
#include "tools/map/geotiff_writer.h"
#include "tools/map/simulated_map.h"

namespace {

using namespace nadir;

const char* kProfile = R"(
name: map_fooling
distance_m: 1600
speed_mps: 40
altitude_agl_m: 250
initial_heading_deg: 0
reference: {latitude_deg: 40.4406, longitude_deg: -79.9959, height_m: 300.0}
terrain: {relief_scale: 1.5}
legs:
  - {type: straight}
)";

struct Case {
  std::string name;
  std::string dir;
};

struct Tally {
  int64_t attempts = 0, accepted = 0, wrong = 0;
  double worst_mahalanobis = 0.0, max_error_m = 0.0;
  std::map<std::string, int64_t> refusals;
  double match_ms = 0.0;
};

// The map made repetitive: pixel p takes the value of the pixel at
// centre + ((p - centre + tile/2) mod tile - tile/2) (per axis).
std::vector<uint8_t> tiled(const map::SimulatedMap& m, int tile_px) {
  std::vector<uint8_t> out(m.orthophoto.size());
  const int cr = m.grid.height / 2, cc = m.grid.width / 2;
  auto wrap = [tile_px](int d) { return ((d + tile_px / 2) % tile_px + tile_px) % tile_px - tile_px / 2; };
  for (int r = 0; r < m.grid.height; ++r)
    for (int c = 0; c < m.grid.width; ++c) {
      const int sr = cr + wrap(r - cr), sc = cc + wrap(c - cc);
      out[static_cast<size_t>(r) * m.grid.width + c] = m.orthophoto[static_cast<size_t>(sr) * m.grid.width + sc];
    }
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"The map matcher against maps built to fool it (studies/map_fooling/README.md)",
               "nadir_study_map_fooling"};
  int attempts = 10000;
  uint64_t seed = 21;
  std::string out = "logs/map_fooling";
  double tile_m = 160.0;
  bool json_only = false;
  app.add_option("--attempts", attempts, "fix attempts in all (split over the four maps)")->capture_default_str();
  app.add_option("--seed", seed, "world seed (the wrong place is seed + 1000)")->capture_default_str();
  app.add_option("--out", out, "output folder (maps, attempts.csv, summary.json)")->capture_default_str();
  app.add_option("--tile", tile_m, "tiled map: the period of its repetition, m")->capture_default_str();
  app.add_flag("--json", json_only, "no progress bar");
  CLI11_PARSE(app, argc, argv);

  const Config config = Config::load_file(default_config_path());
  const sim::FlightProfile profile = sim::FlightProfile::parse(kProfile, "map_fooling profile");
  sim::TerrainOptions terrain_options = profile.terrain;
  terrain_options.seed = seed;
  const sim::Terrain terrain(terrain_options);
  map::SimulatedMapOptions map_options;
  map_options.margin_m = 700.0;
  std::system(("mkdir -p '" + out + "'").c_str());
  const map::SimulatedMap truth_map = map::simulate_map(profile, seed, map_options);
  const map::SimulatedMap other_map = map::simulate_map(profile, seed + 1000, map_options);
  auto write = [&](const std::string& name, const map::MapGrid& grid, const std::vector<uint8_t>& ortho,
                   const std::vector<float>& dem) {
    const std::string dir = out + "/" + name;
    std::system(("mkdir -p '" + dir + "'").c_str());
    map::write_geotiff_byte(dir + "/orthophoto.tif", grid, ortho);
    map::write_geotiff_float(dir + "/dem.tif", grid, dem, -9999.0);
    return dir;
  };
  std::vector<Case> cases = {
      {"true", write("true", truth_map.grid, truth_map.orthophoto, truth_map.dem)},
      {"wrong_place", write("wrong_place", other_map.grid, other_map.orthophoto, truth_map.dem)},
      {"tiled", write("tiled", truth_map.grid, tiled(truth_map, static_cast<int>(tile_m / truth_map.grid.gsd_m)),
                      truth_map.dem)},
  };
  const CameraModel camera_model = CameraModel::from_config(config);
  const sim::SimCamera camera = sim::SimCamera::from_config(config);
  sim::Renderer renderer(camera, terrain, sim::RendererOptions{});
  GeodeticPoint reference;
  reference.latitude_deg = profile.reference_latitude_deg;
  reference.longitude_deg = profile.reference_longitude_deg;
  const map::LocalProjection origin(reference);
  MapMatcherOptions options = MapMatcherOptions::from_config(config);
  std::vector<MapMatcher> matchers;
  for (const Case& c : cases) {
    matchers.emplace_back(options, camera_model, map::ReferenceMap::open(c.dir + "/orthophoto.tif", c.dir + "/dem.tif"));
  }
  const int kinds = 4;  // the three maps above and "shifted" (a decoy pasted into the true map per attempt)
  std::vector<Tally> tally(kinds);
  const char* names[kinds] = {"true", "wrong_place", "tiled", "shifted"};
  std::mt19937_64 rng(seed * 7919 + 1);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::ofstream csv(out + "/attempts.csv");
  csv << "map,north,east,height_m,prior_sigma_m,accepted,refusal,error_m,mahalanobis,sigma_m,score,peak_ratio\n";
  ProgressBar progress("map_fooling", attempts, !json_only && stderr_is_terminal());
  for (int i = 0; i < attempts; ++i) {
    const int kind = i % kinds;
    // A pose over the flight's ground: along the 1.6 km track, up to 250 m aside.
    const double north = 100.0 + 1400.0 * uniform(rng), east = -250.0 + 500.0 * uniform(rng);
    const double height = 150.0 + 200.0 * uniform(rng);
    const Eigen::Vector3d rpy(4.0 * (uniform(rng) - 0.5) * 2, 4.0 * (uniform(rng) - 0.5) * 2, 360.0 * uniform(rng));
    const double sigma = 1.0 + 39.0 * uniform(rng);
    const double dn = sigma * normal(rng), de = sigma * normal(rng);
    const Eigen::Matrix3d world_from_body =
        rotation_from_rpy(deg_to_rad(rpy.x()), deg_to_rad(rpy.y()), deg_to_rad(rpy.z()));
    std::vector<uint8_t> pixels;
    renderer.render({north, east, -(terrain.height(north, east) + height)}, world_from_body * camera.body_from_camera,
                    static_cast<uint64_t>(i), &pixels);
    image_t image{};
    image.utime = 1'000'000 + i;
    image.width = camera.width;
    image.height = camera.height;
    image.stride = camera.width;
    image.pixel_format = image_t::PIXEL_MONO8;
    image.size = static_cast<int32_t>(pixels.size());
    image.data = std::move(pixels);
    pose_t pose{};
    pose.utime = image.utime;
    pose.position_ned[0] = north + dn;
    pose.position_ned[1] = east + de;
    pose.roll = deg_to_rad(rpy.x());
    pose.pitch = deg_to_rad(rpy.y());
    pose.yaw = deg_to_rad(rpy.z());
    pose.height_agl_m = height;
    pose.position_covariance[0][0] = pose.position_covariance[1][1] = sigma * sigma;
    pose.position_covariance[2][2] = 1.0;

    const auto start = std::chrono::steady_clock::now();
    FixAttempt a;
    if (kind < 3) {
      a = matchers[static_cast<size_t>(kind)].attempt(image, pose, origin);
    } else {
      // A decoy: the true map with the frame's own ground pasted at an offset
      // inside the search radius (between 0.4 and 0.9 of it) around the prior.
      const double radius = std::max(options.min_search_radius_m, options.search_sigmas * sigma);
      const double angle = 2.0 * M_PI * uniform(rng), reach = radius * (0.4 + 0.5 * uniform(rng));
      // On a crop of the map around the pose (written per attempt: small).
      const map::MapGrid& g = truth_map.grid;
      const Eigen::Vector2d at = origin.utm(north, east);
      const int half = static_cast<int>(0.45 * height / g.gsd_m) + 2;
      const int cr = static_cast<int>((g.y0 - at.y()) / g.gsd_m), cc = static_cast<int>((at.x() - g.x0) / g.gsd_m);
      const int crop_half = half + static_cast<int>(2.0 * radius / g.gsd_m) + 40;
      map::MapGrid crop = g;
      const int r0 = std::max(0, cr - crop_half), c0 = std::max(0, cc - crop_half);
      crop.width = std::min(g.width - c0, 2 * crop_half);
      crop.height = std::min(g.height - r0, 2 * crop_half);
      crop.x0 = g.x0 + c0 * g.gsd_m;
      crop.y0 = g.y0 - r0 * g.gsd_m;
      std::vector<uint8_t> ortho(static_cast<size_t>(crop.width) * crop.height);
      std::vector<float> dem(ortho.size());
      for (int r = 0; r < crop.height; ++r)
        for (int c = 0; c < crop.width; ++c) {
          const size_t from = static_cast<size_t>(r0 + r) * g.width + (c0 + c);
          ortho[static_cast<size_t>(r) * crop.width + c] = truth_map.orthophoto[from];
          dem[static_cast<size_t>(r) * crop.width + c] = truth_map.dem[from];
        }
      const int dr = static_cast<int>(std::lround(-reach * std::cos(angle) / g.gsd_m));
      const int dc = static_cast<int>(std::lround(reach * std::sin(angle) / g.gsd_m));
      for (int r = -half; r <= half; ++r)
        for (int c = -half; c <= half; ++c) {
          const int sr = cr + r - r0, sc = cc + c - c0, tr = sr + dr, tc = sc + dc;
          if (sr < 0 || sc < 0 || tr < 0 || tc < 0 || sr >= crop.height || tr >= crop.height || sc >= crop.width ||
              tc >= crop.width)
            continue;
          ortho[static_cast<size_t>(tr) * crop.width + tc] = truth_map.orthophoto[static_cast<size_t>(sr + r0) * g.width + sc + c0];
        }
      const std::string dir = write("shifted", crop, ortho, dem);
      const MapMatcher decoy(options, camera_model, map::ReferenceMap::open(dir + "/orthophoto.tif", dir + "/dem.tif"));
      a = decoy.attempt(image, pose, origin);
    }
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    Tally& t = tally[static_cast<size_t>(kind)];
    ++t.attempts;
    t.match_ms += ms;
    double error = -1, mahalanobis = -1, fix_sigma = -1;
    if (a.refusal == FixRefusal::kNone) {
      ++t.accepted;
      const Eigen::Vector2d e(a.fix.position_ne[0] - north, a.fix.position_ne[1] - east);
      Eigen::Matrix2d cov;
      cov << a.fix.covariance_ne[0][0], a.fix.covariance_ne[0][1], a.fix.covariance_ne[1][0],
          a.fix.covariance_ne[1][1];
      error = e.norm();
      mahalanobis = std::sqrt(e.dot(cov.inverse() * e));
      fix_sigma = std::sqrt(std::max(cov(0, 0), cov(1, 1)));
      if (mahalanobis > 3.0) ++t.wrong;
      t.worst_mahalanobis = std::max(t.worst_mahalanobis, mahalanobis);
      t.max_error_m = std::max(t.max_error_m, error);
    } else {
      ++t.refusals[fix_refusal_name(a.refusal)];
    }
    char row[400];
    std::snprintf(row, sizeof(row), "%s,%.2f,%.2f,%.1f,%.2f,%d,%s,%.3f,%.3f,%.3f,%.4f,%.3f\n", names[kind], north, east,
                  height, sigma, a.refusal == FixRefusal::kNone ? 1 : 0, fix_refusal_name(a.refusal), error,
                  mahalanobis, fix_sigma, a.fix.score, a.fix.peak_ratio);
    csv << row;
    progress.update(i + 1);
  }
  progress.finish();
  JsonWriter j;
  j.begin_object().field("attempts", static_cast<int64_t>(attempts)).field("seed", static_cast<int64_t>(seed));
  j.field("tile_m", tile_m).key("maps").begin_object();
  for (int k = 0; k < kinds; ++k) {
    const Tally& t = tally[static_cast<size_t>(k)];
    j.key(names[k]).begin_object();
    j.field("attempts", t.attempts).field("accepted", t.accepted).field("wrong_beyond_3_sigma", t.wrong);
    j.field("worst_mahalanobis", t.worst_mahalanobis).field("max_error_m", t.max_error_m);
    j.field("mean_ms_per_attempt", t.attempts ? t.match_ms / t.attempts : 0.0);
    j.key("refusals").begin_object();
    for (const auto& [reason, n] : t.refusals) j.field(reason, n);
    j.end_object().end_object();
  }
  j.end_object().end_object();
  std::ofstream(out + "/summary.json") << j.str() << "\n";
  std::printf("%s\n", j.str().c_str());
  return 0;
}
