#pragma once
// Compares one channel of two logs message by message (paired in sensor-time
// order): how many payloads are byte-identical and, for POSE, the largest
// numeric difference. Used to check live runs against lockstep replay.

#include <cstdint>
#include <string>

namespace nadir {

struct ChannelComparison {
  std::string channel;
  int64_t count_a = 0;
  int64_t count_b = 0;
  int64_t identical = 0;        // byte-identical payloads among the pairs
  int64_t utime_mismatches = 0; // pairs whose sensor times differ
  double max_abs_difference = 0;  // POSE: position, velocity, attitude fields
  bool within(double tolerance) const;
};

ChannelComparison compare_channel(const std::string& log_a, const std::string& log_b, const std::string& channel);
std::string comparison_json(const ChannelComparison& c, double tolerance);

}  // namespace nadir
