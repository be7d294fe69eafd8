#pragma once
// The DJI photo orientation (the contract, section 3) for a simulator
// camera. The simulator's image has columns along the camera x axis (body
// forward at the nominal mount); a DJI nadir photo has its top towards the
// aircraft's forward. The exporter turns every image 90 deg counter-clockwise
// (cv::ROTATE_90_COUNTERCLOCKWISE) and describes the turned image with:
//  - intrinsics: fx' = fy, fy' = fx, cx' = cy, cy' = W - 1 - cx,
//    k1, k2, k3 unchanged, p1' = -p2, p2' = p1;
//  - the camera frame c' (x' = turned image columns, y' = rows, z' = optical
//    axis): body <- c' = body <- c * [e_y, -e_x, e_z] (nominal mount: Rz(90)),
//    i.e. camera.mount_rpy_deg [0, 0, 90];
//  - DJI gimbal angles: R_world_gimbal = Rz(yaw) Ry(pitch) Rx(roll) in NED,
//    gimbal x = optical axis, y = image columns, z = image rows, so
//    R_world_gimbal = R_world_c' * [e_z, e_x, e_y].

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "common/camera_model.h"

namespace nadir::exporter {

// Turns a simulator image into the DJI orientation.
cv::Mat turn_to_dji(const cv::Mat& sim_image);
// The camera model of the turned image (intrinsics and body <- c' mount).
CameraModel turned_camera(const CameraModel& sim_camera);
// Pixel of the turned image that shows the simulator image's pixel (u, v).
cv::Point2d turned_pixel(const cv::Point2d& sim_pixel, int sim_width);
// c' <- gimbal: the fixed axis permutation above.
Eigen::Matrix3d camera_from_gimbal();

struct DjiAngles {
  double roll_deg = 0, pitch_deg = 0, yaw_deg = 0;
};

// Gimbal angles of a camera with attitude world <- c'. Of the two ZYX
// triples of a rotation, the one whose yaw is nearer `heading_rad` (the
// aircraft's) is chosen, as a DJI gimbal reports yaw ~ heading and pitch
// ~ -90 looking down; its pitch may then lie just beyond -90 (e.g. -92 when
// the body-fixed camera tilts backwards with the nose down).
DjiAngles gimbal_angles(const Eigen::Matrix3d& world_from_camera, double heading_rad);
// World <- c' from gimbal angles (the importer's composition, for tests).
Eigen::Matrix3d camera_attitude_from_gimbal(const DjiAngles& angles);

}  // namespace nadir::exporter
