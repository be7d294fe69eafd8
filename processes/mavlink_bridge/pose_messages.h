#pragma once
// POSE as the autopilots take an external position: VISION_POSITION_ESTIMATE
// and ODOMETRY in the local NED frame POSE is in (x north, y east, z down,
// from the first frame), GPS_INPUT as the latitude/longitude/altitude of the
// path POSE has flown from a configured origin (common/geodetic.h). Covariances: POSE's position covariance and yaw variance, roll and
// pitch variance from the options (they come from the autopilot's own INS).

#include <cstdint>

#include "common/geodetic.h"
#include "nadir/pose_t.hpp"
#include "processes/mavlink_bridge/bridge_options.h"
#include "processes/mavlink_bridge/mavlink_messages.h"

namespace nadir::mavlink_bridge {

mavlink::VisionPositionEstimate vision_position_estimate(const pose_t& pose, double attitude_variance_rad2,
                                                         uint8_t reset_counter);
mavlink::Odometry odometry(const pose_t& pose, double attitude_variance_rad2, uint8_t reset_counter);
// `position`: POSE's position on the track from the origin (altitude AMSL).
mavlink::GpsInput gps_input(const pose_t& pose, const GeodeticPoint& position, const GpsInputOptions& options);

}  // namespace nadir::mavlink_bridge
