#include "processes/ins_bridge/novatel_attitude.h"

#include <Eigen/Geometry>

#include "common/geometry.h"

namespace nadir::ins_bridge {

Eigen::Matrix3d span_rotation_enu_imu(double roll_deg, double pitch_deg, double azimuth_deg) {
  using Eigen::AngleAxisd;
  using Eigen::Vector3d;
  return (AngleAxisd(-deg_to_rad(azimuth_deg), Vector3d::UnitZ()) *
          AngleAxisd(deg_to_rad(pitch_deg), Vector3d::UnitX()) * AngleAxisd(deg_to_rad(roll_deg), Vector3d::UnitY()))
      .toRotationMatrix();
}

SpanConverter::SpanConverter(const Eigen::Vector3d& imu_to_body_rpy_rad)
    : imu_body_(rotation_from_rpy(imu_to_body_rpy_rad.x(), imu_to_body_rpy_rad.y(), imu_to_body_rpy_rad.z())),
      identity_(imu_to_body_rpy_rad.isZero(0.0)) {}

ProjectAttitude SpanConverter::attitude(const InsPva& pva) const {
  ProjectAttitude out;
  if (identity_) {
    // Exact for an aligned IMU (see the header): no trigonometry round trip.
    out.roll = deg_to_rad(pva.roll_deg);
    out.pitch = deg_to_rad(pva.pitch_deg);
    out.yaw = wrap_angle(deg_to_rad(pva.azimuth_deg));
    return out;
  }
  const Eigen::Matrix3d ned_imu =
      rotation_from_rpy(deg_to_rad(pva.roll_deg), deg_to_rad(pva.pitch_deg), deg_to_rad(pva.azimuth_deg));
  const Eigen::Vector3d rpy = rpy_from_rotation(ned_imu * imu_body_);
  out.roll = rpy.x();
  out.pitch = rpy.y();
  out.yaw = wrap_angle(rpy.z());
  return out;
}

Eigen::Vector3d SpanConverter::velocity_ned(const InsPva& pva) {
  return {pva.north_velocity, pva.east_velocity, -pva.up_velocity};
}

}  // namespace nadir::ins_bridge
