#include "processes/yaw_fusion/coast_vertical.h"

namespace nadir {

void CoastVertical::start(double down, double climb_mps, double climb_stddev_mps) {
  state_ << down, climb_mps;
  covariance_.setZero();
  covariance_(1, 1) = climb_stddev_mps * climb_stddev_mps;
}

void CoastVertical::predict(double dt_s, double rate_mps, double q) {
  if (!(dt_s > 0.0)) return;
  state_(0) += rate_mps * dt_s;
  Eigen::Matrix2d transition;
  transition << 1.0, dt_s, 0.0, 1.0;
  Eigen::Matrix2d process;
  process << dt_s * dt_s * dt_s / 3.0, dt_s * dt_s / 2.0, dt_s * dt_s / 2.0, dt_s;
  covariance_ = transition * covariance_ * transition.transpose() + q * q * process;
}

double CoastVertical::update(double measured_down, double variance) {
  const double innovation = measured_down - state_(0);
  const double s = covariance_(0, 0) + variance;
  if (!(s > 0.0)) return innovation;
  const Eigen::Vector2d gain = covariance_.col(0) / s;
  state_ += gain * innovation;
  // Joseph form: stays symmetric and positive with a near-exact measurement.
  Eigen::Matrix2d keep = Eigen::Matrix2d::Identity();
  keep.col(0) -= gain;
  covariance_ = keep * covariance_ * keep.transpose() + variance * gain * gain.transpose();
  return innovation;
}

}  // namespace nadir
