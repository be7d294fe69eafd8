#include "common/status.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace nadir {

std::optional<double> StatusReport::counter(const std::string& name) const {
  for (const auto& [key, value] : counters)
    if (key == name) return value;
  return std::nullopt;
}

void LatencyWindow::add_ms(double latency_ms) {
  period_.push_back(static_cast<float>(latency_ms));
  if (history_.size() < 1000000) history_.push_back(static_cast<float>(latency_ms));
}

void LatencyWindow::take(float* p50_ms, float* p99_ms, float* max_ms) {
  *p50_ms = percentile(period_, 50);
  *p99_ms = percentile(period_, 99);
  *max_ms = period_.empty() ? 0.0f : *std::max_element(period_.begin(), period_.end());
  period_.clear();
}

float percentile(std::vector<float> values, double pct) {
  if (values.empty()) return 0.0f;
  const size_t rank = static_cast<size_t>(std::ceil(pct / 100.0 * values.size()));
  const size_t index = std::min(values.size() - 1, rank == 0 ? 0 : rank - 1);
  std::nth_element(values.begin(), values.begin() + static_cast<long>(index), values.end());
  return values[index];
}

status_t make_status_message(const std::string& name, int32_t pid, int64_t utime, const StatusReport& report,
                             const BusErrorCounts& bus_errors) {
  status_t msg{};
  msg.utime = utime;
  msg.name = name;
  msg.pid = pid;
  msg.state = report.state;
  msg.detail = report.detail;
  if (bus_errors.malformed + bus_errors.handler_errors > 0 && msg.state == status_t::STATE_OK) {
    msg.state = status_t::STATE_WARN;
  }
  if (msg.detail.empty()) msg.detail = bus_errors.last_error;
  msg.received = report.received;
  msg.published = report.published;
  msg.dropped = report.dropped;
  msg.errors = report.errors + bus_errors.handler_errors;
  msg.malformed = bus_errors.malformed;
  msg.num_counters = static_cast<int32_t>(report.counters.size());
  for (const auto& [key, value] : report.counters) {
    msg.counter_names.push_back(key);
    msg.counter_values.push_back(value);
  }
  return msg;
}

std::string format_status_line(const status_t& status) {
  static const char* kStates[] = {"STARTING", "OK", "WARN", "ERROR", "STOPPING"};
  std::ostringstream out;
  const int state = status.state;
  out << status.name << " " << (state >= 0 && state <= 4 ? kStates[state] : "?") << " rx " << status.received
      << " tx " << status.published << " drop " << status.dropped << " err " << status.errors << " malformed "
      << status.malformed;
  if (!status.detail.empty()) out << " (" << status.detail << ")";
  return out.str();
}

}  // namespace nadir
