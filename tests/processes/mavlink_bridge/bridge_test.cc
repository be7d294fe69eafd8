// The bridge logic on a real memq:// LCM bus, fed MAVLink frames from the
// codec: the autopilot clock mapped onto vehicle time (exact with one
// zero-delay sample per block), ATTITUDE and ATTITUDE_QUATERNION -> INS,
// DISTANCE_SENSOR -> ALTIMETER, TIMESYNC both ways, POSE -> VISION_POSITION_
// ESTIMATE / ODOMETRY / GPS_INPUT with rates, covariance layout and the reset
// counter, and config errors.

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>
#include <random>

#include "common/config.h"
#include "common/geometry.h"
#include "processes/mavlink_bridge/mavlink_bridge.h"
#include "processes/mavlink_bridge/pose_messages.h"
#include "tests/processes/ins_bridge/bridge_test_support.h"

namespace nadir::mavlink_bridge {
namespace {

namespace t = nadir::ins_bridge::testing;
using namespace nadir::mavlink;

constexpr int64_t kOffsetUs = 1'700'000'000'000'000;  // vehicle time at autopilot boot

struct Harness {
  explicit Harness(BridgeOptions options = BridgeOptions{})
      : bus(t::memq_bus(&got)),
        bridge(options, *bus, [this](const std::vector<uint8_t>& f) { sent.push_back(f); }),
        autopilot(1, 1) {}

  template <class M>
  void from_autopilot(const M& msg, int64_t arrival_us, int version = 2) {
    const std::vector<uint8_t> bytes = autopilot.encode(msg, version);
    bridge.on_bytes(bytes.data(), bytes.size(), arrival_us, 0.0, true);
    t::drain(*bus);
  }
  void heartbeat() {
    Heartbeat hb;
    hb.autopilot = 12;  // PX4
    from_autopilot(hb, kOffsetUs);
  }
  // SYSTEM_TIME at 10 Hz for `seconds`, delays 0.2..3 ms with one 0 per block.
  void clock_for(double seconds, int64_t start_ms = 1000) {
    std::mt19937 rng(5);
    std::uniform_int_distribution<int> delay(200, 3000);
    for (int i = 0; i < static_cast<int>(seconds * 10); ++i) {
      SystemTime st;
      st.time_boot_ms = static_cast<uint32_t>(start_ms + i * 100);
      from_autopilot(st, kOffsetUs + int64_t{st.time_boot_ms} * 1000 + (i % 10 == 3 ? 0 : delay(rng)));
    }
  }
  // Everything the bridge sent, parsed back.
  std::vector<Frame> sent_frames() {
    FrameParser parser;
    std::vector<Frame> frames;
    for (const auto& f : sent) {
      parser.feed(f.data(), f.size(), 0, 0.0, &frames);
      parser.end_of_datagram(&frames);
    }
    EXPECT_EQ(parser.counts().rejected_spans, 0);
    return frames;
  }
  template <class M>
  std::vector<M> sent_of() {
    std::vector<M> out;
    for (const Frame& f : sent_frames()) {
      if (f.msgid == M::kId) out.push_back(f.decode<M>());
    }
    return out;
  }

  t::Collected got;
  std::unique_ptr<LcmBus> bus;
  std::vector<std::vector<uint8_t>> sent;
  MavlinkBridge bridge;
  FrameEncoder autopilot;
};

TEST(MavlinkBridge, AttitudeIsPublishedOnTheVehicleTimeBaseOnceTheClockIsMapped) {
  Harness h;
  h.heartbeat();
  Attitude a;
  a.time_boot_ms = 500;
  h.from_autopilot(a, kOffsetUs + 501000);
  EXPECT_TRUE(h.got.ins.empty());  // no clock yet
  EXPECT_EQ(h.bridge.input().waiting_for_clock, 1);

  h.clock_for(3.0);
  ASSERT_TRUE(h.bridge.clock_state().valid);
  a.time_boot_ms = 4321;
  a.roll = 0.1f;
  a.pitch = -0.05f;
  a.yaw = 3.0f;
  a.rollspeed = 0.01f;
  a.pitchspeed = -0.02f;
  a.yawspeed = 0.03f;
  h.from_autopilot(a, kOffsetUs + 4321000 + 7000);  // sent 7 ms after the measurement
  ASSERT_EQ(h.got.ins.size(), 1u);
  const ins_t& ins = h.got.ins[0];
  EXPECT_EQ(ins.utime, kOffsetUs + 4321000);  // measurement time, not arrival
  EXPECT_EQ(ins.device_utime, 4321000);
  EXPECT_EQ(ins.roll, 0.1f);
  EXPECT_EQ(ins.pitch, -0.05f);
  EXPECT_EQ(ins.yaw, 3.0f);
  EXPECT_TRUE(ins.has_rates);
  EXPECT_EQ(ins.angular_rate[2], 0.03f);
  EXPECT_EQ(ins.flags, ins_t::FLAG_ALIGNED | ins_t::FLAG_SOLUTION_GOOD);
  EXPECT_EQ(h.bridge.autopilot_system(), 1);
}

TEST(MavlinkBridge, QuaternionAttitudeGivesTheSameAngles) {
  BridgeOptions o;
  o.input.attitude = "attitude_quaternion";
  Harness h(o);
  h.heartbeat();
  h.clock_for(3.0);
  const double roll = 0.2, pitch = -0.1, yaw = -2.5;
  const Eigen::Quaterniond q(rotation_from_rpy(roll, pitch, yaw));
  AttitudeQuaternion a;
  a.time_boot_ms = 4000;
  a.q1 = static_cast<float>(q.w());
  a.q2 = static_cast<float>(q.x());
  a.q3 = static_cast<float>(q.y());
  a.q4 = static_cast<float>(q.z());
  h.from_autopilot(a, kOffsetUs + 4001000);
  h.from_autopilot(Attitude{}, kOffsetUs + 4002000);  // not the configured one: ignored
  ASSERT_EQ(h.got.ins.size(), 1u);
  EXPECT_NEAR(h.got.ins[0].roll, roll, 1e-6);
  EXPECT_NEAR(h.got.ins[0].pitch, pitch, 1e-6);
  EXPECT_NEAR(h.got.ins[0].yaw, yaw, 1e-6);
  EXPECT_EQ(h.bridge.input().attitude_ignored, 1);

  a.q1 = 2.0f;  // not a rotation
  h.from_autopilot(a, kOffsetUs + 4003000);
  EXPECT_EQ(h.got.ins.size(), 1u);
  EXPECT_EQ(h.bridge.input().bad_values, 1);
}

TEST(MavlinkBridge, DownwardDistanceSensorBecomesTheAltimeter) {
  Harness h;
  h.heartbeat();
  h.clock_for(3.0);
  DistanceSensor d;
  d.time_boot_ms = 4000;
  d.min_distance = 20;
  d.max_distance = 60000;
  d.current_distance = 21537;
  d.orientation = kSensorRotationDown;
  d.signal_quality = 87;
  h.from_autopilot(d, kOffsetUs + 4001000, 1);  // MAVLink 1: no signal_quality extension
  d.time_boot_ms = 4100;
  h.from_autopilot(d, kOffsetUs + 4101000);
  d.time_boot_ms = 4200;
  d.current_distance = 60001;  // beyond max: no return
  h.from_autopilot(d, kOffsetUs + 4201000);
  d.time_boot_ms = 4300;
  d.orientation = 0;  // forward: not an altimeter
  h.from_autopilot(d, kOffsetUs + 4301000);
  ASSERT_EQ(h.got.altimeter.size(), 3u);
  EXPECT_EQ(h.got.altimeter[0].utime, kOffsetUs + 4000000);
  EXPECT_DOUBLE_EQ(h.got.altimeter[0].range_m, 215.37);
  EXPECT_EQ(h.got.altimeter[0].signal_quality, -1.0f);  // unknown (v1)
  EXPECT_EQ(h.got.altimeter[0].validity, altimeter_t::VALID_OK);
  EXPECT_EQ(h.got.altimeter[0].beam_body[2], 1.0);
  EXPECT_FLOAT_EQ(h.got.altimeter[1].signal_quality, 0.87f);
  EXPECT_EQ(h.got.altimeter[2].validity, altimeter_t::VALID_OUT_OF_RANGE);
  EXPECT_EQ(h.bridge.input().distance_ignored, 1);
}

TEST(MavlinkBridge, TimesyncRequestsAreAnsweredAndAnswersAreClockSamples) {
  Harness h;
  h.heartbeat();
  TimeSync request;
  request.tc1 = 0;
  request.ts1 = 123456789000;  // the autopilot's boot time, ns
  h.from_autopilot(request, kOffsetUs + 123456789 + 400);
  const std::vector<TimeSync> answers = h.sent_of<TimeSync>();
  ASSERT_EQ(answers.size(), 1u);
  EXPECT_EQ(answers[0].ts1, request.ts1);
  EXPECT_EQ(answers[0].tc1, (kOffsetUs + 123456789 + 400) * 1000);
  EXPECT_EQ(answers[0].target_system, 1);

  // Our requests at 10 Hz, answered by the autopilot 1 ms after they left.
  for (int i = 0; i < 40; ++i) {
    const int64_t now = kOffsetUs + 200'000'000 + i * 100'000;
    h.bridge.tick(now);
    const std::vector<TimeSync> ours = h.sent_of<TimeSync>();
    TimeSync answer;
    answer.ts1 = ours.back().ts1;
    ASSERT_EQ(answer.ts1, now * 1000);
    answer.tc1 = (now - kOffsetUs + 1000) * 1000;
    h.from_autopilot(answer, now + 1000 + (i % 10 == 0 ? 0 : 500));
  }
  EXPECT_TRUE(h.bridge.clock_state().valid);
  EXPECT_EQ(h.bridge.input().clock_samples, 41);
  EXPECT_NEAR(h.bridge.clock_state().offset_us, static_cast<double>(kOffsetUs), 1.0);
  EXPECT_EQ(h.bridge.output().heartbeat, 4);  // 1 Hz over these 4 s
}

pose_t test_pose(int64_t utime, int64_t frames) {
  pose_t p{};
  p.utime = utime;
  p.position_ned[0] = 1110.35;
  p.position_ned[1] = -853.94;
  p.position_ned[2] = -12.5;
  p.velocity_ned[0] = 20.0;
  p.velocity_ned[1] = 1.0;
  p.roll = 0.05;
  p.pitch = -0.02;
  p.yaw = 0.5;
  p.position_covariance[0][0] = 4.0;
  p.position_covariance[0][1] = p.position_covariance[1][0] = 0.5;
  p.position_covariance[1][1] = 5.0;
  p.position_covariance[2][2] = 1.0;
  p.yaw_variance = 1e-4;
  p.frames = frames;
  return p;
}

TEST(MavlinkBridge, PoseLeavesAsVisionPositionEstimateAtTheConfiguredRate) {
  BridgeOptions o;
  o.output.vision_position_estimate_hz = 5.0;
  o.output.odometry_hz = 10.0;
  o.output.attitude_variance_rad2 = 2e-4;
  Harness h(o);
  for (int i = 0; i < 14; ++i) h.bridge.on_pose(test_pose(kOffsetUs + i * 71429, i + 1));  // 14 Hz for 1 s
  const std::vector<VisionPositionEstimate> vpe = h.sent_of<VisionPositionEstimate>();
  const std::vector<Odometry> odo = h.sent_of<Odometry>();
  EXPECT_EQ(vpe.size(), 5u);   // t = 0, 0.214, 0.429, 0.643, 0.857
  EXPECT_EQ(odo.size(), 7u);   // every second pose (0.9 / 10 Hz = 90 ms apart at least)
  EXPECT_TRUE(h.sent_of<GpsInput>().empty());
  const VisionPositionEstimate& v = vpe[0];
  EXPECT_EQ(v.usec, static_cast<uint64_t>(kOffsetUs));
  EXPECT_EQ(v.x, 1110.35f);
  EXPECT_EQ(v.y, -853.94f);
  EXPECT_EQ(v.z, -12.5f);
  EXPECT_EQ(v.yaw, 0.5f);
  // Upper triangle of (x y z roll pitch yaw), row-major.
  EXPECT_EQ(v.covariance[0], 4.0f);   // xx
  EXPECT_EQ(v.covariance[1], 0.5f);   // xy
  EXPECT_EQ(v.covariance[6], 5.0f);   // yy
  EXPECT_EQ(v.covariance[11], 1.0f);  // zz
  EXPECT_EQ(v.covariance[15], 2e-4f); // roll
  EXPECT_EQ(v.covariance[18], 2e-4f); // pitch
  EXPECT_EQ(v.covariance[20], 1e-4f); // yaw
  EXPECT_EQ(v.reset_counter, 0);
  const Odometry& od = odo[0];
  EXPECT_EQ(od.frame_id, kMavFrameLocalNed);
  EXPECT_EQ(od.child_frame_id, kMavFrameBodyFrd);
  const Eigen::Matrix3d r = rotation_from_rpy(0.05, -0.02, 0.5);
  const Eigen::Vector3d vb = r.transpose() * Eigen::Vector3d(20, 1, 0);
  EXPECT_NEAR(od.vx, vb.x(), 1e-5);
  EXPECT_NEAR(od.vy, vb.y(), 1e-5);
  EXPECT_TRUE(std::isnan(od.velocity_covariance[0]));
  const Eigen::Quaterniond q(r);
  EXPECT_NEAR(od.q[0], q.w(), 1e-7);
  EXPECT_NEAR(od.q[3], q.z(), 1e-7);
  EXPECT_EQ(od.estimator_type, kMavEstimatorTypeVio);
}

TEST(MavlinkBridge, ResetCounterCountsEstimatorRestarts) {
  BridgeOptions o;
  o.output.vision_position_estimate_hz = 100.0;
  Harness h(o);
  h.bridge.on_pose(test_pose(kOffsetUs, 10));
  h.bridge.on_pose(test_pose(kOffsetUs + 100000, 11));
  h.bridge.on_pose(test_pose(kOffsetUs + 200000, 1));  // restarted: frames count again from 1
  pose_t init = test_pose(kOffsetUs + 300000, 2);
  init.flags = pose_t::FLAG_INITIALIZING;                // lost its yaw: initialising again
  h.bridge.on_pose(init);
  init.utime += 100000;
  init.frames = 3;
  h.bridge.on_pose(init);                                // still initialising: same reset
  const std::vector<VisionPositionEstimate> vpe = h.sent_of<VisionPositionEstimate>();
  ASSERT_EQ(vpe.size(), 5u);
  EXPECT_EQ(vpe[1].reset_counter, 0);
  EXPECT_EQ(vpe[2].reset_counter, 1);
  EXPECT_EQ(vpe[3].reset_counter, 2);
  EXPECT_EQ(vpe[4].reset_counter, 2);
}

TEST(MavlinkBridge, GpsInputPlacesPoseOnTheGlobeFromTheOrigin) {
  BridgeOptions o;
  o.output.vision_position_estimate_hz = 0;
  o.output.gps_input_hz = 5;
  o.output.gps_input.origin_latitude_deg = 40.0;
  o.output.gps_input.origin_longitude_deg = -80.0;
  o.output.gps_input.origin_altitude_m = 300.0;
  Harness h(o);
  // 2026-01-04T00:00:10Z = GPS week 2400, 10 s + 18 leap seconds into it.
  const int64_t utime = int64_t{1767484810} * 1000000;
  h.bridge.on_pose(test_pose(utime, 1));
  const std::vector<GpsInput> g = h.sent_of<GpsInput>();
  ASSERT_EQ(g.size(), 1u);
  // At 40 deg: 1 deg of latitude = 111 034.6 m, of longitude = 85 394 m (WGS84).
  EXPECT_NEAR(g[0].lat * 1e-7, 40.01, 2e-6);
  EXPECT_NEAR(g[0].lon * 1e-7, -80.01, 2e-6);
  EXPECT_FLOAT_EQ(g[0].alt, 312.5f);
  EXPECT_EQ(g[0].time_week, 2400);
  EXPECT_EQ(g[0].time_week_ms, 28000u);
  EXPECT_EQ(g[0].fix_type, 3);
  EXPECT_FLOAT_EQ(g[0].horiz_accuracy, 3.0f);
  EXPECT_FLOAT_EQ(g[0].vert_accuracy, 1.0f);
  EXPECT_EQ(g[0].vn, 20.0f);
}

TEST(MavlinkBridge, OnlyTheAutopilotIsListenedTo) {
  Harness h;
  h.heartbeat();
  h.clock_for(3.0);
  FrameEncoder other(42, 1);
  const std::vector<uint8_t> bytes = other.encode(Attitude{});
  h.bridge.on_bytes(bytes.data(), bytes.size(), kOffsetUs + 4000000, 0.0, true);
  t::drain(*h.bus);
  EXPECT_TRUE(h.got.ins.empty());
  EXPECT_EQ(h.bridge.input().other_system, 1);
}

TEST(MavlinkBridge, ConfigErrorsNameTheKey) {
  const Config bad = Config::parse("mavlink_bridge:\n  link:\n    kind: tcp\n", "test.yaml");
  try {
    BridgeOptions::from_config(bad);
    FAIL() << "no error";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("mavlink_bridge.link.kind"), std::string::npos) << e.what();
  }
  const Config port = Config::parse("mavlink_bridge:\n  link:\n    local: 127.0.0.1:99999\n", "test.yaml");
  EXPECT_THROW(BridgeOptions::from_config(port), ConfigError);
  const Config rate = Config::parse("mavlink_bridge:\n  output:\n    gps_input_hz: 500\n", "test.yaml");
  EXPECT_THROW(BridgeOptions::from_config(rate), ConfigError);
  EXPECT_NO_THROW(BridgeOptions::from_config(Config::load_file(NADIR_SOURCE_DIR "/config/default.yaml")));
  const BridgeOptions read = BridgeOptions::from_config(Config::parse(
      "mavlink_bridge:\n  input:\n    clock_sync: {window_s: 10, settle_s: 0.5}\n", "test.yaml"));
  EXPECT_EQ(read.input.clock_sync.window_s, 10.0);
  EXPECT_EQ(read.input.clock_sync.settle_s, 0.5);
  EXPECT_EQ(read.input.clock_sync.block_s, ClockSyncOptions{}.block_s);  // absent: the default
  const Config bad_sync =
      Config::parse("mavlink_bridge:\n  input:\n    clock_sync: {window_s: 1}\n", "test.yaml");
  EXPECT_THROW(BridgeOptions::from_config(bad_sync), ConfigError);
}

}  // namespace
}  // namespace nadir::mavlink_bridge
