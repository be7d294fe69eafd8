#pragma once
// Geometry of one feature seen from two level virtual cameras over a tilted
// ground patch (DERIVATION.md). Shared by the solver, its tests and the
// benchmark; independent of the bus.

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cmath>
#include <limits>
#include <vector>

namespace nadir::vo {

// Rotation level-virtual-camera <- camera for a vehicle at roll/pitch:
// R_VC = Ry(pitch) Rx(roll) R_body_camera (the yaw is the virtual camera's own).
Eigen::Matrix3d level_from_camera(double roll, double pitch, const Eigen::Matrix3d& body_from_camera);

// Unit beam direction in the level frame of a vehicle at roll/pitch.
Eigen::Vector3d level_beam(double roll, double pitch, const Eigen::Vector3d& beam_body);

// Standard rotation about z (down): heading change, clockwise positive in NED.
Eigen::Matrix3d rot_z(double angle);

// Ground patch attitude <-> unit normal (pointing down, into the ground) in a
// level frame: n = Ry(pitch) Rx(roll) e_z.
Eigen::Vector3d normal_from_tilt(double roll, double pitch);
void tilt_from_normal(const Eigen::Vector3d& normal, double* roll, double* pitch);

// One feature in the level virtual cameras, each ray scaled to z = 1.
struct LevelFeature {
  Eigen::Vector3d u;  // prev (frame k-1), V^{k-1}
  Eigen::Vector3d v;  // curr (frame k), V^k
};

// The model's state apart from the 5 unknowns: the ground plane passes through
// the altimeter point A = range * beam (in V^k) and the virtual camera V' is
// re-levelled by `relevel` (its z axis is the current ground normal estimate).
struct PlaneGeometry {
  double range_m = 0;
  Eigen::Vector3d beam = Eigen::Vector3d::UnitZ();  // unit, in V^k
  Eigen::Matrix3d relevel = Eigen::Matrix3d::Identity();
};

// The unknowns of eq. (9): translation dx, dy (level frame of prev), heading
// change dyaw, and the ground tilt increments (roll, pitch) of the re-levelled
// virtual camera, which are zero at every re-levelling.
using Params = Eigen::Matrix<double, 5, 1>;
using JacobianRow = Eigen::Matrix<double, 1, 5>;

// Normal of the ground patch in V^k for tilt increments (roll, pitch) about
// the re-levelled camera: relevel * Ry(pitch) Rx(roll) e_z.
Eigen::Vector3d ground_normal(const PlaneGeometry& plane, double d_roll, double d_pitch);

// The point of the ground patch seen along ray v (z = 1) of V^k, in V^k.
// Returns false if the ray does not hit the plane in front of the camera.
bool ground_point(const PlaneGeometry& plane, const Eigen::Vector3d& normal, const Eigen::Vector3d& v,
                  Eigen::Vector3d* point);

// The same with the plane's distance n . A (range * n . beam) computed once
// by the caller for many rays.
inline bool ground_point_at(double plane_distance, const Eigen::Vector3d& normal, const Eigen::Vector3d& v,
                            Eigen::Vector3d* point) {
  const double n_v = normal.dot(v);
  if (!(n_v > 1e-9) || !(plane_distance > 0)) return false;
  *point = (plane_distance / n_v) * v;
  return true;
}

// Everything in eq. (9) that depends on the parameters but not on the
// feature, computed once per evaluation pass (the solver's hot loop).
struct ModelEval {
  Eigen::Vector3d normal;
  double plane_offset = 0;  // n . A: the plane is n . X = plane_offset
  double cos_yaw = 1, sin_yaw = 0;
  Eigen::Vector3d dn_droll, dn_dpitch;      // d normal / d tilt increments
  double offset_droll = 0, offset_dpitch = 0;  // d plane_offset / d tilt increments
};
ModelEval make_model_eval(const PlaneGeometry& plane, const Params& params);

// Eq. (9) for one feature with a prepared evaluation; see plane_residual.
// Inline: it is the solver's inner loop.
inline double model_residual(const LevelFeature& f, const ModelEval& e, const Params& p, JacobianRow* jacobian) {
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

// Exact form of eq. (9): z-component of u x (Rz(dyaw) X^k + [dx, dy, .]),
// which does not depend on dz. Zero for a perfect measurement. Metres; NaN
// when the ray does not meet the plane in front of the camera.
// If `jacobian` is given it receives d residual / d params at the given params
// (analytic; tilt derivatives at the given increments use the exact normal).
double plane_residual(const LevelFeature& f, const PlaneGeometry& plane, const Params& params,
                      JacobianRow* jacobian);

// Predicted point in V^{k-1} (all three coordinates) given dz too.
bool predict_prev_point(const LevelFeature& f, const PlaneGeometry& plane, const Params& params, double dz,
                        Eigen::Vector3d* prev_point);

}  // namespace nadir::vo
