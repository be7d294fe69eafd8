#include "processes/vo_solver/translation_solver.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>
#include <utility>

#include "common/geometry.h"
#include "processes/vo_solver/plane_model.h"
#include "processes/vo_solver/solver_support.h"

namespace nadir::vo {

Variant variant_from_name(const std::string& name) {
  if (name == "paper") return Variant::kPaper;
  if (name == "level_ground") return Variant::kLevelGround;
  if (name == "homography") return Variant::kHomography;
  if (name == "flow") return Variant::kFlow;
  if (name == "feature_depth") return Variant::kFeatureDepth;
  throw std::invalid_argument("unknown solver variant '" + name +
                              "' (allowed: paper, level_ground, homography, flow, feature_depth)");
}

std::string variant_name(Variant variant) {
  switch (variant) {
    case Variant::kPaper: return "paper";
    case Variant::kLevelGround: return "level_ground";
    case Variant::kHomography: return "homography";
    case Variant::kFlow: return "flow";
    case Variant::kFeatureDepth: return "feature_depth";
  }
  return "unknown";
}

namespace {
void require(bool ok, const std::string& field, const std::string& range) {
  if (!ok) throw std::invalid_argument("solver option " + field + " must be " + range);
}
}  // namespace

void SolverOptions::Check() const {
  require(focal_px > 1 && focal_px < 1e5, "focal_px", "in (1, 1e5)");
  require(threshold_focal_px > 1 && threshold_focal_px < 1e5, "threshold_focal_px", "in (1, 1e5)");
  require(min_features >= 5 && min_features <= 10000, "min_features", "in [5, 10000]");
  require(max_robust_iterations >= 1 && max_robust_iterations <= 100, "max_robust_iterations", "in [1, 100]");
  require(max_lm_iterations >= 1 && max_lm_iterations <= 100, "max_lm_iterations", "in [1, 100]");
  require(min_threshold_px > 0 && min_threshold_px <= 100, "min_threshold_px", "in (0, 100]");
  require(threshold_mad_scale >= 1 && threshold_mad_scale <= 20, "threshold_mad_scale", "in [1, 20]");
  require(max_threshold_px >= min_threshold_px && max_threshold_px <= 1000, "max_threshold_px",
          "in [min_threshold_px, 1000]");
  require(convergence_tolerance > 0 && convergence_tolerance <= 1e-2, "convergence_tolerance", "in (0, 1e-2]");
  require(convergence_sigma_fraction >= 0 && convergence_sigma_fraction <= 0.5, "convergence_sigma_fraction",
          "in [0, 0.5]");
  require(max_residual_rms_px > 0 && max_residual_rms_px <= 100, "max_residual_rms_px", "in (0, 100]");
  require(min_inlier_fraction >= 0 && min_inlier_fraction <= 1, "min_inlier_fraction", "in [0, 1]");
  require(homography_ransac_px > 0 && homography_ransac_px <= 100, "homography_ransac_px", "in (0, 100]");
  layers.Check();
  feature_depth.Check();
}

double SolverOptions::pixel_scale() const { return std::max(1.0, focal_px / threshold_focal_px); }

namespace {

// The last line of defence, whatever a variant made of a degenerate pair
// (features in a line, a beam that never meets the ground, attitude at the
// edge of the range): nothing non-finite leaves the solver. A motion that is
// not finite becomes none at all with an unknown (huge) covariance, flagged
// not converged, which every consumer rejects.
void make_finite(Estimate* e) {
  constexpr double kUnknownVariance = 1e6;     // m^2, rad^2: "no information"
  constexpr double kUnknownResidualPx = 1e6;
  const bool motion_finite = e->translation.allFinite() && std::isfinite(e->dyaw) && std::isfinite(e->ground_roll) &&
                             std::isfinite(e->ground_pitch) && std::isfinite(e->altitude_m);
  if (!motion_finite) {
    e->translation.setZero();
    e->dyaw = e->ground_roll = e->ground_pitch = e->altitude_m = 0.0;
  }
  if (!motion_finite || !e->covariance.allFinite()) {
    e->covariance = Eigen::Matrix<double, 6, 6>::Identity() * kUnknownVariance;
    e->quality |= kNotConverged;
  }
  if (!std::isfinite(e->residual_rms_px)) {
    e->residual_rms_px = kUnknownResidualPx;
    e->quality |= kHighResidual;
  }
}

Estimate solve_variant(const FramePair& pair, const SolverOptions& options) {
  switch (options.variant) {
    case Variant::kPaper: return solve_paper(pair, options, true);
    case Variant::kLevelGround: return solve_paper(pair, options, false);
    case Variant::kHomography: return solve_homography(pair, options);
    case Variant::kFlow: return solve_flow(pair, options);
    case Variant::kFeatureDepth: return solve_feature_depth(pair, options);
  }
  return solve_paper(pair, options, true);
}

}  // namespace

Estimate solve(const FramePair& pair, const SolverOptions& options) {
  Estimate estimate = solve_variant(pair, options);
  make_finite(&estimate);
  return estimate;
}

namespace {

// Everything Algorithm 1 iterates on.
struct PaperProblem {
  std::vector<LevelFeature> features;
  std::vector<int> index;  // feature -> index in the input pair
  std::vector<Eigen::Vector2d> prev_measured;
  // Turns the residual (metres) into the image error perpendicular to the
  // feature's radial line in V^{k-1}: 1 / (height |u_xy|), |u_xy| floored so a
  // feature at the nadir (which carries no information here) cannot dominate.
  std::vector<double> residual_scale;
  Eigen::Matrix3d prev_level_from_camera;
  PlaneGeometry plane;
  double height = 0;  // nominal vertical height (range * beam.z), scales residuals
  int num_params = 5;
};

// Weighted normal equations of the scaled residuals.
double accumulate(const PaperProblem& problem, const Params& params, const std::vector<double>& w,
                  Eigen::Matrix<double, 5, 5>* h, Eigen::Matrix<double, 5, 1>* g) {
  double cost = 0;
  if (h) h->setZero();
  if (g) g->setZero();
  JacobianRow row;
  const ModelEval eval = make_model_eval(problem.plane, params);
  for (size_t i = 0; i < problem.features.size(); ++i) {
    if (w[i] <= 0) continue;
    const double sc = problem.residual_scale[i];
    const double r = sc * model_residual(problem.features[i], eval, params, h ? &row : nullptr);
    if (!std::isfinite(r)) {
      // The ray misses the plane at these parameters: a step there is never taken.
      cost += w[i] * 1e12;
      continue;
    }
    cost += w[i] * r * r;
    if (h) {
      row *= sc;
      const JacobianRow weighted = w[i] * row;
      // Lower triangle only (what LDLT reads), mirrored below: the same
      // products in the same order as the full outer product, in 15 of 25.
      for (int c = 0; c < 5; ++c) {
        for (int k = c; k < 5; ++k) (*h)(k, c) += weighted(k) * row(c);
      }
      *g += r * weighted.transpose();
    }
  }
  if (h) h->triangularView<Eigen::StrictlyUpper>() = h->transpose();
  return cost;
}

// dz from eq. (7): each feature's depth in V^{k-1} (least squares along its
// ray) minus its rotated depth in V^k; weighted mean with the robust weights
// times |u_xy|^2 (a feature at the nadir says nothing about dz).
double estimate_dz(const PaperProblem& problem, const Params& p, const std::vector<double>& w, double* variance) {
  const Eigen::Matrix3d rz = rot_z(p(2));
  const Eigen::Vector3d normal = ground_normal(problem.plane, p(3), p(4));
  const double plane_distance = problem.plane.range_m * normal.dot(problem.plane.beam);
  double sum_v = 0, sum_vz = 0;
  std::vector<std::pair<double, double>> samples;
  if (variance) samples.reserve(problem.features.size());
  for (size_t i = 0; i < problem.features.size(); ++i) {
    if (w[i] <= 0) continue;
    const LevelFeature& f = problem.features[i];
    Eigen::Vector3d point;
    if (!ground_point_at(plane_distance, normal, f.v, &point)) continue;
    const Eigen::Vector3d q = rz * point;
    const double ux = f.u.x(), uy = f.u.y();
    const double uu = ux * ux + uy * uy;
    if (uu < 1e-12) continue;
    const double depth_prev = (ux * (q.x() + p(0)) + uy * (q.y() + p(1))) / uu;
    const double dz_i = depth_prev - q.z();
    const double v = w[i] * uu;
    sum_v += v;
    sum_vz += v * dz_i;
    if (variance) samples.emplace_back(v, dz_i);
  }
  if (sum_v <= 0) {
    if (variance) *variance = std::numeric_limits<double>::infinity();
    return 0.0;
  }
  const double dz = sum_vz / sum_v;
  if (variance) {
    double spread = 0;
    for (const auto& [v, dz_i] : samples) spread += v * v * (dz_i - dz) * (dz_i - dz);
    const double n = static_cast<double>(samples.size());
    *variance = n > 1 ? spread / (sum_v * sum_v) * n / (n - 1) : std::numeric_limits<double>::infinity();
  }
  return dz;
}

// Covariance of the fitted unknowns, sigma^2 (J^T W J)^-1 with sigma^2 the
// weighted residual variance over `inliers` (np x np; zero when there are no
// more inliers than unknowns). False when the normal equations are singular.
bool parameter_covariance(const PaperProblem& problem, const Params& params, const std::vector<double>& w,
                          int inliers, Eigen::MatrixXd* covariance) {
  const int np = problem.num_params;
  *covariance = Eigen::MatrixXd::Zero(np, np);
  if (inliers <= np) return true;
  Eigen::Matrix<double, 5, 5> h;
  Eigen::Matrix<double, 5, 1> g;
  const double cost = accumulate(problem, params, w, &h, &g);
  double sum_w = 0;
  for (double wi : w) sum_w += wi;
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(h.topLeftCorner(np, np));
  if (ldlt.info() != Eigen::Success || !ldlt.isPositive()) return false;
  const double sigma2 = cost / sum_w * inliers / (inliers - np);
  *covariance = sigma2 * ldlt.solve(Eigen::MatrixXd::Identity(np, np));
  return true;
}

// Whether one reweighting moved the fit by nothing that matters: each
// unknown by less than `tolerance` (translation / height, rad), or by less
// than `sigma_fraction` of its own standard deviation. The second test ends
// the loop where the ground tilt is barely observable (little parallax: a
// short step, or INS levelling noise that cancels the apparent motion) and
// the reweighting keeps nudging it by amounts far inside its uncertainty;
// without it such pairs were flagged NOT_CONVERGED and dropped, and the
// levelling error they share with their neighbours no longer cancelled.
bool negligible_change(const PaperProblem& problem, const Params& before, const Eigen::Vector3d& normal_before,
                       const Params& after, const std::vector<double>& w, double tolerance, double sigma_fraction) {
  const Eigen::Vector3d normal_change = ground_normal(problem.plane, 0, 0) - normal_before;
  const double change = std::max({(after.head<2>() - before.head<2>()).cwiseAbs().maxCoeff() / problem.height,
                                  std::abs(after(2) - before(2)), normal_change.cwiseAbs().maxCoeff()});
  if (change < tolerance) return true;
  if (!(sigma_fraction > 0)) return false;
  const int inliers = static_cast<int>(std::count_if(w.begin(), w.end(), [](double wi) { return wi > 0; }));
  Eigen::MatrixXd covariance;
  if (!parameter_covariance(problem, after, w, inliers, &covariance) || inliers <= problem.num_params) return false;
  const Eigen::VectorXd sigma = covariance.diagonal().cwiseMax(0.0).cwiseSqrt();
  for (int j = 0; j < 3; ++j) {
    if (std::abs(after(j) - before(j)) >= sigma_fraction * sigma(j)) return false;
  }
  if (problem.num_params == 5 && normal_change.cwiseAbs().maxCoeff() >= sigma_fraction * std::min(sigma(3), sigma(4))) {
    return false;
  }
  return true;
}

// Image reprojection error (pixels) of each feature in the prev image.
void reprojection_errors(const PaperProblem& problem, const Params& p, double dz, double focal_px,
                         std::vector<double>* ire) {
  ire->resize(problem.features.size());
  const Eigen::Matrix3d camera_from_level = problem.prev_level_from_camera.transpose();
  // prev camera <- V^k ground point: rotate by dyaw, shift by the translation.
  const Eigen::Matrix3d rotation = camera_from_level * rot_z(p(2));
  const Eigen::Vector3d shift = camera_from_level * Eigen::Vector3d(p(0), p(1), dz);
  const Eigen::Vector3d normal = ground_normal(problem.plane, p(3), p(4));
  const double plane_distance = problem.plane.range_m * normal.dot(problem.plane.beam);
  for (size_t i = 0; i < problem.features.size(); ++i) {
    Eigen::Vector3d point;
    (*ire)[i] = std::numeric_limits<double>::infinity();
    if (!ground_point_at(plane_distance, normal, problem.features[i].v, &point)) continue;
    (*ire)[i] = image_error_px(rotation * point + shift, problem.prev_measured[i], focal_px);
  }
}

// Linear method (eq. 13): tilt 0, yaw linearized about `dyaw_start` (the INS
// heading change; DERIVATION.md section 4a): the curr rays are pre-rotated by
// it, so only the small difference to it is linearized and any turn between
// the frames, up to +-180 deg, starts near the solution. SVD least squares on m x 3.
bool linear_initialization(const PaperProblem& problem, double dyaw_start, Params* params) {
  const int m = static_cast<int>(problem.features.size());
  const double d = problem.plane.range_m * problem.plane.beam.z();
  const double c = std::cos(dyaw_start), s = std::sin(dyaw_start);
  Eigen::MatrixXd a(m, 3);
  Eigen::VectorXd b(m);
  for (int i = 0; i < m; ++i) {
    const LevelFeature& f = problem.features[i];
    const double vx = c * f.v.x() - s * f.v.y(), vy = s * f.v.x() + c * f.v.y();
    a(i, 0) = -f.u.y();
    a(i, 1) = f.u.x();
    a(i, 2) = d * (f.u.x() * vx + f.u.y() * vy);
    b(i) = -d * (f.u.x() * vy - f.u.y() * vx);
  }
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(a, Eigen::ComputeThinU | Eigen::ComputeThinV);
  const auto& sv = svd.singularValues();
  if (!(sv(2) > 1e-9 * sv(0))) return false;
  const Eigen::Vector3d x = svd.solve(b);
  params->setZero();
  params->head<3>() = x;
  (*params)(2) += dyaw_start;
  return x.allFinite();
}

// One Levenberg-Marquardt run (eq. 15) at fixed weights; re-levels the
// virtual camera after every accepted step (Algorithm 1 lines 10-12).
int levenberg_marquardt(PaperProblem* problem, Params* params, const std::vector<double>& w,
                        const SolverOptions& options, double* damping, bool* degenerate) {
  const int np = problem->num_params;
  double& lambda = *damping;
  int iterations = 0;
  Eigen::Matrix<double, 5, 5> h;
  Eigen::Matrix<double, 5, 1> g;
  double cost = accumulate(*problem, *params, w, &h, &g);
  for (int it = 0; it < options.max_lm_iterations; ++it) {
    Eigen::MatrixXd a = h.topLeftCorner(np, np);
    a.diagonal() *= (1.0 + lambda);
    const Eigen::LDLT<Eigen::MatrixXd> ldlt(a);
    if (ldlt.info() != Eigen::Success || !ldlt.isPositive()) {
      *degenerate = true;
      return iterations;
    }
    const Eigen::VectorXd step = ldlt.solve(-g.head(np));
    if (!step.allFinite()) {
      *degenerate = true;
      return iterations;
    }
    Params trial = *params;
    trial.head(np) += step;
    PlaneGeometry saved = problem->plane;
    if (np == 5) {
      // Re-level: fold the tilt increment into the virtual camera, restart it at 0.
      problem->plane.relevel = ground_relevel(problem->plane, trial(3), trial(4));
      trial(3) = trial(4) = 0;
    }
    // The normal equations at the trial too: most steps are accepted, and
    // then they are the next step's (the cost is the same sum either way).
    Eigen::Matrix<double, 5, 5> trial_h;
    Eigen::Matrix<double, 5, 1> trial_g;
    const double trial_cost = accumulate(*problem, trial, w, &trial_h, &trial_g);
    if (trial_cost <= cost) {
      *params = trial;
      ++iterations;
      lambda = std::max(lambda * 0.1, 1e-12);
      const double change = std::max(step.head<2>().cwiseAbs().maxCoeff() / problem->height,
                                     step.tail(np - 2).cwiseAbs().maxCoeff());
      cost = trial_cost;
      h = trial_h;
      g = trial_g;
      if (change < 0.1 * options.convergence_tolerance) break;
    } else {
      problem->plane = saved;
      lambda *= 10.0;
      if (lambda > 1e10) break;  // at a minimum to machine precision
    }
  }
  return iterations;
}

// A start near the solution (the reverse of a solved pair): no linear
// initialization, weights and ground attitude taken over.
struct WarmStart {
  Params params = Params::Zero();
  Eigen::Matrix3d relevel = Eigen::Matrix3d::Identity();
  const std::vector<double>* weights = nullptr;  // per input feature
};

// The fitted state of Algorithm 1 on one pair, before any output is derived.
struct PaperFit {
  Estimate failed;  // the flagged estimate when the fit could not run (ok == false)
  bool ok = false;
  size_t num_input = 0;
  PaperProblem problem;
  Params params = Params::Zero();
  std::vector<double> w;
  int iterations = 0;
  bool converged = false, degenerate = false;
};

// The share of the features that the cap on the cut removes: those with a
// reprojection error above max_threshold_px and inside the cut that the
// robust spread alone sets.
double share_cut_by_cap(const PaperProblem& problem, const Params& params, double dz, const SolverOptions& options,
                        double min_threshold_px, double max_threshold_px, std::vector<double>* ire) {
  reprojection_errors(problem, params, dz, options.focal_px, ire);
  if (ire->empty()) return 0.0;
  const double wide = robust_cut_px(options.threshold_mad_scale, min_threshold_px, *ire);
  const auto cut = std::count_if(ire->begin(), ire->end(), [&](double e) { return e > max_threshold_px && e < wide; });
  return static_cast<double>(cut) / static_cast<double>(ire->size());
}

PaperFit fit_paper(const FramePair& pair, const SolverOptions& options, bool estimate_tilt, const WarmStart* warm) {
  PaperFit fit;
  Estimate& est = fit.failed;
  if (!start_estimate(pair, &est)) return fit;
  const size_t n = pair.prev_norm.size();
  fit.num_input = n;
  PaperProblem& problem = fit.problem;
  problem.num_params = estimate_tilt ? 5 : 3;
  problem.prev_level_from_camera = level_from_camera(pair.prev_roll, pair.prev_pitch, pair.body_from_camera);
  const Eigen::Matrix3d curr_level_from_camera =
      level_from_camera(pair.curr_roll, pair.curr_pitch, pair.body_from_camera);
  const Eigen::Matrix3d curr_level_from_body = level_from_camera(pair.curr_roll, pair.curr_pitch,
                                                                 Eigen::Matrix3d::Identity());
  problem.plane.range_m = pair.curr_range_m;
  problem.plane.beam = (curr_level_from_body * pair.curr_beam_body).normalized();
  problem.height = pair.curr_range_m * problem.plane.beam.z();
  if (!(pair.curr_range_m > 0) || !std::isfinite(pair.curr_range_m) || !(problem.height > 0) ||
      !problem.plane.beam.allFinite()) {
    est.quality |= kNoAltimeter;
    return fit;
  }
  for (size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d u = problem.prev_level_from_camera * pair.prev_norm[i].homogeneous();
    const Eigen::Vector3d v = curr_level_from_camera * pair.curr_norm[i].homogeneous();
    if (!u.allFinite() || !v.allFinite() || u.z() < 1e-6 || v.z() < 1e-6) continue;
    problem.features.push_back({u / u.z(), v / v.z()});
    problem.index.push_back(static_cast<int>(i));
    problem.prev_measured.push_back(pair.prev_norm[i]);
  }
  for (const LevelFeature& f : problem.features) {
    problem.residual_scale.push_back(1.0 / (problem.height * std::max(0.05, std::hypot(f.u.x(), f.u.y()))));
  }
  const int m = static_cast<int>(problem.features.size());
  if (m < std::max(options.min_features, problem.num_params)) {
    est.quality |= kTooFewFeatures;
    est.outliers = static_cast<int>(n);
    return fit;
  }

  Params& params = fit.params;
  std::vector<double>& w = fit.w;
  w.assign(m, 1.0);
  std::vector<double> ire;
  if (warm) {
    params = warm->params;
    if (estimate_tilt) problem.plane.relevel = warm->relevel;
    for (int i = 0; i < m; ++i) w[i] = (*warm->weights)[problem.index[i]];
  } else if (!linear_initialization(problem,
                                    options.dyaw_start_from_ins ? angle_difference(pair.curr_yaw, pair.prev_yaw) : 0.0,
                                    &params)) {
    est.quality |= kNotConverged;
    return fit;
  }
  double dz = estimate_dz(problem, params, w, nullptr);
  const double min_threshold_px = options.min_threshold_px * options.pixel_scale();
  const double max_threshold_px = options.max_threshold_px * options.pixel_scale();
  double damping = 1e-3;
  // From the second reweighting on, the cut is capped at max_threshold_px, so
  // that a second depth layer (tree tops) cannot widen it enough to get in.
  // A converged fit whose cap cut off less than a layer's share
  // (layers.min_fraction) of the features that the robust spread alone would
  // keep has no second layer: the spread is the model's own error (a
  // levelling error of a degree or more), and the cap would cut the features
  // that balance the fit. The cap is then lifted for good. Should the
  // uncapped fit not settle within its own budget, a settled capped fit
  // stands (the lift never costs a converged pair).
  bool cap_lifted = false;
  struct Snapshot {
    Params params;
    std::vector<double> w;
    PlaneGeometry plane;  // its relevel holds the tilt the params are relative to
  };
  std::optional<Snapshot> settled_capped;
  for (int outer = 0; outer < options.max_robust_iterations && !fit.degenerate; ++outer) {
    // Line 8: weights from the image reprojection errors (Tukey biweight,
    // zero beyond a threshold that shrinks with the robust spread of the IREs).
    reprojection_errors(problem, params, dz, options.focal_px, &ire);
    double threshold = robust_cut_px(options.threshold_mad_scale, min_threshold_px, ire);
    const bool capped = outer > 0 && !cap_lifted;
    if (capped) threshold = std::min(threshold, max_threshold_px);
    int used = 0;
    for (int i = 0; i < m; ++i) {
      const double e = ire[i] / threshold;
      w[i] = e < 1.0 ? (1 - e * e) * (1 - e * e) : 0.0;
      used += w[i] > 0;
    }
    if (used < std::max(options.min_features, problem.num_params)) break;
    const Params before = params;
    const Eigen::Vector3d normal_before = ground_normal(problem.plane, 0, 0);
    fit.iterations += levenberg_marquardt(&problem, &params, w, options, &damping, &fit.degenerate);
    dz = estimate_dz(problem, params, w, nullptr);
    const bool settled = (outer > 0 || threshold <= max_threshold_px) &&
                         negligible_change(problem, before, normal_before, params, w, options.convergence_tolerance,
                                           options.convergence_sigma_fraction);
    // Settled, or out of iterations (features at the cap can flip in and
    // out): is the cap cutting a layer or the spread's tail?
    if (capped && (settled || outer + 1 == options.max_robust_iterations)) {
      const double cut = share_cut_by_cap(problem, params, dz, options, min_threshold_px, max_threshold_px, &ire);
      if (cut > 0 && cut < options.layers.min_fraction) {
        if (settled) settled_capped = Snapshot{params, w, problem.plane};
        cap_lifted = true;
        outer = 0;  // the uncapped fit starts here with a budget of its own (once: the lift is for good)
        continue;
      }
    }
    if (settled) {
      fit.converged = true;
      break;
    }
  }
  if (!fit.converged && settled_capped) {
    params = settled_capped->params;
    w = settled_capped->w;
    problem.plane = settled_capped->plane;
    fit.degenerate = false;  // it was not when it settled
    fit.converged = true;
  }
  fit.ok = true;
  return fit;
}

// Every output of a fit, for the estimate that is published: the fitted dx,
// dy, dyaw, tilt with dz from eq. (7) (or `published_dz` when the dz mode
// combines two solves). Altitude, covariance, residual, inlier counts and
// quality bits all describe that estimate.
// Covariance of a fit's (dx, dy, dz, dyaw, tilt): sigma^2 (J^T W J)^-1 for
// the fitted unknowns, mapped to the output order; dz from the spread of its
// weighted mean. It depends on the fit and its inlier count only, not on the
// published dz, so the symmetric mode computes it once for the forward fit.
struct FitCovariance {
  Eigen::Matrix<double, 6, 6> covariance = Eigen::Matrix<double, 6, 6>::Zero();
  bool degenerate = false;
};

FitCovariance fit_covariance(const PaperFit& fit, int inliers) {
  FitCovariance out;
  const PaperProblem& problem = fit.problem;
  const Params& params = fit.params;
  const std::vector<double>& w = fit.w;
  const int m = static_cast<int>(problem.features.size());
  const int np = problem.num_params;
  bool& degenerate = out.degenerate;
  double dz_variance = 0;
  estimate_dz(problem, params, w, &dz_variance);
  const Eigen::Vector3d normal = ground_normal(problem.plane, 0, 0);
  // Covariance: sigma^2 (J^T W J)^-1 for the fitted unknowns, mapped to the
  // output order; dz from the spread of its weighted mean.
  Eigen::MatrixXd cov_p;
  if (!parameter_covariance(problem, params, w, inliers, &cov_p)) degenerate = true;
  Eigen::Matrix<double, 6, 5> map = Eigen::Matrix<double, 6, 5>::Zero();
  map(0, 0) = 1;
  map(1, 1) = 1;
  map(3, 2) = 1;
  if (np == 5) {
    const Eigen::Vector3d dn_droll = -problem.plane.relevel.col(1);
    const Eigen::Vector3d dn_dpitch = problem.plane.relevel.col(0);
    const double xz = normal.x() * normal.x() + normal.z() * normal.z();
    const double root = std::sqrt(std::max(1e-12, 1 - normal.y() * normal.y()));
    map(4, 3) = -dn_droll.y() / root;
    map(4, 4) = -dn_dpitch.y() / root;
    map(5, 3) = (normal.z() * dn_droll.x() - normal.x() * dn_droll.z()) / xz;
    map(5, 4) = (normal.z() * dn_dpitch.x() - normal.x() * dn_dpitch.z()) / xz;
  }
  // dz depends on the other unknowns through the ground points: propagate
  // their covariance with a numerical gradient, and add the spread of the mean.
  for (int j = 0; j < np; ++j) {
    if (j < 2) {
      // dz is linear in dx, dy: d dz / d dx = sum(w u_x) / sum(w |u_xy|^2).
      double num = 0, den = 0;
      for (int i = 0; i < m; ++i) {
        const LevelFeature& f = problem.features[i];
        num += w[i] * (j == 0 ? f.u.x() : f.u.y());
        den += w[i] * (f.u.x() * f.u.x() + f.u.y() * f.u.y());
      }
      map(2, j) = den > 0 ? num / den : 0.0;
      continue;
    }
    const double step = 1e-6;
    Params plus = params, minus = params;
    plus(j) += step;
    minus(j) -= step;
    map(2, j) = (estimate_dz(problem, plus, w, nullptr) - estimate_dz(problem, minus, w, nullptr)) / (2 * step);
  }
  out.covariance = map.leftCols(np) * cov_p * map.leftCols(np).transpose();
  out.covariance(2, 2) += dz_variance;

  return out;
}

enum class Scoring { kPublished, kIntermediate };

Estimate finish_paper(const PaperFit& fit, const FramePair& pair, const SolverOptions& options,
                      const double* published_dz, Scoring scoring, const FitCovariance* cached = nullptr) {
  if (!fit.ok) return fit.failed;
  Estimate est = fit.failed;
  const PaperProblem& problem = fit.problem;
  const Params& params = fit.params;
  const std::vector<double>& w = fit.w;
  const int m = static_cast<int>(problem.features.size());
  est.iterations = fit.iterations;
  bool degenerate = fit.degenerate;
  const double fitted_dz = estimate_dz(problem, params, w, nullptr);
  for (int i = 0; i < m; ++i) est.weights[problem.index[i]] = w[i];
  est.translation = Eigen::Vector3d(params(0), params(1), published_dz ? *published_dz : fitted_dz);
  // The fit's own heading change (started at the INS one), wrapped to (-pi, pi].
  est.dyaw = wrap_angle(params(2));
  const Eigen::Vector3d normal = ground_normal(problem.plane, 0, 0);
  tilt_from_normal(normal, &est.ground_roll, &est.ground_pitch);
  est.altitude_m = prev_vertical_height(normal, problem.plane.range_m * normal.dot(problem.plane.beam), est.dyaw,
                                        est.translation);
  const int np = problem.num_params;
  if (scoring == Scoring::kPublished) {
    score_estimate(pair, options, std::max(options.min_features, np), &est);
  } else {
    // An intermediate solve of the symmetric mode: only its dz, sigma and failure bits are used.
    est.inliers = static_cast<int>(std::count_if(w.begin(), w.end(), [](double wi) { return wi > 0; }));
    if (est.inliers < std::max(options.min_features, np)) est.quality |= kTooFewFeatures;
  }

  const FitCovariance cov = cached ? *cached : fit_covariance(fit, est.inliers);
  est.covariance = cov.covariance;
  if (cov.degenerate) degenerate = true;
  if (!fit.converged || degenerate) est.quality |= kNotConverged;
  if (!est.translation.allFinite() || !std::isfinite(est.dyaw)) est.quality |= kNotConverged;
  return est;
}

// dz from eq. (7) of the pair and of the pair reversed in time (whose dz is
// -dz): their mean cancels the term h * delta * epsilon that a relative
// levelling error delta = eps(k-1) - eps(k) leaves in either one
// (DERIVATION.md section 7a). The reverse solve starts from the forward
// solution. Where either solve failed, the forward one stands. Every other
// output is then derived again for the published (mean) dz.
Estimate solve_paper_symmetric(const FramePair& pair, const SolverOptions& options, bool estimate_tilt) {
  constexpr int kFailed = kTooFewFeatures | kNoAltimeter | kNotConverged | kNoAttitude;
  const PaperFit forward_fit = fit_paper(pair, options, estimate_tilt, nullptr);
  if (!forward_fit.ok) return forward_fit.failed;
  const FitCovariance forward_cov = fit_covariance(
      forward_fit, static_cast<int>(std::count_if(forward_fit.w.begin(), forward_fit.w.end(),
                                                  [](double wi) { return wi > 0; })));
  const Estimate forward =
      finish_paper(forward_fit, pair, options, nullptr, Scoring::kIntermediate, &forward_cov);
  const auto forward_alone = [&] {
    return finish_paper(forward_fit, pair, options, nullptr, Scoring::kPublished, &forward_cov);
  };
  if (forward.quality & kFailed) return forward_alone();
  // Forward: X(k-1) = Rz(dyaw) X(k) + t. Reverse: X(k) = Rz(-dyaw) (X(k-1) - t).
  WarmStart warm;
  const Eigen::Vector3d t_reverse = -(rot_z(-forward.dyaw) * forward.translation);
  warm.params << t_reverse.x(), t_reverse.y(), -forward.dyaw, 0.0, 0.0;
  // Re-levelled camera whose z axis is the forward ground normal (Ry(pitch) Rx(roll) e_z), seen from k-1.
  warm.relevel = rot_z(forward.dyaw) * level_from_camera(forward.ground_roll, forward.ground_pitch,
                                                         Eigen::Matrix3d::Identity());
  warm.weights = &forward.weights;
  const FramePair backward_pair = reversed_in_time(pair);
  const Estimate backward =
      finish_paper(fit_paper(backward_pair, options, estimate_tilt, &warm), backward_pair, options, nullptr,
                   Scoring::kIntermediate);
  if ((backward.quality & kFailed) || !std::isfinite(backward.translation.z())) return forward_alone();
  const double dz = 0.5 * (forward.translation.z() - backward.translation.z());
  Estimate published = finish_paper(forward_fit, pair, options, &dz, Scoring::kPublished, &forward_cov);
  // The two estimates share their data: their dz errors are far from
  // independent, so the variance of the mean is bounded by the mean sigma.
  // Their gap measures what neither sees in its own spread: the step times
  // the relative pitch/roll levelling error of the two frames (DERIVATION.md
  // section 7b), so half of it is added as a further standard deviation.
  const double sigma = 0.5 * (std::sqrt(forward.covariance(2, 2)) + std::sqrt(backward.covariance(2, 2)));
  const double half_gap = 0.5 * (forward.translation.z() + backward.translation.z());
  published.covariance(2, 2) = sigma * sigma + half_gap * half_gap;
  return published;
}

}  // namespace

Eigen::Matrix3d curr_from_prev(const Estimate& est) {
  const Eigen::Matrix3d tilt = (Eigen::AngleAxisd(est.relative_tilt.x(), Eigen::Vector3d::UnitX()) *
                                Eigen::AngleAxisd(est.relative_tilt.y(), Eigen::Vector3d::UnitY()))
                                   .toRotationMatrix();
  return tilt * rot_z(est.dyaw).transpose();
}

FramePair reversed_in_time(const FramePair& pair) {
  FramePair r = pair;
  std::swap(r.prev_norm, r.curr_norm);
  std::swap(r.prev_roll, r.curr_roll);
  std::swap(r.prev_pitch, r.curr_pitch);
  std::swap(r.prev_yaw, r.curr_yaw);
  std::swap(r.prev_attitude_noise_share, r.curr_attitude_noise_share);
  std::swap(r.prev_range_m, r.curr_range_m);
  std::swap(r.prev_beam_body, r.curr_beam_body);
  // Own depths are in the level frame of prev: they do not describe the reversed pair.
  r.prev_depth_m.clear();
  r.prev_depth_sigma_m.clear();
  return r;
}

Estimate solve_paper(const FramePair& pair, const SolverOptions& options, bool estimate_tilt) {
  if (options.symmetric_dz) return solve_paper_symmetric(pair, options, estimate_tilt);
  return finish_paper(fit_paper(pair, options, estimate_tilt, nullptr), pair, options, nullptr, Scoring::kPublished);
}

}  // namespace nadir::vo
