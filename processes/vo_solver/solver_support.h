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

// The virtual camera re-levelled by tilt increments: relevel * Ry(pitch) Rx(roll).
Eigen::Matrix3d ground_relevel(const PlaneGeometry& plane, double d_roll, double d_pitch);

}  // namespace nadir::vo

namespace nadir::vo {

// Vertical height of the prev camera above the ground plane n . X = offset
// (n unit, in the level frame of curr), given the motion prev -> curr.
double prev_vertical_height(const Eigen::Vector3d& normal, double plane_offset, double dyaw,
                            const Eigen::Vector3d& translation);

}  // namespace nadir::vo
