#include "common/attitude_propagation.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <stdexcept>

#include "common/geometry.h"

namespace nadir {

AttitudePolicy attitude_policy_from_name(const std::string& name) {
  if (name == "propagate") return AttitudePolicy::kPropagate;
  if (name == "interpolate") return AttitudePolicy::kInterpolate;
  if (name == "auto") return AttitudePolicy::kAuto;
  throw std::invalid_argument("attitude policy '" + name + "' is not one of auto, propagate, interpolate");
}

const char* attitude_policy_name(AttitudePolicy policy) {
  switch (policy) {
    case AttitudePolicy::kPropagate: return "propagate";
    case AttitudePolicy::kAuto: return "auto";
    case AttitudePolicy::kInterpolate: break;
  }
  return "interpolate";
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
  const Eigen::Matrix3d r = rotation_from_rpy(base.roll, base.pitch, base.yaw);
  const bool two_samples = earlier != nullptr && earlier->utime < base.utime;
  const double dt_s = static_cast<double>(utime - base.utime) * 1e-6;
  if (!base.has_rate) {
    if (utime == base.utime) return Eigen::Vector3d(base.roll, base.pitch, base.yaw);
    if (!two_samples) return std::nullopt;
    // The rate that joins the two samples: the earlier one, carried on with
    // it, lands on the same attitude, so there is nothing to average.
    const Eigen::Vector3d rate = body_rate_between(rotation_from_rpy(earlier->roll, earlier->pitch, earlier->yaw), r,
                                                   static_cast<double>(base.utime - earlier->utime) * 1e-6);
    return rpy_from_rotation(propagate_attitude(r, rate, dt_s));
  }
  Eigen::Matrix3d at = propagate_attitude(r, base.body_rate, dt_s);
  if (two_samples && earlier->has_rate) {
    // The earlier sample carried to the same time (the mean of the two rates
    // up to the base sample, the base's rate after it) and the two averaged:
    // white attitude noise of the INS halves in variance, as interpolation
    // between two samples reduces it, without waiting for the next sample.
    const Eigen::Matrix3d e = rotation_from_rpy(earlier->roll, earlier->pitch, earlier->yaw);
    const double gap_s = static_cast<double>(base.utime - earlier->utime) * 1e-6;
    const Eigen::Matrix3d earlier_at = propagate_attitude(
        propagate_attitude(e, 0.5 * (earlier->body_rate + base.body_rate), gap_s), base.body_rate, dt_s);
    const Eigen::AngleAxisd between(at.transpose() * earlier_at);
    at = at * Eigen::AngleAxisd(0.5 * between.angle(), between.axis()).toRotationMatrix();
  }
  return rpy_from_rotation(at);
}

double propagated_white_noise_share(const InsAttitude& base, const InsAttitude* earlier, int64_t utime) {
  const bool two_samples = earlier != nullptr && earlier->utime < base.utime;
  if (!two_samples) return 1.0;
  if (base.has_rate) return earlier->has_rate ? 0.5 : 1.0;
  if (utime == base.utime) return 1.0;
  const double k = static_cast<double>(utime - base.utime) / static_cast<double>(base.utime - earlier->utime);
  return (1.0 + k) * (1.0 + k) + k * k;
}

double interpolated_white_noise_share(double fraction) {
  const double f = std::clamp(fraction, 0.0, 1.0);
  return (1.0 - f) * (1.0 - f) + f * f;
}

void InsCompleteness::note_interval(int64_t interval_us) {
  if (interval_us <= 0 || interval_us >= min_interval_us_) return;
  ++short_intervals_;
  bound_us_ = std::min(bound_us_, interval_us);
}

}  // namespace nadir
