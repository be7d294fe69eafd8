#pragma once
// Procedural, seeded terrain: a height field with gentle hills and sharper
// ridges, and a ground albedo with fields, hedges, roads, tree clusters, rocks
// and fine grain. Everything is a pure function of (seed, north, east), so any
// position is computable and the terrain extends as far as any profile flies.
// Heights are relative to the terrain at the world origin (the start point),
// which is the altitude datum: height(0, 0) == 0. Featureless areas
// (featureless_area.h) weaken the albedo's texture in boxes of the map.
//
// With TerrainOptions::ground set, the height and albedo come from that
// source instead (ground_source.h; e.g. the orthophoto and DEM of a real
// place; the seed is then unused here): relief_scale multiplies the source's
// heights about the datum, and the featureless areas, the 1 m grid, its
// tiles and bounds work as for the procedural field. Without it
// everything is exactly as before (same bits).
//
// The surface everyone uses (renderer, altimeter, ground truth) is the
// analytic height sampled on a 1 m grid and interpolated bilinearly: cheap
// enough for one evaluation per pixel, and within millimetres of the
// analytic field (whose finest relief has ~140 m cells). Sample tiles are
// cached; a Terrain is therefore not thread-safe.

#include <cmath>
#include <cstdint>
#include <memory>
#include <unordered_map>
#include <vector>

#include "processes/sim/featureless_area.h"
#include "processes/sim/ground_source.h"

namespace nadir::sim {

// Bounds of the sampled (bilinear) surface over a region: exact for it (a
// bilinear cell lies between its corner samples, and its gradient components
// between its edge differences), so a ray caster may skip empty space with them.
struct HeightBounds {
  double min_height = 0.0, max_height = 0.0;
  double max_slope = 0.0;  // >= |grad h| anywhere in the region
};

struct TerrainOptions {
  uint64_t seed = 1;
  double relief_scale = 1.0;   // multiplies every height octave; 0 = flat
  std::vector<FeaturelessArea> featureless;  // low-texture areas (water, snow); none by default
  // Heights and albedo from here instead of the procedural field (null: procedural).
  std::shared_ptr<const GroundSource> ground;
  // Throws std::invalid_argument naming the key (terrain.featureless[1].contrast).
  void Check() const;
};

class Terrain {
 public:
  explicit Terrain(const TerrainOptions& options);

  // Height above the datum (m, up positive) and, if asked, its gradient
  // (dh/dnorth, dh/deast).
  // Inline: the renderer calls it once per pixel.
  double height(double north, double east, double* dh_dn = nullptr, double* dh_de = nullptr) const {
    const double fn = std::floor(north), fe = std::floor(east);
    const int32_t in = static_cast<int32_t>(fn), ie = static_cast<int32_t>(fe);
    const int32_t tx = in >> kHeightTileLog2, ty = ie >> kHeightTileLog2;
    const int64_t key = (static_cast<int64_t>(tx) << 32) ^ static_cast<int64_t>(static_cast<uint32_t>(ty));
    const HeightTile* t = key == last_key_ ? last_tile_ : height_tile(tx, ty);
    const int i = in - tx * kHeightTile, j = ie - ty * kHeightTile;
    const float* p = &t->h[i * (kHeightTile + 1) + j];
    const double h00 = p[0], h01 = p[1], h10 = p[kHeightTile + 1], h11 = p[kHeightTile + 2];
    const double a = north - fn, b = east - fe;
    if (dh_dn) {
      *dh_dn = (h10 - h00) * (1.0 - b) + (h11 - h01) * b;
      *dh_de = (h01 - h00) * (1.0 - a) + (h11 - h10) * a;
    }
    return h00 + (h10 - h00) * a + (h01 - h00) * b + (h00 - h01 - h10 + h11) * a * b;
  }
  // The analytic field the grid samples (datum-relative), for tests.
  double exact_height(double north, double east) const { return raw_height(north, east, nullptr, nullptr) - datum_; }
  // Bounds used by the ray caster: |grad h| <= max_slope(), and
  // min_height() <= height <= max_height() everywhere.
  double max_slope() const { return max_slope_; }
  double max_height() const { return max_height_; }
  double min_height() const { return min_height_; }
  // Side (m) of the square tiles the sampled surface is cached in; tile
  // (tx, ty) covers north [tx, tx + 1) * side, east [ty, ty + 1) * side.
  static constexpr double kBoundsTileM = 64.0;
  // Bounds over one tile (made on demand), and over the tiles covering
  // [north0, north1] x [east0, east1].
  HeightBounds tile_bounds(int32_t tx, int32_t ty) const { return height_tile(tx, ty)->bounds; }
  HeightBounds bounds(double north0, double north1, double east0, double east1) const;

  // Ground albedo 0..255 at a point (point-sampled; the texture cache
  // prefilters it for the renderer), with the featureless areas applied.
  float albedo(double north, double east) const {
    return featureless_.apply(north, east, ground_ ? ground_->albedo(north, east) : ground_albedo(north, east));
  }

  const TerrainOptions& options() const { return options_; }

 private:
  double raw_height(double north, double east, double* dh_dn, double* dh_de) const;
  // Fields, hedges, roads, trees and rocks, before the featureless areas.
  float ground_albedo(double north, double east) const;

  static constexpr int kHeightTileLog2 = 6;
  static constexpr int kHeightTile = 1 << kHeightTileLog2;  // samples per tile side (1 m spacing), plus one shared edge
  static_assert(kHeightTile == 64, "kBoundsTileM is the tile side");
  struct HeightTile {
    float h[(kHeightTile + 1) * (kHeightTile + 1)];
    HeightBounds bounds;
  };
  const HeightTile* height_tile(int32_t tx, int32_t ty) const;

  TerrainOptions options_;
  FeaturelessGround featureless_;
  const GroundSource* ground_ = nullptr;  // options_.ground, or null
  mutable std::unordered_map<int64_t, std::unique_ptr<HeightTile>> height_tiles_;
  mutable int64_t last_key_ = INT64_MIN;
  mutable const HeightTile* last_tile_ = nullptr;
  uint32_t salt_[16];
  double datum_ = 0.0;
  double max_slope_ = 0.0;
  double max_height_ = 0.0;
  double min_height_ = 0.0;
};

}  // namespace nadir::sim
