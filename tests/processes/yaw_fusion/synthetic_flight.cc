#include "synthetic_flight.h"

#include <algorithm>
#include <cmath>
#include <tuple>

#include "common/channels.h"
#include "common/geometry.h"

namespace nadir::test {

namespace {

constexpr int64_t kStartUs = 1'700'000'000'000'000;
constexpr int64_t kInsPeriodUs = 10'000;
constexpr int64_t kAltimeterPeriodUs = 50'000;
constexpr int64_t kFramePeriodUs = 71'429;

// Yaw rate (rad/s) and bank over a schedule: straight, right turn, straight,
// left turn, repeating every 60 s. Changes happen on the INS grid.
double yaw_rate(const FlightSpec& spec, double t) {
  const double phase = std::fmod(t, 60.0);
  if (phase >= 10.0 && phase < 25.0) return deg_to_rad(spec.turn_rate_dps);
  if (phase >= 35.0 && phase < 50.0) return -deg_to_rad(spec.turn_rate_dps);
  return 0.0;
}

struct State {
  double yaw;
  Eigen::Vector3d position;
};

}  // namespace

SyntheticFlight make_flight(const FlightSpec& spec) {
  SyntheticFlight flight;
  std::mt19937 rng(spec.seed);
  std::mt19937 range_rng(spec.seed + 1000003u);
  std::normal_distribution<double> normal(0.0, 1.0);

  std::vector<int64_t> frame_times;
  for (int k = 0; k < spec.frames; ++k) {
    // Trigger jitter up to 0.5 ms, deterministic.
    frame_times.push_back(kStartUs + 500'000 + k * kFramePeriodUs + (k * 37) % 500);
  }
  const int64_t end_us = frame_times.back() + 300'000;  // less than ins_wait_s: no trailing gap poses

  // Integrate the trajectory at 1 ms; yaw is exactly linear between 10 ms
  // grid points because the rate only changes at whole seconds.
  State state{deg_to_rad(spec.initial_yaw_deg), Eigen::Vector3d::Zero()};
  auto roll_at = [&](double t) { return 0.02 * std::sin(0.7 * t) + 0.3 * yaw_rate(spec, t); };
  auto pitch_at = [&](double t) { return 0.03 + 0.01 * std::cos(0.5 * t); };
  // state.yaw is the track; the heading oscillates about it.
  auto heading_at = [&](double t) {
    return state.yaw + deg_to_rad(spec.heading_oscillation_deg) *
                           std::sin(2.0 * M_PI * t / spec.heading_oscillation_period_s);
  };
  size_t next_frame = 0;
  int64_t next_ins = kStartUs;
  int64_t next_alt = kStartUs;
  double terrain_down = spec.height_agl_m;
  const Eigen::Vector2d terrain_gradient(spec.terrain_gradient_north, spec.terrain_gradient_east);
  // The ground's down coordinate below a horizontal position (the step aside).
  auto ground_relief = [&](const Eigen::Vector2d& p) {
    return terrain_gradient.dot(p) + spec.terrain_wave_m * std::sin(2.0 * M_PI * p.x() / spec.terrain_wave_length_m);
  };
  std::vector<double> terrain_down_at_frame;
  int64_t t_us = kStartUs;
  while (t_us <= end_us) {
    const double t = static_cast<double>(t_us - kStartUs) * 1e-6;
    if (next_frame < frame_times.size() && t_us == frame_times[next_frame]) {
      flight.truth.push_back({t_us, state.position, wrap_angle(heading_at(t)), roll_at(t), pitch_at(t)});
      if (static_cast<int>(next_frame) == spec.terrain_step_frame) terrain_down -= spec.terrain_step_m;
      terrain_down_at_frame.push_back(terrain_down);
      ++next_frame;
    }
    // Attitude samples are piecewise linear between INS grid points: roll and
    // pitch are evaluated on the grid and the INS gives exactly those.
    if (t_us == next_ins) {
      ins_t ins{};
      ins.utime = t_us;
      ins.device_utime = t_us;
      ins.roll = roll_at(t);
      ins.pitch = pitch_at(t);
      ins.yaw = wrap_angle(heading_at(t) + deg_to_rad(spec.ins_yaw_bias_deg) +
                           deg_to_rad(spec.ins_yaw_stddev_deg) * normal(rng));
      ins.has_stddev = true;
      ins.attitude_stddev[0] = ins.attitude_stddev[1] = deg_to_rad(0.05);
      ins.attitude_stddev[2] = deg_to_rad(spec.reported_ins_yaw_stddev_deg);
      ins.flags = ins_t::FLAG_ALIGNED | ins_t::FLAG_SOLUTION_GOOD | ins_t::FLAG_SIMULATED;
      flight.ins.push_back(ins);
      next_ins += kInsPeriodUs;
    }
    if (t_us == next_alt) {
      altimeter_t alt{};
      alt.utime = t_us;
      alt.beam_body[2] = 1.0;
      const double agl = terrain_down + ground_relief(state.position.head<2>()) - state.position.z();
      const Eigen::Vector3d beam = rotation_from_rpy(roll_at(t), pitch_at(t), 0.0) * Eigen::Vector3d::UnitZ();
      alt.range_m = agl / beam.z();
      if (spec.altimeter_along_beam) {
        const Eigen::Vector3d world_beam = rotation_from_rpy(0.0, 0.0, heading_at(t)) * beam;
        for (int iteration = 0; iteration < 20; ++iteration) {
          const Eigen::Vector2d spot = state.position.head<2>() + alt.range_m * world_beam.head<2>();
          alt.range_m = (terrain_down + ground_relief(spot) - state.position.z()) / world_beam.z();
        }
      }
      if (spec.range_stddev_m > 0.0) alt.range_m += spec.range_stddev_m * normal(range_rng);
      alt.signal_quality = 1.0f;
      alt.validity = altimeter_t::VALID_OK;
      flight.altimeter.push_back(alt);
      next_alt += kAltimeterPeriodUs;
    }
    // Step to the next event or 1 ms grid point (the yaw rate only changes
    // on whole seconds, which are grid points).
    int64_t next = (t_us / 1000 + 1) * 1000;
    if (next_frame < frame_times.size()) next = std::min(next, frame_times[next_frame]);
    next = std::min({next, next_ins, next_alt});
    const double dt = static_cast<double>(next - t_us) * 1e-6;
    const double rate = yaw_rate(spec, t);
    const double climb =
        spec.climb_rate_change_s >= 0.0 && t >= spec.climb_rate_change_s ? spec.climb_rate_after_mps : spec.climb_rate_mps;
    state.position += dt * Eigen::Vector3d(spec.speed_mps * std::cos(state.yaw), spec.speed_mps * std::sin(state.yaw),
                                           -climb);
    state.yaw += rate * dt;
    t_us = next;
  }
  // Roll/pitch of the truth frames are the INS values interpolated at frame
  // time (what the estimator reports).
  for (TruthFrame& frame : flight.truth) {
    const auto after = std::lower_bound(flight.ins.begin(), flight.ins.end(), frame.utime,
                                        [](const ins_t& s, int64_t u) { return s.utime < u; });
    const auto before = std::prev(after);
    const double f = static_cast<double>(frame.utime - before->utime) / static_cast<double>(after->utime - before->utime);
    frame.roll = before->roll + f * (after->roll - before->roll);
    frame.pitch = before->pitch + f * (after->pitch - before->pitch);
  }

  for (size_t k = 1; k < flight.truth.size(); ++k) {
    const TruthFrame& a = flight.truth[k - 1];
    const TruthFrame& b = flight.truth[k];
    const Eigen::Vector3d world = b.position - a.position;
    const double c = std::cos(a.yaw);
    const double s = std::sin(a.yaw);
    vo_delta_t d{};
    d.utime = b.utime;
    d.prev_utime = a.utime;
    d.dx = c * world.x() + s * world.y() + spec.translation_stddev_m * normal(rng);
    d.dy = -s * world.x() + c * world.y() + spec.translation_stddev_m * normal(rng);
    d.dz = world.z() + spec.dz_bias_m + spec.dz_stddev_m * normal(rng);
    d.dyaw = wrap_angle(b.yaw - a.yaw) + deg_to_rad(spec.dyaw_stddev_deg) * normal(rng);
    const double st = spec.covariance_translation_stddev_m;
    d.covariance[0][0] = d.covariance[1][1] = d.covariance[2][2] = st * st;
    d.covariance[3][3] = std::pow(deg_to_rad(spec.covariance_dyaw_stddev_deg), 2);
    d.covariance[4][4] = d.covariance[5][5] = std::pow(deg_to_rad(0.5), 2);
    d.altitude_m = spec.height_agl_m + ground_relief(a.position.head<2>()) - a.position.z();
    // The terrain plane in the level frame of frame b (x forward, y right):
    // down changes by `forward` per metre ahead and `right` per metre right;
    // its normal (-forward, -right, 1) as the solver's ground roll/pitch.
    const double forward = std::cos(b.yaw) * terrain_gradient.x() + std::sin(b.yaw) * terrain_gradient.y();
    const double right = -std::sin(b.yaw) * terrain_gradient.x() + std::cos(b.yaw) * terrain_gradient.y();
    d.ground_pitch = std::atan2(-forward, 1.0);
    d.ground_roll = std::atan2(right, std::hypot(forward, 1.0));
    d.inliers = 300;
    d.residual_rms_px = 0.3;
    d.iterations = 4;
    d.quality = 0;
    d.variant = "synthetic";
    flight.deltas.push_back(d);
    if (!spec.ground_points) continue;
    ground_points_t g{};
    g.utime = b.utime;
    const double cb = std::cos(b.yaw), sb = std::sin(b.yaw);
    for (double x = -100.0; x <= spec.ground_points_ahead_m + 1e-9; x += 10.0) {
      for (double y = -60.0; y <= 60.0 + 1e-9; y += 10.0) {
        const Eigen::Vector2d world = b.position.head<2>() + Eigen::Vector2d(cb * x - sb * y, sb * x + cb * y);
        const double z = terrain_down_at_frame[k] + ground_relief(world) - b.position.z();
        g.track_id.push_back(static_cast<int64_t>(k) * 100000 + static_cast<int64_t>(g.track_id.size()));
        g.position_m.push_back({static_cast<float>(x), static_cast<float>(y), static_cast<float>(z)});
        g.depth_sigma_m.push_back(static_cast<float>(spec.ground_points_sigma_m));
      }
    }
    g.num_points = static_cast<int32_t>(g.position_m.size());
    flight.ground.push_back(std::move(g));
  }
  return flight;
}

std::vector<TimedMessage> arrival_order(const SyntheticFlight& flight, int64_t vo_latency_us, int64_t ins_latency_us,
                                        int64_t altimeter_latency_us, uint32_t jitter_seed, int64_t jitter_us) {
  std::mt19937 rng(jitter_seed);
  std::uniform_int_distribution<int64_t> jitter(0, std::max<int64_t>(0, jitter_us));
  // (arrival time, channel rank, sequence) keeps each channel in its own order.
  std::vector<std::tuple<int64_t, int, size_t, TimedMessage>> all;
  auto add = [&](const std::string& channel, int rank, int64_t utime, int64_t latency, std::vector<uint8_t> bytes,
                 int64_t* last_arrival) {
    int64_t arrival = utime + latency + (jitter_us > 0 ? jitter(rng) : 0);
    arrival = std::max(arrival, *last_arrival);  // one producer per channel: in order
    *last_arrival = arrival;
    all.emplace_back(arrival, rank, all.size(), TimedMessage{channel, utime, std::move(bytes)});
  };
  int64_t last_vo = 0, last_ins = 0, last_alt = 0, last_ground = 0;
  // A frame's ground points are published just before its delta (vo_solver).
  for (const auto& g : flight.ground) add(channels::kVoGround, 0, g.utime, vo_latency_us, encode(g), &last_ground);
  for (const auto& d : flight.deltas) add(channels::kVoDelta, 0, d.utime, vo_latency_us, encode(d), &last_vo);
  for (const auto& m : flight.ins) add(channels::kIns, 1, m.utime, ins_latency_us, encode(m), &last_ins);
  for (const auto& m : flight.altimeter) add(channels::kAltimeter, 2, m.utime, altimeter_latency_us, encode(m), &last_alt);
  std::sort(all.begin(), all.end(), [](const auto& a, const auto& b) {
    return std::tie(std::get<0>(a), std::get<1>(a), std::get<2>(a)) < std::tie(std::get<0>(b), std::get<1>(b), std::get<2>(b));
  });
  std::vector<TimedMessage> out;
  out.reserve(all.size());
  for (auto& entry : all) out.push_back(std::move(std::get<3>(entry)));
  return out;
}

}  // namespace nadir::test
