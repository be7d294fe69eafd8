// The map fixes' consistency check: the chi-square quantile it judges by,
// and when it inflates.

#include <gtest/gtest.h>

#include <random>

#include "processes/yaw_fusion/fix_consistency.h"

namespace nadir {
namespace {

TEST(FixConsistency, ChiSquareQuantileMatchesTheTables) {
  // 99 % points from the tables (to 3 decimals).
  EXPECT_NEAR(chi_square_quantile(0.99, 10), 23.209, 0.05);
  EXPECT_NEAR(chi_square_quantile(0.99, 20), 37.566, 0.05);
  EXPECT_NEAR(chi_square_quantile(0.99, 100), 135.807, 0.1);
  EXPECT_NEAR(chi_square_quantile(0.95, 20), 31.410, 0.05);
  EXPECT_NEAR(chi_square_quantile(0.95, 2), 5.991, 0.1);
}

TEST(FixConsistency, InflatesOnlyWhatTheWindowSaysIsBeyondItsBound) {
  FixConsistency none(2, 0);
  for (int i = 0; i < 20; ++i) none.note(100.0);
  EXPECT_EQ(none.inflation(), 1.0);  // window 0: never

  FixConsistency c(2, 10);
  for (int i = 0; i < 9; ++i) c.note(8.0);
  EXPECT_EQ(c.inflation(), 1.0);  // not ten fixes yet
  c.note(8.0);
  EXPECT_DOUBLE_EQ(c.inflation(), 4.0);  // sum 80 over 20 degrees of freedom
  // Agreement again: once the window's sum is under 37.6 it stops.
  for (int i = 0; i < 6; ++i) c.note(1.0);
  EXPECT_DOUBLE_EQ(c.inflation(), (4 * 8.0 + 6 * 1.0) / 20.0);  // 38 > 37.57
  c.note(1.0);
  EXPECT_EQ(c.inflation(), 1.0);
  // NIS drawn from the chi-square it expects: inflated on about 1 % of fixes.
  std::mt19937 rng(3);
  std::chi_squared_distribution<double> nis(2.0);
  FixConsistency consistent(2, 10);
  int inflated = 0;
  const int fixes = 20000;
  for (int i = 0; i < fixes; ++i) {
    if (consistent.inflation() > 1.0) ++inflated;
    consistent.note(nis(rng));
  }
  EXPECT_GT(inflated, fixes / 400);
  EXPECT_LT(inflated, fixes / 40);
}

}  // namespace
}  // namespace nadir
