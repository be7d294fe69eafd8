// The bridge logic on a real memq:// LCM bus: INS and ALTIMETER values, time
// mapping (clock estimator error against the true offset with jitter and
// drift), week rollover, leap seconds, time jumps, flagged altimeter readings,
// baud-mismatch suspicion and config errors.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "common/config.h"
#include "common/geometry.h"
#include "common/gps_time.h"
#include "processes/ins_bridge/ins_bridge.h"
#include "tests/processes/ins_bridge/bridge_test_support.h"
#include "tests/processes/ins_bridge/test_sentences.h"

namespace nadir::ins_bridge {
namespace {

using testing::PvaFields;

struct Harness {
  explicit Harness(const BridgeOptions& options = testing::test_options())
      : bus(testing::memq_bus(&got)), bridge(options, *bus) {}
  void ins(const std::string& text, int64_t arrival_us) {
    bridge.on_ins_bytes(reinterpret_cast<const uint8_t*>(text.data()), text.size(), arrival_us);
    testing::drain(*bus);
  }
  void ins(const std::vector<uint8_t>& bytes, int64_t arrival_us) {
    bridge.on_ins_bytes(bytes.data(), bytes.size(), arrival_us);
    testing::drain(*bus);
  }
  // Feeds a whole frame whose first byte arrived at start_us (the read
  // returns once the last byte, CR LF included, is in).
  void ins_from(const std::string& text, int64_t start_us) {
    const double byte_us = testing::test_options().ins.serial.byte_time_us();
    ins(text, start_us + std::llround(static_cast<double>(text.size()) * byte_us));
  }
  void alt(const std::string& text, int64_t arrival_us) {
    bridge.on_altimeter_bytes(reinterpret_cast<const uint8_t*>(text.data()), text.size(), arrival_us);
    testing::drain(*bus);
  }
  testing::Collected got;
  std::unique_ptr<LcmBus> bus;
  InsBridge bridge;
};

int64_t unix_us_of(unsigned week, double seconds) { return gps_to_unix_us(gps_time_us(week, seconds), 18); }

TEST(InsBridge, PublishesInsInProjectFramesWithStdDev) {
  Harness h;
  PvaFields p;
  const int64_t t = unix_us_of(p.week, p.seconds) + 3000;
  h.ins(testing::ascii_frame('#', testing::long_header("INSSTDEVA", p.week, "345600.000"),
                             {"0.5", "0.6", "0.9", "0.01", "0.02", "0.03", "0.1", "0.2", "0.4", "0", "0", "0", "0",
                              "0"}),
        t - 5000);
  h.ins_from(testing::inspvaa(p), t);
  ASSERT_EQ(h.got.ins.size(), 1u);
  const ins_t& m = h.got.ins[0];
  EXPECT_EQ(m.device_utime, gps_time_us(2300, 345600.25));
  EXPECT_EQ(m.gps_week, 2300);
  EXPECT_DOUBLE_EQ(m.gps_seconds, 345600.25);
  EXPECT_NEAR(m.roll, deg_to_rad(2.5), 1e-12);
  EXPECT_NEAR(m.pitch, deg_to_rad(-1.75), 1e-12);
  EXPECT_NEAR(m.yaw, deg_to_rad(93.5), 1e-12);
  EXPECT_DOUBLE_EQ(m.velocity_ned[0], 20.5);
  EXPECT_DOUBLE_EQ(m.velocity_ned[1], -3.25);
  EXPECT_DOUBLE_EQ(m.velocity_ned[2], -1.125);
  EXPECT_NEAR(m.latitude_deg, p.lat, 1e-11);
  EXPECT_DOUBLE_EQ(m.height_m, 512.25);
  EXPECT_EQ(m.ins_status, kInsSolutionGood);
  EXPECT_EQ(m.flags, ins_t::FLAG_ALIGNED | ins_t::FLAG_SOLUTION_GOOD);
  ASSERT_TRUE(m.has_stddev);
  EXPECT_NEAR(m.attitude_stddev[2], deg_to_rad(0.4), 1e-7);
  EXPECT_NEAR(m.position_stddev[2], 0.9, 1e-7);
  EXPECT_FALSE(m.has_rates);
  // First sample: the offset is its own arrival (no min_delay configured), so
  // utime is the arrival of the frame's first byte.
  EXPECT_NEAR(m.utime, t, 2);
}

TEST(InsBridge, AligningSolutionIsNotFlaggedGood) {
  Harness h;
  PvaFields p;
  p.status = "INS_ALIGNING";
  h.ins(testing::inspvaa(p), unix_us_of(p.week, p.seconds));
  ASSERT_EQ(h.got.ins.size(), 1u);
  EXPECT_EQ(h.got.ins[0].flags, 0);
  EXPECT_EQ(h.got.ins[0].ins_status, kInsAligning);
}

// The ClockSync error against the true offset, through the whole bridge:
// 100 Hz frames, 2 ms minimum transport delay, exponential jitter (mean 3 ms)
// with 5 % of frames held up 20-60 ms, host clock 0.35 s off and drifting 50 ppm.
TEST(InsBridge, ClockEstimatorErrorAgainstTrueOffsetWithJitterAndDrift) {
  BridgeOptions options = testing::test_options();
  options.ins.clock_sync.min_delay_us = 2000;
  Harness h(options);
  std::mt19937 rng(11);
  std::exponential_distribution<double> jitter_ms(1.0 / 3.0);
  std::uniform_real_distribution<double> uniform(0, 1);
  const double byte_us = options.ins.serial.byte_time_us();
  const int64_t d0 = unix_us_of(2300, 345600);
  std::vector<int64_t> truth;
  const int kFrames = 100 * 120;
  for (int i = 0; i < kFrames; ++i) {
    PvaFields p;
    p.seconds = 345600 + i * 0.01;
    const int64_t device_unix = unix_us_of(p.week, p.seconds);
    const double host = static_cast<double>(device_unix) + 350000.0 + 50e-6 * static_cast<double>(device_unix - d0);
    truth.push_back(std::llround(host));
    double delay_us = 2000 + jitter_ms(rng) * 1000;
    if (uniform(rng) < 0.05) delay_us += 20000 + 40000 * uniform(rng);
    const std::string text = testing::inspvaa(p);
    // The read returns the frame (its CR LF included) once its last byte is in.
    const int64_t arrival_end = std::llround(host + delay_us + static_cast<double>(text.size()) * byte_us);
    h.ins(text, arrival_end);
  }
  ASSERT_EQ(h.got.ins.size(), static_cast<size_t>(kFrames));
  double sum2 = 0, worst = 0;
  int n = 0;
  for (int i = 1000; i < kFrames; ++i) {  // after 10 s of convergence
    const double error = static_cast<double>(h.got.ins[static_cast<size_t>(i)].utime - truth[static_cast<size_t>(i)]);
    sum2 += error * error;
    worst = std::max(worst, std::fabs(error));
    ++n;
  }
  const double rms = std::sqrt(sum2 / n);
  std::printf("[ FIGURE ] INS clock estimator vs true offset (120 s, 100 Hz, exp jitter 3 ms + 5%% 20-60 ms, "
              "50 ppm drift): rms %.1f us, max %.1f us; drift estimate %.2f ppm; jumps %lld\n",
              rms, worst, h.bridge.clock_state().drift_ppm, static_cast<long long>(h.bridge.clock_state().jumps));
  EXPECT_LT(rms, 200.0);
  EXPECT_LT(worst, 1000.0);
  EXPECT_NEAR(h.bridge.clock_state().drift_ppm, 50.0, 5.0);
  EXPECT_EQ(h.bridge.clock_state().jumps, 0);
}

// Serial reads delayed 0-20 ms (uniform) after a frame's last byte, in order:
// a read returns every frame in by then, so a frame can wait for a later
// one's delay and frames arrive bunched in one read (the bridge stamps each
// from its place in the chunk). Device time is right throughout: 1,900
// samples at 100 Hz (19 s) without a fault, then the host clock steps by
// `step_us` against the device. A sample is flagged TIME_JUMP when the
// bridge's clock estimate cannot vouch for its time.
struct JitterRun {
  int flagged_before_step = 0;
  int64_t step_flagged_after_us = -1;  // first flagged sample after the step: device time since the step
  double late_bound_us = 0;            // the clock estimate's late bound before the step
};

JitterRun fly_uniform_read_jitter(unsigned seed, int64_t step_us) {
  const BridgeOptions options = testing::test_options();
  Harness h(options);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> jitter_us(0.0, 20000.0);
  const double byte_us = options.ins.serial.byte_time_us();
  const int64_t d0 = unix_us_of(2300, 345600);
  constexpr int kFaultFree = 1900, kAfter = 300;
  std::vector<std::string> texts;
  std::vector<int64_t> read_at;
  for (int i = 0; i < kFaultFree + kAfter; ++i) {
    PvaFields p;
    p.seconds = 345600 + i * 0.01;
    const int64_t device_unix = unix_us_of(p.week, p.seconds);
    const double host = static_cast<double>(device_unix) + 350000.0 + 20e-6 * static_cast<double>(device_unix - d0) +
                        (i >= kFaultFree ? static_cast<double>(step_us) : 0.0);
    texts.push_back(testing::inspvaa(p));
    const int64_t in = std::llround(host + static_cast<double>(texts.back().size()) * byte_us + jitter_us(rng));
    read_at.push_back(read_at.empty() ? in : std::max(in, read_at.back()));
  }
  JitterRun run;
  for (size_t first = 0; first < texts.size();) {
    size_t last = first;
    std::string chunk = texts[first];
    while (last + 1 < texts.size() && read_at[last + 1] == read_at[first]) chunk += texts[++last];
    h.ins(chunk, read_at[first]);
    EXPECT_EQ(h.got.ins.size(), last + 1);
    // A read holding frames from both sides of the step belongs to the step:
    // its first frames are stamped from a chunk the step made.
    const bool step_chunk = last >= static_cast<size_t>(kFaultFree);
    for (size_t i = first; i <= last && i < h.got.ins.size(); ++i) {
      const bool flagged = (h.got.ins[i].flags & ins_t::FLAG_TIME_JUMP) != 0;
      if (!step_chunk) {
        run.flagged_before_step += flagged ? 1 : 0;
      } else if (flagged && run.step_flagged_after_us < 0) {
        run.step_flagged_after_us = std::max<int64_t>(0, (static_cast<int64_t>(i) - kFaultFree) * 10000);
      }
    }
    if (!step_chunk) run.late_bound_us = h.bridge.clock_state().late_bound_us;
    first = last + 1;
  }
  return run;
}

TEST(InsBridge, UniformSerialJitterIsNotAClockStep) {
  int flagged = 0;
  double bound_min = 1e12, bound_max = 0;
  for (unsigned seed = 1; seed <= 20; ++seed) {
    for (const int64_t step_us : {50000, 100000, -100000, 1500000}) {
      const JitterRun run = fly_uniform_read_jitter(seed, step_us);
      flagged += run.flagged_before_step;
      bound_min = std::min(bound_min, run.late_bound_us);
      bound_max = std::max(bound_max, run.late_bound_us);
      EXPECT_EQ(run.flagged_before_step, 0) << "seed " << seed << ", step " << step_us;
      EXPECT_GE(run.step_flagged_after_us, 0) << "seed " << seed << ", step " << step_us << " never flagged";
      EXPECT_LE(run.step_flagged_after_us, 20000) << "seed " << seed << ", step " << step_us;
    }
  }
  std::printf("[ FIGURE ] INS reads 0-20 ms late (uniform), 80 runs of 1900 samples at 100 Hz: %d flagged TIME_JUMP "
              "(late bound %.1f-%.1f ms); steps of +50, +100, -100 and +1500 ms flagged within 20 ms\n",
              flagged, bound_min * 1e-3, bound_max * 1e-3);
}

TEST(InsBridge, WeekRolloverIsContinuousAndCounted) {
  Harness h;
  const double seconds[] = {604799.98, 604799.99};
  for (double s : seconds) {
    PvaFields p;
    p.seconds = s;
    h.ins(testing::inspvaa(p), unix_us_of(p.week, s) + 1000);
  }
  for (int i = 0; i < 3; ++i) {
    PvaFields p;
    p.week = 2301;
    p.seconds = i * 0.01;
    h.ins(testing::inspvaa(p), unix_us_of(p.week, p.seconds) + 1000);
  }
  ASSERT_EQ(h.got.ins.size(), 5u);
  EXPECT_EQ(h.bridge.ins_time().week_changes, 1);
  for (size_t i = 1; i < 5; ++i) {
    EXPECT_EQ(h.got.ins[i].device_utime - h.got.ins[i - 1].device_utime, 10000);
    EXPECT_EQ(h.got.ins[i].utime - h.got.ins[i - 1].utime, 10000);
    EXPECT_EQ(h.got.ins[i].flags & ins_t::FLAG_TIME_JUMP, 0);
  }
}

TEST(InsBridge, WeekReportedModulo1024IsResolvedFromTheHostClock) {
  Harness h;
  PvaFields p;
  p.week = 2300 - 2048;  // what a receiver with a 10-bit week would send
  h.ins(testing::inspvaa(p), unix_us_of(2300, p.seconds) + 1000);
  ASSERT_EQ(h.got.ins.size(), 1u);
  EXPECT_EQ(h.got.ins[0].gps_week, 2300);
  EXPECT_EQ(h.bridge.ins_time().week_unwrapped, 1);
}

TEST(InsBridge, LeapSecondInsertionIsCountedAndFlagged) {
  Harness h;
  // GPS time of 2017-01-01T00:00:00Z, when GPS - UTC went from 17 to 18.
  const int64_t change_gps_s = 1483228800LL - 315964800LL + 18;
  const unsigned week = static_cast<unsigned>(change_gps_s / 604800);
  const double sow = static_cast<double>(change_gps_s % 604800);
  for (int i = -50; i < 50; ++i) {
    PvaFields p;
    p.week = week;
    p.seconds = sow + i * 0.01;
    const int64_t gps_us = gps_time_us(p.week, p.seconds);
    // The host's UTC clock repeats the leap second like the device's UTC does.
    h.ins_from(testing::inspvaa(p), gps_to_unix_us(gps_us, leap_seconds_at(gps_us)) + 1000);
  }
  ASSERT_EQ(h.got.ins.size(), 100u);
  EXPECT_EQ(h.bridge.ins_time().leap_changes, 1);
  EXPECT_EQ(h.bridge.ins_time().leap_seconds, 18);
  EXPECT_NE(h.got.ins[50].flags & ins_t::FLAG_TIME_JUMP, 0);
  EXPECT_EQ(h.got.ins[49].flags & ins_t::FLAG_TIME_JUMP, 0);
  // Vehicle time after the leap is UTC with the new count.
  EXPECT_NEAR(h.got.ins[99].utime, gps_to_unix_us(h.got.ins[99].device_utime, 18) + 1000, 2);
}

TEST(InsBridge, DeviceTimeJumpRestartsTheClockAndIsFlagged) {
  Harness h;
  for (int i = 0; i < 300; ++i) {
    PvaFields p;
    p.seconds = 345600 + i * 0.01 + (i >= 200 ? 5.0 : 0.0);  // the receiver's time steps 5 s
    h.ins_from(testing::inspvaa(p), unix_us_of(2300, 345600 + i * 0.01) + 1500);
  }
  ASSERT_EQ(h.got.ins.size(), 300u);
  EXPECT_EQ(h.bridge.clock_state().jumps, 1);
  EXPECT_NE(h.got.ins[200].flags & ins_t::FLAG_TIME_JUMP, 0);
  // After the restart the published time follows arrival again.
  EXPECT_NEAR(h.got.ins[299].utime, unix_us_of(2300, 345600 + 2.99) + 1500, 2);
  // Duplicates are dropped, time going back is flagged.
  PvaFields same;
  same.seconds = 345600 + 2.99 + 5.0;
  h.ins(testing::inspvaa(same), unix_us_of(2300, 345603) + 1500);
  EXPECT_EQ(h.bridge.ins_time().duplicates, 1);
  PvaFields back;
  back.seconds = 345600 + 1.0;
  h.ins(testing::inspvaa(back), unix_us_of(2300, 345603.01) + 1500);
  EXPECT_EQ(h.bridge.ins_time().time_backwards, 1);
  EXPECT_NE(h.got.ins.back().flags & ins_t::FLAG_TIME_JUMP, 0);
}

TEST(InsBridge, AltimeterReadingsArePublishedFlaggedNeverDroppedSilently) {
  BridgeOptions options = testing::test_options();
  options.altimeter.min_range_m = 1.0;
  options.altimeter.max_range_m = 500.0;
  options.altimeter.min_signal_quality = 0.2;
  options.altimeter.latency_ms = 4.0;
  options.altimeter.beam_body = Eigen::Vector3d(0.1, 0, 1).normalized();
  Harness h(options);
  const int64_t t = 1700000000000000;
  h.alt("150.25 m 90%\r\n", t);
  h.alt("0.50\r\n600.00\r\n--.--\r\n150.00 m 10%\r\ngarbage line\r\n", t + 100000);
  ASSERT_EQ(h.got.altimeter.size(), 6u);
  const auto& a = h.got.altimeter;
  EXPECT_EQ(a[0].validity, altimeter_t::VALID_OK);
  EXPECT_DOUBLE_EQ(a[0].range_m, 150.25);
  EXPECT_FLOAT_EQ(a[0].signal_quality, 0.9f);
  EXPECT_NEAR(a[0].beam_body[0], options.altimeter.beam_body.x(), 1e-15);
  // First byte: 15 bytes (incl. CR LF) before the read at 10 bits/byte, 115200 baud; minus 4 ms latency.
  const double byte_us = 10 * 1e6 / 115200;
  EXPECT_EQ(a[0].utime, t - std::llround(1 * byte_us) - std::llround(12 * byte_us) - 4000);
  EXPECT_EQ(a[1].validity, altimeter_t::VALID_OUT_OF_RANGE);
  EXPECT_EQ(a[2].validity, altimeter_t::VALID_OUT_OF_RANGE);
  EXPECT_EQ(a[3].validity, altimeter_t::VALID_NO_RETURN);
  EXPECT_EQ(a[4].validity, altimeter_t::VALID_LOW_SIGNAL);
  EXPECT_EQ(a[5].validity, altimeter_t::VALID_PARSE_ERROR);
  EXPECT_TRUE(std::isnan(a[5].range_m));
  EXPECT_EQ(h.bridge.altimeter_counts().parse_errors, 1);
  EXPECT_NE(h.bridge.altimeter_counts().last_error.find("byte"), std::string::npos);
}

TEST(InsBridge, NoisyLineWithoutFramesRaisesBaudMismatchWarning) {
  Harness h;
  std::mt19937 rng(5);
  std::vector<uint8_t> noise(4096);
  for (auto& b : noise) b = static_cast<uint8_t>(rng());
  h.ins(noise, 1000);
  EXPECT_TRUE(h.bridge.ins_baud_suspect());
  EXPECT_FALSE(h.bridge.altimeter_baud_suspect());
  StatusReport report;
  h.bridge.report(&report);
  EXPECT_EQ(report.state, status_t::STATE_WARN);
  EXPECT_NE(report.detail.find("baud"), std::string::npos);
  // A good frame clears the suspicion; the episode stays counted.
  h.ins(testing::inspvaa(PvaFields{}), unix_us_of(2300, 345600.25));
  EXPECT_FALSE(h.bridge.ins_baud_suspect());
  EXPECT_EQ(h.bridge.baud_mismatch_episodes(), 1);
}

TEST(BridgeOptions, ConfigErrorsNameTheKey) {
  const char* yaml =
      "altimeter:\n  beam_body: [0, 0, 1]\n"
      "ins_bridge:\n  ins:\n    device: /dev/ttyS9\n    baud: 230401\n";
  try {
    BridgeOptions::from_config(Config::parse(yaml, "test.yaml"));
    FAIL() << "expected a ConfigError";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("ins_bridge.ins.baud"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("test.yaml"), std::string::npos) << e.what();
  }
  const char* parity = "ins_bridge:\n  altimeter:\n    parity: mark\n";
  EXPECT_THROW(BridgeOptions::from_config(Config::parse(parity, "p.yaml")), ConfigError);
  auto expect_named = [](const char* text, const char* key) {
    try {
      BridgeOptions::from_config(Config::parse(text, "r.yaml"));
      ADD_FAILURE() << "expected a ConfigError for " << key;
    } catch (const ConfigError& e) {
      EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << e.what();
    }
  };
  expect_named("ins_bridge:\n  ins:\n    absent_poll_s: 0\n", "ins_bridge.ins.absent_poll_s");
  expect_named("ins_bridge:\n  ins:\n    clock_sync:\n      settle_s: -1\n", "settle_s");
  expect_named("ins_bridge:\n  ins:\n    clock_sync:\n      step_confirm_s: 0\n", "step_confirm_s");
  const char* beam = "altimeter:\n  beam_body: [0, 0]\n";
  EXPECT_THROW(BridgeOptions::from_config(Config::parse(beam, "b.yaml")), ConfigError);
  const BridgeOptions ok = BridgeOptions::from_config(Config::parse(
      "altimeter:\n  beam_body: [0, 0, 1.25]\nins_bridge:\n  ins:\n    imu_to_body_rpy_deg: [0, 0, 180]\n", "ok.yaml"));
  EXPECT_DOUBLE_EQ(ok.altimeter.beam_body.z(), 1.0);
  EXPECT_DOUBLE_EQ(ok.ins.imu_to_body_rpy_deg.z(), 180.0);
}

TEST(BridgeOptions, DefaultConfigFileLoads) {
  const BridgeOptions o =
      BridgeOptions::from_config(Config::load_file(std::string(NADIR_SOURCE_DIR) + "/config/default.yaml"));
  EXPECT_GT(o.ins.serial.baud, 0);
  EXPECT_NEAR(o.altimeter.beam_body.norm(), 1.0, 1e-12);
  EXPECT_DOUBLE_EQ(o.ins.serial.absent_poll_s, 0.1);
  EXPECT_DOUBLE_EQ(o.ins.clock_sync.settle_s, 0.2);
  EXPECT_DOUBLE_EQ(o.ins.clock_sync.step_confirm_s, 0.5);
}

}  // namespace
}  // namespace nadir::ins_bridge
