#pragma once
// Small helpers shared by the solver variants.

#include <Eigen/Core>

#include <vector>

#include "processes/vo_solver/plane_model.h"
#include "processes/vo_solver/translation_solver.h"

namespace nadir::vo {

// Starts every variant's estimate: one zero weight per feature. False (and
// flagged too few features) when the two frames' point lists differ in size.
bool start_estimate(const FramePair& pair, Estimate* est);

// Median of the finite values (infinite ones count as larger than all); 0 if empty.
double median_of(const std::vector<double>& values);

// The robust outlier cut on reprojection errors (pixels): mad_scale robust
// sigmas (1.4826 x median) of the errors, at least min_threshold_px.
double robust_cut_px(double mad_scale, double min_threshold_px, const std::vector<double>& errors);

// The virtual camera re-levelled by tilt increments: relevel * Ry(pitch) Rx(roll).
Eigen::Matrix3d ground_relevel(const PlaneGeometry& plane, double d_roll, double d_pitch);

}  // namespace nadir::vo

namespace nadir::vo {

// Image error (pixels) of a point in the prev camera frame against the tracked
// normalized point; infinite when the point is not in front of the camera.
double image_error_px(const Eigen::Vector3d& in_prev_camera, const Eigen::Vector2d& measured, double focal_px);

// Image reprojection error (pixels, prev image) of every feature under an
// estimate as published: the curr ray meets the patch through the curr
// altimeter spot with attitude (ground_roll, ground_pitch), and that point is
// moved by (dyaw, translation) into the prev camera. Infinite where the ray
// misses the patch. Used by every variant, so VO_DELTA's residual always
// means the same thing. If depth_offsets is given it receives each feature's
// depth triangulated from its two rays with that motion, relative to its depth
// on the patch, minus 1 (NaN where undefined; negative = above the patch).
std::vector<double> estimate_reprojection_errors(const FramePair& pair, const Estimate& est, double focal_px,
                                                 std::vector<double>* depth_offsets = nullptr);

// From the estimate as published and its weights: inliers (weight > 0),
// outliers, residual_rms_px (inlier RMS of estimate_reprojection_errors), and
// the too-few-features (below min_inliers), high-residual and depth-layers
// quality bits.
void score_estimate(const FramePair& pair, const SolverOptions& options, int min_inliers, Estimate* est);

// Vertical height of the prev camera above the ground plane n . X = offset
// (n unit, in the level frame of curr), given the motion prev -> curr.
double prev_vertical_height(const Eigen::Vector3d& normal, double plane_offset, double dyaw,
                            const Eigen::Vector3d& translation);

}  // namespace nadir::vo
