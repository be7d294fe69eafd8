#pragma once
// Per-channel summary of an LCM log (like `rosbag info`).

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "common/capture_accounting.h"
#include "common/log_file.h"
#include "common/log_holes.h"

namespace nadir {

struct ChannelSummary {
  std::string type;
  int64_t messages = 0;
  int64_t bytes = 0;
  int64_t first_utime = 0;   // sensor time of the first message (utime field)
  int64_t last_utime = 0;
  int64_t first_timestamp = 0;  // log (receive) time
  int64_t last_timestamp = 0;
  double rate_hz() const;
};

struct LogSummary {
  std::string path;
  uint64_t file_bytes = 0;
  int64_t events = 0;
  int64_t first_timestamp = 0;
  int64_t last_timestamp = 0;
  int64_t corrupt_records = 0;
  bool truncated = false;
  std::string damage_report;
  std::vector<LogHole> holes;  // stretches of log time a regular channel has no messages for
  // A photo flight's channels, irregular by nature: one summary each instead of holes.
  std::vector<ChannelIntervals> photo_intervals;
  CaptureAccounting accounting;  // the capture against its publishers' STATUS counts
  std::map<std::string, ChannelSummary> channels;
};

// Reads the whole log; throws std::runtime_error naming the file if unreadable.
LogSummary summarize_log(const std::string& path);
std::string format_log_summary(const LogSummary& summary);
std::string log_summary_json(const LogSummary& summary);

}  // namespace nadir
