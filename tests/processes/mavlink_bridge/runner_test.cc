// The bridge's live loop over real links and a real memq:// LCM bus: a
// pseudo-terminal standing in for the autopilot's serial port (with an
// unplug and replug at the same path), and a UDP server socket on loopback.
// The test plays the autopilot: HEARTBEAT, ATTITUDE at 100 Hz stamped with its
// boot time, answers to the bridge's TIMESYNC requests; it checks the INS
// times against the boot time it used, and POSE coming back as
// VISION_POSITION_ESTIMATE.

#include <gtest/gtest.h>
#include <fcntl.h>
#include <poll.h>
#include <unistd.h>

#include <chrono>
#include <cmath>

#include "common/time_base.h"
#include "processes/ins_bridge/pseudo_terminal.h"
#include "processes/mavlink_bridge/bridge_runner.h"
#include "tests/common/test_support.h"
#include "tests/processes/ins_bridge/bridge_test_support.h"

namespace nadir::mavlink_bridge {
namespace {

namespace t = nadir::ins_bridge::testing;
using Clock = std::chrono::steady_clock;

// The autopilot end of a link: frames out through `write`, bytes in through on_bytes().
class Autopilot {
 public:
  explicit Autopilot(std::function<void(const std::vector<uint8_t>&)> write)
      : write_(std::move(write)), encoder_(1, 1), boot_us_(vehicle_time_now_us() - 5'000'000) {}

  // Sends what is due at the current time: HEARTBEAT at 1 Hz, ATTITUDE at 100 Hz.
  void tick() {
    const int64_t now = vehicle_time_now_us();
    if (now - last_heartbeat_us_ >= 1'000'000) {
      last_heartbeat_us_ = now;
      mavlink::Heartbeat hb;
      hb.autopilot = 3;  // ArduPilot
      write_(encoder_.encode(hb));
    }
    if (now - last_attitude_us_ >= 10'000) {
      last_attitude_us_ = now;
      mavlink::Attitude a;
      a.time_boot_ms = static_cast<uint32_t>((now - boot_us_) / 1000);
      a.roll = 0.01f * static_cast<float>(sent_attitude_ % 10);
      write_(encoder_.encode(a));
      ++sent_attitude_;
    }
  }
  void on_bytes(const uint8_t* data, size_t size, bool datagram) {
    std::vector<mavlink::Frame> frames;
    parser_.feed(data, size, 0, 0.0, &frames);
    if (datagram) parser_.end_of_datagram(&frames);
    for (const mavlink::Frame& f : frames) {
      ++received_[f.msgid];
      if (f.msgid == mavlink::TimeSync::kId) {
        mavlink::TimeSync ts = f.decode<mavlink::TimeSync>();
        if (ts.tc1 != 0) continue;
        ts.tc1 = (vehicle_time_now_us() - boot_us_) * 1000;
        write_(encoder_.encode(ts));
      } else if (f.msgid == mavlink::VisionPositionEstimate::kId) {
        last_vpe_ = f.decode<mavlink::VisionPositionEstimate>();
      }
    }
  }
  int64_t boot_us() const { return boot_us_; }
  int sent_attitude() const { return sent_attitude_; }
  int received(uint32_t id) const { return received_.count(id) ? received_.at(id) : 0; }
  const mavlink::VisionPositionEstimate& last_vpe() const { return last_vpe_; }
  const mavlink::FrameCounts& counts() const { return parser_.counts(); }

 private:
  std::function<void(const std::vector<uint8_t>&)> write_;
  mavlink::FrameEncoder encoder_;
  mavlink::FrameParser parser_;
  int64_t boot_us_;
  int64_t last_heartbeat_us_ = 0;
  int64_t last_attitude_us_ = 0;
  int sent_attitude_ = 0;
  std::map<uint32_t, int> received_;
  mavlink::VisionPositionEstimate last_vpe_;
};

pose_t a_pose() {
  pose_t p{};
  p.utime = vehicle_time_now_us();
  p.position_ned[0] = 123.5;
  p.frames = 1;
  return p;
}

// Steps the runner and the autopilot for `seconds`; `serve` reads the autopilot's end.
void run_for(double seconds, BridgeRunner& runner, Autopilot& autopilot, const std::function<void()>& serve) {
  const auto until = Clock::now() + std::chrono::duration<double>(seconds);
  while (Clock::now() < until) {
    autopilot.tick();
    runner.step(2);
    serve();
  }
}

// INS times against the autopilot's boot time: the pty/socket delay is all
// the error there is (ms resolution of time_boot_ms aside).
void expect_times_mapped(const t::Collected& got, int64_t boot_us, int min_count) {
  ASSERT_GE(static_cast<int>(got.ins.size()), min_count);
  double worst_ms = 0;
  for (const ins_t& ins : got.ins) {
    worst_ms = std::max(worst_ms, std::abs(static_cast<double>(ins.utime - (boot_us + ins.device_utime))) / 1000.0);
  }
  EXPECT_LT(worst_ms, 5.0);
  std::printf("%zu INS, worst time error %.3f ms\n", got.ins.size(), worst_ms);
}

TEST(MavlinkBridgeRunner, SerialLinkOverAPseudoTerminalWithAReplug) {
  nadir::testing::TempDir tmp("mavlink_pty");
  const std::string link = tmp.file("autopilot");
  auto pty = std::make_unique<ins_bridge::PseudoTerminal>(link);
  BridgeOptions options;
  options.link.kind = "serial";
  options.link.serial.device = link;
  options.link.serial.baud = 921600;
  options.link.serial.stall_timeout_s = 0.5;
  t::Collected got;
  std::unique_ptr<LcmBus> bus = t::memq_bus(&got);
  BridgeRunner runner(options, *bus, "mavlink_bridge", 0.5);
  Autopilot autopilot([&](const std::vector<uint8_t>& f) { pty->write(f.data(), f.size()); });
  auto serve = [&] {
    uint8_t buffer[4096];
    ::fcntl(pty->master_fd(), F_SETFL, O_NONBLOCK);
    for (ssize_t n; (n = ::read(pty->master_fd(), buffer, sizeof buffer)) > 0;) {
      autopilot.on_bytes(buffer, static_cast<size_t>(n), false);
    }
  };
  run_for(1.5, runner, autopilot, serve);
  t::drain(*bus);
  expect_times_mapped(got, autopilot.boot_us(), 50);
  bus->publish(channels::kPose, a_pose());
  run_for(0.2, runner, autopilot, serve);
  EXPECT_EQ(autopilot.received(mavlink::VisionPositionEstimate::kId), 1);
  EXPECT_EQ(autopilot.last_vpe().x, 123.5f);
  EXPECT_GE(autopilot.received(mavlink::Heartbeat::kId), 1);
  EXPECT_GE(runner.bridge().input().clock_samples, 5);

  // Unplugged for 0.3 s, then an autopilot (rebooted: a new clock) at the same path.
  pty->close();
  const int64_t closed_at_boot_us = vehicle_time_now_us() - autopilot.boot_us();
  const size_t before = got.ins.size();
  run_for(0.3, runner, autopilot, [] {});
  t::drain(*bus);
  for (size_t i = before; i < got.ins.size(); ++i) {
    EXPECT_LE(got.ins[i].device_utime, closed_at_boot_us);  // only what was sent before the unplug
  }
  pty = std::make_unique<ins_bridge::PseudoTerminal>(link);
  Autopilot rebooted([&](const std::vector<uint8_t>& f) { pty->write(f.data(), f.size()); });
  got.ins.clear();
  run_for(1.5, runner, rebooted, [&] {
    uint8_t buffer[4096];
    ::fcntl(pty->master_fd(), F_SETFL, O_NONBLOCK);
    for (ssize_t n; (n = ::read(pty->master_fd(), buffer, sizeof buffer)) > 0;) {
      rebooted.on_bytes(buffer, static_cast<size_t>(n), false);
    }
  });
  t::drain(*bus);
  // Samples while the new clock settles are flagged; the rest are on time.
  std::vector<ins_t> trusted;
  for (const ins_t& ins : got.ins) {
    if (!(ins.flags & ins_t::FLAG_TIME_JUMP)) trusted.push_back(ins);
  }
  t::Collected after;
  after.ins = trusted;
  expect_times_mapped(after, rebooted.boot_us(), 50);
  const StatusReport status = runner.status();
  EXPECT_EQ(status.counter("serial_reopens"), 1.0);
  EXPECT_EQ(runner.bridge().rejected_frames(), 0);
}

// The bridge as a UDP server on loopback and the autopilot on a client socket.
struct UdpServerSetup {
  UdpServerSetup()
      : bus(t::memq_bus(&got)),
        runner(server_options(), *bus, "mavlink_bridge", 0.5),
        socket(false, "127.0.0.1:0", bridge_address()),
        autopilot([this](const std::vector<uint8_t>& f) { socket.send(f.data(), f.size()); }) {
    socket.open();
  }
  static BridgeOptions server_options() {
    BridgeOptions options;
    options.link.kind = "udp_server";
    options.link.local = "127.0.0.1:0";
    return options;
  }
  std::string bridge_address() const { return "127.0.0.1:" + std::to_string(runner.udp_port()); }
  // Reads the autopilot's end of the link.
  void serve() {
    std::vector<uint8_t> datagram;
    while (socket.receive(&datagram)) autopilot.on_bytes(datagram.data(), datagram.size(), true);
  }
  void run(double seconds) { run_for(seconds, runner, autopilot, [this] { serve(); }); }

  t::Collected got;
  std::unique_ptr<LcmBus> bus;
  BridgeRunner runner;
  UdpLink socket;
  Autopilot autopilot;
};

TEST(MavlinkBridgeRunner, UdpServerAnswersWhoeverSent) {
  UdpServerSetup setup;
  auto& [got, bus, runner, socket, autopilot] = setup;
  (void)socket;
  auto serve = [&] { setup.serve(); };
  setup.run(1.5);
  t::drain(*bus);
  expect_times_mapped(got, autopilot.boot_us(), 50);
  bus->publish(channels::kPose, a_pose());
  run_for(0.2, runner, autopilot, serve);
  EXPECT_EQ(autopilot.received(mavlink::VisionPositionEstimate::kId), 1);
  EXPECT_GE(autopilot.received(mavlink::TimeSync::kId), 10);
  EXPECT_EQ(autopilot.counts().rejected_spans, 0);
  EXPECT_EQ(runner.bridge().rejected_frames(), 0);
}

// A datagram from another local port must not take the bridge's replies: not
// one with a bad CRC, not garbage, not a valid frame from a system that is not
// the autopilot. Before the fix, the first of these diverted every frame
// (HEARTBEAT, TIMESYNC, the position) to the sender until the autopilot spoke
// again.
TEST(MavlinkBridgeRunner, UdpServerRepliesOnlyToTheAutopilotsValidFrames) {
  UdpServerSetup setup;
  auto& [got, bus, runner, socket, autopilot] = setup;
  (void)got;
  (void)socket;
  UdpLink intruder(false, "127.0.0.1:0", setup.bridge_address());
  intruder.open();
  setup.run(1.2);
  ASSERT_EQ(runner.bridge().autopilot_system(), 1);

  // A valid ATTITUDE with one byte of its payload flipped (bad CRC), bytes
  // that are no frame at all, and a well-formed frame from system 77.
  mavlink::FrameEncoder autopilot_encoder(1, 1), stranger_encoder(77, 1);
  std::vector<uint8_t> bad_crc = autopilot_encoder.encode(mavlink::Attitude{});
  bad_crc[12] ^= 0x5a;
  const std::vector<uint8_t> garbage(40, 0xfd);
  mavlink::Heartbeat gcs_heartbeat;  // a ground station: not an autopilot
  gcs_heartbeat.autopilot = mavlink::kMavAutopilotInvalid;
  const std::vector<uint8_t> stranger = stranger_encoder.encode(mavlink::Attitude{});
  for (const std::vector<uint8_t>* d : std::initializer_list<const std::vector<uint8_t>*>{&bad_crc, &garbage, &stranger}) {
    intruder.send(d->data(), d->size());
  }
  const std::vector<uint8_t> gcs = stranger_encoder.encode(gcs_heartbeat);
  intruder.send(gcs.data(), gcs.size());

  const int vpe_before = autopilot.received(mavlink::VisionPositionEstimate::kId);
  const int timesync_before = autopilot.received(mavlink::TimeSync::kId);
  // Only the intruder's datagrams this round: the autopilot stays quiet for
  // 0.3 s while the bridge keeps sending (TIMESYNC at 10 Hz) and a POSE comes.
  const auto quiet_until = Clock::now() + std::chrono::milliseconds(300);
  bus->publish(channels::kPose, a_pose());
  while (Clock::now() < quiet_until) {
    runner.step(2);
    setup.serve();
  }
  std::vector<uint8_t> datagram;
  int diverted = 0;
  while (intruder.receive(&datagram)) ++diverted;
  EXPECT_EQ(diverted, 0) << "the bridge sent to the intruder's port";
  EXPECT_EQ(autopilot.received(mavlink::VisionPositionEstimate::kId), vpe_before + 1);
  EXPECT_GT(autopilot.received(mavlink::TimeSync::kId), timesync_before);
  EXPECT_EQ(runner.udp_peer_changes(), 0);
  EXPECT_GE(runner.bridge().rejected_frames(), 1);  // the bad CRC and the garbage were counted
  EXPECT_GE(runner.bridge().input().other_system, 1);
}

// With the autopilot's address pinned, a sender on any other port is not
// even decoded: not a forged heartbeat and ATTITUDE under the autopilot's own
// system id, which an unpinned server would have to accept as the autopilot's.
TEST(MavlinkBridgeRunner, APinnedAutopilotAddressIsTheOnlyOneHeardAndAnswered) {
  // The autopilot's port: a free one, taken from a socket opened and closed.
  uint16_t autopilot_port = 0;
  {
    UdpLink probe(false, "127.0.0.1:0", "127.0.0.1:9");
    probe.open();
    autopilot_port = probe.local_port();
  }
  const std::string autopilot_address = "127.0.0.1:" + std::to_string(autopilot_port);
  BridgeOptions options = UdpServerSetup::server_options();
  options.link.autopilot_address = autopilot_address;
  t::Collected got;
  std::unique_ptr<LcmBus> bus = t::memq_bus(&got);
  BridgeRunner runner(options, *bus, "mavlink_bridge", 0.5);
  const std::string bridge_address = "127.0.0.1:" + std::to_string(runner.udp_port());
  UdpLink socket(false, autopilot_address, bridge_address);
  socket.open();
  Autopilot autopilot([&](const std::vector<uint8_t>& f) { socket.send(f.data(), f.size()); });
  auto serve = [&] {
    std::vector<uint8_t> datagram;
    while (socket.receive(&datagram)) autopilot.on_bytes(datagram.data(), datagram.size(), true);
  };
  UdpLink intruder(false, "127.0.0.1:0", bridge_address);
  intruder.open();

  // Before the autopilot speaks, the bridge already answers only its address.
  mavlink::FrameEncoder forger(1, 1);  // the autopilot's system and component
  const std::vector<uint8_t> forged_heartbeat = forger.encode(mavlink::Heartbeat{});
  const std::vector<uint8_t> forged_attitude = forger.encode(mavlink::Attitude{});
  intruder.send(forged_heartbeat.data(), forged_heartbeat.size());
  intruder.send(forged_attitude.data(), forged_attitude.size());
  run_for(1.2, runner, autopilot, serve);
  EXPECT_EQ(runner.bridge().autopilot_system(), 1);
  intruder.send(forged_attitude.data(), forged_attitude.size());
  bus->publish(channels::kPose, a_pose());
  run_for(0.3, runner, autopilot, serve);

  std::vector<uint8_t> datagram;
  int diverted = 0;
  while (intruder.receive(&datagram)) ++diverted;
  EXPECT_EQ(diverted, 0) << "the bridge sent to the intruder's port";
  EXPECT_EQ(runner.udp_foreign_datagrams(), 3);
  EXPECT_EQ(runner.udp_peer_changes(), 0);
  EXPECT_EQ(autopilot.received(mavlink::VisionPositionEstimate::kId), 1);
  // Every ATTITUDE the bridge read was one the autopilot sent (the forged ones
  // would make it two more).
  const InputCounters& in = runner.bridge().input();
  EXPECT_LE(in.attitude + in.waiting_for_clock, autopilot.sent_attitude());
  EXPECT_EQ(runner.bridge().rejected_frames(), 0);
}

}  // namespace
}  // namespace nadir::mavlink_bridge
