// Map fixes (MAP_FIX) in yaw fusion: a delayed measurement at its frame's
// time that bounds the drift, gated, flagged, the covariance honest, and the
// same poses whenever the fix arrives before it is due.

#include <gtest/gtest.h>

#include <Eigen/LU>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "processes/yaw_fusion/yaw_fusion_estimator.h"
#include "estimator_runner.h"
#include "synthetic_flight.h"

namespace nadir {
namespace {

using test::FlightSpec;
using test::SyntheticFlight;
using test::TimedMessage;

FlightSpec drifting_flight() {
  FlightSpec spec;
  spec.frames = 1400;  // 100 s at 14 Hz
  // VO noise: the position drifts by about the sigma yaw fusion's own
  // uncertainty model gives (0.5-1.3 m over the flight; it does not take the
  // delta's covariance as it is).
  spec.translation_stddev_m = 0.02;
  spec.covariance_translation_stddev_m = 0.02;
  spec.dyaw_stddev_deg = 0.02;
  spec.covariance_dyaw_stddev_deg = 0.02;
  return spec;
}

// A fix of frame k: the truth (from the first frame) + noise of `stddev`, covariance stddev^2.
map_fix_t fix_at(const SyntheticFlight& flight, size_t k, double stddev, std::mt19937* rng,
                 const Eigen::Vector2d& offset_m = Eigen::Vector2d::Zero()) {
  std::normal_distribution<double> noise(0.0, stddev);
  map_fix_t f{};
  f.utime = flight.truth[k].utime;
  const Eigen::Vector3d p = flight.truth[k].position - flight.truth.front().position;
  f.position_ne[0] = p.x() + noise(*rng) + offset_m.x();
  f.position_ne[1] = p.y() + noise(*rng) + offset_m.y();
  f.covariance_ne[0][0] = f.covariance_ne[1][1] = stddev * stddev;
  f.gsd_m = 1.0;
  f.score = 0.8;
  return f;
}

// The flight's messages with `fixes` arriving `latency_us` after their frame
// (VO deltas arrive 80 ms after theirs).
std::vector<TimedMessage> with_fixes(const SyntheticFlight& flight, const std::vector<map_fix_t>& fixes,
                                     int64_t latency_us) {
  const std::vector<TimedMessage> base = test::arrival_order(flight, 80'000, 2'000, 5'000);
  std::vector<TimedMessage> out;
  size_t next = 0;
  for (const TimedMessage& m : base) {
    while (next < fixes.size() && m.channel == channels::kVoDelta && fixes[next].utime + latency_us <= m.utime + 80'000) {
      out.push_back(TimedMessage{channels::kMapFix, fixes[next].utime, test::encode(fixes[next])});
      ++next;
    }
    out.push_back(m);
  }
  return out;
}

// `systematic_stddev_m`: yaw_fusion.map_fix.systematic_stddev_m; 0 (none)
// where a test checks the delayed measurement's own algebra.
std::vector<pose_t> run(const SyntheticFlight& flight, const std::vector<map_fix_t>& fixes, int64_t latency_us,
                        YawFusionCounters* counters = nullptr, double systematic_stddev_m = 0.0) {
  YawFusionOptions options;
  options.map_fix_systematic_stddev_m = systematic_stddev_m;
  // The synthetic INS roll/pitch is exact: no levelling error to carry (a
  // made-up one pads the sigma the fixes are judged against).
  options.sensor_uncertainty.roll_pitch_stddev_deg = 0.0;
  YawFusionEstimator estimator{options};
  const auto poses = test::run(estimator, with_fixes(flight, fixes, latency_us));
  if (counters) *counters = estimator.counters();
  return poses;
}

Eigen::Vector2d horizontal_error(const SyntheticFlight& flight, const pose_t& pose) {
  for (const auto& t : flight.truth) {
    if (t.utime == pose.utime) {
      const Eigen::Vector3d p = t.position - flight.truth.front().position;
      return {pose.position_ned[0] - p.x(), pose.position_ned[1] - p.y()};
    }
  }
  ADD_FAILURE() << "no truth at " << pose.utime;
  return {0, 0};
}

double nees(const SyntheticFlight& flight, const pose_t& pose) {
  const Eigen::Vector2d e = horizontal_error(flight, pose);
  Eigen::Matrix2d c;
  c << pose.position_covariance[0][0], pose.position_covariance[0][1], pose.position_covariance[1][0],
      pose.position_covariance[1][1];
  return e.dot(c.inverse() * e);
}

std::vector<map_fix_t> fixes_every(const SyntheticFlight& flight, size_t every, double stddev, uint32_t seed) {
  std::mt19937 rng(seed);
  std::vector<map_fix_t> fixes;
  for (size_t k = every; k + 20 < flight.truth.size(); k += every) fixes.push_back(fix_at(flight, k, stddev, &rng));
  return fixes;
}

TEST(YawFusionMapFix, FixesBoundTheDriftWithAnHonestCovariance) {
  const SyntheticFlight flight = test::make_flight(drifting_flight());
  const auto free = run(flight, {}, 0);
  YawFusionCounters c;
  const std::vector<map_fix_t> fixes = fixes_every(flight, 14, 0.3, 3);
  const auto fixed = run(flight, fixes, 150'000, &c);
  ASSERT_EQ(free.size(), fixed.size());
  EXPECT_EQ(c.map_fixes_applied, static_cast<int64_t>(fixes.size()));
  EXPECT_EQ(c.map_fixes_rejected, 0);
  int flagged = 0;
  double worst_fixed = 0.0, mean_nees = 0.0;
  for (const pose_t& p : fixed) {
    if (p.flags & pose_t::FLAG_MAP_FIX_APPLIED) ++flagged;
    if (p.utime > fixed.front().utime + 10'000'000) {
      worst_fixed = std::max(worst_fixed, horizontal_error(flight, p).norm());
      mean_nees += nees(flight, p);
    }
  }
  mean_nees /= static_cast<double>(fixed.size());
  EXPECT_EQ(flagged, static_cast<int>(fixes.size()));
  const double free_error = horizontal_error(flight, free.back()).norm();
  const double fixed_error = horizontal_error(flight, fixed.back()).norm();
  const double free_sigma = std::sqrt(free.back().position_covariance[0][0] + free.back().position_covariance[1][1]);
  const double fixed_sigma =
      std::sqrt(fixed.back().position_covariance[0][0] + fixed.back().position_covariance[1][1]);
  // A fix of 0.3 m every second: the error and the sigma stay under a metre.
  EXPECT_LT(worst_fixed, 1.0);
  EXPECT_LT(fixed_sigma, 0.6);
  EXPECT_LT(fixed_sigma, 0.5 * free_sigma) << "free error " << free_error << " fixed " << fixed_error;
  // Consistent: horizontal NEES (2 degrees of freedom) near 2, not far below or above.
  EXPECT_GT(mean_nees, 0.3);
  EXPECT_LT(mean_nees, 4.0);
}

TEST(YawFusionMapFix, FixesSharingAMapErrorStayConsistent) {
  // Fixes of 0.1 m scatter every second, all off by the same offset (a
  // map's georeferencing, or its shading under another sun), drawn per
  // flight from N(0, 0.5 m) each axis. Taken as independent, a hundred
  // fixes average their scatter away and the pose's sigma falls below the
  // offset it keeps; with the map's systematic error (0.5 m) carried as a
  // consider parameter the NEES stays within a factor two of 2.
  const SyntheticFlight flight = test::make_flight(drifting_flight());
  std::mt19937 offsets(17);
  std::normal_distribution<double> map_error(0.0, 0.5);
  auto mean_nees_after_10_s = [&](const std::vector<pose_t>& poses) {
    double sum = 0.0;
    int n = 0;
    for (const pose_t& p : poses) {
      if (p.utime <= poses.front().utime + 10'000'000) continue;
      sum += nees(flight, p);
      ++n;
    }
    return sum / n;
  };
  const int flights = 40;
  double independent = 0.0, considered = 0.0, worst_final = 0.0;
  for (int i = 0; i < flights; ++i) {
    const Eigen::Vector2d offset(map_error(offsets), map_error(offsets));
    std::mt19937 rng(100 + i);
    std::vector<map_fix_t> fixes;
    for (size_t k = 14; k + 20 < flight.truth.size(); k += 14) fixes.push_back(fix_at(flight, k, 0.1, &rng, offset));
    YawFusionCounters c;
    const auto with_map_error = run(flight, fixes, 150'000, &c, 0.5);
    // A fix may be gated where the map's error is beyond 2 sigma of it.
    EXPECT_GE(c.map_fixes_applied, static_cast<int64_t>(fixes.size()) - 3) << offset.transpose();
    independent += mean_nees_after_10_s(run(flight, fixes, 150'000, nullptr, 0.0)) / flights;
    considered += mean_nees_after_10_s(with_map_error) / flights;
    // Held to the fixes: what is left is about the offset, not the drift.
    worst_final = std::max(worst_final, (horizontal_error(flight, with_map_error.back()) - offset).norm());
  }
  std::printf("mean NEES after 10 s over %d flights: %.2f taking the fixes as independent, %.2f with the map's error\n",
              flights, independent, considered);
  // (50.5 against 2.6; the fixes' own scatter and the VO model alone give
  // about 2.)
  EXPECT_GT(independent, 1.5 * considered);
  EXPECT_GT(considered, 1.0);
  EXPECT_LT(considered, 4.0);
  EXPECT_LT(worst_final, 1.0);
}

TEST(YawFusionMapFix, AppliedAsTheDelayedMeasurementAtItsFrame) {
  // One fix, with the filter's variance and the fix's equal: the position
  // at the next pose moves by half the innovation (the motion since the
  // frame is independent of the error at it), the variance by about half
  // the frame's.
  const SyntheticFlight flight = test::make_flight(drifting_flight());
  const auto free = run(flight, {}, 0);
  const size_t k = 700;
  const pose_t& at_frame = free[k];
  ASSERT_EQ(at_frame.utime, flight.truth[k].utime);
  map_fix_t fix{};
  fix.utime = at_frame.utime;
  const double sigma = std::sqrt(at_frame.position_covariance[0][0]);
  fix.position_ne[0] = at_frame.position_ned[0] + 1.0 * sigma;
  fix.position_ne[1] = at_frame.position_ned[1] - 0.7 * sigma;
  fix.covariance_ne[0][0] = at_frame.position_covariance[0][0];
  fix.covariance_ne[1][1] = at_frame.position_covariance[1][1];
  fix.covariance_ne[0][1] = fix.covariance_ne[1][0] = at_frame.position_covariance[0][1];
  YawFusionCounters c;
  const auto fixed = run(flight, {fix}, 100'000, &c);
  EXPECT_EQ(c.map_fixes_applied, 1) << c.last_problem << " unmatched " << c.map_fixes_unmatched << " rejected "
                                    << c.map_fixes_rejected;
  size_t applied = 0;
  for (size_t i = 0; i < fixed.size(); ++i) {
    if (fixed[i].flags & pose_t::FLAG_MAP_FIX_APPLIED) applied = i;
  }
  ASSERT_GT(applied, k);
  // Due 0.5 s after its frame: the first pose at or after that.
  EXPECT_GE(fixed[applied].utime, fix.utime + 500'000);
  EXPECT_LT(fixed[applied - 1].utime, fix.utime + 500'000);
  // (P_f = R and P_f nearly isotropic: half of the innovation.)
  EXPECT_NEAR(fixed[applied].position_ned[0] - free[applied].position_ned[0], 0.5 * sigma, 0.02 * sigma);
  EXPECT_NEAR(fixed[applied].position_ned[1] - free[applied].position_ned[1], -0.35 * sigma, 0.02 * sigma);
  // The variance loses half the frame's (one delta's growth after the fix
  // differs a little: the fix drops the position's correlation with the yaw).
  const double p_frame = at_frame.position_covariance[0][0];
  EXPECT_NEAR(fixed[applied].position_covariance[0][0] - free[applied].position_covariance[0][0], -0.5 * p_frame,
              0.05 * p_frame);
  // Poses before it are untouched.
  for (size_t i = 0; i < applied; ++i) EXPECT_EQ(fixed[i].position_ned[0], free[i].position_ned[0]);
}

TEST(YawFusionMapFix, AWrongFixIsGatedAndChangesNothing) {
  const SyntheticFlight flight = test::make_flight(drifting_flight());
  std::mt19937 rng(5);
  const map_fix_t wrong = fix_at(flight, 600, 0.3, &rng, Eigen::Vector2d(30.0, 0.0));  // 30 m north of the truth, claiming 0.3 m
  map_fix_t broken = fix_at(flight, 900, 1.0, &rng);
  broken.position_ne[1] = std::nan("");
  YawFusionCounters c;
  const auto free = run(flight, {}, 0);
  const auto with_wrong = run(flight, {wrong, broken}, 200'000, &c);
  EXPECT_EQ(c.map_fixes_rejected, 1);
  EXPECT_EQ(c.map_fixes_invalid, 1);
  EXPECT_EQ(c.map_fixes_applied, 0);
  ASSERT_EQ(free.size(), with_wrong.size());
  int rejected_flags = 0;
  for (size_t i = 0; i < free.size(); ++i) {
    EXPECT_EQ(free[i].position_ned[0], with_wrong[i].position_ned[0]);
    EXPECT_EQ(free[i].position_covariance[0][0], with_wrong[i].position_covariance[0][0]);
    if (with_wrong[i].flags & pose_t::FLAG_MAP_FIX_REJECTED) ++rejected_flags;
  }
  EXPECT_EQ(rejected_flags, 1);
}

TEST(YawFusionMapFix, SamePosesWhenTheFixComesAnyTimeBeforeItIsDue) {
  // Live, a fix comes ~0.1-0.3 s after its frame; in a lockstep replay right
  // after its pose. Applied at a fixed sensor time, both give the same poses.
  const SyntheticFlight flight = test::make_flight(drifting_flight());
  const std::vector<map_fix_t> fixes = fixes_every(flight, 14, 0.3, 9);
  const auto early = run(flight, fixes, 0);
  const auto late = run(flight, fixes, 350'000);
  ASSERT_EQ(early.size(), late.size());
  for (size_t i = 0; i < early.size(); ++i) {
    ASSERT_EQ(early[i].utime, late[i].utime);
    EXPECT_EQ(early[i].position_ned[0], late[i].position_ned[0]) << i;
    EXPECT_EQ(early[i].position_ned[1], late[i].position_ned[1]) << i;
    EXPECT_EQ(early[i].flags, late[i].flags) << i;
  }
}

}  // namespace
}  // namespace nadir

namespace nadir {
namespace {

// The DEM's ground under a fix of frame k (POSE's down axis, origin the first
// frame) on the synthetic flight's sloping ground, read at the fix's own
// (noisy) position.
void add_ground(const FlightSpec& spec, const SyntheticFlight& flight, double dem_stddev_m, map_fix_t* fix) {
  const Eigen::Vector3d origin = flight.truth.front().position;
  const Eigen::Vector2d slope(spec.terrain_gradient_north, spec.terrain_gradient_east);
  const Eigen::Vector2d world(fix->position_ne[0] + origin.x(), fix->position_ne[1] + origin.y());
  fix->ground_down_m = spec.height_agl_m + slope.dot(world) - origin.z();
  fix->ground_gradient_ne[0] = slope.x();
  fix->ground_gradient_ne[1] = slope.y();
  fix->ground_down_variance = dem_stddev_m * dem_stddev_m;
}

TEST(YawFusionMapFix, TheDemsGroundFixesTheHeight) {
  // The VO climb is 2 mm too high at every pair (a pitch error of the
  // camera: 2.8 m over the flight) over ground sloping 3 % north; the
  // altimeter measures along its tilted beam.
  FlightSpec spec = drifting_flight();
  spec.dz_bias_m = 0.002;
  spec.dz_stddev_m = 0.005;
  spec.terrain_gradient_north = 0.03;
  spec.altimeter_along_beam = true;
  const SyntheticFlight flight = test::make_flight(spec);
  std::vector<map_fix_t> fixes = fixes_every(flight, 14, 0.3, 5);
  const std::vector<map_fix_t> horizontal = fixes;
  for (map_fix_t& f : fixes) add_ground(spec, flight, 0.1, &f);

  auto fly = [&](const std::vector<map_fix_t>& with, double systematic_vertical_m, YawFusionCounters* counters) {
    YawFusionOptions options;
    options.map_fix_systematic_stddev_m = 0.0;
    options.map_fix_systematic_vertical_stddev_m = systematic_vertical_m;
    options.sensor_uncertainty.roll_pitch_stddev_deg = 0.0;
    YawFusionEstimator estimator{options};
    const auto poses = test::run(estimator, with_fixes(flight, with, 150'000));
    *counters = estimator.counters();
    return poses;
  };
  auto vertical_error = [&](const pose_t& p) {
    for (const auto& t : flight.truth) {
      if (t.utime == p.utime) return p.position_ned[2] - (t.position.z() - flight.truth.front().position.z());
    }
    ADD_FAILURE() << "no truth at " << p.utime;
    return 0.0;
  };
  YawFusionCounters c_free, c_fixed, c_considered;
  const auto free = fly(horizontal, 0.0, &c_free);
  const auto fixed = fly(fixes, 0.0, &c_fixed);
  EXPECT_EQ(c_free.map_fixes_with_height, 0);
  EXPECT_EQ(c_fixed.map_fixes_with_height, static_cast<int64_t>(fixes.size()));
  EXPECT_EQ(c_fixed.map_fixes_rejected, 0);
  ASSERT_EQ(free.size(), fixed.size());
  const double free_error = vertical_error(free.back()), fixed_error = vertical_error(fixed.back());
  EXPECT_GT(std::abs(free_error), 2.0);  // the climb's error, left by horizontal fixes
  EXPECT_LT(std::abs(fixed_error), 0.3) << "free " << free_error;
  double worst = 0.0, nees_sum = 0.0;
  int counted = 0;
  for (const pose_t& p : fixed) {
    if (p.utime < fixed.front().utime + 10'000'000) continue;
    const double e = vertical_error(p);
    worst = std::max(worst, std::abs(e));
    nees_sum += e * e / p.position_covariance[2][2];
    ++counted;
  }
  EXPECT_LT(worst, 0.5);
  EXPECT_LT(nees_sum / counted, 9.0) << "vertical NEES (1 dof)";
  EXPECT_LT(fixed.back().position_covariance[2][2], free.back().position_covariance[2][2]);
  // The horizontal is the same fix's.
  EXPECT_LT(horizontal_error(flight, fixed.back()).norm(), 1.0);

  // A DEM datum that all heights may share (1 m, the default): a
  // disagreement might be the datum's, so each fix pulls less; the climb
  // error here is beyond the pose's covariance, the fixes keep disagreeing
  // and the consistency check (map_fix.consistency_window) widens the pose's
  // sigma until they pull it. The sigma stays wider.
  const auto considered = fly(fixes, 1.0, &c_considered);
  EXPECT_EQ(c_considered.map_fixes_with_height, static_cast<int64_t>(fixes.size()));
  EXPECT_LT(std::abs(vertical_error(considered.back())), std::abs(free_error) - 0.5);
  EXPECT_GT(considered.back().position_covariance[2][2], 4.0 * fixed.back().position_covariance[2][2]);
  std::printf("final vertical error: horizontal fixes %.2f m (sigma %.2f), with heights %.2f m (sigma %.2f), "
              "with a 1 m datum error carried %.2f m (sigma %.2f)\n",
              free_error, std::sqrt(free.back().position_covariance[2][2]), fixed_error,
              std::sqrt(fixed.back().position_covariance[2][2]), vertical_error(considered.back()),
              std::sqrt(considered.back().position_covariance[2][2]));
}

}  // namespace
}  // namespace nadir

namespace nadir {
namespace {

TEST(YawFusionMapFix, FixesThatKeepDisagreeingInflateThePose) {
  // The VO's steps scatter five times what their covariance says (a random
  // walk of about 2 m over 100 s reported as 0.4 m), and the map's error
  // common to all fixes is carried (0.5 m): without the consistency check
  // the pose takes the fixes' disagreement as the map's offset and keeps its
  // error; with it the covariance grows to what the fixes see and the pose
  // follows them.
  FlightSpec spec = drifting_flight();
  spec.translation_stddev_m = 0.05;
  spec.covariance_translation_stddev_m = 0.01;
  spec.seed = 11;
  const SyntheticFlight flight = test::make_flight(spec);
  const std::vector<map_fix_t> fixes = fixes_every(flight, 14, 0.3, 9);
  auto fly = [&](int window) {
    YawFusionOptions options;
    options.map_fix_consistency_window = window;
    options.sensor_uncertainty.roll_pitch_stddev_deg = 0.0;
    // The check alone: with the heading bias estimated the fixes also pull
    // the pose through the bias (map_fix.estimates_heading_bias), and a drift
    // like this one is partly followed that way.
    options.map_fix_estimates_heading_bias = false;
    YawFusionEstimator estimator{options};
    return test::run(estimator, with_fixes(flight, fixes, 150'000));
  };
  const auto locked = fly(0), adapted = fly(10);
  ASSERT_EQ(locked.size(), adapted.size());
  auto stats = [&](const std::vector<pose_t>& poses, double* rms, double* mean_nees) {
    double sum = 0.0, nees_sum = 0.0;
    int n = 0;
    for (const pose_t& p : poses) {
      if (p.utime < poses.front().utime + 30'000'000) continue;
      sum += horizontal_error(flight, p).squaredNorm();
      nees_sum += nees(flight, p);
      ++n;
    }
    *rms = std::sqrt(sum / n);
    *mean_nees = nees_sum / n;
  };
  double locked_rms = 0, locked_nees = 0, adapted_rms = 0, adapted_nees = 0;
  stats(locked, &locked_rms, &locked_nees);
  stats(adapted, &adapted_rms, &adapted_nees);
  std::printf("after 30 s: error %.2f m rms, horizontal NEES %.2f without the check; %.2f m, %.2f with it\n",
              locked_rms, locked_nees, adapted_rms, adapted_nees);
  EXPECT_GT(locked_nees, 4.0);  // the lock: over-confident
  EXPECT_LT(adapted_nees, 3.5);
  EXPECT_LT(adapted_rms, 0.85 * locked_rms);
  // A consistent flight is left as it is: the check never fires on
  // FixesBoundTheDriftWithAnHonestCovariance's flight.
  const SyntheticFlight honest = test::make_flight(drifting_flight());
  const std::vector<map_fix_t> honest_fixes = fixes_every(honest, 14, 0.3, 3);
  YawFusionOptions with_check, without_check;
  without_check.map_fix_consistency_window = 0;
  with_check.map_fix_estimates_heading_bias = without_check.map_fix_estimates_heading_bias = false;
  with_check.sensor_uncertainty.roll_pitch_stddev_deg = without_check.sensor_uncertainty.roll_pitch_stddev_deg = 0.0;
  YawFusionEstimator a{with_check}, b{without_check};
  const auto pa = test::run(a, with_fixes(honest, honest_fixes, 150'000));
  const auto pb = test::run(b, with_fixes(honest, honest_fixes, 150'000));
  ASSERT_EQ(pa.size(), pb.size());
  int differing = 0;
  for (size_t i = 0; i < pa.size(); ++i) differing += pa[i].position_ned[0] != pb[i].position_ned[0];
  EXPECT_LT(differing, static_cast<int>(pa.size()) / 10);
}

}  // namespace
}  // namespace nadir

namespace nadir {
namespace {

// 200 s through turns at 30 m/s, the VO four times quieter than drifting_flight's.
FlightSpec long_turning_flight() {
  FlightSpec spec = drifting_flight();
  spec.frames = 2800;
  spec.translation_stddev_m = spec.covariance_translation_stddev_m = 0.005;
  spec.dyaw_stddev_deg = spec.covariance_dyaw_stddev_deg = 0.005;
  return spec;
}

// long_turning_flight with the INS heading 0.1 deg off all flight, and fixes
// of 0.3 m every second for its first 100 s (none after fixes_end).
struct BiasedHeadingFlight {
  SyntheticFlight flight;
  std::vector<map_fix_t> fixes;
  int64_t fixes_end = 0;
};
BiasedHeadingFlight biased_heading_flight() {
  FlightSpec spec = long_turning_flight();
  spec.ins_yaw_bias_deg = 0.1;
  BiasedHeadingFlight out{test::make_flight(spec), {}, 0};
  out.fixes = fixes_every(out.flight, 14, 0.3, 11);
  out.fixes_end = out.flight.truth.front().utime + 100'000'000;
  out.fixes.erase(std::remove_if(out.fixes.begin(), out.fixes.end(),
                                 [&](const map_fix_t& f) { return f.utime > out.fixes_end; }),
                  out.fixes.end());
  return out;
}

// What yaw fusion is told of biased_heading_flight: an exact map and INS
// roll/pitch, a heading bias of 0.1 deg (constant) with a small walk.
YawFusionOptions biased_heading_options(bool estimate_bias) {
  YawFusionOptions options;
  options.map_fix_systematic_stddev_m = 0.0;
  options.sensor_uncertainty.roll_pitch_stddev_deg = 0.0;
  options.ins_yaw_bias_stddev_deg = 0.1;
  options.ins_yaw_bias_walk_deg_per_sqrt_s = 0.0005;
  options.map_fix_estimates_heading_bias = estimate_bias;
  return options;
}

TEST(YawFusionMapFix, FixesEstimateTheInsHeadingBiasAndTheDriftStopsWithThem) {
  // 200 s at 30 m/s through turns; the INS heading is 0.1 deg off all flight
  // (yaw_fusion.ins_yaw_bias_stddev_deg says 0.1, constant). Fixes of 0.3 m
  // every second for the first 100 s, then none: what the last 3 km drift
  // across the track is what is left of the bias.
  const BiasedHeadingFlight biased = biased_heading_flight();
  const SyntheticFlight& flight = biased.flight;
  const std::vector<map_fix_t>& fixes = biased.fixes;
  const int64_t fixes_end = biased.fixes_end;

  double bias_estimate_deg = 0.0;
  auto fly = [&](bool estimate) {
    YawFusionEstimator estimator{biased_heading_options(estimate)};
    const auto poses = test::run(estimator, with_fixes(flight, fixes, 150'000));
    bias_estimate_deg = rad_to_deg(estimator.filter().yaw_bias_estimate());
    return poses;
  };
  const auto held = fly(false);
  EXPECT_EQ(bias_estimate_deg, 0.0);
  const auto estimated = fly(true);
  ASSERT_EQ(held.size(), estimated.size());
  // While the fixes come both stay within a metre.
  for (size_t i = 0; i < estimated.size(); ++i) {
    if (estimated[i].utime < flight.truth.front().utime + 10'000'000 || estimated[i].utime > fixes_end) continue;
    ASSERT_LT(horizontal_error(flight, estimated[i]).norm(), 1.0) << i;
  }
  const double held_error = horizontal_error(flight, held.back()).norm();
  const double estimated_error = horizontal_error(flight, estimated.back()).norm();
  // Without the estimate the bias drifts 0.1 deg x ~3 km = 5 m after the
  // fixes end; with it, under a metre.
  EXPECT_GT(held_error, 3.0);
  EXPECT_LT(estimated_error, 1.0) << "held " << held_error;
  // The estimate is the bias; the reported yaw stays the INS heading fused
  // with the VO's turns (what the fixes see includes the camera's mounting).
  EXPECT_NEAR(bias_estimate_deg, 0.1, 0.03);
  EXPECT_EQ(estimated.back().yaw_variance, held.back().yaw_variance);
  // The covariance follows: consistent at the end (within the 99.9 % bound
  // of 2 dof), and over the poses after the fixes stop.
  double nees_sum = 0.0;
  int counted = 0;
  for (const pose_t& p : estimated) {
    if (p.utime <= fixes_end) continue;
    nees_sum += nees(flight, p);
    ++counted;
  }
  EXPECT_LT(nees(flight, estimated.back()), 13.8);
  EXPECT_LT(nees_sum / counted, 4.0);
  EXPECT_GT(nees_sum / counted, 0.1);
  std::printf("after 100 s without fixes: %.2f m with the heading bias estimated (sigma %.2f m, the estimate %.3f "
              "deg), %.2f m without; NEES after the fixes %.2f\n",
              estimated_error,
              std::sqrt(estimated.back().position_covariance[0][0] + estimated.back().position_covariance[1][1]),
              bias_estimate_deg, held_error, nees_sum / counted);
}

TEST(YawFusionMapFix, ARestartKeepsTheHeadingBiasTheFixesEstimated) {
  // The flight above, its fixes over the first 100 s. Yaw fusion is killed
  // 10 s after the last fix and restarted 1 s later from its checkpoint. With
  // the bias in the checkpoint the pose goes on as it would have; from a bare
  // POSE (a checkpoint written before the bias was kept) the bias starts
  // again from its prior and the pose drifts with the INS's 0.1 deg.
  const BiasedHeadingFlight biased = biased_heading_flight();
  const SyntheticFlight& flight = biased.flight;
  const YawFusionOptions options = biased_heading_options(true);
  const std::vector<TimedMessage> messages = with_fixes(flight, biased.fixes, 150'000);
  const int64_t killed = biased.fixes_end + 10'000'000;
  const int64_t restarted = killed + 1'000'000;
  std::vector<TimedMessage> before, after;
  for (const TimedMessage& m : messages) {
    if (m.utime <= killed) before.push_back(m);
    if (m.utime >= restarted) after.push_back(m);
  }
  YawFusionEstimator uninterrupted{options};
  test::run(uninterrupted, messages);
  YawFusionEstimator first_run{options};
  const auto first_poses = test::run(first_run, before);
  ASSERT_FALSE(first_poses.empty());
  const yaw_fusion_checkpoint_t checkpoint = first_run.checkpoint(first_poses.back());
  ASSERT_TRUE(checkpoint.has_heading_bias);
  EXPECT_TRUE(checkpoint.heading_bias_estimated);
  EXPECT_NEAR(rad_to_deg(checkpoint.heading_bias_rad[0] + checkpoint.heading_bias_rad[1]), 0.1, 0.03);

  auto resume = [&](bool with_bias, double* bias_deg) {
    YawFusionEstimator run{options};
    if (with_bias) {
      run.resume_from(checkpoint);
    } else {
      run.resume_from(checkpoint.pose);
    }
    const auto poses = test::run(run, after);
    EXPECT_EQ(run.counters().resumed, 1);
    *bias_deg = rad_to_deg(run.filter().yaw_bias_estimate());
    return poses;
  };
  double kept_bias_deg = 0.0, bare_bias_deg = 0.0;
  const auto kept = resume(true, &kept_bias_deg);
  const auto bare = resume(false, &bare_bias_deg);
  ASSERT_GT(kept.size(), 1000u);
  ASSERT_EQ(kept.size(), bare.size());
  EXPECT_NEAR(kept_bias_deg, rad_to_deg(uninterrupted.filter().yaw_bias_estimate()), 0.002);
  EXPECT_EQ(bare_bias_deg, 0.0);
  // Drift over the ~2.6 km after the restart.
  const double kept_drift = (horizontal_error(flight, kept.back()) - horizontal_error(flight, kept.front())).norm();
  const double bare_drift = (horizontal_error(flight, bare.back()) - horizontal_error(flight, bare.front())).norm();
  std::printf("after a restart 10 s past the last fix: %.2f m of drift with the heading bias kept, %.2f m from a "
              "bare POSE; NEES at the end %.2f\n",
              kept_drift, bare_drift, nees(flight, kept.back()));
  EXPECT_LT(kept_drift, 1.0);
  EXPECT_GT(bare_drift, 3.0);
  EXPECT_LT(nees(flight, kept.back()), 13.8);

  // A checkpoint whose bias is damaged still gives the position; the bias
  // starts from its prior, and STATUS says why.
  yaw_fusion_checkpoint_t damaged = checkpoint;
  damaged.heading_bias_covariance[1][1] = -1.0;
  YawFusionEstimator damaged_run{options};
  damaged_run.resume_from(damaged);
  const auto damaged_poses = test::run(damaged_run, after);
  ASSERT_EQ(damaged_poses.size(), kept.size());
  EXPECT_EQ(damaged_run.counters().resumed, 1);
  EXPECT_EQ(damaged_poses.front().position_ned[0], bare.front().position_ned[0]);
  EXPECT_EQ(damaged_run.filter().yaw_bias_estimate(), 0.0);
  EXPECT_NE(damaged_run.counters().last_problem.find("heading bias"), std::string::npos)
      << damaged_run.counters().last_problem;
}

TEST(YawFusionMapFix, AMapsOffsetSeenThroughTurnsIsNotTakenForAHeadingBias) {
  // The same flight with an exact INS heading and a map 1 m off (0.8 m
  // north, 0.6 m south; yaw_fusion.map_fix.systematic_stddev_m says 1 m).
  // Through the turns that offset turns against the track, as a heading
  // bias's drift would: carried as the map's, the heading bias estimate
  // stays near 0 and the pose does not drift once the fixes stop.
  const SyntheticFlight flight = test::make_flight(long_turning_flight());
  std::mt19937 rng(13);
  std::vector<map_fix_t> fixes;
  const int64_t fixes_end = flight.truth.front().utime + 100'000'000;
  for (size_t k = 14; k < flight.truth.size() && flight.truth[k].utime <= fixes_end; k += 14) {
    fixes.push_back(fix_at(flight, k, 0.3, &rng, Eigen::Vector2d(0.8, -0.6)));
  }
  YawFusionOptions options;
  options.map_fix_systematic_stddev_m = 1.0;
  options.sensor_uncertainty.roll_pitch_stddev_deg = 0.0;
  options.ins_yaw_bias_stddev_deg = 0.1;
  options.ins_yaw_bias_walk_deg_per_sqrt_s = 0.0005;
  YawFusionEstimator estimator{options};
  const auto poses = test::run(estimator, with_fixes(flight, fixes, 150'000));
  const double bias_deg = rad_to_deg(estimator.filter().yaw_bias_estimate());
  const Eigen::Vector2d at_end_of_fixes = [&] {
    for (const pose_t& p : poses) {
      if (p.utime > fixes_end) return horizontal_error(flight, p);
    }
    return Eigen::Vector2d(0, 0);
  }();
  const Eigen::Vector2d final_error = horizontal_error(flight, poses.back());
  std::printf("map 1 m off: heading bias estimate %.4f deg; error %.2f m when the fixes stop, %.2f m 3 km later\n",
              bias_deg, at_end_of_fixes.norm(), final_error.norm());
  EXPECT_LT(std::abs(bias_deg), 0.02);
  // What the pose took from the map's offset stays; it does not grow (a
  // 0.02 deg bias would add 1 m over the 3 km).
  EXPECT_LT((final_error - at_end_of_fixes).norm(), 0.6);
}

}  // namespace
}  // namespace nadir
