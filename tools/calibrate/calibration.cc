#include "tools/calibrate/calibration.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <optional>
#include <random>
#include <sstream>
#include <stdexcept>

#include "common/camera_model.h"
#include "common/channels.h"
#include "common/geodetic.h"
#include "common/geometry.h"
#include "common/json_writer.h"
#include "common/log_file.h"
#include "common/message_guard.h"
#include "common/progress.h"
#include "common/robust_stats.h"
#include "common/sensor_calibration.h"
#include "nadir/altimeter_t.hpp"
#include "nadir/ground_truth_t.hpp"
#include "nadir/ins_t.hpp"
#include "nadir/tracks_t.hpp"
#include "nadir/vo_delta_t.hpp"
#include "tools/eval/pair_metrics.h"

namespace nadir::calibrate {
namespace {

template <class Msg>
bool decode(const LogEvent& e, Msg* msg) {
  std::string reason;
  return decode_message(e.data, e.size, msg, &reason);
}

Eigen::Matrix3d exp_so3(const Eigen::Vector3d& v) {
  const double angle = v.norm();
  if (angle < 1e-15) return Eigen::Matrix3d::Identity();
  return Eigen::AngleAxisd(angle, v / angle).toRotationMatrix();
}

Eigen::Vector3d log_so3(const Eigen::Matrix3d& r) {
  const Eigen::AngleAxisd aa(r);
  return aa.angle() * aa.axis();
}

// INS attitude and position at any time in the segment. With body rates: the
// rates integrated (the motion between frames, exact up to gyro errors) and
// pulled to the INS attitude by a centred average of their difference (the
// white attitude noise averages out, the motion is not averaged at all).
// Without rates: a short centred average of roll, pitch, yaw, interpolated
// linearly (attenuates fast motion: a fallback).
class InsTrack {
 public:
  InsTrack(const std::vector<FlightData::InsSample>& ins, double smoothing_s) : ins_(ins) {
    const int n = static_cast<int>(ins.size());
    double rate = 100.0;
    if (n > 1) rate = (n - 1) / ((ins.back().utime - ins.front().utime) * 1e-6);
    rates_ = std::all_of(ins.begin(), ins.end(), [](const FlightData::InsSample& s) { return s.has_rates; });
    attitude_.resize(static_cast<size_t>(n));
    if (rates_) {
      const int h = std::max(0, static_cast<int>(std::lround(smoothing_s * rate)));
      std::vector<Eigen::Matrix3d> gyro(static_cast<size_t>(n));
      gyro[0] = rotation_from_rpy(ins[0].roll, ins[0].pitch, ins[0].yaw);
      for (int i = 0; i + 1 < n; ++i) {
        const double dt = (ins[i + 1].utime - ins[i].utime) * 1e-6;
        gyro[i + 1] = gyro[i] * exp_so3(0.5 * (ins[i].angular_rate + ins[i + 1].angular_rate) * dt);
      }
      // Prefix sums of the error INS vs integrated rates, in the WORLD frame:
      // the integration carries the error of the sample it starts from as a
      // rotation fixed in the world (gyro_i = E * R_i). Seen from the body it
      // turns with every oscillation, so a body-frame average would leave
      // (attitude - its local mean) x E in the attitude whatever the window,
      // which the fit took for boresight and time offset (README, seed 12).
      std::vector<Eigen::Vector3d> sum(static_cast<size_t>(n) + 1, Eigen::Vector3d::Zero());
      for (int i = 0; i < n; ++i)
        sum[i + 1] = sum[i] + log_so3(rotation_from_rpy(ins[i].roll, ins[i].pitch, ins[i].yaw) * gyro[i].transpose());
      Eigen::Vector3d scatter = Eigen::Vector3d::Zero();
      for (int i = 0; i < n; ++i) {
        const int lo = std::max(0, i - h), hi = std::min(n - 1, i + h);
        const Eigen::Vector3d mean = (sum[hi + 1] - sum[lo]) / (hi - lo + 1);
        attitude_[i] = exp_so3(mean) * gyro[i];
        const Eigen::Vector3d d = (sum[i + 1] - sum[i]) - mean;
        scatter += d.cwiseProduct(d);
      }
      noise_rad_ = (scatter / std::max(1, n - 1)).cwiseSqrt();
      window_ = h;
    } else {
      const int h = std::max(0, static_cast<int>(std::lround(std::min(smoothing_s, 0.05) * rate)));
      smoothed_rpy_.resize(static_cast<size_t>(n));
      for (int i = 0; i < n; ++i) {
        Eigen::Vector3d total = Eigen::Vector3d::Zero();
        int count = 0;
        for (int j = std::max(0, i - h); j <= std::min(n - 1, i + h); ++j, ++count)
          total += Eigen::Vector3d(ins[j].roll, ins[j].pitch, ins[i].yaw + angle_difference(ins[j].yaw, ins[i].yaw));
        smoothed_rpy_[i] = total / count;
      }
    }
  }
  bool uses_rates() const { return rates_; }
  // The INS attitude's white noise (world axes, rad) seen against the rates.
  const Eigen::Vector3d& noise_rad() const { return noise_rad_; }
  // A copy whose attitude carries another draw of what the averaging leaves
  // of that noise (a moving average of white noise): for the bootstrap.
  InsTrack perturbed(uint64_t seed) const {
    InsTrack copy = *this;
    if (!rates_) return copy;
    std::mt19937_64 rng(seed);
    std::normal_distribution<double> normal;
    const int n = static_cast<int>(attitude_.size());
    std::vector<Eigen::Vector3d> sum(static_cast<size_t>(n) + 1, Eigen::Vector3d::Zero());
    for (int i = 0; i < n; ++i)
      sum[i + 1] = sum[i] + Eigen::Vector3d(normal(rng), normal(rng), normal(rng)).cwiseProduct(noise_rad_);
    for (int i = 0; i < n; ++i) {
      const int lo = std::max(0, i - window_), hi = std::min(n - 1, i + window_);
      copy.attitude_[i] = exp_so3((sum[hi + 1] - sum[lo]) / (hi - lo + 1)) * attitude_[i];
    }
    return copy;
  }
  int64_t first_utime() const { return ins_.front().utime; }
  int64_t last_utime() const { return ins_.back().utime; }
  bool covers(double utime) const { return utime >= ins_.front().utime && utime <= ins_.back().utime; }
  // Requires covers(utime).
  void at(double utime, Eigen::Matrix3d* world_from_body, Eigen::Vector3d* position_ned) const {
    auto it = std::upper_bound(ins_.begin(), ins_.end(), utime,
                               [](double t, const FlightData::InsSample& s) { return t < static_cast<double>(s.utime); });
    size_t j = static_cast<size_t>(it - ins_.begin());
    if (j == 0) j = 1;
    if (j >= ins_.size()) j = ins_.size() - 1;
    const size_t i = j - 1;
    const double span = static_cast<double>(ins_[j].utime - ins_[i].utime);
    const double w = span > 0 ? (utime - static_cast<double>(ins_[i].utime)) / span : 0.0;
    if (world_from_body) {
      if (rates_) {  // rates interpolated linearly, integrated from sample i to t (trapezoid)
        const double tau = w * span * 1e-6;
        const Eigen::Vector3d mean_rate = ins_[i].angular_rate * (1.0 - 0.5 * w) + ins_[j].angular_rate * (0.5 * w);
        *world_from_body = attitude_[i] * exp_so3(mean_rate * tau);
      } else {
        const Eigen::Vector3d a = smoothed_rpy_[i], b = smoothed_rpy_[j];
        *world_from_body = rotation_from_rpy(a.x() + w * (b.x() - a.x()), a.y() + w * (b.y() - a.y()),
                                             a.z() + w * angle_difference(b.z(), a.z()));
      }
    }
    if (position_ned) *position_ned = ins_[i].position_ned + w * (ins_[j].position_ned - ins_[i].position_ned);
  }

 private:
  const std::vector<FlightData::InsSample>& ins_;
  bool rates_ = false;
  int window_ = 0;
  Eigen::Vector3d noise_rad_ = Eigen::Vector3d::Zero();
  std::vector<Eigen::Matrix3d> attitude_;   // with rates
  std::vector<Eigen::Vector3d> smoothed_rpy_;  // without
};

// The height above ground along the altimeter's beam from the truth
// (GROUND_TRUTH): the terrain is known only under the vehicle's track, and
// the beam's footprint lies h * tan(tilt) away from the point below (with
// the nose-down trim ~10 m behind at 200 m, in proportion to the height, so
// the terrain's slope there would turn into a scale error). The footprint is
// therefore looked up on the track: the terrain height at the track point
// nearest to it (searched within +-5 s), used only when the footprint is
// within `max_offtrack_m` of the track (the rest of the mismatch, across the
// track, comes from the roll oscillations and is not correlated with the
// height). The beam starts at the vehicle's position + `origin_offset_ned`
// (the altimeter's lever arm). Returns false outside the series, for a beam
// tilted beyond 60 deg or a footprint off the track.
bool agl_along_beam(const std::vector<FlightData::TerrainSample>& terrain, double utime,
                    const Eigen::Vector3d& origin_offset_ned, const Eigen::Vector3d& beam_world,
                    double max_offtrack_m, double* range_m) {
  if (terrain.size() < 2 || utime < terrain.front().utime || utime > terrain.back().utime) return false;
  const Eigen::Vector3d beam = beam_world.normalized();
  if (beam.z() < 0.5) return false;
  auto index_at = [&](double t) {
    auto it = std::upper_bound(terrain.begin(), terrain.end(), t, [](double v, const FlightData::TerrainSample& s) {
      return v < static_cast<double>(s.utime);
    });
    return std::clamp<size_t>(static_cast<size_t>(it - terrain.begin()), 1, terrain.size() - 1);
  };
  const size_t j = index_at(utime);
  const auto& a = terrain[j - 1];
  const auto& b = terrain[j];
  const double w = (utime - static_cast<double>(a.utime)) / static_cast<double>(b.utime - a.utime);
  const Eigen::Vector3d position = a.position_ned + w * (b.position_ned - a.position_ned) + origin_offset_ned;
  double ground = a.terrain_height_m + w * (b.terrain_height_m - a.terrain_height_m);
  const size_t lo = index_at(utime - 5e6) - 1, hi = index_at(utime + 5e6);
  double offtrack = 0.0;
  for (int pass = 0; pass < 2; ++pass) {  // the footprint moves with the ground height found there
    const double range = (-position.z() - ground) / beam.z();
    const Eigen::Vector2d footprint = position.head<2>() + range * beam.head<2>();
    offtrack = std::numeric_limits<double>::infinity();
    for (size_t k = lo; k < hi; ++k) {
      const Eigen::Vector2d p0 = terrain[k].position_ned.head<2>(), p1 = terrain[k + 1].position_ned.head<2>();
      const Eigen::Vector2d d = p1 - p0;
      const double u = d.squaredNorm() > 0 ? std::clamp((footprint - p0).dot(d) / d.squaredNorm(), 0.0, 1.0) : 0.0;
      const double dist = (p0 + u * d - footprint).norm();
      if (dist < offtrack) {
        offtrack = dist;
        ground = terrain[k].terrain_height_m + u * (terrain[k + 1].terrain_height_m - terrain[k].terrain_height_m);
      }
    }
  }
  if (offtrack > max_offtrack_m) return false;
  *range_m = (-position.z() - ground) / beam.z();
  return true;
}

// Least squares with a covariance robust to errors shared within a cluster
// (INS attitude errors and terrain are correlated over seconds; treating
// residuals as independent would make the sigmas far too small):
// cov = H^-1 (sum_c g_c g_c^T) H^-1 * G / (G - 1), g_c = J_c^T r_c, never
// below the classical s^2 H^-1.
Eigen::MatrixXd robust_covariance(const Eigen::MatrixXd& jacobian, const Eigen::VectorXd& residual,
                                  const std::vector<int>& cluster, const std::vector<bool>& use) {
  const int p = static_cast<int>(jacobian.cols());
  Eigen::MatrixXd h = Eigen::MatrixXd::Zero(p, p);
  std::map<int, Eigen::VectorXd> g;
  double rss = 0;
  int64_t n = 0;
  for (int i = 0; i < jacobian.rows(); ++i) {
    if (!use[static_cast<size_t>(i)]) continue;
    const Eigen::VectorXd row = jacobian.row(i).transpose();
    h += row * row.transpose();
    auto it = g.find(cluster[static_cast<size_t>(i)]);
    if (it == g.end()) it = g.emplace(cluster[static_cast<size_t>(i)], Eigen::VectorXd::Zero(p)).first;
    it->second += row * residual[i];
    rss += residual[i] * residual[i];
    ++n;
  }
  const Eigen::MatrixXd h_inv = h.ldlt().solve(Eigen::MatrixXd::Identity(p, p));
  Eigen::MatrixXd meat = Eigen::MatrixXd::Zero(p, p);
  for (const auto& [c, v] : g) meat += v * v.transpose();
  const double groups = static_cast<double>(g.size());
  Eigen::MatrixXd cov = h_inv * meat * h_inv * (groups > 1 ? groups / (groups - 1) : 1.0);
  const Eigen::MatrixXd classical = h_inv * (n > p ? rss / static_cast<double>(n - p) : 0.0);
  for (int k = 0; k < p; ++k) {
    if (cov(k, k) < classical(k, k)) {  // keep the larger diagonal, scale its row/column
      const double f = std::sqrt(classical(k, k) / std::max(cov(k, k), 1e-300));
      cov.row(k) *= f;
      cov.col(k) *= f;
    }
  }
  return cov;
}

// The camera fit: parameters boresight roll, pitch, yaw (rad), time offset
// (s), focal scale - 1 and the errors e1, e2 of the first two radial
// distortion coefficients k1, k2. The tracker undistorted each point with the
// configured lens: x~ with distort(x~) = (pixel - c) / f. The true lens
// (focal f (1 + s), k1 + e1, k2 + e2) puts the point where
// distort(x) + (e1 |x|^2 + e2 |x|^4) x = distort(x~) / (1 + s), so to first
// order in s, e1, e2 (each ~0.005: second order 1e-5)
//   x = x~ - J^-1 (s distort(x~) + (e1 |x~|^2 + e2 |x~|^4) x~),
// J the Jacobian of the configured distortion at x~.
constexpr int kCameraParams = 7;

// OpenCV's radial-tangential model (k1, k2, p1, p2, k3) at normalized x, and
// its Jacobian.
struct LensModel {
  double k1 = 0, k2 = 0, p1 = 0, p2 = 0, k3 = 0;
  explicit LensModel(const std::vector<double>& d) {
    const auto at = [&](size_t i) { return i < d.size() ? d[i] : 0.0; };
    k1 = at(0), k2 = at(1), p1 = at(2), p2 = at(3), k3 = at(4);
  }
  Eigen::Vector2d distort(const Eigen::Vector2d& x, Eigen::Matrix2d* jacobian) const {
    const double r2 = x.squaredNorm(), xy = x.x() * x.y();
    const double radial = 1.0 + r2 * (k1 + r2 * (k2 + r2 * k3));
    const double d_radial = k1 + r2 * (2.0 * k2 + 3.0 * r2 * k3);  // d radial / d r2
    *jacobian << radial + 2.0 * x.x() * x.x() * d_radial + 2.0 * p1 * x.y() + 6.0 * p2 * x.x(),
        2.0 * xy * d_radial + 2.0 * p1 * x.x() + 2.0 * p2 * x.y(),
        2.0 * xy * d_radial + 2.0 * p1 * x.x() + 2.0 * p2 * x.y(),
        radial + 2.0 * x.y() * x.y() * d_radial + 6.0 * p1 * x.y() + 2.0 * p2 * x.x();
    return Eigen::Vector2d(x.x() * radial + 2.0 * p1 * xy + p2 * (r2 + 2.0 * x.x() * x.x()),
                           x.y() * radial + p1 * (r2 + 2.0 * x.y() * x.y()) + 2.0 * p2 * xy);
  }
};
class EpipolarFit {
 public:
  // `camera_lever`: the camera centre from the INS reference, body frame (installation drawing).
  EpipolarFit(const FlightData& data, const InsTrack& ins, const CameraModel& configured_camera,
              const Eigen::Vector3d& camera_lever, const CalibrationOptions& options)
      : data_(data),
        ins_(ins),
        lens_(configured_camera.distortion),
        body_from_camera_(configured_camera.body_from_camera),
        camera_lever_(camera_lever),
        options_(options) {
    const double margin_us = 60000.0;  // room for the time offset to move
    for (size_t k = 0; k < data.pairs.size(); ++k) {
      const auto& pair = data.pairs[k];
      if (!ins.covers(pair.prev_utime - margin_us) || !ins.covers(pair.utime + margin_us)) continue;
      Eigen::Vector3d pi, pj;
      ins.at(pair.prev_utime, nullptr, &pi);
      ins.at(pair.utime, nullptr, &pj);
      if ((pj - pi).norm() < options.min_baseline_m) continue;
      pairs_.push_back(k);
      for (size_t f = 0; f < pair.prev_norm.size(); ++f) {
        index_.push_back({k, f});
        const double t = (pair.prev_utime - ins.first_utime()) * 1e-6;
        cluster_.push_back(static_cast<int>(t / options.cluster_s));
        time_s_.push_back(t);
      }
    }
  }
  size_t size() const { return index_.size(); }
  size_t pair_count() const { return pairs_.size(); }
  const std::vector<int>& clusters() const { return cluster_; }
  const std::vector<double>& times_s() const { return time_s_; }

  Eigen::VectorXd residuals(const Eigen::VectorXd& theta) const {
    Eigen::VectorXd r(static_cast<Eigen::Index>(index_.size()));
    const Eigen::Matrix3d r_bc = body_from_camera_ * rotation_from_rpy(theta[0], theta[1], theta[2]);
    const double dt_us = theta[3] * 1e6;
    const double focal_error = theta[4], k1_error = theta[5], k2_error = theta[6];
    auto bearing = [&](const Eigen::Vector2d& norm) {
      Eigen::Matrix2d jacobian;
      const Eigen::Vector2d distorted = lens_.distort(norm, &jacobian);
      const double r2 = norm.squaredNorm();
      const Eigen::Vector2d u =
          norm - jacobian.inverse() * (focal_error * distorted + (k1_error * r2 + k2_error * r2 * r2) * norm);
      return Eigen::Vector3d(u.x(), u.y(), 1.0).normalized();
    };
    size_t row = 0;
    for (size_t k : pairs_) {
      const auto& pair = data_.pairs[k];
      Eigen::Matrix3d ri, rj;
      Eigen::Vector3d pi, pj;
      ins_.at(pair.prev_utime + dt_us, &ri, &pi);
      ins_.at(pair.utime + dt_us, &rj, &pj);
      const Eigen::Vector3d baseline = pj + rj * camera_lever_ - pi - ri * camera_lever_;
      const Eigen::Matrix3d ai = ri * r_bc, aj = rj * r_bc;
      for (size_t f = 0; f < pair.prev_norm.size(); ++f, ++row) {
        const Eigen::Vector3d n = (ai * bearing(pair.prev_norm[f])).cross(baseline);
        const double nn = n.norm();
        r[static_cast<Eigen::Index>(row)] = nn > 0 ? n.dot(aj * bearing(pair.curr_norm[f])) / nn : 0.0;
      }
    }
    return r;
  }

  Eigen::MatrixXd jacobian(const Eigen::VectorXd& theta, const std::vector<bool>& active) const {
    static const double kStep[kCameraParams] = {1e-5, 1e-5, 1e-5, 2e-4, 1e-5, 1e-5, 1e-5};
    Eigen::MatrixXd j = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(size()), kCameraParams);
    for (int k = 0; k < kCameraParams; ++k) {
      if (!active[static_cast<size_t>(k)]) continue;
      Eigen::VectorXd plus = theta, minus = theta;
      plus[k] += kStep[k];
      minus[k] -= kStep[k];
      j.col(k) = (residuals(plus) - residuals(minus)) / (2.0 * kStep[k]);
    }
    return j;
  }

 private:
  struct Index {
    size_t pair, feature;
  };
  const FlightData& data_;
  const InsTrack& ins_;
  LensModel lens_;  // as configured: the lens the tracker undistorted with
  Eigen::Matrix3d body_from_camera_;
  Eigen::Vector3d camera_lever_;
  const CalibrationOptions& options_;
  std::vector<size_t> pairs_;
  std::vector<Index> index_;
  std::vector<int> cluster_;
  std::vector<double> time_s_;  // of each residual's first frame, from the segment start
};

Estimate make_estimate(const std::string& name, double value, double sigma, bool estimated, double limit) {
  Estimate e;
  e.name = name;
  e.value = value;
  e.sigma = sigma;
  e.estimated = estimated;
  e.excited = estimated && sigma <= limit;
  return e;
}

struct CameraFit {
  Eigen::VectorXd theta = Eigen::VectorXd::Zero(kCameraParams);
  Eigen::MatrixXd cov = Eigen::MatrixXd::Zero(kCameraParams, kCameraParams);
  int64_t residuals = 0, outliers = 0;
  double rms = 0.0;
};

// Gauss-Newton from `start`; residuals with a time in [skip_from_s, skip_to_s)
// are left out (the block jackknife).
CameraFit fit_camera(const EpipolarFit& fit, const std::vector<bool>& active, const CalibrationOptions& options,
                     const Eigen::VectorXd& start, int iterations, double skip_from_s = 0.0, double skip_to_s = 0.0) {
  CameraFit out;
  out.theta = start;
  std::vector<bool> use(fit.size(), true);
  auto skipped = [&](size_t i) { return fit.times_s()[i] >= skip_from_s && fit.times_s()[i] < skip_to_s; };
  std::vector<int> act;
  for (int k = 0; k < kCameraParams; ++k)
    if (active[static_cast<size_t>(k)]) act.push_back(k);
  Eigen::VectorXd r;
  Eigen::MatrixXd j;
  for (int it = 0; it < iterations; ++it) {
    r = fit.residuals(out.theta);
    // Robust sigma from the median absolute residual; outliers (mistracks) dropped.
    const double sigma = abs_sigma(std::vector<double>(r.data(), r.data() + r.size()), EvenMedian::kUpper);
    for (size_t i = 0; i < use.size(); ++i)
      use[i] = std::fabs(r[static_cast<Eigen::Index>(i)]) <= options.outlier_sigma * sigma && !skipped(i);
    j = fit.jacobian(out.theta, active);
    Eigen::MatrixXd h = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(act.size()), static_cast<Eigen::Index>(act.size()));
    Eigen::VectorXd g = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(act.size()));
    for (size_t i = 0; i < use.size(); ++i) {
      if (!use[i]) continue;
      Eigen::VectorXd row(static_cast<Eigen::Index>(act.size()));
      for (size_t a = 0; a < act.size(); ++a) row[static_cast<Eigen::Index>(a)] = j(static_cast<Eigen::Index>(i), act[a]);
      h += row * row.transpose();
      g += row * r[static_cast<Eigen::Index>(i)];
    }
    const Eigen::VectorXd step = -h.ldlt().solve(g);
    for (size_t a = 0; a < act.size(); ++a) out.theta[act[a]] += step[static_cast<Eigen::Index>(a)];
    if (step.cwiseAbs().maxCoeff() < 1e-9) break;
  }
  r = fit.residuals(out.theta);
  j = fit.jacobian(out.theta, active);
  Eigen::MatrixXd ja(j.rows(), static_cast<Eigen::Index>(act.size()));
  for (size_t a = 0; a < act.size(); ++a) ja.col(static_cast<Eigen::Index>(a)) = j.col(act[a]);
  const Eigen::MatrixXd cov = robust_covariance(ja, r, fit.clusters(), use);
  for (size_t a = 0; a < act.size(); ++a)
    for (size_t b = 0; b < act.size(); ++b)
      out.cov(act[a], act[b]) = cov(static_cast<Eigen::Index>(a), static_cast<Eigen::Index>(b));
  double rss = 0;
  for (size_t i = 0; i < use.size(); ++i) {
    if (use[i]) {
      rss += r[static_cast<Eigen::Index>(i)] * r[static_cast<Eigen::Index>(i)];
      ++out.residuals;
    } else {
      ++out.outliers;
    }
  }
  out.rms = out.residuals > 0 ? std::sqrt(rss / static_cast<double>(out.residuals)) : 0.0;
  return out;
}

// printf into a string; every conversion in `format` takes a double.
std::string fmt(const char* format, double a, double b = 0.0) {
  char buf[256];
  std::snprintf(buf, sizeof(buf), format, a, b);
  return buf;
}

}  // namespace

void CalibrationOptions::Check() const {
  const std::string src = "calibration options";
  require_option(attitude_smoothing_s >= 0 && attitude_smoothing_s <= 30, src, "attitude_smoothing_s", "must be in [0, 30]");
  require_option(min_baseline_m > 0 && min_baseline_m <= 100, src, "min_baseline_m", "must be in (0, 100]");
  require_option(cluster_s > 0 && cluster_s <= 600, src, "cluster_s", "must be in (0, 600]");
  require_option(jackknife_block_s >= 1 && jackknife_block_s <= 3600, src, "jackknife_block_s", "must be in [1, 3600]");
  require_option(bootstrap_runs == 0 || (bootstrap_runs >= 2 && bootstrap_runs <= 1000), src, "bootstrap_runs", "must be 0 or in [2, 1000]");
  require_option(outlier_sigma >= 2 && outlier_sigma <= 100, src, "outlier_sigma", "must be in [2, 100]");
  require_option(iterations >= 1 && iterations <= 100, src, "iterations", "must be in [1, 100]");
  for (double a : ins_attitude_accuracy_deg)
    require_option(a >= 0 && a <= 10, src, "ins_attitude_accuracy_deg", "must be in [0, 10] per axis");
  require_option(ins_attitude_correlation_s >= 0 && ins_attitude_correlation_s <= 1e5, src,
                 "ins_attitude_correlation_s", "must be in [0, 100000] s");
  require_option(std::isnan(ground_height_m) || std::fabs(ground_height_m) < 1e4, src, "ground_height_m",
                 "must be in (-1e4, 1e4)");
  require_option(altimeter_max_offtrack_m > 0 && altimeter_max_offtrack_m <= 1000, src, "altimeter_max_offtrack_m",
                 "must be in (0, 1000]");
  require_option(gps_scale_min_baseline_m > 0 && gps_scale_min_baseline_m <= 1000, src, "gps_scale_min_baseline_m",
                 "must be in (0, 1000]");
  require_option(segment_from_s >= 0 && segment_until_s > segment_from_s, src, "segment_from_s / segment_until_s",
                 "must satisfy 0 <= from < until");
  require_option(!gps_scale_only || gps_scale_target != GpsScaleTarget::kReport, src, "gps_scale_only",
                 "needs a GNSS scale target (focal or altimeter)");
  require_option(!(gps_scale_target == GpsScaleTarget::kFocal && estimate_focal), src, "gps_scale_target",
                 "focal: the focal length comes from the GNSS scale, so the epipolar focal fit must be off (--no-focal)");
}

FlightData load_flight(const std::string& log_path, bool progress) {
  FlightData data;
  LogReader reader(log_path);
  ProgressBar bar("reading " + log_path, static_cast<double>(reader.size()), progress && stderr_is_terminal());
  std::optional<GeodeticTrack> track;  // the INS fixes' path from the first one
  LogEvent e;
  while (reader.next(&e)) {
    bar.update(static_cast<double>(reader.position()));
    if (e.channel == channels::kIns) {
      ins_t m;
      if (!decode(e, &m)) continue;
      if (!track) {
        track.emplace(GeodeticPoint{m.latitude_deg, m.longitude_deg, m.height_m});
        data.reference_height_m = m.height_m;
      }
      if (!data.ins.empty() && m.utime <= data.ins.back().utime) continue;  // keep time strictly increasing
      data.ins.push_back({m.utime, m.roll, m.pitch, m.yaw, m.has_rates != 0,
                          Eigen::Vector3d(m.angular_rate[0], m.angular_rate[1], m.angular_rate[2]),
                          track->ned({m.latitude_deg, m.longitude_deg, m.height_m})});
    } else if (e.channel == channels::kTracks) {
      tracks_t m;
      if (!decode(e, &m)) continue;
      const int32_t bad = tracks_t::FLAG_FIRST_FRAME | tracks_t::FLAG_FRAME_GAP | tracks_t::FLAG_BAD_IMAGE |
                          tracks_t::FLAG_WRONG_FORMAT;
      if ((m.flags & bad) != 0 || m.num_tracks < 8) continue;
      FlightData::FramePair pair;
      pair.prev_utime = m.prev_utime;
      pair.utime = m.utime;
      for (int32_t i = 0; i < m.num_tracks; ++i) {
        pair.prev_norm.emplace_back(m.prev_norm[i][0], m.prev_norm[i][1]);
        pair.curr_norm.emplace_back(m.curr_norm[i][0], m.curr_norm[i][1]);
      }
      data.pairs.push_back(std::move(pair));
    } else if (e.channel == channels::kAltimeter) {
      altimeter_t m;
      if (!decode(e, &m) || m.validity != altimeter_t::VALID_OK) continue;
      data.altimeter.push_back({m.utime, m.range_m, Eigen::Vector3d(m.beam_body[0], m.beam_body[1], m.beam_body[2])});
    } else if (e.channel == channels::kVoDelta) {
      vo_delta_t m;
      if (!decode(e, &m)) continue;
      data.vo_steps.push_back({m.prev_utime, m.utime, m.dx, m.dy, m.quality});
    } else if (e.channel == channels::kGroundTruth) {
      ground_truth_t m;
      if (!decode(e, &m) || m.kind != ground_truth_t::KIND_INS) continue;
      if (!data.terrain.empty() && m.utime <= data.terrain.back().utime) continue;
      data.terrain.push_back(
          {m.utime, Eigen::Vector3d(m.position_ned[0], m.position_ned[1], m.position_ned[2]), m.terrain_height_m});
    }
  }
  bar.finish();
  data.corrupt_records = reader.corrupt_records();
  // A photo survey of 20 photos carries 40 INS messages (two per photo): enough for the GNSS fits.
  if (data.ins.size() < 20) throw std::runtime_error(log_path + ": fewer than 20 INS messages: no attitude/position reference");
  return data;
}

namespace {

// The part of the flight between from_s and until_s after the first INS
// sample (the INS kept 5 s further on each side for its smoothing).
FlightData restrict_to_segment(const FlightData& all, double from_s, double until_s) {
  if (from_s <= 0.0 && std::isinf(until_s)) return all;
  const double t0 = static_cast<double>(all.ins.front().utime);
  auto inside = [&](int64_t utime, double margin_s) {
    const double t = (static_cast<double>(utime) - t0) * 1e-6;
    return t >= from_s - margin_s && t <= until_s + margin_s;
  };
  FlightData seg;
  seg.reference_height_m = all.reference_height_m;
  seg.corrupt_records = all.corrupt_records;
  for (const auto& s : all.ins)
    if (inside(s.utime, 5.0)) seg.ins.push_back(s);
  for (const auto& p : all.pairs)
    if (inside(p.prev_utime, 0.0) && inside(p.utime, 0.0)) seg.pairs.push_back(p);
  for (const auto& a : all.altimeter)
    if (inside(a.utime, 0.0)) seg.altimeter.push_back(a);
  for (const auto& g : all.terrain)
    if (inside(g.utime, 5.0)) seg.terrain.push_back(g);
  for (const auto& v : all.vo_steps)
    if (inside(v.prev_utime, 0.0) && inside(v.utime, 0.0)) seg.vo_steps.push_back(v);
  if (seg.ins.size() < 2) throw std::runtime_error("calibration segment: no INS data in the chosen segment");
  return seg;
}

}  // namespace

double ins_attitude_sigma_of_mean(double sigma, double correlation_s, double segment_s) {
  if (!(correlation_s > 0) || !(segment_s > 0)) return sigma;
  const double ratio = correlation_s / segment_s;
  return sigma * std::sqrt(2.0 * ratio * (1.0 - ratio * -std::expm1(-1.0 / ratio)));
}

double segment_for_ins_sigma_of_mean(double sigma, double correlation_s, double target) {
  if (sigma <= target) return 0.0;
  if (!(correlation_s > 0) || !(target > 0)) return std::numeric_limits<double>::infinity();
  // The sigma of the mean falls monotonically with the segment: bracket, then bisect.
  double lo = 0.0, hi = correlation_s;
  while (ins_attitude_sigma_of_mean(sigma, correlation_s, hi) > target) {
    lo = hi;
    hi *= 2.0;
  }
  for (int i = 0; i < 60; ++i) {
    const double mid = 0.5 * (lo + hi);
    (ins_attitude_sigma_of_mean(sigma, correlation_s, mid) > target ? lo : hi) = mid;
  }
  return hi;
}

CalibrationResult calibrate(const FlightData& whole_flight, const Config& camera_root,
                            const CalibrationOptions& options) {
  options.Check();
  const FlightData data = restrict_to_segment(whole_flight, options.segment_from_s, options.segment_until_s);
  const CameraModel camera = CameraModel::from_config(camera_root);
  // Installation values the fit takes as known: lever arms, the altimeter
  // beam's misalignment, and the configured range scale and bias (the GNSS scale's start).
  const SensorCalibration configured = SensorCalibration::from_config(camera_root);
  const InsTrack ins(data.ins, options.attitude_smoothing_s);
  CalibrationResult result;
  result.installation = configured;
  result.segment_s = (ins.last_utime() - ins.first_utime()) * 1e-6;

  // --- Camera: boresight, time offset, focal scale, k1 and k2 errors.
  const EpipolarFit fit(data, ins, camera, configured.camera_lever_arm_m, options);
  result.frame_pairs = static_cast<int64_t>(fit.pair_count());
  std::vector<bool> active(kCameraParams, true);
  active[4] = options.estimate_focal;
  active[5] = options.estimate_focal && options.estimate_distortion;
  active[6] = active[5];
  CameraFit cam;
  const bool camera_data = fit.pair_count() >= 20;
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(kCameraParams);
  if (camera_data) {
    cam = fit_camera(fit, active, options, zero, options.iterations);
    // A parameter the flight does not observe is held (focal scale at 1, k1
    // and k2 errors at 0), so that it does not absorb noise into the others.
    // The lens parameters form a chain, focal scale -> k1 -> k2: each is
    // fitted only with the ones before it, so holding one holds the rest.
    auto hold_if_unobservable = [&](int k, double sigma_limit, const char* warning) {
      const size_t index = static_cast<size_t>(k);
      if (!active[index] || std::sqrt(cam.cov(k, k)) <= 5.0 * sigma_limit) return;
      result.warnings.push_back(fmt(warning, std::sqrt(cam.cov(k, k))));
      for (size_t j = index; j < active.size(); ++j) active[j] = false;
      cam = fit_camera(fit, active, options, zero, options.iterations);
    };
    hold_if_unobservable(6, options.distortion_sigma_limit,
                         "distortion_k2_error: not observable in this flight (sigma %.4f); held at 0. Needs rotation "
                         "of several degrees between frames.");
    hold_if_unobservable(5, options.distortion_sigma_limit,
                         "distortion_k1_error: not observable in this flight (sigma %.4f); held at 0. Needs rotation "
                         "of several degrees between frames.");
    hold_if_unobservable(4, options.focal_sigma_limit,
                         "focal_scale: not observable in this flight (sigma %.4f); held at 1. Needs rotation of "
                         "several degrees between frames or a strongly sloped scene.");
    // Block jackknife: errors shared over longer than a cluster (the INS's
    // slowly varying attitude error, the scene) show in how much the estimate
    // moves when a block of the flight is left out. The larger of the two
    // covariances is reported.
    const double span = fit.times_s().empty() ? 0.0 : fit.times_s().back();
    const int blocks = static_cast<int>(std::floor(span / options.jackknife_block_s));
    if (blocks >= 5) {
      std::vector<Eigen::VectorXd> leave_out;
      for (int g = 0; g < blocks; ++g) {
        const double from = g * options.jackknife_block_s;
        const double to = g + 1 == blocks ? span + 1.0 : from + options.jackknife_block_s;
        leave_out.push_back(fit_camera(fit, active, options, cam.theta, 2, from, to).theta);
      }
      Eigen::VectorXd mean = zero;
      for (const auto& v : leave_out) mean += v / static_cast<double>(blocks);
      Eigen::MatrixXd jk = Eigen::MatrixXd::Zero(kCameraParams, kCameraParams);
      for (const auto& v : leave_out) jk += (v - mean) * (v - mean).transpose();
      jk *= static_cast<double>(blocks - 1) / static_cast<double>(blocks);
      for (int k = 0; k < kCameraParams; ++k) {
        if (jk(k, k) > cam.cov(k, k)) {
          const double f = std::sqrt(jk(k, k) / std::max(cam.cov(k, k), 1e-300));
          cam.cov.row(k) *= f;
          cam.cov.col(k) *= f;
        }
      }
    }
    // The residuals hold the tracks' errors; the INS attitude the fit leans
    // on has its own (what the averaging leaves of its noise), and the fit
    // turns small attitude errors into larger boresight and time errors.
    // Bootstrap: refit against the attitude with other draws of that error;
    // the spread is added to the covariance.
    if (options.bootstrap_runs >= 2 && ins.uses_rates()) {
      std::vector<Eigen::VectorXd> draws;
      for (int b = 0; b < options.bootstrap_runs; ++b) {
        const InsTrack other = ins.perturbed(1000 + static_cast<uint64_t>(b));
        const EpipolarFit refit(data, other, camera, configured.camera_lever_arm_m, options);
        draws.push_back(fit_camera(refit, active, options, cam.theta, 2).theta);
      }
      Eigen::VectorXd mean = zero;
      for (const auto& v : draws) mean += v / static_cast<double>(draws.size());
      Eigen::MatrixXd spread = Eigen::MatrixXd::Zero(kCameraParams, kCameraParams);
      for (const auto& v : draws) spread += (v - mean) * (v - mean).transpose() / static_cast<double>(draws.size() - 1);
      cam.cov += spread;
    }
  } else {
    result.warnings.push_back("camera: fewer than 20 usable frame pairs (TRACKS with a baseline >= min_baseline_m); "
                              "replay the tracker over the flight first (nadir_replay --nodes tracker)");
  }
  result.residuals = cam.residuals;
  result.outliers = cam.outliers;
  result.camera_rms_rad = cam.rms;
  const char* names[3] = {"boresight_roll_deg", "boresight_pitch_deg", "boresight_yaw_deg"};
  // Per axis: the fit's own sigma and the INS error's mean over the segment (deg).
  double fit_sigma_deg[3], ins_sigma_deg[3];
  for (int k = 0; k < 3; ++k) {
    fit_sigma_deg[k] = rad_to_deg(std::sqrt(cam.cov(k, k)));
    ins_sigma_deg[k] = ins_attitude_sigma_of_mean(options.ins_attitude_accuracy_deg[static_cast<size_t>(k)],
                                                  options.ins_attitude_correlation_s, result.segment_s);
    result.boresight[static_cast<size_t>(k)] =
        make_estimate(names[k], rad_to_deg(cam.theta[k]), std::hypot(fit_sigma_deg[k], ins_sigma_deg[k]), camera_data,
                      options.boresight_sigma_limit_deg);
  }
  // A boresight pitch error turns every forward step into a climb of the
  // step times the error. When the INS's slowly varying levelling error,
  // averaged over the segment, is most of the pitch's sigma, only a longer
  // segment reduces it: say how long. Over a few correlation times the mean
  // falls only as 1 / sqrt(length) (a segment four times as long halves it):
  // the segment has done what a calibration flight can, and nothing is said.
  constexpr double kLongSegmentCorrelationTimes = 5.0;
  if (camera_data && options.ins_attitude_correlation_s > 0 &&
      result.segment_s < kLongSegmentCorrelationTimes * options.ins_attitude_correlation_s) {
    const double ins_part = ins_sigma_deg[1];
    if (ins_part > fit_sigma_deg[1]) {
      const double halving_s = segment_for_ins_sigma_of_mean(options.ins_attitude_accuracy_deg[1],
                                                             options.ins_attitude_correlation_s, 0.5 * ins_part);
      const double sigma = result.boresight[1].sigma;
      result.warnings.push_back(
          fmt("boresight_pitch_deg: most of its sigma (%.4f deg) is the INS's levelling error averaged over this "
              "%.0f s segment",
              sigma, result.segment_s) +
          fmt(" (%.4f deg); a pitch error turns every step into a climb, %.3f %% of the distance flown at 1 sigma.",
              ins_part, 100.0 * deg_to_rad(sigma)) +
          fmt(" Only a longer segment reduces it: about %.0f s halves it (docs/calibration.md, 'A ten-minute "
              "calibration flight')",
              halving_s));
    }
  }
  result.time_offset_ms = make_estimate("time_offset_ms", cam.theta[3] * 1e3, std::sqrt(cam.cov(3, 3)) * 1e3,
                                        camera_data, options.time_offset_sigma_limit_ms);
  result.focal_scale = make_estimate("focal_scale", 1.0 + cam.theta[4], std::sqrt(cam.cov(4, 4)),
                                     camera_data && active[4], options.focal_sigma_limit);
  result.distortion_k1_error = make_estimate("distortion_k1_error", cam.theta[5], std::sqrt(cam.cov(5, 5)),
                                             camera_data && active[5], options.distortion_sigma_limit);
  result.distortion_k2_error = make_estimate("distortion_k2_error", cam.theta[6], std::sqrt(cam.cov(6, 6)),
                                             camera_data && active[6], options.distortion_sigma_limit);
  const Estimate& e1 = result.distortion_k1_error;
  const Estimate& e2 = result.distortion_k2_error;
  auto significant = [](const Estimate& e) { return std::fabs(e.value) > std::max(3.0 * e.sigma, 0.001); };
  result.distortion = camera.distortion;
  result.distortion.resize(std::max<size_t>(result.distortion.size(), 5), 0.0);
  result.distortion_fitted = e1.estimated && e1.excited && e2.estimated && e2.excited;
  if (result.distortion_fitted) {
    result.distortion[0] += e1.value;
    result.distortion[1] += e2.value;
  }
  if (result.distortion_fitted && (significant(e1) || significant(e2))) {
    result.warnings.push_back(fmt("the lens distortion differs from the configured one (k1 off by %.4f, k2 by %.4f); "
                                  "written with the fitted errors. A chessboard calibration in the lab "
                                  "(OpenCV calibrateCamera) is the better reference",
                                  e1.value, e2.value));
  } else if (e1.estimated && e1.excited && significant(e1)) {
    result.warnings.push_back(fmt("the lens distortion differs from the configured one (k1 off by %.4f +- %.4f) but "
                                  "k2 is not observable here; not written: recalibrate the lens (a chessboard, "
                                  "OpenCV calibrateCamera)",
                                  e1.value, e1.sigma));
  }
  const Eigen::Matrix3d mount = camera.body_from_camera * rotation_from_rpy(cam.theta[0], cam.theta[1], cam.theta[2]);
  result.mount_rpy_deg = rpy_from_rotation(mount) * (180.0 / M_PI);
  result.fx = camera.fx * (1.0 + cam.theta[4]);
  result.fy = camera.fy * (1.0 + cam.theta[4]);
  const char* hints[kCameraParams] = {
      "needs a vertical or sideways baseline (climbs and descents, crabbing) and rotation about the pitch/yaw axes",
      "needs forward flight with rotation about the roll/yaw axes",
      "needs forward flight with rotation about the roll/pitch axes (straight and level flight reveals it only "
      "through the direction of travel)",
      "needs attitude changes (rates of several deg/s that vary: oscillations, turn entries and exits)",
      "needs large rotations between frames",
      "needs large rotations between frames",
      "needs large rotations between frames"};
  const Estimate* camera_estimates[kCameraParams] = {&result.boresight[0], &result.boresight[1],
                                                     &result.boresight[2], &result.time_offset_ms,
                                                     &result.focal_scale,  &result.distortion_k1_error,
                                                     &result.distortion_k2_error};
  for (int k = 0; k < kCameraParams && camera_data; ++k) {
    const Estimate& e = *camera_estimates[k];
    if (e.estimated && !e.excited)
      result.warnings.push_back(e.name + ": weakly excited by this flight (sigma " + fmt("%.4g", e.sigma) + "); " +
                                hints[k]);
  }
  for (int a = 0; a < kCameraParams && camera_data; ++a)
    for (int b = a + 1; b < kCameraParams; ++b) {
      if (!active[static_cast<size_t>(a)] || !active[static_cast<size_t>(b)]) continue;
      const double corr = cam.cov(a, b) / std::sqrt(cam.cov(a, a) * cam.cov(b, b));
      if (std::fabs(corr) > 0.95) {
        result.warnings.push_back(camera_estimates[a]->name + " and " + camera_estimates[b]->name + " are not separable in this flight (correlation " +
                                  fmt("%.3f", corr) + ")");
      }
    }

  // --- Altimeter: measured range = scale * (height above ground along the beam) + bias.
  std::vector<double> x, y;
  std::vector<int> cluster;
  for (const auto& a : data.altimeter) {
    if (!ins.covers(static_cast<double>(a.utime))) continue;
    Eigen::Matrix3d r_wb;
    Eigen::Vector3d p;
    ins.at(static_cast<double>(a.utime), &r_wb, &p);
    const Eigen::Vector3d beam_world = r_wb * configured.true_beam(a.beam_body);
    const Eigen::Vector3d origin_offset = r_wb * configured.altimeter_lever_arm_m;
    double reference = 0.0;
    if (!data.terrain.empty()) {
      if (!agl_along_beam(data.terrain, static_cast<double>(a.utime), origin_offset, beam_world,
                          options.altimeter_max_offtrack_m, &reference))
        continue;
    } else if (!std::isnan(options.ground_height_m)) {
      if (beam_world.z() < 0.5) continue;
      reference = (data.reference_height_m - p.z() - origin_offset.z() - options.ground_height_m) /
                  beam_world.z();  // flat ground
    } else {
      continue;
    }
    x.push_back(reference);
    y.push_back(a.range_m);
    cluster.push_back(static_cast<int>((a.utime - ins.first_utime()) * 1e-6 / options.cluster_s));
  }
  result.altimeter_samples = static_cast<int64_t>(x.size());
  Eigen::Vector2d ab(1.0, 0.0);
  Eigen::Matrix2d acov = Eigen::Matrix2d::Zero();
  const bool altimeter_data = x.size() >= 20;
  if (altimeter_data) {
    // The reference (height above the ground below the vehicle, along the
    // beam) carries the terrain's mismatch with the beam's footprint (metres
    // over relief), the measured range only the altimeter noise: regress the
    // reference on the measurement, x = c1 y + c0 (no attenuation of the
    // slope by the reference's errors), then scale = 1 / c1, bias = -c0 / c1.
    const Eigen::Index n = static_cast<Eigen::Index>(x.size());
    Eigen::MatrixXd j(n, 2);
    Eigen::VectorXd xx(n);
    for (Eigen::Index i = 0; i < n; ++i) {
      j(i, 0) = y[static_cast<size_t>(i)];
      j(i, 1) = 1.0;
      xx[i] = x[static_cast<size_t>(i)];
    }
    std::vector<bool> use(x.size(), true);
    Eigen::Vector2d c(1.0, 0.0);
    for (int it = 0; it < 3; ++it) {  // refit without outliers (terrain edges)
      Eigen::Matrix2d h = Eigen::Matrix2d::Zero();
      Eigen::Vector2d g = Eigen::Vector2d::Zero();
      for (Eigen::Index i = 0; i < n; ++i)
        if (use[static_cast<size_t>(i)]) {
          h += j.row(i).transpose() * j.row(i);
          g += j.row(i).transpose() * xx[i];
        }
      c = h.ldlt().solve(g);
      const Eigen::VectorXd r = xx - j * c;
      const double sigma = abs_sigma(std::vector<double>(r.data(), r.data() + r.size()), EvenMedian::kUpper);
      for (Eigen::Index i = 0; i < n; ++i) use[static_cast<size_t>(i)] = std::fabs(r[i]) <= options.outlier_sigma * sigma;
    }
    const Eigen::VectorXd r = xx - j * c;
    const Eigen::Matrix2d ccov = robust_covariance(j, -r, cluster, use);
    ab = Eigen::Vector2d(1.0 / c[0], -c[1] / c[0]);
    Eigen::Matrix2d g;  // d(scale, bias) / d(c1, c0)
    g << -1.0 / (c[0] * c[0]), 0.0, c[1] / (c[0] * c[0]), -1.0 / c[0];
    acov = g * ccov * g.transpose();
    double rss = 0;
    int64_t used = 0;
    for (Eigen::Index i = 0; i < n; ++i)
      if (use[static_cast<size_t>(i)]) rss += r[i] * r[i], ++used;
    result.altimeter_rms_m = std::sqrt(rss / static_cast<double>(std::max<int64_t>(used, 1)));
  } else {
    result.warnings.push_back("altimeter: fewer than 20 valid ranges with a height-above-ground reference "
                              "(GROUND_TRUTH in the log, or --ground-height-m over flat ground)");
  }
  result.altimeter_scale = make_estimate("altimeter_scale", ab[0], std::sqrt(acov(0, 0)), altimeter_data,
                                         options.altimeter_scale_sigma_limit);
  result.altimeter_bias_m = make_estimate("altimeter_bias_m", ab[1], std::sqrt(acov(1, 1)), altimeter_data,
                                          options.altimeter_bias_sigma_limit_m);
  if (altimeter_data) {
    double mean = 0, var = 0;
    for (double v : x) mean += v / static_cast<double>(x.size());
    for (double v : x) var += (v - mean) * (v - mean) / static_cast<double>(x.size());
    const double corr = acov(0, 1) / std::sqrt(acov(0, 0) * acov(1, 1));
    if (!result.altimeter_scale.excited || !result.altimeter_bias_m.excited || std::fabs(corr) > 0.99)
      result.warnings.push_back(fmt("altimeter scale and bias: poorly separated (height range spread %.1f m, "
                                    "correlation %.3f); fly at two or more heights at least 50 m apart",
                                    std::sqrt(var), corr));
  }

  // --- Image scale against GNSS, from the VO_DELTA of a replay.
  std::vector<PositionSample> positions;
  for (const auto& s : data.ins) positions.push_back({s.utime, s.position_ned, s.yaw});
  const GpsScaleFit gps = fit_gps_scale(data.vo_steps, positions, kUnsolvedQualityMask,
                                        options.gps_scale_min_baseline_m, options.outlier_sigma);
  // The recorded yaw against the images' heading, on the same pairs.
  const HeadingOffsetFit heading = fit_heading_offset(data.vo_steps, positions, kUnsolvedQualityMask,
                                                      options.gps_scale_min_baseline_m, options.outlier_sigma);
  result.heading_offset_deg = make_estimate("heading_offset_deg", heading.offset_rad * (180.0 / M_PI),
                                            heading.sigma_rad * (180.0 / M_PI), heading.pairs >= 10, 2.0);
  result.heading_offset_applied = options.gps_scale_only && result.heading_offset_deg.estimated &&
                                  std::fabs(result.heading_offset_deg.value) > 3.0 * result.heading_offset_deg.sigma;
  result.configured_mount_rpy_deg = rpy_from_rotation(camera.body_from_camera) * (180.0 / M_PI);
  result.gps_scale_pairs = gps.pairs;
  result.gps_scale = make_estimate("gps_scale", gps.scale, gps.sigma, gps.pairs >= 10, 0.01);
  result.gps_scale_target = options.gps_scale_target;
  result.range_scale = altimeter_data ? result.altimeter_scale.value : configured.altimeter_range_scale;
  result.range_bias_m = altimeter_data ? result.altimeter_bias_m.value : configured.altimeter_range_bias_m;
  result.scale_only = options.gps_scale_only;
  if (options.gps_scale_target != CalibrationOptions::GpsScaleTarget::kReport) {
    if (!result.gps_scale.estimated)
      throw std::runtime_error(fmt("GNSS scale: %.0f solved frame pair(s) with VO_DELTA and a GNSS baseline of at "
                                   "least %.1f m, 10 needed (replay vo_solver over the flight first, or give a "
                                   "longer segment)",
                                   static_cast<double>(gps.pairs), options.gps_scale_min_baseline_m));
    if (options.gps_scale_target == CalibrationOptions::GpsScaleTarget::kFocal) {
      result.fx = camera.fx / gps.scale;
      result.fy = camera.fy / gps.scale;
    } else {
      if (altimeter_data)
        throw std::runtime_error("GNSS scale into the altimeter: the altimeter scale was also fitted from ranges "
                                 "against a height reference; use one of the two");
      result.range_scale = configured.altimeter_range_scale / gps.scale;
    }
  }
  return result;
}

std::string CalibrationResult::config_fragment(const std::string& source) const {
  std::ostringstream o;
  auto line = [&](const Estimate& e) {
    return (e.estimated ? fmt("%.4f +- %.4f", e.value, e.sigma) : std::string("not estimated")) +
           (e.estimated && !e.excited ? " (weakly excited)" : "");
  };
  o << "# nadir_calibrate: from " << source << " (" << frame_pairs << " frame pairs, " << altimeter_samples
    << " altimeter ranges, " << fmt("%.1f", segment_s) << " s)\n";
  o << "# boresight roll  " << line(boresight[0]) << " deg\n";
  o << "# boresight pitch " << line(boresight[1]) << " deg\n";
  o << "# boresight yaw   " << line(boresight[2]) << " deg\n";
  o << "# time offset     " << line(time_offset_ms) << " ms\n";
  o << "# focal scale     " << line(focal_scale) << "\n";
  o << "# k1 error        " << line(distortion_k1_error) << "\n";
  o << "# k2 error        " << line(distortion_k2_error) << "\n";
  o << "# altimeter scale " << line(altimeter_scale) << "\n";
  o << "# altimeter bias  " << line(altimeter_bias_m) << " m\n";
  o << "# GNSS scale      " << line(gps_scale) << " (GNSS baseline / VO step, " << gps_scale_pairs << " pairs"
    << (gps_scale_target == CalibrationOptions::GpsScaleTarget::kFocal       ? "; written as the focal length"
        : gps_scale_target == CalibrationOptions::GpsScaleTarget::kAltimeter ? "; written as the altimeter scale"
                                                                             : "; not applied")
    << ")\n";
  o << "# heading offset  " << line(heading_offset_deg) << " deg (image heading - recorded yaw, the same pairs"
    << (heading_offset_applied ? "; written into the camera mount's yaw"
        : scale_only           ? "; not written: within 3 sigma of zero, the recorded yaw is kept"
                               : "; not applied")
    << ")\n";
  for (const std::string& w : warnings) o << "# warning: " << w << "\n";
  if (scale_only) {  // only the keys the GNSS scale sets; everything else stays as configured
    const bool focal = gps_scale_target == CalibrationOptions::GpsScaleTarget::kFocal;
    if (focal || heading_offset_applied) o << "camera:\n";
    if (focal) o << "  fx: " << fmt("%.3f", fx) << "\n  fy: " << fmt("%.3f", fy) << "\n";
    if (heading_offset_applied) {
      o << "  mount_rpy_deg: [" << fmt("%.4f", configured_mount_rpy_deg[0]) << ", "
        << fmt("%.4f", configured_mount_rpy_deg[1]) << ", "
        << fmt("%.4f", configured_mount_rpy_deg[2] + heading_offset_deg.value) << "]\n";
    }
    if (!focal) o << "altimeter:\n  range_scale: " << fmt("%.5f", range_scale) << "\n";
    return o.str();
  }
  o << "camera:\n";
  o << "  mount_rpy_deg: [" << fmt("%.4f", mount_rpy_deg[0]) << ", " << fmt("%.4f", mount_rpy_deg[1]) << ", "
    << fmt("%.4f", mount_rpy_deg[2]) << "]\n";
  if ((focal_scale.estimated && focal_scale.excited) ||
      gps_scale_target == CalibrationOptions::GpsScaleTarget::kFocal) {
    o << "  fx: " << fmt("%.3f", fx) << "\n";
    o << "  fy: " << fmt("%.3f", fy) << "\n";
  }
  if (!distortion.empty()) {
    if (distortion_fitted) {
      o << "  # the configured k1, k2 with the fitted errors (k1 " << fmt("%+.4f", distortion_k1_error.value)
        << ", k2 " << fmt("%+.4f", distortion_k2_error.value) << ")\n";
    } else {
      o << "  # as configured (not fitted here)\n";
    }
    o << "  distortion: [";
    for (size_t k = 0; k < distortion.size(); ++k) o << (k ? ", " : "") << fmt("%.5g", distortion[k]);
    o << "]\n";
  }
  o << "  # exposure time = image stamp + offset (vo_solver and yaw_fusion read the INS/altimeter there).\n";
  o << "  time_offset_us: " << fmt("%.0f", time_offset_ms.estimated ? time_offset_ms.value * 1e3 : 0.0) << "\n";
  auto vector = [](const auto& v) {
    std::string out = "[";
    for (Eigen::Index k = 0; k < v.size(); ++k) out += (k ? ", " : "") + fmt("%.4g", v[k]);
    return out + "]";
  };
  const char* kGiven = "  # as configured (the installation drawing), not fitted\n";
  if (!installation.camera_lever_arm_m.isZero(0.0))
    o << kGiven << "  lever_arm_m: " << vector(installation.camera_lever_arm_m) << "\n";
  o << "altimeter:\n";
  if (!installation.altimeter_lever_arm_m.isZero(0.0) || !installation.altimeter_beam_misalignment_rad.isZero(0.0)) {
    o << kGiven << "  lever_arm_m: " << vector(installation.altimeter_lever_arm_m) << "\n";
    o << "  beam_misalignment_deg: " << vector(Eigen::Vector2d(installation.altimeter_beam_misalignment_rad * (180.0 / M_PI)))
      << "\n";
  }
  o << "  # vo_solver and yaw_fusion use true range = (measured - range_bias_m) / range_scale.\n";
  o << "  range_scale: " << fmt("%.5f", range_scale) << "\n";
  o << "  range_bias_m: " << fmt("%.3f", range_bias_m) << "\n";
  return o.str();
}

std::string CalibrationResult::json() const {
  JsonWriter j;
  j.begin_object();
  auto put = [&](const Estimate& e) {
    j.key(e.name).begin_object();
    j.field("value", e.value).field("sigma", e.sigma).field("estimated", e.estimated).field("excited", e.excited);
    j.end_object();
  };
  for (const Estimate& e : boresight) put(e);
  put(time_offset_ms);
  put(focal_scale);
  put(distortion_k1_error);
  put(distortion_k2_error);
  put(altimeter_scale);
  put(altimeter_bias_m);
  put(gps_scale);
  put(heading_offset_deg);
  j.field("heading_offset_applied", heading_offset_applied);
  j.key("mount_rpy_deg").begin_array().value(mount_rpy_deg[0]).value(mount_rpy_deg[1]).value(mount_rpy_deg[2]).end_array();
  j.field("frame_pairs", frame_pairs).field("residuals", residuals).field("outliers", outliers);
  j.field("altimeter_samples", altimeter_samples).field("camera_rms_rad", camera_rms_rad);
  j.field("altimeter_rms_m", altimeter_rms_m).field("segment_s", segment_s);
  j.key("warnings").begin_array();
  for (const std::string& w : warnings) j.value(w);
  j.end_array();
  j.end_object();
  return j.str();
}

}  // namespace nadir::calibrate
