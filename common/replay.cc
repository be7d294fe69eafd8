#include "common/replay.h"

#include <algorithm>
#include <stdexcept>

#include "common/channels.h"
#include "common/message_guard.h"
#include "common/paths.h"
#include "common/process_main.h"
#include "common/progress.h"
#include "common/time_base.h"
#include "nadir/config_t.hpp"
#include "nadir/status_t.hpp"

namespace nadir {

void ReplayBus::forward(const std::string& channel, const uint8_t* data, size_t size) {
  if (out_ != nullptr) out_->write(log_time_, channel, data, size);
  ++published_;
  ++per_channel_[channel];
}

void ReplayOptions::Check() const {
  if (in_path.empty()) throw std::invalid_argument("--in: an input log is required");
  if (out_path.empty()) throw std::invalid_argument("--out: an output log is required");
  if (in_path == out_path) throw std::invalid_argument("--out must differ from --in");
  if (nodes.empty()) throw std::invalid_argument("--nodes: name at least one node");
  std::set<std::string> seen;
  for (const auto& n : nodes) {
    if (!seen.insert(n).second) throw std::invalid_argument("--nodes: '" + n + "' is named twice");
  }
}

namespace {

// True for CONFIG/STATUS input events that belong to a node being replayed:
// the replay writes its own.
bool is_replaced_bookkeeping(const LogEvent& event, const std::set<std::string>& node_names) {
  if (event.channel == channels::kConfig) {
    config_t msg;
    std::string reason;
    return decode_message(event.data, event.size, &msg, &reason) && node_names.count(msg.name) != 0;
  }
  if (event.channel == channels::kStatus) {
    status_t msg;
    std::string reason;
    return decode_message(event.data, event.size, &msg, &reason) && node_names.count(msg.name) != 0;
  }
  return false;
}

}  // namespace

ReplaySummary run_replay(const ReplayOptions& options, const NodeRegistry& registry) {
  options.Check();
  for (const auto& name : options.nodes) {
    if (registry.find(name) == nullptr) {
      std::string known;
      for (const auto& n : registry.names()) known += (known.empty() ? "" : ", ") + n;
      throw std::invalid_argument("--nodes: unknown node '" + name + "' (known: " + known + ")");
    }
  }
  const std::string config_path = options.config_path.empty() ? default_config_path() : options.config_path;
  Config config = Config::load_file(config_path);
  for (const auto& path : options.overlays) config.apply_overlay(Config::load_file(path));
  for (const auto& o : options.overrides) config.apply_override(o);

  LogReader reader(options.in_path);
  LogWriter writer(options.out_path);
  ReplayBus bus(&writer);

  std::vector<std::unique_ptr<Node>> nodes;
  std::set<std::string> produced;
  std::set<std::string> node_names(options.nodes.begin(), options.nodes.end());
  for (const auto& name : options.nodes) {
    nodes.push_back((*registry.find(name))(config, bus));
    for (const auto& ch : nodes.back()->output_channels()) produced.insert(ch);
  }

  ReplaySummary summary;
  const int64_t wall_start = monotonic_now_us();
  ProgressBar bar("replay", static_cast<double>(reader.size()), options.progress);
  LogEvent event;
  bool first = true;
  int64_t first_ts = 0;
  int64_t last_ts = 0;
  int64_t next_tick = 0;
  auto publish_status = [&](int64_t log_time) {
    for (const auto& node : nodes) {
      // pid 0 and no latency: replay STATUS must be deterministic.
      bus.publish(channels::kStatus, make_status_message(node->name(), 0, log_time, node->status(), bus.error_counts()));
    }
  };
  while (reader.next(&event)) {
    ++summary.events_in;
    if (first) {
      first = false;
      first_ts = event.timestamp;
      next_tick = first_ts + 1000000;
      bus.set_log_time(event.timestamp);
      for (const auto& node : nodes) publish_config(bus, node->name(), config, event.timestamp);
    }
    // Timestamps in a captured log are receive times and may step back a
    // little; the replay clock never does.
    last_ts = std::max(last_ts, event.timestamp);
    bus.set_log_time(last_ts);
    while (last_ts >= next_tick) {
      for (const auto& node : nodes) node->on_tick(next_tick);
      publish_status(next_tick);
      next_tick += 1000000;
    }
    if (produced.count(event.channel) != 0 || is_replaced_bookkeeping(event, node_names)) {
      ++summary.replaced_input;
      continue;
    }
    if (options.passthrough) {
      writer.write(event.timestamp, event.channel, event.data, event.size);
      ++summary.passed_through;
    }
    bus.deliver(event.channel, event.data, event.size);
    bar.update(static_cast<double>(reader.position()));
  }
  if (!first) publish_status(last_ts);
  bar.finish();
  writer.flush();

  if (summary.events_in == 0) {
    throw std::runtime_error(options.in_path + ": no LCM events in " + std::to_string(reader.size()) +
                             " bytes (not an lcm-logger log?)" +
                             (reader.damage_report().empty() ? "" : "\n" + reader.damage_report()));
  }
  summary.published = bus.published();
  summary.published_per_channel = bus.published_per_channel();
  summary.corrupt_records = reader.corrupt_records();
  summary.truncated = reader.truncated();
  summary.damage_report = reader.damage_report();
  summary.log_seconds = us_to_s(last_ts - first_ts);
  summary.wall_seconds = us_to_s(monotonic_now_us() - wall_start);
  for (const auto& node : nodes) {
    summary.final_status.push_back(make_status_message(node->name(), 0, last_ts, node->status(), bus.error_counts()));
  }
  return summary;
}

}  // namespace nadir
