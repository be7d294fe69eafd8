#pragma once
// Holes in a capture: stretches of log time (the logger's receive time) in
// which a channel that is otherwise regular carries no messages (lcm-logger
// stopped or stalled, a full receive buffer, a publisher that paused). A
// damaged log is reported by LogReader; a log with a hole is intact byte for
// byte, so nothing else would say that data is missing. Log time, not the
// messages' sensor time: a forged or mis-stamped utime must neither make nor
// hide a hole.

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "common/log_file.h"

namespace nadir {

struct LogHole {
  // The channel; STATUS per process: "STATUS from NAME" (each process's
  // heartbeat is a regular 1 Hz stream, their union is not).
  std::string channel;
  int64_t from_timestamp = 0;  // log time of the last message before the hole
  int64_t to_timestamp = 0;    // and of the first one after it
  int64_t expected_messages = 0;  // at the channel's median interval
  double seconds() const { return static_cast<double>(to_timestamp - from_timestamp) * 1e-6; }
};

struct LogHoleOptions {
  int min_messages = 20;          // channels with fewer messages are not judged (CONFIG, a short STATUS run)
  double interval_factor = 5.0;   // a step this many mean intervals long is a hole...
  double min_hole_s = 0.5;        // ...and at least this long
};

// Collects each channel's log times while a log is read, then finds holes.
class LogHoleFinder {
 public:
  explicit LogHoleFinder(const LogHoleOptions& options = LogHoleOptions()) : options_(options) {}
  void add(const LogEvent& event);
  std::vector<LogHole> holes() const;

 private:
  LogHoleOptions options_;
  std::map<std::string, std::vector<int64_t>> timestamps_;  // per stream: channel, or STATUS per process
};

// "CHANNEL: no messages for 3.000 s (log time A to B, ~N missing)" lines.
std::string format_log_holes(const std::vector<LogHole>& holes);

}  // namespace nadir
