#include "common/log_holes.h"

#include <algorithm>
#include <cstdio>

#include "common/bus.h"

namespace nadir {

void LogHoleFinder::add(const LogEvent& event) {
  int64_t utime = 0;
  if (encoded_utime(event.data, event.size, &utime)) utimes_[event.channel].push_back(utime);
}

std::vector<LogHole> LogHoleFinder::holes() const {
  std::vector<LogHole> out;
  for (const auto& [channel, recorded] : utimes_) {
    if (static_cast<int>(recorded.size()) < options_.min_messages) continue;
    // Sorted: a channel whose publishers reorder a little is still regular.
    std::vector<int64_t> times = recorded;
    std::sort(times.begin(), times.end());
    std::vector<int64_t> steps;
    steps.reserve(times.size());
    for (size_t i = 1; i < times.size(); ++i) {
      if (times[i] > times[i - 1]) steps.push_back(times[i] - times[i - 1]);
    }
    if (steps.empty()) continue;
    std::vector<int64_t> sorted_steps = steps;
    std::nth_element(sorted_steps.begin(), sorted_steps.begin() + static_cast<std::ptrdiff_t>(sorted_steps.size() / 2),
                     sorted_steps.end());
    const int64_t median = sorted_steps[sorted_steps.size() / 2];
    const double limit = std::max(options_.interval_factor * static_cast<double>(median), options_.min_hole_s * 1e6);
    for (size_t i = 1; i < times.size(); ++i) {
      const int64_t step = times[i] - times[i - 1];
      if (static_cast<double>(step) <= limit) continue;
      LogHole hole;
      hole.channel = channel;
      hole.from_utime = times[i - 1];
      hole.to_utime = times[i];
      hole.expected_messages = median > 0 ? step / median - 1 : 0;
      out.push_back(hole);
    }
  }
  return out;
}

std::string format_log_holes(const std::vector<LogHole>& holes) {
  std::string text;
  char line[256];
  for (const LogHole& h : holes) {
    std::snprintf(line, sizeof(line), "%s: no messages for %.3f s of sensor time (utime %lld to %lld, ~%lld missing)\n",
                  h.channel.c_str(), h.seconds(), static_cast<long long>(h.from_utime),
                  static_cast<long long>(h.to_utime), static_cast<long long>(h.expected_messages));
    text += line;
  }
  return text;
}

}  // namespace nadir
