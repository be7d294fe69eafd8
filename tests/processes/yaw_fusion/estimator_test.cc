// YawFusionEstimator on synthetic flights with known truth.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <sstream>

#include "common/channels.h"
#include "common/geometry.h"
#include "processes/yaw_fusion/yaw_fusion_estimator.h"
#include "estimator_runner.h"
#include "synthetic_flight.h"

namespace nadir {
namespace {

using test::FlightSpec;
using test::SyntheticFlight;
using test::TimedMessage;

using test::run;
using test::run_flight;

// Names the first field two poses differ in ("" when their bytes are equal).
std::string first_difference(const pose_t& a, const pose_t& b) {
  if (test::encode(a) == test::encode(b)) return "";
  std::ostringstream text;
  text.precision(17);
  if (a.utime != b.utime) text << "utime " << a.utime << " vs " << b.utime;
  for (int i = 0; i < 3; ++i) {
    if (a.position_ned[i] != b.position_ned[i]) text << " position[" << i << "] " << a.position_ned[i] << " vs " << b.position_ned[i];
    if (a.velocity_ned[i] != b.velocity_ned[i]) text << " velocity[" << i << "]";
  }
  if (a.yaw != b.yaw) text << " yaw " << a.yaw << " vs " << b.yaw;
  if (a.roll != b.roll || a.pitch != b.pitch) text << " roll/pitch";
  if (a.height_agl_m != b.height_agl_m) text << " height " << a.height_agl_m << " vs " << b.height_agl_m;
  if (a.yaw_variance != b.yaw_variance) text << " yaw_variance";
  if (a.flags != b.flags) text << " flags " << a.flags << " vs " << b.flags;
  if (a.frames != b.frames) text << " frames";
  const std::string out = text.str();
  return out.empty() ? "covariance" : out;
}

std::map<int64_t, const test::TruthFrame*> truth_by_time(const SyntheticFlight& flight) {
  std::map<int64_t, const test::TruthFrame*> out;
  for (const auto& f : flight.truth) out[f.utime] = &f;
  return out;
}

TEST(YawFusionEstimator, RecoversPositionExactlyFromNoiseFreeInputs) {
  FlightSpec spec;
  spec.frames = 600;  // 43 s: two turns, heading crosses +-180 deg
  const SyntheticFlight flight = test::make_flight(spec);
  YawFusionCounters counters;
  YawFusionOptions options;
  options.altimeter_interpolate = true;  // exact height needs the range after each frame too
  const auto poses = run_flight(flight, options, &counters);
  ASSERT_EQ(poses.size(), flight.truth.size());
  const auto truth = truth_by_time(flight);
  const Eigen::Vector3d origin = flight.truth.front().position;
  for (size_t i = 0; i < poses.size(); ++i) {
    const pose_t& p = poses[i];
    ASSERT_EQ(truth.count(p.utime), 1u);
    const test::TruthFrame& t = *truth.at(p.utime);
    const Eigen::Vector3d expected = t.position - origin;
    EXPECT_NEAR(p.position_ned[0], expected.x(), 1e-6) << "frame " << i;
    EXPECT_NEAR(p.position_ned[1], expected.y(), 1e-6) << "frame " << i;
    EXPECT_NEAR(p.position_ned[2], expected.z(), 1e-6) << "frame " << i;
    EXPECT_NEAR(angle_difference(p.yaw, t.yaw), 0.0, 1e-9) << "frame " << i;
    EXPECT_NEAR(p.roll, t.roll, 1e-12);
    EXPECT_NEAR(p.pitch, t.pitch, 1e-12);
    // The slant range is interpolated between 20 Hz samples taken at other
    // attitudes and levelled with the frame's: exact to a few 1e-5 m.
    EXPECT_NEAR(p.height_agl_m, spec.height_agl_m - t.position.z(), 1e-4);
    EXPECT_EQ(p.frames, static_cast<int64_t>(i));
    EXPECT_EQ(p.flags, i == 0 ? pose_t::FLAG_INITIALIZING : 0) << "frame " << i;
  }
  // Velocity of the last frame: the displacement over the velocity window
  // (the newest frame at least velocity_window_s older than the last one).
  const auto& b = flight.truth.back();
  const int64_t window_us = static_cast<int64_t>(YawFusionOptions{}.velocity_window_s * 1e6);
  size_t k = flight.truth.size() - 2;
  while (k > 0 && b.utime - flight.truth[k].utime < window_us) --k;
  const auto& a = flight.truth[k];
  const Eigen::Vector3d v = (b.position - a.position) / (static_cast<double>(b.utime - a.utime) * 1e-6);
  EXPECT_NEAR(poses.back().velocity_ned[0], v.x(), 1e-6);
  EXPECT_NEAR(poses.back().velocity_ned[1], v.y(), 1e-6);
  EXPECT_NEAR(poses.back().velocity_ned[2], -spec.climb_rate_mps, 1e-6);
  // The flight did cross the wrap and went somewhere.
  EXPECT_GT(std::hypot(poses.back().position_ned[0], poses.back().position_ned[1]), 800.0);
  EXPECT_EQ(counters.vo_deltas_integrated, spec.frames - 1);
  EXPECT_EQ(counters.ins_yaw_rejected, 0);
  EXPECT_EQ(counters.vo_deltas_without_ins, 0);
  EXPECT_EQ(counters.poses, static_cast<int64_t>(poses.size()));
}

TEST(YawFusionEstimator, GatesInsYawOutliers) {
  FlightSpec spec;
  spec.frames = 400;
  spec.ins_yaw_stddev_deg = 0.3;
  spec.dyaw_stddev_deg = 0.05;
  SyntheticFlight flight = test::make_flight(spec);
  // Spikes of 15 deg on the INS around some frames (every INS sample within 30 ms).
  std::vector<int64_t> spiked_frames;
  for (size_t k = 20; k < flight.truth.size(); k += 37) spiked_frames.push_back(flight.truth[k].utime);
  for (auto& ins : flight.ins) {
    for (int64_t t : spiked_frames) {
      if (std::abs(ins.utime - t) <= 30'000) ins.yaw = wrap_angle(ins.yaw + deg_to_rad(15.0));
    }
  }
  YawFusionCounters counters;
  const auto poses = run_flight(flight, YawFusionOptions{}, &counters);
  ASSERT_EQ(poses.size(), flight.truth.size());
  const auto truth = truth_by_time(flight);
  int flagged = 0;
  double worst_yaw_error = 0.0;
  for (const pose_t& p : poses) {
    const bool spiked = std::find(spiked_frames.begin(), spiked_frames.end(), p.utime) != spiked_frames.end();
    if (spiked) {
      EXPECT_TRUE(p.flags & pose_t::FLAG_INS_YAW_REJECTED) << p.utime;
    }
    if (p.flags & pose_t::FLAG_INS_YAW_REJECTED) ++flagged;
    worst_yaw_error = std::max(worst_yaw_error, std::abs(angle_difference(p.yaw, truth.at(p.utime)->yaw)));
  }
  EXPECT_EQ(flagged, static_cast<int>(spiked_frames.size()));  // and no good sample rejected
  EXPECT_EQ(counters.ins_yaw_rejected, static_cast<int64_t>(spiked_frames.size()));
  EXPECT_LT(rad_to_deg(worst_yaw_error), 0.6);

  // Without the gate the same spikes pull the yaw several degrees.
  YawFusionOptions no_gate;
  no_gate.ins_yaw_gate_sigma = 100.0;
  const auto ungated = run_flight(flight, no_gate);
  double worst_ungated = 0.0;
  for (const pose_t& p : ungated) {
    worst_ungated = std::max(worst_ungated, std::abs(angle_difference(p.yaw, truth.at(p.utime)->yaw)));
  }
  EXPECT_GT(rad_to_deg(worst_ungated), 2.0);
}

TEST(YawFusionEstimator, FusedYawIsLessNoisyThanInsYaw) {
  FlightSpec spec;
  spec.frames = 800;
  spec.ins_yaw_stddev_deg = 0.5;
  spec.reported_ins_yaw_stddev_deg = 0.5;
  spec.dyaw_stddev_deg = 0.02;
  spec.covariance_dyaw_stddev_deg = 0.02;
  const SyntheticFlight flight = test::make_flight(spec);
  const auto poses = run_flight(flight, YawFusionOptions{});
  const auto truth = truth_by_time(flight);
  double sum_sq = 0.0;
  int n = 0;
  for (size_t i = 100; i < poses.size(); ++i) {
    const double e = angle_difference(poses[i].yaw, truth.at(poses[i].utime)->yaw);
    sum_sq += e * e;
    ++n;
  }
  const double rms_deg = rad_to_deg(std::sqrt(sum_sq / n));
  std::printf("fused yaw error %.3f deg rms (INS 0.5 deg), reported %.3f deg\n", rms_deg,
              rad_to_deg(std::sqrt(poses.back().yaw_variance)));
  EXPECT_LT(rms_deg, 0.25);  // INS alone: 0.5 deg
  // The reported variance is consistent with the error (within a factor 2 in sigma).
  const double reported_deg = rad_to_deg(std::sqrt(poses.back().yaw_variance));
  EXPECT_GT(reported_deg, rms_deg / 2.0);
  EXPECT_LT(reported_deg, rms_deg * 2.0);
}

TEST(YawFusionEstimator, InsYawBiasWalkAddsToTheReportedYawVariance) {
  FlightSpec spec;
  spec.frames = 500;
  const SyntheticFlight flight = test::make_flight(spec);
  YawFusionOptions white_only, walking;
  white_only.ins_yaw_bias_walk_deg_per_sqrt_s = 0.0;
  walking.ins_yaw_bias_walk_deg_per_sqrt_s = 0.01;
  walking.ins_yaw_bias_stddev_deg = 0.02;
  const auto a = run_flight(flight, white_only);
  const auto b = run_flight(flight, walking);
  ASSERT_EQ(a.size(), b.size());
  // The same yaw (the walk is not a state: it cannot be observed), its variance
  // larger by the initial bias variance plus the walk over the flight's time.
  const double t = static_cast<double>(b.back().utime - b.front().utime) * 1e-6;
  const double added = std::pow(deg_to_rad(0.02), 2) + std::pow(deg_to_rad(0.01), 2) * t;
  EXPECT_EQ(a.back().yaw, b.back().yaw);
  EXPECT_NEAR(b.back().yaw_variance - a.back().yaw_variance, added, 0.02 * added);
}

TEST(YawFusionEstimator, YawVarianceBoundedWithInsAndGrowingWithout) {
  FlightSpec spec;
  spec.frames = 500;
  SyntheticFlight flight = test::make_flight(spec);
  {
    // The synthetic INS yaw has white noise only: no bias walk to report.
    YawFusionOptions white_only;
    white_only.ins_yaw_bias_walk_deg_per_sqrt_s = 0.0;
    const auto poses = run_flight(flight, white_only);
    const double ins_var = std::pow(deg_to_rad(spec.reported_ins_yaw_stddev_deg), 2);
    for (const pose_t& p : poses) EXPECT_LE(p.yaw_variance, ins_var * (1.0 + 1e-9));
    EXPECT_NEAR(poses[300].yaw_variance, poses.back().yaw_variance, 1e-3 * ins_var);  // steady state
  }
  // After frame 100 the INS reports a yaw stddev above max_ins_yaw_stddev_deg: no yaw updates.
  const int64_t cutoff = flight.truth[100].utime;
  for (auto& ins : flight.ins) {
    if (ins.utime > cutoff - 20'000) ins.attitude_stddev[2] = deg_to_rad(45.0);
  }
  YawFusionCounters counters;
  const auto poses = run_flight(flight, YawFusionOptions{}, &counters);
  ASSERT_EQ(poses.size(), flight.truth.size());
  // A pose carries its own frame's levelling error once, not accumulated, and
  // that varies with the share of the INS's white noise in the frame's
  // attitude (interpolated between samples: 1/2 to 1 of one sample's): from
  // pose to pose the sum may fall by up to half of it; over a second it grows.
  const double frame_term = 2 * levelling_variance_m2(400.0, deg_to_rad(0.05));  // both axes, above the flight
  auto horizontal = [&](size_t i) { return poses[i].position_covariance[0][0] + poses[i].position_covariance[1][1]; };
  for (size_t i = 101; i < poses.size(); ++i) {
    EXPECT_GT(poses[i].yaw_variance, poses[i - 1].yaw_variance) << i;
    EXPECT_GE(horizontal(i) + 0.5 * frame_term, horizontal(i - 1)) << i;
    if (i >= 115) {
      EXPECT_GT(horizontal(i), horizontal(i - 14)) << i;
    }
  }
  EXPECT_GE(counters.ins_yaw_unusable, static_cast<int64_t>(poses.size()) - 102);
  // Pure VO yaw integration stays exact on noise-free deltas.
  EXPECT_NEAR(angle_difference(poses.back().yaw, flight.truth.back().yaw), 0.0, 1e-9);
}

TEST(YawFusionEstimator, VoGapsAreFlaggedDeadReckonedAndSurvived) {
  FlightSpec spec;
  spec.frames = 300;
  spec.turn_rate_dps = 0.0;  // straight: dead reckoning with the last velocity is exact
  spec.climb_rate_mps = 0.0;
  SyntheticFlight flight = test::make_flight(spec);
  // Deltas 100..119 are lost (frames 101..120 missing), delta 150 is flagged.
  std::vector<vo_delta_t> kept;
  for (size_t k = 0; k < flight.deltas.size(); ++k) {
    if (k >= 100 && k < 120) continue;
    kept.push_back(flight.deltas[k]);
  }
  for (auto& d : kept) {
    if (d.utime == flight.truth[151].utime) d.quality = vo_delta_t::QUALITY_NOT_CONVERGED;  // coasting aside
  }
  flight.deltas = kept;
  YawFusionCounters counters;
  const auto poses = run_flight(flight, YawFusionOptions{}, &counters);
  const Eigen::Vector3d origin = flight.truth.front().position;

  int gap_poses = 0;
  double cov_before_gap = 0.0;
  double cov_in_gap = 0.0;
  for (const pose_t& p : poses) {
    if (p.utime < flight.truth[101].utime) cov_before_gap = p.position_covariance[0][0];
    if (p.flags & pose_t::FLAG_VO_GAP) {
      ++gap_poses;
      cov_in_gap = std::max(cov_in_gap, p.position_covariance[0][0]);
    }
  }
  // Gap poses at the camera rate for the missing frames 101..119, one at
  // frame 120 (where delta 120 starts), and the flagged frame 151.
  EXPECT_EQ(counters.gap_poses, 20);
  EXPECT_EQ(counters.gap_bridges, 1);
  EXPECT_EQ(gap_poses, 20 + 1);
  EXPECT_EQ(poses.size(), flight.truth.size());
  EXPECT_EQ(counters.vo_deltas_quality_rejected, 1);
  EXPECT_GT(cov_in_gap, cov_before_gap + 1.0);
  // Through the gap the straight flight is dead-reckoned to within a frame's trigger jitter.
  const pose_t& last = poses.back();
  const Eigen::Vector3d expected = flight.truth.back().position - origin;
  EXPECT_NEAR(last.position_ned[0], expected.x(), 0.2);
  EXPECT_NEAR(last.position_ned[1], expected.y(), 0.2);
  EXPECT_EQ(last.frames, static_cast<int64_t>(kept.size()) - 1);
  EXPECT_EQ(last.flags, 0);
  // Poses keep increasing in time.
  for (size_t i = 1; i < poses.size(); ++i) EXPECT_GT(poses[i].utime, poses[i - 1].utime);
}

// A turn flown while VO is missing (a photo survey's line reversal, unsolved
// pairs): nothing but the INS measures the yaw then, so its yaw is taken, not
// gated against the last yaw held constant -- which would reject it for
// max_consecutive_yaw_rejections frames and register them 40 deg off.
TEST(YawFusionEstimator, TurnDuringAVoGapTakesTheInsYaw) {
  FlightSpec spec;
  spec.frames = 200;
  spec.turn_rate_dps = 30.0;
  SyntheticFlight flight = test::make_flight(spec);
  std::vector<vo_delta_t> kept;
  for (size_t k = 0; k < flight.deltas.size(); ++k) {
    if (k >= 100 && k < 120) continue;  // ~1.4 s of the turn without VO
    kept.push_back(flight.deltas[k]);
  }
  flight.deltas = kept;
  YawFusionCounters counters;
  const auto poses = run_flight(flight, YawFusionOptions{}, &counters);
  const auto truth = truth_by_time(flight);
  EXPECT_GT(counters.yaw_from_ins_in_gap, 0);
  EXPECT_EQ(counters.ins_yaw_rejected, 0);
  double worst_after_gap_deg = 0.0;
  for (const pose_t& p : poses) {
    EXPECT_EQ(p.flags & pose_t::FLAG_INS_YAW_REJECTED, 0) << p.utime;
    const auto t = truth.find(p.utime);
    if (t == truth.end() || p.utime <= flight.truth[120].utime) continue;
    worst_after_gap_deg = std::max(worst_after_gap_deg, std::fabs(rad_to_deg(angle_difference(p.yaw, t->second->yaw))));
  }
  EXPECT_LT(worst_after_gap_deg, 0.05);
}

// Flagged deltas at the start (e.g. no altimeter yet) publish no poses: the
// origin is the first frame VO measures from, so no motion is lost there.
TEST(YawFusionEstimator, StartsAtTheFirstUsableDelta) {
  FlightSpec spec;
  spec.frames = 120;
  SyntheticFlight flight = test::make_flight(spec);
  for (size_t k = 0; k < 8; ++k) flight.deltas[k].quality = vo_delta_t::QUALITY_NO_ALTIMETER;
  YawFusionCounters counters;
  const auto poses = run_flight(flight, YawFusionOptions{}, &counters);
  EXPECT_EQ(counters.vo_deltas_before_start, 8);
  ASSERT_FALSE(poses.empty());
  EXPECT_EQ(poses.front().utime, flight.deltas[8].prev_utime);
  EXPECT_TRUE(poses.front().flags & pose_t::FLAG_INITIALIZING);
  EXPECT_EQ(poses.size(), flight.truth.size() - 8);
  // Exact, as from a flight that had started there.
  const Eigen::Vector3d origin = truth_by_time(flight).at(poses.front().utime)->position;
  const pose_t& last = poses.back();
  const Eigen::Vector3d expected = flight.truth.back().position - origin;
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(last.position_ned[i], expected[i], 1e-6) << i;
  for (const pose_t& p : poses) EXPECT_FALSE(p.flags & pose_t::FLAG_VO_GAP);
}

TEST(YawFusionEstimator, LongGapHoldsPositionAfterMaxPropagation) {
  FlightSpec spec;
  spec.frames = 200;
  spec.turn_rate_dps = 0.0;
  SyntheticFlight flight = test::make_flight(spec);
  flight.deltas.resize(50);  // VO stops at frame 50; INS goes on for ~10 s
  YawFusionOptions options;
  options.gap_max_propagation_s = 2.0;
  options.gap_max_duration_s = 5.0;
  YawFusionEstimator estimator(options);
  const auto poses = run(estimator, test::arrival_order(flight, 80'000, 2'000, 5'000));
  ASSERT_GT(poses.size(), 51u);
  const pose_t& last_good = poses[50];
  const pose_t& last = poses.back();
  EXPECT_EQ(last_good.flags, 0);
  EXPECT_NEAR(static_cast<double>(last.utime - last_good.utime) * 1e-6, 5.0, 0.08);
  const double moved = std::hypot(last.position_ned[0] - last_good.position_ned[0],
                                  last.position_ned[1] - last_good.position_ned[1]);
  EXPECT_NEAR(moved, spec.speed_mps * 2.0, 0.5);  // 2 s of dead reckoning, then held
  EXPECT_EQ(last.velocity_ned[0], 0.0);
  EXPECT_TRUE(estimator.vo_lost());
}

TEST(YawFusionEstimator, ArrivalOrderDoesNotChangePoses) {
  FlightSpec spec;
  spec.frames = 300;
  spec.ins_yaw_stddev_deg = 0.3;
  spec.dyaw_stddev_deg = 0.05;
  spec.translation_stddev_m = 0.05;
  SyntheticFlight flight = test::make_flight(spec);
  flight.deltas.erase(flight.deltas.begin() + 100, flight.deltas.begin() + 110);  // and a gap
  // interpolate mode waits for the altimeter sample after each frame, so even
  // a random 250 ms interleaving of the channels gives the same poses.
  YawFusionOptions interpolate;
  interpolate.altimeter_interpolate = true;
  YawFusionEstimator a{interpolate};
  YawFusionEstimator b{interpolate};
  YawFusionEstimator c{interpolate};
  const auto pa = run(a, test::arrival_order(flight, 80'000, 2'000, 5'000));
  const auto pb = run(b, test::arrival_order(flight, 0, 300'000, 150'000));   // INS 300 ms late
  const auto pc = run(c, test::arrival_order(flight, 0, 0, 0, 99, 250'000));   // random interleaving
  ASSERT_EQ(pa.size(), pb.size());
  ASSERT_EQ(pa.size(), pc.size());
  for (size_t i = 0; i < pa.size(); ++i) {
    EXPECT_EQ(first_difference(pa[i], pb[i]), "") << "pose " << i;
    EXPECT_EQ(first_difference(pa[i], pc[i]), "") << "pose " << i;
  }
  // latest mode (the default, no altimeter wait) needs the altimeter to be
  // no later than the INS on arrival; with that, order still does not matter.
  YawFusionEstimator d{YawFusionOptions{}};
  YawFusionEstimator e{YawFusionOptions{}};
  const auto pd = run(d, test::arrival_order(flight, 80'000, 2'000, 1'000));
  const auto pe = run(e, test::arrival_order(flight, 0, 300'000, 150'000));
  ASSERT_EQ(pd.size(), pe.size());
  for (size_t i = 0; i < pd.size(); ++i) EXPECT_EQ(first_difference(pd[i], pe[i]), "") << "pose " << i;
}

TEST(YawFusionEstimator, MalformedValuesAreCountedAndSurvived) {
  FlightSpec spec;
  spec.frames = 120;
  SyntheticFlight flight = test::make_flight(spec);
  flight.deltas[30].dx = std::nan("");
  flight.deltas[40].covariance[0][0] = -1.0;
  flight.deltas[50].prev_utime = flight.deltas[50].utime;  // zero interval
  flight.ins[500].yaw = std::numeric_limits<double>::infinity();
  flight.ins[600].pitch = 4.0;
  flight.altimeter[20].validity = altimeter_t::VALID_NO_RETURN;
  flight.altimeter[21].range_m = std::nan("");
  YawFusionCounters counters;
  const auto poses = run_flight(flight, YawFusionOptions{}, &counters);
  EXPECT_EQ(counters.vo_deltas_invalid, 3);
  EXPECT_EQ(counters.ins_invalid, 2);
  EXPECT_EQ(counters.altimeter_invalid, 2);
  EXPECT_FALSE(counters.last_problem.empty());
  // Frames 31 and 41 become flagged gap frames; frame 51 (zero-interval delta
  // dropped) gets a flagged pose when delta 51, which starts there, arrives.
  EXPECT_EQ(poses.size(), flight.truth.size());
  int gaps = 0;
  for (const pose_t& p : poses) gaps += (p.flags & pose_t::FLAG_VO_GAP) ? 1 : 0;
  EXPECT_EQ(gaps, 3);
  for (const pose_t& p : poses) {
    for (double v : p.position_ned) EXPECT_TRUE(std::isfinite(v));
    EXPECT_TRUE(std::isfinite(p.yaw));
  }
  EXPECT_NEAR(poses.back().position_ned[0], flight.truth.back().position.x() - flight.truth.front().position.x(), 1.0);
}

TEST(YawFusionEstimator, ASingleTimestampJumpIsDroppedARealJumpAccepted) {
  FlightSpec spec;
  spec.frames = 150;
  SyntheticFlight flight = test::make_flight(spec);
  const auto clean = run_flight(flight, YawFusionOptions{});
  // One INS sample and one altimeter sample, in their places in the stream,
  // stamped an hour ahead (an extra copy each, so the clean run is the reference).
  auto messages = test::arrival_order(flight, 80'000, 2'000, 5'000);
  std::vector<TimedMessage> corrupted;
  for (const TimedMessage& m : messages) {
    corrupted.push_back(m);
    if (m.channel == channels::kIns && m.utime == flight.ins[700].utime) {
      ins_t bad = flight.ins[700];
      bad.utime += 3'600'000'000LL;
      corrupted.push_back({m.channel, bad.utime, test::encode(bad)});
    }
    if (m.channel == channels::kAltimeter && m.utime == flight.altimeter[100].utime) {
      altimeter_t bad = flight.altimeter[100];
      bad.utime += 3'600'000'000LL;
      corrupted.push_back({m.channel, bad.utime, test::encode(bad)});
    }
  }
  YawFusionEstimator estimator{YawFusionOptions{}};
  const auto poses = run(estimator, corrupted);
  EXPECT_EQ(estimator.counters().time_jumps_dropped, 2);
  ASSERT_EQ(poses.size(), clean.size());
  for (size_t i = 0; i < poses.size(); ++i) EXPECT_EQ(first_difference(poses[i], clean[i]), "") << i;

  // A real jump of the whole time base (every channel) costs one message per channel.
  SyntheticFlight jumped = flight;
  const int64_t jump = 3'600'000'000LL;
  const int64_t from = flight.truth[100].utime;
  for (auto& d : jumped.deltas) {
    if (d.prev_utime >= from) {
      d.utime += jump;
      d.prev_utime += jump;
    }
  }
  for (auto& m : jumped.ins) m.utime += m.utime > from ? jump : 0;
  for (auto& m : jumped.altimeter) m.utime += m.utime > from ? jump : 0;
  YawFusionCounters jump_counters;
  const auto after_jump = run_flight(jumped, YawFusionOptions{}, &jump_counters);
  EXPECT_GE(jump_counters.time_jumps_dropped, 2);
  EXPECT_LE(jump_counters.time_jumps_dropped, 3);
  EXPECT_GT(after_jump.back().utime, from + jump);
  EXPECT_GT(jump_counters.vo_deltas_integrated, 140);
}

TEST(YawFusionEstimator, LevelTerrainModeBoundsVerticalDriftOverLevelGround) {
  FlightSpec spec;
  spec.frames = 700;
  spec.dz_bias_m = 0.02;  // a biased dz: 14 m of drift over the flight
  spec.dz_stddev_m = 0.05;
  const SyntheticFlight flight = test::make_flight(spec);
  const Eigen::Vector3d origin = flight.truth.front().position;
  const double truth_down = flight.truth.back().position.z() - origin.z();

  const auto vo_only = run_flight(flight, YawFusionOptions{});
  YawFusionOptions level;
  level.altitude_mode = AltitudeMode::kLevelTerrain;
  YawFusionCounters counters;
  const auto corrected = run_flight(flight, level, &counters);
  std::printf("down error after %d frames: vo_dz %.2f m, level_terrain %.2f m\n", spec.frames,
              vo_only.back().position_ned[2] - truth_down, corrected.back().position_ned[2] - truth_down);
  EXPECT_GT(std::abs(vo_only.back().position_ned[2] - truth_down), 10.0);
  // The filter trusts the (reported 5 cm) dz more than the 1.7 m altimeter,
  // so a bias leaves a lag of a few bias/gain steps, but no drift.
  EXPECT_LT(std::abs(corrected.back().position_ned[2] - truth_down), 3.0);
  EXPECT_LT(corrected.back().position_covariance[2][2], vo_only.back().position_covariance[2][2]);
  EXPECT_EQ(counters.altimeter_rejected, 0);

  // A 30 m terrain step is detected and not taken as a 30 m altitude change.
  FlightSpec step = spec;
  step.dz_bias_m = 0.0;
  step.terrain_step_m = 30.0;
  step.terrain_step_frame = 300;
  const SyntheticFlight stepped = test::make_flight(step);
  YawFusionCounters step_counters;
  const auto step_poses = run_flight(stepped, level, &step_counters);
  EXPECT_GE(step_counters.altimeter_rejected, 1);
  const double step_truth_down = stepped.truth.back().position.z() - stepped.truth.front().position.z();
  EXPECT_LT(std::abs(step_poses.back().position_ned[2] - step_truth_down), 1.0);
}

// A yaw fusion killed mid-flight and restarted 1.5 s later continues from its
// last POSE (the checkpoint): the position goes on where it was, within the
// covariance it reports, instead of starting again at zero.
TEST(YawFusionEstimator, ResumesFromACheckpointAfterARestart) {
  FlightSpec spec;
  spec.frames = 600;
  const SyntheticFlight flight = test::make_flight(spec);
  const auto messages = test::arrival_order(flight, 80'000, 2'000, 5'000);
  YawFusionOptions options;
  YawFusionEstimator uninterrupted(options);
  const auto reference = run(uninterrupted, messages);
  std::map<int64_t, pose_t> reference_at;
  for (const pose_t& p : reference) reference_at[p.utime] = p;

  const int64_t killed = flight.truth[300].utime;
  const int64_t restarted = killed + 1500000;
  std::vector<TimedMessage> before, after;
  for (const TimedMessage& m : messages) {
    if (m.utime <= killed) before.push_back(m);
    if (m.utime >= restarted) after.push_back(m);
  }
  YawFusionEstimator first_run(options);
  const auto first_poses = run(first_run, before);
  ASSERT_FALSE(first_poses.empty());
  const pose_t checkpoint = first_poses.back();

  YawFusionEstimator second_run(options);
  second_run.resume_from(checkpoint);
  const auto resumed = run(second_run, after);
  ASSERT_GT(resumed.size(), 200u);
  EXPECT_EQ(second_run.counters().resumed, 1);
  const pose_t& p0 = resumed.front();
  EXPECT_TRUE(p0.flags & pose_t::FLAG_VO_GAP);
  EXPECT_FALSE(p0.flags & pose_t::FLAG_INITIALIZING);
  EXPECT_GT(p0.frames, checkpoint.frames - 1);
  // Never reset: the covariance only grew over the restart.
  EXPECT_GT(p0.position_covariance[0][0], checkpoint.position_covariance[0][0]);
  for (const pose_t& p : resumed) {
    ASSERT_EQ(reference_at.count(p.utime), 1u);
    const pose_t& r = reference_at.at(p.utime);
    for (int axis = 0; axis < 2; ++axis) {
      const double sigma = std::sqrt(p.position_covariance[axis][axis]);
      EXPECT_LT(std::abs(p.position_ned[axis] - r.position_ned[axis]), 3.0 * sigma) << "axis " << axis;
    }
  }
  // 1.5 s at 30 m/s in a 6 deg/s turn bridged by straight dead reckoning:
  // about 0.5 * v * omega * t^2 = 3.5 m off (6.2 m measured), far below the
  // 45 m of flight a fresh origin would lose, and within 3 sigma throughout.
  const pose_t& last = resumed.back();
  const pose_t& r = reference_at.at(last.utime);
  EXPECT_LT(std::hypot(last.position_ned[0] - r.position_ned[0], last.position_ned[1] - r.position_ned[1]), 10.0);

  // A checkpoint from another flight (its time after this one's) is ignored.
  YawFusionEstimator stale(options);
  pose_t future = checkpoint;
  future.utime = restarted + 3600000000LL;
  stale.resume_from(future);
  const auto fresh = run(stale, after);
  ASSERT_FALSE(fresh.empty());
  EXPECT_EQ(stale.counters().resumed, 0);
  EXPECT_TRUE(fresh.front().flags & pose_t::FLAG_INITIALIZING);
  EXPECT_EQ(fresh.front().position_ned[0], 0.0);
  EXPECT_NE(stale.counters().last_problem.find("not resumed"), std::string::npos);
}

TEST(YawFusionOptions, BadConfigNamesTheKey) {
  const Config root = Config::parse("yaw_fusion:\n  ins_yaw_gate_sigma: 0.5\n", "test.yaml");
  try {
    YawFusionOptions::from_config(root);
    FAIL() << "expected ConfigError";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("yaw_fusion.ins_yaw_gate_sigma"), std::string::npos) << e.what();
  }
  const Config mode = Config::parse("yaw_fusion:\n  altitude_mode: baro\n", "test.yaml");
  EXPECT_THROW(YawFusionOptions::from_config(mode), ConfigError);
  const Config gap = Config::parse("yaw_fusion:\n  gap: {max_duration_s: -1}\n", "test.yaml");
  EXPECT_THROW(YawFusionOptions::from_config(gap), ConfigError);
  const Config ok = Config::parse("camera: {rate_hz: 20}\nyaw_fusion: {altitude_mode: level_terrain}\n", "test.yaml");
  const YawFusionOptions o = YawFusionOptions::from_config(ok);
  EXPECT_EQ(o.altitude_mode, AltitudeMode::kLevelTerrain);
  EXPECT_EQ(o.frame_period_us(), 50'000);
}

TEST(YawFusionOptions, CheckedInDefaultConfigLoads) {
  const Config root = Config::load_file(std::string(NADIR_SOURCE_DIR) + "/config/default.yaml");
  const YawFusionOptions o = YawFusionOptions::from_config(root);
  EXPECT_EQ(o.altitude_mode, AltitudeMode::kVoDz);
  EXPECT_EQ(o.reject_quality_mask, vo_delta_t::QUALITY_TOO_FEW_FEATURES | vo_delta_t::QUALITY_NO_ALTIMETER |
                                       vo_delta_t::QUALITY_NOT_CONVERGED | vo_delta_t::QUALITY_NO_ATTITUDE |
                                       vo_delta_t::QUALITY_HEADING_CONTRADICTS);
  EXPECT_EQ(o.reject_quality_mask, YawFusionOptions{}.reject_quality_mask);
}

// The camera stamps each frame 3 ms before its exposure and the
// altimeter measures 1.01 * true + 0.3 m. With camera.time_offset_us and
// altimeter.range_scale / range_bias_m in the config the noise-free flight is
// recovered exactly (poses keep the frames' stamps); without them it is not.
TEST(YawFusionEstimator, CalibrationRemovesTimeOffsetAndAltimeterScaleAndBias) {
  FlightSpec spec;
  spec.frames = 300;  // a turn: roll and yaw change, so a 3 ms shift shows
  SyntheticFlight flight = test::make_flight(spec);
  const int64_t offset_us = 3000;
  const double scale = 1.01, bias_m = 0.3;
  for (auto& d : flight.deltas) {
    d.utime -= offset_us;
    d.prev_utime -= offset_us;
  }
  for (auto& a : flight.altimeter) a.range_m = scale * a.range_m + bias_m;
  YawFusionOptions options = YawFusionOptions::from_config(Config::parse(
      "camera: {time_offset_us: 3000}\naltimeter: {range_scale: 1.01, range_bias_m: 0.3}\n", "cal.yaml"));
  options.altimeter_interpolate = true;
  YawFusionOptions uncalibrated = options;
  uncalibrated.calibration = SensorCalibration{};
  YawFusionCounters counters;
  const auto poses = run_flight(flight, options, &counters);
  const auto plain = run_flight(flight, uncalibrated);
  ASSERT_EQ(poses.size(), flight.truth.size());
  ASSERT_EQ(plain.size(), flight.truth.size());
  const Eigen::Vector3d origin = flight.truth.front().position;
  double plain_roll_error = 0.0, plain_height_error = 0.0;
  for (size_t i = 0; i < poses.size(); ++i) {
    const pose_t& p = poses[i];
    const test::TruthFrame& t = flight.truth[i];
    ASSERT_EQ(p.utime, t.utime - offset_us) << "poses keep the frame's stamp";
    const Eigen::Vector3d expected = t.position - origin;
    EXPECT_NEAR(p.position_ned[0], expected.x(), 1e-6) << "frame " << i;
    EXPECT_NEAR(p.position_ned[1], expected.y(), 1e-6) << "frame " << i;
    EXPECT_NEAR(p.position_ned[2], expected.z(), 1e-6) << "frame " << i;
    EXPECT_NEAR(angle_difference(p.yaw, t.yaw), 0.0, 1e-9) << "frame " << i;
    EXPECT_NEAR(p.roll, t.roll, 1e-12) << "frame " << i;
    EXPECT_NEAR(p.pitch, t.pitch, 1e-12) << "frame " << i;
    EXPECT_NEAR(p.height_agl_m, spec.height_agl_m - t.position.z(), 1e-4) << "frame " << i;
    EXPECT_EQ(p.flags, i == 0 ? pose_t::FLAG_INITIALIZING : 0) << "frame " << i;
    plain_roll_error = std::max(plain_roll_error, std::abs(plain[i].roll - t.roll));
    const double true_height = spec.height_agl_m - t.position.z();
    plain_height_error = std::max(plain_height_error, std::abs(plain[i].height_agl_m - true_height));
  }
  EXPECT_EQ(counters.vo_deltas_integrated, spec.frames - 1);
  EXPECT_EQ(counters.vo_deltas_without_ins, 0);
  EXPECT_GT(plain_roll_error, 1e-5) << "the flight must make the time offset matter";
  EXPECT_GT(plain_height_error, 2.0);
}

TEST(YawFusionOptions, CalibrationKeysAreChecked) {
  const Config bad = Config::parse("altimeter: {range_scale: 3}\n", "bad.yaml");
  try {
    YawFusionOptions::from_config(bad);
    FAIL() << "expected ConfigError";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("altimeter.range_scale"), std::string::npos) << e.what();
  }
  YawFusionOptions o;
  o.calibration.camera_time_offset_us = -1000000;
  EXPECT_THROW(o.Check(), ConfigError);
}

}  // namespace
}  // namespace nadir
