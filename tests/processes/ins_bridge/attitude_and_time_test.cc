// NovAtel SPAN attitude -> project ZYX attitude with known values, GPS time and
// leap seconds, and the altimeter line protocols.

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "common/config.h"
#include "common/geometry.h"
#include "processes/ins_bridge/altimeter_parser.h"
#include "common/gps_time.h"
#include "processes/ins_bridge/novatel_attitude.h"

namespace nadir::ins_bridge {
namespace {

InsPva span(double roll, double pitch, double azimuth) {
  InsPva p;
  p.roll_deg = roll;
  p.pitch_deg = pitch;
  p.azimuth_deg = azimuth;
  return p;
}

Eigen::Matrix3d project_rotation(const ProjectAttitude& a) { return rotation_from_rpy(a.roll, a.pitch, a.yaw); }

// ENU <-> NED and SPAN (x right, y fwd, z up) <-> project (x fwd, y right, z down).
const Eigen::Matrix3d kP = (Eigen::Matrix3d() << 0, 1, 0, 1, 0, 0, 0, 0, -1).finished();

TEST(SpanAttitude, HeadingEastLevel) {
  const SpanConverter c(Eigen::Vector3d::Zero());
  const ProjectAttitude a = c.attitude(span(0, 0, 90));
  EXPECT_NEAR(a.yaw, M_PI / 2, 1e-12);
  const Eigen::Vector3d forward = project_rotation(a) * Eigen::Vector3d::UnitX();
  EXPECT_TRUE(forward.isApprox(Eigen::Vector3d(0, 1, 0), 1e-12)) << forward.transpose();  // east in NED
}

TEST(SpanAttitude, AzimuthWrapsToProjectYawRange) {
  const SpanConverter c(Eigen::Vector3d::Zero());
  EXPECT_NEAR(c.attitude(span(0, 0, 270)).yaw, -M_PI / 2, 1e-12);
  EXPECT_NEAR(c.attitude(span(0, 0, 360)).yaw, 0.0, 1e-12);
  EXPECT_NEAR(c.attitude(span(0, 0, 180)).yaw, M_PI, 1e-12);
}

TEST(SpanAttitude, NoseUpPitchAndRightWingDownRoll) {
  const SpanConverter c(Eigen::Vector3d::Zero());
  // Pitch +10 deg heading north: the nose points up (negative down component).
  const Eigen::Vector3d nose = project_rotation(c.attitude(span(0, 10, 0))) * Eigen::Vector3d::UnitX();
  EXPECT_NEAR(nose.z(), -std::sin(deg_to_rad(10)), 1e-12);
  EXPECT_NEAR(nose.x(), std::cos(deg_to_rad(10)), 1e-12);
  // Roll +20 deg: the right wing (body y) dips (positive down component).
  const Eigen::Vector3d wing = project_rotation(c.attitude(span(20, 0, 0))) * Eigen::Vector3d::UnitY();
  EXPECT_NEAR(wing.z(), std::sin(deg_to_rad(20)), 1e-12);
}

TEST(SpanAttitude, MatchesSpanDefinitionBuiltInEnuForRandomAngles) {
  const SpanConverter c(Eigen::Vector3d::Zero());
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> roll(-180, 180), pitch(-89, 89), az(0, 360);
  for (int i = 0; i < 500; ++i) {
    const InsPva p = span(roll(rng), pitch(rng), az(rng));
    const Eigen::Matrix3d reference = kP * span_rotation_enu_imu(p.roll_deg, p.pitch_deg, p.azimuth_deg) * kP;
    EXPECT_TRUE(project_rotation(c.attitude(p)).isApprox(reference, 1e-12)) << i;
  }
}

TEST(SpanAttitude, ImuMountedBackwardsIsCorrectedByTheConfiguredRotation) {
  // IMU y axis points to the tail: R_imu_body = Rz(180 deg).
  const SpanConverter c(Eigen::Vector3d(0, 0, M_PI));
  const ProjectAttitude a = c.attitude(span(0, 10, 0));  // IMU "nose" north and 10 deg up
  EXPECT_NEAR(std::fabs(a.yaw), M_PI, 1e-9);             // the body faces south
  EXPECT_NEAR(a.pitch, deg_to_rad(-10), 1e-9);           // and its nose is down
  EXPECT_NEAR(a.roll, 0.0, 1e-9);
  // General case against the composition.
  const SpanConverter tilted(Eigen::Vector3d(deg_to_rad(1.5), deg_to_rad(-2.0), deg_to_rad(0.7)));
  const InsPva p = span(5, -3, 47);
  const Eigen::Matrix3d expected = kP * span_rotation_enu_imu(5, -3, 47) * kP *
                                   rotation_from_rpy(deg_to_rad(1.5), deg_to_rad(-2.0), deg_to_rad(0.7));
  EXPECT_TRUE(project_rotation(tilted.attitude(p)).isApprox(expected, 1e-12));
}

TEST(SpanAttitude, VelocityUpBecomesDown) {
  InsPva p;
  p.north_velocity = 1;
  p.east_velocity = -2;
  p.up_velocity = 3;
  EXPECT_TRUE(SpanConverter::velocity_ned(p).isApprox(Eigen::Vector3d(1, -2, -3)));
}

TEST(GpsTime, EpochLeapSecondsAndWeeks) {
  EXPECT_EQ(gps_time_us(0, 0), 0);
  EXPECT_EQ(gps_time_us(1, 0.5), 604800500000);
  EXPECT_EQ(gps_to_unix_us(0, 0), 315964800LL * 1000000);
  // 2017-01-01T00:00:00Z = Unix 1483228800 introduced GPS - UTC = 18 s.
  const int64_t gps_2017 = (1483228800LL - 315964800LL + 18) * 1000000;
  EXPECT_EQ(leap_seconds_at(gps_2017), 18);
  EXPECT_EQ(leap_seconds_at(gps_2017 - 1000000), 17);
  EXPECT_EQ(leap_seconds_at(0), 0);
  EXPECT_EQ(gps_to_unix_us(gps_2017, 18), 1483228800LL * 1000000);
  EXPECT_EQ(unix_to_gps_us(1700000000LL * 1000000), (1700000000LL - 315964800LL + 18) * 1000000);
  // Week 2300 day 3 noon: GPS seconds 302400 + 43200.
  const int64_t t = gps_time_us(2300, 345600);
  EXPECT_EQ(gps_to_unix_us(t, 18), (315964800LL + 2300LL * 604800 + 345600 - 18) * 1000000);
}

TEST(GpsTime, WeekModulo1024ResolvesToTheNearestEpoch) {
  const int64_t now = gps_time_us(2300, 1000);
  EXPECT_EQ(unwrap_week_1024(2300 % 1024, 1000, now), 2300u);
  EXPECT_EQ(unwrap_week_1024(2300 - 2048, 1000, now), 2300u);
  // Across the rollover: reported 1023 (end of the previous 1024 block) near week 2048.
  EXPECT_EQ(unwrap_week_1024(1023, 604000, gps_time_us(2048, 10)), 2047u);
  EXPECT_EQ(unwrap_week_1024(0, 10, gps_time_us(2047, 604000)), 2048u);
}

TEST(AltimeterParsers, LightwareStyleLines) {
  const LightwareAsciiParser parser;
  AltimeterReading r = parser.parse("123.45");
  ASSERT_TRUE(r.parsed);
  EXPECT_DOUBLE_EQ(r.range_m, 123.45);
  EXPECT_FLOAT_EQ(r.signal_quality, -1.0f);
  r = parser.parse("  87.20 m 64%");
  ASSERT_TRUE(r.parsed) << r.error;
  EXPECT_DOUBLE_EQ(r.range_m, 87.2);
  EXPECT_FLOAT_EQ(r.signal_quality, 0.64f);
  r = parser.parse("87.20 m,100");
  ASSERT_TRUE(r.parsed) << r.error;
  EXPECT_FLOAT_EQ(r.signal_quality, 1.0f);
  EXPECT_TRUE(parser.parse("--.--").no_return);
  EXPECT_TRUE(parser.parse("-1.00").no_return);
  for (const char* bad : {"", "m", "abc", "12.3 ft", "12.3 m 101%", "12.3 m x", "1\x01" "2"}) {
    EXPECT_FALSE(parser.parse(bad).parsed) << bad;
    EXPECT_FALSE(parser.parse(bad).error.empty()) << bad;
  }
}

TEST(AltimeterParsers, NumberUnitLinesWithConfiguredPrefixUnitAndQuality) {
  NumberUnitOptions o;
  o.prefix = "D=";
  o.unit = "cm";
  o.quality_prefix = "Q=";
  o.no_return_token = "NO TARGET";
  const NumberUnitParser parser(o);
  AltimeterReading r = parser.parse("D=12345 cm Q=80");
  ASSERT_TRUE(r.parsed) << r.error;
  EXPECT_DOUBLE_EQ(r.range_m, 123.45);
  EXPECT_FLOAT_EQ(r.signal_quality, 0.8f);
  r = parser.parse("D= 250.5cm");
  ASSERT_TRUE(r.parsed) << r.error;
  EXPECT_DOUBLE_EQ(r.range_m, 2.505);
  EXPECT_TRUE(parser.parse("NO TARGET").no_return);
  for (const char* bad : {"12345 cm", "D=12345 m", "D=12345 cmx", "D=abc cm", "D=1 cm Q=", "D=1 cm R=3"}) {
    EXPECT_FALSE(parser.parse(bad).parsed) << bad;
  }
  NumberUnitOptions feet;
  feet.unit = "ft";
  EXPECT_DOUBLE_EQ(NumberUnitParser(feet).parse("100 ft").range_m, 30.48);
  NumberUnitOptions wrong;
  wrong.unit = "yd";
  EXPECT_THROW(NumberUnitParser parser_with_bad_unit(wrong), ConfigError);
}

}  // namespace
}  // namespace nadir::ins_bridge
