#include "tools/eval/map_fix_metrics.h"

#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>

#include <algorithm>
#include <cmath>

#include "common/status.h"

namespace nadir {

MapFixMetrics map_fix_metrics(const std::vector<map_fix_t>& fixes, const std::vector<pose_t>& poses,
                              const std::vector<ground_truth_t>& truth, const pose_t& first, const TruthAt& truth0) {
  MapFixMetrics m;
  for (const pose_t& p : poses) {
    if (p.flags & pose_t::FLAG_MAP_FIX_APPLIED) ++m.applied;
    if (p.flags & pose_t::FLAG_MAP_FIX_REJECTED) ++m.rejected;
  }
  std::vector<float> errors, sigmas;
  for (const map_fix_t& f : fixes) {
    TruthAt t{};
    if (!truth_at(truth, f.utime, &t)) continue;
    const Eigen::Vector2d error(f.position_ne[0] - first.position_ned[0] - (t.position[0] - truth0.position[0]),
                                f.position_ne[1] - first.position_ned[1] - (t.position[1] - truth0.position[1]));
    Eigen::Matrix2d cov;
    cov << f.covariance_ne[0][0], f.covariance_ne[0][1], f.covariance_ne[1][0], f.covariance_ne[1][1];
    const double mahalanobis = std::sqrt(std::max(0.0, error.dot(cov.inverse() * error)));
    ++m.fixes;
    errors.push_back(static_cast<float>(error.norm()));
    sigmas.push_back(static_cast<float>(
        std::sqrt(std::max(0.0, Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(cov).eigenvalues().maxCoeff()))));
    m.mahalanobis_max = std::max(m.mahalanobis_max, mahalanobis);
    if (mahalanobis > 3.0) ++m.beyond_3_sigma;
  }
  if (!errors.empty()) {
    m.error_median_m = percentile(errors, 50);
    m.error_p95_m = percentile(errors, 95);
    m.error_max_m = percentile(errors, 100);
    m.sigma_median_m = percentile(sigmas, 50);
  }
  return m;
}

}  // namespace nadir
