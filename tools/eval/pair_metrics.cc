#include "tools/eval/pair_metrics.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <utility>
#include <stdexcept>

#include "common/geometry.h"
#include "common/ground_footprint.h"
#include "common/status.h"
#include "tools/eval/truth_lookup.h"

namespace nadir {

namespace {

double overlap_pct(const CameraModel& camera, const TruthAt& a, const TruthAt& b) {
  const double ground_down_m = a.position[2] + a.height_agl_m;
  auto footprint = [&](const TruthAt& t) {
    return ground_footprint(camera, Eigen::Vector3d(t.position[0], t.position[1], t.position[2]),
                            rotation_from_rpy(t.roll, t.pitch, t.yaw), ground_down_m);
  };
  return 100.0 * footprint_overlap(footprint(a), footprint(b));
}

}  // namespace

PairMetrics evaluate_pairs(const std::vector<vo_delta_t>& deltas, const std::vector<ground_truth_t>& truth,
                           const CameraModel* camera, int32_t reject_quality_mask, double min_step_m) {
  PairMetrics m;
  m.reject_quality_mask = reject_quality_mask;
  m.footprints = camera != nullptr;
  int64_t overlapping = 0;
  std::vector<float> errors, steps;
  for (const vo_delta_t& d : deltas) {
    TruthAt a{}, b{};
    if (!truth_at(truth, d.prev_utime, &a) || !truth_at(truth, d.utime, &b)) continue;
    PairSample s;
    s.utime = d.utime;
    s.prev_utime = d.prev_utime;
    s.quality = d.quality;
    s.inliers = d.inliers;
    s.solved = (d.quality & reject_quality_mask) == 0;
    // Truth step in the level frame of the previous frame (x along its heading).
    const double dn = b.position[0] - a.position[0], de = b.position[1] - a.position[1];
    const double c = std::cos(a.yaw), sn = std::sin(a.yaw);
    const double step_x = c * dn + sn * de, step_y = -sn * dn + c * de;
    s.step_m = std::hypot(dn, de);
    s.true_x = step_x;
    s.true_y = step_y;
    s.dx = d.dx;
    s.dy = d.dy;
    s.true_dyaw_deg = rad_to_deg(angle_difference(b.yaw, a.yaw));
    s.dyaw_deg = rad_to_deg(wrap_angle(d.dyaw));
    s.error_h_m = std::hypot(d.dx - step_x, d.dy - step_y);
    s.error_pct = s.step_m > 0 ? 100.0 * s.error_h_m / s.step_m : 0.0;
    if (camera != nullptr) {
      s.overlap_pct = overlap_pct(*camera, a, b);
      if (s.overlap_pct < kApartOverlapPct) {
        ++m.apart;
      } else {
        ++overlapping;
        if (s.solved) ++m.overlapping_solved;
      }
    }
    ++m.pairs;
    for (int bit = 0; bit < kVoQualityBits; ++bit) {
      if (d.quality & reject_quality_mask & (1 << bit)) ++m.not_solved_by_bit[bit];
    }
    if (s.solved) {
      ++m.solved;
      if (s.step_m >= min_step_m) {
        ++m.measured;
        errors.push_back(static_cast<float>(s.error_pct));
      }
    }
    steps.push_back(static_cast<float>(s.step_m));
    m.samples.push_back(s);
  }
  if (m.pairs > 0) m.solved_pct = 100.0 * static_cast<double>(m.solved) / static_cast<double>(m.pairs);
  if (overlapping > 0) {
    m.overlapping_solved_pct = 100.0 * static_cast<double>(m.overlapping_solved) / static_cast<double>(overlapping);
  }
  m.error_pct_median = percentile(errors, 50);
  m.error_pct_p90 = percentile(errors, 90);
  m.step_median_m = percentile(steps, 50);
  return m;
}

std::string format_not_solved(const PairMetrics& metrics) {
  std::vector<std::pair<int64_t, int>> counts;
  for (int bit = 0; bit < kVoQualityBits; ++bit) {
    if (metrics.not_solved_by_bit[bit] > 0) counts.emplace_back(-metrics.not_solved_by_bit[bit], bit);
  }
  std::sort(counts.begin(), counts.end());
  std::string text;
  for (const auto& [minus_count, bit] : counts) {
    text += (text.empty() ? "" : ", ") + std::to_string(-minus_count) + " " + vo_quality_name(bit);
  }
  return text;
}

void write_pairs_csv(const PairMetrics& metrics, const std::string& path) {
  std::ofstream out(path);
  if (!out) throw std::runtime_error(path + ": cannot write");
  out << "utime,prev_utime,step_m,true_x,true_y,dx,dy,true_dyaw_deg,dyaw_deg,error_h_m,error_pct,quality,inliers,"
         "solved,overlap_pct\n";
  out.precision(10);
  for (const PairSample& s : metrics.samples) {
    out << s.utime << ',' << s.prev_utime << ',' << s.step_m << ',' << s.true_x << ',' << s.true_y << ',' << s.dx << ','
        << s.dy << ',' << s.true_dyaw_deg << ',' << s.dyaw_deg << ','
        << s.error_h_m << ',' << s.error_pct << ',' << s.quality << ',' << s.inliers << ',' << (s.solved ? 1 : 0)
        << ',' << s.overlap_pct << '\n';
  }
}

}  // namespace nadir
