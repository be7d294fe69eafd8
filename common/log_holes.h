#pragma once
// Holes in a capture: stretches of log time (the logger's receive time) in
// which a channel that is otherwise regular carries no messages (lcm-logger
// stopped or stalled, a full receive buffer, a publisher that paused). A
// damaged log is reported by LogReader; a log with a hole is intact byte for
// byte, so nothing else would say that data is missing. Log time, not the
// messages' sensor time: a forged or mis-stamped utime must neither make nor
// hide a hole.
//
// A photo flight's channels are irregular by nature: a log that holds the
// CONFIG nadir_import writes for photos (name "import", mode "photos") has
// every channel at the photo times (the import writes each photo's INS,
// altimeter, image and truth at its time; a replay of it publishes and
// heartbeats at those log times), so its long intervals are the photos'
// spacing, not lost messages. Such a log has no holes; each channel is
// summarised in one line instead, its gaps being the intervals over twice its
// median (a pause in the survey, a turn without photos).
//
// VO_GROUND is never judged: vo_solver publishes it only for frames whose own
// depths it trusts, so its silences are ground not seen.

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

// One irregular channel's intervals (log time).
struct ChannelIntervals {
  std::string channel;
  int64_t intervals = 0;
  double median_s = 0;
  double max_s = 0;
  int64_t gaps = 0;        // intervals longer than gap_limit_s
  double gap_limit_s = 0;  // twice the median interval (at least LogHoleOptions::min_hole_s)
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
  // The log is a photo import (or a replay of one): its channels are irregular.
  bool photo_intervals() const { return photo_intervals_; }
  // Holes of the regular channels (none in a photo import).
  std::vector<LogHole> holes() const;
  // A photo import's judged channels (none for any other log).
  std::vector<ChannelIntervals> irregular_channels() const;

 private:
  // Calls visit(channel, sorted log times, hole limit in us, mean interval in us)
  // for every channel that is judged.
  template <class Visit>
  void for_each_judged(Visit visit) const;

  LogHoleOptions options_;
  std::map<std::string, std::vector<int64_t>> timestamps_;  // per stream: channel, or STATUS per process
  bool photo_intervals_ = false;
};

// "CHANNEL: no messages for 3.000 s (log time A to B, ~N missing)" lines.
std::string format_log_holes(const std::vector<LogHole>& holes);

// "CHANNEL: N intervals, median X s, max Y s, K gaps over Z s" (no newline),
// and such lines for every channel.
std::string format_channel_interval(const ChannelIntervals& channel);
std::string format_channel_intervals(const std::vector<ChannelIntervals>& channels);

}  // namespace nadir
