#include "processes/sim/texture_cache.h"

#include <algorithm>
#include <cmath>

namespace nadir::sim {
namespace {

int64_t tile_key(int32_t tx, int32_t ty) {
  return (static_cast<int64_t>(tx) << 32) ^ static_cast<int64_t>(static_cast<uint32_t>(ty));
}

}  // namespace

TextureCache::Tile* TextureCache::generate(int32_t tx, int32_t ty) {
  auto tile = std::make_unique<Tile>();
  const int n = kTileTexels;
  // Level 0 is point-sampled at texel centres: 0.25 m is finer than any
  // pixel footprint we fly (>= 0.37 m at 150 m), the mip levels do the filtering.
  std::vector<float>& l0 = tile->level[0];
  l0.resize(static_cast<size_t>(n) * n);
  const double n_origin = tx * kTileM, e_origin = ty * kTileM;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      l0[static_cast<size_t>(i) * n + j] = terrain_.albedo(n_origin + (i + 0.5) * kTexelM, e_origin + (j + 0.5) * kTexelM);
  for (int level = 1; level < kLevels; ++level) {
    const int size = n >> level, prev = size * 2;
    const std::vector<float>& src = tile->level[level - 1];
    std::vector<float>& dst = tile->level[level];
    dst.resize(static_cast<size_t>(size) * size);
    for (int i = 0; i < size; ++i)
      for (int j = 0; j < size; ++j) {
        const size_t a = static_cast<size_t>(2 * i) * prev + 2 * j;
        dst[static_cast<size_t>(i) * size + j] = 0.25f * (src[a] + src[a + 1] + src[a + prev] + src[a + prev + 1]);
      }
  }
  ++generated_;
  Tile* raw = tile.get();
  tiles_[tile_key(tx, ty)] = std::move(tile);
  return raw;
}

TextureCache::Tile* TextureCache::tile_at(int32_t tx, int32_t ty) {
  const int32_t gx = tx - grid_tx0_, gy = ty - grid_ty0_;
  Tile* t = nullptr;
  if (gx >= 0 && gy >= 0 && gx < grid_nx_ && gy < grid_ny_) t = grid_[static_cast<size_t>(gx) * grid_ny_ + gy];
  if (t) return t;
  auto it = tiles_.find(tile_key(tx, ty));
  t = it != tiles_.end() ? it->second.get() : generate(tx, ty);
  t->last_used = frame_;
  return t;
}

void TextureCache::prepare(double n0, double n1, double e0, double e1, int64_t frame) {
  frame_ = frame;
  grid_tx0_ = static_cast<int32_t>(std::floor(n0 / kTileM));
  grid_ty0_ = static_cast<int32_t>(std::floor(e0 / kTileM));
  grid_nx_ = static_cast<int32_t>(std::floor(n1 / kTileM)) - grid_tx0_ + 1;
  grid_ny_ = static_cast<int32_t>(std::floor(e1 / kTileM)) - grid_ty0_ + 1;
  grid_.assign(static_cast<size_t>(grid_nx_) * grid_ny_, nullptr);
  for (int32_t i = 0; i < grid_nx_; ++i)
    for (int32_t j = 0; j < grid_ny_; ++j) {
      const int32_t tx = grid_tx0_ + i, ty = grid_ty0_ + j;
      auto it = tiles_.find(tile_key(tx, ty));
      Tile* t = it != tiles_.end() ? it->second.get() : generate(tx, ty);
      t->last_used = frame;
      grid_[static_cast<size_t>(i) * grid_ny_ + j] = t;
    }
}

void TextureCache::evict(int64_t frame, int64_t keep_frames) {
  for (auto it = tiles_.begin(); it != tiles_.end();) {
    if (frame - it->second->last_used > keep_frames) {
      it = tiles_.erase(it);
    } else {
      ++it;
    }
  }
  grid_.clear();
  grid_nx_ = grid_ny_ = 0;
}

float TextureCache::texel(int32_t i, int32_t j, int level) {
  const int shift = kTileLog2 - level;
  Tile* t = tile_at(i >> shift, j >> shift);
  const int32_t mask = (1 << shift) - 1;
  return t->level[level][static_cast<size_t>(i & mask) * (1 << shift) + (j & mask)];
}

float TextureCache::sample_level(double north, double east, int level) {
  const double texel_m = kTexelM * (1 << level);
  const double gx = north / texel_m - 0.5, gy = east / texel_m - 0.5;
  const double fx = std::floor(gx), fy = std::floor(gy);
  const int32_t i = static_cast<int32_t>(fx), j = static_cast<int32_t>(fy);
  const float ax = static_cast<float>(gx - fx), ay = static_cast<float>(gy - fy);
  const int shift = kTileLog2 - level;
  const int32_t mask = (1 << shift) - 1;
  float v00, v01, v10, v11;
  if ((i & mask) != mask && (j & mask) != mask) {
    // Fast path: all four texels in one tile.
    const Tile* t = tile_at(i >> shift, j >> shift);
    const int size = 1 << shift;
    const float* p = &t->level[level][static_cast<size_t>(i & mask) * size + (j & mask)];
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

float TextureCache::sample(double north, double east, double footprint_m) {
  const double lambda = std::log2(std::max(footprint_m, 1e-6) / kTexelM);
  if (lambda <= 0.0) return sample_level(north, east, 0);
  if (lambda >= kLevels - 1) return sample_level(north, east, kLevels - 1);
  const int l0 = static_cast<int>(lambda);
  const float w = static_cast<float>(lambda - l0);
  const float a = sample_level(north, east, l0);
  const float b = sample_level(north, east, l0 + 1);
  return a + (b - a) * w;
}

}  // namespace nadir::sim
