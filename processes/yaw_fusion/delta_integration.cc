#include "processes/yaw_fusion/delta_integration.h"

#include <Eigen/Eigenvalues>

#include <cmath>

#include "common/geometry.h"

namespace nadir {

namespace {

// The nearest positive semi-definite matrix (negative eigenvalues to 0): a
// delta published without the sensor part (uncertainty disabled, an older
// solver) has less than the shared part to give.
Eigen::Matrix4d psd_part(const Eigen::Matrix4d& m) {
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix4d> eig(0.5 * (m + m.transpose()));
  const Eigen::Vector4d clamped = eig.eigenvalues().cwiseMax(0.0);
  return eig.eigenvectors() * clamped.asDiagonal() * eig.eigenvectors().transpose();
}

// The INS yaw bias over one delta of `dt` seconds: the walk's variance, and
// the offset at the start (`first`) either as a constant or as a first-order
// Gauss-Markov error with its stationary variance.
PoseFilter::YawBiasStep yaw_bias_step(const YawFusionOptions& options, double dt, bool first) {
  PoseFilter::YawBiasStep step;
  const double walk = deg_to_rad(options.ins_yaw_bias_walk_deg_per_sqrt_s);
  const double offset_variance = std::pow(deg_to_rad(options.ins_yaw_bias_stddev_deg), 2);
  step.walk_variance_added = walk * walk * dt;
  if (options.ins_yaw_bias_correlation_s > 0.0) {
    step.markov_decay = std::exp(-dt / options.ins_yaw_bias_correlation_s);
    step.markov_variance_added = offset_variance * (first ? 1.0 : 1.0 - step.markov_decay * step.markov_decay);
  } else if (first) {
    step.walk_variance_added += offset_variance;
  }
  return step;
}

}  // namespace

Eigen::Vector3d integrate_delta(PoseFilter* filter, const vo_delta_t& delta, const Eigen::Matrix4d& covariance,
                                const FrameAttitudeNoise& prev, const FrameAttitudeNoise& curr,
                                const YawFusionOptions& options) {
  const DeltaUncertaintyOptions& u = options.sensor_uncertainty;
  const Eigen::Vector3d translation(delta.dx, delta.dy, delta.dz);
  double prev_levelling = 0.0, curr_levelling = 0.0, range_scale_variance = 0.0;
  double prev_heading = 0.0, curr_heading = 0.0;
  if (u.enabled) {
    // Exactly what vo_solver put on dx, dy and dyaw (the VO solver's sensor covariance).
    const double prev_rp = u.frame_roll_pitch_stddev_rad(prev.noise_share);
    const double curr_rp = u.frame_roll_pitch_stddev_rad(curr.noise_share);
    frame_levelling_variances(delta.altitude_m, delta.dz, prev_rp, curr_rp, &prev_levelling, &curr_levelling);
    range_scale_variance = u.range_scale_stddev * u.range_scale_stddev;
    prev_heading = levelling_yaw_variance_rad2(prev.pitch, prev_rp);
    curr_heading = levelling_yaw_variance_rad2(curr.pitch, curr_rp);
  }
  Eigen::Matrix4d shared = Eigen::Matrix4d::Zero();
  shared(0, 0) = shared(1, 1) = prev_levelling + curr_levelling;
  shared.topLeftCorner<3, 3>() += range_scale_variance * translation * translation.transpose();
  shared(3, 3) = prev_heading + curr_heading;
  const Eigen::Vector3d world = filter->predict_with_delta(translation, delta.dyaw, psd_part(covariance - shared));
  filter->step_frame_yaw_levelling(delta.prev_utime, delta.utime, prev_heading, curr_heading);
  const double dt = std::max(0.0, static_cast<double>(delta.utime - delta.prev_utime) * 1e-6);
  filter->apply_heading_drift(dt, u.heading_drift_stddev_rad_s(), u.heading_drift_time_s);

  filter->add_shared_errors(prev_levelling, curr_levelling, world, range_scale_variance,
                            yaw_bias_step(options, dt, !filter->yaw_bias_started()));
  return world;
}

}  // namespace nadir
