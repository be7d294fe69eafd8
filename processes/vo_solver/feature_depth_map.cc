#include "processes/vo_solver/feature_depth_map.h"

#include <Eigen/Dense>

#include <cmath>
#include <limits>

#include "processes/vo_solver/plane_model.h"

namespace nadir::vo {

void FeatureDepthMap::reset() {
  if (!depths_.empty()) ++resets_;
  depths_.clear();
  utime_ = INT64_MIN;
}

void FeatureDepthMap::fill(const std::vector<int64_t>& ids, int64_t prev_utime, FramePair* pair) {
  if (prev_utime != utime_) reset();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  pair->prev_depth_m.assign(ids.size(), nan);
  pair->prev_depth_sigma_m.assign(ids.size(), nan);
  for (size_t i = 0; i < ids.size(); ++i) {
    const auto it = depths_.find(ids[i]);
    if (it == depths_.end()) continue;
    pair->prev_depth_m[i] = it->second.depth;
    pair->prev_depth_sigma_m[i] = it->second.sigma;
  }
}

void FeatureDepthMap::update(const std::vector<int64_t>& ids, int64_t curr_utime, const FramePair& pair,
                             const Estimate& est) {
  constexpr int kFailed = kTooFewFeatures | kNoAltimeter | kNotConverged | kNoAttitude;
  const size_t n = ids.size();
  if ((est.quality & kFailed) || pair.prev_norm.size() != n || pair.curr_norm.size() != n) {
    reset();
    return;
  }
  const FeatureDepthOptions& o = options_.feature_depth;
  const Eigen::Matrix3d prev_level = level_from_camera(pair.prev_roll, pair.prev_pitch, pair.body_from_camera);
  const Eigen::Matrix3d curr_level = level_from_camera(pair.curr_roll, pair.curr_pitch, pair.body_from_camera);
  const Eigen::Matrix3d rz = rot_z(est.dyaw);
  const Eigen::Vector3d& t = est.translation;
  // Angular noise of the two rays together, and the epipolar gate, in radians.
  const double ray_sigma = std::sqrt(2.0) * o.triangulation_noise_px / options_.focal_px;
  const double max_epipolar = o.max_epipolar_px * options_.pixel_scale() / options_.focal_px;
  const bool has_prior = pair.prev_depth_m.size() == n && pair.prev_depth_sigma_m.size() == n;
  std::unordered_map<int64_t, Entry> next;
  next.reserve(n);
  for (size_t i = 0; i < n; ++i) {
    Eigen::Vector3d u = prev_level * pair.prev_norm[i].homogeneous();
    Eigen::Vector3d v = curr_level * pair.curr_norm[i].homogeneous();
    if (!u.allFinite() || !v.allFinite() || u.z() < 1e-6 || v.z() < 1e-6) continue;
    u /= u.z();
    v /= v.z();
    const bool used_own = i < est.used_own_depth.size() && est.used_own_depth[i];
    const double weight = i < est.weights.size() ? est.weights[i] : 0.0;
    // Its own depth was used and the fit rejected it: the surface under the
    // track changed (cliff edge) or moves. Start again from this pair alone.
    bool prior_ok = has_prior && std::isfinite(pair.prev_depth_m[i]) && pair.prev_depth_m[i] > 0;
    if (used_own && !(weight > 0)) {
      prior_ok = false;
      ++rejected_;
    }
    // Triangulation: lambda (R v) + t = mu u in the least-squares sense.
    const Eigen::Vector3d a = rz * v;
    const double aa = a.dot(a), ab = a.dot(u), bb = u.dot(u);
    const double det = aa * bb - ab * ab;
    const double parallax = std::asin(std::min(1.0, a.cross(u).norm() / std::sqrt(aa * bb)));
    double tri = std::numeric_limits<double>::quiet_NaN(), tri_sigma = tri;
    if (det > 0 && parallax >= o.min_parallax_rad) {
      const double lambda = (-bb * a.dot(t) + ab * u.dot(t)) / det;
      const double mu = (ab * a.dot(t) - aa * u.dot(t)) / -det;
      const Eigen::Vector3d gap = lambda * a + t - mu * u;
      if (lambda > 0 && mu > 0) {
        if (gap.norm() / (lambda * std::sqrt(aa)) > max_epipolar) {
          // Not a static point under this motion (a mismatch this frame, a
          // moving object): no depth from this pair. A carried depth stays
          // only if the fit did not reject it (above).
          ++off_epipolar_;
        } else {
          tri = lambda;
          tri_sigma = lambda * ray_sigma / std::sin(parallax);
        }
      }
    }
    // The previous depth carried into curr, re-anchored on this pair's altimeter.
    double prior = std::numeric_limits<double>::quiet_NaN(), prior_sigma = prior;
    if (prior_ok) {
      const double mu = est.depth_scale * pair.prev_depth_m[i];
      const Eigen::Vector3d in_curr = rz.transpose() * (mu * u - t);
      if (in_curr.z() > 0) {
        prior = in_curr.z();
        const double rel = pair.prev_depth_sigma_m[i] / pair.prev_depth_m[i];
        prior_sigma = prior * std::sqrt(rel * rel + o.relative_process_noise * o.relative_process_noise);
      }
    }
    // The carried depth and this pair's disagree beyond their noise: the
    // surface under the track changed (a cliff edge). Start again from this pair.
    if (std::isfinite(tri) && std::isfinite(prior) &&
        std::abs(tri - prior) > o.max_depth_jump_sigma * std::hypot(tri_sigma, prior_sigma)) {
      prior = std::numeric_limits<double>::quiet_NaN();
      prior_ok = false;
      ++rejected_;
    }
    const auto old = depths_.find(ids[i]);
    const int seen = prior_ok && old != depths_.end() ? old->second.observations : 0;
    Entry e;
    if (std::isfinite(tri) && std::isfinite(prior)) {
      const double wt = 1.0 / (tri_sigma * tri_sigma), wp = 1.0 / (prior_sigma * prior_sigma);
      e.depth = (wt * tri + wp * prior) / (wt + wp);
      e.sigma = 1.0 / std::sqrt(wt + wp);
      e.observations = seen + 1;
    } else if (std::isfinite(tri)) {
      e = {tri, tri_sigma, 1};
    } else if (std::isfinite(prior)) {
      e = {prior, prior_sigma, seen};  // no parallax this pair (hover): carried over only
    } else {
      continue;
    }
    if (std::isfinite(e.depth) && e.depth > 0 && std::isfinite(e.sigma)) next[ids[i]] = e;
  }
  depths_.swap(next);
  utime_ = curr_utime;
}

}  // namespace nadir::vo
