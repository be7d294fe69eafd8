// CoastVertical: the height while coasting, a down/climb Kalman filter.

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "processes/yaw_fusion/coast_vertical.h"
#include "processes/yaw_fusion/coasting.h"

namespace nadir {
namespace {

TEST(CoastVertical, WithoutMeasurementsItIsTheHeldClimbAndTheCoastModel) {
  CoastVertical v;
  v.start(-150.0, -0.4, 0.5);
  double t = 0.0;
  for (int k = 0; k < 140; ++k) {
    const double dt = 0.05 + 0.03 * (k % 3);  // uneven frame intervals
    v.predict(dt, v.climb(), 0.3);
    t += dt;
  }
  EXPECT_NEAR(v.down(), -150.0 - 0.4 * t, 1e-9);
  EXPECT_EQ(v.climb(), -0.4);
  // The steps add up to the continuous model's variance exactly.
  EXPECT_NEAR(v.down_variance(), coast_position_variance(0.5, 0.3, t), 1e-9 * coast_position_variance(0.5, 0.3, t));
  EXPECT_NEAR(v.climb_variance(), 0.25 + 0.09 * t, 1e-12);
}

TEST(CoastVertical, ExactDownsGiveTheTrueHeightAndClimb) {
  CoastVertical v;
  v.start(-150.0, 0.0, 0.5);
  const double dt = 1.0 / 14.0, climb = -1.5;  // the truth climbs 1.5 m/s; the held climb says level
  for (int k = 1; k <= 40; ++k) {
    v.predict(dt, v.climb(), 0.3);
    v.update(-150.0 + climb * k * dt, 1e-8);
  }
  EXPECT_NEAR(v.down(), -150.0 + climb * 40 * dt, 1e-6);
  EXPECT_NEAR(v.climb(), climb, 1e-3);
  EXPECT_LT(v.down_variance(), 1e-7);
}

// Noisy downs over 4 s, then 6 s on, the true climb off the held one by the
// held climb's sigma: the climb the filter carries on and the height are
// right within their reported sigma over many coasts (NEES ~ 1).
TEST(CoastVertical, NoisyDownsAreAveragedAndTheReportedVarianceIsTheError) {
  std::mt19937 rng(7);
  const double sigma = 0.5, dt = 1.0 / 14.0;
  std::normal_distribution<double> noise(0.0, sigma), climb_error(0.0, 0.05);
  double nees_down = 0.0, nees_climb = 0.0, sq_filter = 0.0;
  const int runs = 2000;
  for (int r = 0; r < runs; ++r) {
    const double climb = climb_error(rng);  // the held climb says level, good to 0.05 m/s
    CoastVertical v;
    v.start(0.0, 0.0, 0.05);
    for (int k = 1; k <= 56; ++k) {
      v.predict(dt, v.climb(), 0.0);  // no accelerations: the model is the truth
      v.update(climb * k * dt + noise(rng), sigma * sigma);
    }
    for (int k = 0; k < 84; ++k) v.predict(dt, v.climb(), 0.0);
    const double down_error = v.down() - climb * 140 * dt, climb_off = v.climb() - climb;
    nees_down += down_error * down_error / v.down_variance();
    nees_climb += climb_off * climb_off / v.climb_variance();
    sq_filter += down_error * down_error;
  }
  EXPECT_NEAR(nees_down / runs, 1.0, 0.1);
  EXPECT_NEAR(nees_climb / runs, 1.0, 0.1);
  // 10 s on: the held climb alone would be off by 0.05 m/s x 10 s = 0.5 m rms; the downs make it smaller.
  EXPECT_LT(std::sqrt(sq_filter / runs), 0.4);
}

TEST(CoastVertical, TheInnovationIsTheMeasurementAgainstThePrediction) {
  CoastVertical v;
  v.start(-100.0, 0.5, 0.1);
  v.predict(2.0, v.climb(), 0.0);
  EXPECT_DOUBLE_EQ(v.update(-97.0, 1.0), 2.0);  // predicted -99
  EXPECT_GT(v.down(), -99.0);
  EXPECT_LT(v.down(), -97.0);
}

}  // namespace
}  // namespace nadir
