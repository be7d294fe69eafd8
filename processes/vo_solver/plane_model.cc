#include "processes/vo_solver/plane_model.h"

#include <cmath>
#include <limits>

namespace nadir::vo {

Eigen::Matrix3d level_from_camera(double roll, double pitch, const Eigen::Matrix3d& body_from_camera) {
  const Eigen::Matrix3d level_from_body =
      (Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) * Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
          .toRotationMatrix();
  return level_from_body * body_from_camera;
}

Eigen::Vector3d level_beam(double roll, double pitch, const Eigen::Vector3d& beam_body) {
  return (level_from_camera(roll, pitch, Eigen::Matrix3d::Identity()) * beam_body).normalized();
}

Eigen::Matrix3d rot_z(double angle) {
  const double c = std::cos(angle), s = std::sin(angle);
  Eigen::Matrix3d r;
  r << c, -s, 0, s, c, 0, 0, 0, 1;
  return r;
}

Eigen::Vector3d normal_from_tilt(double roll, double pitch) {
  const double cr = std::cos(roll), sr = std::sin(roll), cp = std::cos(pitch), sp = std::sin(pitch);
  return {sp * cr, -sr, cp * cr};
}

void tilt_from_normal(const Eigen::Vector3d& normal, double* roll, double* pitch) {
  const Eigen::Vector3d n = normal.normalized();
  *roll = std::atan2(-n.y(), std::hypot(n.x(), n.z()));
  *pitch = std::atan2(n.x(), n.z());
}

Eigen::Vector3d ground_normal(const PlaneGeometry& plane, double d_roll, double d_pitch) {
  return plane.relevel * normal_from_tilt(d_roll, d_pitch);
}

bool ground_point(const PlaneGeometry& plane, const Eigen::Vector3d& normal, const Eigen::Vector3d& v,
                  Eigen::Vector3d* point) {
  // Plane: n . X = n . A with A = range * beam; ray X = lambda v.
  return ground_point_at(plane.range_m * normal.dot(plane.beam), normal, v, point);
}

ModelEval make_model_eval(const PlaneGeometry& plane, const Params& p) {
  ModelEval e;
  const double cr = std::cos(p(3)), sr = std::sin(p(3)), cp = std::cos(p(4)), sp = std::sin(p(4));
  e.normal = plane.relevel * Eigen::Vector3d(sp * cr, -sr, cp * cr);
  e.dn_droll = plane.relevel * Eigen::Vector3d(-sp * sr, -cr, -cp * sr);
  e.dn_dpitch = plane.relevel * Eigen::Vector3d(cp * cr, 0.0, -sp * cr);
  const Eigen::Vector3d a = plane.range_m * plane.beam;  // the altimeter spot
  e.plane_offset = e.normal.dot(a);
  e.offset_droll = e.dn_droll.dot(a);
  e.offset_dpitch = e.dn_dpitch.dot(a);
  e.cos_yaw = std::cos(p(2));
  e.sin_yaw = std::sin(p(2));
  return e;
}

double plane_residual(const LevelFeature& f, const PlaneGeometry& plane, const Params& p, JacobianRow* jacobian) {
  return model_residual(f, make_model_eval(plane, p), p, jacobian);
}

bool predict_prev_point(const LevelFeature& f, const PlaneGeometry& plane, const Params& p, double dz,
                        Eigen::Vector3d* prev_point) {
  Eigen::Vector3d curr_point;
  if (!ground_point(plane, ground_normal(plane, p(3), p(4)), f.v, &curr_point)) return false;
  *prev_point = rot_z(p(2)) * curr_point + Eigen::Vector3d(p(0), p(1), dz);
  return true;
}

}  // namespace nadir::vo
