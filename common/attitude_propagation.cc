#include "common/attitude_propagation.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <stdexcept>

#include "common/geometry.h"

namespace nadir {

AttitudePolicy attitude_policy_from_name(const std::string& name) {
  if (name == "propagate") return AttitudePolicy::kPropagate;
  if (name == "interpolate") return AttitudePolicy::kInterpolate;
  throw std::invalid_argument("attitude policy '" + name + "' is not one of propagate, interpolate");
}

const char* attitude_policy_name(AttitudePolicy policy) {
  return policy == AttitudePolicy::kPropagate ? "propagate" : "interpolate";
}

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

std::optional<Eigen::Vector3d> propagated_rpy(const InsAttitude& base, const InsAttitude* earlier, int64_t utime) {
  if (utime == base.utime) return Eigen::Vector3d(base.roll, base.pitch, base.yaw);
  const Eigen::Matrix3d r = rotation_from_rpy(base.roll, base.pitch, base.yaw);
  Eigen::Vector3d rate = base.body_rate;
  if (!base.has_rate) {
    if (earlier == nullptr || earlier->utime >= base.utime) return std::nullopt;
    rate = body_rate_between(rotation_from_rpy(earlier->roll, earlier->pitch, earlier->yaw), r,
                             static_cast<double>(base.utime - earlier->utime) * 1e-6);
  }
  return rpy_from_rotation(propagate_attitude(r, rate, static_cast<double>(utime - base.utime) * 1e-6));
}

void InsCompleteness::note_interval(int64_t interval_us) {
  if (interval_us <= 0 || interval_us >= min_interval_us_) return;
  ++short_intervals_;
  bound_us_ = std::min(bound_us_, interval_us);
}

}  // namespace nadir
