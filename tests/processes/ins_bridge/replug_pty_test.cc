// The live bridge over a real pseudo-terminal when the INS is unplugged and
// comes back with another clock (a receiver reboot or another receiver):
// no sample is stamped off by more than the jump threshold without
// FLAG_TIME_JUMP; an offset step without an unplug is caught per sample too;
// a device back after an unplug is reopened within the absent-path poll
// interval even when the default backoff would have grown past 1 s.

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <thread>

#include "common/time_base.h"
#include "processes/ins_bridge/bridge_runner.h"
#include "common/gps_time.h"
#include "processes/ins_bridge/novatel_encoder.h"
#include "processes/ins_bridge/pseudo_terminal.h"
#include "tests/common/test_support.h"
#include "tests/processes/ins_bridge/bridge_test_support.h"

namespace nadir::ins_bridge {
namespace {

using Clock = std::chrono::steady_clock;

struct Replug {
  double before_s = 1.5;                   // streaming with GPS = host + offset_before
  double gap_s = 2.0;                      // the receiver silent this long ...
  bool unplug = true;                      // ... with its pty closed (false: connected, a time step)
  double after_s = 1.5;                    // back with GPS = host + offset_after
  int64_t gps_offset_before_us = 1500000;
  int64_t gps_offset_after_us = 0;
  // Like a USB serial adapter: what the receiver sends while the bridge has
  // not reopened the port is lost (a pty would buffer it).
  bool lossy = false;
  double absent_poll_s = 0.1;  // the bridge's poll of the absent path
};

struct Sent {
  int64_t true_utime = 0;      // vehicle time of the measurement
  double after_replug_s = -1;  // send time after the replug (or offset step); < 0 before it
  bool delivered = false;      // false: sent into a closed port (lossy) and lost
};

struct ReplugRun {
  testing::Collected got;
  std::map<int64_t, Sent> sent;  // by GPS microseconds
  DeviceLinkCounters link;
  double reopen_delay_s = -1;    // replug -> the bridge's open (wall clock, a figure only)
  StatusReport status;
};

InsPva sample(int i, int64_t gps_us) {
  InsPva p;
  p.gps_week = static_cast<uint32_t>(gps_us / (kSecondsPerWeek * 1000000));
  p.gps_seconds = static_cast<double>(gps_us % (kSecondsPerWeek * 1000000)) * 1e-6;
  p.latitude_deg = 47.0;
  p.longitude_deg = 8.5;
  p.height_m = 650;
  p.roll_deg = 10 * std::sin(i / 50.0);
  p.azimuth_deg = std::fmod(i * 0.573, 360.0);
  p.status = kInsSolutionGood;
  return p;
}

// INSPVAA, INSPVAB and INSPVASA in turn.
std::vector<uint8_t> encode(int i, const InsPva& pva) {
  NovatelHeader header;
  header.gps_week = pva.gps_week;
  header.gps_seconds = pva.gps_seconds;
  if (i % 3 == 1) return encode_inspva_binary(header, pva);
  const std::string text = i % 3 == 0 ? encode_inspva_ascii(header, pva) : encode_inspvas_ascii(pva);
  return {text.begin(), text.end()};
}

// The receiver at 100 Hz. `bridge_opens` is the runner's open count, kept
// current by the main thread (a lossy device delivers only into an open port).
void run_receiver(const Replug& script, const std::string& link, std::unique_ptr<PseudoTerminal>& pty,
                  const std::atomic<int64_t>& bridge_opens, ReplugRun* run, Clock::time_point* replug_time) {
  const auto start = Clock::now();
  const int ticks = static_cast<int>(std::lround((script.before_s + script.gap_s + script.after_s) * 100));
  bool unplugged = false, replugged = false;
  int64_t opens_at_replug = 0;
  for (int i = 0; i < ticks; ++i) {
    std::this_thread::sleep_until(start + std::chrono::milliseconds(10 * i));
    const double t = i * 0.01;
    if (!unplugged && t >= script.before_s) {
      if (script.unplug) pty.reset();  // master closed: the bridge sees a hangup
      unplugged = true;
    }
    if (unplugged && !replugged && t >= script.before_s + script.gap_s) {
      if (!pty) pty = std::make_unique<PseudoTerminal>(link);
      opens_at_replug = bridge_opens.load();
      *replug_time = Clock::now();
      replugged = true;
    }
    if (!pty || (unplugged && !replugged)) continue;
    const int64_t offset = replugged ? script.gps_offset_after_us : script.gps_offset_before_us;
    const int64_t host_gps = unix_to_gps_us(vehicle_time_now_us());
    const int64_t gps_us = host_gps + offset;
    Sent s;
    s.true_utime = gps_to_unix_us(gps_us - offset, leap_seconds_at(gps_us - offset));
    if (replugged) s.after_replug_s = std::chrono::duration<double>(Clock::now() - *replug_time).count();
    s.delivered = !script.lossy || !replugged || !script.unplug || bridge_opens.load() > opens_at_replug;
    if (s.delivered) {
      const std::vector<uint8_t> bytes = encode(i, sample(i, gps_us));
      size_t done = 0;
      while (done < bytes.size()) {
        done += pty->write(bytes.data() + done, bytes.size() - done);
        if (done < bytes.size()) std::this_thread::sleep_for(std::chrono::milliseconds(1));
      }
    }
    run->sent[gps_us] = s;
  }
}

ReplugRun run_replug(const Replug& script) {
  const nadir::testing::TempDir folder("ins_bridge_replug");
  const std::string link = folder.file("ins");
  auto pty = std::make_unique<PseudoTerminal>(link);
  BridgeOptions options = testing::test_options();
  options.ins.serial.device = link;  // default reopen policy: 0.1 s poll while absent, backoff 0.1 .. 5 s
  // A pty delivers a frame at once; at 4 Mbaud the bridge's estimate of when
  // its first byte arrived (last byte minus the frame's time on the line) is
  // within 1 ms of that, so the stamps can be checked against the send time.
  options.ins.serial.baud = 4000000;
  options.ins.serial.absent_poll_s = script.absent_poll_s;
  ReplugRun run;
  std::unique_ptr<LcmBus> bus = testing::memq_bus(&run.got);
  BridgeRunner runner(options, *bus, "ins_bridge", 0.5);
  std::atomic<int64_t> opens{0};
  std::atomic<bool> done{false};
  Clock::time_point replug_time{}, reopen_time{};
  std::thread receiver([&] {
    run_receiver(script, link, pty, opens, &run, &replug_time);
    done = true;
  });
  while (!done) {
    runner.step(5);
    if (runner.ins_link().opens != opens.load()) {
      opens = runner.ins_link().opens;
      reopen_time = Clock::now();
    }
  }
  const auto drain_until = Clock::now() + std::chrono::milliseconds(150);
  while (Clock::now() < drain_until) runner.step(5);
  receiver.join();
  runner.publish_status();
  testing::drain(*bus);
  run.link = runner.ins_link();
  run.status = runner.status();
  if (opens.load() >= 2) run.reopen_delay_s = std::chrono::duration<double>(reopen_time - replug_time).count();
  return run;
}

struct StampCheck {
  int published_after = 0;    // samples sent after the replug/step that were published
  int flagged_after = 0;      // ... with FLAG_TIME_JUMP
  double worst_unflagged_us = 0;
  double worst_flagged_us = 0;
  double last_error_us = 0;
};

// Every published sample: flagged, or stamped within the threshold of its true time.
StampCheck check_stamps(const ReplugRun& run, double threshold_us) {
  StampCheck c;
  for (const ins_t& m : run.got.ins) {
    const auto it = run.sent.find(m.device_utime);
    EXPECT_NE(it, run.sent.end()) << "published a sample that was not sent: " << m.device_utime;
    if (it == run.sent.end()) continue;
    const double error = static_cast<double>(m.utime - it->second.true_utime);
    const bool flagged = (m.flags & ins_t::FLAG_TIME_JUMP) != 0;
    if (!flagged) {
      EXPECT_LE(std::fabs(error), threshold_us) << "unflagged sample " << it->second.after_replug_s
                                                << " s after the replug is " << error << " us off";
      c.worst_unflagged_us = std::max(c.worst_unflagged_us, std::fabs(error));
    } else {
      c.worst_flagged_us = std::max(c.worst_flagged_us, std::fabs(error));
    }
    if (it->second.after_replug_s >= 0) {
      ++c.published_after;
      c.flagged_after += flagged ? 1 : 0;
    }
    c.last_error_us = error;
  }
  return c;
}

TEST(InsBridgeReplug, ReceiverBackWithAnotherClockIsNeverMisStampedUnflagged) {
  Replug script;  // GPS = host + 1.5 s, unplugged 2 s, back with GPS = host
  const ReplugRun run = run_replug(script);
  const double threshold = testing::test_options().ins.clock_sync.jump_threshold_us;
  const StampCheck c = check_stamps(run, threshold);
  std::printf("[ FIGURE ] replug with a 1.5 s clock change: %d samples after the replug, %d flagged; worst error "
              "unflagged %.0f us, flagged %.0f us; last sample %.0f us; reopened %.3f s after the replug\n",
              c.published_after, c.flagged_after, c.worst_unflagged_us, c.worst_flagged_us, c.last_error_us,
              run.reopen_delay_s);
  // A pty buffers what was sent before the reopen: everything arrives.
  EXPECT_EQ(run.got.ins.size(), run.sent.size());
  EXPECT_EQ(run.link.opens, 2);
  EXPECT_GE(run.status.counter("clock_jumps"), 1.0);
  // Flagged while the new estimate settles, then re-established.
  EXPECT_GT(c.flagged_after, 0);
  EXPECT_LT(c.flagged_after, c.published_after / 2);
  EXPECT_LT(std::fabs(c.last_error_us), 5000.0);
  EXPECT_EQ(run.status.counter("clock_settling"), 0.0);
}

// The same with the reopen ~0.45 s late: the pty holds the ~45 samples
// sent since the replug, read at once at the reopen, each one older than its
// arrival says. They are flagged until the minimum holds, not stamped late.
TEST(InsBridgeReplug, BacklogReadAtTheReopenIsFlaggedNotStampedLate) {
  Replug script;
  script.absent_poll_s = 0.5;
  script.gap_s = 1.65;  // polls at 0.1 + 0.5 k s after the unplug: the reopen comes ~0.45 s after the replug
  const ReplugRun run = run_replug(script);
  const StampCheck c = check_stamps(run, testing::test_options().ins.clock_sync.jump_threshold_us);
  std::printf("[ FIGURE ] replug, reopen %.3f s late (backlog): %d samples after the replug, %d flagged; worst "
              "error unflagged %.0f us, flagged %.0f us\n",
              run.reopen_delay_s, c.published_after, c.flagged_after, c.worst_unflagged_us, c.worst_flagged_us);
  EXPECT_EQ(run.got.ins.size(), run.sent.size());
  EXPECT_GT(c.flagged_after, 0);
  EXPECT_LT(std::fabs(c.last_error_us), 5000.0);
}

// The receiver pauses 0.5 s (connected, shorter than the stall timeout) and
// resumes with its time 100 ms behind: device time still moves forward, but
// every sample now arrives 100 ms later than the model expects.
TEST(InsBridgeReplug, OffsetStepWhileConnectedIsFlaggedPerSample) {
  Replug script;
  script.before_s = 2.5;  // two 1 s blocks closed: the fit is in its steady state
  script.gap_s = 0.5;
  script.unplug = false;
  script.gps_offset_before_us = 0;
  script.gps_offset_after_us = -100000;
  const ReplugRun run = run_replug(script);
  const StampCheck c = check_stamps(run, testing::test_options().ins.clock_sync.jump_threshold_us);
  std::printf("[ FIGURE ] 100 ms offset step while connected: %d samples after it, %d flagged; worst error "
              "unflagged %.0f us, flagged %.0f us\n",
              c.published_after, c.flagged_after, c.worst_unflagged_us, c.worst_flagged_us);
  EXPECT_EQ(run.link.opens, 1);
  EXPECT_EQ(run.status.counter("clock_jumps"), 1.0);
  EXPECT_GT(c.flagged_after, 0);
  EXPECT_LT(std::fabs(c.last_error_us), 5000.0);
}

TEST(InsBridgeReplug, DeviceBackAfterUnplugIsReopenedWithinThePollInterval) {
  Replug script;
  script.before_s = 1.0;
  script.after_s = 1.0;
  script.gap_s = 2.05;  // the replug half a poll interval after a poll of the absent path
  script.lossy = true;
  const ReplugRun run = run_replug(script);
  std::printf("[ FIGURE ] device back after a 2 s unplug reopened %.3f s after the replug (absent polls %lld)\n",
              run.reopen_delay_s, static_cast<long long>(run.link.absent_polls));
  // The first sample sent 150 ms or more after the replug reached the bridge
  // (with the old doubling backoff the port was closed until 1.1 s after it).
  const Sent* first_late = nullptr;
  int64_t first_late_gps = 0;
  for (const auto& [gps, s] : run.sent) {
    if (s.after_replug_s >= 0.15) {
      first_late = &s;
      first_late_gps = gps;
      break;
    }
  }
  ASSERT_NE(first_late, nullptr);
  EXPECT_TRUE(first_late->delivered);
  const bool received = std::any_of(run.got.ins.begin(), run.got.ins.end(),
                                    [&](const ins_t& m) { return m.device_utime == first_late_gps; });
  EXPECT_TRUE(received);
  EXPECT_EQ(run.link.opens, 2);
  EXPECT_EQ(run.link.open_failures, 0);   // absence is not a failure: no backoff
  EXPECT_GE(run.link.absent_polls, 10);  // ~20 polls in 2.05 s
  EXPECT_LE(run.link.absent_polls, 25);
  check_stamps(run, testing::test_options().ins.clock_sync.jump_threshold_us);
}

}  // namespace
}  // namespace nadir::ins_bridge
