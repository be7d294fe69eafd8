#include "processes/vo_solver/attitude_propagation.h"

#include <Eigen/Geometry>

namespace nadir::vo {

Eigen::Matrix3d propagate_attitude(const Eigen::Matrix3d& world_from_body, const Eigen::Vector3d& body_rate_rad_s,
                                   double dt_s) {
  const Eigen::Vector3d rotation_vector = body_rate_rad_s * dt_s;
  const double angle = rotation_vector.norm();
  if (angle == 0.0) return world_from_body;
  return world_from_body * Eigen::AngleAxisd(angle, rotation_vector / angle).toRotationMatrix();
}

Eigen::Vector3d body_rate_between(const Eigen::Matrix3d& earlier, const Eigen::Matrix3d& later, double dt_s) {
  const Eigen::AngleAxisd step(earlier.transpose() * later);
  return step.axis() * (step.angle() / dt_s);
}

}  // namespace nadir::vo
