#pragma once
// Procedural, seeded terrain: a height field with gentle hills and sharper
// ridges, and a ground albedo with fields, hedges, roads, tree clusters, rocks
// and fine grain. Everything is a pure function of (seed, north, east), so any
// position is computable and the terrain extends as far as any profile flies.
// Heights are relative to the terrain at the world origin (the start point),
// which is the altitude datum: height(0, 0) == 0.

#include <cstdint>

namespace nadir::sim {

struct TerrainOptions {
  uint64_t seed = 1;
  double relief_scale = 1.0;   // multiplies every height octave; 0 = flat
  void Check() const;
};

class Terrain {
 public:
  explicit Terrain(const TerrainOptions& options);

  // Height above the datum (m, up positive) and, if asked, its gradient
  // (dh/dnorth, dh/deast).
  double height(double north, double east, double* dh_dn = nullptr, double* dh_de = nullptr) const;
  // Bounds used by the ray caster: |grad h| <= max_slope(), and
  // min_height() <= height <= max_height() everywhere.
  double max_slope() const { return max_slope_; }
  double max_height() const { return max_height_; }
  double min_height() const { return min_height_; }

  // Ground albedo 0..255 at a point (point-sampled; the texture cache
  // prefilters it for the renderer).
  float albedo(double north, double east) const;

  const TerrainOptions& options() const { return options_; }

 private:
  double raw_height(double north, double east, double* dh_dn, double* dh_de) const;

  TerrainOptions options_;
  uint32_t salt_[16];
  double datum_ = 0.0;
  double max_slope_ = 0.0;
  double max_height_ = 0.0;
  double min_height_ = 0.0;
};

}  // namespace nadir::sim
