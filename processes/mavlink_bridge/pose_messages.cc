#include "processes/mavlink_bridge/pose_messages.h"

#include <Eigen/Geometry>

#include <cmath>
#include <limits>

#include "common/geodetic.h"
#include "common/geometry.h"
#include "common/gps_time.h"

namespace nadir::mavlink_bridge {
namespace {

constexpr float kUnknown = std::numeric_limits<float>::quiet_NaN();

// Upper triangle, row-major, of the 6x6 covariance of (x, y, z, roll, pitch,
// yaw): the MAVLink layout of VISION_POSITION_ESTIMATE and ODOMETRY.
std::array<float, 21> pose_covariance(const pose_t& pose, double attitude_variance_rad2) {
  double full[6][6] = {};
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) full[r][c] = pose.position_covariance[r][c];
  }
  full[3][3] = attitude_variance_rad2;
  full[4][4] = attitude_variance_rad2;
  full[5][5] = pose.yaw_variance;
  std::array<float, 21> out{};
  int k = 0;
  for (int r = 0; r < 6; ++r) {
    for (int c = r; c < 6; ++c) out[static_cast<size_t>(k++)] = static_cast<float>(full[r][c]);
  }
  return out;
}

}  // namespace

mavlink::VisionPositionEstimate vision_position_estimate(const pose_t& pose, double attitude_variance_rad2,
                                                         uint8_t reset_counter) {
  mavlink::VisionPositionEstimate m;
  m.usec = static_cast<uint64_t>(pose.utime);
  m.x = static_cast<float>(pose.position_ned[0]);
  m.y = static_cast<float>(pose.position_ned[1]);
  m.z = static_cast<float>(pose.position_ned[2]);
  m.roll = static_cast<float>(pose.roll);
  m.pitch = static_cast<float>(pose.pitch);
  m.yaw = static_cast<float>(wrap_angle(pose.yaw));
  m.covariance = pose_covariance(pose, attitude_variance_rad2);
  m.reset_counter = reset_counter;
  return m;
}

mavlink::Odometry odometry(const pose_t& pose, double attitude_variance_rad2, uint8_t reset_counter) {
  mavlink::Odometry m;
  m.time_usec = static_cast<uint64_t>(pose.utime);
  m.frame_id = mavlink::kMavFrameLocalNed;
  m.child_frame_id = mavlink::kMavFrameBodyFrd;
  m.x = static_cast<float>(pose.position_ned[0]);
  m.y = static_cast<float>(pose.position_ned[1]);
  m.z = static_cast<float>(pose.position_ned[2]);
  const Eigen::Matrix3d body_to_ned = rotation_from_rpy(pose.roll, pose.pitch, pose.yaw);
  const Eigen::Quaterniond q(body_to_ned);
  m.q = {static_cast<float>(q.w()), static_cast<float>(q.x()), static_cast<float>(q.y()), static_cast<float>(q.z())};
  // ODOMETRY's velocity is in the child frame (body FRD).
  const Eigen::Vector3d v_body =
      body_to_ned.transpose() * Eigen::Vector3d(pose.velocity_ned[0], pose.velocity_ned[1], pose.velocity_ned[2]);
  m.vx = static_cast<float>(v_body.x());
  m.vy = static_cast<float>(v_body.y());
  m.vz = static_cast<float>(v_body.z());
  m.rollspeed = m.pitchspeed = m.yawspeed = kUnknown;  // POSE carries no rates
  m.pose_covariance = pose_covariance(pose, attitude_variance_rad2);
  m.velocity_covariance.fill(0.0f);
  m.velocity_covariance[0] = kUnknown;  // NaN first: unknown (POSE has no velocity covariance)
  m.reset_counter = reset_counter;
  m.estimator_type = mavlink::kMavEstimatorTypeVio;
  m.quality = 0;  // unknown
  return m;
}

mavlink::GpsInput gps_input(const pose_t& pose, const GeodeticPoint& geo, const GpsInputOptions& o) {
  mavlink::GpsInput m;
  m.time_usec = static_cast<uint64_t>(pose.utime);
  // The vehicle time base is UTC (CLOCK_REALTIME): GPS week and milliseconds.
  const int64_t gps_us = unix_to_gps_us(pose.utime);
  const int64_t week_us = kSecondsPerWeek * 1000000;
  m.time_week = static_cast<uint16_t>(gps_us / week_us);
  m.time_week_ms = static_cast<uint32_t>((gps_us % week_us) / 1000);
  m.lat = static_cast<int32_t>(std::llround(geo.latitude_deg * 1e7));
  m.lon = static_cast<int32_t>(std::llround(geo.longitude_deg * 1e7));
  m.alt = static_cast<float>(geo.height_m);
  m.hdop = static_cast<float>(o.hdop);
  m.vdop = static_cast<float>(o.vdop);
  m.vn = static_cast<float>(pose.velocity_ned[0]);
  m.ve = static_cast<float>(pose.velocity_ned[1]);
  m.vd = static_cast<float>(pose.velocity_ned[2]);
  m.speed_accuracy = static_cast<float>(o.speed_accuracy_m_s);
  m.horiz_accuracy =
      static_cast<float>(std::sqrt(std::max(0.0, pose.position_covariance[0][0] + pose.position_covariance[1][1])));
  m.vert_accuracy = static_cast<float>(std::sqrt(std::max(0.0, pose.position_covariance[2][2])));
  m.ignore_flags = 0;
  m.gps_id = 0;
  m.fix_type = 3;  // 3D fix
  m.satellites_visible = static_cast<uint8_t>(o.satellites_visible);
  m.yaw = 0;       // not available: the autopilot has its own heading
  return m;
}

}  // namespace nadir::mavlink_bridge
