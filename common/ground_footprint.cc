#include "common/ground_footprint.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>

namespace nadir {

std::vector<Eigen::Vector2d> ground_footprint(const CameraModel& camera, const Eigen::Vector3d& position_ned,
                                              const Eigen::Matrix3d& world_from_body, double ground_down_m) {
  const float w = static_cast<float>(camera.width - 1), h = static_cast<float>(camera.height - 1);
  const std::vector<cv::Point2f> edge{{0, 0}, {w / 2, 0}, {w, 0}, {w, h / 2}, {w, h}, {w / 2, h}, {0, h}, {0, h / 2}};
  const Eigen::Matrix3d world_from_camera = world_from_body * camera.body_from_camera;
  std::vector<Eigen::Vector2d> out;
  for (const cv::Point2d& n : camera.undistort(edge)) {
    const Eigen::Vector3d ray = world_from_camera * Eigen::Vector3d(n.x, n.y, 1.0);
    if (ray.z() <= 1e-6) continue;  // above the horizon: no footprint corner
    const double s = (ground_down_m - position_ned.z()) / ray.z();
    out.emplace_back(position_ned.x() + s * ray.x(), position_ned.y() + s * ray.y());
  }
  return out;
}

double footprint_overlap(const std::vector<Eigen::Vector2d>& a, const std::vector<Eigen::Vector2d>& b) {
  auto hull = [](const std::vector<Eigen::Vector2d>& p) {
    std::vector<cv::Point2f> points, out;
    for (const auto& q : p) points.emplace_back(static_cast<float>(q.x()), static_cast<float>(q.y()));
    if (points.size() >= 3) cv::convexHull(points, out);
    return out;
  };
  const std::vector<cv::Point2f> ha = hull(a), hb = hull(b);
  if (ha.size() < 3 || hb.size() < 3) return 0.0;
  const double area_a = cv::contourArea(ha);
  if (area_a <= 0) return 0.0;
  std::vector<cv::Point2f> common;
  const float inter = cv::intersectConvexConvex(ha, hb, common, true);
  return std::max(0.0f, inter) / area_a;
}

}  // namespace nadir
