#include "tools/calibrate/gps_scale.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "common/robust_stats.h"

namespace nadir::calibrate {
namespace {

// Linear interpolation of the positions at utime; false outside their span.
bool position_at(const std::vector<PositionSample>& positions, int64_t utime, Eigen::Vector3d* out) {
  if (positions.empty() || utime < positions.front().utime || utime > positions.back().utime) return false;
  const auto after = std::lower_bound(positions.begin(), positions.end(), utime,
                                      [](const PositionSample& s, int64_t t) { return s.utime < t; });
  if (after->utime == utime || after == positions.begin()) {
    *out = after->position_ned;
    return true;
  }
  const auto before = after - 1;
  const double a = static_cast<double>(utime - before->utime) / static_cast<double>(after->utime - before->utime);
  *out = (1.0 - a) * before->position_ned + a * after->position_ned;
  return true;
}

}  // namespace

GpsScaleFit fit_gps_scale(const std::vector<VoStep>& steps, const std::vector<PositionSample>& positions,
                          int32_t unsolved_mask, double min_baseline_m, double outlier_sigma) {
  GpsScaleFit fit;
  std::vector<double> log_ratio;
  for (const VoStep& s : steps) {
    if ((s.quality & unsolved_mask) != 0) continue;
    Eigen::Vector3d a, b;
    if (!position_at(positions, s.prev_utime, &a) || !position_at(positions, s.utime, &b)) continue;
    const double gnss = std::hypot(b.x() - a.x(), b.y() - a.y());
    const double vo = std::hypot(s.dx, s.dy);
    if (gnss < min_baseline_m || !(vo > 0.0) || !std::isfinite(vo)) {
      ++fit.rejected;
      continue;
    }
    log_ratio.push_back(std::log(gnss / vo));
  }
  if (log_ratio.empty()) return fit;
  // Median of the log ratio (a scale error is multiplicative), robust spread
  // from the median absolute deviation, outliers (mismatched pairs) dropped.
  double centre = median(log_ratio);
  const double spread = mad_sigma(log_ratio);
  std::vector<double> kept;
  for (double r : log_ratio)
    if (spread == 0.0 || std::fabs(r - centre) <= outlier_sigma * spread) kept.push_back(r);
  fit.rejected += static_cast<int64_t>(log_ratio.size() - kept.size());
  centre = median(kept);
  fit.pairs = static_cast<int64_t>(kept.size());
  fit.scale = std::exp(centre);
  // The median's standard error is sqrt(pi/2) times the mean's.
  fit.sigma = fit.scale * 1.2533 * spread / std::sqrt(static_cast<double>(kept.size()));
  return fit;
}

}  // namespace nadir::calibrate
