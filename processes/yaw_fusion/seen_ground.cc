#include "processes/yaw_fusion/seen_ground.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <utility>
#include <vector>

namespace nadir {

namespace {
// Depth sigmas below this are not believed (float rounding, a track at the
// end of a long baseline): no single point outweighs the rest.
constexpr double kMinPointSigmaM = 0.1;
}  // namespace

void SeenGround::note_frame(const ground_points_t& points, const Eigen::Vector3d& position, double yaw) {
  const double c = std::cos(yaw), s = std::sin(yaw);
  const size_t n = std::min({static_cast<size_t>(std::max(0, points.num_points)), points.track_id.size(),
                             points.position_m.size(), points.depth_sigma_m.size()});
  for (size_t i = 0; i < n; ++i) {
    const double x = points.position_m[i][0], y = points.position_m[i][1], z = points.position_m[i][2];
    const double sigma = std::max<double>(points.depth_sigma_m[i], kMinPointSigmaM);
    const Point p{{position.x() + c * x - s * y, position.y() + s * x + c * y}, position.z() + z, sigma * sigma,
                  points.utime};
    if (p.horizontal.allFinite() && std::isfinite(p.down) && std::isfinite(p.variance)) {
      points_[points.track_id[i]] = p;
    }
  }
  note_frame_without_points(points.utime);
}

void SeenGround::note_frame_without_points(int64_t utime) {
  for (auto it = points_.begin(); it != points_.end();) {
    it = utime - it->second.utime > window_us_ ? points_.erase(it) : std::next(it);
  }
}

std::optional<SeenGround::Height> SeenGround::ground_down(const Eigen::Vector2d& horizontal,
                                                          const SeenGroundOptions& options) const {
  // Weighted least squares: down = a + b dn + c de about the query position.
  Eigen::Matrix3d normal = Eigen::Matrix3d::Zero();
  Eigen::Vector3d rhs = Eigen::Vector3d::Zero();
  double weights = 0.0;
  const double r2 = options.radius_m * options.radius_m;
  auto near = [&](const Point& p) { return (p.horizontal - horizontal).squaredNorm() <= r2; };
  // In track id order: the sums do not depend on the hash table's layout.
  std::vector<std::pair<int64_t, const Point*>> used;
  for (const auto& [id, p] : points_) {
    if (near(p)) used.emplace_back(id, &p);
  }
  std::sort(used.begin(), used.end());
  for (const auto& [id, q] : used) {
    const Point& p = *q;
    const Eigen::Vector2d d = p.horizontal - horizontal;
    const double w = 1.0 / p.variance;
    const Eigen::Vector3d row(1.0, d.x(), d.y());
    normal += w * row * row.transpose();
    rhs += w * p.down * row;
    weights += w;
  }
  const int n = static_cast<int>(used.size());
  if (n < std::max(3, options.min_points)) return std::nullopt;
  // The points must lie around the position, not only on one side of it (the
  // edge of what the frames saw), where the plane would be extrapolated. Their
  // plain centroid: the weights grow toward the frames' older, better tracks.
  Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
  for (const auto& [id, q] : used) centroid += q->horizontal - horizontal;
  centroid /= static_cast<double>(n);
  if (centroid.norm() > options.max_centroid_offset * options.radius_m) return std::nullopt;
  // A plane needs the points to span the area (not one line of them): the
  // smallest eigenvalue of their (weighted) position spread, against the radius.
  const Eigen::Matrix3d spread = normal / weights;
  const Eigen::Vector2d mean = spread.block<2, 1>(1, 0);
  const Eigen::Matrix2d position_cov = spread.block<2, 2>(1, 1) - mean * mean.transpose();
  if (Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(position_cov).eigenvalues()(0) < 0.01 * r2) return std::nullopt;
  const Eigen::LDLT<Eigen::Matrix3d> ldlt = normal.ldlt();
  const Eigen::Vector3d coef = ldlt.solve(rhs);
  // Of the plane's value here, with the points' variances as reported.
  const double fit_variance = ldlt.solve(Eigen::Vector3d::UnitX())(0);
  constexpr int parameters = 3;
  // Scatter of the points about the fit against their reported variances:
  // noise and the ground's roughness about the plane together.
  double chi2 = 0.0;
  for (const auto& [id, q] : used) {
    const Point& p = *q;
    const Eigen::Vector2d d = p.horizontal - horizontal;
    const double e = p.down - coef.dot(Eigen::Vector3d(1.0, d.x(), d.y()));
    chi2 += e * e / p.variance;
  }
  const double reduced = n > parameters ? chi2 / (n - parameters) : 1.0;
  const double point_variance = n / weights;  // the points' harmonic mean variance
  Height out;
  out.points = n;
  out.down = coef(0);
  // The fit, scaled by the scatter when it exceeds the reported noise, and the
  // ground under the beam off the plane by what the scatter holds beyond that noise.
  out.variance = fit_variance * std::max(1.0, reduced) + std::max(0.0, (reduced - 1.0) * point_variance);
  return out;
}

}  // namespace nadir
