#pragma once
// Deterministic lockstep replay (DESIGN.md "Runtime"): the chosen nodes run in
// one process on a ReplayBus. Input events are read in file order and handed
// to subscribers synchronously; whatever the nodes publish is appended to the
// output log (stamped with the input event's timestamp) and delivered in FIFO
// order before the next input event. Same input + same config => same bytes.

#include <cstdint>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "common/bus.h"
#include "common/local_bus.h"
#include "common/log_file.h"
#include "common/node.h"

namespace nadir {

class ReplayBus : public LocalBus {
 public:
  explicit ReplayBus(LogWriter* out) : out_(out) {}

  void set_log_time(int64_t timestamp) { log_time_ = timestamp; }
  int64_t published() const { return published_; }
  const std::map<std::string, int64_t>& published_per_channel() const { return per_channel_; }

 protected:
  // Appends to the output log, stamped with the input event's time.
  void forward(const std::string& channel, const uint8_t* data, size_t size) override;

 private:
  LogWriter* out_;
  int64_t log_time_ = 0;
  int64_t published_ = 0;
  std::map<std::string, int64_t> per_channel_;
};

struct ReplayOptions {
  std::string in_path;
  std::string out_path;
  std::vector<std::string> nodes;
  std::string config_path;      // empty: default_config_path()
  std::vector<std::string> overlays;   // YAML fragments merged into the config in order (Config::apply_overlay)
  std::vector<std::string> overrides;  // "section.key=value", applied in order after the overlays
  bool passthrough = true;      // copy input events into the output log
  bool progress = false;        // progress bar on stderr
  void Check() const;           // throws std::invalid_argument naming the option
};

struct ReplaySummary {
  int64_t events_in = 0;
  int64_t passed_through = 0;
  int64_t replaced_input = 0;   // input events on channels the nodes produce
  int64_t published = 0;
  int64_t corrupt_records = 0;
  bool truncated = false;
  std::string damage_report;
  double log_seconds = 0.0;     // span of the input log's timestamps
  double wall_seconds = 0.0;
  std::map<std::string, int64_t> published_per_channel;
  std::vector<status_t> final_status;  // one per node
};

// Runs a replay; throws std::runtime_error / ConfigError naming the problem.
ReplaySummary run_replay(const ReplayOptions& options, const NodeRegistry& registry);

}  // namespace nadir
