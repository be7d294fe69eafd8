#include "processes/sim/sim_camera.h"

#include <opencv2/calib3d.hpp>

#include "common/sensor_calibration.h"
#include "processes/sim/sim_rotation.h"

namespace nadir::sim {

SimCamera SimCamera::from_config(const Config& root) {
  const Config c = root.section("camera");
  c.require_known_keys(SensorCalibration::camera_keys());
  SimCamera cam;
  cam.width = c.get_in_range<int>("width", cam.width, 16, 8192);
  cam.height = c.get_in_range<int>("height", cam.height, 16, 8192);
  cam.fx = c.get_in_range<double>("fx", cam.fx, 1.0, 1e5);
  cam.fy = c.get_in_range<double>("fy", cam.fy, 1.0, 1e5);
  cam.cx = c.get_in_range<double>("cx", cam.cx, -1e4, 1e4);
  cam.cy = c.get_in_range<double>("cy", cam.cy, -1e4, 1e4);
  cam.distortion = c.get<std::vector<double>>("distortion", cam.distortion);
  if (cam.distortion.size() != 4 && cam.distortion.size() != 5)
    throw c.error("distortion", "must list 4 or 5 coefficients (k1, k2, p1, p2[, k3])");
  for (double d : cam.distortion) c.check_range("distortion", d, -10.0, 10.0);
  const auto mount = c.get<std::vector<double>>("mount_rpy_deg", std::vector<double>{0, 0, 0});
  if (mount.size() != 3) throw c.error("mount_rpy_deg", "must list roll, pitch, yaw in degrees");
  for (double m : mount) c.check_range("mount_rpy_deg", m, -180.0, 180.0);
  cam.body_from_camera = world_from_body(deg2rad(mount[0]), deg2rad(mount[1]), deg2rad(mount[2]));
  cam.rate_hz = c.get_in_range<double>("rate_hz", cam.rate_hz, 0.1, 200.0);
  return cam;
}

cv::Matx33d SimCamera::camera_matrix() const { return cv::Matx33d(fx, 0, cx, 0, fy, cy, 0, 0, 1); }

cv::Mat SimCamera::distortion_coefficients() const {
  cv::Mat d(1, static_cast<int>(distortion.size()), CV_64F);
  for (size_t i = 0; i < distortion.size(); ++i) d.at<double>(0, static_cast<int>(i)) = distortion[i];
  return d;
}

std::vector<cv::Point2d> SimCamera::undistort(const std::vector<cv::Point2d>& pixels) const {
  std::vector<cv::Point2d> out;
  if (pixels.empty()) return out;
  cv::undistortPoints(pixels, out, camera_matrix(), distortion_coefficients(), cv::noArray(), cv::noArray(),
                      cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 100, 1e-14));
  return out;
}

std::vector<cv::Point2d> SimCamera::project(const std::vector<cv::Point3d>& points_camera) const {
  std::vector<cv::Point2d> out;
  if (points_camera.empty()) return out;
  cv::projectPoints(points_camera, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), camera_matrix(), distortion_coefficients(),
                    out);
  return out;
}

}  // namespace nadir::sim
