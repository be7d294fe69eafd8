#include <gtest/gtest.h>

#include <stdexcept>

#include "common/geodetic.h"
#include "common/pose_origin.h"

namespace nadir {
namespace {

// A vehicle flying north at 20 m/s from `start`; its INS position is exact.
ins_t ins_at(const GeodeticPoint& start, int64_t utime) {
  GeodeticTrack track(start);
  const GeodeticPoint p = track.geodetic(Eigen::Vector3d(20.0 * static_cast<double>(utime) * 1e-6, 0.0, 0.0));
  ins_t s{};
  s.utime = utime;
  s.latitude_deg = p.latitude_deg;
  s.longitude_deg = p.longitude_deg;
  s.height_m = p.height_m;
  s.velocity_ned[0] = 20.0;
  return s;
}

pose_t pose_at(int64_t utime, double north, double east) {
  pose_t p{};
  p.utime = utime;
  p.position_ned[0] = north;
  p.position_ned[1] = east;
  return p;
}

// The local position of `p` in a frame whose origin is `origin`.
Eigen::Vector3d local(const GeodeticPoint& origin, const GeodeticPoint& p) {
  GeodeticTrack track(origin);
  return track.ned(p);
}

const GeodeticPoint kStart{40.4406, -79.9959, 450.0};

TEST(PoseOrigin, TheFirstPoseIsPlacedBetweenTheInsSamplesAroundIt) {
  PoseOrigin origin;
  origin.add_ins(ins_at(kStart, 0));
  origin.add_pose(pose_at(4'000, 0.0, 0.0));  // the INS after it has not come yet
  EXPECT_FALSE(origin.known());
  origin.add_pose(pose_at(75'000, 1.3, -0.3));  // the next pose, with the first pair's error
  origin.add_ins(ins_at(kStart, 10'000));
  ASSERT_TRUE(origin.known());
  EXPECT_EQ(origin.anchored_utime(), 4'000);
  // POSE's (0, 0) is where the vehicle was at the first pose: 0.08 m north of the start.
  const Eigen::Vector3d at = local(kStart, origin.origin());
  EXPECT_NEAR(at.x(), 0.08, 1e-6);
  EXPECT_NEAR(at.y(), 0.0, 1e-6);
  EXPECT_NEAR(at.z(), 0.0, 1e-6);
  EXPECT_EQ(origin.poses_passed_over(), 0);
}

TEST(PoseOrigin, AnInsStartingJustAfterTheFirstPoseIsMovedBackAlongItsVelocity) {
  PoseOrigin origin(0.05);
  origin.add_pose(pose_at(-30, 0.0, 0.0));
  origin.add_pose(pose_at(71'400, 1.3, -0.3));
  origin.add_ins(ins_at(kStart, 0));
  ASSERT_TRUE(origin.known());
  EXPECT_EQ(origin.anchored_utime(), -30);
  const Eigen::Vector3d at = local(kStart, origin.origin());
  EXPECT_NEAR(at.x(), -20.0 * 30e-6, 1e-7);
  EXPECT_NEAR(at.y(), 0.0, 1e-7);
}

TEST(PoseOrigin, APoseTheInsCannotPlaceIsPassedOverAndTheNextOneMovedBackByItsPosition) {
  PoseOrigin origin(0.05);
  origin.add_pose(pose_at(0, 0.0, 0.0));           // the INS starts 0.2 s later
  origin.add_pose(pose_at(300'000, 5.0, -2.0));    // this pose says it is 5 m north, 2 m west of the origin
  origin.add_ins(ins_at(kStart, 200'000));
  EXPECT_FALSE(origin.known());
  EXPECT_EQ(origin.poses_passed_over(), 1);
  origin.add_ins(ins_at(kStart, 310'000));
  ASSERT_TRUE(origin.known());
  EXPECT_EQ(origin.anchored_utime(), 300'000);
  // The INS at 0.3 s is 6 m north of the start; the origin lies (5, -2) m back from it, the down too.
  const Eigen::Vector3d at = local(kStart, origin.origin());
  EXPECT_NEAR(at.x(), 1.0, 1e-6);
  EXPECT_NEAR(at.y(), 2.0, 1e-6);
}

TEST(PoseOrigin, TheHeightIsThatOfPosesDownZero) {
  PoseOrigin origin;
  origin.add_ins(ins_at(kStart, 0));
  pose_t p = pose_at(0, 0.0, 0.0);
  p.position_ned[2] = -3.0;  // the first pose 3 m above its down 0
  origin.add_pose(p);
  ASSERT_TRUE(origin.known());
  EXPECT_NEAR(origin.origin().height_m, kStart.height_m - 3.0, 1e-9);
}

TEST(PoseOrigin, ExtrapolationLimitIsChecked) {
  EXPECT_THROW(PoseOrigin(-0.1), std::invalid_argument);
  EXPECT_THROW(PoseOrigin(2.0), std::invalid_argument);
}

}  // namespace
}  // namespace nadir
