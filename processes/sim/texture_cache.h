#pragma once
// The ground albedo prefiltered into mip-mapped tiles, generated on demand
// from the procedural terrain and evicted when unused. The renderer samples
// it trilinearly by each pixel's ground footprint, which is its anti-aliasing.
// Tile content depends only on (seed, tile index): eviction never changes an image.

#include <cmath>
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

  // Level 1 (0.5 m) is the albedo point-sampled at texel centres and levels
  // 2.. are box-filtered from it. Level 0 (0.25 m, point-sampled) is made
  // only when a pixel footprint below 0.5 m asks for it (low flight): each
  // level is a pure function of (seed, tile), so when it is made never
  // changes a pixel.
  struct Tile {
    int32_t tx = 0, ty = 0;
    // Row-major (index = i_north * size + i_east), 8-bit: a quarter of the
    // memory of floats keeps the frame's texture in cache.
    std::vector<uint8_t> level[kLevels];
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
  // Bilinear sample of one level (inline: two per pixel).
  float sample_level(double north, double east, int level) {
    const double inv_texel = kInvTexel[level];
    const double gx = north * inv_texel - 0.5, gy = east * inv_texel - 0.5;
    const double fx = std::floor(gx), fy = std::floor(gy);
    const int32_t i = static_cast<int32_t>(fx), j = static_cast<int32_t>(fy);
    const float ax = static_cast<float>(gx - fx), ay = static_cast<float>(gy - fy);
    const int shift = kTileLog2 - level;
    const int32_t mask = (1 << shift) - 1;
    float v00, v01, v10, v11;
    const Tile* t;
    if ((i & mask) != mask && (j & mask) != mask && (t = grid_tile(i >> shift, j >> shift)) != nullptr &&
        !t->level[level].empty()) {
      // Fast path: all four texels in one tile of this frame's grid.
      const int size = 1 << shift;
      const uint8_t* p = &t->level[level][static_cast<size_t>(i & mask) * size + (j & mask)];
      v00 = p[0];
      v01 = p[1];
      v10 = p[size];
      v11 = p[size + 1];
    } else {
      v00 = texel(i, j, level);
      v01 = texel(i, j + 1, level);
      v10 = texel(i + 1, j, level);
      v11 = texel(i + 1, j + 1, level);
    }
    const float top = v00 + (v01 - v00) * ay, bottom = v10 + (v11 - v10) * ay;
    return top + (bottom - top) * ax;
  }

  size_t tiles() const { return tiles_.size(); }
  int64_t tiles_generated() const { return generated_; }
  int64_t level0_generated() const { return level0_generated_; }

 private:
  static constexpr double kInvTexel[kLevels] = {1.0 / kTexelM,         1.0 / (2 * kTexelM),  1.0 / (4 * kTexelM),
                                                1.0 / (8 * kTexelM),    1.0 / (16 * kTexelM), 1.0 / (32 * kTexelM),
                                                1.0 / (64 * kTexelM)};
  const Tile* grid_tile(int32_t tx, int32_t ty) const {
    const int32_t gx = tx - grid_tx0_, gy = ty - grid_ty0_;
    if (gx < 0 || gy < 0 || gx >= grid_nx_ || gy >= grid_ny_) return nullptr;
    return grid_[static_cast<size_t>(gx) * grid_ny_ + gy];
  }
  Tile* tile_at(int32_t tx, int32_t ty);
  Tile* generate(int32_t tx, int32_t ty);
  void make_level0(Tile* tile);
  float texel(int32_t i, int32_t j, int level);

  const Terrain& terrain_;
  std::unordered_map<int64_t, std::unique_ptr<Tile>> tiles_;
  int64_t generated_ = 0;
  int64_t level0_generated_ = 0;
  int64_t frame_ = 0;
  // Pointer grid for the current frame.
  int32_t grid_tx0_ = 0, grid_ty0_ = 0, grid_nx_ = 0, grid_ny_ = 0;
  std::vector<Tile*> grid_;
};

}  // namespace nadir::sim
