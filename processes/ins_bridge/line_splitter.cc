#include "processes/ins_bridge/line_splitter.h"

#include <cmath>

namespace nadir::ins_bridge {

void LineSplitter::reset() {
  if (!current_.empty()) ++truncated_;
  current_.clear();
  discarding_ = false;
}

void LineSplitter::feed(const uint8_t* data, size_t size, int64_t arrival_us, double byte_time_us,
                        std::vector<SerialLine>* out) {
  bytes_ += static_cast<int64_t>(size);
  for (size_t i = 0; i < size; ++i, ++stream_offset_) {
    const char c = static_cast<char>(data[i]);
    if (c == '\n' || c == '\r') {
      if (!discarding_ && !current_.empty()) {
        SerialLine line;
        line.text = current_;
        line.offset = current_offset_;
        line.end_arrival_us = arrival_us - std::llround(static_cast<double>(size - 1 - i) * byte_time_us);
        line.start_arrival_us =
            line.end_arrival_us - std::llround(static_cast<double>(current_.size()) * byte_time_us);
        out->push_back(std::move(line));
      }
      current_.clear();
      discarding_ = false;
      continue;
    }
    if (discarding_) continue;
    if (current_.empty()) current_offset_ = stream_offset_;
    if (current_.size() >= kMaxLine) {
      ++overlong_;
      current_.clear();
      discarding_ = true;
      continue;
    }
    current_.push_back(c);
  }
}

}  // namespace nadir::ins_bridge
