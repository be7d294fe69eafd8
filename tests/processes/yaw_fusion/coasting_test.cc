// Coasting: deltas whose translation cannot be trusted are not
// integrated; the pose coasts on the last velocity, flagged, with a growing
// covariance, and resumes without a jump. Also: nothing non-finite is ever
// published whatever the VO_DELTA holds.

#include <gtest/gtest.h>

#include <cmath>
#include <deque>
#include <limits>
#include <map>
#include <random>
#include <set>

#include "common/channels.h"
#include "common/geometry.h"
#include "processes/yaw_fusion/coast_terrain.h"
#include "processes/yaw_fusion/coasting.h"
#include "processes/vo_solver/plane_model.h"
#include "processes/yaw_fusion/yaw_fusion_estimator.h"
#include "estimator_runner.h"
#include "synthetic_flight.h"

namespace nadir {
namespace {

using test::FlightSpec;
using test::SyntheticFlight;
using test::TimedMessage;

std::vector<pose_t> fly(const SyntheticFlight& flight, const YawFusionOptions& options,
                        YawFusionCounters* counters = nullptr) {
  return test::run_flight(flight, options, counters);
}

const pose_t* pose_at(const std::vector<pose_t>& poses, int64_t utime) {
  for (const pose_t& p : poses) {
    if (p.utime == utime) return &p;
  }
  return nullptr;
}

Eigen::Vector3d position(const pose_t& p) { return {p.position_ned[0], p.position_ned[1], p.position_ned[2]}; }

FlightSpec straight_spec() {
  FlightSpec spec;
  spec.frames = 400;
  spec.turn_rate_dps = 0.0;
  spec.climb_rate_mps = 0.0;
  return spec;
}

// Deltas [first, last) get `quality` (the solver's view of an altimeter
// outage); with an altimeter bit the ranges over those frames are removed too.
void flag_deltas(SyntheticFlight* flight, size_t first, size_t last, int32_t quality) {
  for (size_t k = first; k < last && k < flight->deltas.size(); ++k) flight->deltas[k].quality |= quality;
  if ((quality & (vo_delta_t::QUALITY_STALE_ALTIMETER | vo_delta_t::QUALITY_NO_ALTIMETER)) == 0) return;
  const int64_t from = flight->truth[first].utime + 1, to = flight->truth[std::min(last, flight->truth.size() - 1)].utime;
  std::vector<altimeter_t> kept;
  for (const altimeter_t& a : flight->altimeter) {
    if (a.utime < from || a.utime > to) kept.push_back(a);
  }
  flight->altimeter = kept;
}

// Texture gone over deltas [first, last): the tracker keeps measuring from
// its last good frame, so the flagged deltas all start there; then it
// restarts (a first frame without motion, so the delta after is missing).
void lose_texture(SyntheticFlight* flight, size_t first, size_t last) {
  const int64_t kept_prev = flight->deltas[first - 1].utime;
  for (size_t k = first; k < last; ++k) {
    vo_delta_t& d = flight->deltas[k];
    d = vo_delta_t{};
    d.utime = flight->truth[k + 1].utime;
    d.prev_utime = kept_prev;
    d.quality = vo_delta_t::QUALITY_TOO_FEW_FEATURES | vo_delta_t::QUALITY_FRAME_GAP;
    d.variant = "synthetic";
  }
  flight->deltas[last].prev_utime = 0;
}

TEST(CoastPositionVariance, GrowsAsConstantVelocityErrorPlusRandomWalk) {
  EXPECT_EQ(coast_position_variance(1.0, 0.5, 0.0), 0.0);
  EXPECT_EQ(coast_position_variance(1.0, 0.5, -3.0), 0.0);
  EXPECT_EQ(coast_position_variance(1.0, 0.5, std::numeric_limits<double>::quiet_NaN()), 0.0);
  // sigma_v^2 t^2 + q^2 t^3 / 3.
  EXPECT_NEAR(coast_position_variance(1.0, 0.0, 10.0), 100.0, 1e-12);
  EXPECT_NEAR(coast_position_variance(0.0, 0.5, 10.0), 0.25 * 1000.0 / 3.0, 1e-9);
  EXPECT_NEAR(coast_position_variance(2.0, 0.5, 4.0), 4.0 * 16.0 + 0.25 * 64.0 / 3.0, 1e-9);
  // The random-walk part is what a simulated random walk of the velocity gives.
  std::mt19937 rng(3);
  std::normal_distribution<double> normal;
  const double q = 0.7, dt = 0.01, t = 5.0;
  double sum_sq = 0.0;
  const int runs = 4000;
  for (int r = 0; r < runs; ++r) {
    double v = 0.0, p = 0.0;
    for (int i = 0; i < static_cast<int>(t / dt); ++i) {
      v += q * std::sqrt(dt) * normal(rng);
      p += v * dt;
    }
    sum_sq += p * p;
  }
  EXPECT_NEAR(sum_sq / runs, coast_position_variance(0.0, q, t), 0.08 * coast_position_variance(0.0, q, t));
}

TEST(Coasting, StaleAltimeterIsCoastedWithGrowingCovarianceAndResumesWithoutAJump) {
  SyntheticFlight flight = test::make_flight(straight_spec());
  // 10 s of stale ranges (140 deltas at 14 Hz): the solver mis-scales them by 30 %.
  for (size_t k = 100; k < 240; ++k) {
    flight.deltas[k].dx *= 1.3;
    flight.deltas[k].dy *= 1.3;
  }
  flag_deltas(&flight, 100, 240, vo_delta_t::QUALITY_STALE_ALTIMETER);
  YawFusionCounters counters;
  YawFusionOptions options;
  options.coast.max_range_age_s = 0.06;  // from the first frame without a range (20 Hz altimeter)
  // The held climb rate's variance growth, checked exactly below (the first
  // frames still have a range within max_altimeter_age_s, which the height
  // would follow: TextureLossHeightFollowsTheAltimeterOverTheTerrainPlane).
  options.coast.follow_altimeter = false;
  const auto poses = fly(flight, options, &counters);
  ASSERT_EQ(poses.size(), flight.truth.size());
  const Eigen::Vector3d origin = flight.truth.front().position;

  // The poses of the stale frames (and the resuming ones) are flagged coasting, no others.
  const int resume = options.coast.resume_good_deltas - 1;  // clean deltas still coasted
  for (size_t k = 1; k < flight.truth.size(); ++k) {
    const bool coasted = k >= 101 && k < 241 + static_cast<size_t>(resume);
    const pose_t* p = pose_at(poses, flight.truth[k].utime);
    ASSERT_NE(p, nullptr);
    EXPECT_EQ((p->flags & pose_t::FLAG_COASTING) != 0, coasted) << "frame " << k;
    EXPECT_FALSE(p->flags & pose_t::FLAG_VO_GAP) << "frame " << k;
  }
  EXPECT_EQ(counters.vo_deltas_coasted, 140 + resume);
  EXPECT_EQ(counters.coast_reasons[0], 140);  // kCoastQuality
  EXPECT_EQ(counters.coast_reasons[4], resume);  // kCoastResuming
  EXPECT_EQ(counters.coast_episodes, 1);

  // Covariance: the coast model on top of what the last integrated frame had.
  const pose_t* before = pose_at(poses, flight.truth[100].utime);
  const pose_t* end = pose_at(poses, flight.truth[240].utime);
  const double t = static_cast<double>(end->utime - before->utime) * 1e-6;
  const double grown = coast_position_variance(options.coast.velocity_stddev_mps,
                                               options.coast.velocity_random_walk, t);
  EXPECT_NEAR(end->position_covariance[0][0] - before->position_covariance[0][0], grown, 1e-6 * grown);
  EXPECT_NEAR(end->position_covariance[1][1] - before->position_covariance[1][1], grown, 1e-6 * grown);
  const double grown_down = coast_position_variance(options.coast.vertical_velocity_stddev_mps,
                                                    options.coast.velocity_random_walk, t);
  EXPECT_NEAR(end->position_covariance[2][2] - before->position_covariance[2][2], grown_down, 1e-6 * grown_down);
  // Straight and level: the held velocity is right, the mis-scaled motion is not taken.
  const Eigen::Vector3d truth_end = flight.truth[240].position - origin;
  EXPECT_LT((position(*end) - truth_end).norm(), 0.3);
  EXPECT_LT((position(*end) - truth_end).norm(), 3.0 * std::sqrt(end->position_covariance[0][0]));

  // No jump when integration resumes: each step is one frame's motion.
  for (size_t k = 230; k < 260; ++k) {
    const pose_t* a = pose_at(poses, flight.truth[k].utime);
    const pose_t* b = pose_at(poses, flight.truth[k + 1].utime);
    const double step = (position(*b) - position(*a)).norm();
    const double truth_step = (flight.truth[k + 1].position - flight.truth[k].position).norm();
    EXPECT_NEAR(step, truth_step, 0.05) << "frame " << k;
  }
  const pose_t& last = poses.back();
  EXPECT_EQ(last.flags, 0);
  EXPECT_LT((position(last) - (flight.truth.back().position - origin)).norm(), 0.3);
}

// One or two missed returns: the solver flags STALE_ALTIMETER (its nearest
// range is over 200 ms old) but a range within coast.max_range_age_s is there:
// integrated as before, not coasted.
TEST(Coasting, StaleFlagWithARecentRangeIsIntegrated) {
  SyntheticFlight flight = test::make_flight(straight_spec());
  for (size_t k = 100; k < 103; ++k) flight.deltas[k].quality |= vo_delta_t::QUALITY_STALE_ALTIMETER;
  YawFusionCounters counters;
  const auto poses = fly(flight, YawFusionOptions{}, &counters);
  EXPECT_EQ(counters.vo_deltas_coasted, 0);
  EXPECT_EQ(counters.vo_deltas_integrated, static_cast<int64_t>(flight.deltas.size()));
  for (const pose_t& p : poses) EXPECT_FALSE(p.flags & pose_t::FLAG_COASTING);
}

TEST(Coasting, HeldVelocityFollowsTheInsHeadingInATurn) {
  FlightSpec spec = straight_spec();
  spec.turn_rate_dps = 6.0;
  SyntheticFlight flight = test::make_flight(spec);
  flag_deltas(&flight, 100, 240, vo_delta_t::QUALITY_NO_ALTIMETER);
  YawFusionOptions options;
  const auto poses = fly(flight, options);
  const Eigen::Vector3d origin = flight.truth.front().position;
  const pose_t* end = pose_at(poses, flight.truth[240].utime);
  ASSERT_NE(end, nullptr);
  EXPECT_TRUE(end->flags & pose_t::FLAG_COASTING);
  const double coasted_error = (position(*end) - (flight.truth[240].position - origin)).norm();
  // The same coast with the velocity held in the world (what a VO gap does) is far off in a turn.
  const Eigen::Vector3d start = flight.truth[100].position;
  const Eigen::Vector3d v_world = (flight.truth[100].position - flight.truth[86].position) /
                                  (static_cast<double>(flight.truth[100].utime - flight.truth[86].utime) * 1e-6);
  const Eigen::Vector3d world_held =
      start + v_world * (static_cast<double>(flight.truth[240].utime - flight.truth[100].utime) * 1e-6);
  const double world_held_error = (world_held - flight.truth[240].position).norm();
  EXPECT_LT(coasted_error, 0.5 * world_held_error);
  EXPECT_LT(coasted_error, 3.0 * std::sqrt(end->position_covariance[0][0] + end->position_covariance[1][1]));
}

// A photo flight's frames can be seconds apart: one coasted step of 10 s
// through a 60 deg turn (the pair across it unsolved; it supersedes the gap
// poses published while waiting for it) follows the INS heading along it, as
// 140 short steps do.
TEST(Coasting, OneLongStepFollowsTheInsHeadingThroughATurn) {
  FlightSpec spec = straight_spec();
  spec.turn_rate_dps = 6.0;
  SyntheticFlight many = test::make_flight(spec);
  SyntheticFlight one = many;
  lose_texture(&many, 100, 240);
  // The same outage with no frame in between: one delta from frame 100 to 240.
  vo_delta_t across{};
  across.utime = one.truth[240].utime;
  across.prev_utime = one.truth[100].utime;
  across.quality = vo_delta_t::QUALITY_TOO_FEW_FEATURES;
  across.variant = "synthetic";
  one.deltas.erase(one.deltas.begin() + 100, one.deltas.begin() + 240);
  one.deltas.insert(one.deltas.begin() + 100, across);
  one.deltas[101].prev_utime = 0;  // the tracker restarts after it
  const auto poses_many = fly(many, YawFusionOptions{});
  const auto poses_one = fly(one, YawFusionOptions{});
  const pose_t* end_many = pose_at(poses_many, one.truth[240].utime);
  const pose_t* end_one = pose_at(poses_one, one.truth[240].utime);
  ASSERT_NE(end_many, nullptr);
  ASSERT_NE(end_one, nullptr);
  EXPECT_TRUE(end_one->flags & pose_t::FLAG_COASTING);
  const Eigen::Vector3d truth = one.truth[240].position - one.truth.front().position;
  // 300 m flown along a 60 deg arc: held along the heading at either end it
  // would be ~80 m off; along the INS heading it is where the short steps put it.
  EXPECT_LT((position(*end_one) - position(*end_many)).head<2>().norm(), 0.5);
  EXPECT_LT((position(*end_one) - truth).head<2>().norm(), 2.0);
  EXPECT_NEAR(end_one->position_covariance[0][0], end_many->position_covariance[0][0],
              0.01 * end_many->position_covariance[0][0]);
}

TEST(HeldLevelVelocity, TrackOverTheWindowInTheFrameOfItsMeanHeading) {
  // 3 s at 20 m/s on a track of 85 deg, climbing 1 m/s; the heading is the
  // track plus a crab of 2 deg plus an oscillation of 1 deg that sums to zero
  // over the registering frames (all but the last).
  const double track = deg_to_rad(85.0), crab = deg_to_rad(2.0), speed = 20.0, climb = 1.0;
  const int n = 42;  // registering frames
  std::deque<CoastSample> window;
  for (int k = 0; k <= n; ++k) {
    const double t = 3.0 * k / n;
    CoastSample s;
    s.utime = 1'000'000 + static_cast<int64_t>(std::llround(t * 1e6));
    s.position = Eigen::Vector3d(speed * t * std::cos(track), speed * t * std::sin(track), -climb * t);
    s.yaw = track + crab + deg_to_rad(1.0) * std::sin(2.0 * M_PI * k / n);
    window.push_back(s);
  }
  const auto level = held_level_velocity(window);
  ASSERT_TRUE(level.has_value());
  EXPECT_NEAR(level->x(), speed * std::cos(crab), 1e-6);
  EXPECT_NEAR(level->y(), -speed * std::sin(crab), 1e-6);  // the track is left of the heading
  EXPECT_NEAR(level->z(), -climb, 1e-9);
  // The last frame's heading (1 deg of oscillation off the mean) is not the one used.
  window.back().yaw = track + crab + deg_to_rad(1.0);
  EXPECT_NEAR(held_level_velocity(window)->y(), -speed * std::sin(crab), 1e-6);

  // The same window turned to fly across +-180 deg: wrapped yaws average right.
  std::deque<CoastSample> across;
  const double south = M_PI - deg_to_rad(1.0);
  for (int k = 0; k <= n; ++k) {
    CoastSample s = window[k];
    const double t = 3.0 * k / n;
    s.position = Eigen::Vector3d(speed * t * std::cos(south), speed * t * std::sin(south), -climb * t);
    s.yaw = wrap_angle(south + crab + deg_to_rad(1.0) * std::sin(2.0 * M_PI * k / n));
    across.push_back(s);
  }
  const auto level_across = held_level_velocity(across);
  ASSERT_TRUE(level_across.has_value());
  EXPECT_NEAR(level_across->x(), speed * std::cos(crab), 1e-6);
  EXPECT_NEAR(level_across->y(), -speed * std::sin(crab), 1e-6);

  // Fewer than two samples, or no time between them: nothing to hold.
  EXPECT_FALSE(held_level_velocity({}).has_value());
  EXPECT_FALSE(held_level_velocity({window.front()}).has_value());
  EXPECT_FALSE(held_level_velocity({window.front(), window.front()}).has_value());
}

TEST(Coasting, HeldTrackIgnoresAHeadingOscillationTheTrackDoesNotFollow) {
  // Straight flight; the heading swings 1 deg about the track every 3 s. The
  // texture goes with the last good frame at a peak of the swing, the worst
  // moment to take the angle between track and heading from that frame alone.
  FlightSpec spec = straight_spec();
  spec.heading_oscillation_deg = 1.0;
  spec.heading_oscillation_period_s = 3.0;
  SyntheticFlight flight = test::make_flight(spec);
  const double track = deg_to_rad(spec.initial_yaw_deg);
  size_t first = 100;  // deltas [first, last) lost; the last good frame is truth[first]
  for (size_t k = 100; k < 142; ++k) {
    if (std::abs(wrap_angle(flight.truth[k].yaw - track)) > std::abs(wrap_angle(flight.truth[first].yaw - track))) {
      first = k;
    }
  }
  const size_t last = first + 140;  // 10 s
  lose_texture(&flight, first, last);
  const auto poses = fly(flight, YawFusionOptions{});
  const Eigen::Vector3d origin = flight.truth.front().position;
  const pose_t* end = pose_at(poses, flight.truth[last].utime);
  ASSERT_NE(end, nullptr);
  EXPECT_TRUE(end->flags & pose_t::FLAG_COASTING);
  const double coasted_error = (position(*end) - (flight.truth[last].position - origin)).norm();
  // The last second's velocity put into the frame of the last frame's
  // heading and turned with the heading from there on: the track it holds
  // is off by the swing's amplitude, on average.
  const test::TruthFrame& from = flight.truth[first];
  const test::TruthFrame& second_before = flight.truth[first - 14];
  const Eigen::Vector3d v_level = rotation_from_rpy(0.0, 0.0, -from.yaw) * (from.position - second_before.position) /
                                  (static_cast<double>(from.utime - second_before.utime) * 1e-6);
  Eigen::Vector3d last_heading_held = from.position;
  for (size_t k = first; k < last; ++k) {
    const double dt = static_cast<double>(flight.truth[k + 1].utime - flight.truth[k].utime) * 1e-6;
    last_heading_held += rotation_from_rpy(0.0, 0.0, flight.truth[k + 1].yaw) * v_level * dt;
  }
  const double last_heading_error = (last_heading_held - flight.truth[last].position).norm();
  EXPECT_GT(last_heading_error, 3.0);  // 30 m/s for 10 s, ~1 deg off: ~5 m
  EXPECT_LT(coasted_error, 0.25 * last_heading_error);
  EXPECT_LT(coasted_error, 3.0 * std::sqrt(end->position_covariance[0][0] + end->position_covariance[1][1]));
}

TEST(Coasting, BeyondMaxDurationItIsAVoGap) {
  SyntheticFlight flight = test::make_flight(straight_spec());
  flag_deltas(&flight, 100, 240, vo_delta_t::QUALITY_STALE_ALTIMETER);
  YawFusionOptions options;
  options.coast.max_duration_s = 4.0;
  YawFusionCounters counters;
  const auto poses = fly(flight, options, &counters);
  const pose_t* early = pose_at(poses, flight.truth[140].utime);   // ~2.9 s into it
  const pose_t* late = pose_at(poses, flight.truth[200].utime);    // ~7 s
  ASSERT_NE(early, nullptr);
  ASSERT_NE(late, nullptr);
  EXPECT_TRUE(early->flags & pose_t::FLAG_COASTING);
  EXPECT_FALSE(early->flags & pose_t::FLAG_VO_GAP);
  EXPECT_TRUE(late->flags & pose_t::FLAG_VO_GAP);
  EXPECT_FALSE(late->flags & pose_t::FLAG_COASTING);
  EXPECT_GT(counters.coast_expired, 80);
  EXPECT_EQ(poses.back().flags, 0);
}

TEST(Coasting, DisabledKeepsTheOldBehaviour) {
  SyntheticFlight flight = test::make_flight(straight_spec());
  for (size_t k = 100; k < 240; ++k) flight.deltas[k].dx *= 1.3;
  flag_deltas(&flight, 100, 240, vo_delta_t::QUALITY_STALE_ALTIMETER);
  YawFusionOptions options;
  options.coast.enabled = false;
  YawFusionCounters counters;
  const auto poses = fly(flight, options, &counters);
  EXPECT_EQ(counters.vo_deltas_coasted, 0);
  for (const pose_t& p : poses) EXPECT_FALSE(p.flags & pose_t::FLAG_COASTING);
  // The mis-scaled motion is integrated: 30 % of 10 s at 30 m/s.
  const Eigen::Vector3d truth_end = flight.truth.back().position - flight.truth.front().position;
  EXPECT_GT((position(poses.back()) - truth_end).norm(), 50.0);
}

TEST(Coasting, InlierDropVerticalJumpAndHighResidualMajorityCoast) {
  SyntheticFlight flight = test::make_flight(straight_spec());
  // Near-featureless ground: a few deltas still solve, with few inliers and a wild dz.
  for (size_t k = 100; k < 104; ++k) {
    flight.deltas[k].inliers = 30;
    flight.deltas[k].dz += 2.5;
  }
  // A vertical jump the altimeter does not see, with normal inliers.
  flight.deltas[150].dz += 6.0;
  // HIGH_RESIDUAL on 30 of 40 deltas.
  for (size_t k = 200; k < 240; ++k) {
    if (k % 4 != 0) flight.deltas[k].quality |= vo_delta_t::QUALITY_HIGH_RESIDUAL;
  }
  YawFusionCounters counters;
  const YawFusionOptions options;
  const auto poses = fly(flight, options, &counters);
  EXPECT_EQ(counters.coast_reasons[1], 4);  // kCoastInlierDrop
  EXPECT_GE(counters.coast_reasons[2], 1);  // kCoastVertical (the 2.5 m ones too)
  EXPECT_GT(counters.coast_reasons[3], 0);  // kCoastHighResidual
  EXPECT_TRUE(pose_at(poses, flight.truth[101].utime)->flags & pose_t::FLAG_COASTING);
  EXPECT_TRUE(pose_at(poses, flight.truth[151].utime)->flags & pose_t::FLAG_COASTING);
  EXPECT_TRUE(pose_at(poses, flight.truth[240].utime)->flags & pose_t::FLAG_COASTING);
  // None of the bad vertical motion got in.
  const Eigen::Vector3d origin = flight.truth.front().position;
  for (const pose_t& p : poses) {
    for (size_t k = 0; k < flight.truth.size(); ++k) {
      if (flight.truth[k].utime == p.utime) {
        EXPECT_NEAR(p.position_ned[2], flight.truth[k].position.z() - origin.z(), 0.2) << "frame " << k;
      }
    }
  }
}

// A noisy altimeter (1.5 m per range: 0.5 % at 300 m) makes the fixed 3 m
// gate fire on good deltas; every coast drops a delta whose levelling error
// the neighbours share. The gate follows the ground steps' own robust spread
// (5 sigma) once its window is full, and still catches a real jump.
TEST(Coasting, VerticalGateFollowsTheSpreadOfANoisyAltimeter) {
  FlightSpec spec = straight_spec();
  spec.frames = 800;
  SyntheticFlight flight = test::make_flight(spec);
  std::mt19937 rng(3);
  std::normal_distribution<double> range_noise(0.0, 1.5);
  for (altimeter_t& a : flight.altimeter) a.range_m += range_noise(rng);
  flight.deltas[300].dz += 25.0;  // a jump no altimeter noise explains
  YawFusionCounters fixed_counters, counters;
  YawFusionOptions fixed;
  fixed.coast.vertical_gate_sigmas = 0.0;
  fly(flight, fixed, &fixed_counters);
  const auto poses = fly(flight, YawFusionOptions(), &counters);
  // The fixed gate: the ground step's noise (~2 m) crosses 3 m + the 2.1 m step on ~1 % of the deltas (6 here).
  EXPECT_GE(fixed_counters.coast_reasons[2], 4);
  // Self-calibrated: only the jump.
  EXPECT_LE(counters.coast_reasons[2], 1);
  EXPECT_TRUE(pose_at(poses, flight.truth[301].utime)->flags & pose_t::FLAG_COASTING);
}

// Coasting holds a speed measured over speed_window_s (3 s) of integrated
// motion. Before that much is behind (the start of a flight, after a gap) a
// delta the detector only judged (here a vertical jump) is integrated, not
// coasted on a speed of a few noisy deltas; a delta without a range still coasts.
TEST(Coasting, NothingJudgedIsCoastedBeforeASpeedIsHeld) {
  SyntheticFlight flight = test::make_flight(straight_spec());
  flight.deltas[10].dz += 6.0;  // 0.7 s in
  flight.deltas[100].dz += 6.0;
  flag_deltas(&flight, 20, 21, vo_delta_t::QUALITY_NO_ALTIMETER);
  YawFusionCounters counters;
  const auto poses = fly(flight, YawFusionOptions(), &counters);
  EXPECT_FALSE(pose_at(poses, flight.truth[11].utime)->flags & pose_t::FLAG_COASTING);
  EXPECT_TRUE(pose_at(poses, flight.truth[21].utime)->flags & pose_t::FLAG_COASTING);
  EXPECT_TRUE(pose_at(poses, flight.truth[101].utime)->flags & pose_t::FLAG_COASTING);
  EXPECT_EQ(counters.coast_reasons[2], 1);  // kCoastVertical: the one at frame 100
}

// Texture gone: the tracker keeps measuring from its last good frame, so the
// flagged deltas all start there (and span up to 10 s): coasted, not dropped as
// overlapping or too long; then the tracker restarts (a first frame, a missing delta).
TEST(Coasting, TextureLossDeltasFromTheLastGoodFrameAreCoasted) {
  SyntheticFlight flight = test::make_flight(straight_spec());
  lose_texture(&flight, 100, 240);
  YawFusionCounters counters;
  const auto poses = fly(flight, YawFusionOptions{}, &counters);
  EXPECT_EQ(counters.vo_deltas_late, 0);
  EXPECT_EQ(counters.vo_deltas_invalid, 0);
  EXPECT_EQ(counters.coast_reasons[0], 140);
  for (size_t k = 101; k < 241; ++k) {
    const pose_t* p = pose_at(poses, flight.truth[k].utime);
    ASSERT_NE(p, nullptr) << "frame " << k;
    EXPECT_TRUE(p->flags & pose_t::FLAG_COASTING) << "frame " << k;
    EXPECT_FALSE(p->flags & pose_t::FLAG_VO_GAP) << "frame " << k;
  }
  // Frame 241 (the delta after the restart starts there) is coasted over too.
  EXPECT_TRUE(pose_at(poses, flight.truth[241].utime)->flags & pose_t::FLAG_COASTING);
  const Eigen::Vector3d truth_end = flight.truth.back().position - flight.truth.front().position;
  EXPECT_LT((position(poses.back()) - truth_end).norm(), 0.5);
  EXPECT_EQ(poses.back().flags, 0);
}

// The ground patch's tilt is the terrain's slope in the world.
TEST(CoastTerrain, GroundGradientFromThePatchTilt) {
  // Ground down coordinate rising 0.1 m per metre forward, falling 0.05 per metre right:
  // normal (-0.1, 0.05, 1) in the level frame.
  double roll = 0.0, pitch = 0.0;
  vo::tilt_from_normal(Eigen::Vector3d(-0.1, 0.05, 1.0), &roll, &pitch);
  const Eigen::Vector2d level = ground_gradient_ned(roll, pitch, 0.0);
  EXPECT_NEAR(level.x(), 0.1, 1e-12);
  EXPECT_NEAR(level.y(), -0.05, 1e-12);
  // Heading east: forward is east, right is south.
  const Eigen::Vector2d east = ground_gradient_ned(roll, pitch, M_PI_2);
  EXPECT_NEAR(east.x(), 0.05, 1e-12);
  EXPECT_NEAR(east.y(), 0.1, 1e-12);
}

TEST(CoastTerrain, PlaneThroughTheAveragedGroundPointsAlongTheMeanSlope) {
  CoastTerrain terrain(1.0);
  EXPECT_FALSE(terrain.anchor());  // no frames
  const Eigen::Vector2d gradient(0.02, -0.01);
  // 2 s of frames at 10 Hz flying north-east over the plane down = 100 + g . p, at alternating heights.
  for (int k = 0; k <= 20; ++k) {
    const Eigen::Vector2d p(3.0 * k, 2.0 * k);
    const double height = 50.0 + (k % 2 ? 0.5 : -0.5);
    const double ground = 100.0 + gradient.dot(p);
    terrain.note_frame(k * 100'000, Eigen::Vector3d(p.x(), p.y(), ground - height), height, gradient);
  }
  ASSERT_TRUE(terrain.anchor());
  EXPECT_NEAR(terrain.gradient().x(), 0.02, 1e-12);
  EXPECT_NEAR(terrain.gradient().y(), -0.01, 1e-12);
  EXPECT_NEAR(terrain.ground_down(Eigen::Vector2d(300.0, -40.0)), 100.0 + gradient.dot(Eigen::Vector2d(300.0, -40.0)),
              1e-9);
  terrain.clear();
  EXPECT_FALSE(terrain.anchored());
  // Frames without a range give no ground point.
  terrain.note_frame(0, Eigen::Vector3d::Zero(), std::numeric_limits<double>::quiet_NaN(), gradient);
  EXPECT_FALSE(terrain.anchor());
}

// 10 s of texture loss over a 3 % slope while the climb rate changes from 0
// to 2 m/s: the held climb rate would end ~13 m off; the height follows the
// altimeter above the last frames' ground plane instead, with a vertical
// sigma that does not grow while the horizontal one does, and the vertical
// error after VO resumes is what it was before the coast.
TEST(Coasting, TextureLossHeightFollowsTheAltimeterOverTheTerrainPlane) {
  FlightSpec spec = straight_spec();
  spec.terrain_gradient_north = 0.03;
  spec.terrain_gradient_east = -0.01;
  spec.climb_rate_change_s = 11.0;  // frame ~147, in the coast
  spec.climb_rate_after_mps = 2.0;
  SyntheticFlight flight = test::make_flight(spec);
  lose_texture(&flight, 100, 240);
  const Eigen::Vector3d origin = flight.truth.front().position;
  auto vertical_error = [&](const pose_t& p, size_t k) {
    return p.position_ned[2] - (flight.truth[k].position.z() - origin.z());
  };
  YawFusionOptions held;
  held.coast.follow_altimeter = false;
  const auto held_poses = fly(flight, held);
  YawFusionCounters counters;
  YawFusionOptions options;
  options.coast.follow_altimeter = true;
  // The synthetic ground is a plane whose slope the deltas carry exactly.
  options.coast.terrain_slope_stddev = 0.0;
  const auto poses = fly(flight, options, &counters);
  EXPECT_EQ(counters.coast_reasons[0], 140);
  // With the default slope error the terrain and the held climb are weighted:
  // the vertical sigma then grows, but less than either's alone and less than the horizontal.
  YawFusionOptions weighted_options;
  weighted_options.coast.follow_altimeter = true;
  const auto weighted = fly(flight, weighted_options);
  const pose_t* before = pose_at(poses, flight.truth[100].utime);  // the last integrated frame
  ASSERT_NE(before, nullptr);
  const double sigma_down_before = std::sqrt(before->position_covariance[2][2]);
  double worst = 0.0, worst_held = 0.0;
  for (size_t k = 101; k <= 241; ++k) {
    const pose_t* p = pose_at(poses, flight.truth[k].utime);
    const pose_t* h = pose_at(held_poses, flight.truth[k].utime);
    ASSERT_NE(p, nullptr) << "frame " << k;
    ASSERT_NE(h, nullptr) << "frame " << k;
    EXPECT_TRUE(p->flags & pose_t::FLAG_COASTING) << "frame " << k;
    worst = std::max(worst, std::abs(vertical_error(*p, k)));
    worst_held = std::max(worst_held, std::abs(vertical_error(*h, k)));
    // Vertical sigma: the anchor's plus two ranges' noise (0.1 m + 0.1 % of ~300 m), never growing.
    EXPECT_LT(std::sqrt(p->position_covariance[2][2]), std::hypot(sigma_down_before, std::sqrt(2.0) * 0.45))
        << "frame " << k;
  }
  // The altimeter's newest range is up to 50 ms old at 2 m/s climb and 30 m/s over a 3 % slope: 0.15 m.
  EXPECT_LT(worst, 0.3);
  EXPECT_GT(worst_held, 8.0);  // what holding the climb rate gives (the test's reason to exist)
  // Horizontal sigma grows as the coast model says.
  const pose_t* end = pose_at(poses, flight.truth[240].utime);
  const double t = static_cast<double>(end->utime - before->utime) * 1e-6;
  const double grown = coast_position_variance(options.coast.velocity_stddev_mps, options.coast.velocity_random_walk, t);
  EXPECT_NEAR(end->position_covariance[0][0] - before->position_covariance[0][0], grown, 1e-6 * grown);
  EXPECT_GT(std::sqrt(end->position_covariance[0][0]), 5.0 * std::sqrt(end->position_covariance[2][2]));
  const pose_t* weighted_end = pose_at(weighted, flight.truth[240].utime);
  const double held_variance = coast_position_variance(options.coast.vertical_velocity_stddev_mps,
                                                       options.coast.velocity_random_walk, t);
  EXPECT_LT(weighted_end->position_covariance[2][2], before->position_covariance[2][2] + held_variance);
  EXPECT_LT(weighted_end->position_covariance[2][2], weighted_end->position_covariance[0][0]);
  const double weighted_error = std::abs(vertical_error(*weighted_end, 240));
  EXPECT_LT(weighted_error, std::abs(vertical_error(*pose_at(held_poses, flight.truth[240].utime), 240)));
  EXPECT_LT(weighted_error, 3.0 * std::sqrt(weighted_end->position_covariance[2][2]));
  // After VO resumes the vertical error is not frozen at the held climb's: back within 0.3 m.
  const pose_t& last = poses.back();
  EXPECT_EQ(last.flags, 0);
  EXPECT_LT(std::abs(vertical_error(last, flight.truth.size() - 1)), 0.3);
  EXPECT_GT(std::abs(vertical_error(held_poses.back(), flight.truth.size() - 1)), 8.0);
  // No vertical jump at the resume: each step within 0.3 m of the true one.
  for (size_t k = 236; k < 250; ++k) {
    const pose_t* a = pose_at(poses, flight.truth[k].utime);
    const pose_t* b = pose_at(poses, flight.truth[k + 1].utime);
    const double step = b->position_ned[2] - a->position_ned[2];
    const double truth_step = flight.truth[k + 1].position.z() - flight.truth[k].position.z();
    EXPECT_NEAR(step, truth_step, 0.3) << "frame " << k;
  }
}

// 10 s of texture loss over a swell (5 m high, 400 m long) while the climb
// rate changes from 0 to 2 m/s (2 s into it), the frames' ground points covering 200 m
// ahead: over the ground the last frame saw, the height is that ground's
// minus the range (no climb held, no plane guessed); beyond it the climb
// measured over it is held. The plane through the last frames misses the
// swell, the held climb misses the climb.
TEST(Coasting, TextureLossOverSeenGroundFollowsItAndHoldsTheClimbMeasuredOverIt) {
  FlightSpec spec = straight_spec();
  spec.terrain_wave_m = 5.0;
  spec.climb_rate_change_s = 9.0;  // frame ~119, 2 s into the coast, 3 s before the seen ground ends
  spec.climb_rate_after_mps = 2.0;
  spec.ground_points = true;
  spec.height_agl_m = 150.0;  // the points within 25 m make the ground
  spec.altimeter_along_beam = true;  // 2 deg pitch: the beam hits the ground 5 m behind
  SyntheticFlight flight = test::make_flight(spec);
  lose_texture(&flight, 100, 240);
  const Eigen::Vector3d origin = flight.truth.front().position;
  auto vertical_error = [&](const pose_t& p, size_t k) {
    return p.position_ned[2] - (flight.truth[k].position.z() - origin.z());
  };
  YawFusionOptions seen_options;  // the default
  ASSERT_TRUE(seen_options.coast.follow_seen_ground);
  YawFusionCounters counters;
  const auto seen = fly(flight, seen_options, &counters);
  YawFusionOptions plane_options;
  plane_options.coast.follow_seen_ground = false;
  plane_options.coast.follow_altimeter = true;
  const auto plane = fly(flight, plane_options);
  YawFusionOptions held_options;
  held_options.coast.follow_seen_ground = false;
  const auto held = fly(flight, held_options);
  EXPECT_EQ(counters.ground_frames_received, static_cast<int64_t>(flight.ground.size()));
  // 30 m/s over 200 m of seen ground, less the edge where the points lie only behind: ~6 s (~85 frames).
  EXPECT_GT(counters.coast_seen_ground_poses, 80);
  EXPECT_LT(counters.coast_seen_ground_poses, 100);
  const pose_t* before = pose_at(seen, flight.truth[100].utime);
  ASSERT_NE(before, nullptr);
  double worst_over_seen = 0.0, worst_seen = 0.0, worst_plane = 0.0, worst_held = 0.0;
  for (size_t k = 101; k <= 241; ++k) {
    const pose_t* p = pose_at(seen, flight.truth[k].utime);
    ASSERT_NE(p, nullptr) << "frame " << k;
    EXPECT_TRUE(p->flags & pose_t::FLAG_COASTING) << "frame " << k;
    const double e = std::abs(vertical_error(*p, k));
    worst_seen = std::max(worst_seen, e);
    if (k <= 195) {
      worst_over_seen = std::max(worst_over_seen, e);
      // Over seen ground the vertical sigma stays that of the ground and the range, the horizontal grows.
      EXPECT_LT(std::sqrt(p->position_covariance[2][2]), std::hypot(std::sqrt(before->position_covariance[2][2]), 1.0))
          << "frame " << k;
    }
    worst_plane = std::max(worst_plane, std::abs(vertical_error(*pose_at(plane, flight.truth[k].utime), k)));
    worst_held = std::max(worst_held, std::abs(vertical_error(*pose_at(held, flight.truth[k].utime), k)));
    EXPECT_LT(e, 3.0 * std::sqrt(p->position_covariance[2][2])) << "frame " << k;
  }
  // Each range is a measurement of the height filter, whose climb follows a
  // change as fast as the coast model's random walk lets it: an instant 2 m/s
  // (a real climb starts over seconds) is followed within 0.35 m (measured).
  EXPECT_LT(worst_over_seen, 0.45);
  EXPECT_LT(worst_seen, 0.45);
  EXPECT_GT(worst_plane, 3.0);
  EXPECT_GT(worst_held, 8.0);
  // At the coast's end the vertical has grown for the ~3 s since the seen ground, the horizontal for 10 s.
  const pose_t* end = pose_at(seen, flight.truth[240].utime);
  EXPECT_GT(std::sqrt(end->position_covariance[0][0]), 2.0 * std::sqrt(end->position_covariance[2][2]));
  // After VO resumes nothing is frozen in.
  EXPECT_EQ(seen.back().flags, 0);
  EXPECT_LT(std::abs(vertical_error(seen.back(), flight.truth.size() - 1)), 0.3);
  // With the option but no VO_GROUND (another solver variant): the held climb, as without it.
  spec.ground_points = false;
  SyntheticFlight no_points = test::make_flight(spec);
  lose_texture(&no_points, 100, 240);
  const auto without = fly(no_points, seen_options);
  ASSERT_EQ(without.size(), held.size());
  for (size_t i = 0; i < held.size(); ++i) EXPECT_EQ(without[i].position_ned[2], held[i].position_ned[2]) << i;
}

// Level flight at 200 m over a swell with the altimeter's noise (0.3 m a
// range, as the standard sensors at that height): over seen ground each range
// is one measurement of the height filter, so the noise averages out of the
// height; the climb carried on past the seen ground (~5 s of it at 200 m and
// 30 m/s) is the one measured over it. Ten flights.
TEST(Coasting, TextureLossOverSeenGroundAveragesTheRangesNoise) {
  const double range_noise = 0.3;
  double sum_sq_end = 0.0, sum_sq_seen = 0.0;
  int seen_poses = 0;
  const int flights = 10;
  for (int f = 0; f < flights; ++f) {
    FlightSpec spec = straight_spec();
    spec.terrain_wave_m = 5.0;
    spec.ground_points = true;
    spec.height_agl_m = 200.0;
    spec.altimeter_along_beam = true;
    spec.range_stddev_m = range_noise;
    spec.seed = 100 + static_cast<uint32_t>(f);
    SyntheticFlight flight = test::make_flight(spec);
    lose_texture(&flight, 100, 240);
    const Eigen::Vector3d origin = flight.truth.front().position;
    YawFusionCounters counters;
    const auto poses = fly(flight, YawFusionOptions{}, &counters);
    EXPECT_GT(counters.coast_seen_ground_poses, 40) << f;
    for (size_t k = 101; k <= 240; ++k) {
      const pose_t* p = pose_at(poses, flight.truth[k].utime);
      ASSERT_NE(p, nullptr) << f << " frame " << k;
      const double e = p->position_ned[2] - (flight.truth[k].position.z() - origin.z());
      EXPECT_LT(std::abs(e), 3.0 * std::sqrt(p->position_covariance[2][2])) << f << " frame " << k;
      if (k <= 150) {  // the first 3.5 s: over seen ground on every flight
        sum_sq_seen += e * e;
        ++seen_poses;
      }
      if (k == 240) sum_sq_end += e * e;
    }
  }
  // Measured: 0.18 m over seen ground, 0.63 m at the end (the climb from ~4 s of ranges, held
  // 6 s; with the two climb models 0.16 m and 0.35 m).
  EXPECT_LT(std::sqrt(sum_sq_seen / seen_poses), 0.75 * range_noise);
  EXPECT_LT(std::sqrt(sum_sq_end / flights), 0.8);
}

// The delta a perfect solver gives from frame `a` to frame `b` (level frame
// of `a`), flagged as a frame gap: the tracker matched its last good frame
// with the first after the featureless ground.
vo_delta_t delta_between(const SyntheticFlight& flight, size_t a, size_t b) {
  const test::TruthFrame& from = flight.truth[a];
  const test::TruthFrame& to = flight.truth[b];
  const Eigen::Vector3d world = to.position - from.position;
  const double c = std::cos(from.yaw), s = std::sin(from.yaw);
  vo_delta_t d = flight.deltas[b - 1];
  d.prev_utime = from.utime;
  d.utime = to.utime;
  d.dx = c * world.x() + s * world.y();
  d.dy = -s * world.x() + c * world.y();
  d.dz = world.z();
  d.dyaw = wrap_angle(to.yaw - from.yaw);
  d.altitude_m = flight.deltas[a].altitude_m;
  d.inliers = 200;
  d.quality = vo_delta_t::QUALITY_FRAME_GAP;
  return d;
}

// The flight with the texture lost over frames 100-240 and the coast ended
// by `across` (the delta from frame 100 to 241, as the tracker matched it).
SyntheticFlight bridged_by(const SyntheticFlight& flight, const vo_delta_t& across) {
  SyntheticFlight bridged = flight;
  lose_texture(&bridged, 100, 240);
  bridged.deltas[240] = across;
  return bridged;
}

// 10 s of texture loss through a turn while the climb changes (the held
// climb misses it); the first frame after it is matched with the last good
// one. That delta ends the coast: the filter goes back to the last good frame
// and integrates its climb and heading change with the coast's horizontal,
// so the height is where it would have been without the loss, the horizontal
// the coast's (bridge_horizontal coast). Without it (coast.bridge off) the
// coast's height error stays; with bridge_horizontal pair the delta's
// horizontal is taken too.
TEST(Coasting, ADeltaFromTheLastGoodFrameAcrossTheCoastEndsIt) {
  FlightSpec spec;  // turning at 6 deg/s, climbing
  spec.frames = 400;
  spec.climb_rate_change_s = 10.0;
  spec.climb_rate_after_mps = 3.0;
  SyntheticFlight flight = test::make_flight(spec);
  const SyntheticFlight bridged = bridged_by(flight, delta_between(flight, 100, 241));
  const Eigen::Vector3d origin = flight.truth.front().position;
  auto error = [&](const pose_t& p, size_t k) -> Eigen::Vector3d {
    return position(p) - (flight.truth[k].position - origin);
  };
  YawFusionCounters counters, coast_counters, whole_counters;
  YawFusionOptions coast_horizontal;
  coast_horizontal.coast.bridge_horizontal = BridgeHorizontal::kCoast;
  const auto poses = fly(bridged, coast_horizontal, &counters);
  YawFusionOptions no_bridge;
  no_bridge.coast.bridge = false;
  const auto coasted = fly(bridged, no_bridge, &coast_counters);
  YawFusionOptions whole;
  whole.coast.bridge_horizontal = BridgeHorizontal::kPair;
  const auto taken = fly(bridged, whole, &whole_counters);
  EXPECT_EQ(counters.coast_episodes, 1);
  EXPECT_EQ(counters.coasts_bridged, 1);
  EXPECT_EQ(counters.vo_deltas_invalid + counters.vo_deltas_late, 0);
  EXPECT_EQ(coast_counters.coasts_bridged, 0);
  EXPECT_EQ(coast_counters.vo_deltas_invalid, 1);  // longer than max_delta_interval_s, and nothing to bridge
  // The coast's poses were published, flagged; the bridged frame and all after it are not.
  for (size_t k = 101; k <= 240; ++k) {
    const pose_t* p = pose_at(poses, flight.truth[k].utime);
    ASSERT_NE(p, nullptr) << "frame " << k;
    EXPECT_TRUE(p->flags & pose_t::FLAG_COASTING) << "frame " << k;
  }
  const pose_t* first = pose_at(poses, flight.truth[241].utime);
  const pose_t* coast_end = pose_at(poses, flight.truth[240].utime);
  ASSERT_NE(first, nullptr);
  EXPECT_FALSE(first->flags & pose_t::FLAG_COASTING);
  const size_t last = flight.truth.size() - 1;
  // Noise-free: the height exact; the horizontal is what the coast flew (the
  // held velocity turned with the INS heading: within centimetres here).
  EXPECT_LT(std::abs(error(*first, 241).z()), 1e-6);
  EXPECT_LT(std::abs(error(poses.back(), last).z()), 1e-6);
  EXPECT_NEAR(error(*first, 241).head<2>().norm(), error(*coast_end, 240).head<2>().norm(), 0.05);
  EXPECT_LT(error(poses.back(), last).head<2>().norm(), 0.2);
  EXPECT_LT(error(taken.back(), last).norm(), 1e-6);
  // The held climb missed the 3 m/s, and without the bridge the error stays.
  EXPECT_GT(std::abs(error(*coast_end, 240).z()), 5.0);
  EXPECT_GT(std::abs(error(coasted.back(), last).z()), 5.0);
  // The vertical variance is the delta's again; the horizontal is the coast's.
  EXPECT_LT(first->position_covariance[2][2], 0.1 * coast_end->position_covariance[2][2]);
  EXPECT_GT(first->position_covariance[0][0], 0.9 * coast_end->position_covariance[0][0]);
  const pose_t* taken_first = pose_at(taken, flight.truth[241].utime);
  EXPECT_LT(taken_first->position_covariance[0][0], 0.1 * coast_end->position_covariance[0][0]);
}

// The heading swings about the track (1 deg over 20 s: neither the held
// velocity's 3 s window nor a 10 s coast averages it) and the pair across the
// coast is 6 % long (a single-plane solve over the strip at the images'
// edges can be). The coast's direction is off, the pair's length:
// bridge_horizontal pair_direction takes the coast's length along the pair's
// direction, with the coast's variance along it and the pair's across.
TEST(Coasting, ABridgeCanTakeThePairsDirectionWithTheCoastsLength) {
  FlightSpec spec = straight_spec();
  spec.heading_oscillation_deg = 1.0;
  spec.heading_oscillation_period_s = 20.0;
  SyntheticFlight flight = test::make_flight(spec);
  vo_delta_t across = delta_between(flight, 100, 241);
  across.dx *= 1.06;
  across.dy *= 1.06;
  const SyntheticFlight bridged = bridged_by(flight, across);
  const Eigen::Vector3d origin = flight.truth.front().position;
  auto horizontal_error = [&](const std::vector<pose_t>& poses, size_t k) {
    const pose_t* p = pose_at(poses, flight.truth[k].utime);
    EXPECT_NE(p, nullptr) << "frame " << k;
    return p ? (position(*p) - (flight.truth[k].position - origin)).head<2>().norm() : 1e9;
  };
  std::map<BridgeHorizontal, std::vector<pose_t>> flown;
  for (BridgeHorizontal source : {BridgeHorizontal::kCoast, BridgeHorizontal::kPair, BridgeHorizontal::kPairDirection}) {
    YawFusionOptions options;
    options.coast.bridge_horizontal = source;
    YawFusionCounters counters;
    flown[source] = fly(bridged, options, &counters);
    EXPECT_EQ(counters.coasts_bridged, 1);
  }
  const double span_m = (flight.truth[241].position - flight.truth[100].position).norm();
  EXPECT_GT(horizontal_error(flown[BridgeHorizontal::kCoast], 241), 0.005 * span_m);  // the swing, followed
  EXPECT_NEAR(horizontal_error(flown[BridgeHorizontal::kPair], 241), 0.06 * span_m, 0.01 * span_m);
  EXPECT_LT(horizontal_error(flown[BridgeHorizontal::kPairDirection], 241), 0.1);
  EXPECT_LT(horizontal_error(flown[BridgeHorizontal::kPairDirection], flight.truth.size() - 1), 0.1);
  // Its variance: the coast's along the track, the pair's across it.
  auto variance = [&](BridgeHorizontal source, size_t k, const Eigen::Vector2d& axis) {
    const pose_t* p = pose_at(flown[source], flight.truth[k].utime);
    Eigen::Matrix2d c;
    c << p->position_covariance[0][0], p->position_covariance[0][1], p->position_covariance[1][0],
        p->position_covariance[1][1];
    return axis.dot(c * axis);
  };
  const Eigen::Vector2d track = (flight.truth[241].position - flight.truth[100].position).head<2>().normalized();
  const Eigen::Vector2d side(-track.y(), track.x());
  EXPECT_NEAR(variance(BridgeHorizontal::kPairDirection, 241, track), variance(BridgeHorizontal::kCoast, 241, track),
              0.01 * variance(BridgeHorizontal::kCoast, 241, track));
  EXPECT_LT(variance(BridgeHorizontal::kPairDirection, 241, side), 0.1 * variance(BridgeHorizontal::kCoast, 241, side));
}

// The pair across the coast turned 0.5 deg too far and stepped sideways by
// that angle times 100 m (a strip of common ground 100 m from the nadir: a
// turn about the nadir and a sideways step move it alike), as its covariance
// says (dy and dyaw correlated through those 100 m). With the INS's heading
// change in place of its own the step is moved back with it, and the heading
// after the coast is the INS's.
TEST(Coasting, ABridgeTakesTheInsHeadingChangeAndMovesThePairsStepWithIt) {
  FlightSpec spec;  // turning at 6 deg/s
  spec.frames = 400;
  spec.reported_ins_yaw_stddev_deg = 0.05;
  SyntheticFlight flight = test::make_flight(spec);
  vo_delta_t across = delta_between(flight, 100, 241);
  const double error_rad = deg_to_rad(0.5), strip_m = 100.0, own_variance = std::pow(deg_to_rad(0.06), 2);
  across.dyaw += error_rad;
  across.dy += strip_m * error_rad;
  across.covariance[3][3] = own_variance;
  across.covariance[1][3] = across.covariance[3][1] = strip_m * own_variance;
  across.covariance[1][1] = strip_m * strip_m * own_variance + 0.01;
  const SyntheticFlight bridged = bridged_by(flight, across);
  const Eigen::Vector3d origin = flight.truth.front().position;
  YawFusionOptions pair_only;
  pair_only.coast.bridge_horizontal = BridgeHorizontal::kPair;
  YawFusionOptions own_heading = pair_only;
  own_heading.coast.bridge_heading_from_ins = false;
  const auto with_ins = fly(bridged, pair_only);
  const auto without = fly(bridged, own_heading);
  const pose_t* a = pose_at(with_ins, flight.truth[241].utime);
  const pose_t* b = pose_at(without, flight.truth[241].utime);
  ASSERT_NE(a, nullptr);
  ASSERT_NE(b, nullptr);
  const Eigen::Vector3d truth = flight.truth[241].position - origin;
  EXPECT_LT((position(*a) - truth).head<2>().norm(), 1e-3);
  EXPECT_NEAR((position(*b) - truth).head<2>().norm(), strip_m * error_rad, 0.1);
  EXPECT_LT(std::abs(wrap_angle(a->yaw - flight.truth[241].yaw)), deg_to_rad(0.01));
  EXPECT_GT(std::abs(wrap_angle(b->yaw - flight.truth[241].yaw)), deg_to_rad(0.1));
  // The step's variance across: what the heading did not explain, plus the INS's turn times 100 m.
  const double ins_turn_variance = 2.0 * std::pow(deg_to_rad(0.05), 2);
  EXPECT_GT(a->position_covariance[0][0] + a->position_covariance[1][1],
            strip_m * strip_m * ins_turn_variance * 0.5);
}

// A 30 m terrain step (a cliff) under the beam while coasting on the
// altimeter is the ground's, not a climb: the plane moves, the height stays.
TEST(Coasting, AGroundStepWhileFollowingTheAltimeterMovesThePlane) {
  FlightSpec spec = straight_spec();
  spec.terrain_step_m = 30.0;
  spec.terrain_step_frame = 170;
  SyntheticFlight flight = test::make_flight(spec);
  lose_texture(&flight, 100, 240);
  YawFusionCounters counters;
  YawFusionOptions options;
  options.coast.follow_altimeter = true;
  const auto poses = fly(flight, options, &counters);
  EXPECT_EQ(counters.coast_ground_steps, 1);
  const Eigen::Vector3d origin = flight.truth.front().position;
  for (size_t k = 101; k < flight.truth.size(); ++k) {
    const pose_t* p = pose_at(poses, flight.truth[k].utime);
    ASSERT_NE(p, nullptr) << "frame " << k;
    EXPECT_NEAR(p->position_ned[2], flight.truth[k].position.z() - origin.z(), 0.3) << "frame " << k;
  }
}

TEST(Coasting, CleanFlightNeverCoasts) {
  FlightSpec spec;
  spec.frames = 600;
  spec.translation_stddev_m = 0.05;
  spec.dz_stddev_m = 0.05;
  spec.dyaw_stddev_deg = 0.02;
  spec.ins_yaw_stddev_deg = 0.3;
  YawFusionCounters counters;
  const auto poses = fly(test::make_flight(spec), YawFusionOptions{}, &counters);
  EXPECT_EQ(counters.vo_deltas_coasted, 0);
  for (const pose_t& p : poses) EXPECT_FALSE(p.flags & pose_t::FLAG_COASTING);
}

bool pose_finite(const pose_t& p) {
  bool ok = std::isfinite(p.roll) && std::isfinite(p.pitch) && std::isfinite(p.yaw) && std::isfinite(p.height_agl_m) &&
            std::isfinite(p.yaw_variance);
  for (int i = 0; i < 3; ++i) {
    ok = ok && std::isfinite(p.position_ned[i]) && std::isfinite(p.velocity_ned[i]);
    for (int j = 0; j < 3; ++j) ok = ok && std::isfinite(p.position_covariance[i][j]);
  }
  return ok;
}

// Degenerate VO_DELTAs: huge, zero, negative, non-finite covariances and
// values, every quality bit, time jumps back and forth: every POSE field
// stays finite, and poses of deltas not integrated are flagged.
TEST(YawFusionFuzz, DegenerateDeltasNeverPublishNonFinitePoses) {
  const double kBad[] = {0.0,  -1.0, 1e-300, 1e300, -1e300, std::numeric_limits<double>::infinity(),
                         std::numeric_limits<double>::quiet_NaN(), 1e12, 1e155, 1.0};
  int64_t reverted = 0;
  for (uint32_t seed = 1; seed <= 6; ++seed) {
    FlightSpec spec;
    spec.frames = 400;
    spec.seed = seed;
    SyntheticFlight flight = test::make_flight(spec);
    std::mt19937 rng(seed);
    std::uniform_int_distribution<int> pick(0, static_cast<int>(std::size(kBad)) - 1);
    std::uniform_int_distribution<int> what(0, 9);
    std::set<int64_t> corrupted;
    for (size_t k = 20; k < flight.deltas.size(); ++k) {
      vo_delta_t& d = flight.deltas[k];
      const int w = what(rng);
      if (w > 5) continue;
      corrupted.insert(d.utime);
      if (w == 0) {
        for (int r = 0; r < 6; ++r)
          for (int c = 0; c < 6; ++c) d.covariance[r][c] = kBad[pick(rng)];
      } else if (w == 1) {
        const double v = kBad[pick(rng)];
        for (int r = 0; r < 6; ++r) d.covariance[r][r] = v;
      } else if (w == 2) {
        d.dx = kBad[pick(rng)];
        d.dz = kBad[pick(rng)];
        d.dyaw = kBad[pick(rng)];
      } else if (w == 3) {
        d.quality = 0xff;
      } else if (w == 4) {
        d.altitude_m = kBad[pick(rng)];
        d.inliers = (k % 2) ? 0 : -5;
      } else {
        d.utime += (k % 2) ? 3'600'000'000LL : -50'000;  // a jump ahead, a step back
      }
    }
    YawFusionCounters counters;
    const auto poses = fly(flight, YawFusionOptions{}, &counters);
    ASSERT_GT(poses.size(), 100u) << "seed " << seed;
    for (const pose_t& p : poses) {
      EXPECT_TRUE(pose_finite(p)) << "seed " << seed << " utime " << p.utime;
      EXPECT_GE(p.height_agl_m, -1.0);
    }
    EXPECT_GT(counters.vo_deltas_invalid + counters.vo_deltas_coasted + counters.vo_deltas_quality_rejected, 0);
    reverted += counters.deltas_reverted;
  }
  EXPECT_GT(reverted, 0);  // finite values that overflow the state were met and undone
}

TEST(CoastOptions, ConfigErrorsNameTheKey) {
  const Config bad = Config::parse("yaw_fusion:\n  coast: {inlier_drop_fraction: 2}\n", "test.yaml");
  try {
    YawFusionOptions::from_config(bad);
    FAIL() << "no error";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("inlier_drop_fraction"), std::string::npos) << e.what();
  }
  try {
    YawFusionOptions::from_config(Config::parse("yaw_fusion:\n  coast: {terrain_window_s: -1}\n", "test.yaml"));
    FAIL() << "no error";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("yaw_fusion.coast.terrain_window_s"), std::string::npos) << e.what();
  }
  const Config ok = Config::parse("yaw_fusion:\n  coast: {enabled: false, max_duration_s: 12}\n", "test.yaml");
  const YawFusionOptions o = YawFusionOptions::from_config(ok);
  EXPECT_FALSE(o.coast.enabled);
  EXPECT_EQ(o.coast.max_duration_s, 12.0);
  const Config root = Config::load_file(std::string(NADIR_SOURCE_DIR) + "/config/default.yaml");
  const YawFusionOptions d = YawFusionOptions::from_config(root);
  EXPECT_TRUE(d.coast.enabled);
  EXPECT_EQ(d.coast.quality_mask, CoastOptions{}.quality_mask);
  EXPECT_EQ(d.coast.max_duration_s, CoastOptions{}.max_duration_s);
}

}  // namespace
}  // namespace nadir
