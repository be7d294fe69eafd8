#include "processes/vo_solver/delta_uncertainty.h"

#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "common/geometry.h"

namespace nadir::vo {

namespace {

// Variance in rad^2 of a standard deviation given in degrees.
double variance_rad2(double stddev_deg) { return deg_to_rad(stddev_deg) * deg_to_rad(stddev_deg); }

// Rotation level frame <- camera at this roll/pitch (the yaw is the level frame's own).
Eigen::Matrix3d level_rotation(double roll, double pitch, const Eigen::Matrix3d& body_from_camera) {
  return rotation_from_rpy(roll, pitch, 0.0) * body_from_camera;
}

// Vertical component of the levelled altimeter beam.
double beam_down(double roll, double pitch, const Eigen::Vector3d& beam_body) {
  return (rotation_from_rpy(roll, pitch, 0.0) * beam_body.normalized()).z();
}

struct Fit {
  Eigen::Vector2d translation = Eigen::Vector2d::Zero();
  double dyaw = 0;
  double dz = 0;
};

// Ground points (z = height, level frame of side a) fitted by side b's
// levelled rays per unit height: P_xy = t + lambda Rz(psi) q, closed form.
Fit fit_similarity(const std::vector<Eigen::Vector3d>& points_a, double height_a,
                   const std::vector<Eigen::Vector2d>& per_unit_height_b) {
  const int n = static_cast<int>(points_a.size());
  Eigen::Vector2d mean_p = Eigen::Vector2d::Zero(), mean_q = Eigen::Vector2d::Zero();
  for (int i = 0; i < n; ++i) {
    mean_p += points_a[i].head<2>();
    mean_q += per_unit_height_b[i];
  }
  mean_p /= n;
  mean_q /= n;
  double dot = 0, cross = 0, qq = 0;
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector2d p = points_a[i].head<2>() - mean_p;
    const Eigen::Vector2d q = per_unit_height_b[i] - mean_q;
    dot += q.dot(p);
    cross += q.x() * p.y() - q.y() * p.x();
    qq += q.squaredNorm();
  }
  Fit fit;
  fit.dyaw = std::atan2(cross, dot);
  const double lambda = std::hypot(dot, cross) / qq;  // height of side b above the plane
  const double c = std::cos(fit.dyaw), s = std::sin(fit.dyaw);
  fit.translation = mean_p - lambda * Eigen::Vector2d(c * mean_q.x() - s * mean_q.y(), s * mean_q.x() + c * mean_q.y());
  fit.dz = height_a - lambda;
  return fit;
}

// Side a's rays (camera frame) on the plane `height` below it, levelled by `level_a`.
std::vector<Eigen::Vector3d> ground_points(const std::vector<Eigen::Vector3d>& rays, const Eigen::Matrix3d& level_a,
                                           double height) {
  std::vector<Eigen::Vector3d> points;
  points.reserve(rays.size());
  for (const Eigen::Vector3d& r : rays) {
    const Eigen::Vector3d d = level_a * r;
    points.push_back(d * (height / d.z()));
  }
  return points;
}

std::vector<Eigen::Vector2d> per_unit_height(const std::vector<Eigen::Vector3d>& rays, const Eigen::Matrix3d& level_b) {
  std::vector<Eigen::Vector2d> q;
  q.reserve(rays.size());
  for (const Eigen::Vector3d& r : rays) {
    const Eigen::Vector3d d = level_b * r;
    q.emplace_back(d.x() / d.z(), d.y() / d.z());
  }
  return q;
}

// The nominal scene of an estimate: prev camera rays of a 3 x 3 image grid
// (normalized +-0.15: near the nadir, where a tilt error shifts the ground
// by the height times the angle, as the solver's tilt-fitted plane does) and the curr camera's
// rays to the same ground points.
struct Scene {
  std::vector<Eigen::Vector3d> prev_rays, curr_rays;
  double prev_height = 0, curr_height = 0;
};

Scene nominal_scene(const FramePair& pair, const Estimate& est) {
  Scene scene;
  const Eigen::Matrix3d prev_level = level_rotation(pair.prev_roll, pair.prev_pitch, pair.body_from_camera);
  const Eigen::Matrix3d curr_level = level_rotation(pair.curr_roll, pair.curr_pitch, pair.body_from_camera);
  scene.prev_height = est.altitude_m > 0 ? est.altitude_m
                                         : pair.prev_range_m * beam_down(pair.prev_roll, pair.prev_pitch,
                                                                         pair.prev_beam_body);
  scene.curr_height = scene.prev_height - est.translation.z();
  const double c = std::cos(est.dyaw), s = std::sin(est.dyaw);
  Eigen::Matrix3d rz;
  rz << c, -s, 0, s, c, 0, 0, 0, 1;
  for (double v : {-0.15, 0.0, 0.15}) {
    for (double u : {-0.15, 0.0, 0.15}) {
      const Eigen::Vector3d ray(u, v, 1.0);
      const Eigen::Vector3d d = prev_level * ray;
      if (!(d.z() > 0.05)) continue;  // not towards the ground
      const Eigen::Vector3d ground = d * (scene.prev_height / d.z());
      // X_prev = Rz(dyaw) X_curr + t  =>  X_curr = Rz(dyaw)^T (X_prev - t).
      const Eigen::Vector3d in_curr_level = rz.transpose() * (ground - est.translation);
      if (!(in_curr_level.z() > 0.05 * scene.curr_height)) continue;
      scene.prev_rays.push_back(ray);
      scene.curr_rays.push_back(curr_level.transpose() * in_curr_level);
    }
  }
  return scene;
}

}  // namespace

SensorVector measured_inputs(const FramePair& pair) {
  SensorVector x;
  x << pair.prev_roll, pair.prev_pitch, pair.curr_roll, pair.curr_pitch, pair.prev_range_m, pair.curr_range_m, 0.0;
  return x;
}

Eigen::Vector4d delta_model(const FramePair& pair, const Estimate& est, bool symmetric_dz,
                            const SensorVector& inputs) {
  const Scene scene = nominal_scene(pair, est);
  if (scene.prev_rays.size() < 3) return Eigen::Vector4d::Constant(std::nan(""));
  const SensorVector nominal = measured_inputs(pair);
  const double scale = 1.0 + inputs(kRangeScale);
  // Heights as the altimeter gives them, relative to the nominal scene's.
  const double prev_height =
      scene.prev_height * (inputs(kPrevRange) * scale * beam_down(inputs(kPrevRoll), inputs(kPrevPitch),
                                                                  pair.prev_beam_body)) /
      (nominal(kPrevRange) * beam_down(nominal(kPrevRoll), nominal(kPrevPitch), pair.prev_beam_body));
  const double curr_height =
      scene.curr_height * (inputs(kCurrRange) * scale * beam_down(inputs(kCurrRoll), inputs(kCurrPitch),
                                                                  pair.curr_beam_body)) /
      (nominal(kCurrRange) * beam_down(nominal(kCurrRoll), nominal(kCurrPitch), pair.curr_beam_body));
  const Eigen::Matrix3d prev_level = level_rotation(inputs(kPrevRoll), inputs(kPrevPitch), pair.body_from_camera);
  const Eigen::Matrix3d curr_level = level_rotation(inputs(kCurrRoll), inputs(kCurrPitch), pair.body_from_camera);
  // As the solver: the plane passes through curr's altimeter point and prev's
  // rays are fitted to it; the fit gives X_curr = t' + Rz(psi') X_prev.
  const Fit on_curr = fit_similarity(ground_points(scene.curr_rays, curr_level, curr_height), curr_height,
                                     per_unit_height(scene.prev_rays, prev_level));
  // Inverted: X_prev = Rz(-psi') (X_curr - t'); prev is lambda = curr_height + dz' above the plane.
  const double dyaw = -on_curr.dyaw;
  const double c = std::cos(dyaw), s = std::sin(dyaw);
  const Eigen::Vector2d t(-(c * on_curr.translation.x() - s * on_curr.translation.y()),
                          -(s * on_curr.translation.x() + c * on_curr.translation.y()));
  double dz = -on_curr.dz;  // prev height - curr height
  if (symmetric_dz) {
    // The time-reversed solve: the plane through prev's altimeter point, curr's rays fitted to it.
    const Fit on_prev = fit_similarity(ground_points(scene.prev_rays, prev_level, prev_height), prev_height,
                                       per_unit_height(scene.curr_rays, curr_level));
    dz = 0.5 * (dz + on_prev.dz);
  }
  return Eigen::Vector4d(t.x(), t.y(), dz, dyaw);
}

SensorJacobian sensor_jacobian(const FramePair& pair, const Estimate& est, bool symmetric_dz) {
  const SensorVector x0 = measured_inputs(pair);
  SensorJacobian j;
  for (int k = 0; k < kSensorInputs; ++k) {
    // Angles and the scale in radians / fractions; ranges relative to their size.
    const double step = (k == kPrevRange || k == kCurrRange) ? 1e-4 * std::max(1.0, std::abs(x0(k))) : 1e-5;
    SensorVector plus = x0, minus = x0;
    plus(k) += step;
    minus(k) -= step;
    Eigen::Vector4d diff = delta_model(pair, est, symmetric_dz, plus) - delta_model(pair, est, symmetric_dz, minus);
    diff(3) = wrap_angle(diff(3));
    j.col(k) = diff / (2 * step);
  }
  return j;
}

Eigen::Matrix<double, kSensorInputs, kSensorInputs> sensor_input_covariance(const FramePair& pair,
                                                                             const UncertaintyOptions& options) {
  const double prev_rp = std::pow(options.frame_roll_pitch_stddev_rad(pair.prev_attitude_noise_share), 2);
  const double curr_rp = std::pow(options.frame_roll_pitch_stddev_rad(pair.curr_attitude_noise_share), 2);
  Eigen::Matrix<double, kSensorInputs, 1> variance;
  const double sp = options.range_stddev(pair.prev_range_m), sc = options.range_stddev(pair.curr_range_m);
  variance << prev_rp, prev_rp, curr_rp, curr_rp, sp * sp, sc * sc,
      options.range_scale_stddev * options.range_scale_stddev;
  return variance.asDiagonal();
}

double relief_along_variance_per_m(const Estimate& est, Variant variant, const UncertaintyOptions& options) {
  if (variant != Variant::kFeatureDepth) return 0.0;
  const double v = options.feature_depth_relief_heights * est.anchor_model_variance * est.altitude_m;
  return std::isfinite(v) && v > 0.0 ? v : 0.0;
}

Eigen::Matrix2d relief_walk_covariance(const Eigen::Vector2d& step, Variant variant,
                                       const UncertaintyOptions& options, double relief_along_m2_per_m) {
  const double length = step.norm();
  if (!(length > 0.0) || !std::isfinite(length)) return Eigen::Matrix2d::Zero();
  const Eigen::Vector2d along = step / length;
  const Eigen::Matrix2d along_part = along * along.transpose();
  const bool own_depths = variant == Variant::kFeatureDepth;
  const double a = own_depths ? options.feature_depth_walk_along_m_per_sqrt_m : options.relief_walk_along_m_per_sqrt_m;
  const double c =
      own_depths ? options.feature_depth_walk_across_m_per_sqrt_m : options.relief_walk_across_m_per_sqrt_m;
  return length * ((a * a + relief_along_m2_per_m) * along_part + c * c * (Eigen::Matrix2d::Identity() - along_part));
}

Eigen::Matrix4d sensor_covariance(const FramePair& pair, const Estimate& est, const SolverOptions& solver,
                                  const UncertaintyOptions& options) {
  if (!options.enabled || !est.translation.allFinite() || !std::isfinite(est.dyaw)) return Eigen::Matrix4d::Zero();
  const bool symmetric = solver.symmetric_dz && (solver.variant == Variant::kPaper ||
                                                 solver.variant == Variant::kLevelGround);
  // dz's response to levelling errors is under-predicted (the model has no
  // ground tilt fit; the solver's dz moves ~2.5x more): a known gap, dz is not
  // part of the horizontal protection level.
  SensorJacobian j = sensor_jacobian(pair, est, symmetric);
  if (!j.allFinite()) return Eigen::Matrix4d::Zero();
  // dx, dy against the attitudes: the analytic h * eps per frame instead of
  // the model's (whose grid adds ~1 % of perspective the solver's tilt fit
  // does not have), so that yaw fusion removes exactly what is added here.
  j.block<2, 4>(0, kPrevRoll).setZero();
  // dyaw against the attitudes: each frame's heading term (levelling_yaw_variance_rad2).
  j.block<1, 4>(3, kPrevRoll).setZero();
  Eigen::Matrix4d cov = j * sensor_input_covariance(pair, options) * j.transpose();
  const double prev_rp = options.frame_roll_pitch_stddev_rad(pair.prev_attitude_noise_share);
  const double curr_rp = options.frame_roll_pitch_stddev_rad(pair.curr_attitude_noise_share);
  double prev_levelling = 0, curr_levelling = 0;
  frame_levelling_variances(est.altitude_m, est.translation.z(), prev_rp, curr_rp, &prev_levelling, &curr_levelling);
  cov(0, 0) += prev_levelling + curr_levelling;
  cov(1, 1) += prev_levelling + curr_levelling;
  cov(3, 3) += levelling_yaw_variance_rad2(pair.prev_pitch, prev_rp) + levelling_yaw_variance_rad2(pair.curr_pitch, curr_rp);
  // `flow` takes its heading change from the INS: both frames' yaw noise.
  if (solver.variant == Variant::kFlow) cov(3, 3) += 2 * variance_rad2(options.yaw_stddev_deg);
  // A feature_depth pair its own depths did not solve (the first pairs of a
  // track set, too few depths near the beam) is the one-plane solve's, with
  // its model error.
  const Variant solved_by =
      solver.variant == Variant::kFeatureDepth && !est.own_depths_used ? Variant::kPaper : solver.variant;
  cov.topLeftCorner<2, 2>() += relief_walk_covariance(est.translation.head<2>(), solved_by, options,
                                                      relief_along_variance_per_m(est, solved_by, options));
  cov(3, 3) += variance_rad2(options.dyaw_model_stddev_deg);
  return 0.5 * (cov + cov.transpose());
}

void add_sensor_uncertainty(const FramePair& pair, const SolverOptions& solver, const UncertaintyOptions& options,
                            Estimate* est) {
  est->covariance.topLeftCorner<4, 4>() += sensor_covariance(pair, *est, solver, options);
}

}  // namespace nadir::vo
