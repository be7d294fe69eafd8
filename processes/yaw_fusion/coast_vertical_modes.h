#pragma once
// The coast's height with two models of the climb, mixed as an interacting
// multiple model filter: *steady* -- the climb held from the frames before
// stays what it was, to within a small error and random walk (level flight,
// a climb flown on) -- and *changing* -- the climb may already be off by the
// coast model's sigma_v and changes as its random walk q (a climb that starts
// or ends in the coast). Each is a CoastVertical; every step they are mixed
// by the chance of switching between them, and over seen ground each range's
// down weighs them by how well each predicted it. In level flight the ranges
// fit the steady model and the held climb is kept; where a climb starts they
// stop fitting it and the changing model takes over.
//
// With the changing model's probability 1 and no switching this is that
// model alone (the coast model, as without seen ground).

#include <array>
#include <optional>

#include "processes/yaw_fusion/coast_vertical.h"

namespace nadir {

struct CoastClimbModel {
  double climb_stddev_mps = 0.0;  // of the held climb at the coast's start
  double random_walk = 0.0;       // m/s per sqrt(s)
};

class CoastVerticalModes {
 public:
  struct Options {
    CoastClimbModel steady, changing;
    double changing_probability = 1.0;  // at the coast's start
    double switch_rate_per_s = 0.0;     // each way
  };
  void start(double down, double climb_mps, const Options& options);
  // `dt_s` on. Each model's down moves by its own climb, or by `rate_mps`
  // when given (a stale-range delta's direction).
  void predict(double dt_s, std::optional<double> rate_mps = std::nullopt);
  // A down measured with `variance`. Returns the innovation of the combined
  // estimate before the update.
  double update(double measured_down, double variance);

  double down() const;
  double climb() const;
  double down_variance() const;
  double climb_variance() const;
  double changing_probability() const { return probability_[kChanging]; }

 private:
  static constexpr int kSteady = 0, kChanging = 1;
  // The two models' moment-matched combination (mean and covariance).
  void combine(Eigen::Vector2d* mean, Eigen::Matrix2d* covariance) const;
  Options options_;
  std::array<CoastVertical, 2> models_;
  std::array<double, 2> probability_{0.0, 1.0};
};

}  // namespace nadir
