#pragma once
// The pure frame-to-frame solver of the paper's Algorithm 1 and the variants
// it is compared with. No bus, no time: one pair of frames in, one estimate out,
// so it can be unit-tested and benchmarked on its own. DERIVATION.md holds the
// geometry (plane depth, the exact form of eq. (9), eq. (7) for dz).

#include <Eigen/Core>

#include <string>
#include <vector>

#include "processes/vo_solver/depth_layers.h"
#include "processes/vo_solver/feature_depth_options.h"

namespace nadir::vo {

enum class Variant { kPaper, kLevelGround, kHomography, kFlow, kFeatureDepth };

// "paper", "level_ground", "homography", "flow", "feature_depth"; throws std::invalid_argument otherwise.
Variant variant_from_name(const std::string& name);
std::string variant_name(Variant variant);

struct SolverOptions {
  // The paper's solver when unset; config/default.yaml ships feature_depth
  // (better on Table 1's profiles and over relief: README § Rough ground).
  Variant variant = Variant::kPaper;
  double focal_px = 398.79;            // for image reprojection errors in pixels
  // The *_px thresholds below are pixels of a camera with this focal length;
  // a camera with a longer focal length (more pixels per radian: a survey
  // camera's full-resolution photos) gets them scaled by focal_px / this, so
  // the same attitude and model errors (angles) stay within them. Never scaled down.
  double threshold_focal_px = 398.79;
  int min_features = 8;                // below this (before or after the robust fit): flagged
  int max_robust_iterations = 20;      // outer loop of Algorithm 1 (lines 7-20)
  int max_lm_iterations = 4;           // inner loop (lines 9-16), per reweighting
  double min_threshold_px = 2.0;       // IRE beyond which a feature is an outlier, at least
  double threshold_mad_scale = 4.0;    // ... or this many robust sigmas of the IREs, if larger, ...
  // ... but never above this: a share of off-plane points (tree tops) inflates
  // the robust sigma and would let itself in. Not applied to the first
  // reweighting after the tilt-free linear start, which can be pixels off on a slope.
  double max_threshold_px = 10.0;
  double convergence_tolerance = 1e-6; // parameter change (translation / height, rad)
  // ... or, paper / level_ground, every unknown moved by less than this share
  // of its own standard deviation (0: the absolute tolerance only).
  double convergence_sigma_fraction = 0.02;
  double max_residual_rms_px = 3.0;    // inlier IRE RMS above this: QUALITY_HIGH_RESIDUAL
  double min_inlier_fraction = 0.3;    // inlier share below this: QUALITY_HIGH_RESIDUAL
  double homography_ransac_px = 3.0;   // homography variant: RANSAC threshold
  DepthLayerOptions layers;            // QUALITY_DEPTH_LAYERS
  FeatureDepthOptions feature_depth;   // feature_depth variant (feature_depth.h)
  // paper / level_ground: dz from eq. (7) in the forward pair only, or the
  // mean of the forward and the time-reversed pair, which cancels the
  // second-order dz bias of INS levelling noise (DERIVATION.md section 7a).
  bool symmetric_dz = true;
  // paper / level_ground: the linear start (and so the fit) begins at the INS
  // heading change curr_yaw - prev_yaw instead of 0, so that any turn between
  // frames up to +-180 deg is solved; the published dyaw is the fit's own.
  bool dyaw_start_from_ins = true;
  // Throws std::invalid_argument naming the field and the allowed range.
  void Check() const;
  // max(1, focal_px / threshold_focal_px): the factor on every *_px threshold.
  double pixel_scale() const;
};

// One pair of frames, prev (k-1) and curr (k), with everything measured at
// each frame's own time (attitude and altimeter interpolated by the caller).
struct FramePair {
  std::vector<Eigen::Vector2d> prev_norm;  // undistorted normalized camera coordinates
  std::vector<Eigen::Vector2d> curr_norm;
  Eigen::Matrix3d body_from_camera = Eigen::Matrix3d::Identity();
  // INS, rad. Yaw: the start of paper / level_ground's heading change, and `flow`'s heading change.
  double prev_roll = 0, prev_pitch = 0, prev_yaw = 0;
  double curr_roll = 0, curr_pitch = 0, curr_yaw = 0;
  // The share of one INS sample's white noise variance in each frame's
  // attitude (FrameState::attitude_noise_share): the uncertainty model's.
  double prev_attitude_noise_share = 1.0, curr_attitude_noise_share = 1.0;
  double prev_range_m = 0, curr_range_m = 0;  // altimeter slant ranges along the beam
  // The altimeter's noise on prev_range_m (1 sigma, m; the node's from the
  // uncertainty options): what feature_depth's scale filter weighs the anchor with.
  double prev_range_sigma_m = 0;
  Eigen::Vector3d prev_beam_body = Eigen::Vector3d::UnitZ();
  Eigen::Vector3d curr_beam_body = Eigen::Vector3d::UnitZ();
  // feature_depth variant: each feature's own depth in the level frame of
  // prev (metres along u with u.z = 1, i.e. vertical depth below the prev
  // camera) and its standard deviation, from earlier frames of its track
  // (FeatureDepthMap). Empty, or NaN for a feature: unknown (the patch is used).
  std::vector<double> prev_depth_m, prev_depth_sigma_m;
  // feature_depth: how many pairs in a row before this one kept the own
  // depths' scale without an anchor (0: the pair before was anchored on the
  // altimeter); -1 where the depths hold no anchored scale (a new map, or
  // the paper's model alone solved the pair before). FeatureDepthMap.
  int carried_scale_pairs = -1;
  // feature_depth scale_filter: the variance (relative, squared) of the scale
  // the own depths hold, as the pair before left it (carried_scale_pairs >= 0).
  double prev_scale_variance = 0;
  // feature_depth with ins_tilt_sigma_deg > 0: the prev frame's INS roll /
  // pitch error as the pairs before estimated it (rotation of the INS-levelled
  // frame about level x, then y, rad) and its variance (rad^2, per axis).
  // Zero and the INS's own variance where nothing is known (FeatureDepthMap).
  Eigen::Vector2d prev_tilt = Eigen::Vector2d::Zero();
  Eigen::Vector2d prev_tilt_variance = Eigen::Vector2d::Zero();
  // feature_depth with anchor_spots track: where the altimeter beams of the
  // frames before prev met the ground (range x beam from each frame's camera,
  // moved by the solved motions), in the level frame of prev, metres from the
  // prev camera; newest first (FeatureDepthMap). Prev's own spot is not in it.
  std::vector<Eigen::Vector3d> earlier_ground_spots;
};

// Quality bits, the same values as nadir::vo_delta_t::QUALITY_*.
enum Quality : int {
  kTooFewFeatures = 1,
  kNoAltimeter = 2,
  kStaleAltimeter = 4,
  kNotConverged = 8,
  kNoAttitude = 16,
  kFrameGap = 32,
  kHighResidual = 64,
  kDepthLayers = 128,
  kHeadingContradicts = 256,
};
// An estimate with any of these has no motion to build on (own depths, velocity).
constexpr int kEstimateFailed = kTooFewFeatures | kNoAltimeter | kNotConverged | kNoAttitude;

struct Estimate {
  // Translation of the camera from prev to curr in the level frame of prev
  // (x forward along prev heading, y right, z down), metres.
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();
  double dyaw = 0;          // heading change curr - prev, rad (clockwise positive)
  double ground_roll = 0;   // ground patch attitude in the level frame of curr, rad
  double ground_pitch = 0;
  double altitude_m = 0;    // vertical height of the prev camera above the ground patch
  // dx, dy, dz, dyaw, ground_roll, ground_pitch.
  Eigen::Matrix<double, 6, 6> covariance = Eigen::Matrix<double, 6, 6>::Zero();
  int inliers = 0;
  int outliers = 0;
  double residual_rms_px = 0;  // image reprojection error RMS over the inliers
  int iterations = 0;          // Levenberg-Marquardt iterations (or refinement steps)
  int quality = 0;             // Quality bits; 0 = good
  std::vector<double> weights;  // final robust weight per feature (0 = outlier)
  // feature_depth variant: the factor that re-anchored the features' own
  // depths on this pair's altimeter (1 where none was used), and per feature
  // whether its own depth was used (else the patch's).
  double depth_scale = 1.0;
  // feature_depth variant: whether the own depths solved the pair (false:
  // the paper's model alone), and whether they kept the scale the pair
  // before left them, no anchor holding (scale_carry_pairs).
  bool own_depths_used = false;
  bool scale_carried = false;
  // The variance (relative, squared) of the scale the own depths were given:
  // the anchor's, or with scale_filter the fused one; 0 where unused.
  double scale_variance = 0.0;
  // How far the patch missed the own depths, in their sigmas (the young
  // features' weight went down by its square where above 1); 0 where unused.
  double patch_misfit = 0.0;
  // The own depths' relative variance about the surface the altimeter
  // anchored them on, beyond their own sigmas (relief the surface does not
  // follow); 0 where no anchor was fitted (carried scale, paper alone).
  double anchor_model_variance = 0.0;
  std::vector<char> used_own_depth;
  // feature_depth with ins_tilt_sigma_deg > 0: the tilt of curr's
  // INS-levelled frame against prev's beyond what the INS roll/pitch say
  // (rotation about level x, then y, rad; the difference of the two frames'
  // filtered errors), and curr's error with its variance (FramePair::prev_tilt
  // of the next pair). Zero otherwise.
  Eigen::Vector2d relative_tilt = Eigen::Vector2d::Zero();
  Eigen::Vector2d curr_tilt = Eigen::Vector2d::Zero();
  Eigen::Vector2d curr_tilt_variance = Eigen::Vector2d::Zero();
};

// The rotation from the level frame of prev to the (INS-levelled) level frame
// of curr: Rx(tilt x) Ry(tilt y) Rz(-dyaw). A point X in prev's frame is at
// curr_from_prev(est) (X - est.translation) in curr's.
Eigen::Matrix3d curr_from_prev(const Estimate& est);

// The same pair seen backwards in time: curr becomes prev and vice versa
// (points, attitudes, headings, altimeter ranges and beams all swap).
FramePair reversed_in_time(const FramePair& pair);

// Runs the configured variant. Never throws on bad data: a degenerate input
// gives an Estimate with quality bits set.
Estimate solve(const FramePair& pair, const SolverOptions& options);

// paper (estimate_tilt) / level_ground; dz one-way or symmetric per options.symmetric_dz.
Estimate solve_paper(const FramePair& pair, const SolverOptions& options, bool estimate_tilt);
Estimate solve_homography(const FramePair& pair, const SolverOptions& options);
Estimate solve_flow(const FramePair& pair, const SolverOptions& options);
// feature_depth_solver.cc: the features' own depths where known well enough,
// the patch elsewhere; without enough of them exactly solve_paper.
Estimate solve_feature_depth(const FramePair& pair, const SolverOptions& options);

}  // namespace nadir::vo
