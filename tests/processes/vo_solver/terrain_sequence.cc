#include "tests/processes/vo_solver/terrain_sequence.h"

#include <Eigen/Geometry>

#include <cmath>
#include <random>

#include "common/geometry.h"

namespace nadir::vo::testing {

TerrainSequence::TerrainSequence(const TerrainSpec& spec) : spec_(spec) {
  std::mt19937 rng(spec.seed);
  const double length = 200.0 * spec.step_m + 600.0;
  std::uniform_real_distribution<double> along(-300.0, length), across(-300.0, 300.0), unit(0.0, 1.0);
  const double c = std::cos(spec.heading), s = std::sin(spec.heading);
  for (int i = 0; i < spec.num_points; ++i) {
    const double a = along(rng), b = across(rng);
    double up = 0.0;  // height above the level corridor
    if (std::abs(b) > spec.corridor_half_width_m) {
      // Blocks 20 m wide: each a different height, some below the corridor.
      const int cell = static_cast<int>(std::floor(a / 20.0)) * 7919 + static_cast<int>(std::floor(b / 20.0));
      std::mt19937 cell_rng(static_cast<uint32_t>(cell) * 2654435761u + spec.seed);
      up = spec.relief_m * (1.5 * std::uniform_real_distribution<double>(0.0, 1.0)(cell_rng) - 0.5);
    }
    const double north = c * a - s * b, east = s * a + c * b;
    points_.emplace_back(north, east, -up - ridge_up(north, east));
  }
}

double TerrainSequence::ridge_up(double north, double east) const {
  if (spec_.ridge_amplitude_m == 0.0) return 0.0;
  const double along = std::cos(spec_.heading) * north + std::sin(spec_.heading) * east;
  // Crests sharper than the valleys (a second harmonic), as ridges are.
  const double phase = 2.0 * M_PI * along / spec_.ridge_wavelength_m;
  if (spec_.sharp_crests) return spec_.ridge_amplitude_m * (1.0 - 2.0 * std::abs(std::sin(0.5 * phase)));
  return spec_.ridge_amplitude_m * (std::cos(phase) + 0.5 * std::cos(2.0 * phase));
}

double TerrainSequence::range_to_corridor(const Eigen::Vector3d& position, const Eigen::Vector3d& beam) const {
  // The beam meets z = -ridge_up(x, y): fixed-point iteration on the range
  // (the ridges' slopes stay far below the beam's steepness).
  double range = -position.z() / beam.z();
  for (int i = 0; i < 100; ++i) {
    const Eigen::Vector3d spot = position + range * beam;
    range = (-ridge_up(spot.x(), spot.y()) - position.z()) / beam.z();
  }
  return range;
}

double TerrainSequence::range_at(const FramePose& pose) const {
  return range_to_corridor(pose.position, rotation_from_rpy(pose.roll, pose.pitch, pose.yaw).col(2));
}

FramePose TerrainSequence::pose(int k) const {
  if (pose_override) return pose_override(k);
  FramePose p;
  const double c = std::cos(spec_.heading), s = std::sin(spec_.heading);
  p.position = Eigen::Vector3d(c * spec_.step_m * k, s * spec_.step_m * k, -spec_.height_m - spec_.climb_per_frame_m * k);
  p.roll = 0.04 * std::sin(0.3 * k);
  p.pitch = -0.03 + 0.02 * std::cos(0.2 * k);
  p.yaw = spec_.heading + 0.02 * std::sin(0.1 * k) + spec_.yaw_rate * k;
  return p;
}

SequencePair TerrainSequence::pair(int k) const { return pair(k - 1, k); }

SequencePair TerrainSequence::pair(int j, int k) const {
  SequencePair out;
  const FramePose a = pose(j), b = pose(k);
  FramePair& pair = out.pair;
  pair.prev_roll = a.roll;
  pair.prev_pitch = a.pitch;
  pair.prev_yaw = a.yaw;
  pair.curr_roll = b.roll;
  pair.curr_pitch = b.pitch;
  pair.curr_yaw = b.yaw;
  // Altimeter along body z onto the corridor (level, or over the ridges).
  const Eigen::Matrix3d ra = rotation_from_rpy(a.roll, a.pitch, a.yaw), rb = rotation_from_rpy(b.roll, b.pitch, b.yaw);
  pair.prev_range_m = range_to_corridor(a.position, ra.col(2));
  pair.curr_range_m = range_to_corridor(b.position, rb.col(2));
  std::mt19937 rng(spec_.seed * 7919u + static_cast<uint32_t>(k));
  std::normal_distribution<double> noise(0.0, spec_.noise_px / spec_.fx);
  auto project = [&](const Eigen::Matrix3d& r, const Eigen::Vector3d& centre, const Eigen::Vector3d& x,
                     Eigen::Vector2d* norm) {
    const Eigen::Vector3d in_cam = r.transpose() * (x - centre);
    if (in_cam.z() <= 0) return false;
    *norm = in_cam.head<2>() / in_cam.z();
    const double u = norm->x() * spec_.fx + spec_.cx, v = norm->y() * spec_.fx + spec_.cy;
    return u >= 0 && v >= 0 && u <= spec_.width - 1 && v <= spec_.height - 1;
  };
  for (size_t i = 0; i < points_.size(); ++i) {
    Eigen::Vector2d p, q;
    const Eigen::Vector3d xa = point_motion ? Eigen::Vector3d(points_[i] + point_motion(i, j)) : points_[i];
    const Eigen::Vector3d xb = point_motion ? Eigen::Vector3d(points_[i] + point_motion(i, k)) : points_[i];
    if (!project(ra, a.position, xa, &p) || !project(rb, b.position, xb, &q)) continue;
    if (spec_.noise_px > 0) {
      p += Eigen::Vector2d(noise(rng), noise(rng));
      q += Eigen::Vector2d(noise(rng), noise(rng));
    }
    pair.prev_norm.push_back(p);
    pair.curr_norm.push_back(q);
    out.ids.push_back(static_cast<int64_t>(i));
    out.curr_depth_m.push_back(xb.z() - b.position.z());
  }
  out.translation = Eigen::AngleAxisd(a.yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix().transpose() * (b.position - a.position);
  out.dyaw = wrap_angle(b.yaw - a.yaw);
  return out;
}

}  // namespace nadir::vo::testing
