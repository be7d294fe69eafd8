#include "tests/processes/vo_solver/synthetic_scene.h"

#include <Eigen/Geometry>

#include <cmath>
#include <stdexcept>

#include "common/geometry.h"

namespace nadir::vo::testing {

Scene make_scene(const SceneSpec& spec) {
  Scene scene;
  // World: NED with the prev camera at the origin.
  const Eigen::Matrix3d world_from_prev_body = rotation_from_rpy(spec.prev_roll, spec.prev_pitch, spec.prev_yaw);
  const Eigen::Matrix3d world_from_curr_body = rotation_from_rpy(spec.curr_roll, spec.curr_pitch, spec.curr_yaw);
  const Eigen::Matrix3d world_from_prev_cam = world_from_prev_body * spec.body_from_camera;
  const Eigen::Matrix3d world_from_curr_cam = world_from_curr_body * spec.body_from_camera;
  const Eigen::Vector3d prev_centre = Eigen::Vector3d::Zero();
  const Eigen::Vector3d curr_centre =
      Eigen::AngleAxisd(spec.prev_yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix() * spec.translation;
  // Plane attitude given in the level frame of curr (heading curr_yaw): a
  // surface a vehicle would sit on with that roll and pitch.
  const Eigen::Matrix3d plane_rotation = rotation_from_rpy(spec.ground_roll, spec.ground_pitch, spec.curr_yaw);
  const Eigen::Vector3d normal = plane_rotation.col(2);
  const Eigen::Vector3d plane_point = curr_centre + spec.height_m * Eigen::Vector3d::UnitZ();
  auto hit_layer = [&](const Eigen::Vector3d& origin, const Eigen::Vector3d& dir, double above_m, double* t) {
    const double denom = normal.dot(dir);
    if (std::abs(denom) < 1e-12) return false;
    *t = normal.dot(plane_point - above_m * normal - origin) / denom;
    return *t > 0;
  };
  auto hit = [&](const Eigen::Vector3d& origin, const Eigen::Vector3d& dir, double* t) {
    return hit_layer(origin, dir, 0.0, t);
  };
  double prev_range = 0, curr_range = 0;
  if (!hit(prev_centre, world_from_prev_body * spec.beam_body, &prev_range) ||
      !hit(curr_centre, world_from_curr_body * spec.beam_body, &curr_range)) {
    throw std::invalid_argument("synthetic scene: altimeter beam misses the plane");
  }

  FramePair& pair = scene.pair;
  pair.body_from_camera = spec.body_from_camera;
  pair.prev_roll = spec.prev_roll;
  pair.prev_pitch = spec.prev_pitch;
  pair.prev_yaw = spec.prev_yaw;
  pair.curr_roll = spec.curr_roll;
  pair.curr_pitch = spec.curr_pitch;
  pair.curr_yaw = spec.curr_yaw;
  pair.prev_range_m = prev_range;
  pair.curr_range_m = curr_range;
  pair.prev_beam_body = spec.beam_body;
  pair.curr_beam_body = spec.beam_body;

  std::mt19937 rng(spec.seed);
  std::uniform_real_distribution<double> px_u(0.0, spec.width - 1.0), px_v(0.0, spec.height - 1.0);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::normal_distribution<double> noise(0.0, 1.0);
  int attempts = 0;
  while (static_cast<int>(pair.curr_norm.size()) < spec.num_features) {
    if (++attempts > spec.num_features * 100) throw std::invalid_argument("synthetic scene: too few visible features");
    const Eigen::Vector2d curr((px_u(rng) - spec.cx) / spec.fx, (px_v(rng) - spec.cy) / spec.fx);
    const Eigen::Vector3d dir = world_from_curr_cam * curr.homogeneous();
    double t = 0;
    const bool raised = spec.raised_fraction > 0 && unit(rng) < spec.raised_fraction;
    if (!hit_layer(curr_centre, dir, raised ? spec.raised_height_m : 0.0, &t)) continue;
    const Eigen::Vector3d ground = curr_centre + t * dir;
    const Eigen::Vector3d in_prev = world_from_prev_cam.transpose() * (ground - prev_centre);
    if (in_prev.z() <= 0) continue;
    const Eigen::Vector2d prev = in_prev.head<2>() / in_prev.z();
    const double u = prev.x() * spec.fx + spec.cx, v = prev.y() * spec.fx + spec.cy;
    if (u < 0 || v < 0 || u > spec.width - 1 || v > spec.height - 1) continue;
    Eigen::Vector2d curr_obs = curr, prev_obs = prev;
    if (spec.noise_px > 0) {
      curr_obs += spec.noise_px / spec.fx * Eigen::Vector2d(noise(rng), noise(rng));
      prev_obs += spec.noise_px / spec.fx * Eigen::Vector2d(noise(rng), noise(rng));
    }
    const bool outlier = unit(rng) < spec.outlier_fraction;
    if (outlier) {
      const double angle = 2 * M_PI * unit(rng);
      const double size = spec.outlier_min_px + (spec.outlier_max_px - spec.outlier_min_px) * unit(rng);
      curr_obs += size / spec.fx * Eigen::Vector2d(std::cos(angle), std::sin(angle));
    }
    pair.prev_norm.push_back(prev_obs);
    pair.curr_norm.push_back(curr_obs);
    scene.is_outlier.push_back(outlier);
    scene.is_raised.push_back(raised);
  }
  scene.translation = spec.translation;
  scene.dyaw = wrap_angle(spec.curr_yaw - spec.prev_yaw);
  scene.ground_roll = spec.ground_roll;
  scene.ground_pitch = spec.ground_pitch;
  // Vertical line down from the prev camera to the plane.
  double down = 0;
  hit(prev_centre, Eigen::Vector3d::UnitZ(), &down);
  scene.prev_altitude_m = down;
  return scene;
}

}  // namespace nadir::vo::testing
