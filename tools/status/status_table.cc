#include "tools/status/status_table.h"

#include <cstdio>
#include <sstream>

#include "common/json_writer.h"
#include "common/time_base.h"

namespace nadir {
namespace {
const char* state_name(int8_t state) {
  static const char* kNames[] = {"STARTING", "OK", "WARN", "ERROR", "STOPPING"};
  return state >= 0 && state <= 4 ? kNames[state] : "?";
}
}  // namespace

void StatusTable::update(const status_t& status, int64_t now_us) {
  const std::string key = status.name + "/" + std::to_string(status.pid);
  ProcessRow& row = rows_[key];
  if (row.heard_us != 0 && status.utime > row.last.utime) {
    const double dt = us_to_s(status.utime - row.last.utime);
    row.rx_rate_hz = static_cast<double>(status.received - row.last.received) / dt;
    row.tx_rate_hz = static_cast<double>(status.published - row.last.published) / dt;
  }
  row.last = status;
  row.heard_us = now_us;
}

bool StatusTable::stale(const ProcessRow& row, int64_t now_us) const {
  return us_to_s(now_us - row.heard_us) > stale_after_s_ || row.last.state == status_t::STATE_STOPPING;
}

std::string StatusTable::format(int64_t now_us) const {
  std::ostringstream out;
  char line[512];
  std::snprintf(line, sizeof(line), "%-16s %7s %-8s %6s %8s %8s %7s %7s %9s %8s %8s  %s\n", "process", "pid", "state",
                "alive", "rx/s", "tx/s", "dropped", "errors", "malformed", "p50_ms", "p99_ms", "detail");
  out << line;
  for (const auto& [key, row] : rows_) {
    const status_t& s = row.last;
    std::snprintf(line, sizeof(line), "%-16s %7d %-8s %6s %8.1f %8.1f %7lld %7lld %9lld %8.2f %8.2f  %s\n",
                  s.name.c_str(), s.pid, state_name(s.state), stale(row, now_us) ? "STALE" : "yes", row.rx_rate_hz,
                  row.tx_rate_hz, static_cast<long long>(s.dropped), static_cast<long long>(s.errors),
                  static_cast<long long>(s.malformed), s.latency_p50_ms, s.latency_p99_ms, s.detail.c_str());
    out << line;
  }
  if (rows_.empty()) out << "(no STATUS heard yet)\n";
  return out.str();
}

std::string StatusTable::json(int64_t now_us) const {
  JsonWriter j;
  j.begin_array();
  for (const auto& [key, row] : rows_) {
    const status_t& s = row.last;
    j.begin_object();
    j.field("name", s.name).field("pid", static_cast<int64_t>(s.pid)).field("state", state_name(s.state));
    j.field("alive", !stale(row, now_us)).field("rx_rate_hz", row.rx_rate_hz).field("tx_rate_hz", row.tx_rate_hz);
    j.field("received", s.received).field("published", s.published).field("dropped", s.dropped);
    j.field("errors", s.errors).field("malformed", s.malformed);
    j.field("latency_p50_ms", static_cast<double>(s.latency_p50_ms));
    j.field("latency_p99_ms", static_cast<double>(s.latency_p99_ms));
    j.field("latency_max_ms", static_cast<double>(s.latency_max_ms)).field("detail", s.detail);
    j.key("counters").begin_object();
    for (int i = 0; i < s.num_counters; ++i) j.field(s.counter_names[i], s.counter_values[i]);
    j.end_object();
    j.end_object();
  }
  j.end_array();
  return j.str();
}

}  // namespace nadir
