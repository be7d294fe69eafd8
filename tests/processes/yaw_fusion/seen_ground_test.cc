// SeenGround: a frame's ground points placed in the world, and the ground
// below a position from the points around it.

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "processes/yaw_fusion/seen_ground.h"

namespace nadir {
namespace {

// A frame at `position` with heading `yaw` seeing a 5 m grid (x from -50 to
// 100 m ahead, y +-40 m) of the ground down = f(north, east).
template <class Ground>
ground_points_t grid(const Eigen::Vector3d& position, double yaw, Ground ground, float sigma = 0.5f) {
  ground_points_t g{};
  const double c = std::cos(yaw), s = std::sin(yaw);
  for (double x = -50.0; x <= 100.0; x += 5.0) {
    for (double y = -40.0; y <= 40.0; y += 5.0) {
      const Eigen::Vector2d world = position.head<2>() + Eigen::Vector2d(c * x - s * y, s * x + c * y);
      g.position_m.push_back({static_cast<float>(x), static_cast<float>(y),
                              static_cast<float>(ground(world) - position.z())});
      g.depth_sigma_m.push_back(sigma);
    }
  }
  g.num_points = static_cast<int32_t>(g.position_m.size());
  return g;
}

TEST(SeenGround, RecoversASlopedGroundExactlyInTheWorldWhateverTheHeading) {
  auto plane = [](const Eigen::Vector2d& p) { return 120.0 + 0.04 * p.x() - 0.02 * p.y(); };
  for (double yaw : {0.0, 1.0, -2.5, M_PI}) {
    SeenGround seen;
    const Eigen::Vector3d position(1000.0, -300.0, -30.0);
    seen.note_frame(grid(position, yaw, plane), position, yaw);
    // 60 m ahead along the heading, 10 m to the right: far from any grid point's spacing.
    const Eigen::Vector2d ahead = position.head<2>() + 60.0 * Eigen::Vector2d(std::cos(yaw), std::sin(yaw)) +
                                  Eigen::Vector2d(-std::sin(yaw), std::cos(yaw)) * 12.5;
    const auto h = seen.ground_down(ahead, SeenGroundOptions{});
    ASSERT_TRUE(h.has_value()) << yaw;
    EXPECT_NEAR(h->down, plane(ahead), 1e-3) << yaw;  // float positions: ~1e-4 m
    EXPECT_GT(h->points, 50) << yaw;
    // The points lie on the plane: the fit's variance with their reported 0.5 m, no roughness.
    EXPECT_GE(h->variance, 0.999 * 0.25 / h->points) << yaw;
    EXPECT_LT(h->variance, 1.5 * 0.25 / h->points) << yaw;
    // At the edge of what the frame saw (its last row, 100 m ahead) the points
    // lie behind: no ground (a fit there would be extrapolated); beyond it none.
    const Eigen::Vector2d forward(std::cos(yaw), std::sin(yaw));
    EXPECT_TRUE(seen.ground_down(position.head<2>() + 85.0 * forward, SeenGroundOptions{}).has_value()) << yaw;
    EXPECT_FALSE(seen.ground_down(position.head<2>() + 100.0 * forward, SeenGroundOptions{}).has_value()) << yaw;
    EXPECT_FALSE(seen.ground_down(position.head<2>() + 160.0 * forward, SeenGroundOptions{}).has_value()) << yaw;
  }
}

TEST(SeenGround, NoisyPointsOverRoughGroundReportTheirScatter) {
  std::mt19937 rng(5);
  std::normal_distribution<double> normal;
  // Rough ground: 1 m of bumps about a plane, points with 0.5 m depth noise.
  auto rough = [&](const Eigen::Vector2d& p) { return 80.0 + 0.03 * p.x() + 1.0 * normal(rng); };
  SeenGround seen;
  const Eigen::Vector3d position(0.0, 0.0, -70.0);
  ground_points_t g = grid(position, 0.3, rough);
  for (auto& p : g.position_m) p[2] += static_cast<float>(0.5 * normal(rng));
  seen.note_frame(g, position, 0.3);
  const Eigen::Vector2d where(40.0, 10.0);
  const auto h = seen.ground_down(where, SeenGroundOptions{});
  ASSERT_TRUE(h.has_value());
  // The ground under a beam is off the fitted plane by the roughness (1 m): the
  // variance holds it, not only the fit's (0.5 m / sqrt(n)).
  EXPECT_GT(h->variance, 0.6);
  EXPECT_LT(h->variance, 1.6);
  EXPECT_LT(std::abs(h->down - (80.0 + 0.03 * where.x())), 3.0 * std::sqrt(h->variance));
}

TEST(SeenGround, TooFewOrCollinearPoints) {
  SeenGround seen;
  EXPECT_FALSE(seen.ground_down(Eigen::Vector2d::Zero(), SeenGroundOptions{}).has_value());  // nothing seen
  // One line of points along north (a plane is not defined across it): their weighted mean.
  ground_points_t g{};
  for (int i = -5; i <= 5; ++i) {
    g.position_m.push_back({static_cast<float>(3.0 * i), 0.0f, static_cast<float>(50.0 + (i % 2 ? 0.2 : -0.2))});
    g.depth_sigma_m.push_back(i == 0 ? 0.25f : 0.5f);
  }
  g.num_points = static_cast<int32_t>(g.position_m.size());
  seen.note_frame(g, Eigen::Vector3d(0.0, 0.0, -50.0), 0.0);
  const auto h = seen.ground_down(Eigen::Vector2d(0.0, 1.0), SeenGroundOptions{});
  ASSERT_TRUE(h.has_value());
  // Six odd i at +0.2, four even at -0.2 (weight 1 each), i = 0 at -0.2 with weight 4.
  EXPECT_NEAR(h->down, (6.0 * 0.2 + 4.0 * -0.2 + 4.0 * -0.2) / 14.0, 1e-6);
  EXPECT_EQ(h->points, 11);
  SeenGroundOptions strict;
  strict.min_points = 12;
  EXPECT_FALSE(seen.ground_down(Eigen::Vector2d::Zero(), strict).has_value());
  seen.clear();
  EXPECT_EQ(seen.size(), 0u);
}

}  // namespace
}  // namespace nadir
