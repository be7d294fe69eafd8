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
  const double n_v = normal.dot(v);
  const double plane_distance = plane.range_m * normal.dot(plane.beam);
  if (!(n_v > 1e-9) || !(plane_distance > 0)) return false;
  *point = (plane_distance / n_v) * v;
  return true;
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

double model_residual(const LevelFeature& f, const ModelEval& e, const Params& p, JacobianRow* jacobian) {
  // Depth of the ground point seen along v (v.z = 1) in V^k: X = lambda v, n . X = n . A.
  const double n_v = e.normal.dot(f.v);
  if (!(n_v > 1e-9) || !(e.plane_offset > 0)) return std::numeric_limits<double>::quiet_NaN();
  const double lambda = e.plane_offset / n_v;
  // r_v = Rz(dyaw) v; q = lambda r_v is the ground point rotated into V^{k-1} axes.
  const double rvx = e.cos_yaw * f.v.x() - e.sin_yaw * f.v.y();
  const double rvy = e.sin_yaw * f.v.x() + e.cos_yaw * f.v.y();
  const double qx = lambda * rvx, qy = lambda * rvy;
  const double residual = f.u.x() * (qy + p(1)) - f.u.y() * (qx + p(0));
  if (jacobian) {
    (*jacobian)(0) = -f.u.y();
    (*jacobian)(1) = f.u.x();
    // d(Rz v)/d yaw = (-rvy, rvx, 0).
    (*jacobian)(2) = f.u.x() * qx + f.u.y() * qy;
    // d lambda = (d offset - lambda (dn . v)) / (n . v).
    const double cross = f.u.x() * rvy - f.u.y() * rvx;  // d residual / d lambda
    (*jacobian)(3) = cross * (e.offset_droll - lambda * e.dn_droll.dot(f.v)) / n_v;
    (*jacobian)(4) = cross * (e.offset_dpitch - lambda * e.dn_dpitch.dot(f.v)) / n_v;
  }
  return residual;
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
