// Variant `flow`, as PX4Flow does it: de-rotate the image motion with the INS
// attitude (roll, pitch of each frame and the INS heading change), take the
// mean flow and scale it by the altitude. The ground is assumed level; the two
// altimeter heights are used so that a climb does not bias the flow.

#include <algorithm>
#include <cmath>

#include "common/geometry.h"
#include "processes/vo_solver/plane_model.h"
#include "processes/vo_solver/solver_support.h"
#include "processes/vo_solver/translation_solver.h"

namespace nadir::vo {

Estimate solve_flow(const FramePair& pair, const SolverOptions& options) {
  Estimate est;
  if (!start_estimate(pair, &est)) return est;
  const size_t n = pair.prev_norm.size();
  const Eigen::Matrix3d prev_level = level_from_camera(pair.prev_roll, pair.prev_pitch, pair.body_from_camera);
  const Eigen::Matrix3d curr_level = level_from_camera(pair.curr_roll, pair.curr_pitch, pair.body_from_camera);
  // Vertical heights: slant range times the down component of the levelled beam.
  const Eigen::Matrix3d identity = Eigen::Matrix3d::Identity();
  const Eigen::Vector3d prev_beam = level_from_camera(pair.prev_roll, pair.prev_pitch, identity) * pair.prev_beam_body;
  const Eigen::Vector3d curr_beam = level_from_camera(pair.curr_roll, pair.curr_pitch, identity) * pair.curr_beam_body;
  const double prev_height = pair.prev_range_m * prev_beam.normalized().z();
  const double curr_height = pair.curr_range_m * curr_beam.normalized().z();
  if (!(prev_height > 0) || !(curr_height > 0) || !std::isfinite(prev_height) || !std::isfinite(curr_height)) {
    est.quality |= kNoAltimeter;
    return est;
  }
  const double dyaw = angle_difference(pair.curr_yaw, pair.prev_yaw);
  const Eigen::Matrix3d derotate = rot_z(dyaw) * curr_level;
  // Per feature: the horizontal motion it implies, H_prev u - H_curr Rz v (level ground).
  std::vector<Eigen::Vector2d> motion;
  std::vector<int> index;
  for (size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d u = prev_level * pair.prev_norm[i].homogeneous();
    const Eigen::Vector3d v = derotate * pair.curr_norm[i].homogeneous();
    if (!u.allFinite() || !v.allFinite() || u.z() < 1e-6 || v.z() < 1e-6) continue;
    motion.push_back(prev_height * u.head<2>() / u.z() - curr_height * v.head<2>() / v.z());
    index.push_back(static_cast<int>(i));
  }
  if (static_cast<int>(motion.size()) < options.min_features) {
    est.quality |= kTooFewFeatures;
    est.outliers = static_cast<int>(n);
    return est;
  }
  // Robust mean: reject features far from the component-wise median, then average.
  std::vector<double> xs, ys, deviation;
  for (const auto& t : motion) {
    xs.push_back(t.x());
    ys.push_back(t.y());
  }
  const Eigen::Vector2d median(median_of(xs), median_of(ys));
  for (const auto& t : motion) deviation.push_back((t - median).norm());
  const double metres_per_px = prev_height / options.focal_px;
  const double threshold = std::max(options.min_threshold_px * options.pixel_scale() * metres_per_px,
                                    options.threshold_mad_scale * 1.4826 * median_of(deviation));
  Eigen::Vector2d sum = Eigen::Vector2d::Zero();
  int used = 0;
  for (size_t j = 0; j < motion.size(); ++j) {
    if (deviation[j] > threshold) continue;
    sum += motion[j];
    est.weights[index[j]] = 1.0;
    ++used;
  }
  if (used == 0) {
    est.quality |= kTooFewFeatures;
    est.outliers = static_cast<int>(n);
    return est;
  }
  const Eigen::Vector2d mean = sum / used;
  double sum_sq = 0;
  for (size_t j = 0; j < motion.size(); ++j) {
    if (est.weights[index[j]] > 0) sum_sq += (motion[j] - mean).squaredNorm();
  }
  est.translation = Eigen::Vector3d(mean.x(), mean.y(), prev_height - curr_height);
  est.dyaw = dyaw;
  est.altitude_m = prev_height;
  est.iterations = 1;
  score_estimate(pair, options, options.min_features, &est);
  const double var_xy = sum_sq / (2.0 * used) / std::max(1, used - 1);
  // dyaw and dz come from the INS and altimeter, not from the images; their
  // variances here are nominal (1 mrad, 0.1 m), the ground tilt is assumed 0.
  est.covariance.diagonal() << var_xy, var_xy, 0.01, 1e-6, 0.0, 0.0;
  return est;
}

}  // namespace nadir::vo
