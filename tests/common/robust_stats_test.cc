#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <stdexcept>
#include <vector>

#include "common/robust_stats.h"

namespace nadir {
namespace {

TEST(RobustStats, MedianOfAnOddCountIsTheMiddleValue) {
  EXPECT_EQ(median({7.0}), 7.0);
  EXPECT_EQ(median({5.0, -1.0, 3.0}), 3.0);
  EXPECT_EQ(median({9.0, 1.0, 8.0, 2.0, 7.0}), 7.0);
  EXPECT_EQ(median({9.0, 1.0, 8.0, 2.0, 7.0}, EvenMedian::kUpper), 7.0);  // the rule only matters for even counts
}

TEST(RobustStats, MedianOfAnEvenCountFollowsTheRequestedRule) {
  const std::vector<double> v{4.0, 1.0, 10.0, 2.0};  // sorted: 1 2 4 10
  EXPECT_EQ(median(v), 3.0);
  EXPECT_EQ(median(v, EvenMedian::kMidpoint), 3.0);
  EXPECT_EQ(median(v, EvenMedian::kUpper), 4.0);
  EXPECT_EQ(median({2.0, 1.0}), 1.5);
  EXPECT_EQ(median({2.0, 1.0}, EvenMedian::kUpper), 2.0);
}

TEST(RobustStats, MedianHandlesRepeatsAndLeavesTheCallersVectorAlone) {
  const std::vector<double> v{3.0, 3.0, 1.0, 3.0, 0.0, 3.0};  // sorted: 0 1 3 3 3 3
  EXPECT_EQ(median(v), 3.0);
  EXPECT_EQ(v, (std::vector<double>{3.0, 3.0, 1.0, 3.0, 0.0, 3.0}));
}

TEST(RobustStats, MedianAbsUsesMagnitudes) {
  EXPECT_EQ(median_abs({-5.0, 1.0, -2.0}), 2.0);
  EXPECT_EQ(median_abs({-4.0, 1.0, -2.0, 3.0}), 2.5);  // |x| sorted: 1 2 3 4
  EXPECT_EQ(median_abs({-4.0, 1.0, -2.0, 3.0}, EvenMedian::kUpper), 3.0);
}

TEST(RobustStats, MadSigmaMatchesTheDefinition) {
  // median 3; |x - 3| = 2 1 0 1 97 -> median 1: one wild value does not move it.
  EXPECT_DOUBLE_EQ(mad_sigma({1.0, 2.0, 3.0, 4.0, 100.0}), kMadToSigma * 1.0);
  // Even: median 2.5; |x - 2.5| = 1.5 0.5 0.5 1.5 -> midpoint 1.0, upper 1.5.
  EXPECT_DOUBLE_EQ(mad_sigma({1.0, 2.0, 3.0, 4.0}), kMadToSigma * 1.0);
  // Upper rule throughout: median 3; |x - 3| = 2 1 0 1 -> upper 1.
  EXPECT_DOUBLE_EQ(mad_sigma({1.0, 2.0, 3.0, 4.0}, EvenMedian::kUpper), kMadToSigma * 1.0);
  EXPECT_EQ(mad_sigma({5.0, 5.0, 5.0}), 0.0);
  EXPECT_DOUBLE_EQ(abs_sigma({-3.0, 1.0, 2.0}), kMadToSigma * 2.0);
}

TEST(RobustStats, MadSigmaOfNormalSamplesEstimatesTheirSigma) {
  // kMadToSigma = 1 / 0.67449 (the standard normal's MAD). 100 000 samples:
  // the estimate's standard error is ~0.4 %, the tolerance 3 %.
  std::mt19937_64 rng(7);
  std::normal_distribution<double> normal(10.0, 2.5);
  std::vector<double> v(100000);
  for (double& x : v) x = normal(rng);
  EXPECT_NEAR(mad_sigma(v), 2.5, 0.075);
  EXPECT_NEAR(median(v), 10.0, 0.05);
  // Ten percent wild values move the robust sigma little.
  for (size_t i = 0; i < v.size(); i += 10) v[i] = 1e6;
  EXPECT_NEAR(mad_sigma(v), 2.5, 0.5);
}

TEST(RobustStats, EmptyInputThrowsInvalidArgument) {
  EXPECT_THROW(median({}), std::invalid_argument);
  EXPECT_THROW(median({}, EvenMedian::kUpper), std::invalid_argument);
  EXPECT_THROW(median_abs({}), std::invalid_argument);
  EXPECT_THROW(mad_sigma({}), std::invalid_argument);
  EXPECT_THROW(abs_sigma({}), std::invalid_argument);
}

TEST(RobustStats, NanInputThrowsNamingItsIndex) {
  try {
    median({1.0, std::numeric_limits<double>::quiet_NaN(), 2.0});
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("index 1 of 3"), std::string::npos) << e.what();
  }
  EXPECT_THROW(mad_sigma({std::numeric_limits<double>::quiet_NaN()}), std::invalid_argument);
}

TEST(RobustStats, InfinitiesAreOrdinaryValues) {
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_EQ(median({inf, -inf, 1.0}), 1.0);
  EXPECT_EQ(median_abs({-inf, 1.0, 2.0}), 2.0);
}

}  // namespace
}  // namespace nadir
