#pragma once
// The bridge's logic without any I/O: bytes from the INS and the altimeter
// (with the time they arrived) in, INS and ALTIMETER messages on the bus out.
// INS time: GPS week/seconds -> GPS microseconds (device_utime) -> UTC with
// the leap-second count -> ClockSync against the byte arrival times ->
// vehicle time (utime). Altimeter time: arrival of the line's first byte
// minus the configured latency (the device has no clock).

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "common/bus.h"
#include "common/clock_sync.h"
#include "common/status.h"
#include "processes/ins_bridge/altimeter_parser.h"
#include "processes/ins_bridge/bridge_options.h"
#include "processes/ins_bridge/line_splitter.h"
#include "processes/ins_bridge/novatel_attitude.h"
#include "processes/ins_bridge/novatel_parser.h"

namespace nadir::ins_bridge {

struct InsTimeCounters {
  int64_t duplicates = 0;       // same GPS time twice: dropped
  int64_t time_backwards = 0;   // GPS time went back: published flagged TIME_JUMP
  int64_t week_changes = 0;     // seconds-of-week wrapped into the next week
  int64_t week_unwrapped = 0;   // weeks reported modulo 1024 and resolved
  int64_t leap_changes = 0;     // GPS - UTC changed while running
  int leap_seconds = 0;         // in use
};

struct AltimeterCounters {
  int64_t lines = 0;
  int64_t ok = 0;
  int64_t no_return = 0;
  int64_t out_of_range = 0;
  int64_t low_signal = 0;
  int64_t parse_errors = 0;
  std::string last_error;
};

class InsBridge {
 public:
  InsBridge(const BridgeOptions& options, Bus& bus);

  void on_ins_bytes(const uint8_t* data, size_t size, int64_t arrival_us);
  void on_altimeter_bytes(const uint8_t* data, size_t size, int64_t arrival_us);
  // The device was closed/reopened: a partial frame or line is dropped; the
  // INS clock estimate restarts.
  void on_ins_reopened();
  void on_altimeter_reopened();

  // Counters, clock state and a WARN/detail for suspected baud mismatch.
  void report(StatusReport* report) const;
  // INS sentences and altimeter lines rejected (STATUS `malformed`).
  int64_t rejected_sentences() const;

  const NovatelParserCounts& ins_counts() const { return ins_parser_.counts(); }
  const InsTimeCounters& ins_time() const { return time_; }
  const AltimeterCounters& altimeter_counts() const { return alt_; }
  const ClockSyncState& clock_state() const { return clock_.state(); }
  int64_t ins_published() const { return ins_published_; }
  int64_t altimeter_published() const { return alt_published_; }
  bool ins_baud_suspect() const { return ins_bytes_since_good_ >= options_.baud_mismatch_bytes; }
  bool altimeter_baud_suspect() const { return alt_bytes_since_good_ >= options_.baud_mismatch_bytes; }
  int64_t baud_mismatch_episodes() const { return baud_episodes_; }

 private:
  void handle_frame(const NovatelFrame& frame);
  void handle_line(const SerialLine& line);
  void note_bytes(int64_t* since_good, bool* flagged, size_t size);
  int64_t altimeter_rejected() const;

  BridgeOptions options_;
  Bus& bus_;
  NovatelParser ins_parser_;
  LineSplitter alt_splitter_;
  std::unique_ptr<AltimeterLineParser> alt_parser_;
  SpanConverter converter_;
  ClockSync clock_;
  double ins_byte_time_us_;
  double alt_byte_time_us_;

  bool have_last_ = false;
  int64_t last_gps_us_ = 0;
  uint32_t last_week_ = 0;
  bool have_leap_ = false;
  bool have_stddev_ = false;
  InsStdDev stddev_;
  int64_t stddev_gps_us_ = 0;
  InsTimeCounters time_;
  AltimeterCounters alt_;
  int64_t ins_published_ = 0;
  int64_t alt_published_ = 0;
  int64_t ins_bytes_since_good_ = 0;
  int64_t alt_bytes_since_good_ = 0;
  bool ins_suspect_flagged_ = false;
  bool alt_suspect_flagged_ = false;
  int64_t baud_episodes_ = 0;
  std::vector<NovatelFrame> frames_;  // reused buffers
  std::vector<SerialLine> lines_;
};

}  // namespace nadir::ins_bridge
