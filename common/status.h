#pragma once
// What a node reports once a second, and the STATUS message built from it.

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "common/bus.h"
#include "nadir/status_t.hpp"

namespace nadir {

struct StatusReport {
  int8_t state = status_t::STATE_OK;
  std::string detail;          // why state is not OK
  int64_t received = 0;
  int64_t published = 0;
  int64_t dropped = 0;
  int64_t errors = 0;
  // Process-specific counters and estimator state, e.g. {"clock_offset_us", 12.5}.
  std::vector<std::pair<std::string, double>> counters;

  // The value of the counter called name; empty when the report has none.
  std::optional<double> counter(const std::string& name) const;
};

// Latencies (sensor time -> publish) collected over one status period.
class LatencyWindow {
 public:
  void add_ms(double latency_ms);
  // p50, p99 and max over the samples since the last call; zeros when empty.
  void take(float* p50_ms, float* p99_ms, float* max_ms);
  // All samples ever added (for end-of-run summaries), capped in size.
  const std::vector<float>& history() const { return history_; }

 private:
  std::vector<float> period_;
  std::vector<float> history_;
};

// Percentile (0..100) of a sample set by nearest rank; 0 for an empty set.
float percentile(std::vector<float> values, double pct);

status_t make_status_message(const std::string& name, int32_t pid, int64_t utime, const StatusReport& report,
                             const BusErrorCounts& bus_errors);

// One line for a terminal: "tracker OK rx 140 tx 139 drop 0 err 0".
std::string format_status_line(const status_t& status);

}  // namespace nadir
