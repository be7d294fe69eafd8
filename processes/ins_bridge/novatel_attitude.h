#pragma once
// NovAtel SPAN attitude and velocity into project frames.
//
// SPAN (INSPVA): IMU/vehicle frame x right, y forward, z up; local level is
// east-north-up. Azimuth is a left-handed rotation about z (clockwise from
// north seen from above), pitch a right-handed rotation about x (nose up
// positive), roll a right-handed rotation about y (right wing down positive),
// applied in the order azimuth, pitch, roll:
//   R_enu_imu = Rz(-azimuth) * Rx(pitch) * Ry(roll).
// Project: world north-east-down, body x forward, y right, z down,
//   R_ned_body = Rz(yaw) * Ry(pitch) * Rx(roll).
// P = [[0,1,0],[1,0,0],[0,0,-1]] maps ENU to NED and SPAN axes to project axes
// (a proper rotation, det +1), so R_ned_imu' = P R_enu_imu P, and conjugating
// each factor gives Rz(azimuth) Ry(pitch) Rx(roll): with an aligned IMU the
// angles carry over one to one (yaw = azimuth). The mount enters as
//   R_ned_body = R_ned_imu' * R_imu_body,  R_imu_body = rotation_from_rpy(imu_to_body_rpy)
// where imu' is the SPAN output frame re-axed to x forward, y right, z down.
// The angles are then recovered with rpy_from_rotation (yaw wrapped to (-pi, pi]).

#include <Eigen/Core>

#include "processes/ins_bridge/novatel_messages.h"

namespace nadir::ins_bridge {

// SPAN's definition, built literally in ENU / SPAN axes (used by tests as the reference).
Eigen::Matrix3d span_rotation_enu_imu(double roll_deg, double pitch_deg, double azimuth_deg);

struct ProjectAttitude {
  double roll = 0, pitch = 0, yaw = 0;  // rad, ZYX, yaw in (-pi, pi]
};

class SpanConverter {
 public:
  // imu_to_body_rpy_rad: ZYX angles of R_imu_body (identity for an aligned IMU).
  explicit SpanConverter(const Eigen::Vector3d& imu_to_body_rpy_rad);
  ProjectAttitude attitude(const InsPva& pva) const;
  // North-east-down from north-east-up.
  static Eigen::Vector3d velocity_ned(const InsPva& pva);

 private:
  Eigen::Matrix3d imu_body_;
  bool identity_;
};

}  // namespace nadir::ins_bridge
