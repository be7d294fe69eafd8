#include "tools/log/log_summary.h"

#include <cstdio>
#include <sstream>

#include "common/bus.h"
#include "common/json_writer.h"
#include "common/message_types.h"
#include "common/time_base.h"

namespace nadir {

double ChannelSummary::rate_hz() const {
  const double span = us_to_s(last_timestamp - first_timestamp);
  return messages > 1 && span > 0 ? static_cast<double>(messages - 1) / span : 0.0;
}

LogSummary summarize_log(const std::string& path) {
  LogReader reader(path);
  LogSummary s;
  s.path = path;
  s.file_bytes = reader.size();
  LogEvent event;
  LogHoleFinder hole_finder;
  CaptureAccountant accountant;
  while (reader.next(&event)) {
    hole_finder.add(event);
    accountant.add(event);
    if (s.events == 0) s.first_timestamp = event.timestamp;
    s.last_timestamp = event.timestamp;
    ++s.events;
    ChannelSummary& c = s.channels[event.channel];
    int64_t utime = 0;
    const bool has_utime = encoded_utime(event.data, event.size, &utime);
    if (c.messages == 0) {
      c.type = message_type_name(event.data, event.size);
      c.first_timestamp = event.timestamp;
      if (has_utime) c.first_utime = utime;
    }
    ++c.messages;
    c.bytes += static_cast<int64_t>(event.size);
    c.last_timestamp = event.timestamp;
    if (has_utime) c.last_utime = utime;
  }
  s.corrupt_records = reader.corrupt_records();
  s.truncated = reader.truncated();
  s.damage_report = reader.damage_report();
  s.holes = hole_finder.holes();
  s.photo_intervals = hole_finder.irregular_channels();
  s.accounting = accountant.result();
  return s;
}

std::string format_log_summary(const LogSummary& s) {
  std::ostringstream out;
  char line[512];
  out << "path:     " << s.path << "\n";
  std::snprintf(line, sizeof(line), "size:     %.1f MB, %lld events, %.3f s\n", s.file_bytes / 1e6,
                static_cast<long long>(s.events), us_to_s(s.last_timestamp - s.first_timestamp));
  out << line;
  out << "damage:   " << s.corrupt_records << " corrupt record(s)" << (s.truncated ? ", truncated" : "") << "\n";
  out << "holes:    " << s.holes.size() << " (stretches a regular channel has no messages for)\n";
  out << "missing:  " << s.accounting.missing_total() << " message(s) its publishers' STATUS counted but the capture "
      << "lacks; " << s.accounting.udp_rx_drops_total() << " datagram(s) dropped by receivers' kernels\n";
  std::snprintf(line, sizeof(line), "%-16s %-24s %9s %9s %11s %19s %19s\n", "channel", "type", "messages", "rate_hz",
                "MB", "first_utime", "last_utime");
  out << line;
  for (const auto& [name, c] : s.channels) {
    std::snprintf(line, sizeof(line), "%-16s %-24s %9lld %9.2f %11.3f %19lld %19lld\n", name.c_str(), c.type.c_str(),
                  static_cast<long long>(c.messages), c.rate_hz(), c.bytes / 1e6,
                  static_cast<long long>(c.first_utime), static_cast<long long>(c.last_utime));
    out << line;
  }
  if (!s.damage_report.empty()) out << s.damage_report;
  out << format_log_holes(s.holes);
  if (!s.photo_intervals.empty()) {
    out << "intervals: a photo flight (its channels follow the photo times; long intervals are not holes)\n"
        << format_channel_intervals(s.photo_intervals);
  }
  out << format_capture_accounting(s.accounting);
  return out.str();
}

std::string log_summary_json(const LogSummary& s) {
  JsonWriter j;
  j.begin_object();
  j.field("path", s.path).field("bytes", static_cast<int64_t>(s.file_bytes)).field("events", s.events);
  j.field("duration_s", us_to_s(s.last_timestamp - s.first_timestamp));
  j.field("corrupt_records", s.corrupt_records).field("truncated", s.truncated);
  j.key("channels").begin_object();
  for (const auto& [name, c] : s.channels) {
    j.key(name).begin_object();
    j.field("type", c.type).field("messages", c.messages).field("rate_hz", c.rate_hz()).field("bytes", c.bytes);
    j.field("first_utime", c.first_utime).field("last_utime", c.last_utime);
    j.end_object();
  }
  j.end_object();
  j.field("damage", s.damage_report);
  j.key("holes").begin_array();
  for (const LogHole& h : s.holes) {
    j.begin_object().field("channel", h.channel).field("from_timestamp", h.from_timestamp).field("to_timestamp", h.to_timestamp);
    j.field("seconds", h.seconds()).field("expected_messages", h.expected_messages).end_object();
  }
  j.end_array();
  j.key("accounting").begin_object();
  j.field("missing_total", s.accounting.missing_total()).field("udp_rx_drops_total", s.accounting.udp_rx_drops_total());
  j.key("channels").begin_array();
  for (const ChannelAccount& c : s.accounting.channels) {
    j.begin_object().field("channel", c.channel).field("publishers", c.publishers).field("published", c.published);
    j.field("captured", c.captured).field("missing", c.missing()).field("unaccounted", c.unaccounted()).end_object();
  }
  j.end_array();
  j.key("udp_rx_drops").begin_object();
  for (const auto& [name, drops] : s.accounting.udp_rx_drops) j.field(name, drops);
  j.end_object();
  j.end_object();
  j.end_object();
  return j.str();
}

}  // namespace nadir
