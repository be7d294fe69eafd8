#include "tools/eval/map_fix_metrics.h"

#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <stdexcept>

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
    MapFixRow row;
    row.utime = f.utime;
    row.error_north_m = error.x();
    row.error_east_m = error.y();
    row.sigma_north_m = std::sqrt(std::max(0.0, cov(0, 0)));
    row.sigma_east_m = std::sqrt(std::max(0.0, cov(1, 1)));
    row.mahalanobis = mahalanobis;
    row.score = f.score;
    row.peak_ratio = f.peak_ratio;
    row.search_radius_m = f.search_radius_m;
    row.gsd_m = f.gsd_m;
    m.rows.push_back(row);
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

void write_map_fixes_csv(const MapFixMetrics& m, const std::string& path) {
  if (m.rows.empty()) return;
  std::ofstream out(path);
  out << "utime,error_north_m,error_east_m,sigma_north_m,sigma_east_m,mahalanobis,score,peak_ratio,search_radius_m,"
         "gsd_m\n";
  char line[256];
  for (const MapFixRow& r : m.rows) {
    std::snprintf(line, sizeof(line), "%lld,%.3f,%.3f,%.3f,%.3f,%.3f,%.4f,%.3f,%.2f,%.2f\n",
                  static_cast<long long>(r.utime), r.error_north_m, r.error_east_m, r.sigma_north_m, r.sigma_east_m,
                  r.mahalanobis, r.score, r.peak_ratio, r.search_radius_m, r.gsd_m);
    out << line;
  }
  if (!out.flush()) throw std::runtime_error(path + ": write failed");
}

}  // namespace nadir
