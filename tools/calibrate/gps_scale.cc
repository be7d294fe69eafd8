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

namespace {

// A solved pair with its GNSS positions at both frames and the recorded yaw
// at the previous one.
struct GnssPair {
  const VoStep* step;
  Eigen::Vector3d a, b;
  double yaw;
};

// The solved pairs the positions cover with a GNSS baseline of at least
// `min_baseline_m` and a finite, non-zero VO step; `rejected` counts the
// covered ones left out.
std::vector<GnssPair> gnss_pairs(const std::vector<VoStep>& steps, const std::vector<PositionSample>& positions,
                                 int32_t unsolved_mask, double min_baseline_m, int64_t* rejected) {
  std::vector<GnssPair> out;
  for (const VoStep& s : steps) {
    if ((s.quality & unsolved_mask) != 0) continue;
    GnssPair p{&s, {}, {}, 0.0};
    if (!position_at(positions, s.prev_utime, &p.a, &p.yaw) || !position_at(positions, s.utime, &p.b)) continue;
    const double gnss = std::hypot(p.b.x() - p.a.x(), p.b.y() - p.a.y());
    const double vo = std::hypot(s.dx, s.dy);
    if (gnss < min_baseline_m || !(vo > 0.0) || !std::isfinite(vo)) {
      ++*rejected;
      continue;
    }
    out.push_back(p);
  }
  return out;
}

}  // namespace

GpsScaleFit fit_gps_scale(const std::vector<VoStep>& steps, const std::vector<PositionSample>& positions,
                          int32_t unsolved_mask, double min_baseline_m, double outlier_sigma) {
  GpsScaleFit fit;
  std::vector<double> log_ratio;
  for (const GnssPair& p : gnss_pairs(steps, positions, unsolved_mask, min_baseline_m, &fit.rejected)) {
    log_ratio.push_back(std::log(std::hypot(p.b.x() - p.a.x(), p.b.y() - p.a.y()) / std::hypot(p.step->dx, p.step->dy)));
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
  for (const GnssPair& p : gnss_pairs(steps, positions, unsolved_mask, min_baseline_m, &fit.rejected)) {
    const double vo_heading = p.yaw + std::atan2(p.step->dy, p.step->dx);  // the step in the level frame, x forward, y right
    differences.push_back(std::remainder(std::atan2(p.b.y() - p.a.y(), p.b.x() - p.a.x()) - vo_heading, 2.0 * M_PI));
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
