#pragma once
// A seeded random stream with a portable normal deviate (Box-Muller on
// mt19937_64 bits): std::normal_distribution differs between standard
// libraries, and the same seed must give the same log everywhere.

#include <cmath>
#include <cstdint>
#include <random>

namespace nadir::sim {

class RandomStream {
 public:
  RandomStream(uint64_t seed, uint64_t stream) : rng_(seed * 0x9e3779b97f4a7c15ULL + stream * 0xbf58476d1ce4e5b9ULL + 1) {}
  // Uniform in (0, 1).
  double uniform() { return ((rng_() >> 11) + 0.5) * (1.0 / 9007199254740992.0); }
  double normal() {
    if (has_spare_) {
      has_spare_ = false;
      return spare_;
    }
    const double u1 = uniform(), u2 = uniform();
    const double r = std::sqrt(-2.0 * std::log(u1));
    spare_ = r * std::sin(2.0 * M_PI * u2);
    has_spare_ = true;
    return r * std::cos(2.0 * M_PI * u2);
  }
  bool bernoulli(double p) { return uniform() < p; }
  uint64_t bits() { return rng_(); }

 private:
  std::mt19937_64 rng_;
  double spare_ = 0.0;
  bool has_spare_ = false;
};

}  // namespace nadir::sim
