// The feature_depth variant (DERIVATION.md section 13): features with their
// own depth (triangulated over earlier frames of their track, FeatureDepthMap)
// constrain the motion with that depth, re-anchored on this pair's altimeter;
// the others with the paper's ground patch.

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <utility>
#include <vector>

#include "common/geometry.h"
#include "processes/vo_solver/plane_model.h"
#include "processes/vo_solver/solver_support.h"
#include "processes/vo_solver/translation_solver.h"

namespace nadir::vo {

void FeatureDepthOptions::Check() const {
  auto require = [](bool ok, const char* field, const char* range) {
    if (!ok) throw std::invalid_argument(std::string("feature_depth.") + field + " must be " + range);
  };
  require(max_relative_sigma > 0 && max_relative_sigma <= 1, "max_relative_sigma", "in (0, 1]");
  require(min_own_depth_features >= 5 && min_own_depth_features <= 10000, "min_own_depth_features", "in [5, 10000]");
  require(anchor_radius > 0 && anchor_radius <= 2, "anchor_radius", "in (0, 2]");
  require(min_anchor_features >= 3 && min_anchor_features <= 10000, "min_anchor_features", "in [3, 10000]");
  require(scale_carry_pairs >= 0 && scale_carry_pairs <= 1000, "scale_carry_pairs", "in [0, 1000]");
  require(scale_process_noise > 0 && scale_process_noise <= 1, "scale_process_noise", "in (0, 1]");
  require(patch_feature_weight >= 0 && patch_feature_weight <= 1, "patch_feature_weight", "in [0, 1]");
  require(triangulation_noise_px > 0 && triangulation_noise_px <= 100, "triangulation_noise_px", "in (0, 100]");
  require(min_parallax_rad > 0 && min_parallax_rad <= 0.5, "min_parallax_rad", "in (0, 0.5]");
  require(relative_process_noise >= 0 && relative_process_noise <= 1, "relative_process_noise", "in [0, 1]");
  require(max_epipolar_px > 0 && max_epipolar_px <= 100, "max_epipolar_px", "in (0, 100]");
  require(max_depth_jump_sigma >= 1 && max_depth_jump_sigma <= 100, "max_depth_jump_sigma", "in [1, 100]");
  require(ins_tilt_sigma_deg >= 0 && ins_tilt_sigma_deg <= 5, "ins_tilt_sigma_deg", "in [0, 5]");
}

namespace {

struct DepthFeature {
  Eigen::Vector3d u, v;  // level rays of prev and curr, z = 1
  double depth = 0;      // along u (vertical depth below the prev camera), metres
  double relative_sigma = 0;  // an own depth's sigma over the depth
  double base_weight = 0;
  bool own = false;
  int index = 0;         // in the input pair
};

// The own-depth structure around the prev altimeter beam: inverse depth as a
// function of the ray's offset d = u_xy - center from a centre ray (level rays,
// z = 1): 1/z = c0 + c1 dx + c2 dy (a plane in space) or with the quadratic
// terms c3 dx^2 + c4 dx dy + c5 dy^2 (a curved surface: a crest, a valley).
// The rays are known without error and an own depth's noise is relative, so
// the fit is linear with noise in 1/z alone. The beam meets it at depth 1/c0.
using AnchorVector = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, 6, 1>;
using AnchorMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 6, 6>;

AnchorVector anchor_basis(const Eigen::Vector3d& u, const Eigen::Vector2d& center, int terms) {
  const Eigen::Vector2d d = u.head<2>() - center;
  AnchorVector x(terms);
  x(0) = 1.0;
  x(1) = d.x();
  x(2) = d.y();
  if (terms == 6) {
    x(3) = d.x() * d.x();
    x(4) = d.x() * d.y();
    x(5) = d.y() * d.y();
  }
  return x;
}

// The kernel both the surface fit and the track's spots are weighted with:
// Gaussian in the ray offset from the centre, sigma = radius / 2.
double anchor_kernel(double offset, const FeatureDepthOptions& o) {
  const double sd = 0.5 * o.anchor_radius;
  return std::exp(-0.5 * offset * offset / (sd * sd));
}

// The surface above fitted around `center` (a level ray's xy, z = 1) to the
// own-depth features whose rays lie within `anchor_radius` of it (the
// kernel's weights, one pass of 3 MAD outlier rejection on the relative
// depth residual). Its relative sigma: of the weighted mean inverse depth.
struct AnchorSurface {
  AnchorVector coef;
  Eigen::Vector2d center;
  double relative_sigma = 0;
  // The surface's model error near its centre, as a relative variance: the
  // kernel-weighted mean of (residual^2 - the own depth's sigma^2) over the
  // depths the fit kept, relative, floored at 0.
  double model_variance = 0;
  double inverse_depth(const Eigen::Vector3d& ray) const {
    return coef.dot(anchor_basis(ray, center, static_cast<int>(coef.size())));
  }
};

bool fit_anchor_surface(const std::vector<DepthFeature>& features, const Eigen::Vector2d& center,
                        const FeatureDepthOptions& o, AnchorSurfaceModel model, AnchorSurface* surface) {
  const int np = model == AnchorSurfaceModel::kQuadratic ? 6 : 3;
  std::vector<const DepthFeature*> near;
  std::vector<AnchorVector> basis;
  std::vector<double> weight;
  for (const DepthFeature& f : features) {
    const double d = (f.u.head<2>() - center).norm();
    if (!f.own || d > o.anchor_radius) continue;
    near.push_back(&f);
    basis.push_back(anchor_basis(f.u, center, np));
    // 1/z has the relative depth noise over z: weight z^2.
    weight.push_back(anchor_kernel(d, o) * f.depth * f.depth);
  }
  AnchorVector coef = AnchorVector::Zero(np);
  std::vector<double> residual(near.size(), 0.0);  // relative to the depth
  double cut = std::numeric_limits<double>::infinity();
  double sum_w = 0, sum_w2r2 = 0;
  std::vector<char> kept(near.size(), 0);
  for (int pass = 0; pass < 2; ++pass) {
    AnchorMatrix a = AnchorMatrix::Zero(np, np);
    AnchorVector b = AnchorVector::Zero(np);
    int used = 0;
    sum_w = 0;
    for (size_t k = 0; k < near.size(); ++k) {
      kept[k] = std::abs(residual[k]) <= cut;
      if (!kept[k]) continue;
      a += weight[k] * basis[k] * basis[k].transpose();
      b += weight[k] / near[k]->depth * basis[k];
      sum_w += weight[k];
      ++used;
    }
    if (used < std::max(o.min_anchor_features, 2 * np)) return false;
    const Eigen::LDLT<AnchorMatrix> ldlt(a);
    if (ldlt.info() != Eigen::Success || !ldlt.isPositive()) return false;
    coef = ldlt.solve(b);
    std::vector<double> abs_res;
    sum_w2r2 = 0;
    for (size_t k = 0; k < near.size(); ++k) {
      const double r = 1.0 / near[k]->depth - coef.dot(basis[k]);
      residual[k] = r * near[k]->depth;
      abs_res.push_back(std::abs(residual[k]));
      if (std::abs(residual[k]) <= cut) sum_w2r2 += weight[k] * weight[k] * r * r;
    }
    cut = std::max(1e-9, 3.0 * 1.4826 * median_of(abs_res));
  }
  if (!(coef(0) > 0)) return false;
  double sum_k = 0, sum_excess = 0;
  for (size_t k = 0; k < near.size(); ++k) {
    if (!kept[k]) continue;
    const double kernel = weight[k] / (near[k]->depth * near[k]->depth);
    sum_k += kernel;
    sum_excess += kernel * (residual[k] * residual[k] - near[k]->relative_sigma * near[k]->relative_sigma);
  }
  surface->model_variance = sum_k > 0 ? std::max(0.0, sum_excess / sum_k) : 0.0;
  surface->coef = coef;
  surface->center = center;
  surface->relative_sigma = std::sqrt(sum_w2r2) / sum_w / coef(0);
  return true;
}

// The altimeter spots of the anchor_spots track mode as one line, built
// once per pair whatever surface is then fitted: prev's own spot (range x
// beam) and the earlier frames' within 2 x anchor_radius of it (ray offset),
// used only when they reach back at least 1.8 x anchor_radius. The centre is
// halfway between the line's ends along its main direction; each spot within
// anchor_radius of it along that direction (xi) is weighted as the surface
// fit weighs the own depths across the line there (the kernel on the disc of
// the anchor radius), times its depth and its share of the line (half the gap
// to its neighbours along it), so that the spots count as a uniform sampling
// of the ground along the track however the attitude's oscillation spaced them.
struct SpotLine {
  Eigen::Vector2d center = Eigen::Vector2d::Zero();
  std::vector<Eigen::Vector3d> spots;  // within anchor_radius of the centre along the line
  std::vector<double> weight;          // parallel to spots
};

bool spot_line(const FramePair& pair, const Eigen::Vector3d& prev_beam, const FeatureDepthOptions& o,
               SpotLine* line) {
  std::vector<Eigen::Vector3d> spots{pair.prev_range_m * prev_beam};
  const Eigen::Vector2d beam_xy = prev_beam.head<2>() / prev_beam.z();
  double reach = 0;
  for (const Eigen::Vector3d& x : pair.earlier_ground_spots) {
    if (!(x.z() > 0)) continue;
    const double offset = (x.head<2>() / x.z() - beam_xy).norm();
    if (offset > 2.0 * o.anchor_radius) continue;
    spots.push_back(x);
    reach = std::max(reach, offset);
  }
  if (reach < 1.8 * o.anchor_radius) return false;
  const size_t n = spots.size();
  std::vector<Eigen::Vector2d> rays(n);
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (size_t j = 0; j < n; ++j) mean += (rays[j] = spots[j].head<2>() / spots[j].z());
  mean /= static_cast<double>(n);
  Eigen::Matrix2d spread = Eigen::Matrix2d::Zero();
  for (const Eigen::Vector2d& d : rays) spread += (d - mean) * (d - mean).transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> axes(spread);
  const Eigen::Vector2d axis = axes.eigenvectors().col(1);
  std::vector<std::pair<double, size_t>> along(n);
  for (size_t j = 0; j < n; ++j) along[j] = {(rays[j] - mean).dot(axis), j};
  std::sort(along.begin(), along.end());
  const double middle = 0.5 * (along.front().first + along.back().first);
  line->center = mean + middle * axis;
  const double r = o.anchor_radius;
  for (size_t k = 0; k < n; ++k) {
    const double xi = along[k].first - middle;
    if (std::abs(xi) > r) continue;
    const double share = 0.5 * (along[std::min(k + 1, n - 1)].first - along[k > 0 ? k - 1 : 0].first);
    const Eigen::Vector3d& x = spots[along[k].second];
    const double across = std::sqrt(std::max(0.0, r * r - xi * xi));
    line->spots.push_back(x);
    line->weight.push_back(share * anchor_kernel(xi, o) * std::erf(across / (0.5 * r * std::sqrt(2.0))) * x.z());
  }
  return true;
}

// Scale of the own depths from the altimeter. Beam (line null): the surface
// fitted around prev's beam meets it at 1/c0, and
// range_along_beam(structure) * scale = measured range. Track: the surface
// fitted around the spot line's centre, and the scale is the weighted mean
// over the spots of (spot depth) x (surface's inverse depth on the spot's
// ray). Where the ground varies along the track only (a ridge across it), the
// fit's residuals average to zero with the line's weights, so its misfit to a
// sharp crest cancels instead of biasing the scale (DERIVATION.md section 13).
bool fit_anchor(const std::vector<DepthFeature>& features, const FramePair& pair, const Eigen::Vector3d& prev_beam,
                const SpotLine* line, const FeatureDepthOptions& o, AnchorSurfaceModel model, double* scale,
                double* relative_sigma, double* model_variance) {
  AnchorSurface surface;
  if (!line) {
    if (!fit_anchor_surface(features, prev_beam.head<2>() / prev_beam.z(), o, model, &surface)) return false;
    // The beam point lambda * beam: depth 1 / c0 on the beam line.
    const double lambda = 1.0 / (surface.coef(0) * prev_beam.z());
    *scale = pair.prev_range_m / lambda;
  } else {
    if (!fit_anchor_surface(features, line->center, o, model, &surface)) return false;
    double sum_a = 0, sum_as = 0;
    for (size_t j = 0; j < line->spots.size(); ++j) {
      const Eigen::Vector3d& x = line->spots[j];
      const double g = surface.inverse_depth(x / x.z());
      if (!(g > 0)) continue;
      sum_a += line->weight[j];
      sum_as += line->weight[j] * x.z() * g;
    }
    if (!(sum_a > 0)) return false;
    *scale = sum_as / sum_a;
  }
  *relative_sigma = surface.relative_sigma;
  *model_variance = surface.model_variance;
  return std::isfinite(*scale) && *scale > 0;
}

// The configured surface; a quadratic the own depths near the beam cannot
// hold (too few, or all along one line) falls back to the plane. The spot
// line (anchor_spots track, once it reaches back far enough) serves both.
bool anchor_scale(const std::vector<DepthFeature>& features, const FramePair& pair, const Eigen::Vector3d& prev_beam,
                  const FeatureDepthOptions& o, double* scale, double* relative_sigma, double* model_variance) {
  if (!(prev_beam.z() > 1e-9)) return false;
  SpotLine line;
  const bool on_line = o.anchor_spots == AnchorSpots::kTrack && spot_line(pair, prev_beam, o, &line);
  const SpotLine* spots = on_line ? &line : nullptr;
  if (fit_anchor(features, pair, prev_beam, spots, o, o.anchor_surface, scale, relative_sigma, model_variance)) {
    return true;
  }
  return o.anchor_surface == AnchorSurfaceModel::kQuadratic &&
         fit_anchor(features, pair, prev_beam, spots, o, AnchorSurfaceModel::kPlane, scale, relative_sigma,
                    model_variance);
}

// The motion m = (dx, dy, dz, dyaw, tilt x, tilt y) as the reprojection
// needs it, computed once per evaluation: Y = rotation (depth u - t) with
// rotation = Rx(tilt x) Ry(tilt y) Rz(-dyaw) (curr_from_prev), and the
// rotation's derivatives by dyaw and by the two tilts.
using Motion = Eigen::Matrix<double, 6, 1>;
using MotionMatrix = Eigen::Matrix<double, 6, 6>;
struct MotionRotation {
  Eigen::Matrix3d rotation, by_dyaw, by_tilt_x, by_tilt_y;
  explicit MotionRotation(const Motion& m) {
    const double c = std::cos(m(3)), s = std::sin(m(3));
    const double ca = std::cos(m(4)), sa = std::sin(m(4)), cb = std::cos(m(5)), sb = std::sin(m(5));
    Eigen::Matrix3d rz, drz, rx, drx, ry, dry;
    rz << c, s, 0, -s, c, 0, 0, 0, 1;  // Rz(-dyaw)
    drz << -s, c, 0, -c, -s, 0, 0, 0, 0;
    rx << 1, 0, 0, 0, ca, -sa, 0, sa, ca;
    drx << 0, 0, 0, 0, -sa, -ca, 0, ca, -sa;
    ry << cb, 0, sb, 0, 1, 0, -sb, 0, cb;
    dry << -sb, 0, cb, 0, 0, 0, -cb, 0, -sb;
    const Eigen::Matrix3d tilt = rx * ry;
    rotation = tilt * rz;
    by_dyaw = tilt * drz;
    by_tilt_x = drx * ry * rz;
    by_tilt_y = rx * dry * rz;
  }
};

// Reprojection of feature f into the curr level frame: error (Y_xy / Y_z -
// v_xy) in pixels; Jacobian 2 x 6 if asked. False when the point is behind
// curr.
bool reprojection(const DepthFeature& f, const Motion& m, const MotionRotation& r, double focal_px,
                  Eigen::Vector2d* error, Eigen::Matrix<double, 2, 6>* jacobian) {
  const Eigen::Vector3d p = f.depth * f.u - m.head<3>();
  const Eigen::Vector3d y = r.rotation * p;
  if (!(y.z() > 1e-9)) return false;
  const double iz = 1.0 / y.z();
  *error = focal_px * Eigen::Vector2d(y.x() * iz - f.v.x(), y.y() * iz - f.v.y());
  if (jacobian) {
    // dY/dm (3 x 6), then the projection's derivative focal / Y_z [1 0 -x; 0 1 -y]
    // (x, y the projected point) applied row by row.
    Eigen::Matrix<double, 3, 6> dy;
    dy.leftCols<3>() = -r.rotation;
    dy.col(3) = r.by_dyaw * p;
    dy.col(4) = r.by_tilt_x * p;
    dy.col(5) = r.by_tilt_y * p;
    const double s = focal_px * iz, x = y.x() * iz, yy = y.y() * iz;
    jacobian->row(0) = s * (dy.row(0) - x * dy.row(2));
    jacobian->row(1) = s * (dy.row(1) - yy * dy.row(2));
  }
  return error->allFinite();
}

// Depth along the level ray u (z = 1) of the patch seen from prev,
// n' . X = prev_offset; false when the ray does not meet it in front.
bool patch_depth(const Eigen::Vector3d& u, const Eigen::Vector3d& prev_normal, double prev_offset, double* depth) {
  const double along = prev_normal.dot(u);
  if (!(along > 1e-9)) return false;
  *depth = prev_offset / along;
  return true;
}

// How far the patch misses the own depths, in their own sigmas: 1.4826 x the
// median over the own-depth features of |patch depth / own depth - 1| /
// relative sigma (a robust normalized residual: an own depth gone wrong does
// not move it). About 1 or less where the ground is the plane the patch
// assumes, several over hills; relief under less than half the own depths
// (a few blocks on level ground) leaves it low. 0 when no own feature sees
// the patch in front of it.
double patch_misfit(const std::vector<DepthFeature>& features, const Eigen::Vector3d& prev_normal,
                    double prev_offset) {
  std::vector<double> normalized;
  double depth = 0;
  for (const DepthFeature& f : features) {
    if (!f.own || !(f.relative_sigma > 0) || !patch_depth(f.u, prev_normal, prev_offset, &depth)) continue;
    normalized.push_back(std::abs(depth / f.depth - 1.0) / f.relative_sigma);
  }
  return normalized.empty() ? 0.0 : 1.4826 * median_of(normalized);
}

}  // namespace

Estimate solve_feature_depth(const FramePair& pair, const SolverOptions& options) {
  const FeatureDepthOptions& o = options.feature_depth;
  // The paper's model alone: the INS tilt as it is, so curr keeps prev's
  // estimated tilt error (the chain of tilts still telescopes).
  auto paper_alone = [&]() {
    Estimate est = solve_paper(pair, options, true);
    est.curr_tilt = pair.prev_tilt;
    est.curr_tilt_variance = pair.prev_tilt_variance;
    return est;
  };
  const size_t n = pair.prev_norm.size();
  auto own_usable = [&](size_t i) {
    if (i >= pair.prev_depth_m.size() || i >= pair.prev_depth_sigma_m.size()) return false;
    const double d = pair.prev_depth_m[i], sd = pair.prev_depth_sigma_m[i];
    return std::isfinite(d) && std::isfinite(sd) && d > 0 && sd >= 0 && sd <= o.max_relative_sigma * d;
  };
  int own_count = 0;
  for (size_t i = 0; i < n; ++i) own_count += own_usable(i);
  // Too few own depths (the start of a track set, a hover, after a gap): the paper's model alone.
  if (own_count < o.min_own_depth_features || pair.curr_norm.size() != n) return paper_alone();

  const Eigen::Matrix3d prev_level = level_from_camera(pair.prev_roll, pair.prev_pitch, pair.body_from_camera);
  const Eigen::Matrix3d curr_level = level_from_camera(pair.curr_roll, pair.curr_pitch, pair.body_from_camera);
  const Eigen::Vector3d prev_beam = level_beam(pair.prev_roll, pair.prev_pitch, pair.prev_beam_body);
  const Eigen::Vector3d curr_beam = level_beam(pair.curr_roll, pair.curr_pitch, pair.curr_beam_body);
  std::vector<DepthFeature> features;
  features.reserve(n);
  for (size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d u = prev_level * pair.prev_norm[i].homogeneous();
    const Eigen::Vector3d v = curr_level * pair.curr_norm[i].homogeneous();
    if (!u.allFinite() || !v.allFinite() || u.z() < 1e-6 || v.z() < 1e-6) continue;
    DepthFeature f;
    f.u = u / u.z();
    f.v = v / v.z();
    f.index = static_cast<int>(i);
    f.own = own_usable(i);
    f.depth = f.own ? pair.prev_depth_m[i] : 0.0;
    f.relative_sigma = f.own ? pair.prev_depth_sigma_m[i] / pair.prev_depth_m[i] : 0.0;
    features.push_back(f);
  }
  double scale = 1, scale_sigma = 0, model_variance = 0;
  bool scale_carried = false;
  if (!(pair.prev_range_m > 0)) return paper_alone();
  // The scale the own depths hold (the pair before's), where they hold an anchored one.
  const bool map_scaled = pair.carried_scale_pairs >= 0;
  // scale_filter: its variance, the pair before's grown by the map's own wander.
  const double carried_variance = pair.prev_scale_variance + o.scale_process_noise * o.scale_process_noise;
  if (!anchor_scale(features, pair, prev_beam, o, &scale, &scale_sigma, &model_variance)) {
    // Too few own depths near the beam: they keep the scale the pair before
    // left them (anchored at most scale_carry_pairs pairs back), else the paper.
    if (!map_scaled || pair.carried_scale_pairs >= o.scale_carry_pairs) return paper_alone();
    scale = 1.0;
    // The pair before's scale, with its error.
    scale_sigma = o.scale_filter ? std::sqrt(carried_variance) : o.relative_process_noise;
    scale_carried = true;
  } else if (o.scale_filter) {
    // The altimeter's scale (its fit's variance and the surface's model
    // error) fused with the carried one (DERIVATION.md section 13).
    const double anchor_variance =
        scale_sigma * scale_sigma + model_variance + std::pow(pair.prev_range_sigma_m / pair.prev_range_m, 2);
    if (map_scaled) {
      const double gain = carried_variance / (carried_variance + anchor_variance);
      scale = 1.0 + gain * (scale - 1.0);
      scale_sigma = std::sqrt((1.0 - gain) * carried_variance);
    } else {
      scale_sigma = std::sqrt(anchor_variance);
    }
  }
  // The patch: ground attitude, young features' depths, the start and the fallback.
  SolverOptions forward = options;
  forward.symmetric_dz = false;
  const Estimate patch = solve_paper(pair, forward, true);
  if (patch.quality & kEstimateFailed) return paper_alone();

  // Young features: depth on the patch (through the curr altimeter spot),
  // seen from prev: n' . X = n . A + n' . t with n' = Rz(dyaw) n. Their
  // weight is patch_feature_weight over the square of how far the patch
  // misses the own depths in their sigmas: full where the ground is the
  // patch's plane (and the curr altimeter's range then holds dz), little over
  // relief, where the plane puts them at wrong depths.
  const Eigen::Vector3d normal = normal_from_tilt(patch.ground_roll, patch.ground_pitch);
  const double plane_offset = normal.dot(pair.curr_range_m * curr_beam);
  const Eigen::Vector3d prev_normal = rot_z(patch.dyaw) * normal;
  const double prev_offset = plane_offset + prev_normal.dot(patch.translation);
  for (DepthFeature& f : features) {
    if (!f.own) continue;
    f.depth *= scale;
    f.base_weight = 1.0;
  }
  const double misfit = patch_misfit(features, prev_normal, prev_offset);
  const double patch_weight = o.patch_feature_weight / std::max(1.0, misfit * misfit);
  for (DepthFeature& f : features) {
    if (f.own) continue;
    if (!patch_depth(f.u, prev_normal, prev_offset, &f.depth)) f.depth = 0.0;
    f.base_weight = f.depth > 0 ? patch_weight : 0.0;
  }

  // The relative tilt (curr's INS tilt error minus prev's): its prior from
  // prev's estimated error (mean -prev, variance prev's + the INS's), in the
  // units of the fit's cost (over the image noise, set from the residuals at
  // each robust pass). Not fitted at all without an INS sigma.
  const bool fit_tilt = o.ins_tilt_sigma_deg > 0;
  const double ins_tilt_variance = o.ins_tilt_variance();
  const Eigen::Vector2d prev_tilt_variance = pair.prev_tilt_variance.cwiseMax(0.0);
  const Eigen::Vector2d tilt_prior_mean = -pair.prev_tilt;
  const Eigen::Vector2d tilt_prior_variance = prev_tilt_variance + Eigen::Vector2d::Constant(ins_tilt_variance);
  Eigen::Vector2d tilt_prior = Eigen::Vector2d::Zero();  // weights; set per robust pass
  double image_variance = 1.0;  // px^2, the prior's unit
  const int unknowns = fit_tilt ? 6 : 4;
  Motion motion;
  motion << patch.translation, patch.dyaw, 0.0, 0.0;
  const size_t m = features.size();
  std::vector<double> w(m, 0.0), err(m, std::numeric_limits<double>::infinity());
  auto errors = [&](const Motion& mo) {
    const MotionRotation rotation(mo);
    Eigen::Vector2d e;
    for (size_t i = 0; i < m; ++i) {
      err[i] = features[i].base_weight > 0 && reprojection(features[i], mo, rotation, options.focal_px, &e, nullptr)
                   ? e.norm()
                   : std::numeric_limits<double>::infinity();
    }
  };
  auto normal_equations = [&](const Motion& mo, MotionMatrix* h, Motion* g) {
    const Eigen::Vector2d off_prior = mo.tail<2>() - tilt_prior_mean;
    double cost = tilt_prior.dot(off_prior.cwiseAbs2());
    if (h) h->setZero();
    if (g) g->setZero();
    if (h) h->diagonal().tail<2>() = tilt_prior;
    if (g) g->tail<2>() = tilt_prior.cwiseProduct(off_prior);
    const MotionRotation rotation(mo);
    Eigen::Vector2d e;
    Eigen::Matrix<double, 2, 6> j;
    for (size_t i = 0; i < m; ++i) {
      if (w[i] <= 0) continue;
      if (!reprojection(features[i], mo, rotation, options.focal_px, &e, h ? &j : nullptr)) {
        cost += w[i] * 1e12;
        continue;
      }
      cost += w[i] * e.squaredNorm();
      if (h) {
        // J^T w J: the lower triangle (what LDLT reads; with three entries
        // above it) in column blocks of fixed size, mirrored below; the same
        // products in the same order as the full outer product, in 24 of 36.
        const Eigen::Matrix<double, 6, 2> weighted = w[i] * j.transpose();
        for (int c = 0; c < 2; ++c) h->col(c) += weighted.col(0) * j(0, c) + weighted.col(1) * j(1, c);
        for (int c = 2; c < 4; ++c) {
          h->col(c).tail<4>() += weighted.col(0).tail<4>() * j(0, c) + weighted.col(1).tail<4>() * j(1, c);
        }
        for (int c = 4; c < 6; ++c) {
          h->col(c).tail<2>() += weighted.col(0).tail<2>() * j(0, c) + weighted.col(1).tail<2>() * j(1, c);
        }
        *g += weighted * e;
      }
    }
    if (h) h->triangularView<Eigen::StrictlyUpper>() = h->transpose();
    return cost;
  };
  const double min_threshold_px = options.min_threshold_px * options.pixel_scale();
  const double max_threshold_px = options.max_threshold_px * options.pixel_scale();
  const int min_used = std::max(options.min_features, 4);
  // The LM step of the unknowns fitted (the tilt's stays 0 where it is not
  // fitted); false where the damped system is not positive definite.
  auto lm_step = [&](const MotionMatrix& h, const Motion& g, double lambda, Motion* step) {
    step->setZero();
    MotionMatrix a = h;
    a.diagonal() *= 1.0 + lambda;
    if (fit_tilt) {
      const Eigen::LDLT<MotionMatrix> ldlt(a);
      if (ldlt.info() != Eigen::Success || !ldlt.isPositive()) return false;
      *step = ldlt.solve(g);
      return true;
    }
    const Eigen::LDLT<Eigen::Matrix4d> ldlt(a.topLeftCorner<4, 4>());
    if (ldlt.info() != Eigen::Success || !ldlt.isPositive()) return false;
    step->head<4>() = ldlt.solve(g.head<4>());
    return true;
  };
  // How far the motion moved: translation over the range, angles in rad.
  auto change_between = [&](const Motion& a, const Motion& b) {
    return std::max((a - b).head<3>().cwiseAbs().maxCoeff() / pair.curr_range_m,
                    (a - b).tail<3>().cwiseAbs().maxCoeff());
  };
  bool converged = false, degenerate = false;
  int iterations = 0;
  for (int outer = 0; outer < options.max_robust_iterations && !degenerate; ++outer) {
    errors(motion);
    std::vector<double> finite_err;
    for (size_t i = 0; i < m; ++i) {
      if (features[i].base_weight > 0) finite_err.push_back(err[i]);
    }
    // The start is the patch's solution, which relief can leave pixels off: no cap at first.
    double threshold = robust_cut_px(options.threshold_mad_scale, min_threshold_px, finite_err);
    if (outer > 0) threshold = std::min(threshold, max_threshold_px);
    int used = 0;
    for (size_t i = 0; i < m; ++i) {
      const double e = err[i] / threshold;
      w[i] = e < 1.0 ? features[i].base_weight * (1 - e * e) * (1 - e * e) : 0.0;
      used += w[i] > 0;
    }
    if (used < min_used) break;
    if (fit_tilt) {
      double sum_sq = 0, sum_w = 0;
      for (size_t i = 0; i < m; ++i) {
        if (w[i] <= 0) continue;
        sum_sq += w[i] * err[i] * err[i];
        sum_w += w[i];
      }
      image_variance = std::max(sum_sq / sum_w, 1e-12);
      tilt_prior = image_variance * tilt_prior_variance.cwiseInverse();
    }
    const Motion before = motion;
    double lambda = 1e-3;
    MotionMatrix h;
    Motion g;
    double cost = normal_equations(motion, &h, &g);
    for (int it = 0; it < options.max_lm_iterations; ++it) {
      Motion step;
      if (!lm_step(h, g, lambda, &step)) {
        degenerate = true;
        break;
      }
      const Motion trial = motion - step;
      if (!trial.allFinite()) {
        degenerate = true;
        break;
      }
      MotionMatrix trial_h;
      Motion trial_g;
      const double trial_cost = normal_equations(trial, &trial_h, &trial_g);
      if (trial_cost <= cost) {
        const double change = change_between(trial, motion);
        motion = trial;
        cost = trial_cost;
        h = trial_h;
        g = trial_g;
        ++iterations;
        lambda = std::max(lambda * 0.1, 1e-12);
        if (change < 0.1 * options.convergence_tolerance) break;
      } else {
        lambda *= 10.0;
        if (lambda > 1e10) break;
      }
    }
    if (change_between(motion, before) < options.convergence_tolerance && threshold <= max_threshold_px) {
      converged = true;
      break;
    }
  }
  // The filter: curr's tilt error from prev's, the pair's relative tilt and
  // the INS (DERIVATION.md section 13); the motion then moved, along its
  // covariance with the tilt, to the relative tilt that is the difference of
  // the two frames' errors, so the sideways motion a tilt error leaves still
  // telescopes over the pairs.
  Eigen::Vector2d curr_tilt = pair.prev_tilt, curr_tilt_variance = pair.prev_tilt_variance;
  if (fit_tilt && !degenerate) {
    MotionMatrix h;
    Motion g;
    normal_equations(motion, &h, &g);
    const Eigen::LDLT<MotionMatrix> ldlt(h);
    if (ldlt.info() == Eigen::Success && ldlt.isPositive()) {
      const MotionMatrix cov = image_variance * ldlt.solve(MotionMatrix::Identity());
      const Eigen::Vector2d gain = ins_tilt_variance * tilt_prior_variance.cwiseInverse();
      curr_tilt = gain.cwiseProduct(pair.prev_tilt + motion.tail<2>());
      curr_tilt_variance =
          gain.cwiseProduct(prev_tilt_variance) + gain.cwiseAbs2().cwiseProduct(cov.diagonal().tail<2>());
      const Eigen::Vector2d used = curr_tilt - pair.prev_tilt;
      const Eigen::Matrix2d tilt_cov = cov.bottomRightCorner<2, 2>();
      motion.head<4>() += cov.topRightCorner<4, 2>() * tilt_cov.ldlt().solve(used - motion.tail<2>());
      motion.tail<2>() = used;
    } else {
      curr_tilt = pair.prev_tilt + motion.tail<2>();
    }
  }

  Estimate est;
  est.curr_tilt = curr_tilt;
  est.curr_tilt_variance = curr_tilt_variance;
  est.weights.assign(n, 0.0);
  est.used_own_depth.assign(n, 0);
  est.translation = motion.head<3>();
  est.dyaw = wrap_angle(motion(3));
  est.relative_tilt = motion.tail<2>();
  est.ground_roll = patch.ground_roll;
  est.ground_pitch = patch.ground_pitch;
  est.altitude_m = prev_vertical_height(normal, plane_offset, est.dyaw, est.translation);
  est.iterations = patch.iterations + iterations;
  est.depth_scale = scale;
  est.own_depths_used = true;
  est.scale_carried = scale_carried;
  est.scale_variance = scale_sigma * scale_sigma;
  est.patch_misfit = misfit;
  est.anchor_model_variance = scale_carried ? 0.0 : model_variance;
  errors(motion);
  double sum_sq = 0, sum_w = 0;
  for (size_t i = 0; i < m; ++i) {
    const int k = features[i].index;
    est.weights[k] = w[i];
    est.used_own_depth[k] = features[i].own;
    if (w[i] <= 0) continue;
    ++est.inliers;
    sum_sq += err[i] * err[i];
    sum_w += w[i];
  }
  est.outliers = static_cast<int>(n) - est.inliers;
  est.residual_rms_px = est.inliers > 0 ? std::sqrt(sum_sq / est.inliers) : 0.0;
  if (est.inliers < min_used) est.quality |= kTooFewFeatures;
  if (!(est.residual_rms_px <= options.max_residual_rms_px * options.pixel_scale()) ||
      est.inliers < options.min_inlier_fraction * static_cast<double>(n)) {
    est.quality |= kHighResidual;
  }
  if (!converged || degenerate) est.quality |= kNotConverged;
  // Covariance: sigma^2 (J^T W J)^-1 of (dx, dy, dz, dyaw), the relative
  // tilt (where fitted, with its prior) marginalised out; the ground
  // attitude's from the patch; the anchor's scale uncertainty along t.
  MotionMatrix h;
  Motion g;
  const double data_cost =
      normal_equations(motion, &h, &g) - tilt_prior.dot((motion.tail<2>() - tilt_prior_mean).cwiseAbs2());
  est.covariance = patch.covariance;
  est.covariance.topLeftCorner<4, 4>().setZero();
  est.covariance.block<4, 2>(0, 4).setZero();
  est.covariance.block<2, 4>(4, 0).setZero();
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(h.topLeftCorner(unknowns, unknowns));
  if (est.inliers > unknowns && sum_w > 0 && ldlt.info() == Eigen::Success && ldlt.isPositive()) {
    const double sigma2 = data_cost / sum_w * est.inliers / (est.inliers - unknowns);
    const Eigen::MatrixXd inverse = ldlt.solve(Eigen::MatrixXd::Identity(unknowns, unknowns));
    est.covariance.topLeftCorner<4, 4>() = sigma2 * inverse.topLeftCorner<4, 4>();
    est.covariance.topLeftCorner<3, 3>() += scale_sigma * scale_sigma * est.translation * est.translation.transpose();
  } else {
    est.quality |= kNotConverged;
  }
  return est;
}

}  // namespace nadir::vo
