// Profiles fly what their YAML says: distance, speed, height above ground,
// with smooth helicopter-like attitude; bad profiles name the key.
#include <gtest/gtest.h>

#include <cmath>

#include "processes/sim/flight_profile.h"
#include "processes/sim/sim_rotation.h"
#include "processes/sim/terrain.h"
#include "sim_test_support.h"

namespace nadir::sim {
namespace {

struct Expected {
  const char* name;
  double distance_m, agl_m, speed_mps;
  double mean_agl_tolerance = 0.12;  // fraction of agl_m; the rough profiles climb over rising ground
};

class ProfileFlight : public ::testing::TestWithParam<Expected> {};

TEST_P(ProfileFlight, MatchesItsYaml) {
  const Expected x = GetParam();
  const FlightProfile p = testing::profile(x.name);
  // The YAML says what the paper's Table 1 says.
  EXPECT_EQ(p.name, x.name);
  EXPECT_DOUBLE_EQ(p.distance_m, x.distance_m);
  EXPECT_DOUBLE_EQ(p.altitude_agl_m, x.agl_m);
  EXPECT_DOUBLE_EQ(p.speed_mps, x.speed_mps);

  const Trajectory traj(p, 1);
  TerrainOptions terrain_options = p.terrain;
  terrain_options.seed = 1;
  const Terrain terrain(terrain_options);
  EXPECT_NEAR(traj.duration_s(), x.distance_m / x.speed_mps, 1e-6);

  // Path length by summing 0.05 s chords (independent of the integrator's step).
  double length = 0, agl_sum = 0, max_roll = 0, max_pitch_rate = 0;
  int n = 0;
  TruthState prev = traj.at(0.0);
  EXPECT_NEAR(prev.position_ned.head<2>().norm(), 0.0, 1e-9);
  EXPECT_NEAR(-prev.position_ned.z() - terrain.height(0, 0), x.agl_m, 1e-9);
  for (double t = 0.05; t <= traj.duration_s() + 1e-9; t += 0.05) {
    const TruthState s = traj.at(t);
    length += std::hypot(s.position_ned.x() - prev.position_ned.x(), s.position_ned.y() - prev.position_ned.y());
    EXPECT_NEAR(std::hypot(s.velocity_ned.x(), s.velocity_ned.y()), x.speed_mps, 1e-9);
    // Velocity is the derivative of position (central difference).
    const Eigen::Vector3d numeric = (traj.at(t + 1e-3).position_ned - traj.at(t - 1e-3).position_ned) / 2e-3;
    EXPECT_LT((numeric - s.velocity_ned).norm(), 1e-3) << "t = " << t;
    agl_sum += -s.position_ned.z() - terrain.height(s.position_ned.x(), s.position_ned.y());
    max_roll = std::max(max_roll, std::fabs(s.roll));
    max_pitch_rate = std::max(max_pitch_rate, std::fabs(s.angular_rate_body.y()));
    ++n;
    prev = s;
  }
  EXPECT_NEAR(length, x.distance_m, 1e-3 * x.distance_m);
  EXPECT_NEAR(agl_sum / n, x.agl_m, x.mean_agl_tolerance * x.agl_m);
  EXPECT_GT(rad2deg(max_roll), 5.0);   // banked turns
  EXPECT_LT(rad2deg(max_roll), 20.0);  // helicopter-like
  EXPECT_LT(rad2deg(max_pitch_rate), 5.0);
}

INSTANTIATE_TEST_SUITE_P(Table1, ProfileFlight,
                         ::testing::Values(Expected{"test1", 7800, 300, 30}, Expected{"test2", 3700, 150, 20},
                                           Expected{"test3", 4500, 200, 20}, Expected{"demo", 1200, 200, 20},
                                           Expected{"rough_120", 5000, 120, 20, 0.3},
                                           Expected{"rough_250", 5000, 250, 25, 0.3}),
                         [](const auto& info) { return std::string(info.param.name); });

// The rough profiles fly low over the steepest relief: with every
// seed the rough study uses, the aircraft stays well clear of the ground
// (at least half its nominal height above the terrain below it).
TEST(RoughProfiles, KeepClearOfTheRidges) {
  for (const char* name : {"rough_120", "rough_250"}) {
    const FlightProfile p = testing::profile(name);
    EXPECT_GE(p.terrain.relief_scale, 2.0) << name;
    for (uint64_t seed : {1, 2, 3}) {
      const Trajectory traj(p, seed);
      TerrainOptions terrain_options = p.terrain;
      terrain_options.seed = seed;
      const Terrain terrain(terrain_options);
      double min_agl = 1e9, max_agl = -1e9;
      for (double t = 0.0; t <= traj.duration_s(); t += 0.1) {
        const TruthState s = traj.at(t);
        const double agl = -s.position_ned.z() - terrain.height(s.position_ned.x(), s.position_ned.y());
        min_agl = std::min(min_agl, agl);
        max_agl = std::max(max_agl, agl);
      }
      EXPECT_GT(min_agl, 0.5 * p.altitude_agl_m) << name << " seed " << seed;
      EXPECT_GT(max_agl - min_agl, 40.0) << name << " seed " << seed;  // relief and climbs are really there
    }
  }
}

// --relief-scale: the same flight over other relief, and CONFIG says so.
TEST(RoughProfiles, ReliefOverrideKeepsTheFlight) {
  FlightProfile p = testing::profile("rough_120");
  const Trajectory rough(p, 2);
  p.override_relief_scale(0.0);
  EXPECT_EQ(p.terrain.relief_scale, 0.0);
  ASSERT_EQ(p.overrides.size(), 1u);
  EXPECT_EQ(p.overrides[0], "terrain.relief_scale");
  const FlightProfile reparsed = FlightProfile::parse(p.yaml, "override");
  EXPECT_EQ(reparsed.terrain.relief_scale, 0.0);
  EXPECT_EQ(reparsed.name, "rough_120");
  EXPECT_EQ(reparsed.legs.size(), p.legs.size());
  const Trajectory flat(p, 2);
  for (double t = 0.0; t < rough.duration_s(); t += 7.3)
    EXPECT_EQ((rough.at(t).position_ned - flat.at(t).position_ned).norm(), 0.0) << "t = " << t;
  try {
    p.override_relief_scale(3.5);
    FAIL() << "relief 3.5 accepted";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("terrain.relief_scale"), std::string::npos) << e.what();
  }
}

// --altitude-agl-m: the same flight shifted down by the change, and CONFIG says so.
TEST(RoughProfiles, AltitudeOverrideShiftsTheFlightAndNothingElse) {
  FlightProfile p = testing::profile("rough_120");
  const Trajectory original(p, 2);
  p.override_relief_scale(0.0);
  p.override_altitude_agl(59.0);
  EXPECT_EQ(p.altitude_agl_m, 59.0);
  ASSERT_EQ(p.overrides.size(), 2u);
  EXPECT_EQ(p.overrides[1], "altitude_agl_m");
  const FlightProfile reparsed = FlightProfile::parse(p.yaml, "override");
  EXPECT_EQ(reparsed.altitude_agl_m, 59.0);
  EXPECT_EQ(reparsed.terrain.relief_scale, 0.0);
  const Trajectory lower(p, 2);
  for (double t = 0.0; t < original.duration_s(); t += 7.3) {
    const TruthState a = original.at(t), b = lower.at(t);
    EXPECT_EQ(a.position_ned.x(), b.position_ned.x()) << "t = " << t;
    EXPECT_EQ(a.position_ned.y(), b.position_ned.y()) << "t = " << t;
    EXPECT_NEAR(b.position_ned.z() - a.position_ned.z(), 120.0 - 59.0, 1e-9) << "t = " << t;
    EXPECT_EQ(a.yaw, b.yaw) << "t = " << t;
    EXPECT_EQ(a.roll, b.roll) << "t = " << t;
  }
  try {
    p.override_altitude_agl(20.0);
    FAIL() << "20 m accepted";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("altitude_agl_m"), std::string::npos) << e.what();
  }
}

TEST(ProfileAttitude, YawFollowsTheTrackAndRollFollowsTheTurn) {
  const FlightProfile p = testing::profile("test1");
  const Trajectory traj(p, 2);
  for (double t = 1.0; t < traj.duration_s(); t += 3.3) {
    const TruthState s = traj.at(t);
    const double track = std::atan2(s.velocity_ned.y(), s.velocity_ned.x());
    EXPECT_LT(std::fabs(wrap_pi(s.yaw - track)), deg2rad(3.0)) << "t = " << t;
    // Body rates integrate the attitude: R(t + dt) ~ R(t) (I + [w] dt).
    const double dt = 1e-3;
    const Eigen::Matrix3d r1 = traj.at(t + dt).world_from_body();
    const Eigen::Vector3d w = s.angular_rate_body;
    Eigen::Matrix3d skew;
    skew << 0, -w.z(), w.y(), w.z(), 0, -w.x(), -w.y(), w.x(), 0;
    EXPECT_LT((r1 - s.world_from_body() * (Eigen::Matrix3d::Identity() + skew * dt)).norm(), 1e-5);
  }
  // A right turn (positive angle) banks right (positive roll) and yaws clockwise.
  const double turn_mid = 1800.0 / 30.0 + 22.0;
  EXPECT_GT(traj.at(turn_mid).roll, deg2rad(5.0));
  EXPECT_GT(traj.at(turn_mid).angular_rate_body.z(), 0.0);
}

void expect_profile_error(const std::string& yaml, const std::string& key) {
  try {
    FlightProfile::parse(yaml, "bad_profile.yaml");
    FAIL() << "expected an error naming " << key;
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("bad_profile.yaml"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << e.what();
  }
}

TEST(ProfileErrors, NameTheKey) {
  const std::string head = "name: x\ndistance_m: 3000\nspeed_mps: 20\naltitude_agl_m: 150\n";
  expect_profile_error(head + "legs:\n  - {type: straight}\n  - {type: turn, bank_deg: 10}\n", "legs[1].angle_deg");
  expect_profile_error(head + "legs:\n  - {type: straight}\n  - {type: turn, angle_deg: 90, bank_deg: 80}\n",
                       "legs[1].bank_deg");
  expect_profile_error(head + "legs:\n  - {type: loop}\n", "legs[0].type");
  expect_profile_error(head + "legs:\n  - {type: straight, distance_m: 100}\n", "legs");
  expect_profile_error("name: x\nspeed_mps: 500\nlegs:\n  - {type: straight}\n", "speed_mps");
  expect_profile_error("name: x\nlegs: []\n", "legs");
  expect_profile_error("distance_m: 100\nlegs:\n  - {type: straight}\n", "name");
}

}  // namespace
}  // namespace nadir::sim
