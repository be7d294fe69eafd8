// A range sampled before its frame, moved to the camera at the frame
// (range_at_frame.h): checked against the spot computed here from the two
// camera positions and a ground plane, and the velocity it uses.

#include "processes/vo_solver/range_at_frame.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <cmath>

#include "processes/vo_solver/plane_model.h"

namespace nadir::vo {
namespace {

Eigen::Vector3d level(const RollPitch& a, const Eigen::Vector3d& body) {
  return level_from_camera(a.roll, a.pitch, Eigen::Matrix3d::Identity()) * body;
}

TEST(RangeAtFrame, AClimbingCameraSeesTheSpotAtItsHeight) {
  // Level, 100 m over flat ground at the frame, flying 20 m/s and climbing
  // 2 m/s; the range was sampled 80 ms earlier, 0.16 m lower.
  const Eigen::Vector3d velocity(20.0, 0.0, -2.0);  // level frame, z down
  double range = 100.0 - 0.16;
  Eigen::Vector3d beam = Eigen::Vector3d::UnitZ();
  move_range_to_frame(0.08, velocity, {}, {}, &range, &beam);
  const Eigen::Vector3d spot = range * beam;
  EXPECT_NEAR(spot.z(), 100.0, 1e-12) << "the camera's height at the frame";
  EXPECT_NEAR(spot.x(), -1.6, 1e-12) << "the spot it measured is behind it";
  EXPECT_NEAR(spot.y(), 0.0, 1e-12);
}

TEST(RangeAtFrame, TheMovedBeamMeetsTheSampledSpotOnSlopedGround) {
  // Ground n . X = d in the frame's level frame (the camera at the origin),
  // sloped; the aircraft turned between the sample and the frame.
  const Eigen::Vector3d n = Eigen::Vector3d(0.2, -0.1, 1.0).normalized();
  const double d = 80.0;
  const Eigen::Vector3d velocity(15.0, 5.0, 1.0);
  const double age = 0.09;
  const RollPitch sampled{0.05, -0.03}, frame{-0.02, 0.04};
  const Eigen::Vector3d beam_body = Eigen::Vector3d(0.05, 0.0, 1.0).normalized();
  const Eigen::Vector3d then = -age * velocity;  // camera at the sample time
  const Eigen::Vector3d beam_then = level(sampled, beam_body);
  double range = (d - n.dot(then)) / n.dot(beam_then);
  const Eigen::Vector3d true_spot = then + range * beam_then;
  Eigen::Vector3d beam = beam_body;
  move_range_to_frame(age, velocity, sampled, frame, &range, &beam);
  const Eigen::Vector3d spot = range * level(frame, beam);
  EXPECT_LT((spot - true_spot).norm(), 1e-10);
  EXPECT_NEAR(beam.norm(), 1.0, 1e-12);
}

TEST(RangeAtFrame, ARangeNotOlderThanItsFrameIsLeftAlone) {
  for (const double age : {0.0, -0.02}) {
    double range = 123.0;
    Eigen::Vector3d beam = Eigen::Vector3d(0.1, 0.0, 1.0);
    move_range_to_frame(age, Eigen::Vector3d(20, 0, -3), {0.1, 0.1}, {0.2, 0.0}, &range, &beam);
    EXPECT_EQ(range, 123.0);
    EXPECT_EQ(beam, Eigen::Vector3d(0.1, 0.0, 1.0));
  }
}

// A flight at a constant world velocity turning 0.01 rad a pair: each pair's
// translation in its prev level frame, with the INS attitude noise of its two
// frames (e_k - e_{k-1}: it telescopes), as the solver reports it.
TEST(LevelVelocity, AveragesThePairsAndTurnsWithTheHeading) {
  const Eigen::Vector3d world_velocity(18.0, 6.0, -1.5);  // north, east, down
  const int64_t dt_us = 71429;
  const double dt = 1e-6 * dt_us, dyaw = 0.01;
  LevelVelocity velocity(0.5);
  double heading = 0;
  double noise_prev = 0;
  double worst_pair = 0;
  Eigen::Vector3d v;
  for (int k = 1; k <= 60; ++k) {
    const double noise = (k % 2 ? 0.15 : -0.15);  // metres, alternating: the worst case for a mean
    const Eigen::Vector3d in_prev = rot_z(heading).transpose() * world_velocity * dt;
    const Eigen::Vector3d t = in_prev + Eigen::Vector3d(noise - noise_prev, 0, 0);
    worst_pair = std::max(worst_pair, std::abs(noise - noise_prev) / dt);
    noise_prev = noise;
    velocity.add(k * dt_us - dt_us, k * dt_us, t, dyaw);
    heading += dyaw;
    ASSERT_TRUE(velocity.at(k * dt_us, &v));
  }
  // In the last frame's level frame: the world velocity turned by its heading.
  const Eigen::Vector3d truth = rot_z(heading).transpose() * world_velocity;
  EXPECT_LT((v - truth).norm(), 0.1 * worst_pair) << v.transpose() << " vs " << truth.transpose();
  EXPECT_LT((v - truth).norm(), 0.5);
  EXPECT_FALSE(velocity.at(59 * dt_us, &v)) << "only for the last solved frame";
}

TEST(LevelVelocity, AGapStartsItAgain) {
  LevelVelocity velocity(0.5);
  velocity.add(0, 100000, Eigen::Vector3d(2.0, 0, 0), 0.0);
  velocity.add(100000, 200000, Eigen::Vector3d(2.0, 0, 0), 0.0);
  // Not continuing from 200000: this pair alone.
  velocity.add(500000, 600000, Eigen::Vector3d(0.0, 3.0, 0), 0.0);
  Eigen::Vector3d v;
  ASSERT_TRUE(velocity.at(600000, &v));
  EXPECT_NEAR((v - Eigen::Vector3d(0, 30, 0)).norm(), 0.0, 1e-12);
  velocity.reset();
  EXPECT_FALSE(velocity.at(600000, &v));
}

}  // namespace
}  // namespace nadir::vo
