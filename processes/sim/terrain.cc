#include "processes/sim/terrain.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "processes/sim/procedural_noise.h"

namespace nadir::sim {
namespace {

// Height octaves: lattice cell (m) and amplitude (m). Gentle hills from the
// long octaves; the ridge octave (1 - |n|)^2 gives the sharper features with
// slopes up to ~15 degrees.
struct Octave {
  double cell_m;
  double amplitude_m;
};
constexpr Octave kHills[] = {{1300.0, 16.0}, {470.0, 6.5}, {170.0, 2.2}};
constexpr Octave kRidge = {140.0, 4.5};
// Per-axis derivative bound of value_noise per lattice cell (see procedural_noise.h).
constexpr double kNoiseSlopeBound = 3.75 * 1.41421356237;

enum Layer : uint32_t {
  kLayerHill0 = 0, kLayerHill1, kLayerHill2, kLayerRidge,
  kLayerField, kLayerRoad, kLayerTreeCluster, kLayerTree, kLayerRock,
  kLayerGrain0, kLayerGrain1, kLayerGrain2, kLayerPatch, kLayerCount
};

constexpr int kTileSide = 64;
constexpr int kTileRow = kTileSide + 1;

// Bounds of the bilinear surface through a tile's (side + 1)^2 samples.
HeightBounds sample_bounds(const float* h) {
  float lo = h[0], hi = h[0], dn = 0.0f, de = 0.0f;
  for (int i = 0; i <= kTileSide; ++i)
    for (int j = 0; j <= kTileSide; ++j) {
      const float v = h[i * kTileRow + j];
      lo = std::min(lo, v);
      hi = std::max(hi, v);
      if (i < kTileSide) dn = std::max(dn, std::fabs(h[(i + 1) * kTileRow + j] - v));
      if (j < kTileSide) de = std::max(de, std::fabs(h[i * kTileRow + j + 1] - v));
    }
  HeightBounds b;
  // Heights are read back as the floats stored, so the float bounds are exact;
  // the slope gets a relative hair for the double arithmetic of height().
  b.min_height = lo;
  b.max_height = hi;
  b.max_slope = std::hypot(static_cast<double>(dn), static_cast<double>(de)) * (1.0 + 1e-6);
  return b;
}

float clamp_albedo(double v) { return static_cast<float>(std::min(250.0, std::max(8.0, v))); }

}  // namespace

void TerrainOptions::Check() const {
  if (!(relief_scale >= 0.0 && relief_scale <= 3.0))
    throw std::invalid_argument("terrain.relief_scale must be in [0, 3]");
  for (size_t i = 0; i < featureless.size(); ++i)
    featureless[i].Check("terrain.featureless[" + std::to_string(i) + "]");
  if (ground) {
    const GroundBounds b = ground->bounds();
    if (!(std::isfinite(b.min_height) && std::isfinite(b.max_height) && b.min_height <= b.max_height &&
          std::isfinite(b.max_slope) && b.max_slope >= 0.0))
      throw std::invalid_argument(ground->describe() + ": ground bounds are not finite or min > max");
  }
}

Terrain::Terrain(const TerrainOptions& options) : options_(options), featureless_(options.featureless) {
  options_.Check();
  for (uint32_t i = 0; i < 16; ++i) salt_[i] = mix_salt(options.seed, i);
  ground_ = options_.ground.get();
  if (ground_) {
    // The source's bounds hold for its own field; the grid's bilinear
    // surface has edge differences of at most max_slope per metre along
    // north and east, so its gradient is within sqrt(2) of that. A hair on
    // top for the float samples.
    const GroundBounds g = ground_->bounds();
    const double s = options_.relief_scale;
    datum_ = raw_height(0.0, 0.0, nullptr, nullptr);
    max_slope_ = std::sqrt(2.0) * g.max_slope * s * (1.0 + 1e-6) + 1e-9;
    const double pad = 1e-3 + 1e-6 * std::max(std::fabs(g.min_height), std::fabs(g.max_height)) * s;
    max_height_ = s * g.max_height - datum_ + pad;
    min_height_ = s * g.min_height - datum_ - pad;
    return;
  }
  double slope = 0.0, amp = 0.0;
  for (const Octave& o : kHills) {
    slope += o.amplitude_m * kNoiseSlopeBound / o.cell_m;
    amp += o.amplitude_m;
  }
  slope += kRidge.amplitude_m * 2.0 * kNoiseSlopeBound / kRidge.cell_m;
  max_slope_ = slope * options_.relief_scale;
  datum_ = raw_height(0.0, 0.0, nullptr, nullptr);  // grid sample (0, 0) is exact, so height(0, 0) == 0
  max_height_ = (amp + kRidge.amplitude_m) * options_.relief_scale - datum_;
  min_height_ = -amp * options_.relief_scale - datum_;
}

double Terrain::raw_height(double north, double east, double* dh_dn, double* dh_de) const {
  const double s = options_.relief_scale;
  if (ground_) {
    if (dh_dn) {  // central differences over 0.5 m
      *dh_dn = s * (ground_->height(north + 0.25, east) - ground_->height(north - 0.25, east)) / 0.5;
      *dh_de = s * (ground_->height(north, east + 0.25) - ground_->height(north, east - 0.25)) / 0.5;
    }
    return s * ground_->height(north, east);
  }
  double h = 0.0, gn = 0.0, ge = 0.0;
  for (int i = 0; i < 3; ++i) {
    const Octave& o = kHills[i];
    double dx, dy;
    const double inv = 1.0 / o.cell_m;
    h += o.amplitude_m * value_noise(north * inv, east * inv, salt_[kLayerHill0 + i], &dx, &dy);
    gn += o.amplitude_m * inv * dx;
    ge += o.amplitude_m * inv * dy;
  }
  {
    double dx, dy;
    const double inv = 1.0 / kRidge.cell_m;
    const double n = value_noise(north * inv, east * inv, salt_[kLayerRidge], &dx, &dy);
    const double r = 1.0 - std::fabs(n);
    const double sign = n >= 0 ? 1.0 : -1.0;
    h += kRidge.amplitude_m * (r * r - 0.3);
    gn += kRidge.amplitude_m * 2.0 * r * (-sign) * dx * inv;
    ge += kRidge.amplitude_m * 2.0 * r * (-sign) * dy * inv;
  }
  if (dh_dn) {
    *dh_dn = s * gn;
    *dh_de = s * ge;
  }
  return s * h;
}

const Terrain::HeightTile* Terrain::height_tile(int32_t tx, int32_t ty) const {
  const int64_t key = (static_cast<int64_t>(tx) << 32) ^ static_cast<int64_t>(static_cast<uint32_t>(ty));
  if (key == last_key_) return last_tile_;
  auto it = height_tiles_.find(key);
  if (it == height_tiles_.end()) {
    // Content depends only on (seed, tile): dropping the cache changes nothing.
    if (height_tiles_.size() > 4096) height_tiles_.clear();
    auto tile = std::make_unique<HeightTile>();
    for (int i = 0; i <= kHeightTile; ++i)
      for (int j = 0; j <= kHeightTile; ++j)
        tile->h[i * (kHeightTile + 1) + j] = static_cast<float>(
            raw_height(static_cast<double>(tx) * kHeightTile + i, static_cast<double>(ty) * kHeightTile + j, nullptr,
                       nullptr) - datum_);
    tile->bounds = sample_bounds(tile->h);
    it = height_tiles_.emplace(key, std::move(tile)).first;
  }
  last_key_ = key;
  last_tile_ = it->second.get();
  return last_tile_;
}

HeightBounds Terrain::bounds(double north0, double north1, double east0, double east1) const {
  const int32_t tx0 = static_cast<int32_t>(std::floor(north0)) >> kHeightTileLog2;
  const int32_t tx1 = static_cast<int32_t>(std::floor(north1)) >> kHeightTileLog2;
  const int32_t ty0 = static_cast<int32_t>(std::floor(east0)) >> kHeightTileLog2;
  const int32_t ty1 = static_cast<int32_t>(std::floor(east1)) >> kHeightTileLog2;
  HeightBounds b = tile_bounds(tx0, ty0);
  for (int32_t tx = tx0; tx <= tx1; ++tx)
    for (int32_t ty = ty0; ty <= ty1; ++ty) {
      const HeightBounds t = tile_bounds(tx, ty);
      b.min_height = std::min(b.min_height, t.min_height);
      b.max_height = std::max(b.max_height, t.max_height);
      b.max_slope = std::max(b.max_slope, t.max_slope);
    }
  return b;
}

float Terrain::ground_albedo(double north, double east) const {
  // Fields: Voronoi cells of ~110 m, each with its own albedo and pattern;
  // hedges along cell borders give long edges and corners where they meet.
  constexpr double kFieldCell = 110.0;
  const double fx = north / kFieldCell, fy = east / kFieldCell;
  const int32_t cx = static_cast<int32_t>(std::floor(fx)), cy = static_cast<int32_t>(std::floor(fy));
  double d1 = 1e9, d2 = 1e9;
  int32_t best_x = 0, best_y = 0;
  for (int32_t j = -1; j <= 1; ++j) {
    for (int32_t i = -1; i <= 1; ++i) {
      const uint32_t h = lattice_hash(cx + i, cy + j, salt_[kLayerField]);
      const double px = cx + i + 0.1 + 0.8 * ((h & 0xffff) / 65536.0);
      const double py = cy + j + 0.1 + 0.8 * ((h >> 16) / 65536.0);
      const double d = (px - fx) * (px - fx) + (py - fy) * (py - fy);
      if (d < d1) {
        d2 = d1;
        d1 = d;
        best_x = cx + i;
        best_y = cy + j;
      } else if (d < d2) {
        d2 = d;
      }
    }
  }
  const uint32_t field = lattice_hash(best_x, best_y, salt_[kLayerField] ^ 0x5bd1e995U);
  const double base = 70.0 + 120.0 * ((field & 0xff) / 255.0);
  const int pattern = static_cast<int>((field >> 8) % 5);  // 0 plain, 1-2 crop rows, 3 forest, 4 meadow
  const double angle = ((field >> 12) & 0xff) / 255.0 * M_PI;
  const double period = 2.5 + 5.0 * (((field >> 20) & 0xff) / 255.0);

  // Large-scale and fine grain inside every field.
  double value = base;
  value += 18.0 * value_noise(north / 23.0, east / 23.0, salt_[kLayerGrain0]);
  value += 15.0 * value_noise(north / 4.1, east / 4.1, salt_[kLayerGrain1]);
  value += 12.0 * value_noise(north / 1.3, east / 1.3, salt_[kLayerGrain2]);
  if (pattern == 1 || pattern == 2) {
    const double along = north * std::cos(angle) + east * std::sin(angle);
    value += (pattern == 1 ? 16.0 : 10.0) * std::sin(2.0 * M_PI * along / period);
  } else if (pattern == 4) {
    value += 22.0 * value_noise(north / 9.0, east / 9.0, salt_[kLayerPatch]);
  }

  // Hedge or track along field borders (distance to the bisector ~ (d2 - d1)).
  const double border_m = (std::sqrt(d2) - std::sqrt(d1)) * kFieldCell * 0.5;
  if (border_m < 1.6) value = 0.55 * value + 10.0;

  // Roads: thin bright lines along the zero set of a slow noise field.
  {
    double dx, dy;
    const double n = value_noise(north / 650.0, east / 650.0, salt_[kLayerRoad], &dx, &dy);
    const double grad = std::sqrt(dx * dx + dy * dy) / 650.0 + 1e-9;
    const double dist_m = std::fabs(n) / grad;
    if (dist_m < 3.5) value = 205.0 + 10.0 * value_noise(north / 2.0, east / 2.0, salt_[kLayerGrain1]);
    else if (dist_m < 4.5) value = 0.6 * value;
  }

  // Trees: one per 6 m cell where the cluster density allows, disc radius
  // 1.2-2.6 m kept inside its cell, dark crown with a lit side.
  {
    const double density_noise = value_noise(north / 90.0, east / 90.0, salt_[kLayerTreeCluster]);
    // Scattered bushes everywhere (5 %), clusters where the slow noise is high.
    double density = pattern == 3 ? 0.85 : 0.05 + std::max(0.0, density_noise - 0.35) * 1.6;
    if (density > 0.0) {
      constexpr double kTreeCell = 6.0;
      const double tx = north / kTreeCell, ty = east / kTreeCell;
      const int32_t ix = static_cast<int32_t>(std::floor(tx)), iy = static_cast<int32_t>(std::floor(ty));
      const uint32_t h = lattice_hash(ix, iy, salt_[kLayerTree]);
      if ((h & 0xffff) / 65536.0 < density) {
        const double radius = 1.2 + 1.4 * (((h >> 16) & 0xff) / 255.0);
        const double margin = radius / kTreeCell;
        const double px = ix + margin + (1.0 - 2.0 * margin) * (((h >> 24) & 0xf) / 15.0);
        const double py = iy + margin + (1.0 - 2.0 * margin) * (((h >> 28) & 0xf) / 15.0);
        const double dn = (tx - px) * kTreeCell, de = (ty - py) * kTreeCell;
        const double r2 = dn * dn + de * de;
        if (r2 < radius * radius) {
          const double lit = std::max(0.0, -(dn + de) / (1.41421356 * radius));
          value = 38.0 + 10.0 * ((h >> 8) & 0x7) + 45.0 * lit;
        }
      }
    }
  }

  // Rocks: small bright or dark blobs, about one per 150 m^2.
  {
    constexpr double kRockCell = 9.0;
    const double rx = north / kRockCell, ry = east / kRockCell;
    const int32_t ix = static_cast<int32_t>(std::floor(rx)), iy = static_cast<int32_t>(std::floor(ry));
    const uint32_t h = lattice_hash(ix, iy, salt_[kLayerRock]);
    if ((h & 0xff) < 140) {
      const double radius = 0.5 + 0.9 * (((h >> 8) & 0xff) / 255.0);
      const double px = ix + 0.2 + 0.6 * (((h >> 16) & 0xff) / 255.0);
      const double py = iy + 0.2 + 0.6 * (((h >> 24) & 0xff) / 255.0);
      const double dn = (rx - px) * kRockCell, de = (ry - py) * kRockCell;
      if (dn * dn + de * de < radius * radius) value = (h & 0x100) ? 235.0 : 30.0;
    }
  }
  return clamp_albedo(value);
}

}  // namespace nadir::sim
