#include "processes/yaw_fusion/pose_filter.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>

#include "common/geometry.h"

namespace nadir {

void PoseFilter::initialise(double yaw, double yaw_variance) {
  x_.setZero();
  p_.setZero();
  x_(kYaw) = wrap_angle(yaw);
  p_(kYaw, kYaw) = yaw_variance;
  initialised_ = true;
  terrain_initialised_ = false;
  have_origin_levelling_ = false;
  origin_levelling_variance_ = frame_levelling_variance_ = 0.0;
  displacement_.setZero();
  range_scale_variance_ = 0.0;
  yaw_bias_.setZero();
  yaw_bias_estimate_.setZero();
  yaw_bias_corrected_ = false;
  yaw_bias_started_ = false;
  yaw_bias_unestimated_.setZero();
  yaw_bias_path_.setZero();
  have_yaw_levelling_frame_ = false;
  have_heading_drift_ = false;
}

void PoseFilter::restore(const Eigen::Vector3d& position, const Eigen::Matrix3d& position_covariance, double yaw,
                         double yaw_variance) {
  initialise(yaw, yaw_variance);
  x_.head<3>() = position;
  p_.topLeftCorner<3, 3>() = 0.5 * (position_covariance + position_covariance.transpose());
}

Eigen::Vector3d PoseFilter::predict_with_delta(const Eigen::Vector3d& translation, double dyaw,
                                               const Eigen::Matrix4d& covariance) {
  const double c = std::cos(yaw());
  const double s = std::sin(yaw());
  const Eigen::Vector3d world(c * translation.x() - s * translation.y(), s * translation.x() + c * translation.y(),
                              translation.z());
  x_.head<3>() += world;
  x_(kYaw) = wrap_angle(x_(kYaw) + dyaw);

  // Jacobian of the new state w.r.t. the old one: only the registration
  // depends on the old yaw.
  Matrix f = Matrix::Identity();
  f(kNorth, kYaw) = -world.y();
  f(kEast, kYaw) = world.x();
  // Jacobian w.r.t. the delta (dx, dy, dz, dyaw).
  Eigen::Matrix<double, kSize, 4> g = Eigen::Matrix<double, kSize, 4>::Zero();
  g(kNorth, 0) = c;
  g(kNorth, 1) = -s;
  g(kEast, 0) = s;
  g(kEast, 1) = c;
  g(kDown, 2) = 1.0;
  g(kYaw, 3) = 1.0;
  p_ = f * p_ * f.transpose() + g * covariance * g.transpose();
  p_ = 0.5 * (p_ + p_.transpose());
  return world;
}

void PoseFilter::step_frame_yaw_levelling(int64_t prev_frame, int64_t curr_frame, double prev_variance,
                                          double curr_variance) {
  if (!have_yaw_levelling_frame_ || yaw_levelling_frame_ != prev_frame) {
    p_.row(kYawLevelling).setZero();
    p_.col(kYawLevelling).setZero();
    p_(kYawLevelling, kYawLevelling) = std::max(0.0, prev_variance);
  }
  // prev's term leaves the yaw: P <- F P F^T with F = I - e_yaw e_levelling^T,
  // as a row and a column operation.
  p_.row(kYaw) -= p_.row(kYawLevelling);
  p_.col(kYaw) -= p_.col(kYawLevelling);
  const double v = std::max(0.0, curr_variance);  // curr's enters it and is held
  p_.row(kYawLevelling).setZero();
  p_.col(kYawLevelling).setZero();
  p_(kYaw, kYaw) += v;
  p_(kYaw, kYawLevelling) = p_(kYawLevelling, kYaw) = v;
  p_(kYawLevelling, kYawLevelling) = v;
  yaw_levelling_frame_ = curr_frame;
  have_yaw_levelling_frame_ = true;
}

void PoseFilter::apply_heading_drift(double dt, double stddev, double time_s) {
  if (!(stddev > 0.0) || !(time_s > 0.0) || !(dt > 0.0)) return;
  const double stationary = stddev * stddev;
  if (!have_heading_drift_) {
    x_(kHeadingDrift) = 0.0;
    p_.row(kHeadingDrift).setZero();
    p_.col(kHeadingDrift).setZero();
    p_(kHeadingDrift, kHeadingDrift) = stationary;
    have_heading_drift_ = true;
  }
  // The delta's dyaw held the drift of its interval: take the estimate out.
  x_(kYaw) = wrap_angle(x_(kYaw) - x_(kHeadingDrift) * dt);
  // P <- F P F^T with F = I - dt e_yaw e_drift^T, then the drift row and
  // column times the decay, as row and column operations.
  const double decay = std::exp(-dt / time_s);
  x_(kHeadingDrift) *= decay;
  p_.row(kYaw) -= dt * p_.row(kHeadingDrift);
  p_.row(kHeadingDrift) *= decay;
  p_.col(kYaw) -= dt * p_.col(kHeadingDrift);
  p_.col(kHeadingDrift) *= decay;
  p_(kHeadingDrift, kHeadingDrift) += stationary * (1.0 - decay * decay);
  p_ = 0.5 * (p_ + p_.transpose());
}

void PoseFilter::propagate_without_vo(const Eigen::Vector3d& displacement_ned,
                                      const Eigen::Vector3d& position_variance_added, double yaw_variance_added) {
  x_.head<3>() += displacement_ned;
  for (int i = 0; i < 3; ++i) p_(i, i) += position_variance_added(i);
  p_(kYaw, kYaw) += yaw_variance_added;
}

void PoseFilter::add_shared_errors(double prev_levelling_variance, double curr_levelling_variance,
                                   const Eigen::Vector3d& world_translation, double range_scale_variance,
                                   const YawBiasStep& yaw_bias) {
  if (!have_origin_levelling_) {
    origin_levelling_variance_ = prev_levelling_variance;
    have_origin_levelling_ = true;
  }
  frame_levelling_variance_ = curr_levelling_variance;
  yaw_bias_started_ = true;
  displacement_ += world_translation;
  range_scale_variance_ = range_scale_variance;
  // The translation was registered with the yaw of the previous frame, which
  // carries the bias as it was before this delta's walk.
  Eigen::Matrix4d f = Eigen::Matrix4d::Identity();
  f(0, kWalkBias) = f(0, kMarkovBias) = -world_translation.y();
  f(1, kWalkBias) = f(1, kMarkovBias) = world_translation.x();
  f(kMarkovBias, kMarkovBias) = yaw_bias.markov_decay;
  yaw_bias_ = f * yaw_bias_ * f.transpose();
  yaw_bias_(kWalkBias, kWalkBias) += yaw_bias.walk_variance_added;
  yaw_bias_(kMarkovBias, kMarkovBias) += yaw_bias.markov_variance_added;
  yaw_bias_estimate_(1) *= yaw_bias.markov_decay;
  yaw_bias_path_ += Eigen::Vector2d(-world_translation.y(), world_translation.x());
  if (yaw_bias_corrected_) {
    yaw_bias_unestimated_(0, 1) *= yaw_bias.markov_decay;
    yaw_bias_unestimated_(1, 0) *= yaw_bias.markov_decay;
    yaw_bias_unestimated_(1, 1) *= yaw_bias.markov_decay * yaw_bias.markov_decay;
    yaw_bias_unestimated_(0, 0) += yaw_bias.walk_variance_added;
    yaw_bias_unestimated_(1, 1) += yaw_bias.markov_variance_added;
  }
}

void PoseFilter::correct_yaw_bias(const Eigen::Vector2d& correction, const Eigen::Matrix2d& variance_removed) {
  if (!yaw_bias_corrected_) yaw_bias_unestimated_ = yaw_bias_covariance();
  yaw_bias_corrected_ = true;
  yaw_bias_estimate_ += correction;
  Eigen::Matrix2d bias = yaw_bias_covariance() - 0.5 * (variance_removed + variance_removed.transpose());
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eigen(0.5 * (bias + bias.transpose()));
  bias = eigen.eigenvectors() * eigen.eigenvalues().cwiseMax(0.0).asDiagonal() * eigen.eigenvectors().transpose();
  yaw_bias_.block<2, 2>(kWalkBias, kWalkBias) = bias;
}

PoseFilter::YawBiasState PoseFilter::yaw_bias_state() const {
  YawBiasState state;
  state.estimate = yaw_bias_estimate_;
  state.covariance = yaw_bias_covariance();
  state.estimated = yaw_bias_corrected_;
  state.prior_covariance = yaw_bias_corrected_ ? yaw_bias_unestimated_ : Eigen::Matrix2d(yaw_bias_covariance());
  return state;
}

void PoseFilter::restore_yaw_bias(const YawBiasState& state) {
  yaw_bias_.setZero();
  yaw_bias_.block<2, 2>(kWalkBias, kWalkBias) = 0.5 * (state.covariance + state.covariance.transpose());
  yaw_bias_estimate_ = state.estimate;
  yaw_bias_corrected_ = state.estimated;
  yaw_bias_unestimated_ = state.estimated
                              ? Eigen::Matrix2d(0.5 * (state.prior_covariance + state.prior_covariance.transpose()))
                              : Eigen::Matrix2d::Zero();
  yaw_bias_path_.setZero();
  yaw_bias_started_ = true;
}

void PoseFilter::hold_yaw_bias_correlation(const Eigen::Matrix2d& cross) {
  // The position error split as A beta + r, r independent of the bias error
  // beta: A = cross Sigma^-1 (a pseudo-inverse: a part without variance
  // explains nothing), the explained part A Sigma A' = cross Sigma^+ cross'.
  const Eigen::Matrix2d sigma = yaw_bias_covariance();
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eigen(sigma);
  Eigen::Vector2d inverse = Eigen::Vector2d::Zero();
  const double largest = eigen.eigenvalues().maxCoeff();
  for (int i = 0; i < 2; ++i) {
    if (eigen.eigenvalues()(i) > 1e-12 * largest && largest > 0.0) inverse(i) = 1.0 / eigen.eigenvalues()(i);
  }
  const Eigen::Matrix2d pseudo_inverse = eigen.eigenvectors() * inverse.asDiagonal() * eigen.eigenvectors().transpose();
  Eigen::Matrix2d explained = cross * pseudo_inverse * cross.transpose();
  explained = 0.5 * (explained + explained.transpose());
  // What stays in the filter must remain a covariance: explain no more than it holds.
  const Eigen::Matrix2d held = p_.topLeftCorner<2, 2>();
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> rest(held - explained);
  double scale = 1.0;
  if (rest.eigenvalues().minCoeff() < 0.0) {
    // Largest s in [0, 1] with held - s explained >= 0 (generalised eigenvalue).
    Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::Matrix2d> g(explained, held + 1e-12 * Eigen::Matrix2d::Identity());
    const double top = g.eigenvalues().maxCoeff();
    scale = top > 0.0 ? std::min(1.0, 0.999 / top) : 0.0;
  }
  p_.topLeftCorner<2, 2>() -= scale * explained;
  yaw_bias_.topLeftCorner<2, 2>() = scale * explained;
  yaw_bias_.block<2, 2>(0, kWalkBias) = std::sqrt(scale) * cross;
  yaw_bias_.block<2, 2>(kWalkBias, 0) = std::sqrt(scale) * cross.transpose();
}

Eigen::Matrix3d PoseFilter::reported_position_covariance() const {
  Eigen::Matrix3d p = position_covariance();
  const double levelling = origin_levelling_variance_ + frame_levelling_variance_;
  p(0, 0) += levelling;
  p(1, 1) += levelling;
  p += range_scale_variance_ * displacement_ * displacement_.transpose();
  p.topLeftCorner<2, 2>() += yaw_bias_.topLeftCorner<2, 2>();
  return p;
}

void PoseFilter::joseph_update(const Vector& k, const Eigen::Matrix<double, 1, kSize>& h, double r) {
  const Matrix a = Matrix::Identity() - k * h;
  p_ = a * p_ * a.transpose() + k * r * k.transpose();
  p_ = 0.5 * (p_ + p_.transpose());
}

PoseFilter::UpdateResult PoseFilter::update_yaw(double measured_yaw, double variance, double gate_sigma) {
  const double innovation = angle_difference(measured_yaw, x_(kYaw));
  last_yaw_innovation_ = innovation;
  const double s = p_(kYaw, kYaw) + variance;
  if (innovation * innovation > gate_sigma * gate_sigma * s) return UpdateResult::kRejected;
  Vector k = Vector::Zero();
  k(kYaw) = p_(kYaw, kYaw) / s;
  k(kHeadingDrift) = p_(kHeadingDrift, kYaw) / s;
  Eigen::Matrix<double, 1, kSize> h = Eigen::Matrix<double, 1, kSize>::Zero();
  h(kYaw) = 1.0;
  x_(kYaw) = wrap_angle(x_(kYaw) + k(kYaw) * innovation);
  x_(kHeadingDrift) += k(kHeadingDrift) * innovation;
  joseph_update(k, h, variance);
  return UpdateResult::kAccepted;
}

void PoseFilter::set_down(double down, double variance) {
  x_(kDown) = down;
  p_.row(kDown).setZero();
  p_.col(kDown).setZero();
  p_(kDown, kDown) = variance;
}

template <int N>
void PoseFilter::fix_position(const Eigen::Matrix<double, N, 1>& correction,
                              const Eigen::Matrix<double, N, N>& covariance) {
  x_.head<N>() += correction;
  origin_levelling_variance_ = 0.0;
  displacement_.head<N>().setZero();
  yaw_bias_.topRows<2>().setZero();
  yaw_bias_.leftCols<2>().setZero();
  // What the filter itself must hold so that the reported covariance is `covariance`.
  Eigen::Matrix<double, N, N> wanted = 0.5 * (covariance + covariance.transpose());
  wanted.template topLeftCorner<2, 2>() -= frame_levelling_variance_ * Eigen::Matrix2d::Identity();
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, N, N>> eigen(wanted);
  const Eigen::Matrix<double, N, 1> values = eigen.eigenvalues().cwiseMax(1e-6);
  p_.topRows<N>().setZero();
  p_.leftCols<N>().setZero();
  p_.topLeftCorner<N, N>() = eigen.eigenvectors() * values.asDiagonal() * eigen.eigenvectors().transpose();
}

void PoseFilter::apply_horizontal_fix(const Eigen::Vector2d& correction, const Eigen::Matrix2d& covariance) {
  fix_position<2>(correction, covariance);
}

void PoseFilter::apply_position_fix(const Eigen::Vector3d& correction, const Eigen::Matrix3d& covariance,
                                    bool vertical) {
  if (!vertical) {
    apply_horizontal_fix(correction.head<2>(), covariance.topLeftCorner<2, 2>());
    return;
  }
  const double terrain_variance = p_(kTerrain, kTerrain);
  fix_position<3>(correction, covariance);
  if (terrain_initialised_) {
    // Down and terrain moved together: the altimeter's constraint between them holds.
    x_(kTerrain) += correction.z();
    p_(kTerrain, kDown) = p_(kDown, kTerrain) = p_(kDown, kDown);
    p_(kTerrain, kTerrain) = std::max(terrain_variance, p_(kDown, kDown));
  }
}

void PoseFilter::reset_yaw(double yaw, double variance) {
  x_(kYaw) = wrap_angle(yaw);
  p_.row(kYaw).setZero();
  p_.col(kYaw).setZero();
  p_(kYaw, kYaw) = variance;
}

void PoseFilter::anchor_terrain(double height_agl, double variance) {
  x_(kTerrain) = x_(kDown) + height_agl;
  p_.row(kTerrain) = p_.row(kDown);
  p_.col(kTerrain) = p_.col(kDown);
  p_(kTerrain, kTerrain) = p_(kDown, kDown) + variance;
  terrain_initialised_ = true;
}

PoseFilter::UpdateResult PoseFilter::update_height_agl(double height_agl, double variance, double gate_sigma,
                                                       bool terrain_moves) {
  Eigen::Matrix<double, 1, kSize> h = Eigen::Matrix<double, 1, kSize>::Zero();
  h(kDown) = -1.0;
  h(kTerrain) = 1.0;
  const double innovation = height_agl - (x_(kTerrain) - x_(kDown));
  const double s = (h * p_ * h.transpose())(0, 0) + variance;
  if (innovation * innovation > gate_sigma * gate_sigma * s) return UpdateResult::kRejected;
  // Only the vertical states take the correction; horizontal position and yaw
  // are not observable from a height above level ground.
  Vector k = p_ * h.transpose() / s;
  for (int i = 0; i < kSize; ++i) {
    if (i != kDown && (i != kTerrain || !terrain_moves)) k(i) = 0.0;
  }
  x_ += k * innovation;
  joseph_update(k, h, variance);
  return UpdateResult::kAccepted;
}

}  // namespace nadir
