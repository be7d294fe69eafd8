#pragma once
// Holes in a capture: stretches of sensor time in which a channel that is
// otherwise regular carries no messages (lcm-logger stopped or stalled, a
// full receive buffer, a publisher that paused). A damaged log is reported by
// LogReader; a log with a hole is intact byte for byte, so nothing else would
// say that data is missing.

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "common/log_file.h"

namespace nadir {

struct LogHole {
  std::string channel;
  int64_t from_utime = 0;  // sensor time of the last message before the hole
  int64_t to_utime = 0;    // and of the first one after it
  int64_t expected_messages = 0;  // at the channel's median interval
  double seconds() const { return static_cast<double>(to_utime - from_utime) * 1e-6; }
};

struct LogHoleOptions {
  int min_messages = 20;          // channels with fewer messages are not judged (CONFIG, a short STATUS run)
  double interval_factor = 4.0;   // a step this many median intervals long is a hole...
  double min_hole_s = 0.25;       // ...and at least this long
};

// Collects each channel's sensor times while a log is read, then finds holes.
class LogHoleFinder {
 public:
  explicit LogHoleFinder(const LogHoleOptions& options = LogHoleOptions()) : options_(options) {}
  void add(const LogEvent& event);
  std::vector<LogHole> holes() const;

 private:
  LogHoleOptions options_;
  std::map<std::string, std::vector<int64_t>> utimes_;
};

// "CHANNEL: no messages for 3.000 s of sensor time (utime A to B, ~N missing)" lines.
std::string format_log_holes(const std::vector<LogHole>& holes);

}  // namespace nadir
