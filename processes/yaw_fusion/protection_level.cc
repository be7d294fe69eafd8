#include "processes/yaw_fusion/protection_level.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>

namespace nadir {

double ProtectionLevelOptions::sigma_factor() const { return std::sqrt(-2.0 * std::log(1.0 - probability)); }

double horizontal_protection_level(const Eigen::Matrix2d& horizontal_covariance, int32_t flags,
                                   const ProtectionLevelOptions& options) {
  if (flags & kProtectionLevelUnavailableFlags) return -1.0;
  if (!horizontal_covariance.allFinite()) return -1.0;
  const Eigen::Matrix2d sym = 0.5 * (horizontal_covariance + horizontal_covariance.transpose());
  const double largest = std::max(0.0, Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(sym).eigenvalues().maxCoeff());
  double level = options.sigma_factor() * std::sqrt(largest);
  if (flags & kProtectionLevelInflatingFlags) level *= options.flagged_inflation;
  return level;
}

}  // namespace nadir
