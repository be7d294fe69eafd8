#pragma once
// Synthetic flights with known truth for the yaw fusion tests: a vehicle flying
// straight and turning (heading crossing +-180 deg), climbing, over level
// ground; INS at 100 Hz, altimeter at 20 Hz, camera frames at ~14 Hz with
// trigger jitter, and the VO deltas a perfect solver would give (plus optional
// noise). Attitude is piecewise linear in time with breakpoints on the INS
// sample grid, so interpolating the INS at a frame time is exact.

#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "nadir/altimeter_t.hpp"
#include "nadir/ground_points_t.hpp"
#include "nadir/ins_t.hpp"
#include "nadir/vo_delta_t.hpp"

namespace nadir::test {

struct FlightSpec {
  int frames = 300;
  double speed_mps = 30.0;
  double climb_rate_mps = 1.0;          // up
  double initial_yaw_deg = 170.0;
  double turn_rate_dps = 6.0;           // during turns
  double height_agl_m = 300.0;          // at the start, level terrain
  double ins_yaw_stddev_deg = 0.0;      // noise on INS yaw
  double reported_ins_yaw_stddev_deg = 0.3;  // what the INS says
  double dyaw_stddev_deg = 0.0;         // noise on VO dyaw
  double translation_stddev_m = 0.0;    // noise on VO dx, dy
  double dz_bias_m = 0.0;               // added to every VO dz
  double dz_stddev_m = 0.0;
  double covariance_translation_stddev_m = 0.05;  // what the solver reports
  double covariance_dyaw_stddev_deg = 0.05;
  double terrain_step_m = 0.0;          // terrain rises this much at terrain_step_frame
  int terrain_step_frame = -1;
  // Terrain down coordinate changes by this much per metre north and east (a
  // plane; the deltas carry its tilt as ground_roll/ground_pitch).
  double terrain_gradient_north = 0.0;
  double terrain_gradient_east = 0.0;
  // A swell on top of the plane: the ground's down moves by
  // terrain_wave_m * sin(2 pi north / terrain_wave_length_m) (the deltas' ground tilt does not show it).
  double terrain_wave_m = 0.0;
  double terrain_wave_length_m = 400.0;
  // Each frame's ground points (VO_GROUND, as the feature_depth solver would
  // publish them): a 10 m grid from 100 m behind to ground_points_ahead_m
  // ahead and 60 m either side, exact, with ground_points_sigma_m reported.
  bool ground_points = false;
  // The altimeter's range to where its tilted beam hits the ground (the
  // simulator's ray cast); false: the height below the vehicle over the beam's cosine.
  bool altimeter_along_beam = false;
  double range_stddev_m = 0.0;          // white noise on each range (its own random stream)
  double ground_points_ahead_m = 200.0;
  double ground_points_sigma_m = 0.5;
  double climb_rate_change_s = -1.0;    // from this flight time on (>= 0) the climb rate is ...
  double climb_rate_after_mps = 0.0;    // ... this
  // The heading (truth, INS and the frames the deltas are measured in)
  // oscillates about the track by this amplitude with this period; the
  // track does not follow it (sideslip, a helicopter's yaw wander).
  double heading_oscillation_deg = 0.0;
  double heading_oscillation_period_s = 3.0;
  double ins_yaw_bias_deg = 0.0;        // added to every INS yaw (a heading bias the INS does not report)
  uint32_t seed = 7;
};

struct TruthFrame {
  int64_t utime;
  Eigen::Vector3d position;  // NED, metres
  double yaw;
  double roll;
  double pitch;
};

// Messages on their own channel with their sensor times.
struct TimedMessage {
  std::string channel;
  int64_t utime;
  std::vector<uint8_t> bytes;
};

struct SyntheticFlight {
  std::vector<TruthFrame> truth;  // one per frame; deltas[k] goes from truth[k] to truth[k+1]
  std::vector<vo_delta_t> deltas;
  std::vector<ins_t> ins;
  std::vector<altimeter_t> altimeter;
  std::vector<ground_points_t> ground;  // with FlightSpec::ground_points, one per frame from the second
};

SyntheticFlight make_flight(const FlightSpec& spec);

// All messages ordered by arrival: sensor time plus a per-channel latency
// (and a per-message jitter from `seed` when nonzero) -- different values give
// different interleavings of the same messages.
std::vector<TimedMessage> arrival_order(const SyntheticFlight& flight, int64_t vo_latency_us, int64_t ins_latency_us,
                                        int64_t altimeter_latency_us, uint32_t jitter_seed = 0,
                                        int64_t jitter_us = 0);

template <class Msg>
std::vector<uint8_t> encode(const Msg& msg) {
  std::vector<uint8_t> bytes(static_cast<size_t>(msg.getEncodedSize()));
  msg.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
  return bytes;
}

}  // namespace nadir::test
