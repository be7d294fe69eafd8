#include "tools/map/changed_patches.h"

#include <algorithm>
#include <cmath>

#include "processes/sim/procedural_noise.h"

namespace nadir::map {
namespace {

// splitmix64: a fixed, portable sequence (std:: distributions are not).
struct SplitMix {
  uint64_t state;
  uint64_t next() {
    uint64_t z = (state += 0x9e3779b97f4a7c15ULL);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
  }
  double uniform(double lo, double hi) { return lo + (hi - lo) * static_cast<double>(next() >> 11) * 0x1.0p-53; }
};

}  // namespace

bool ChangedPatch::contains(double n, double e) const {
  const double dn = n - north, de = e - east;
  if (shape == kDisc) return dn * dn + de * de < half_north * half_north;
  return std::fabs(dn) < half_north && std::fabs(de) < half_east;
}

double ChangedPatch::area_m2() const {
  return shape == kDisc ? M_PI * half_north * half_north : 4.0 * half_north * half_east;
}

double ChangedPatch::albedo_at(double n, double e) const {
  return albedo + grain * sim::value_noise(n / 5.0, e / 5.0, salt);
}

std::vector<ChangedPatch> make_changed_patches(double north0, double north1, double east0, double east1,
                                               double area_fraction, uint64_t seed) {
  SplitMix rng{seed ^ 0x6d61705f70617463ULL};  // "map_patc"
  const double target = area_fraction * (north1 - north0) * (east1 - east0);
  std::vector<ChangedPatch> patches;
  double area = 0.0;
  while (area < target) {
    ChangedPatch p;
    p.shape = rng.next() & 1 ? ChangedPatch::kDisc : ChangedPatch::kRectangle;
    if (p.shape == ChangedPatch::kDisc) {
      p.half_north = p.half_east = rng.uniform(8.0, 30.0);
    } else {
      p.half_north = rng.uniform(7.5, 30.0);
      p.half_east = rng.uniform(7.5, 30.0);
    }
    area += p.area_m2();
    p.north = rng.uniform(north0, north1);
    p.east = rng.uniform(east0, east1);
    p.albedo = rng.uniform(40.0, 220.0);
    p.grain = rng.uniform(3.0, 20.0);
    p.salt = static_cast<uint32_t>(rng.next());
    patches.push_back(p);
  }
  return patches;
}

PatchIndex::PatchIndex(const std::vector<ChangedPatch>& patches, double north0, double east0)
    : patches_(patches), north0_(north0), east0_(east0) {
  double n1 = north0, e1 = east0;
  for (const ChangedPatch& p : patches) {
    n1 = std::max(n1, p.north + p.half_north);
    e1 = std::max(e1, p.east + p.half_east);
  }
  cells_n_ = static_cast<int>((n1 - north0) / kCellM) + 1;
  cells_e_ = static_cast<int>((e1 - east0) / kCellM) + 1;
  cells_.resize(static_cast<size_t>(cells_n_) * cells_e_);
  for (size_t k = 0; k < patches.size(); ++k) {
    const ChangedPatch& p = patches[k];
    const int i0 = std::max(0, static_cast<int>(std::floor((p.north - p.half_north - north0) / kCellM)));
    const int i1 = std::min(cells_n_ - 1, static_cast<int>(std::floor((p.north + p.half_north - north0) / kCellM)));
    const int j0 = std::max(0, static_cast<int>(std::floor((p.east - p.half_east - east0) / kCellM)));
    const int j1 = std::min(cells_e_ - 1, static_cast<int>(std::floor((p.east + p.half_east - east0) / kCellM)));
    for (int i = i0; i <= i1; ++i)
      for (int j = j0; j <= j1; ++j) cells_[static_cast<size_t>(i) * cells_e_ + j].push_back(static_cast<int>(k));
  }
}

bool PatchIndex::albedo(double n, double e, double* value) const {
  const double fi = std::floor((n - north0_) / kCellM), fj = std::floor((e - east0_) / kCellM);
  if (fi < 0 || fj < 0 || fi >= cells_n_ || fj >= cells_e_) return false;
  const std::vector<int>& cell = cells_[static_cast<size_t>(fi) * cells_e_ + static_cast<size_t>(fj)];
  for (auto it = cell.rbegin(); it != cell.rend(); ++it) {
    const ChangedPatch& p = patches_[static_cast<size_t>(*it)];
    if (p.contains(n, e)) {
      *value = std::clamp(p.albedo_at(n, e), 8.0, 250.0);
      return true;
    }
  }
  return false;
}

}  // namespace nadir::map
