#pragma once
// The `propagate` attitude policy shared by vo_solver and yaw_fusion: a
// frame's attitude from the INS samples at or before its trigger, rotated on
// to the trigger time with the body rates, so no node waits for the INS
// sample after a frame. Rotations are world_from_body (common/geometry.h).
// Only sample times and values decide, never arrival: live = lockstep replay.
// `auto` propagates where the INS reports body rates and interpolates where it
// does not: carried on with the rate between its two newest samples, a
// rate-less INS's white attitude noise grows (up to 2.1x its sigma a sample
// interval on), where interpolation averages it
// (docs/research/2026-11-latency.md).

#include <Eigen/Core>

#include <cstdint>
#include <optional>
#include <string>

namespace nadir {

enum class AttitudePolicy { kInterpolate, kPropagate, kAuto };
AttitudePolicy attitude_policy_from_name(const std::string& name);  // throws std::invalid_argument
const char* attitude_policy_name(AttitudePolicy policy);
// Whether `policy` propagates from a newest sample at or before the frame
// that has (or lacks) body rates.
inline bool propagates(AttitudePolicy policy, bool sample_has_rate) {
  return policy == AttitudePolicy::kPropagate || (policy == AttitudePolicy::kAuto && sample_has_rate);
}

// R(t0 + dt) = R(t0) * exp([rate]x dt) for a body-frame rate held constant
// over dt: exact for a constant body rate; with an angular acceleration a the
// error is about a * dt^2 / 2.
Eigen::Matrix3d propagate_attitude(const Eigen::Matrix3d& world_from_body, const Eigen::Vector3d& body_rate_rad_s,
                                   double dt_s);

// The constant body-frame rate that turns `earlier` into `later` in dt_s > 0
// seconds (the inverse of propagate_attitude), for an INS without rates.
Eigen::Vector3d body_rate_between(const Eigen::Matrix3d& earlier, const Eigen::Matrix3d& later, double dt_s);

struct InsAttitude {
  int64_t utime = 0;
  double roll = 0, pitch = 0, yaw = 0;
  bool has_rate = false;
  Eigen::Vector3d body_rate = Eigen::Vector3d::Zero();  // rad/s
};

// Roll, pitch, yaw at `utime` (>= base.utime) from `base`, with its own rate
// or, without one, the rate from `earlier` (the sample before it; may be
// null) to it. Nothing when there is no rate at all. With rates in both
// samples, the mean of `base` and `earlier` each carried to `utime`: the
// INS's white attitude noise enters with half its variance (interpolation
// between two samples: 1/2 to 1), the motion is not averaged.
std::optional<Eigen::Vector3d> propagated_rpy(const InsAttitude& base, const InsAttitude* earlier, int64_t utime);

// The share of one sample's white attitude noise variance in a frame's
// attitude made from the samples around it (each sample's noise independent):
// propagated_rpy's from the same arguments -- 1/2 for two samples with rates
// averaged, 1 for one, (1 + k)^2 + k^2 for a rate-less INS carried on k
// sample intervals past its newest -- and interpolation's at `fraction` of
// the way from one sample to the next, (1 - f)^2 + f^2. The uncertainty
// models scale the white part of the INS noise by it.
double propagated_white_noise_share(const InsAttitude& base, const InsAttitude* earlier, int64_t utime);
double interpolated_white_noise_share(double fraction);

// When the propagate policy may use the INS for a frame: every sample at or
// before the frame is in once a later one is, or once the newest is closer
// before the frame than the INS interval (the next cannot be at or before
// it). Intervals shorter than the configured minimum, seen in sample times,
// lower the bound.
class InsCompleteness {
 public:
  explicit InsCompleteness(int64_t min_interval_us) : min_interval_us_(min_interval_us), bound_us_(min_interval_us) {}
  // The interval between two neighbouring sample times (> 0).
  void note_interval(int64_t interval_us);
  bool complete_at(int64_t utime, int64_t newest_utime) const {
    return newest_utime >= utime || utime - newest_utime < bound_us_;
  }
  int64_t short_intervals() const { return short_intervals_; }

 private:
  int64_t min_interval_us_;
  int64_t bound_us_;
  int64_t short_intervals_ = 0;
};

}  // namespace nadir
