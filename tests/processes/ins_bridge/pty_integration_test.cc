// The bridge's live loop over real pseudo-terminals and a real memq:// LCM bus.
// A scripted device thread writes 100 Hz INS (INSPVAA, INSPVAB and INSPVASA in
// turn, INSSTDEVA at 1 Hz) and 10 Hz altimeter lines; the runner publishes;
// counts and values must match what was written, through an unplug/replug of
// the INS pty, garbage bursts on either device and an altimeter stall.

#include <gtest/gtest.h>
#include <stdlib.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <map>
#include <memory>
#include <random>
#include <thread>

#include "common/geometry.h"
#include "tests/common/test_support.h"
#include "common/time_base.h"
#include "processes/ins_bridge/bridge_runner.h"
#include "common/gps_time.h"
#include "processes/ins_bridge/novatel_encoder.h"
#include "processes/ins_bridge/pseudo_terminal.h"
#include "tests/processes/ins_bridge/bridge_test_support.h"

namespace nadir::ins_bridge {
namespace {

using Clock = std::chrono::steady_clock;


struct Script {
  double duration_s = 2.0;
  double unplug_ins_at_s = -1;     // close the INS pty (cable pulled) ...
  double replug_after_s = 0.4;     // ... and create a new one at the same path
  double ins_garbage_at_s = -1;    // 8 KB of random bytes on the INS line
  double alt_garbage_at_s = -1;    // 8 KB of random bytes on the altimeter line
  double alt_pause_at_s = -1;      // altimeter silent for alt_pause_s (a stall)
  double alt_pause_s = 0.8;
};

struct Written {
  std::map<int64_t, InsPva> ins;        // fully written INS frames by GPS microseconds
  std::vector<double> altimeter;        // fully written ranges, in order
  int64_t partial_writes = 0;
};

InsPva flight_sample(int i, int64_t gps_us) {
  InsPva p;
  p.gps_week = static_cast<uint32_t>(gps_us / (kSecondsPerWeek * 1000000));
  p.gps_seconds = static_cast<double>(gps_us % (kSecondsPerWeek * 1000000)) * 1e-6;
  p.latitude_deg = 47.0 + i * 1e-6;
  p.longitude_deg = 8.5 + i * 2e-6;
  p.height_m = 650 + 0.1 * i;
  p.north_velocity = 25 * std::cos(i * 0.01);
  p.east_velocity = 25 * std::sin(i * 0.01);
  p.up_velocity = 0.5;
  p.roll_deg = 10 * std::sin(i / 50.0);
  p.pitch_deg = 5 * std::cos(i / 70.0);
  p.azimuth_deg = std::fmod(i * 0.573, 360.0);
  p.status = kInsSolutionGood;
  return p;
}

void write_all(PseudoTerminal& pty, const std::vector<uint8_t>& bytes) {
  size_t done = 0;
  while (done < bytes.size()) {
    done += pty.write(bytes.data() + done, bytes.size() - done);
    if (done < bytes.size()) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
}

// The scripted devices: 100 Hz INS, 10 Hz altimeter, faults at given times.
// The ptys stay with the caller so they outlive the writer (the bridge drains them).
void run_devices(const Script& script, std::unique_ptr<PseudoTerminal>& ins, std::unique_ptr<PseudoTerminal>& alt,
                 const std::string& ins_link, Written* out) {
  std::mt19937 rng(99);
  const auto start = Clock::now();
  const int64_t gps0 = (unix_to_gps_us(vehicle_time_now_us()) / 10000) * 10000;
  const int ticks = static_cast<int>(script.duration_s * 100);
  bool unplugged = false, replugged = false, ins_garbage_done = false, alt_garbage_done = false;
  NovatelHeader header;
  auto garbage = [&](PseudoTerminal& pty) {
    std::vector<uint8_t> junk(8192);
    for (auto& b : junk) b = static_cast<uint8_t>(rng());
    junk.push_back('\r');
    junk.push_back('\n');
    write_all(pty, junk);
  };
  for (int i = 0; i < ticks; ++i) {
    std::this_thread::sleep_until(start + std::chrono::milliseconds(10 * i));
    const double t = i * 0.01;
    if (script.unplug_ins_at_s >= 0 && !unplugged && t >= script.unplug_ins_at_s) {
      ins.reset();  // master closed: the bridge sees a hangup
      unplugged = true;
    }
    if (unplugged && !replugged && t >= script.unplug_ins_at_s + script.replug_after_s) {
      ins = std::make_unique<PseudoTerminal>(ins_link);
      replugged = true;
    }
    if (ins && script.ins_garbage_at_s >= 0 && !ins_garbage_done && t >= script.ins_garbage_at_s) {
      garbage(*ins);
      ins_garbage_done = true;
    }
    if (script.alt_garbage_at_s >= 0 && !alt_garbage_done && t >= script.alt_garbage_at_s) {
      garbage(*alt);
      alt_garbage_done = true;
    }
    const int64_t gps_us = gps0 + static_cast<int64_t>(i) * 10000;
    const InsPva pva = flight_sample(i, gps_us);
    if (ins) {
      header.gps_week = pva.gps_week;
      header.gps_seconds = pva.gps_seconds;
      header.sequence = static_cast<uint16_t>(i);
      std::vector<uint8_t> frame;
      if (i % 100 == 0) {
        InsStdDev s;
        s.gps_week = pva.gps_week;
        s.gps_seconds = pva.gps_seconds;
        s.roll_deg = s.pitch_deg = 0.01f;
        s.azimuth_deg = 0.05f;
        const std::string text = encode_insstdev_ascii(header, s);
        frame.assign(text.begin(), text.end());
      }
      if (i % 3 == 1) {
        const std::vector<uint8_t> b = encode_inspva_binary(header, pva);
        frame.insert(frame.end(), b.begin(), b.end());
      } else {
        const std::string text = i % 3 == 0 ? encode_inspva_ascii(header, pva) : encode_inspvas_ascii(pva);
        frame.insert(frame.end(), text.begin(), text.end());
      }
      if (ins->write(frame.data(), frame.size()) == frame.size()) out->ins[gps_us] = pva;
      else ++out->partial_writes;
    }
    const bool alt_paused =
        script.alt_pause_at_s >= 0 && t >= script.alt_pause_at_s && t < script.alt_pause_at_s + script.alt_pause_s;
    if (i % 10 == 0 && !alt_paused) {
      const double range = 150.0 + 10.0 * std::sin(i / 50.0);
      char line[64];
      std::snprintf(line, sizeof line, "%.2f m %d%%\r\n", range, 80);
      const size_t n = std::strlen(line);
      if (alt->write(line, n) == n) out->altimeter.push_back(std::round(range * 100) / 100);
      else ++out->partial_writes;
    }
  }
}

struct LiveRun {
  testing::Collected got;
  Written written;
  StatusReport final_status;
  DeviceLinkCounters ins_link, alt_link;
};

LiveRun run_live(const Script& script) {
  const nadir::testing::TempDir folder("ins_bridge_pty");
  const std::string ins_link = folder.file("ins");
  const std::string alt_link = folder.file("alt");
  auto ins = std::make_unique<PseudoTerminal>(ins_link);
  auto alt = std::make_unique<PseudoTerminal>(alt_link);
  BridgeOptions options = testing::test_options();
  options.ins.serial.device = ins_link;
  options.altimeter.serial.device = alt_link;
  options.ins.serial.stall_timeout_s = 0.3;
  options.altimeter.serial.stall_timeout_s = 0.3;
  options.ins.serial.reopen_min_s = 0.02;
  options.ins.serial.reopen_max_s = 0.1;
  options.altimeter.serial.reopen_min_s = 0.02;
  options.altimeter.serial.reopen_max_s = 0.1;

  LiveRun run;
  std::unique_ptr<LcmBus> bus = testing::memq_bus(&run.got);
  BridgeRunner runner(options, *bus, "ins_bridge", 0.5);
  std::atomic<bool> done{false};
  std::thread devices([&] {
    run_devices(script, ins, alt, ins_link, &run.written);
    done = true;
  });
  while (!done) runner.step(20);
  // Shorter than the stall timeout: the end of the script is not a stall.
  const auto drain_until = Clock::now() + std::chrono::milliseconds(150);
  while (Clock::now() < drain_until) runner.step(20);
  devices.join();
  runner.publish_status();
  testing::drain(*bus);
  run.final_status = runner.status();
  run.ins_link = runner.ins_link();
  run.alt_link = runner.altimeter_link();
  return run;
}

void expect_ins_matches(const LiveRun& run) {
  ASSERT_EQ(run.got.ins.size(), run.written.ins.size());
  for (const ins_t& m : run.got.ins) {
    const auto it = run.written.ins.find(m.device_utime);
    ASSERT_NE(it, run.written.ins.end()) << m.device_utime;
    const InsPva& p = it->second;
    EXPECT_NEAR(m.roll, deg_to_rad(p.roll_deg), 1e-9);
    EXPECT_NEAR(m.pitch, deg_to_rad(p.pitch_deg), 1e-9);
    EXPECT_NEAR(angle_difference(m.yaw, deg_to_rad(p.azimuth_deg)), 0.0, 1e-9);
    EXPECT_NEAR(m.velocity_ned[2], -p.up_velocity, 1e-4);
    EXPECT_NEAR(m.latitude_deg, p.latitude_deg, 1e-10);
    EXPECT_EQ(m.ins_status, kInsSolutionGood);
  }
}

std::vector<double> ok_ranges(const LiveRun& run) {
  std::vector<double> ranges;
  for (const altimeter_t& a : run.got.altimeter)
    if (a.validity == altimeter_t::VALID_OK) ranges.push_back(a.range_m);
  return ranges;
}

TEST(InsBridgePty, CountsAndValuesMatchWhatTheDevicesWrote) {
  Script script;
  const LiveRun run = run_live(script);
  EXPECT_EQ(run.written.ins.size(), 200u);
  EXPECT_EQ(run.written.altimeter.size(), 20u);
  expect_ins_matches(run);
  EXPECT_EQ(ok_ranges(run), run.written.altimeter);
  EXPECT_EQ(run.got.altimeter.size(), run.written.altimeter.size());
  // STATUS went out with the bridge's counters.
  ASSERT_FALSE(run.got.status.empty());
  const status_t& last = run.got.status.back();
  EXPECT_EQ(testing::counter(last, "ins_published"), 200.0);
  EXPECT_EQ(testing::counter(last, "alt_ok"), 20.0);
  EXPECT_EQ(testing::counter(last, "ins_rejected_crc"), 0.0);
  EXPECT_EQ(testing::counter(last, "clock_valid"), 1.0);
  EXPECT_EQ(run.ins_link.opens, 1);
  EXPECT_EQ(run.alt_link.opens, 1);
  bool has_stddev = false;
  for (const ins_t& m : run.got.ins) has_stddev |= m.has_stddev;
  EXPECT_TRUE(has_stddev);
}

TEST(InsBridgePty, UnpluggingAndReplugTheInsMidStreamIsSurvived) {
  Script script;
  script.duration_s = 2.5;
  script.unplug_ins_at_s = 1.0;
  const LiveRun run = run_live(script);
  // 40 ticks without a device; everything written to either pty arrives.
  EXPECT_GE(run.written.ins.size(), 200u);
  expect_ins_matches(run);
  EXPECT_GE(run.ins_link.hangups + run.ins_link.stalls, 1);
  EXPECT_GE(run.ins_link.opens, 2);
  EXPECT_GE(run.ins_link.absent_polls, 1);  // the path was gone for a while
  // The altimeter never noticed.
  EXPECT_EQ(ok_ranges(run), run.written.altimeter);
  EXPECT_EQ(run.alt_link.opens, 1);
  EXPECT_EQ(run.alt_link.hangups + run.alt_link.stalls, 0);
}

TEST(InsBridgePty, GarbageOrStallOnOneDeviceDoesNotInterruptTheOther) {
  Script script;
  script.duration_s = 3.0;
  script.alt_garbage_at_s = 0.5;
  script.ins_garbage_at_s = 1.2;
  script.alt_pause_at_s = 1.8;
  const LiveRun run = run_live(script);
  EXPECT_EQ(run.written.ins.size(), 300u);
  expect_ins_matches(run);                              // no INS frame lost to altimeter trouble
  EXPECT_EQ(ok_ranges(run), run.written.altimeter);     // no altimeter line lost to INS garbage
  const auto& counters = run.final_status.counters;
  auto value = [&](const std::string& name) {
    for (const auto& [key, v] : counters)
      if (key == name) return v;
    return -1.0;
  };
  EXPECT_GT(value("ins_garbage_bytes"), 1000.0);
  EXPECT_GT(value("alt_rejected_parse") + value("alt_rejected_overlong"), 0.0);
  EXPECT_GE(run.alt_link.stalls, 1);   // the 0.8 s silence was seen and the port reopened
  EXPECT_GE(run.alt_link.opens, 2);
  EXPECT_EQ(run.ins_link.stalls + run.ins_link.hangups, 0);
}

}  // namespace
}  // namespace nadir::ins_bridge
