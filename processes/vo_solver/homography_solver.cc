// Variant `homography`, after Caballero et al.: the ground patch induces a
// homography between the two images; its decomposition gives rotation, the
// plane normal and translation / plane distance, and the altimeter gives the
// scale. The INS is used only to pick the decomposition whose normal points
// down and to express the result in the level frame.

// Eigen must come before OpenCV's eigen.hpp (it checks).
#include <Eigen/Core>
// clang-format off
#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>
// clang-format on

#include <cmath>

#include "processes/vo_solver/plane_model.h"
#include "processes/vo_solver/solver_support.h"
#include "processes/vo_solver/translation_solver.h"

namespace nadir::vo {

Estimate solve_homography(const FramePair& pair, const SolverOptions& options) {
  Estimate est;
  if (!start_estimate(pair, &est)) return est;
  const size_t n = pair.prev_norm.size();
  std::vector<cv::Point2d> curr, prev;
  std::vector<int> index;
  for (size_t i = 0; i < n; ++i) {
    if (!pair.prev_norm[i].allFinite() || !pair.curr_norm[i].allFinite()) continue;
    curr.emplace_back(pair.curr_norm[i].x(), pair.curr_norm[i].y());
    prev.emplace_back(pair.prev_norm[i].x(), pair.prev_norm[i].y());
    index.push_back(static_cast<int>(i));
  }
  const Eigen::Matrix3d prev_level = level_from_camera(pair.prev_roll, pair.prev_pitch, pair.body_from_camera);
  const Eigen::Matrix3d curr_level = level_from_camera(pair.curr_roll, pair.curr_pitch, pair.body_from_camera);
  const Eigen::Vector3d beam_camera = (pair.body_from_camera.transpose() * pair.curr_beam_body).normalized();
  if (!(pair.curr_range_m > 0) || !std::isfinite(pair.curr_range_m) || !beam_camera.allFinite()) {
    est.quality |= kNoAltimeter;
    return est;
  }
  if (static_cast<int>(curr.size()) < std::max(options.min_features, 4)) {
    est.quality |= kTooFewFeatures;
    est.outliers = static_cast<int>(n);
    return est;
  }
  // Maps curr -> prev: X_prev = R X_curr + t with the plane n . X_curr = d in camera curr.
  std::vector<unsigned char> mask;
  const cv::Mat h = cv::findHomography(curr, prev, cv::RANSAC, options.homography_ransac_px * options.pixel_scale() / options.focal_px, mask,
                                       2000, 0.999);
  if (h.empty()) {
    est.quality |= kNotConverged;
    return est;
  }
  std::vector<cv::Mat> rotations, translations, normals;
  cv::decomposeHomographyMat(h, cv::Mat::eye(3, 3, CV_64F), rotations, translations, normals);
  const Eigen::Vector3d down_in_camera = curr_level.transpose() * Eigen::Vector3d::UnitZ();
  int best = -1;
  double best_dot = 0.0;
  for (size_t s = 0; s < normals.size(); ++s) {
    Eigen::Vector3d normal;
    cv::cv2eigen(normals[s], normal);
    if (normal.dot(beam_camera) <= 0) continue;  // the altimeter must hit the plane in front
    const double dot = normal.normalized().dot(down_in_camera);
    if (dot > best_dot) {
      best_dot = dot;
      best = static_cast<int>(s);
    }
  }
  if (best < 0) {
    est.quality |= kNotConverged;
    return est;
  }
  Eigen::Matrix3d rotation;
  Eigen::Vector3d translation_over_d, normal;
  cv::cv2eigen(rotations[best], rotation);
  cv::cv2eigen(translations[best], translation_over_d);
  cv::cv2eigen(normals[best], normal);
  normal.normalize();
  const double plane_distance = pair.curr_range_m * normal.dot(beam_camera);
  const Eigen::Vector3d translation_camera = translation_over_d * plane_distance;  // curr centre in prev camera
  est.translation = prev_level * translation_camera;
  const Eigen::Matrix3d level_rotation = prev_level * rotation * curr_level.transpose();
  est.dyaw = std::atan2(level_rotation(1, 0), level_rotation(0, 0));
  const Eigen::Vector3d level_normal = curr_level * normal;
  tilt_from_normal(level_normal, &est.ground_roll, &est.ground_pitch);
  est.altitude_m = prev_vertical_height(level_normal, plane_distance, est.dyaw, est.translation);
  est.iterations = 1;

  for (size_t j = 0; j < curr.size(); ++j) {
    if (mask[j]) est.weights[index[j]] = 1.0;
  }
  score_estimate(pair, options, std::max(options.min_features, 4), &est);
  // First-order spread only (diagonal): image noise over the inliers, scaled
  // to metres at the plane distance. Not a full homography covariance.
  const double sigma = est.residual_rms_px / options.focal_px;
  const double m = std::max(1, est.inliers);
  est.covariance.diagonal() << 2 * std::pow(plane_distance * sigma, 2) / m, 2 * std::pow(plane_distance * sigma, 2) / m,
      8 * std::pow(plane_distance * sigma, 2) / m, 2 * sigma * sigma / m, 8 * sigma * sigma / m, 8 * sigma * sigma / m;

  if (!est.translation.allFinite()) est.quality |= kNotConverged;
  return est;
}

}  // namespace nadir::vo
