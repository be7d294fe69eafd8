#include "tools/map/simulated_map.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>

#include "processes/sim/terrain.h"

namespace nadir::map {
namespace {

// Local north/east of fractional pixel positions: exact (geodetic) at nodes
// every kNodeStep pixels, bilinear in between. The map's projection is
// smooth at this scale (its second derivative moves a 32-pixel cell's middle
// by far less than a millimetre), and it spares a geodetic solve per subsample.
class LocalLookup {
 public:
  static constexpr int kNodeStep = 32;
  LocalLookup(const MapGrid& grid, const LocalProjection& projection) {
    nodes_c_ = grid.width / kNodeStep + 2;
    nodes_r_ = grid.height / kNodeStep + 2;
    nodes_.resize(static_cast<size_t>(nodes_c_) * nodes_r_);
    for (int r = 0; r < nodes_r_; ++r)
      for (int c = 0; c < nodes_c_; ++c) {
        const Eigen::Vector2d p = grid.projected(c * kNodeStep, r * kNodeStep);
        nodes_[static_cast<size_t>(r) * nodes_c_ + c] = projection.local_from_utm(p.x(), p.y());
      }
  }
  Eigen::Vector2d local(double col, double row) const {
    const double fc = col / kNodeStep, fr = row / kNodeStep;
    const int c = std::min(nodes_c_ - 2, static_cast<int>(fc)), r = std::min(nodes_r_ - 2, static_cast<int>(fr));
    const double a = fc - c, b = fr - r;
    const Eigen::Vector2d* n = &nodes_[static_cast<size_t>(r) * nodes_c_ + c];
    return (1 - b) * ((1 - a) * n[0] + a * n[1]) + b * ((1 - a) * n[nodes_c_] + a * n[nodes_c_ + 1]);
  }

 private:
  int nodes_c_ = 0, nodes_r_ = 0;
  std::vector<Eigen::Vector2d> nodes_;
};

// Pearson correlation from running sums.
struct Correlation {
  double n = 0, sx = 0, sy = 0, sxx = 0, syy = 0, sxy = 0;
  void add(double x, double y) {
    n += 1;
    sx += x;
    sy += y;
    sxx += x * x;
    syy += y * y;
    sxy += x * y;
  }
  double value() const {
    const double vx = n * sxx - sx * sx, vy = n * syy - sy * sy;
    return vx > 0 && vy > 0 ? (n * sxy - sx * sy) / std::sqrt(vx * vy) : 0.0;
  }
};

std::string number(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", v);
  return text;
}

}  // namespace

void SimulatedMapOptions::Check() const {
  if (!(gsd_m >= 0.5 && gsd_m <= 2.0)) throw std::invalid_argument("gsd_m " + number(gsd_m) + ": must be in [0.5, 2] m");
  if (!(margin_m >= 0.0 && margin_m <= 5000.0))
    throw std::invalid_argument("margin_m " + number(margin_m) + ": must be in [0, 5000] m");
  if (subsamples < 1 || subsamples > 8)
    throw std::invalid_argument("subsamples " + std::to_string(subsamples) + ": must be in [1, 8]");
  if (!(changed_fraction >= 0.0 && changed_fraction <= 0.1))
    throw std::invalid_argument("changed_fraction " + number(changed_fraction) + ": must be in [0, 0.1]");
  if (!(max_megapixels >= 0.0)) throw std::invalid_argument("max_megapixels " + number(max_megapixels) + ": must be >= 0");
  if (!(max_gsd_m >= gsd_m && max_gsd_m <= 10.0))
    throw std::invalid_argument("max_gsd_m " + number(max_gsd_m) + ": must be in [gsd_m, 10] m");
  season.Check();
}

std::vector<Eigen::Vector2d> flight_track(const sim::FlightProfile& profile, uint64_t seed, double step_s) {
  const sim::Trajectory trajectory(profile, seed);
  std::vector<Eigen::Vector2d> track;
  for (double t = 0.0;; t += step_s) {
    const double tt = std::min(t, trajectory.duration_s());
    track.push_back(trajectory.at(tt).position_ned.head<2>());
    if (tt >= trajectory.duration_s()) break;
  }
  return track;
}

SimulatedMap simulate_map(const sim::FlightProfile& profile, uint64_t seed, const SimulatedMapOptions& options) {
  options.Check();
  const LocalProjection projection(
      {profile.reference_latitude_deg, profile.reference_longitude_deg, profile.reference_height_m});
  std::vector<Eigen::Vector2d> corners;
  for (const Eigen::Vector2d& p : flight_track(profile, seed, 0.5)) corners.push_back(projection.utm(p.x(), p.y()));
  SimulatedMap map;
  map.grid = grid_around(corners, options.margin_m, options.gsd_m, projection.epsg());
  // A pixel budget: the finest ground sample distance up to max_gsd_m (in
  // steps of 0.25 m) that keeps the map within it.
  const double budget = options.max_megapixels * 1e6;
  for (double gsd = options.gsd_m; budget > 0.0 && double(map.grid.width) * map.grid.height > budget;) {
    gsd = std::floor(gsd / 0.25 + 1.0 + 1e-9) * 0.25;
    if (gsd > options.max_gsd_m + 1e-9) {
      throw std::invalid_argument("the flight's map would hold " + number(double(map.grid.width) * map.grid.height / 1e6) +
                                  " million pixels at " + number(options.max_gsd_m) + " m, over max_megapixels " +
                                  number(options.max_megapixels) + ": the flight spans too much ground for one map");
    }
    map.grid = grid_around(corners, options.margin_m, gsd, projection.epsg());
  }
  const MapGrid& g = map.grid;

  const LocalLookup lookup(g, projection);
  map.north_min = map.east_min = 1e300;
  map.north_max = map.east_max = -1e300;
  for (double r : {0.0, static_cast<double>(g.height)})
    for (double c : {0.0, static_cast<double>(g.width)}) {
      const Eigen::Vector2d l = lookup.local(c, r);
      map.north_min = std::min(map.north_min, l.x());
      map.north_max = std::max(map.north_max, l.x());
      map.east_min = std::min(map.east_min, l.y());
      map.east_max = std::max(map.east_max, l.y());
    }
  map.patch_seed = seed * 0x9e3779b97f4a7c15ULL + 0x6d6170;  // the map's own stream, fixed by the run seed
  map.patches = make_changed_patches(map.north_min, map.north_max, map.east_min, map.east_max,
                                     options.changed_fraction, map.patch_seed);
  const PatchIndex patches(map.patches, map.north_min, map.east_min);

  // The simulator's world: its Terrain seeded with the run seed (simulator.cc).
  sim::TerrainOptions terrain_options = profile.terrain;
  terrain_options.seed = seed;
  const sim::Terrain terrain(terrain_options);

  const size_t pixels = static_cast<size_t>(g.width) * g.height;
  map.orthophoto.resize(pixels);
  map.dem.resize(pixels);
  const int k = options.subsamples;
  Correlation correlation;
  for (int row = 0; row < g.height; ++row) {
    for (int col = 0; col < g.width; ++col) {
      double world = 0.0, seen = 0.0;
      for (int i = 0; i < k; ++i)
        for (int j = 0; j < k; ++j) {
          const Eigen::Vector2d l = lookup.local(col + (j + 0.5) / k, row + (i + 0.5) / k);
          const double a = terrain.albedo(l.x(), l.y());
          double changed = 0.0;
          world += a;
          seen += patches.albedo(l.x(), l.y(), &changed) ? changed : a;
        }
      world /= k * k;
      seen /= k * k;
      const Eigen::Vector2d centre = lookup.local(col + 0.5, row + 0.5);
      double dh_dn = 0.0, dh_de = 0.0;
      const double h = terrain.height(centre.x(), centre.y(), &dh_dn, &dh_de);
      const size_t index = static_cast<size_t>(row) * g.width + col;
      map.orthophoto[index] = options.season.apply(seen, dh_dn, dh_de);
      map.dem[index] = static_cast<float>(profile.reference_height_m + h);
      correlation.add(world, map.orthophoto[index]);
    }
  }
  map.albedo_correlation = correlation.value();
  return map;
}

}  // namespace nadir::map
