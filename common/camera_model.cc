#include "common/camera_model.h"

#include <opencv2/calib3d.hpp>

#include <cmath>

#include "common/geometry.h"
#include "common/sensor_calibration.h"

namespace nadir {

CameraModel CameraModel::pinhole(int width, int height, double focal_px) {
  CameraModel c;
  c.width = width;
  c.height = height;
  c.fx = c.fy = focal_px;
  c.cx = 0.5 * (width - 1);
  c.cy = 0.5 * (height - 1);
  c.distortion = {0, 0, 0, 0, 0};
  return c;
}

CameraModel CameraModel::from_config(const Config& root) {
  const Config c = root.section("camera");
  c.require_known_keys(SensorCalibration::camera_keys());
  CameraModel m;
  m.width = c.get<int>("width");
  m.height = c.get<int>("height");
  m.fx = c.get<double>("fx");
  m.fy = c.get<double>("fy");
  m.cx = c.get<double>("cx");
  m.cy = c.get<double>("cy");
  m.distortion = c.get<std::vector<double>>("distortion", std::vector<double>{0, 0, 0, 0, 0});
  if (m.distortion.size() != 4 && m.distortion.size() != 5) {
    throw c.error("distortion", "must list 4 or 5 coefficients (k1, k2, p1, p2[, k3])");
  }
  const auto mount = c.get<std::vector<double>>("mount_rpy_deg", std::vector<double>{0, 0, 0});
  if (mount.size() != 3) throw c.error("mount_rpy_deg", "must list roll, pitch, yaw in degrees");
  for (int i = 0; i < 3; ++i) c.check_range("mount_rpy_deg", mount[i], -180.0, 180.0);
  m.body_from_camera = rotation_from_rpy(deg_to_rad(mount[0]), deg_to_rad(mount[1]), deg_to_rad(mount[2]));
  m.rate_hz = c.get_in_range<double>("rate_hz", 14.0, 0.1, 1000.0);
  m.Check(c.source());
  return m;
}

void CameraModel::Check(const std::string& source) const {
  require_option(width >= 16 && width <= 16384, source, "camera.width", "must be in [16, 16384]");
  require_option(height >= 16 && height <= 16384, source, "camera.height", "must be in [16, 16384]");
  require_option(fx > 0 && fy > 0, source, "camera.fx/fy", "must be > 0");
  require_option(cx >= 0 && cx <= width && cy >= 0 && cy <= height, source, "camera.cx/cy",
                 "must lie inside the image");
}

cv::Matx33d CameraModel::camera_matrix() const { return {fx, 0, cx, 0, fy, cy, 0, 0, 1}; }

cv::Mat CameraModel::distortion_coefficients() const { return cv::Mat(distortion, true).reshape(1, 1); }

double CameraModel::horizontal_fov_rad() const { return 2.0 * std::atan2(width / 2.0, fx); }

std::vector<cv::Point2d> CameraModel::undistort(const std::vector<cv::Point2f>& pixels) const {
  std::vector<cv::Point2d> out;
  if (pixels.empty()) return out;
  std::vector<cv::Point2d> in(pixels.begin(), pixels.end());
  // Iterative undistortion with a tight stop so points round-trip to ~1e-9.
  cv::undistortPoints(in, out, camera_matrix(), distortion_coefficients(), cv::noArray(), cv::noArray(),
                      cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 50, 1e-12));
  return out;
}

std::vector<cv::Point2f> CameraModel::distort(const std::vector<cv::Point2d>& normalized) const {
  std::vector<cv::Point2f> out;
  if (normalized.empty()) return out;
  std::vector<cv::Point3d> rays;
  rays.reserve(normalized.size());
  for (const auto& p : normalized) rays.emplace_back(p.x, p.y, 1.0);
  std::vector<cv::Point2d> projected;
  cv::projectPoints(rays, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), camera_matrix(), distortion_coefficients(),
                    projected);
  out.assign(projected.begin(), projected.end());
  return out;
}

cv::Matx22d CameraModel::pixel_jacobian(const cv::Point2d& normalized) const {
  const double k1 = distortion[0], k2 = distortion[1], p1 = distortion[2], p2 = distortion[3];
  const double k3 = distortion.size() > 4 ? distortion[4] : 0.0;
  const double x = normalized.x, y = normalized.y, r2 = x * x + y * y;
  const double radial = 1.0 + r2 * (k1 + r2 * (k2 + r2 * k3));
  const double radial_dr2 = k1 + r2 * (2.0 * k2 + 3.0 * r2 * k3);  // d radial / d r^2
  const double dxd_dx = radial + 2.0 * x * x * radial_dr2 + 2.0 * p1 * y + 6.0 * p2 * x;
  const double dxd_dy = 2.0 * x * y * radial_dr2 + 2.0 * p1 * x + 2.0 * p2 * y;
  const double dyd_dx = 2.0 * x * y * radial_dr2 + 2.0 * p1 * x + 2.0 * p2 * y;
  const double dyd_dy = radial + 2.0 * y * y * radial_dr2 + 6.0 * p1 * y + 2.0 * p2 * x;
  return cv::Matx22d(fx * dxd_dx, fx * dxd_dy, fy * dyd_dx, fy * dyd_dy);
}

}  // namespace nadir
