#include "tools/export/dji_orientation.h"

#include <opencv2/core.hpp>

#include <cmath>

#include "common/geometry.h"

namespace nadir::exporter {

cv::Mat turn_to_dji(const cv::Mat& sim_image) {
  cv::Mat turned;
  cv::rotate(sim_image, turned, cv::ROTATE_90_COUNTERCLOCKWISE);
  return turned;
}

CameraModel turned_camera(const CameraModel& sim) {
  CameraModel c = sim;
  c.width = sim.height;
  c.height = sim.width;
  c.fx = sim.fy;
  c.fy = sim.fx;
  c.cx = sim.cy;
  c.cy = sim.width - 1 - sim.cx;
  c.distortion.resize(5, 0.0);
  const std::vector<double> d = c.distortion;
  c.distortion[2] = -d[3];
  c.distortion[3] = d[2];
  Eigen::Matrix3d turn;  // c <- c': columns are c' axes in c
  turn << 0, -1, 0,  //
      1, 0, 0,       //
      0, 0, 1;
  c.body_from_camera = sim.body_from_camera * turn;
  return c;
}

cv::Point2d turned_pixel(const cv::Point2d& p, int sim_width) { return {p.y, sim_width - 1 - p.x}; }

Eigen::Matrix3d camera_from_gimbal() {
  Eigen::Matrix3d m;  // columns: gimbal x, y, z in c'
  m << 0, 1, 0,  //
      0, 0, 1,   //
      1, 0, 0;
  return m;
}

DjiAngles gimbal_angles(const Eigen::Matrix3d& world_from_camera, double heading_rad) {
  const Eigen::Vector3d rpy = rpy_from_rotation(world_from_camera * camera_from_gimbal());
  // The other triple of the same rotation: (roll + pi, pi - pitch, yaw + pi).
  const Eigen::Vector3d other(wrap_angle(rpy[0] + M_PI), -M_PI - rpy[1], wrap_angle(rpy[2] + M_PI));
  const bool use_other = std::fabs(angle_difference(other[2], heading_rad)) <
                         std::fabs(angle_difference(rpy[2], heading_rad));
  const Eigen::Vector3d& chosen = use_other ? other : rpy;
  return {rad_to_deg(chosen[0]), rad_to_deg(chosen[1]), rad_to_deg(chosen[2])};
}

Eigen::Matrix3d camera_attitude_from_gimbal(const DjiAngles& a) {
  return rotation_from_rpy(deg_to_rad(a.roll_deg), deg_to_rad(a.pitch_deg), deg_to_rad(a.yaw_deg)) *
         camera_from_gimbal().transpose();
}

}  // namespace nadir::exporter
