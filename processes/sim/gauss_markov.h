#pragma once
// A first-order Gauss-Markov process with stationary sigma and correlation
// time tau, stepped exactly for any interval:
//   x' = a x + sigma sqrt(1 - a^2) n,  a = exp(-dt / tau),
// so its autocorrelation is sigma^2 exp(-|dt| / tau) at every sampling rate.
// sigma = 0 is off: no random numbers are drawn (logs of sets without it stay
// as they were).

#include <cmath>

#include "processes/sim/sim_random.h"

namespace nadir::sim {

class GaussMarkov {
 public:
  GaussMarkov() = default;
  GaussMarkov(double sigma, double tau_s) : sigma_(sigma), tau_s_(tau_s) {}

  bool on() const { return sigma_ > 0; }
  // Draws the start from the stationary distribution.
  void start(RandomStream* rng) {
    if (on()) x_ = sigma_ * rng->normal();
  }
  void step(double dt_s, RandomStream* rng) {
    if (!on()) return;
    const double a = std::exp(-dt_s / tau_s_);
    x_ = a * x_ + sigma_ * std::sqrt(1.0 - a * a) * rng->normal();
  }
  double value() const { return x_; }

 private:
  double sigma_ = 0.0, tau_s_ = 1.0;
  double x_ = 0.0;
};

}  // namespace nadir::sim
