#include "tools/calibrate/gps_scale.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "common/robust_stats.h"

namespace nadir::calibrate {
namespace {

// Linear interpolation of the positions (and the yaw, along the shorter way)
// at utime; false outside their span.
bool position_at(const std::vector<PositionSample>& positions, int64_t utime, Eigen::Vector3d* out,
                 double* yaw = nullptr) {
  if (positions.empty() || utime < positions.front().utime || utime > positions.back().utime) return false;
  const auto after = std::lower_bound(positions.begin(), positions.end(), utime,
                                      [](const PositionSample& s, int64_t t) { return s.utime < t; });
  if (after->utime == utime || after == positions.begin()) {
    *out = after->position_ned;
    if (yaw) *yaw = after->yaw;
    return true;
  }
  const auto before = after - 1;
  const double a = static_cast<double>(utime - before->utime) / static_cast<double>(after->utime - before->utime);
  *out = (1.0 - a) * before->position_ned + a * after->position_ned;
  if (yaw) *yaw = before->yaw + a * std::remainder(after->yaw - before->yaw, 2.0 * M_PI);
  return true;
}

// Median of `values` after dropping those beyond outlier_sigma robust sigmas
// of the first median; the kept values' robust spread.
struct RobustCentre {
  double centre = 0.0, spread = 0.0;
  int64_t kept = 0, dropped = 0;
};
RobustCentre robust_centre(const std::vector<double>& values, double outlier_sigma) {
  RobustCentre r;
  double centre = median(values);
  const double spread = mad_sigma(values);
  std::vector<double> kept;
  for (double v : values)
    if (spread == 0.0 || std::fabs(v - centre) <= outlier_sigma * spread) kept.push_back(v);
  r.dropped = static_cast<int64_t>(values.size() - kept.size());
  r.kept = static_cast<int64_t>(kept.size());
  r.centre = median(kept);
  r.spread = spread;
  return r;
}

// The median's standard error is sqrt(pi/2) times the mean's.
constexpr double kMedianEfficiency = 1.2533;

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
  const RobustCentre c = robust_centre(log_ratio, outlier_sigma);
  fit.rejected += c.dropped;
  fit.pairs = c.kept;
  fit.scale = std::exp(c.centre);
  fit.sigma = fit.scale * kMedianEfficiency * c.spread / std::sqrt(static_cast<double>(c.kept));
  return fit;
}

HeadingOffsetFit fit_heading_offset(const std::vector<VoStep>& steps, const std::vector<PositionSample>& positions,
                                    int32_t unsolved_mask, double min_baseline_m, double outlier_sigma) {
  HeadingOffsetFit fit;
  std::vector<double> differences;
  for (const VoStep& s : steps) {
    if ((s.quality & unsolved_mask) != 0) continue;
    Eigen::Vector3d a, b;
    double yaw = 0.0;
    if (!position_at(positions, s.prev_utime, &a, &yaw) || !position_at(positions, s.utime, &b)) continue;
    const double gnss = std::hypot(b.x() - a.x(), b.y() - a.y());
    if (gnss < min_baseline_m || !(std::hypot(s.dx, s.dy) > 0.0) || !std::isfinite(s.dx + s.dy)) {
      ++fit.rejected;
      continue;
    }
    const double vo_heading = yaw + std::atan2(s.dy, s.dx);  // the step in the level frame, x forward, y right
    differences.push_back(std::remainder(std::atan2(b.y() - a.y(), b.x() - a.x()) - vo_heading, 2.0 * M_PI));
  }
  if (differences.empty()) return fit;
  // About the circular mean's direction, so that offsets near 180 deg do not wrap.
  double sx = 0.0, sy = 0.0;
  for (double d : differences) sx += std::cos(d), sy += std::sin(d);
  const double around = std::atan2(sy, sx);
  for (double& d : differences) d = std::remainder(d - around, 2.0 * M_PI);
  const RobustCentre c = robust_centre(differences, outlier_sigma);
  fit.rejected += c.dropped;
  fit.pairs = c.kept;
  fit.offset_rad = std::remainder(around + c.centre, 2.0 * M_PI);
  fit.sigma_rad = kMedianEfficiency * c.spread / std::sqrt(static_cast<double>(c.kept));
  return fit;
}

}  // namespace nadir::calibrate
