#include "processes/vo_solver/solver_support.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

namespace nadir::vo {

bool start_estimate(const FramePair& pair, Estimate* est) {
  est->weights.assign(pair.prev_norm.size(), 0.0);
  if (pair.curr_norm.size() == pair.prev_norm.size()) return true;
  est->quality |= kTooFewFeatures;
  return false;
}

double median_of(const std::vector<double>& values) {
  if (values.empty()) return 0.0;
  std::vector<double> copy(values);
  const size_t mid = copy.size() / 2;
  std::nth_element(copy.begin(), copy.begin() + static_cast<long>(mid), copy.end());
  return copy[mid];
}

double robust_cut_px(double mad_scale, double min_threshold_px, const std::vector<double>& errors) {
  return std::max(min_threshold_px, mad_scale * 1.4826 * median_of(errors));
}

}  // namespace nadir::vo

namespace nadir::vo {

Eigen::Matrix3d ground_relevel(const PlaneGeometry& plane, double d_roll, double d_pitch) {
  const Eigen::Matrix3d increment = (Eigen::AngleAxisd(d_pitch, Eigen::Vector3d::UnitY()) *
                                     Eigen::AngleAxisd(d_roll, Eigen::Vector3d::UnitX()))
                                        .toRotationMatrix();
  return plane.relevel * increment;
}

}  // namespace nadir::vo

namespace nadir::vo {

double prev_vertical_height(const Eigen::Vector3d& normal, double plane_offset, double dyaw,
                            const Eigen::Vector3d& translation) {
  const Eigen::Vector3d prev_camera = -rot_z(dyaw).transpose() * translation;
  return (plane_offset - normal.dot(prev_camera)) / normal.z();
}

}  // namespace nadir::vo

namespace nadir::vo {

double image_error_px(const Eigen::Vector3d& in_prev_camera, const Eigen::Vector2d& measured, double focal_px) {
  if (!(in_prev_camera.z() > 1e-9)) return std::numeric_limits<double>::infinity();
  return focal_px * (in_prev_camera.head<2>() / in_prev_camera.z() - measured).norm();
}

std::vector<double> estimate_reprojection_errors(const FramePair& pair, const Estimate& est, double focal_px,
                                                 std::vector<double>* depth_offsets) {
  const Eigen::Matrix3d identity = Eigen::Matrix3d::Identity();
  const Eigen::Matrix3d prev_camera_from_level =
      level_from_camera(pair.prev_roll, pair.prev_pitch, pair.body_from_camera).transpose();
  const Eigen::Matrix3d curr_level_from_camera =
      level_from_camera(pair.curr_roll, pair.curr_pitch, pair.body_from_camera);
  const Eigen::Matrix3d curr_level_from_body = level_from_camera(pair.curr_roll, pair.curr_pitch, identity);
  const Eigen::Vector3d spot = pair.curr_range_m * (curr_level_from_body * pair.curr_beam_body).normalized();
  const Eigen::Vector3d normal = normal_from_tilt(est.ground_roll, est.ground_pitch);
  const double offset = normal.dot(spot);
  const Eigen::Matrix3d rotation = prev_camera_from_level * curr_from_prev(est).transpose();
  const Eigen::Vector3d shift = prev_camera_from_level * est.translation;
  std::vector<double> errors(pair.prev_norm.size(), std::numeric_limits<double>::infinity());
  if (depth_offsets) depth_offsets->assign(errors.size(), std::numeric_limits<double>::quiet_NaN());
  for (size_t i = 0; i < errors.size() && i < pair.curr_norm.size(); ++i) {
    const Eigen::Vector3d ray = curr_level_from_camera * pair.curr_norm[i].homogeneous();
    const double along = normal.dot(ray);
    if (!(std::abs(along) > 1e-12) || !(offset / along > 0)) continue;
    const double depth = offset / along;
    const double e = image_error_px(rotation * (depth * ray) + shift, pair.prev_norm[i], focal_px);
    if (std::isfinite(e)) errors[i] = e;
    if (!depth_offsets) continue;
    // Depth along the curr ray triangulated with the prev ray: u x (mu R v + shift) = 0.
    const Eigen::Vector3d u = pair.prev_norm[i].homogeneous();
    const Eigen::Vector3d a = u.cross(rotation * ray);
    const double aa = a.squaredNorm();
    (*depth_offsets)[i] = aa > 0 ? -a.dot(u.cross(shift)) / aa / depth - 1.0 : std::numeric_limits<double>::quiet_NaN();
  }
  return errors;
}

void score_estimate(const FramePair& pair, const SolverOptions& options, int min_inliers, Estimate* est) {
  std::vector<double> depth_offsets, inlier_offsets;
  const std::vector<double> errors = estimate_reprojection_errors(pair, *est, options.focal_px, &depth_offsets);
  double sum_sq = 0;
  est->inliers = 0;
  for (size_t i = 0; i < errors.size(); ++i) {
    if (!(est->weights[i] > 0)) continue;
    ++est->inliers;
    sum_sq += errors[i] * errors[i];
    inlier_offsets.push_back(depth_offsets[i]);
  }
  if (split_into_depth_layers(std::move(inlier_offsets), options.layers)) est->quality |= kDepthLayers;
  const int n = static_cast<int>(errors.size());
  est->outliers = n - est->inliers;
  est->residual_rms_px = est->inliers > 0 ? std::sqrt(sum_sq / est->inliers) : 0.0;
  if (est->inliers < min_inliers) est->quality |= kTooFewFeatures;
  if (!(est->residual_rms_px <= options.max_residual_rms_px * options.pixel_scale()) || est->inliers < options.min_inlier_fraction * n) {
    est->quality |= kHighResidual;
  }
}

}  // namespace nadir::vo
