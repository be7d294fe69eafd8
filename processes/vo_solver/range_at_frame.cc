#include "processes/vo_solver/range_at_frame.h"

#include <Eigen/Dense>

#include <algorithm>

#include "processes/vo_solver/plane_model.h"

namespace nadir::vo {

void LevelVelocity::add(int64_t prev_utime, int64_t utime, const Eigen::Vector3d& translation, double dyaw) {
  const double dt = 1e-6 * static_cast<double>(utime - prev_utime);
  if (!(dt > 0) || !translation.allFinite()) {
    reset();
    return;
  }
  const Eigen::Vector3d pair_velocity = translation / dt;
  // The first pair after a start or a gap stands alone; later ones are
  // blended in with weight dt / time_constant.
  const bool continues = utime_ == prev_utime;
  const double w = continues ? std::min(1.0, dt / time_constant_s_) : 1.0;
  const Eigen::Vector3d blended = continues ? ((1.0 - w) * velocity_ + w * pair_velocity).eval() : pair_velocity;
  velocity_ = rot_z(dyaw).transpose() * blended;  // into curr's level frame
  utime_ = utime;
}

bool LevelVelocity::at(int64_t utime, Eigen::Vector3d* velocity) const {
  if (utime_ == kNone || utime != utime_) return false;
  *velocity = velocity_;
  return true;
}

void move_range_to_frame(double age_s, const Eigen::Vector3d& velocity_level, const RollPitch& sampled,
                         const RollPitch& frame, double* range_m, Eigen::Vector3d* beam_body) {
  if (!(age_s > 0) || !(*range_m > 0)) return;
  const Eigen::Matrix3d identity = Eigen::Matrix3d::Identity();
  const Eigen::Vector3d beam_then = level_from_camera(sampled.roll, sampled.pitch, identity) * *beam_body;
  const Eigen::Vector3d spot = *range_m * beam_then.normalized() - age_s * velocity_level;
  const double range = spot.norm();
  if (!(range > 0) || !spot.allFinite()) return;
  *range_m = range;
  *beam_body = level_from_camera(frame.roll, frame.pitch, identity).transpose() * (spot / range);
}

}  // namespace nadir::vo
