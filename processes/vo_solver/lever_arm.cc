#include "processes/vo_solver/lever_arm.h"

#include <cmath>

#include "common/geometry.h"

namespace nadir::vo {

void move_to_ins_reference(const FramePair& pair, const Eigen::Vector3d& camera_lever_body, Estimate* est) {
  if (camera_lever_body.isZero(0.0)) return;
  const Eigen::Matrix3d prev_level = rotation_from_rpy(pair.prev_roll, pair.prev_pitch, 0.0);
  const Eigen::Matrix3d curr_level = rotation_from_rpy(pair.curr_roll, pair.curr_pitch, 0.0);
  const Eigen::Matrix3d turn = rotation_from_rpy(0.0, 0.0, est->dyaw);
  const Eigen::Vector3d prev_lever = prev_level * camera_lever_body;
  const Eigen::Vector3d curr_lever = curr_level * camera_lever_body;
  est->translation -= turn * curr_lever - prev_lever;
  // z is down: the INS reference lies lever.z above the camera.
  est->altitude_m += prev_lever.z();
  // d translation / d dyaw = -Rz(dyaw) [e_z]x curr_lever.
  Eigen::Matrix<double, 6, 6> jacobian = Eigen::Matrix<double, 6, 6>::Identity();
  jacobian.block<3, 1>(0, 3) = -(turn * Eigen::Vector3d(-curr_lever.y(), curr_lever.x(), 0.0));
  est->covariance = jacobian * est->covariance * jacobian.transpose();
}

}  // namespace nadir::vo
