#include "tools/log/log_compare.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "common/bus.h"
#include "common/channels.h"
#include "common/json_writer.h"
#include "common/log_file.h"
#include "common/message_guard.h"
#include "nadir/pose_t.hpp"

namespace nadir {
namespace {

struct Payload {
  int64_t utime;
  std::vector<uint8_t> bytes;
};

std::vector<Payload> read_channel(const std::string& path, const std::string& channel) {
  LogReader reader(path);
  LogEvent e;
  std::vector<Payload> out;
  while (reader.next(&e)) {
    if (e.channel != channel) continue;
    Payload p{0, std::vector<uint8_t>(e.data, e.data + e.size)};
    encoded_utime(e.data, e.size, &p.utime);
    out.push_back(std::move(p));
  }
  std::stable_sort(out.begin(), out.end(), [](const Payload& a, const Payload& b) { return a.utime < b.utime; });
  return out;
}

double pose_difference(const Payload& a, const Payload& b) {
  pose_t pa{}, pb{};
  std::string reason;
  if (!decode_message(a.bytes.data(), a.bytes.size(), &pa, &reason) ||
      !decode_message(b.bytes.data(), b.bytes.size(), &pb, &reason)) {
    return INFINITY;
  }
  double d = 0;
  for (int i = 0; i < 3; ++i) {
    d = std::max(d, std::fabs(pa.position_ned[i] - pb.position_ned[i]));
    d = std::max(d, std::fabs(pa.velocity_ned[i] - pb.velocity_ned[i]));
  }
  d = std::max({d, std::fabs(pa.roll - pb.roll), std::fabs(pa.pitch - pb.pitch), std::fabs(pa.yaw - pb.yaw),
                std::fabs(pa.height_agl_m - pb.height_agl_m)});
  return d;
}

}  // namespace

bool ChannelComparison::within(double tolerance) const {
  return count_a == count_b && utime_mismatches == 0 && max_abs_difference <= tolerance;
}

ChannelComparison compare_channel(const std::string& log_a, const std::string& log_b, const std::string& channel) {
  const auto a = read_channel(log_a, channel);
  const auto b = read_channel(log_b, channel);
  ChannelComparison c;
  c.channel = channel;
  c.count_a = static_cast<int64_t>(a.size());
  c.count_b = static_cast<int64_t>(b.size());
  const size_t n = std::min(a.size(), b.size());
  for (size_t i = 0; i < n; ++i) {
    if (a[i].utime != b[i].utime) ++c.utime_mismatches;
    if (a[i].bytes == b[i].bytes) {
      ++c.identical;
    } else if (channel == channels::kPose) {
      c.max_abs_difference = std::max(c.max_abs_difference, pose_difference(a[i], b[i]));
    } else {
      c.max_abs_difference = INFINITY;  // no numeric comparison for this type
    }
  }
  return c;
}

std::string comparison_json(const ChannelComparison& c, double tolerance) {
  JsonWriter j;
  j.begin_object().field("channel", c.channel).field("count_a", c.count_a).field("count_b", c.count_b);
  j.field("identical", c.identical).field("utime_mismatches", c.utime_mismatches);
  j.field("max_abs_difference", c.max_abs_difference).field("tolerance", tolerance);
  j.field("match", c.within(tolerance)).end_object();
  return j.str();
}

}  // namespace nadir
