#pragma once
// The simulator's own frame conventions, written independently of
// common/geometry so that a convention bug cannot cancel itself between the
// simulator (the judge) and the estimator.
// World: local north-east-down. Body: x forward, y right, z down.
// Attitude: R_world_body = Rz(yaw) * Ry(pitch) * Rx(roll), yaw clockwise from north.

#include <Eigen/Core>
#include <cmath>

namespace nadir::sim {

inline Eigen::Matrix3d rot_x(double a) {
  const double c = std::cos(a), s = std::sin(a);
  Eigen::Matrix3d r;
  r << 1, 0, 0, 0, c, -s, 0, s, c;
  return r;
}
inline Eigen::Matrix3d rot_y(double a) {
  const double c = std::cos(a), s = std::sin(a);
  Eigen::Matrix3d r;
  r << c, 0, s, 0, 1, 0, -s, 0, c;
  return r;
}
inline Eigen::Matrix3d rot_z(double a) {
  const double c = std::cos(a), s = std::sin(a);
  Eigen::Matrix3d r;
  r << c, -s, 0, s, c, 0, 0, 0, 1;
  return r;
}
inline Eigen::Matrix3d world_from_body(double roll, double pitch, double yaw) {
  return rot_z(yaw) * rot_y(pitch) * rot_x(roll);
}
inline double deg2rad(double d) { return d * M_PI / 180.0; }
inline double rad2deg(double r) { return r * 180.0 / M_PI; }
inline double wrap_pi(double a) {
  a = std::fmod(a + M_PI, 2.0 * M_PI);
  if (a <= 0) a += 2.0 * M_PI;
  return a - M_PI;
}

}  // namespace nadir::sim
