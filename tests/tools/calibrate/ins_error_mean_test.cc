// The boresight's share of the INS attitude error: the sigma of the mean of a
// Gauss-Markov error over a calibration segment, against the statistics of
// the simulator's own Gauss-Markov process.
#include <gtest/gtest.h>

#include <cmath>

#include "processes/sim/gauss_markov.h"
#include "tools/calibrate/calibration.h"

namespace nadir::calibrate {
namespace {

TEST(InsErrorMean, LimitsOfTheFormula) {
  EXPECT_DOUBLE_EQ(ins_attitude_sigma_of_mean(0.015, 0.0, 600.0), 0.015);  // a constant error
  EXPECT_NEAR(ins_attitude_sigma_of_mean(0.015, 1e5, 1.0), 0.015, 1e-6);    // a segment far shorter than tau
  // Far longer than tau: the mean of T / (2 tau) independent samples.
  EXPECT_NEAR(ins_attitude_sigma_of_mean(0.015, 1.0, 1e5), 0.015 * std::sqrt(2.0 / 1e5), 1e-9);
}

// The segment that brings the mean's sigma to a target is the formula's inverse.
TEST(InsErrorMean, SegmentForATargetSigmaInvertsTheFormula) {
  const double sigma = 0.015, tau = 60.0;
  const double at_97 = ins_attitude_sigma_of_mean(sigma, tau, 97.0);
  const double halving = segment_for_ins_sigma_of_mean(sigma, tau, 0.5 * at_97);
  EXPECT_NEAR(ins_attitude_sigma_of_mean(sigma, tau, halving), 0.5 * at_97, 1e-9);
  EXPECT_GT(halving, 600.0);  // the 600 s flight leaves 0.0064, just over half of 0.0118
  EXPECT_LT(halving, 800.0);
  EXPECT_EQ(segment_for_ins_sigma_of_mean(sigma, tau, sigma), 0.0);  // already there
  EXPECT_TRUE(std::isinf(segment_for_ins_sigma_of_mean(sigma, 0.0, 0.5 * sigma)));  // a constant error
  EXPECT_TRUE(std::isinf(segment_for_ins_sigma_of_mean(sigma, tau, 0.0)));
}

// 4000 segments of the simulator's process at 100 Hz: the spread of their
// means within 5 % (about 4 standard errors) of the formula, for a 97 s and
// a 600 s calibration flight with a 60 s correlation time.
TEST(InsErrorMean, MatchesTheSpreadOfSimulatedMeans) {
  const double sigma = 0.015, tau = 60.0, dt = 0.01;
  for (const double segment_s : {97.0, 600.0}) {
    sim::RandomStream rng(7, static_cast<uint64_t>(segment_s));
    const int segments = 4000, steps = static_cast<int>(segment_s / dt);
    double sum_sq = 0;
    for (int k = 0; k < segments; ++k) {
      sim::GaussMarkov error(sigma, tau);
      error.start(&rng);
      double sum = 0;
      for (int i = 0; i < steps; ++i) {
        sum += error.value();
        error.step(dt, &rng);
      }
      sum_sq += std::pow(sum / steps, 2);
    }
    const double spread = std::sqrt(sum_sq / segments);
    EXPECT_NEAR(spread / ins_attitude_sigma_of_mean(sigma, tau, segment_s), 1.0, 0.05) << segment_s << " s";
  }
  EXPECT_NEAR(ins_attitude_sigma_of_mean(sigma, tau, 97.0), 0.0118, 0.0001);
  EXPECT_NEAR(ins_attitude_sigma_of_mean(sigma, tau, 600.0), 0.0064, 0.0001);
}

}  // namespace
}  // namespace nadir::calibrate
