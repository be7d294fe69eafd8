#pragma once
// Hash-based lattice noise: any world position is computable on its own, so
// the terrain extends without limit and never repeats at any scale we fly.

#include <cmath>
#include <cstdint>

namespace nadir::sim {

// 32-bit integer hash of a lattice point and a salt (seed + layer).
inline uint32_t lattice_hash(int32_t ix, int32_t iy, uint32_t salt) {
  uint32_t h = salt ^ (static_cast<uint32_t>(ix) * 0x27d4eb2dU) ^ (static_cast<uint32_t>(iy) * 0x165667b1U);
  h ^= h >> 15;
  h *= 0x2c1b3c6dU;
  h ^= h >> 12;
  h *= 0x297a2d39U;
  h ^= h >> 15;
  return h;
}
// Uniform in [0, 1).
inline double hash_unit(int32_t ix, int32_t iy, uint32_t salt) {
  return static_cast<double>(lattice_hash(ix, iy, salt)) * (1.0 / 4294967296.0);
}
// Uniform in [-1, 1).
inline double hash_signed(int32_t ix, int32_t iy, uint32_t salt) { return 2.0 * hash_unit(ix, iy, salt) - 1.0; }

inline uint32_t mix_salt(uint64_t seed, uint32_t layer) {
  uint64_t z = seed + 0x9e3779b97f4a7c15ULL * (layer + 1);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return static_cast<uint32_t>(z ^ (z >> 31));
}

// Value noise with quintic fade, in [-1, 1], and its gradient (per unit of x, y).
// |d/dx| <= 3.75 and |d/dy| <= 3.75 per lattice cell (max fade slope 1.875 times
// a value range of 2): the Lipschitz bound the ray caster relies on.
[[gnu::always_inline]] inline double value_noise(double x, double y, uint32_t salt, double* dx, double* dy) {
  const double fx = std::floor(x), fy = std::floor(y);
  const int32_t ix = static_cast<int32_t>(fx), iy = static_cast<int32_t>(fy);
  const double tx = x - fx, ty = y - fy;
  const double ux = tx * tx * tx * (tx * (tx * 6.0 - 15.0) + 10.0);
  const double uy = ty * ty * ty * (ty * (ty * 6.0 - 15.0) + 10.0);
  const double a = hash_signed(ix, iy, salt), b = hash_signed(ix + 1, iy, salt);
  const double c = hash_signed(ix, iy + 1, salt), d = hash_signed(ix + 1, iy + 1, salt);
  const double k = a - b - c + d;
  if (dx) {
    const double dux = 30.0 * tx * tx * (tx * (tx - 2.0) + 1.0);
    const double duy = 30.0 * ty * ty * (ty * (ty - 2.0) + 1.0);
    *dx = dux * ((b - a) + k * uy);
    *dy = duy * ((c - a) + k * ux);
  }
  return a + (b - a) * ux + (c - a) * uy + k * ux * uy;
}

inline double value_noise(double x, double y, uint32_t salt) { return value_noise(x, y, salt, nullptr, nullptr); }

}  // namespace nadir::sim
