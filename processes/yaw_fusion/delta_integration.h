#pragma once
// One VO delta into the pose filter with its shared errors taken apart
// (README § Consistency): the INS levelling and altimeter scale parts of the
// delta's covariance are not independent from delta to delta, so they are
// removed from what the filter integrates and kept once, as PoseFilter's
// shared-error terms (the levelling's heading part as its kYawLevelling
// state); the rest (image noise, altimeter noise, model error) is integrated
// as independent.

#include <Eigen/Core>

#include "nadir/vo_delta_t.hpp"
#include "processes/yaw_fusion/pose_filter.h"
#include "processes/yaw_fusion/yaw_fusion_options.h"

namespace nadir {

// `covariance`: the delta's, over (dx, dy, dz, dyaw), as yaw fusion uses it.
// `prev_pitch`, `curr_pitch`: the INS pitch (rad) of the delta's two frames,
// NaN where unknown (then that frame's heading levelling term stays in the
// delta as independent). Returns the world translation added
// (PoseFilter::predict_with_delta).
Eigen::Vector3d integrate_delta(PoseFilter* filter, const vo_delta_t& delta, const Eigen::Matrix4d& covariance,
                                double prev_pitch, double curr_pitch, const YawFusionOptions& options);

}  // namespace nadir
