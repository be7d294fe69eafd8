// The map matcher against maps built to fool it, and against the true map:
// frames rendered by the simulator's renderer at random poses over a
// simulated world, each matched with a prior drawn from its own covariance
// against
//   true        the world's simulated map (another season, changed patches):
//               the control, where fixes must land within their covariance;
//   wrong_place the map of another world (another seed) under the same grid;
//   repetitive  ground that repeats every 25-70 m (a patch of the true map
//               tiled), seen by the camera and in the map alike: every period
//               fits as well as the truth;
//   decoy       the true map with a copy of the frame's own ground pasted a
//               template's width or more away, inside the search: two places
//               fit equally (flights low enough, priors wide enough for it);
//   featureless the true map over the world's featureless area (contrast 0.08,
//               the relief's shading kept, as in the featureless_crossing
//               profile), where fixes are to be refused, not counted as wrong
//               when they come.
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
#include <algorithm>
#include <string>
#include <vector>

#include <Eigen/LU>

#include "common/camera_model.h"
#include "common/config.h"
#include "common/geometry.h"
#include "common/json_writer.h"
#include "common/paths.h"
#include "common/progress.h"
#include "processes/map_matcher/frame_ortho.h"
#include "processes/map_matcher/map_matcher.h"
#include "processes/sim/renderer.h"
#include "processes/sim/sim_camera.h"
#include "processes/sim/terrain.h"
#include "tools/map/geotiff_writer.h"
#include "tools/map/simulated_map.h"
#include "tests/processes/map_matcher/matcher_scene.h"

namespace {

using namespace nadir;

const char* kProfile = R"(
name: map_fooling
distance_m: 2800
speed_mps: 40
altitude_agl_m: 250
initial_heading_deg: 0
reference: {latitude_deg: 40.4406, longitude_deg: -79.9959, height_m: 300.0}
terrain:
  relief_scale: 1.5
  featureless:
    - {north_m: [1700, 2700], east_m: [-600, 600], contrast: 0.08, shore_m: 100}
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

// A north-up crop of a simulated map around a local point, as its own grid.
struct Crop {
  map::MapGrid grid;
  std::vector<uint8_t> ortho;
  std::vector<float> dem;
  int centre_row = 0, centre_col = 0;  // the point's pixel in the crop
};

Crop crop_around(const map::SimulatedMap& m, const map::LocalProjection& origin, double north, double east, int half) {
  const map::MapGrid& g = m.grid;
  const Eigen::Vector2d at = origin.utm(north, east);
  const int cr = static_cast<int>((g.y0 - at.y()) / g.gsd_m), cc = static_cast<int>((at.x() - g.x0) / g.gsd_m);
  const int r0 = std::max(0, cr - half), c0 = std::max(0, cc - half);
  Crop out;
  out.grid = g;
  out.grid.width = std::min(g.width - c0, 2 * half);
  out.grid.height = std::min(g.height - r0, 2 * half);
  out.grid.x0 = g.x0 + c0 * g.gsd_m;
  out.grid.y0 = g.y0 - r0 * g.gsd_m;
  out.centre_row = cr - r0;
  out.centre_col = cc - c0;
  out.ortho.resize(static_cast<size_t>(out.grid.width) * out.grid.height);
  out.dem.resize(out.ortho.size());
  for (int r = 0; r < out.grid.height; ++r)
    for (int c = 0; c < out.grid.width; ++c) {
      const size_t from = static_cast<size_t>(r0 + r) * g.width + (c0 + c), to = static_cast<size_t>(r) * out.grid.width + c;
      out.ortho[to] = m.orthophoto[from];
      out.dem[to] = m.dem[from];
    }
  return out;
}

// A frame of level ground that looks like `ground` (a crop whose pixel
// (centre_row, centre_col) is below the camera), seen from `height` with this
// attitude: the camera's rays meet the plane, the crop is sampled there
// (bilinear), plus 2 DN of noise. `grid_from_local` turns local (north,
// east) metres into the crop's grid (northing, easting) metres: the map
// grid's north is not true north (UTM grid convergence), and the matcher
// honours the difference.
std::vector<uint8_t> render_flat(const CameraModel& camera, const Crop& ground, double height,
                                 const Eigen::Matrix3d& world_from_body, const Eigen::Matrix2d& grid_from_local,
                                 std::mt19937_64* rng) {
  std::vector<cv::Point2f> pixels;
  for (int v = 0; v < camera.height; ++v)
    for (int u = 0; u < camera.width; ++u) pixels.emplace_back(static_cast<float>(u), static_cast<float>(v));
  const std::vector<cv::Point2d> rays = camera.undistort(pixels);
  const Eigen::Matrix3d world_from_camera = world_from_body * camera.body_from_camera;
  std::normal_distribution<double> noise(0.0, 2.0);
  std::vector<uint8_t> image(pixels.size(), 0);
  const double gsd = ground.grid.gsd_m;
  for (size_t i = 0; i < rays.size(); ++i) {
    const Eigen::Vector3d w = world_from_camera * Eigen::Vector3d(rays[i].x, rays[i].y, 1.0);
    if (w.z() <= 0.0) continue;
    const Eigen::Vector2d grid = grid_from_local * Eigen::Vector2d(height * w.x() / w.z(), height * w.y() / w.z());
    const double north = grid.x(), east = grid.y();
    const double row = ground.centre_row + 0.5 - north / gsd - 0.5, col = ground.centre_col + 0.5 + east / gsd - 0.5;
    const int r = static_cast<int>(std::floor(row)), c = static_cast<int>(std::floor(col));
    if (r < 0 || c < 0 || r + 1 >= ground.grid.height || c + 1 >= ground.grid.width) continue;
    const double a = row - r, b = col - c;
    auto at = [&](int rr, int cc) { return double(ground.ortho[static_cast<size_t>(rr) * ground.grid.width + cc]); };
    const double value = (1 - a) * ((1 - b) * at(r, c) + b * at(r, c + 1)) + a * ((1 - b) * at(r + 1, c) + b * at(r + 1, c + 1));
    image[i] = static_cast<uint8_t>(std::clamp(value + noise(*rng), 0.0, 255.0));
  }
  return image;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"The map matcher against maps built to fool it (studies/README.md, docs/research/2026-12-map-fixes.md)",
               "nadir_study_map_fooling"};
  int attempts = 10000;
  uint64_t seed = 21;
  std::string out = "logs/map_fooling";
  bool json_only = false;
  std::vector<std::string> only;
  app.add_option("--attempts", attempts, "fix attempts in all (split over the five kinds)")->capture_default_str();
  app.add_option("--seed", seed, "world seed (the wrong place is seed + 1000)")->capture_default_str();
  app.add_option("--out", out, "output folder (maps, attempts.csv, summary.json)")->capture_default_str();
  app.add_flag("--json", json_only, "no progress bar");
  app.add_option("--kinds", only, "only these kinds, in turn (true, wrong_place, repetitive, decoy, featureless)")
      ->check(CLI::IsMember({"true", "wrong_place", "repetitive", "decoy", "featureless"}));
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
  const int kinds = 5;  // the two maps above, then per attempt: repetitive ground, a decoy; the true map, featureless
  std::vector<Tally> tally(kinds);
  const char* names[kinds] = {"true", "wrong_place", "repetitive", "decoy", "featureless"};
  std::vector<int> selected;
  for (int k = 0; k < kinds; ++k)
    if (only.empty() || std::find(only.begin(), only.end(), names[k]) != only.end()) selected.push_back(k);
  std::mt19937_64 rng(seed * 7919 + 1);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::ofstream csv(out + "/attempts.csv");
  csv << "map,north,east,height_m,prior_sigma_m,accepted,refusal,error_m,mahalanobis,sigma_m,score,peak_ratio,"
         "frame_edge,map_edge,map_self_similarity\n";
  ProgressBar progress("map_fooling", attempts, !json_only && stderr_is_terminal());
  for (int i = 0; i < attempts; ++i) {
    const int kind = selected[static_cast<size_t>(i) % selected.size()];
    // A pose over the flight's ground: along the 1.6 km track, up to 250 m aside.
    // The featureless kind: inside the area, the footprint within its box.
    double north = 100.0 + 1400.0 * uniform(rng), east = -250.0 + 500.0 * uniform(rng);
    if (kind == 4) {
      north = 2000.0 + 400.0 * (north - 100.0) / 1400.0;
      east = 0.6 * east;
    }
    double height = 150.0 + 200.0 * uniform(rng);
    if (kind == 3) height = 120.0 + 80.0 * uniform(rng);  // low: a template narrower than the search
    const double template_m = options.template_fraction * nadir_square_side_m(camera_model, height);
    const Eigen::Vector3d rpy(8.0 * (uniform(rng) - 0.5), 8.0 * (uniform(rng) - 0.5), 360.0 * uniform(rng));
    double sigma = 1.0 + 39.0 * uniform(rng);
    // The decoy needs a search wider than the template: radius 1.15 template .. 200 m.
    if (kind == 3) sigma = (1.15 * template_m + (200.0 - 1.15 * template_m) * uniform(rng)) / options.search_sigmas;
    const double dn = sigma * normal(rng), de = sigma * normal(rng);
    const Eigen::Matrix3d world_from_body =
        rotation_from_rpy(deg_to_rad(rpy.x()), deg_to_rad(rpy.y()), deg_to_rad(rpy.z()));
    Crop crop;
    std::vector<uint8_t> pixels;
    if (kind == 2) {
      // Repetitive ground: a P x P patch of the true map tiled over the crop,
      // the world and the map alike (level).
      const int period = static_cast<int>(25.0 + 45.0 * uniform(rng));
      crop = crop_around(truth_map, origin, north, east, static_cast<int>(1.2 * height + 3.0 * sigma * 4) + 60);
      const std::vector<uint8_t> source = crop.ortho;
      const float level = crop.dem[static_cast<size_t>(crop.centre_row) * crop.grid.width + crop.centre_col];
      for (int r = 0; r < crop.grid.height; ++r)
        for (int c = 0; c < crop.grid.width; ++c) {
          const size_t to = static_cast<size_t>(r) * crop.grid.width + c;
          crop.ortho[to] = source[static_cast<size_t>(r % period) * crop.grid.width + (c % period)];
          crop.dem[to] = level;
        }
      const Eigen::Vector2d at = origin.utm(north, east);
      Eigen::Matrix2d grid_from_local;  // rows (northing, easting), columns (north, east)
      const Eigen::Vector2d d_north = origin.utm(north + 1.0, east) - at, d_east = origin.utm(north, east + 1.0) - at;
      grid_from_local << d_north.y(), d_east.y(), d_north.x(), d_east.x();
      pixels = render_flat(camera_model, crop, height, world_from_body, grid_from_local, &rng);
    } else {
      renderer.render({north, east, -(terrain.height(north, east) + height)},
                      world_from_body * camera.body_from_camera, static_cast<uint64_t>(i), &pixels);
    }
    const int64_t utime = 1'000'000 + i;
    const image_t image = test::mono8_frame(std::move(pixels), camera.width, camera.height, utime);
    const pose_t pose = test::prior_pose(north + dn, east + de, rpy * M_PI / 180.0, height, sigma, utime);

    if (kind == 3) {
      // The frame's ground (a square a little larger than the template)
      // copied a template's width or more away, inside the search radius.
      const double radius = options.search_sigmas * sigma;
      crop = crop_around(truth_map, origin, north, east, static_cast<int>(2.0 * radius + template_m) + 60);
      const double angle = 2.0 * M_PI * uniform(rng);
      const double reach = 1.05 * template_m + (radius - 1.05 * template_m) * uniform(rng);
      const int half = static_cast<int>(0.5 * template_m) + 5;
      const int dr = static_cast<int>(std::lround(-reach * std::cos(angle))), dc = static_cast<int>(std::lround(reach * std::sin(angle)));
      const std::vector<uint8_t> source = crop.ortho;
      for (int r = -half; r <= half; ++r)
        for (int c = -half; c <= half; ++c) {
          const int sr = crop.centre_row + r, sc = crop.centre_col + c, tr = sr + dr, tc = sc + dc;
          if (sr < 0 || sc < 0 || tr < 0 || tc < 0 || sr >= crop.grid.height || tr >= crop.grid.height ||
              sc >= crop.grid.width || tc >= crop.grid.width)
            continue;
          crop.ortho[static_cast<size_t>(tr) * crop.grid.width + tc] = source[static_cast<size_t>(sr) * crop.grid.width + sc];
        }
    }
    const auto start = std::chrono::steady_clock::now();
    FixAttempt a;
    if (kind < 2 || kind == 4) {
      a = matchers[kind == 4 ? 0 : static_cast<size_t>(kind)].attempt(image, pose, origin);
    } else {
      const std::string dir = write(names[kind], crop.grid, crop.ortho, crop.dem);
      const MapMatcher per_attempt(options, camera_model,
                                   map::ReferenceMap::open(dir + "/orthophoto.tif", dir + "/dem.tif"));
      a = per_attempt.attempt(image, pose, origin);
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
    char row[500];
    std::snprintf(row, sizeof(row), "%s,%.2f,%.2f,%.1f,%.2f,%d,%s,%.3f,%.3f,%.3f,%.4f,%.3f,%.3f,%.3f,%.4f\n",
                  names[kind], north, east, height, sigma, a.refusal == FixRefusal::kNone ? 1 : 0,
                  fix_refusal_name(a.refusal), error, mahalanobis, fix_sigma, a.fix.score, a.fix.peak_ratio,
                  a.frame_edge_strength, a.map_edge_strength, a.map_self_similarity);
    csv << row;
    progress.update(i + 1);
  }
  progress.finish();
  JsonWriter j;
  j.begin_object().field("attempts", static_cast<int64_t>(attempts)).field("seed", static_cast<int64_t>(seed));
  j.key("maps").begin_object();
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
