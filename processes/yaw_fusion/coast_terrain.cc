#include "processes/yaw_fusion/coast_terrain.h"

#include <cmath>

namespace nadir {

Eigen::Vector2d ground_gradient_ned(double ground_roll, double ground_pitch, double yaw) {
  // Plane n . X = d with n = (sin p cos r, -sin r, cos p cos r): the ground's
  // down coordinate changes by -n_x / n_z per metre forward, -n_y / n_z per metre right.
  const double forward = -std::tan(ground_pitch);
  const double right = std::tan(ground_roll) / std::cos(ground_pitch);
  const double c = std::cos(yaw), s = std::sin(yaw);
  return {c * forward - s * right, s * forward + c * right};
}

void CoastTerrain::note_frame(int64_t utime, const Eigen::Vector3d& position, double height_agl,
                              const Eigen::Vector2d& gradient) {
  frames_.push_back({utime, position, height_agl, gradient});
  while (frames_.size() > 1 && utime - frames_.front().utime > window_us_) frames_.pop_front();
}

bool CoastTerrain::anchor() {
  anchored_ = false;
  if (frames_.empty()) return false;
  Eigen::Vector2d gradient = Eigen::Vector2d::Zero();
  int gradients = 0;
  for (const Frame& f : frames_) {
    if (f.gradient.allFinite()) {
      gradient += f.gradient;
      ++gradients;
    }
  }
  if (gradients > 0) gradient /= gradients;
  // Each ground point carried to the last frame along the mean slope, then
  // averaged: the altimeter's noise shrinks by the number of frames.
  const Eigen::Vector2d last = frames_.back().position.head<2>();
  double sum = 0.0;
  int points = 0;
  for (const Frame& f : frames_) {
    if (!std::isfinite(f.height_agl)) continue;
    sum += f.position.z() + f.height_agl + gradient.dot(last - f.position.head<2>());
    ++points;
  }
  if (points == 0) return false;
  origin_ = last;
  origin_down_ = sum / points;
  gradient_ = gradient;
  anchored_ = true;
  return true;
}

double CoastTerrain::ground_down(const Eigen::Vector2d& horizontal) const {
  return origin_down_ + gradient_.dot(horizontal - origin_);
}

}  // namespace nadir
