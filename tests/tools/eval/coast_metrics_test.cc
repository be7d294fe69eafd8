// coast_episodes: each run of COASTING poses, timed from the last VO pose
// before it, with the error it added.
#include "tools/eval/coast_metrics.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "nadir/pose_t.hpp"
#include "tools/eval/trajectory_metrics.h"

namespace nadir {
namespace {

EvalSample sample(double t, bool coasting, double error_n, double error_e, double error_v) {
  EvalSample s;
  s.t_s = t;
  s.truth = {20.0 * t, 5.0, -1.0};
  s.estimate = {s.truth[0] + error_n, s.truth[1] + error_e, s.truth[2] + error_v};
  s.error_h_m = std::hypot(error_n, error_e);
  s.error_v_m = error_v;
  s.sigma_h_m = 2.0 + t;
  s.flags = coasting ? pose_t::FLAG_COASTING : pose_t::FLAG_NO_ALTIMETER * (t == 1.0);
  return s;
}

TEST(CoastEpisodes, EachRunFromTheLastVoPoseWithTheErrorItAdded) {
  std::vector<EvalSample> s;
  for (int i = 0; i <= 10; ++i) {
    const double t = i;
    const bool coasting = (i >= 3 && i <= 5) || i >= 9;
    // Error (1, 0, 0.5) until the first coast, (1, 3, -0.25) from its end; (4, -1, 2) from 9 on.
    if (i <= 2) s.push_back(sample(t, coasting, 1.0, 0.0, 0.5));
    else if (i <= 8) s.push_back(sample(t, coasting, 1.0, 3.0 * std::min(1.0, (t - 2.0) / 3.0), 0.5 - 0.75 * std::min(1.0, (t - 2.0) / 3.0)));
    else s.push_back(sample(t, coasting, 4.0, -1.0, 2.0));
  }
  const auto c = coast_episodes(s, pose_t::FLAG_COASTING);
  ASSERT_EQ(c.size(), 2u);
  EXPECT_DOUBLE_EQ(c[0].start_s, 2.0);  // the last VO pose
  EXPECT_DOUBLE_EQ(c[0].duration_s, 3.0);
  EXPECT_NEAR(c[0].added_h_m, 3.0, 1e-12);
  EXPECT_NEAR(c[0].added_v_m, -0.75, 1e-12);
  EXPECT_NEAR(c[0].error_h_m, std::hypot(1.0, 3.0), 1e-12);
  EXPECT_DOUBLE_EQ(c[0].sigma_h_m, 7.0);
  EXPECT_DOUBLE_EQ(c[1].start_s, 8.0);  // a coast still on at the end ends there
  EXPECT_DOUBLE_EQ(c[1].duration_s, 2.0);
  EXPECT_NEAR(c[1].added_h_m, std::hypot(3.0, -4.0), 1e-12);
  EXPECT_NEAR(c[1].added_v_m, 2.25, 1e-12);
  // Other flags are not coasting; nothing flagged, nothing found.
  for (EvalSample& x : s) x.flags &= ~pose_t::FLAG_COASTING;
  EXPECT_TRUE(coast_episodes(s, pose_t::FLAG_COASTING).empty());
}

TEST(CoastEpisodes, ARunFromTheFirstPoseStartsThere) {
  std::vector<EvalSample> s = {sample(0.0, true, 0.0, 0.0, 0.0), sample(0.5, true, 0.3, 0.4, 0.0),
                               sample(1.0, false, 0.3, 0.4, 0.0)};
  const auto c = coast_episodes(s, pose_t::FLAG_COASTING);
  ASSERT_EQ(c.size(), 1u);
  EXPECT_DOUBLE_EQ(c[0].start_s, 0.0);
  EXPECT_DOUBLE_EQ(c[0].duration_s, 0.5);
  EXPECT_NEAR(c[0].added_h_m, 0.5, 1e-12);
}

}  // namespace
}  // namespace nadir
