#pragma once
// One VO delta into the pose filter with its shared errors taken apart
// (README § Consistency): the INS levelling and altimeter scale parts of the
// delta's covariance are not independent from delta to delta, so they are
// removed from what the filter integrates and kept once, as PoseFilter's
// shared-error terms (the levelling's heading part as its kYawLevelling
// state); the rest (image noise, altimeter noise, model error) is integrated
// as independent.

#include <Eigen/Core>

#include <limits>

#include "nadir/vo_delta_t.hpp"
#include "processes/yaw_fusion/pose_filter.h"
#include "processes/yaw_fusion/yaw_fusion_options.h"

namespace nadir {

// The INS attitude of one of a delta's frames as yaw fusion has it: the pitch
// (rad), NaN where unknown (then that frame's heading levelling term stays in
// the delta as independent), and the share of one INS sample's white noise
// variance in it (attitude_propagation.h; the VO solver's FrameSync makes the
// frame's attitude from the same samples the same way).
struct FrameAttitudeNoise {
  double pitch = std::numeric_limits<double>::quiet_NaN();
  double noise_share = 1.0;
};

// `covariance`: the delta's, over (dx, dy, dz, dyaw), as yaw fusion uses it.
// `prev`, `curr`: the delta's two frames. Returns the world translation added
// (PoseFilter::predict_with_delta).
Eigen::Vector3d integrate_delta(PoseFilter* filter, const vo_delta_t& delta, const Eigen::Matrix4d& covariance,
                                const FrameAttitudeNoise& prev, const FrameAttitudeNoise& curr,
                                const YawFusionOptions& options);

}  // namespace nadir
