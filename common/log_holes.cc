#include "common/log_holes.h"

#include <algorithm>
#include <cstdio>

#include "common/channels.h"
#include "common/message_guard.h"
#include "nadir/status_t.hpp"


namespace nadir {

void LogHoleFinder::add(const LogEvent& event) {
  if (event.channel != channels::kStatus) {
    timestamps_[event.channel].push_back(event.timestamp);
    return;
  }
  // Six processes' 1 Hz heartbeats, sent within ~0.2 s of each other, leave
  // 0.8 s between bursts: more than 5 mean intervals of their union. Each
  // process's stream is judged on its own; an undecodable STATUS is nobody's.
  status_t status;
  std::string reason;
  if (decode_message(event.data, event.size, &status, &reason)) {
    timestamps_[std::string(channels::kStatus) + " from " + status.name].push_back(event.timestamp);
  }
}

std::vector<LogHole> LogHoleFinder::holes() const {
  std::vector<LogHole> out;
  for (const auto& [channel, recorded] : timestamps_) {
    // CONFIG comes once per process start: never a regular stream.
    if (channel == channels::kConfig || static_cast<int>(recorded.size()) < options_.min_messages) continue;
    // Sorted: lcm-logger writes in arrival order, which several publishers
    // on one channel may interleave a little. The mean interval, not the
    // median: a channel with several publishers has bursts of short
    // intervals and long ones between them.
    std::vector<int64_t> times = recorded;
    std::sort(times.begin(), times.end());
    const double mean = static_cast<double>(times.back() - times.front()) / static_cast<double>(times.size() - 1);
    if (!(mean > 0.0)) continue;
    const double limit = std::max(options_.interval_factor * mean, options_.min_hole_s * 1e6);
    for (size_t i = 1; i < times.size(); ++i) {
      const int64_t step = times[i] - times[i - 1];
      if (static_cast<double>(step) <= limit) continue;
      LogHole hole;
      hole.channel = channel;
      hole.from_timestamp = times[i - 1];
      hole.to_timestamp = times[i];
      hole.expected_messages = static_cast<int64_t>(static_cast<double>(step) / mean) - 1;
      out.push_back(hole);
    }
  }
  return out;
}

std::string format_log_holes(const std::vector<LogHole>& holes) {
  std::string text;
  char line[256];
  for (const LogHole& h : holes) {
    std::snprintf(line, sizeof(line), "%s: no messages for %.3f s (log time %lld to %lld, ~%lld missing)\n",
                  h.channel.c_str(), h.seconds(), static_cast<long long>(h.from_timestamp),
                  static_cast<long long>(h.to_timestamp), static_cast<long long>(h.expected_messages));
    text += line;
  }
  return text;
}

}  // namespace nadir
