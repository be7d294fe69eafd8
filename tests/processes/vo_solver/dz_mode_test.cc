// Why forward and time-reversed dz disagree, and what each dz mode does with
// INS levelling errors that are white or correlated in time
// (DERIVATION.md section 7b). The study table printed here is the synthetic
// part of the dz-mode study (docs/research/).

#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <utility>

#include "common/geometry.h"
#include "processes/vo_solver/translation_solver.h"
#include "tests/processes/vo_solver/synthetic_scene.h"

namespace nadir::vo {
namespace {

using testing::make_scene;
using testing::Scene;
using testing::SceneSpec;

SceneSpec tilted_pair(double height_m, double step_m, uint32_t seed) {
  SceneSpec s;
  s.height_m = height_m;
  s.ground_roll = deg_to_rad(4.0);
  s.ground_pitch = deg_to_rad(-8.0);
  s.prev_roll = deg_to_rad(1.0);
  s.prev_pitch = deg_to_rad(-2.0);
  s.curr_pitch = deg_to_rad(-1.0);
  s.translation = Eigen::Vector3d(step_m, 0.5, -0.3);
  s.num_features = 200;
  s.seed = seed;
  return s;
}

SolverOptions forward_mode() {
  SolverOptions o;
  o.symmetric_dz = false;
  return o;
}

// Ranges, beams, attitudes and the plane anchor all swap: on exact data the
// reversed pair gives exactly -dz, and with white pixel noise the two agree to
// millimetres at 40 m / 14 m. Pixel noise is not what splits them.
TEST(DzModes, ReversedPairIsTheExactTimeReverse) {
  for (uint32_t seed = 1; seed <= 10; ++seed) {
    SceneSpec s = tilted_pair(40.0, 14.0, seed);
    const Scene exact = make_scene(s);
    const double forward = solve(exact.pair, forward_mode()).translation.z();
    const double reverse = -solve(reversed_in_time(exact.pair), forward_mode()).translation.z();
    EXPECT_NEAR(forward, s.translation.z(), 1e-9 * s.height_m);
    EXPECT_NEAR(reverse, s.translation.z(), 1e-9 * s.height_m);
    s.noise_px = 0.5;
    const Scene noisy = make_scene(s);
    EXPECT_NEAR(solve(noisy.pair, forward_mode()).translation.z(),
                -solve(reversed_in_time(noisy.pair), forward_mode()).translation.z(), 0.03);
  }
}

// A levelling error common to both frames pitches the frame the step is
// expressed in: both directions report dz - step * eps (measured to 6 %). An
// error in one frame only (relative error delta) enters mostly the direction
// anchored at that frame: forward - reverse ~ -step * delta (measured 0.8-1.6x;
// the rest is the second-order term of section 7a, larger at 80 m). The
// symmetric mode's reported dz sigma covers the gap.
TEST(DzModes, LevellingErrorTimesTheStepSplitsTheDirections) {
  const double eps = deg_to_rad(1.0);
  for (double height : {40.0, 80.0}) {
    for (double step : {7.0, 14.0}) {
      SCOPED_TRACE("h " + std::to_string(height) + " step " + std::to_string(step));
      double common_f = 0, common_r = 0, gap = 0;
      const int n = 5;
      for (uint32_t seed = 1; seed <= n; ++seed) {
        SceneSpec s = tilted_pair(height, step, seed);
        s.noise_px = 0.2;
        const Scene scene = make_scene(s);
        FramePair both = scene.pair;
        both.prev_pitch += eps;
        both.curr_pitch += eps;
        common_f += solve(both, forward_mode()).translation.z() - s.translation.z();
        common_r += -solve(reversed_in_time(both), forward_mode()).translation.z() - s.translation.z();
        FramePair prev_only = scene.pair;
        prev_only.prev_pitch += eps;
        const double f = solve(prev_only, forward_mode()).translation.z();
        const double r = -solve(reversed_in_time(prev_only), forward_mode()).translation.z();
        gap += f - r;
        const Estimate symmetric = solve(prev_only, SolverOptions{});
        EXPECT_GE(std::sqrt(symmetric.covariance(2, 2)), 0.5 * std::abs(f - r));
      }
      EXPECT_NEAR(common_f / n, -step * eps, 0.1 * step * eps);
      EXPECT_NEAR(common_r / n, -step * eps, 0.1 * step * eps);
      EXPECT_LT(gap / n, -0.5 * step * eps);
      EXPECT_GT(gap / n, -1.8 * step * eps);
    }
  }
}

// Consecutive pairs of a straight flight over a slope, every frame with its
// own cached levelling error: white (independent per frame) or first-order
// Gauss-Markov (frame-to-frame correlation rho). Vertical error summed over
// the flight and RMS per pair, forward and symmetric.
struct ModeErrors {
  double sum_forward = 0, sum_symmetric = 0, sq_forward = 0, sq_symmetric = 0;
};

ModeErrors fly(double height, double step, double sigma_deg, double rho, uint32_t seed) {
  constexpr int kFrames = 150;
  std::mt19937 rng(seed);
  std::normal_distribution<double> gauss(0.0, deg_to_rad(sigma_deg));
  double er = gauss(rng), ep = gauss(rng);
  double prev_er = er, prev_ep = ep;
  ModeErrors e;
  const double drive = std::sqrt(1 - rho * rho);
  for (int k = 1; k < kFrames; ++k) {
    er = rho * er + drive * gauss(rng);
    ep = rho * ep + drive * gauss(rng);
    SceneSpec s = tilted_pair(height, step, seed * 1000 + k);
    s.noise_px = 0.3;
    Scene scene = make_scene(s);
    scene.pair.prev_roll += prev_er;
    scene.pair.prev_pitch += prev_ep;
    scene.pair.curr_roll += er;
    scene.pair.curr_pitch += ep;
    prev_er = er;
    prev_ep = ep;
    const double f = solve(scene.pair, forward_mode()).translation.z() - s.translation.z();
    const double m = solve(scene.pair, SolverOptions{}).translation.z() - s.translation.z();
    e.sum_forward += f;
    e.sum_symmetric += m;
    e.sq_forward += f * f / (kFrames - 1);
    e.sq_symmetric += m * m / (kFrames - 1);
  }
  return e;
}

TEST(DzModes, StudyWhiteAndCorrelatedLevellingErrors) {
  struct Case {
    const char* name;
    double height, step, sigma_deg, rho;
  };
  const Case cases[] = {
      {"40 m / 14 m, white 0.5 deg", 40, 14, 0.5, 0.0},   {"40 m / 14 m, GM 0.5 deg rho 0.98", 40, 14, 0.5, 0.98},
      {"300 m / 2.1 m, white 1 deg", 300, 2.1, 1.0, 0.0}, {"300 m / 2.1 m, GM 1 deg rho 0.98", 300, 2.1, 1.0, 0.98},
  };
  std::printf("| pairs (150 frames x 3 flights) | sum dz err forward | symmetric "
              "| rms per pair forward | symmetric |\n");
  for (const Case& c : cases) {
    double sf = 0, ss = 0, qf = 0, qs = 0;
    for (uint32_t seed = 1; seed <= 3; ++seed) {
      const ModeErrors e = fly(c.height, c.step, c.sigma_deg, c.rho, seed);
      sf += std::abs(e.sum_forward) / 3;
      ss += std::abs(e.sum_symmetric) / 3;
      qf += e.sq_forward / 3;
      qs += e.sq_symmetric / 3;
    }
    std::printf("| %s | %.2f m | %.2f m | %.3f m | %.3f m |\n", c.name, sf, ss, std::sqrt(qf), std::sqrt(qs));
    if (c.rho > 0) {
      // Correlated errors: consecutive frames share their levelling error, the
      // two directions see nearly the same frame, the modes agree.
      EXPECT_NEAR(ss, sf, 0.25 * std::max(sf, 1.0)) << c.name;
    }
  }
}


// An independent reference solve: the gold-standard two-image cost (every
// feature's reprojection error in both images, the plane through the curr
// altimeter spot), six unknowns dx, dy, dz, dyaw, ground roll, ground pitch,
// Levenberg-Marquardt with a numerical Jacobian. Built from world poses like
// the scene generator, sharing no code with the solver. Same inputs (the INS
// attitudes as given), so it sees the same levelling errors.
using RefParams = Eigen::Matrix<double, 6, 1>;

Eigen::VectorXd reference_residuals(const FramePair& pair, const RefParams& p, double focal_px) {
  const Eigen::Matrix3d prev_cam = rotation_from_rpy(pair.prev_roll, pair.prev_pitch, pair.prev_yaw) *
                                   pair.body_from_camera;
  const Eigen::Matrix3d curr_body = rotation_from_rpy(pair.curr_roll, pair.curr_pitch, pair.prev_yaw + p(3));
  const Eigen::Matrix3d curr_cam = curr_body * pair.body_from_camera;
  const Eigen::Vector3d centre = rotation_from_rpy(0, 0, pair.prev_yaw) * p.head<3>();
  const Eigen::Vector3d normal = rotation_from_rpy(p(4), p(5), pair.prev_yaw + p(3)).col(2);
  const Eigen::Vector3d spot = centre + pair.curr_range_m * (curr_body * pair.curr_beam_body);
  auto project = [](const Eigen::Vector3d& x) { return Eigen::Vector2d(x.x() / x.z(), x.y() / x.z()); };
  const size_t m = pair.prev_norm.size();
  Eigen::VectorXd r(4 * m);
  for (size_t i = 0; i < m; ++i) {
    const Eigen::Vector3d ray_curr = curr_cam * pair.curr_norm[i].homogeneous();
    const Eigen::Vector3d on_plane_curr = centre + normal.dot(spot - centre) / normal.dot(ray_curr) * ray_curr;
    r.segment<2>(4 * i) = focal_px * (project(prev_cam.transpose() * on_plane_curr) - pair.prev_norm[i]);
    const Eigen::Vector3d ray_prev = prev_cam * pair.prev_norm[i].homogeneous();
    const Eigen::Vector3d on_plane_prev = normal.dot(spot) / normal.dot(ray_prev) * ray_prev;
    r.segment<2>(4 * i + 2) = focal_px * (project(curr_cam.transpose() * (on_plane_prev - centre)) - pair.curr_norm[i]);
  }
  return r;
}

RefParams reference_solve(const FramePair& pair, RefParams p, double focal_px) {
  double lambda = 1e-3;
  Eigen::VectorXd r = reference_residuals(pair, p, focal_px);
  for (int it = 0; it < 50; ++it) {
    Eigen::MatrixXd j(r.size(), 6);
    for (int k = 0; k < 6; ++k) {
      const double h = k < 3 ? 1e-6 : 1e-8;
      RefParams plus = p, minus = p;
      plus(k) += h;
      minus(k) -= h;
      j.col(k) = (reference_residuals(pair, plus, focal_px) - reference_residuals(pair, minus, focal_px)) / (2 * h);
    }
    Eigen::Matrix<double, 6, 6> a = j.transpose() * j;
    a.diagonal() *= 1 + lambda;
    const RefParams step = a.ldlt().solve(-j.transpose() * r);
    const Eigen::VectorXd trial = reference_residuals(pair, p + step, focal_px);
    if (trial.squaredNorm() < r.squaredNorm()) {
      p += step;
      r = trial;
      lambda *= 0.1;
      if (step.cwiseAbs().maxCoeff() < 1e-10) break;
    } else {
      lambda *= 10;
    }
  }
  return p;
}

// Noisy tilted pairs (0.5 px, no gross outliers), with and without white INS
// levelling errors: how far each dz mode lands from the reference solve and
// from the truth. Printed for the README; asserted only where it is sharp:
// without levelling errors both modes are within 3 cm RMS of the reference.
TEST(DzModes, AgainstAnIndependentReferenceSolve) {
  struct Case {
    const char* name;
    double height, step, ins_sigma_deg, common_sigma_deg;  // white per frame, shared by the two frames
  };
  const Case cases[] = {{"40 m / 14 m, INS exact", 40, 14, 0.0, 0.0},
                        {"40 m / 14 m, INS white 0.5 deg", 40, 14, 0.5, 0.0},
                        {"40 m / 14 m, INS 0.5 deg shared + 0.05 deg white", 40, 14, 0.05, 0.5},
                        {"300 m / 2.1 m, INS exact", 300, 2.1, 0.0, 0.0},
                        {"300 m / 2.1 m, INS white 1 deg", 300, 2.1, 1.0, 0.0},
                        {"300 m / 2.1 m, INS 1 deg shared + 0.05 deg white", 300, 2.1, 0.05, 1.0}};
  std::printf("| 20 pairs | dz rms vs reference: forward | symmetric "
              "| dz rms vs truth: forward | symmetric | reference |\n");
  for (const Case& c : cases) {
    std::mt19937 rng(11);
    std::normal_distribution<double> gauss(0.0, deg_to_rad(c.ins_sigma_deg));
    std::normal_distribution<double> shared(0.0, deg_to_rad(c.common_sigma_deg));
    double f_ref = 0, s_ref = 0, f_true = 0, s_true = 0, r_true = 0;
    const int n = 20;
    for (uint32_t seed = 1; seed <= n; ++seed) {
      SceneSpec spec = tilted_pair(c.height, c.step, seed);
      spec.noise_px = 0.5;
      Scene scene = make_scene(spec);
      const double shared_roll = shared(rng), shared_pitch = shared(rng);
      scene.pair.prev_roll += shared_roll + gauss(rng);
      scene.pair.prev_pitch += shared_pitch + gauss(rng);
      scene.pair.curr_roll += shared_roll + gauss(rng);
      scene.pair.curr_pitch += shared_pitch + gauss(rng);
      const Estimate forward = solve(scene.pair, forward_mode());
      const Estimate symmetric = solve(scene.pair, SolverOptions{});
      RefParams start;
      start << forward.translation, forward.dyaw, forward.ground_roll, forward.ground_pitch;
      const double ref = reference_solve(scene.pair, start, SolverOptions{}.focal_px)(2);
      const double truth = spec.translation.z();
      f_ref += std::pow(forward.translation.z() - ref, 2) / n;
      s_ref += std::pow(symmetric.translation.z() - ref, 2) / n;
      f_true += std::pow(forward.translation.z() - truth, 2) / n;
      s_true += std::pow(symmetric.translation.z() - truth, 2) / n;
      r_true += std::pow(ref - truth, 2) / n;
    }
    std::printf("| %s | %.3f m | %.3f m | %.3f m | %.3f m | %.3f m |\n", c.name, std::sqrt(f_ref), std::sqrt(s_ref),
                std::sqrt(f_true), std::sqrt(s_true), std::sqrt(r_true));
    if (c.ins_sigma_deg == 0 && c.common_sigma_deg == 0) {
      EXPECT_LT(std::sqrt(f_ref), 0.03 * c.height / 40) << c.name;
      EXPECT_LT(std::sqrt(s_ref), 0.03 * c.height / 40) << c.name;
    }
  }
}

}  // namespace
}  // namespace nadir::vo
