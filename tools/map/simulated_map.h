#pragma once
// The reference map of a simulated world: an orthophoto and a DEM of exactly
// the terrain `nadir_sim --profile P --seed N` flies over (the Terrain seeded
// with the run seed, as the simulator does), covering the flight's horizontal
// extent plus a margin, on the UTM grid of map_grid.h.
//
// Orthophoto pixel: the terrain albedo averaged over the pixel's footprint
// (a box filter of subsamples x subsamples points on a regular grid inside
// it), with the changed patches' albedo where they lie, then the season
// transform (season_transform.h) with the terrain gradient at the pixel
// centre. DEM pixel: reference height + Terrain::height at the pixel centre
// (ellipsoidal, Float32, on the orthophoto's grid).

#include <cstdint>
#include <vector>

#include "processes/sim/flight_profile.h"
#include "tools/map/changed_patches.h"
#include "tools/map/map_grid.h"
#include "tools/map/season_transform.h"

namespace nadir::map {

struct SimulatedMapOptions {
  double gsd_m = 1.0;        // ground sample distance, [0.5, 2]
  double margin_m = 500.0;   // around the flight's horizontal extent, [0, 5000]
  int subsamples = 3;        // per pixel side (box filter), [1, 8]
  double changed_fraction = 0.02;  // of the map's area, [0, 0.1]
  // More pixels than this (millions; 0: no limit) at gsd_m: the map is made
  // at the finest gsd in steps of 0.25 m up to max_gsd_m that keeps within
  // it (invalid_argument beyond). The gsd used is the grid's.
  double max_megapixels = 0.0;
  double max_gsd_m = 2.0;  // [gsd_m, 10]
  SeasonTransform season;
  // Throws std::invalid_argument naming the option and its range.
  void Check() const;
};

struct SimulatedMap {
  MapGrid grid;
  std::vector<uint8_t> orthophoto;  // row-major, grid.width * grid.height
  std::vector<float> dem;           // same grid, metres above the WGS84 ellipsoid
  std::vector<ChangedPatch> patches;
  uint64_t patch_seed = 0;
  // Local north/east box the grid covers (for the record).
  double north_min = 0, north_max = 0, east_min = 0, east_max = 0;
  // Pearson correlation of the orthophoto with the footprint-averaged albedo
  // of the world (without patches or season): how alike map and world are.
  double albedo_correlation = 0.0;
};

SimulatedMap simulate_map(const sim::FlightProfile& profile, uint64_t seed, const SimulatedMapOptions& options);

// The trajectory's horizontal positions (local north/east) every `step_s`.
std::vector<Eigen::Vector2d> flight_track(const sim::FlightProfile& profile, uint64_t seed, double step_s);

}  // namespace nadir::map
