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
ground_points_t grid(const Eigen::Vector3d& position, double yaw, Ground ground, float sigma = 0.5f,
                     int64_t utime = 0, int64_t first_id = 0) {
  ground_points_t g{};
  g.utime = utime;
  const double c = std::cos(yaw), s = std::sin(yaw);
  for (double x = -50.0; x <= 100.0; x += 5.0) {
    for (double y = -40.0; y <= 40.0; y += 5.0) {
      const Eigen::Vector2d world = position.head<2>() + Eigen::Vector2d(c * x - s * y, s * x + c * y);
      g.track_id.push_back(first_id + static_cast<int64_t>(g.track_id.size()));
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
    SeenGround seen(1.0);
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
    // Just past the edge of what the frame saw (its last row is 100 m ahead)
    // the points lie behind: no ground (the plane would be extrapolated).
    const Eigen::Vector2d forward(std::cos(yaw), std::sin(yaw));
    EXPECT_TRUE(seen.ground_down(position.head<2>() + 85.0 * forward, SeenGroundOptions{}).has_value()) << yaw;
    EXPECT_FALSE(seen.ground_down(position.head<2>() + 105.0 * forward, SeenGroundOptions{}).has_value()) << yaw;
    EXPECT_FALSE(seen.ground_down(position.head<2>() + 160.0 * forward, SeenGroundOptions{}).has_value()) << yaw;
  }
}

TEST(SeenGround, NoisyPointsOverRoughGroundReportTheirScatter) {
  std::mt19937 rng(5);
  std::normal_distribution<double> normal;
  // Rough ground: 1 m of bumps about a plane, points with 0.5 m depth noise.
  auto rough = [&](const Eigen::Vector2d& p) { return 80.0 + 0.03 * p.x() + 1.0 * normal(rng); };
  SeenGround seen(1.0);
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

// Each track's newest point counts; a frame's points stay for the window
// after the frame that last had them, whether later frames had points or not.
TEST(SeenGround, KeepsEachTracksNewestPointOverTheWindow) {
  SeenGround seen(1.0);
  const int64_t t0 = 1'000'000'000;
  auto at = [](double down) { return [down](const Eigen::Vector2d&) { return down; }; };
  const Eigen::Vector3d position(0.0, 0.0, -100.0);
  // Frame 1 saw level ground at down 50, tracks 0..; frame 2 (0.5 s later, 100 m on) the
  // same tracks 2 m higher (a better depth), and new ones (ids from 100000) ahead.
  seen.note_frame(grid(position, 0.0, at(50.0), 0.5f, t0, 0), position, 0.0);
  const Eigen::Vector2d ahead(60.0, 0.0);
  EXPECT_NEAR(seen.ground_down(ahead, SeenGroundOptions{})->down, 50.0, 1e-4);
  const Eigen::Vector3d later(100.0, 0.0, -100.0);
  ground_points_t second = grid(position, 0.0, at(48.0), 0.5f, t0 + 500'000, 0);
  seen.note_frame(second, position, 0.0);
  EXPECT_NEAR(seen.ground_down(ahead, SeenGroundOptions{})->down, 48.0, 1e-4);  // replaced, not averaged
  seen.note_frame(grid(later, 0.0, at(47.0), 0.5f, t0 + 500'000, 100000), later, 0.0);
  EXPECT_NEAR(seen.ground_down(Eigen::Vector2d(180.0, 0.0), SeenGroundOptions{})->down, 47.0, 1e-4);
  // 1.2 s after frame 1 (0.7 s after frame 2), a frame without points: all kept.
  seen.note_frame_without_points(t0 + 1'200'000);
  EXPECT_TRUE(seen.ground_down(ahead, SeenGroundOptions{}).has_value());
  // 1.6 s: frame 2's points are older than the window.
  seen.note_frame_without_points(t0 + 1'600'000);
  EXPECT_EQ(seen.size(), 0u);
}

TEST(SeenGround, TooFewOrCollinearPoints) {
  SeenGround seen(1.0);
  EXPECT_FALSE(seen.ground_down(Eigen::Vector2d::Zero(), SeenGroundOptions{}).has_value());  // nothing seen
  // One line of points along north: a plane is not defined across it.
  ground_points_t g{};
  auto add = [&](double north, double east, double down) {
    g.track_id.push_back(static_cast<int64_t>(g.track_id.size()));
    g.position_m.push_back({static_cast<float>(north), static_cast<float>(east), static_cast<float>(down + 50.0)});
    g.depth_sigma_m.push_back(0.5f);
    g.num_points = static_cast<int32_t>(g.track_id.size());
  };
  for (int i = -5; i <= 5; ++i) add(3.0 * i, 0.0, 0.02 * 3.0 * i);
  seen.note_frame(g, Eigen::Vector3d(0.0, 0.0, -50.0), 0.0);
  EXPECT_FALSE(seen.ground_down(Eigen::Vector2d(0.0, 1.0), SeenGroundOptions{}).has_value());
  // A second line 10 m east: the plane down = 0.02 north + 0.01 east, exact between them.
  for (int i = -5; i <= 5; ++i) add(3.0 * i, 10.0, 0.02 * 3.0 * i + 0.1);
  seen.note_frame(g, Eigen::Vector3d(0.0, 0.0, -50.0), 0.0);
  const auto h = seen.ground_down(Eigen::Vector2d(1.0, 4.0), SeenGroundOptions{});
  ASSERT_TRUE(h.has_value());
  EXPECT_NEAR(h->down, 0.02 * 1.0 + 0.01 * 4.0, 1e-5);
  EXPECT_EQ(h->points, 22);
  SeenGroundOptions strict;
  strict.min_points = 23;
  EXPECT_FALSE(seen.ground_down(Eigen::Vector2d(1.0, 4.0), strict).has_value());
  seen.clear();
  EXPECT_EQ(seen.size(), 0u);
}

}  // namespace
}  // namespace nadir
