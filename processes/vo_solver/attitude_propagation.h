#pragma once
// Attitude at a time after an INS sample, from the sample and the body
// angular rate (the `propagate` attitude policy of FrameSync): no waiting for
// the INS sample after a frame. Rotations are world_from_body (common/geometry.h).

#include <Eigen/Core>

namespace nadir::vo {

// R(t0 + dt) = R(t0) * exp([rate]x dt) for a body-frame rate held constant
// over dt: exact for a constant body rate; with an angular acceleration a the
// error is about a * dt^2 / 2.
Eigen::Matrix3d propagate_attitude(const Eigen::Matrix3d& world_from_body, const Eigen::Vector3d& body_rate_rad_s,
                                   double dt_s);

// The constant body-frame rate that turns `earlier` into `later` in dt_s > 0
// seconds (the inverse of propagate_attitude), for an INS without rates.
Eigen::Vector3d body_rate_between(const Eigen::Matrix3d& earlier, const Eigen::Matrix3d& later, double dt_s);

}  // namespace nadir::vo
