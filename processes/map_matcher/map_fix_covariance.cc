#include "processes/map_matcher/map_fix_covariance.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>

#include "common/geometry.h"

namespace nadir {

bool map_fix_covariance(const MapMatcherOptions& options, const Registration& registration, int template_pixels,
                        double height_m, Eigen::Matrix2d* covariance_ne) {
  const Eigen::Matrix2d curvature = -registration.hessian;
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eigen(curvature);
  if (eigen.info() != Eigen::Success || !(eigen.eigenvalues().minCoeff() > 0.0)) return false;
  const double rho = std::clamp(registration.score, 1e-3, 1.0);
  const double samples = std::max(1.0, template_pixels / std::max(1.0, double(registration.lobe_pixels)));
  const double scale = options.peak_stddev_scale * options.peak_stddev_scale * (1.0 - rho) / rho / samples;
  // Per eigen-direction, floored.
  Eigen::Vector2d variances = eigen.eigenvalues().cwiseInverse() * scale;
  const double floor = options.min_stddev_px * options.min_stddev_px;
  variances = variances.cwiseMax(floor);
  const Eigen::Matrix2d px = eigen.eigenvectors() * variances.asDiagonal() * eigen.eigenvectors().transpose();
  // (col, row) = (east, south) -> (north, east).
  Eigen::Matrix2d turn;
  turn << 0.0, -1.0, 1.0, 0.0;
  const double gsd2 = options.gsd_m * options.gsd_m;
  const double attitude = height_m * deg_to_rad(std::max(options.attitude_stddev_deg, options.ins_attitude_stddev_deg));
  *covariance_ne = gsd2 * turn * px * turn.transpose() +
                   (options.map_stddev_m * options.map_stddev_m + attitude * attitude) * Eigen::Matrix2d::Identity();
  return true;
}

}  // namespace nadir
