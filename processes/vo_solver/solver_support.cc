#include "processes/vo_solver/solver_support.h"

#include <Eigen/Geometry>

#include <algorithm>

namespace nadir::vo {

bool start_estimate(const FramePair& pair, Estimate* est) {
  est->weights.assign(pair.prev_norm.size(), 0.0);
  if (pair.curr_norm.size() == pair.prev_norm.size()) return true;
  est->quality |= kTooFewFeatures;
  return false;
}

double median_of(const std::vector<double>& values) {
  if (values.empty()) return 0.0;
  std::vector<double> copy(values);
  const size_t mid = copy.size() / 2;
  std::nth_element(copy.begin(), copy.begin() + static_cast<long>(mid), copy.end());
  return copy[mid];
}

}  // namespace nadir::vo

namespace nadir::vo {

Eigen::Matrix3d ground_relevel(const PlaneGeometry& plane, double d_roll, double d_pitch) {
  const Eigen::Matrix3d increment = (Eigen::AngleAxisd(d_pitch, Eigen::Vector3d::UnitY()) *
                                     Eigen::AngleAxisd(d_roll, Eigen::Vector3d::UnitX()))
                                        .toRotationMatrix();
  return plane.relevel * increment;
}

}  // namespace nadir::vo

namespace nadir::vo {

double prev_vertical_height(const Eigen::Vector3d& normal, double plane_offset, double dyaw,
                            const Eigen::Vector3d& translation) {
  const Eigen::Vector3d prev_camera = -rot_z(dyaw).transpose() * translation;
  return (plane_offset - normal.dot(prev_camera)) / normal.z();
}

}  // namespace nadir::vo
