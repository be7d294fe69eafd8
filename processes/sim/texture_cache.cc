#include "processes/sim/texture_cache.h"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace nadir::sim {
namespace {

int64_t tile_key(int32_t tx, int32_t ty) {
  return (static_cast<int64_t>(tx) << 32) ^ static_cast<int64_t>(static_cast<uint32_t>(ty));
}

}  // namespace

TextureCache::Tile* TextureCache::generate(int32_t tx, int32_t ty) {
  auto tile = std::make_unique<Tile>();
  const int n = kTileTexels;
  tile->tx = tx;
  tile->ty = ty;
  const int n1 = n / 2;
  std::vector<uint8_t>& l1 = tile->level[1];
  l1.resize(static_cast<size_t>(n1) * n1);
  const double n_origin = tx * kTileM, e_origin = ty * kTileM, texel1 = 2.0 * kTexelM;
  for (int i = 0; i < n1; ++i)
    for (int j = 0; j < n1; ++j)
      l1[static_cast<size_t>(i) * n1 + j] = static_cast<uint8_t>(
          terrain_.albedo(n_origin + (i + 0.5) * texel1, e_origin + (j + 0.5) * texel1) + 0.5f);
  for (int level = 2; level < kLevels; ++level) {
    const int size = n >> level, prev = size * 2;
    const std::vector<uint8_t>& src = tile->level[level - 1];
    std::vector<uint8_t>& dst = tile->level[level];
    dst.resize(static_cast<size_t>(size) * size);
    for (int i = 0; i < size; ++i)
      for (int j = 0; j < size; ++j) {
        const size_t a = static_cast<size_t>(2 * i) * prev + 2 * j;
        dst[static_cast<size_t>(i) * size + j] =
            static_cast<uint8_t>((src[a] + src[a + 1] + src[a + prev] + src[a + prev + 1] + 2) / 4);
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

void TextureCache::make_level0(Tile* tile) {
  const int n = kTileTexels;
  std::vector<uint8_t>& l0 = tile->level[0];
  l0.resize(static_cast<size_t>(n) * n);
  const double n_origin = tile->tx * kTileM, e_origin = tile->ty * kTileM;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      l0[static_cast<size_t>(i) * n + j] = static_cast<uint8_t>(
          terrain_.albedo(n_origin + (i + 0.5) * kTexelM, e_origin + (j + 0.5) * kTexelM) + 0.5f);
  ++level0_generated_;
}

float TextureCache::texel(int32_t i, int32_t j, int level) {
  const int shift = kTileLog2 - level;
  Tile* t = tile_at(i >> shift, j >> shift);
  if (t->level[level].empty()) make_level0(t);
  const int32_t mask = (1 << shift) - 1;
  return t->level[level][static_cast<size_t>(i & mask) * (1 << shift) + (j & mask)];
}

float TextureCache::sample(double north, double east, double footprint_m) {
  // log2 from the float's exponent and a linear mantissa: the mip blend
  // weight only needs to be monotone and continuous.
  const float ratio = static_cast<float>(std::max(footprint_m, 1e-6) / kTexelM);
  uint32_t bits;
  std::memcpy(&bits, &ratio, sizeof bits);
  const int exponent = static_cast<int>((bits >> 23) & 0xff) - 127;
  const float mantissa = static_cast<float>(bits & 0x7fffff) * (1.0f / 8388608.0f);  // ratio = (1 + m) 2^e
  const double lambda = exponent + mantissa;
  if (lambda <= 0.0) return sample_level(north, east, 0);
  if (lambda >= kLevels - 1) return sample_level(north, east, kLevels - 1);
  const int l0 = static_cast<int>(lambda);
  const float w = static_cast<float>(lambda - l0);
  // Near a level, one bilinear lookup is as good as the blend (and halves
  // the cost of the renderer's most expensive step).
  if (w < 0.25f) return sample_level(north, east, l0);
  if (w > 0.75f) return sample_level(north, east, l0 + 1);
  const float a = sample_level(north, east, l0);
  const float b = sample_level(north, east, l0 + 1);
  return a + (b - a) * w;
}

}  // namespace nadir::sim
