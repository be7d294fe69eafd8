#include "processes/vo_solver/feature_depth_map.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <limits>

#include "processes/vo_solver/plane_model.h"

namespace nadir::vo {

void FeatureDepthMap::reset() {
  if (!depths_.empty()) ++resets_;
  depths_.clear();
  spots_.clear();
  utime_ = INT64_MIN;
  tilt_.setZero();
  carried_scale_pairs_ = -1;
  scale_variance_ = 0;
}

size_t FeatureDepthMap::size() const {
  size_t n = 0;
  for (const auto& entry : depths_) n += std::isfinite(entry.second.depth);
  return n;
}

void FeatureDepthMap::fill(const std::vector<int64_t>& ids, int64_t prev_utime, FramePair* pair) {
  if (prev_utime != utime_) reset();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  pair->prev_depth_m.assign(ids.size(), nan);
  pair->prev_depth_sigma_m.assign(ids.size(), nan);
  // The frame's INS tilt error as the pairs so far estimated it; nothing
  // known (a new map): zero, with the INS's own variance.
  pair->prev_tilt = tilt_;
  pair->prev_tilt_variance = utime_ == INT64_MIN
                                 ? Eigen::Vector2d::Constant(options_.feature_depth.ins_tilt_variance())
                                 : tilt_variance_;
  pair->carried_scale_pairs = carried_scale_pairs_;
  pair->prev_scale_variance = scale_variance_;
  pair->earlier_ground_spots.clear();
  if (options_.feature_depth.anchor_spots == AnchorSpots::kTrack) pair->earlier_ground_spots = spots_;
  for (size_t i = 0; i < ids.size(); ++i) {
    const auto it = depths_.find(ids[i]);
    if (it == depths_.end() || !std::isfinite(it->second.depth)) continue;  // tracked, no parallax yet
    pair->prev_depth_m[i] = it->second.depth;
    pair->prev_depth_sigma_m[i] = it->second.sigma;
  }
}

namespace {

struct Triangulation {
  double depth = std::numeric_limits<double>::quiet_NaN();  // vertical, below the curr camera
  double relative_sigma = std::numeric_limits<double>::quiet_NaN();
  bool off_epipolar = false;
  bool ok() const { return std::isfinite(depth); }
};

// The ray origin + mu * ray (first sight of the track) against the curr ray
// t + lambda * a (a.z = 1), least squares; all in the level frame of prev.
// No depth below min_parallax (hover); off_epipolar when the rays miss each
// other by more than max_epipolar (radians at the point).
Triangulation triangulate(const Eigen::Vector3d& origin, const Eigen::Vector3d& ray, const Eigen::Vector3d& t,
                          const Eigen::Vector3d& a, double ray_sigma, double floor, double max_epipolar,
                          double min_parallax) {
  Triangulation out;
  const Eigen::Vector3d d = t - origin;
  const double rr = ray.dot(ray), ra = ray.dot(a), aa = a.dot(a);
  const double det = rr * aa - ra * ra;
  const double parallax = std::asin(std::min(1.0, ray.cross(a).norm() / std::sqrt(rr * aa)));
  if (!(det > 0) || parallax < min_parallax) return out;
  const double mu = (aa * ray.dot(d) - ra * a.dot(d)) / det;
  const double lambda = (ra * ray.dot(d) - rr * a.dot(d)) / det;
  if (!(lambda > 0) || !(mu > 0)) return out;
  const Eigen::Vector3d gap = origin + mu * ray - t - lambda * a;
  if (gap.norm() / (lambda * std::sqrt(aa)) > max_epipolar) {
    out.off_epipolar = true;
    return out;
  }
  const double from_rays = ray_sigma / std::sin(parallax);
  out.depth = lambda;
  out.relative_sigma = std::sqrt(from_rays * from_rays + floor * floor);
  return out;
}

}  // namespace

void FeatureDepthMap::move_spots(const FramePair& pair, const Eigen::Matrix3d& to_curr, const Eigen::Vector3d& t) {
  // Spots further back than this (ray offset from the vertical, and in
  // number: a hover) are beyond any anchor the solver fits.
  const double max_offset = 2.0 * options_.feature_depth.anchor_radius + 0.5;
  constexpr size_t kMaxSpots = 2000;
  std::vector<Eigen::Vector3d> moved;
  moved.reserve(std::min(spots_.size() + 1, kMaxSpots));
  if (pair.prev_range_m > 0 && std::isfinite(pair.prev_range_m)) {
    spots_.insert(spots_.begin(),
                  pair.prev_range_m * level_beam(pair.prev_roll, pair.prev_pitch, pair.prev_beam_body));
  }
  for (const Eigen::Vector3d& spot : spots_) {
    const Eigen::Vector3d x = to_curr * (spot - t);
    if (!(x.z() > 0) || x.head<2>().norm() > max_offset * x.z() || moved.size() == kMaxSpots) continue;
    moved.push_back(x);
  }
  spots_.swap(moved);
}

void FeatureDepthMap::update(const std::vector<int64_t>& ids, int64_t curr_utime, const FramePair& pair,
                             const Estimate& est) {
  const size_t n = ids.size();
  if ((est.quality & kEstimateFailed) || pair.prev_norm.size() != n || pair.curr_norm.size() != n) {
    reset();
    return;
  }
  if (!est.own_depths_used) {
    carried_scale_pairs_ = -1;
  } else {
    carried_scale_pairs_ = est.scale_carried ? std::max(carried_scale_pairs_, 0) + 1 : 0;
  }
  scale_variance_ = est.scale_variance;
  const FeatureDepthOptions& o = options_.feature_depth;
  const Eigen::Matrix3d prev_level = level_from_camera(pair.prev_roll, pair.prev_pitch, pair.body_from_camera);
  const Eigen::Matrix3d curr_level = level_from_camera(pair.curr_roll, pair.curr_pitch, pair.body_from_camera);
  // Into curr's level frame (with the pair's fitted relative tilt, if any),
  // the frame the next pair's INS-levelled rays are in.
  const Eigen::Matrix3d to_curr = curr_from_prev(est);
  const Eigen::Vector3d& t = est.translation;
  // Angular noise of the two rays together, and the epipolar gate, in radians.
  const double ray_sigma = std::sqrt(2.0) * o.triangulation_noise_px / options_.focal_px;
  const double max_epipolar = o.max_epipolar_px * options_.pixel_scale() / options_.focal_px;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::unordered_map<int64_t, Entry> next;
  next.reserve(n);
  for (size_t i = 0; i < n; ++i) {
    Eigen::Vector3d u = prev_level * pair.prev_norm[i].homogeneous();
    Eigen::Vector3d v = curr_level * pair.curr_norm[i].homogeneous();
    if (!u.allFinite() || !v.allFinite() || u.z() < 1e-6 || v.z() < 1e-6) continue;
    u /= u.z();
    v /= v.z();
    const Eigen::Vector3d a = to_curr.transpose() * v;
    const bool used_own = i < est.used_own_depth.size() && est.used_own_depth[i];
    const double weight = i < est.weights.size() ? est.weights[i] : 0.0;
    const auto old = depths_.find(ids[i]);
    bool carried = old != depths_.end();
    // Its own depth was used and the fit rejected it: the surface under the
    // track changed (cliff edge) or moves. Start again from this pair alone.
    if (used_own && !(weight > 0)) {
      carried = false;
      ++rejected_;
    }
    const Triangulation this_pair =
        triangulate(Eigen::Vector3d::Zero(), u, t, a, ray_sigma, o.relative_process_noise, max_epipolar,
                    o.min_parallax_rad);
    Entry e;
    if (this_pair.off_epipolar) {
      // Not a static point under this motion (a mismatch this frame, a moving
      // object): nothing from this pair. A carried track stays as it was, moved
      // into curr, only if the fit did not reject it (above).
      ++off_epipolar_;
      if (!carried) continue;
      e = old->second;
      e.origin = to_curr * (est.depth_scale * e.origin - t);
      e.ray = to_curr * e.ray;
      const Eigen::Vector3d point = to_curr * (est.depth_scale * e.depth * u - t);
      e.depth = std::isfinite(e.depth) && point.z() > 0 ? point.z() : nan;
      e.point = point;
      if (std::isfinite(e.depth)) next[ids[i]] = e;
      continue;
    }
    // The track's first ray, re-anchored on this pair's altimeter (its origin
    // scales with every depth about the prev camera), against the curr ray:
    // the whole track's baseline, not one pair's, so the depth's noise shrinks
    // as the track grows and no pair's parallax draw weighs on it.
    Eigen::Vector3d origin = Eigen::Vector3d::Zero(), ray = u;
    if (carried) {
      origin = est.depth_scale * old->second.origin;
      ray = old->second.ray;
    }
    Triangulation whole = carried ? triangulate(origin, ray, t, a, ray_sigma, o.relative_process_noise,
                                                max_epipolar, o.min_parallax_rad)
                                  : this_pair;
    // The track slid (off its own first ray), or this pair's depth and the
    // track's disagree beyond their noise: the surface under the track changed
    // (a cliff edge). Start again from this pair.
    const bool jump = whole.ok() && this_pair.ok() &&
                      std::abs(whole.depth - this_pair.depth) >
                          o.max_depth_jump_sigma * std::hypot(whole.depth * whole.relative_sigma,
                                                              this_pair.depth * this_pair.relative_sigma);
    if (carried && (whole.off_epipolar || jump)) {
      ++rejected_;
      origin.setZero();
      ray = u;
      whole = this_pair;
    }
    e.origin = to_curr * (origin - t);
    e.ray = to_curr * ray;
    e.depth = whole.depth;
    e.sigma = whole.depth * whole.relative_sigma;
    e.point = whole.depth * v;  // on curr's ray, v.z() = 1
    next[ids[i]] = e;
  }
  depths_.swap(next);
  if (o.anchor_spots == AnchorSpots::kTrack) move_spots(pair, to_curr, t);
  utime_ = curr_utime;
  tilt_ = est.curr_tilt;
  tilt_variance_ = est.curr_tilt_variance;
}

std::vector<FeatureDepthMap::GroundPoint> FeatureDepthMap::trusted_points(double max_relative_sigma) const {
  std::vector<GroundPoint> out;
  for (const auto& [id, e] : depths_) {
    if (std::isfinite(e.depth) && e.depth > 0.0 && std::isfinite(e.sigma) && e.sigma <= max_relative_sigma * e.depth) {
      out.push_back({id, e.point, e.sigma});
    }
  }
  std::sort(out.begin(), out.end(), [](const GroundPoint& a, const GroundPoint& b) { return a.track_id < b.track_id; });
  return out;
}

}  // namespace nadir::vo
