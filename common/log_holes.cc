#include "common/log_holes.h"

#include <algorithm>
#include <cstdio>

#include "common/channels.h"
#include "common/message_guard.h"
#include "nadir/config_t.hpp"
#include "nadir/status_t.hpp"

namespace nadir {

namespace {

// The CONFIG nadir_import writes for a photo folder (tools/import: name
// "import", its YAML's `mode: photos`).
bool is_photo_import_config(const LogEvent& event) {
  config_t config;
  std::string reason;
  return decode_message(event.data, event.size, &config, &reason) && config.name == "import" &&
         config.yaml.find("mode: photos") != std::string::npos;
}

}  // namespace

void LogHoleFinder::add(const LogEvent& event) {
  if (event.channel == channels::kConfig && is_photo_import_config(event)) photo_intervals_ = true;
  // VO_GROUND comes only for frames whose own depths the solver trusts: a
  // silence is ground not seen (featureless, a restart), not a lost message.
  if (event.channel == channels::kVoGround) return;
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

template <class Visit>
void LogHoleFinder::for_each_judged(Visit visit) const {
  for (const auto& [channel, recorded] : timestamps_) {
    // CONFIG comes once per process start, MAP_FIX only where the map
    // matcher trusts a match: never regular streams.
    if (channel == channels::kConfig || channel == channels::kMapFix ||
        static_cast<int>(recorded.size()) < options_.min_messages)
      continue;
    // Sorted: lcm-logger writes in arrival order, which several publishers
    // on one channel may interleave a little. The mean interval, not the
    // median: a channel with several publishers has bursts of short
    // intervals and long ones between them.
    std::vector<int64_t> times = recorded;
    std::sort(times.begin(), times.end());
    const double mean = static_cast<double>(times.back() - times.front()) / static_cast<double>(times.size() - 1);
    if (!(mean > 0.0)) continue;
    visit(channel, times, std::max(options_.interval_factor * mean, options_.min_hole_s * 1e6), mean);
  }
}

std::vector<LogHole> LogHoleFinder::holes() const {
  std::vector<LogHole> out;
  if (photo_intervals_) return out;
  for_each_judged([&](const std::string& channel, const std::vector<int64_t>& times, double limit, double mean) {
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
  });
  return out;
}

std::vector<ChannelIntervals> LogHoleFinder::irregular_channels() const {
  std::vector<ChannelIntervals> out;
  if (!photo_intervals_) return out;
  for_each_judged([&](const std::string& channel, const std::vector<int64_t>& times, double, double) {
    std::vector<int64_t> steps;
    for (size_t i = 1; i < times.size(); ++i) steps.push_back(times[i] - times[i - 1]);
    std::sort(steps.begin(), steps.end());
    ChannelIntervals c;
    c.channel = channel;
    c.intervals = static_cast<int64_t>(steps.size());
    c.median_s = static_cast<double>(steps[steps.size() / 2]) * 1e-6;
    c.max_s = static_cast<double>(steps.back()) * 1e-6;
    c.gap_limit_s = std::max(2.0 * c.median_s, options_.min_hole_s);
    for (int64_t step : steps) c.gaps += static_cast<double>(step) * 1e-6 > c.gap_limit_s ? 1 : 0;
    out.push_back(c);
  });
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

std::string format_channel_interval(const ChannelIntervals& c) {
  char line[256];
  std::snprintf(line, sizeof(line), "%s: %lld intervals, median %.1f s, max %.1f s, %lld gap%s over %.1f s",
                c.channel.c_str(), static_cast<long long>(c.intervals), c.median_s, c.max_s,
                static_cast<long long>(c.gaps), c.gaps == 1 ? "" : "s", c.gap_limit_s);
  return line;
}

std::string format_channel_intervals(const std::vector<ChannelIntervals>& channels) {
  std::string text;
  for (const ChannelIntervals& c : channels) text += format_channel_interval(c) + "\n";
  return text;
}

}  // namespace nadir
