// A camera and an altimeter mounted away from the INS reference
// point, the altimeter's beam misaligned. The pair is built here from world
// poses (INS position and attitude, each sensor at INS + R lever) and plain
// ray/plane intersection; with the installation in SensorCalibration the
// solver's VO_DELTA is the INS reference point's motion, exactly.

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>
#include <utility>

#include "common/geometry.h"
#include "common/sensor_calibration.h"
#include "processes/vo_solver/lever_arm.h"
#include "processes/vo_solver/translation_solver.h"

namespace nadir::vo {
namespace {

struct Pose {
  Eigen::Vector3d position;  // INS reference point, NED
  double roll, pitch, yaw;
  Eigen::Matrix3d world_from_body() const { return rotation_from_rpy(roll, pitch, yaw); }
};

// Ground plane n . X = d (NED, n pointing down into the ground).
struct Plane {
  Eigen::Vector3d normal;
  double d;
  double hit(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction) const {
    return (d - normal.dot(origin)) / normal.dot(direction);
  }
};

struct Installation {
  Eigen::Vector3d camera_lever{1.5, 0.0, 0.3};
  Eigen::Vector3d altimeter_lever{1.2, 0.2, 0.4};
  Eigen::Vector2d beam_misalignment{deg_to_rad(0.2), deg_to_rad(-0.15)};
};

// Features on the plane seen by both cameras (camera axes = body axes), and
// each frame's altimeter range along its true beam from its own position.
FramePair make_pair(const Pose& prev, const Pose& curr, const Plane& plane, const Installation& inst) {
  FramePair pair;
  pair.prev_roll = prev.roll, pair.prev_pitch = prev.pitch, pair.prev_yaw = prev.yaw;
  pair.curr_roll = curr.roll, pair.curr_pitch = curr.pitch, pair.curr_yaw = curr.yaw;
  const Eigen::Vector3d prev_camera = prev.position + prev.world_from_body() * inst.camera_lever;
  const Eigen::Vector3d curr_camera = curr.position + curr.world_from_body() * inst.camera_lever;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-0.6, 0.6);
  while (pair.prev_norm.size() < 300) {
    const Eigen::Vector3d ray = prev.world_from_body() * Eigen::Vector3d(u(rng), u(rng), 1.0);
    const Eigen::Vector3d ground = prev_camera + plane.hit(prev_camera, ray) * ray;
    const Eigen::Vector3d a = prev.world_from_body().transpose() * (ground - prev_camera);
    const Eigen::Vector3d b = curr.world_from_body().transpose() * (ground - curr_camera);
    if (b.z() <= 0 || std::abs(b.x() / b.z()) > 0.7 || std::abs(b.y() / b.z()) > 0.6) continue;
    pair.prev_norm.emplace_back(a.x() / a.z(), a.y() / a.z());
    pair.curr_norm.emplace_back(b.x() / b.z(), b.y() / b.z());
  }
  const Eigen::Matrix3d misalign = rotation_from_rpy(inst.beam_misalignment.x(), inst.beam_misalignment.y(), 0.0);
  auto range = [&](const Pose& p) {
    const Eigen::Vector3d origin = p.position + p.world_from_body() * inst.altimeter_lever;
    return plane.hit(origin, p.world_from_body() * misalign * Eigen::Vector3d::UnitZ());
  };
  pair.prev_range_m = range(prev);  // measured, along the reported beam (body z)
  pair.curr_range_m = range(curr);
  return pair;
}

SensorCalibration installed(const Installation& inst) {
  SensorCalibration c;
  c.camera_lever_arm_m = inst.camera_lever;
  c.altimeter_lever_arm_m = inst.altimeter_lever;
  c.altimeter_beam_misalignment_rad = inst.beam_misalignment;
  return c;
}

// What FrameSync does with each range: the ray from the camera to the point the beam hit.
void apply(const SensorCalibration& c, FramePair* pair) {
  for (auto [range, beam] : {std::pair{&pair->prev_range_m, &pair->prev_beam_body},
                             std::pair{&pair->curr_range_m, &pair->curr_beam_body}}) {
    const AltimeterRay ray = c.ray_from(c.camera_lever_arm_m, *range, *beam);
    *range = ray.range_m;
    *beam = ray.beam_body;
  }
}

// The INS reference point's motion in the level frame of prev.
Eigen::Vector3d ins_motion(const Pose& prev, const Pose& curr) {
  return rotation_from_rpy(0.0, 0.0, prev.yaw).transpose() * (curr.position - prev.position);
}

const Pose kPrev{{0.0, 0.0, -200.0}, deg_to_rad(2.0), deg_to_rad(-3.0), deg_to_rad(10.0)};
const Pose kCurr{{13.0, 3.5, -199.2}, deg_to_rad(-2.5), deg_to_rad(1.5), deg_to_rad(14.0)};
const Plane kSlope{Eigen::Vector3d(0.05, -0.03, 1.0).normalized(), 0.0};

TEST(LeverArms, SolverGivesTheInsMotionExactlyWithSensorsAwayFromTheIns) {
  const Installation inst;
  FramePair pair = make_pair(kPrev, kCurr, kSlope, inst);
  apply(installed(inst), &pair);
  const Estimate camera = solve(pair, SolverOptions{});
  Estimate est = camera;
  move_to_ins_reference(pair, inst.camera_lever, &est);
  ASSERT_EQ(est.quality, 0);
  const Eigen::Vector3d truth = ins_motion(kPrev, kCurr);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(est.translation(k), truth(k), 1e-6) << "component " << k;
  EXPECT_NEAR(est.dyaw, kCurr.yaw - kPrev.yaw, 1e-9);
  // altitude_m: the camera's vertical height above the patch, and the INS's
  // is the lever's vertical part (levelled) more; both against the truth
  // below each point (the 5 % slope under the 1.5 m lever: 7.5 cm apart).
  const Eigen::Vector3d down = Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d prev_camera = kPrev.position + kPrev.world_from_body() * inst.camera_lever;
  EXPECT_NEAR(camera.altitude_m, kSlope.hit(prev_camera, down), 1e-6);
  EXPECT_NEAR(est.altitude_m - camera.altitude_m, (kPrev.world_from_body() * inst.camera_lever).z(), 1e-12);
}

TEST(LeverArms, WithoutTheInstallationTheStepIsOffByTheTurnedLeverAndTheAltimeterOffset) {
  const Installation inst;
  const FramePair raw = make_pair(kPrev, kCurr, kSlope, inst);
  const Eigen::Vector3d truth = ins_motion(kPrev, kCurr);
  const Estimate est = solve(raw, SolverOptions{});
  // The lever turned by 4.5 deg of roll and pitch: ~0.1 m; the altimeter
  // 0.1 m below the camera: 0.05 % of the step's scale.
  EXPECT_GT((est.translation - truth).norm(), 0.05);
  // Only the camera's lever (altimeter taken as mounted at the camera): still off.
  Installation camera_only = inst;
  camera_only.altimeter_lever = inst.camera_lever;
  camera_only.beam_misalignment.setZero();
  FramePair pair = make_pair(kPrev, kCurr, kSlope, camera_only);
  apply(installed(camera_only), &pair);
  Estimate moved = solve(pair, SolverOptions{});
  move_to_ins_reference(pair, camera_only.camera_lever, &moved);
  EXPECT_LT((moved.translation - truth).norm(), 1e-6);
  // A zero lever changes nothing, bit for bit.
  Estimate same = est;
  move_to_ins_reference(raw, Eigen::Vector3d::Zero(), &same);
  EXPECT_EQ(same.translation, est.translation);
  EXPECT_EQ(same.covariance, est.covariance);
}

// The translation's covariance follows the turned lever's dependence on dyaw.
TEST(LeverArms, CovarianceCarriesTheLeverTurnedByTheHeadingChange) {
  const Installation inst;
  FramePair pair = make_pair(kPrev, kCurr, kSlope, inst);
  apply(installed(inst), &pair);
  Estimate est = solve(pair, SolverOptions{});
  est.covariance.setZero();
  const double dyaw_sigma = 0.01;
  est.covariance(3, 3) = dyaw_sigma * dyaw_sigma;
  Estimate moved = est;
  move_to_ins_reference(pair, inst.camera_lever, &moved);
  // Numerically: the translation's change per radian of dyaw.
  Estimate plus = est, minus = est;
  plus.dyaw += 1e-6;
  minus.dyaw -= 1e-6;
  move_to_ins_reference(pair, inst.camera_lever, &plus);
  move_to_ins_reference(pair, inst.camera_lever, &minus);
  const Eigen::Vector3d slope = (plus.translation - minus.translation) / 2e-6;
  const Eigen::Matrix3d expected = slope * slope.transpose() * dyaw_sigma * dyaw_sigma;
  const Eigen::Matrix3d moved_block = moved.covariance.topLeftCorner<3, 3>();
  EXPECT_TRUE(moved_block.isApprox(expected, 1e-6)) << moved.covariance;
  EXPECT_NEAR(moved.covariance(3, 3), dyaw_sigma * dyaw_sigma, 1e-15);
}

TEST(SensorCalibrationRay, IsThePointTheBeamHitSeenFromTheOrigin) {
  SensorCalibration c;
  // Defaults: the same range and beam, bit for bit.
  const Eigen::Vector3d beam = Eigen::Vector3d(0.01, -0.02, 1.0).normalized();
  const AltimeterRay same = c.ray_from(Eigen::Vector3d::Zero(), 123.456, beam);
  EXPECT_EQ(same.range_m, 123.456);
  EXPECT_EQ(same.beam_body, beam);
  EXPECT_FALSE(c.moves_altimeter_ray());
  // Altimeter 1 m ahead, 0.5 m below the origin; beam pitched 0.1 rad (nose up turns z towards +x).
  c.altimeter_lever_arm_m = Eigen::Vector3d(1.0, 0.0, 0.5);
  c.altimeter_beam_misalignment_rad = Eigen::Vector2d(0.0, 0.1);
  c.altimeter_range_scale = 1.01;
  c.altimeter_range_bias_m = 0.2;
  EXPECT_TRUE(c.moves_altimeter_ray());
  const double measured = 1.01 * 10.0 + 0.2;  // true range 10 m
  const AltimeterRay ray = c.ray_from(Eigen::Vector3d::Zero(), measured, Eigen::Vector3d::UnitZ());
  const Eigen::Vector3d point(1.0 + 10.0 * std::sin(0.1), 0.0, 0.5 + 10.0 * std::cos(0.1));
  EXPECT_NEAR(ray.range_m, point.norm(), 1e-12);
  EXPECT_TRUE((ray.range_m * ray.beam_body).isApprox(point, 1e-12));
  // From a camera 1 m ahead of the INS: the altimeter is 0.5 m below it.
  const AltimeterRay from_camera = c.ray_from(Eigen::Vector3d(1.0, 0.0, 0.0), measured, Eigen::Vector3d::UnitZ());
  EXPECT_TRUE((from_camera.range_m * from_camera.beam_body).isApprox(point - Eigen::Vector3d(1.0, 0.0, 0.0), 1e-12));
}

}  // namespace
}  // namespace nadir::vo
