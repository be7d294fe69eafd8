#pragma once
// Whether a reported covariance means something: the normalised estimation
// error squared (NEES) e' P^-1 e of each pose against the truth. For a
// consistent estimator it is chi-square distributed with as many degrees of
// freedom as e has: mean 2 for the horizontal position, 1 for yaw, and 95 %
// of the samples below the chi-square 95 % point (5.991 and 3.841). Far above
// means over-confident (the errors are larger than the reported sigma says),
// far below under-confident.

#include <cstdint>

namespace nadir {

constexpr double kChi2Dof2Pct95 = 5.991;
constexpr double kChi2Dof1Pct95 = 3.841;

// e' P^-1 e for a horizontal error (north, east) and its 2x2 covariance;
// negative when P is not positive definite (no statement possible).
double horizontal_nees(double error_n, double error_e, double p_nn, double p_ne, double p_ee);

// e^2 / variance; negative when the variance is not positive.
double scalar_nees(double error, double variance);

// Mean and share within the 95 % point over the samples that have a value.
class NeesSummary {
 public:
  explicit NeesSummary(double chi2_95) : chi2_95_(chi2_95) {}
  void add(double nees);
  int64_t samples() const { return n_; }
  double mean() const { return n_ > 0 ? sum_ / static_cast<double>(n_) : 0.0; }
  double within_95_pct() const { return n_ > 0 ? 100.0 * static_cast<double>(within_) / static_cast<double>(n_) : 0.0; }

 private:
  double chi2_95_;
  int64_t n_ = 0, within_ = 0;
  double sum_ = 0.0;
};

// How often the true horizontal error exceeded the published protection
// level (pose_t.horizontal_protection_level_m; < 0 = unavailable, not counted).
class ProtectionLevelSummary {
 public:
  void add(double error_h_m, double protection_level_m);
  int64_t samples() const { return n_; }
  int64_t exceeded() const { return exceeded_; }
  int64_t unavailable() const { return unavailable_; }
  double exceeded_pct() const { return n_ > 0 ? 100.0 * static_cast<double>(exceeded_) / static_cast<double>(n_) : 0.0; }

 private:
  int64_t n_ = 0, exceeded_ = 0, unavailable_ = 0;
};

}  // namespace nadir
