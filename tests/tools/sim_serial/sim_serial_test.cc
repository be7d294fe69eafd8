// nadir_sim_serial: its device formatting inverts the bridge's conversion, its
// generated flight is consistent, and end to end a simulator log played into
// real pseudo-terminals comes out of the real bridge loop message for message.

#include <gtest/gtest.h>
#include <signal.h>
#include <stdlib.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>

#include "common/channels.h"
#include "common/config.h"
#include "common/geometry.h"
#include "tests/common/test_support.h"
#include "common/lcm_bus.h"
#include "common/log_file.h"
#include "processes/ins_bridge/bridge_runner.h"
#include "common/gps_time.h"
#include "processes/ins_bridge/novatel_attitude.h"
#include "processes/ins_bridge/novatel_parser.h"
#include "tools/sim_serial/device_formatter.h"
#include "tools/sim_serial/flight_source.h"

namespace nadir::sim_serial {
namespace {

ins_t sample_ins(int i) {
  ins_t m{};
  m.utime = 1700000000000000 + i * 10000;
  m.roll = deg_to_rad(20 * std::sin(i * 0.05));
  m.pitch = deg_to_rad(10 * std::cos(i * 0.03));
  m.yaw = wrap_angle(deg_to_rad(170 + i * 0.3));  // crosses +-180 deg
  m.velocity_ned[0] = 30;
  m.velocity_ned[1] = -4;
  m.velocity_ned[2] = 1.5;
  m.latitude_deg = 46.5 + i * 1e-6;
  m.longitude_deg = 7.25;
  m.height_m = 800 + i * 0.01;
  m.ins_status = 3;
  return m;
}

TEST(DeviceFormatter, EveryFormatDecodesBackToTheSameAttitude) {
  for (const Eigen::Vector3d& mount : {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(0.02, -0.01, M_PI / 2)}) {
    for (InsFormat format : {InsFormat::kAscii, InsFormat::kShortAscii, InsFormat::kBinary}) {
      DeviceFormatter formatter(format, mount, true);
      ins_bridge::NovatelParser parser;
      const ins_bridge::SpanConverter converter(mount);
      for (int i = 0; i < 300; ++i) {
        const ins_t m = sample_ins(i);
        const int64_t gps_us = gps_time_us(2300, 1000 + i * 0.01);
        const std::vector<uint8_t> bytes = formatter.ins_bytes(m, gps_us);
        std::vector<ins_bridge::NovatelFrame> frames;
        parser.feed(bytes.data(), bytes.size(), 0, 0, &frames);
        ASSERT_FALSE(frames.empty()) << parser.counts().last_error;
        const ins_bridge::NovatelFrame& f = frames.back();
        ASSERT_EQ(f.kind, ins_bridge::NovatelFrame::Kind::kInsPva);
        EXPECT_EQ(gps_time_us(f.pva.gps_week, f.pva.gps_seconds), gps_us);
        const ins_bridge::ProjectAttitude a = converter.attitude(f.pva);
        const double tolerance = format == InsFormat::kBinary ? 1e-12 : 1e-9;
        EXPECT_NEAR(a.roll, m.roll, tolerance) << i;
        EXPECT_NEAR(a.pitch, m.pitch, tolerance) << i;
        EXPECT_NEAR(angle_difference(a.yaw, m.yaw), 0.0, tolerance) << i;
        EXPECT_NEAR(f.pva.up_velocity, -1.5, 1e-9);
      }
      EXPECT_EQ(parser.counts().crc_failures + parser.counts().field_errors + parser.counts().garbage_bytes, 0);
    }
  }
}

// INSSTDEVA (once per GPS second) reports the attitude sigmas of the log's
// INS messages, so that the bridge and yaw fusion see how good the simulated
// INS really is; without them in the log, fixed figures.
TEST(DeviceFormatter, StdDevReportsTheLogsAttitudeSigmas) {
  for (const bool from_log : {true, false}) {
    DeviceFormatter formatter(InsFormat::kAscii, Eigen::Vector3d::Zero(), true);
    ins_bridge::NovatelParser parser;
    ins_t m = sample_ins(0);
    m.has_stddev = from_log;
    m.attitude_stddev[0] = m.attitude_stddev[1] = deg_to_rad(0.05);
    m.attitude_stddev[2] = deg_to_rad(0.1);
    const std::vector<uint8_t> bytes = formatter.ins_bytes(m, gps_time_us(2300, 1000.0));
    std::vector<ins_bridge::NovatelFrame> frames;
    parser.feed(bytes.data(), bytes.size(), 0, 0, &frames);
    ASSERT_EQ(frames.size(), 2u) << parser.counts().last_error;
    ASSERT_EQ(frames[0].kind, ins_bridge::NovatelFrame::Kind::kInsStdDev);
    const ins_bridge::InsStdDev& s = frames[0].stddev;
    EXPECT_NEAR(s.roll_deg, from_log ? 0.05 : 0.005, 1e-6);
    EXPECT_NEAR(s.pitch_deg, from_log ? 0.05 : 0.005, 1e-6);
    EXPECT_NEAR(s.azimuth_deg, from_log ? 0.1 : 0.02, 1e-6);
  }
}

TEST(DeviceFormatter, AltimeterLinesCarryRangeQualityAndNoReturn) {
  altimeter_t a{};
  a.range_m = 301.256;
  a.signal_quality = 0.734f;
  a.validity = altimeter_t::VALID_OK;
  EXPECT_EQ(DeviceFormatter::altimeter_line(a), "301.26 m 73%\r\n");
  a.signal_quality = -1;
  EXPECT_EQ(DeviceFormatter::altimeter_line(a), "301.26 m\r\n");
  a.validity = altimeter_t::VALID_NO_RETURN;
  EXPECT_EQ(DeviceFormatter::altimeter_line(a), "--.--\r\n");
}

TEST(GeneratedFlight, RatesAndSlantRangeAreConsistent) {
  GeneratedFlightOptions o;
  o.duration_s = 10;
  auto source = make_generated_source(o);
  Sample s;
  int ins = 0, alt = 0, ok = 0;
  int64_t last = -1;
  ins_t last_ins{};
  while (source->next(&s)) {
    ASSERT_GE(s.t_us, last);
    last = s.t_us;
    if (s.kind == Sample::Kind::kIns) {
      ++ins;
      last_ins = s.ins;
      EXPECT_NEAR(std::hypot(s.ins.velocity_ned[0], s.ins.velocity_ned[1]), 30.0, 1e-9);
    } else {
      ++alt;
      if (s.altimeter.validity != altimeter_t::VALID_OK) continue;
      ++ok;
      // Beam straight down in the body: range * cos(roll) * cos(pitch) = height above ground.
      const double agl = last_ins.height_m - o.terrain_height_m;
      EXPECT_NEAR(s.altimeter.range_m * std::cos(last_ins.roll) * std::cos(last_ins.pitch), agl, 0.5);
    }
  }
  EXPECT_EQ(ins, 1001);
  EXPECT_EQ(alt, 101);
  EXPECT_GE(ok, 90);
}


std::string bin_dir() {
  const char* env = std::getenv("NADIR_BIN_DIR");
  return env ? env : std::string(NADIR_BINARY_DIR) + "/bin";
}

TEST(SimSerialEndToEnd, LogPlayedIntoPtysComesOutOfTheBridge) {
  const nadir::testing::TempDir folder("sim_serial");
  const std::string log = folder.file("flight.lcmlog");
  std::map<int64_t, ins_t> written_ins;  // by source utime
  std::vector<altimeter_t> written_alt;
  {
    LogWriter writer(log);
    for (int i = 0; i < 150; ++i) {
      const ins_t m = sample_ins(i);
      std::vector<uint8_t> buf(static_cast<size_t>(m.getEncodedSize()));
      m.encode(buf.data(), 0, static_cast<int>(buf.size()));
      writer.write(m.utime, channels::kIns, buf.data(), buf.size());
      written_ins[m.utime] = m;
      if (i % 10 == 5) {
        altimeter_t a{};
        a.utime = m.utime;
        a.range_m = 250 + i;
        a.signal_quality = 0.8f;
        a.validity = i == 55 ? altimeter_t::VALID_NO_RETURN : altimeter_t::VALID_OK;
        std::vector<uint8_t> abuf(static_cast<size_t>(a.getEncodedSize()));
        a.encode(abuf.data(), 0, static_cast<int>(abuf.size()));
        writer.write(a.utime, channels::kAltimeter, abuf.data(), abuf.size());
        written_alt.push_back(a);
      }
    }
  }
  const std::string config = std::string(NADIR_SOURCE_DIR) + "/config/default.yaml";
  const std::string ins_link = folder.file("ins"), alt_link = folder.file("alt");
  const std::string program = bin_dir() + "/nadir_sim_serial";
  const pid_t child = fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    freopen("/dev/null", "w", stdout);
    execl(program.c_str(), program.c_str(), "--config", config.c_str(), "--log", log.c_str(), "--ins-link",
          ins_link.c_str(), "--altimeter-link", alt_link.c_str(), "--ins-format", "mixed", "--start-delay", "0.3",
          "--linger", "0.4", static_cast<char*>(nullptr));
    _exit(127);
  }

  ins_bridge::BridgeOptions options = ins_bridge::BridgeOptions::from_config(Config::load_file(config));
  options.ins.serial.device = ins_link;
  options.altimeter.serial.device = alt_link;
  options.ins.serial.reopen_min_s = options.altimeter.serial.reopen_min_s = 0.02;
  options.ins.serial.reopen_max_s = options.altimeter.serial.reopen_max_s = 0.05;
  LcmBusOptions bus_options;
  bus_options.url = "memq://";
  bus_options.queue_capacity = 10000;
  LcmBus bus(bus_options);
  std::vector<ins_t> got_ins;
  std::vector<altimeter_t> got_alt;
  bus.subscribe<ins_t>(channels::kIns, [&](const ins_t& m) { got_ins.push_back(m); });
  bus.subscribe<altimeter_t>(channels::kAltimeter, [&](const altimeter_t& m) { got_alt.push_back(m); });
  ins_bridge::BridgeRunner runner(options, bus, "ins_bridge", 1.0);
  int status = 0;
  const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(30);
  while (waitpid(child, &status, WNOHANG) == 0) {
    runner.step(20);
    if (std::chrono::steady_clock::now() > give_up) {
      kill(child, SIGKILL);
      waitpid(child, &status, 0);
      FAIL() << "nadir_sim_serial did not finish";
    }
  }
  while (bus.handle(0) > 0) {
  }
  ASSERT_TRUE(WIFEXITED(status));
  ASSERT_EQ(WEXITSTATUS(status), 0);

  ASSERT_EQ(got_ins.size(), written_ins.size());
  ASSERT_EQ(got_alt.size(), written_alt.size());
  // Device time is the log's sample spacing; values survive the round trip.
  const int64_t first_device = got_ins.front().device_utime;
  const int64_t first_source = written_ins.begin()->first;
  double worst_spacing_error = 0;
  for (const ins_t& m : got_ins) {
    const auto it = written_ins.find(first_source + (m.device_utime - first_device));
    ASSERT_NE(it, written_ins.end()) << m.device_utime;
    EXPECT_NEAR(m.roll, it->second.roll, 1e-9);
    EXPECT_NEAR(m.pitch, it->second.pitch, 1e-9);
    EXPECT_NEAR(angle_difference(m.yaw, it->second.yaw), 0.0, 1e-9);
    EXPECT_NEAR(m.velocity_ned[2], 1.5, 1e-4);
    worst_spacing_error = std::max(
        worst_spacing_error,
        std::fabs(static_cast<double>((m.utime - got_ins.front().utime) - (it->first - first_source))));
  }
  for (size_t i = 0; i < got_alt.size(); ++i) {
    EXPECT_EQ(got_alt[i].validity, written_alt[i].validity);
    if (written_alt[i].validity == altimeter_t::VALID_OK) {
      EXPECT_NEAR(got_alt[i].range_m, written_alt[i].range_m, 0.005);
    }
  }
  std::printf("[ FIGURE ] sim_serial -> pty -> bridge: %zu INS, %zu ALTIMETER; INS utime spacing vs log spacing "
              "worst %.0f us\n",
              got_ins.size(), got_alt.size(), worst_spacing_error);
}

}  // namespace
}  // namespace nadir::sim_serial
