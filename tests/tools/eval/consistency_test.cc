#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "tools/eval/consistency.h"

namespace nadir {
namespace {

TEST(Consistency, HorizontalNeesIsTheMahalanobisDistanceSquared) {
  EXPECT_DOUBLE_EQ(horizontal_nees(1.0, 0.0, 1.0, 0.0, 1.0), 1.0);
  EXPECT_DOUBLE_EQ(horizontal_nees(2.0, 1.0, 4.0, 0.0, 1.0), 2.0);
  // Correlated: against the explicit inverse of [[2, 0.5], [0.5, 1]].
  const double det = 2.0 * 1.0 - 0.25;
  const double expected = (0.3 * 0.3 * 1.0 - 2 * 0.3 * -0.7 * 0.5 + 0.7 * 0.7 * 2.0) / det;
  EXPECT_NEAR(horizontal_nees(0.3, -0.7, 2.0, 0.5, 1.0), expected, 1e-12);
  EXPECT_LT(horizontal_nees(1.0, 1.0, 0.0, 0.0, 0.0), 0.0);   // no covariance: no statement
  EXPECT_LT(horizontal_nees(1.0, 1.0, 1.0, 1.0, 1.0), 0.0);   // singular
  EXPECT_DOUBLE_EQ(scalar_nees(0.5, 0.25), 1.0);
  EXPECT_LT(scalar_nees(0.5, 0.0), 0.0);
}

// Errors drawn from the covariance the estimator reports: the NEES must come
// out chi-square with 2 (1) degrees of freedom -- mean 2 (1), 95 % within.
TEST(Consistency, ErrorsDrawnFromTheReportedCovarianceAreConsistent) {
  std::mt19937 rng(23);
  std::normal_distribution<double> n01;
  const double p_nn = 9.0, p_ne = 2.4, p_ee = 4.0;
  const double l11 = std::sqrt(p_nn), l21 = p_ne / l11, l22 = std::sqrt(p_ee - l21 * l21);  // Cholesky
  NeesSummary h(kChi2Dof2Pct95), yaw(kChi2Dof1Pct95);
  for (int i = 0; i < 40000; ++i) {
    const double a = n01(rng), b = n01(rng);
    h.add(horizontal_nees(l11 * a, l21 * a + l22 * b, p_nn, p_ne, p_ee));
    yaw.add(scalar_nees(0.01 * n01(rng), 1e-4));
  }
  h.add(-1.0);  // undefined samples are not counted
  EXPECT_EQ(h.samples(), 40000);
  EXPECT_NEAR(h.mean(), 2.0, 0.05);
  EXPECT_NEAR(h.within_95_pct(), 95.0, 0.5);
  EXPECT_NEAR(yaw.mean(), 1.0, 0.03);
  EXPECT_NEAR(yaw.within_95_pct(), 95.0, 0.5);
  // Reported 3x too small (sigma): NEES 9x too large.
  NeesSummary over(kChi2Dof1Pct95);
  for (int i = 0; i < 40000; ++i) over.add(scalar_nees(0.03 * n01(rng), 1e-4));
  EXPECT_NEAR(over.mean(), 9.0, 0.3);
}

TEST(Consistency, ProtectionLevelExceedanceCountsOnlyAvailableLevels) {
  ProtectionLevelSummary s;
  s.add(1.0, 2.0);   // inside
  s.add(3.0, 2.0);   // exceeded
  s.add(2.0, 2.0);   // on the bound: inside
  s.add(5.0, -1.0);  // unavailable
  s.add(std::nan(""), 2.0);  // no error: no statement
  EXPECT_EQ(s.samples(), 3);
  EXPECT_EQ(s.exceeded(), 1);
  EXPECT_EQ(s.unavailable(), 2);
  EXPECT_NEAR(s.exceeded_pct(), 100.0 / 3.0, 1e-12);
  EXPECT_EQ(ProtectionLevelSummary().exceeded_pct(), 0.0);
}

}  // namespace
}  // namespace nadir
