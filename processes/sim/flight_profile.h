#pragma once
// Flight profiles (YAML files under config/profiles/) and the smooth,
// helicopter-like trajectory they describe: straight legs, banked turns with
// a raised-cosine turn rate (coordinated bank = atan(V * yaw_rate / g)),
// climbs and descents with a raised-cosine vertical speed, and small seeded
// roll/pitch/yaw oscillations. Horizontal speed is constant.

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "common/config.h"
#include "processes/sim/terrain.h"

namespace nadir::sim {

struct FlightLeg {
  enum Type { kStraight, kTurn, kClimb } type = kStraight;
  double distance_m = -1.0;  // straight/climb; < 0 on one straight leg: the rest of distance_m
  double angle_deg = 0.0;    // turn: positive = right (clockwise seen from above)
  double bank_deg = 15.0;    // turn: peak bank
  double delta_alt_m = 0.0;  // climb (negative: descent)
};

struct FlightProfile {
  std::string name;
  std::string source;          // file it came from
  std::string yaml;            // its text, for CONFIG
  double distance_m = 1000.0;  // total horizontal path length
  double speed_mps = 20.0;
  double altitude_agl_m = 200.0;  // above the terrain at the start point (the datum)
  double initial_heading_deg = 0.0;
  double pitch_trim_deg = -2.0;
  double roll_oscillation_deg = 0.8;  // RMS of the small attitude oscillations
  double pitch_oscillation_deg = 0.6;
  double yaw_oscillation_deg = 0.4;
  double reference_latitude_deg = 40.4406;
  double reference_longitude_deg = -79.9959;
  double reference_height_m = 300.0;  // ellipsoidal height of the datum
  TerrainOptions terrain;
  // world: {orthophoto: FILE, dem: FILE}: a real place instead of the
  // procedural world (tools/map/raster_ground.h opens it; the profile itself
  // only keeps the paths, resolved against the profile file's folder). Both
  // empty: the procedural world. With a world, reference.latitude_deg and
  // longitude_deg are required and reference.height_m is refused: the datum
  // is the DEM's height at the reference point.
  std::string world_orthophoto;
  std::string world_dem;
  bool has_world() const { return !world_dem.empty(); }
  std::vector<FlightLeg> legs;
  // Keys changed after loading (e.g. "terrain.relief_scale"), for CONFIG.
  std::vector<std::string> overrides;

  // Parses and checks a profile; errors name the file and key (legs[2].angle_deg).
  static FlightProfile load(const std::string& path);
  static FlightProfile parse(const std::string& yaml_text, const std::string& source);
  // NAME -> <checkout>/config/profiles/NAME.yaml; anything with '/' or '.yaml' is a path.
  static std::string resolve(const std::string& name_or_path);
  // Replaces terrain.relief_scale (the same flight over other relief): the
  // YAML text follows, and the key is listed in `overrides`. Throws
  // ConfigError naming the key when outside [0, 3].
  void override_relief_scale(double relief_scale);
  // Replaces altitude_agl_m (the same flight shifted up or down: every climb
  // and turn as before), recorded the same way; e.g. flat ground flown at the
  // height a relief flight has above its ground. Throws ConfigError naming
  // the key outside [30, 3000].
  void override_altitude_agl(double altitude_agl_m);
};

struct TruthState {
  double t = 0.0;  // seconds since start
  Eigen::Vector3d position_ned = Eigen::Vector3d::Zero();
  Eigen::Vector3d velocity_ned = Eigen::Vector3d::Zero();
  double roll = 0, pitch = 0, yaw = 0;
  Eigen::Vector3d angular_rate_body = Eigen::Vector3d::Zero();
  Eigen::Matrix3d world_from_body() const;
};

class Trajectory {
 public:
  Trajectory(const FlightProfile& profile, uint64_t seed);
  double duration_s() const { return duration_; }
  TruthState at(double t) const;

 private:
  struct LegSpan {
    FlightLeg::Type type;
    double t0, duration;
    double heading0, altitude0;
    double turn_angle;  // rad
    double delta_alt;
  };
  struct Sinusoid {
    double amplitude, omega, phase;
  };
  const LegSpan& leg_at(double t) const;
  double heading(double t, double* rate) const;
  double altitude(double t, double* climb_rate) const;
  Eigen::Vector2d horizontal_velocity(double t) const;
  Eigen::Vector2d integrate(double t0, double t1) const;
  void attitude(double t, double* roll, double* pitch, double* yaw) const;
  static double oscillation(const std::vector<Sinusoid>& s, double t);

  double speed_ = 0.0, duration_ = 0.0, pitch_trim_ = 0.0;
  std::vector<LegSpan> legs_;
  std::vector<Sinusoid> roll_osc_, pitch_osc_, yaw_osc_;
  double key_dt_ = 0.1;
  std::vector<Eigen::Vector2d> keys_;  // horizontal position every key_dt_
};

}  // namespace nadir::sim
