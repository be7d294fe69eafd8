#pragma once
// Frames and rotations used by the estimator.
// World: local north-east-down. Body: x forward, y right, z down.
// Attitude as ZYX Euler angles: R_world_body = Rz(yaw) * Ry(pitch) * Rx(roll).

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace nadir {

Eigen::Matrix3d rotation_from_rpy(double roll, double pitch, double yaw);
// Inverse of rotation_from_rpy (pitch in [-pi/2, pi/2]).
Eigen::Vector3d rpy_from_rotation(const Eigen::Matrix3d& r);
// Wraps an angle to (-pi, pi].
double wrap_angle(double angle);
// Shortest signed difference a - b, wrapped.
double angle_difference(double a, double b);
inline double deg_to_rad(double deg) { return deg * M_PI / 180.0; }
inline double rad_to_deg(double rad) { return rad * 180.0 / M_PI; }

}  // namespace nadir
