#pragma once
// The ground albedo prefiltered into mip-mapped tiles, generated on demand
// from the procedural terrain and evicted when unused. The renderer samples
// it trilinearly by each pixel's ground footprint, which is its anti-aliasing.
// Tile content depends only on (seed, tile index): eviction never changes an image.

#include <cstdint>
#include <memory>
#include <unordered_map>
#include <vector>

#include "processes/sim/terrain.h"

namespace nadir::sim {

class TextureCache {
 public:
  static constexpr double kTexelM = 0.25;      // level-0 texel size
  static constexpr int kTileLog2 = 8;          // 256 texels = 64 m per tile
  static constexpr int kTileTexels = 1 << kTileLog2;
  static constexpr int kLevels = 7;            // 0.25 m .. 16 m texels
  static constexpr double kTileM = kTexelM * kTileTexels;

  struct Tile {
    std::vector<float> level[kLevels];  // row-major: index = i_north * size + i_east
    int64_t last_used = 0;
  };

  explicit TextureCache(const Terrain& terrain) : terrain_(terrain) {}

  // Makes sure the tiles covering [n0, n1] x [e0, e1] exist and fills a grid
  // of pointers to them for fast lookups during one frame.
  void prepare(double n0, double n1, double e0, double e1, int64_t frame);
  // Drops tiles not used within the last `keep_frames` frames.
  void evict(int64_t frame, int64_t keep_frames);

  // Trilinear sample at a world position with a footprint (m).
  float sample(double north, double east, double footprint_m);
  // Bilinear sample of one level.
  float sample_level(double north, double east, int level);

  size_t tiles() const { return tiles_.size(); }
  int64_t tiles_generated() const { return generated_; }

 private:
  Tile* tile_at(int32_t tx, int32_t ty);
  Tile* generate(int32_t tx, int32_t ty);
  float texel(int32_t i, int32_t j, int level);

  const Terrain& terrain_;
  std::unordered_map<int64_t, std::unique_ptr<Tile>> tiles_;
  int64_t generated_ = 0;
  int64_t frame_ = 0;
  // Pointer grid for the current frame.
  int32_t grid_tx0_ = 0, grid_ty0_ = 0, grid_nx_ = 0, grid_ny_ = 0;
  std::vector<Tile*> grid_;
};

}  // namespace nadir::sim
