#include "processes/yaw_fusion/coast_vertical_modes.h"

#include <algorithm>
#include <cmath>

namespace nadir {

namespace {
// A model never becomes impossible: a few ranges that fit the other one
// must be able to bring it back.
constexpr double kMinProbability = 1e-6;
}  // namespace

void CoastVerticalModes::start(double down, double climb_mps, const Options& options) {
  options_ = options;
  models_[kSteady].start(down, climb_mps, options.steady.climb_stddev_mps);
  models_[kChanging].start(down, climb_mps, options.changing.climb_stddev_mps);
  probability_[kChanging] = std::clamp(options.changing_probability, 0.0, 1.0);
  probability_[kSteady] = 1.0 - probability_[kChanging];
}

void CoastVerticalModes::predict(double dt_s, std::optional<double> rate_mps) {
  if (!(dt_s > 0.0)) return;
  // Mixing: the chance each model is the one now, given the switch over dt
  // (a two-state Markov chain), and each model's start from that mixture.
  const double p_switch = 0.5 * (1.0 - std::exp(-2.0 * options_.switch_rate_per_s * dt_s));
  std::array<double, 2> predicted{};
  std::array<CoastVertical, 2> mixed = models_;
  for (int j = 0; j < 2; ++j) {
    const double from[2] = {probability_[0] * (j == 0 ? 1.0 - p_switch : p_switch),
                            probability_[1] * (j == 1 ? 1.0 - p_switch : p_switch)};
    predicted[j] = from[0] + from[1];
    if (predicted[j] <= 0.0) continue;
    Eigen::Vector2d mean = Eigen::Vector2d::Zero();
    for (int i = 0; i < 2; ++i) mean += from[i] / predicted[j] * models_[i].state();
    Eigen::Matrix2d covariance = Eigen::Matrix2d::Zero();
    for (int i = 0; i < 2; ++i) {
      const Eigen::Vector2d d = models_[i].state() - mean;
      covariance += from[i] / predicted[j] * (models_[i].covariance() + d * d.transpose());
    }
    mixed[j].set(mean, covariance);
  }
  models_ = mixed;
  probability_ = predicted;
  const CoastClimbModel* model[2] = {&options_.steady, &options_.changing};
  for (int j = 0; j < 2; ++j) {
    models_[j].predict(dt_s, rate_mps.value_or(models_[j].climb()), model[j]->random_walk);
  }
}

double CoastVerticalModes::update(double measured_down, double variance) {
  const double innovation = measured_down - down();
  std::array<double, 2> weight{};
  double sum = 0.0;
  for (int j = 0; j < 2; ++j) {
    const double s = models_[j].down_variance() + variance;
    const double nu = measured_down - models_[j].down();
    const double likelihood = s > 0.0 ? std::exp(-0.5 * nu * nu / s) / std::sqrt(s) : 0.0;
    weight[j] = probability_[j] * likelihood;
    sum += weight[j];
    models_[j].update(measured_down, variance);
  }
  if (sum > 0.0 && std::isfinite(sum)) {
    for (int j = 0; j < 2; ++j) probability_[j] = weight[j] / sum;
  }
  // Only a model that can be (probability above 0 at the start) is kept from vanishing.
  for (int j = 0; j < 2; ++j) {
    if (probability_[j] > 0.0) probability_[j] = std::max(probability_[j], kMinProbability);
  }
  const double total = probability_[0] + probability_[1];
  for (double& p : probability_) p /= total;
  return innovation;
}

void CoastVerticalModes::combine(Eigen::Vector2d* mean, Eigen::Matrix2d* covariance) const {
  *mean = probability_[0] * models_[0].state() + probability_[1] * models_[1].state();
  covariance->setZero();
  for (int j = 0; j < 2; ++j) {
    const Eigen::Vector2d d = models_[j].state() - *mean;
    *covariance += probability_[j] * (models_[j].covariance() + d * d.transpose());
  }
}

double CoastVerticalModes::down() const { return probability_[0] * models_[0].down() + probability_[1] * models_[1].down(); }

double CoastVerticalModes::climb() const {
  return probability_[0] * models_[0].climb() + probability_[1] * models_[1].climb();
}

double CoastVerticalModes::down_variance() const {
  Eigen::Vector2d mean;
  Eigen::Matrix2d covariance;
  combine(&mean, &covariance);
  return covariance(0, 0);
}

double CoastVerticalModes::climb_variance() const {
  Eigen::Vector2d mean;
  Eigen::Matrix2d covariance;
  combine(&mean, &covariance);
  return covariance(1, 1);
}

}  // namespace nadir
