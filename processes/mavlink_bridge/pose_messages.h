#pragma once
// POSE as the autopilots take an external position: VISION_POSITION_ESTIMATE
// and ODOMETRY in the local NED frame POSE is in (x north, y east, z down,
// from the first frame), GPS_INPUT as latitude/longitude from a configured
// origin. Covariances: POSE's position covariance and yaw variance, roll and
// pitch variance from the options (they come from the autopilot's own INS).

#include <cstdint>

#include "nadir/pose_t.hpp"
#include "processes/mavlink_bridge/bridge_options.h"
#include "processes/mavlink_bridge/mavlink_messages.h"

namespace nadir::mavlink_bridge {

mavlink::VisionPositionEstimate vision_position_estimate(const pose_t& pose, double attitude_variance_rad2,
                                                         uint8_t reset_counter);
mavlink::Odometry odometry(const pose_t& pose, double attitude_variance_rad2, uint8_t reset_counter);
mavlink::GpsInput gps_input(const pose_t& pose, const GpsInputOptions& options);

// North/east/down metres from an origin on the WGS84 ellipsoid to latitude,
// longitude (deg) and altitude (m, origin altitude minus down), with the
// ellipsoid's radii of curvature at the origin: within centimetres over the
// few kilometres of a flight.
void ned_to_geodetic(double origin_lat_deg, double origin_lon_deg, double origin_alt_m, double north, double east,
                     double down, double* lat_deg, double* lon_deg, double* alt_m);

}  // namespace nadir::mavlink_bridge
