#pragma once
// Splits a serial byte stream into CR/LF-terminated lines with their arrival
// times; overlong lines (a missing line end, a baud mismatch) are dropped and
// counted instead of growing without bound.

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace nadir::ins_bridge {

struct SerialLine {
  std::string text;             // without CR/LF
  uint64_t offset = 0;          // stream byte offset of its first byte
  int64_t start_arrival_us = 0; // estimated arrival of its first byte
  int64_t end_arrival_us = 0;   // arrival of its line end
};

class LineSplitter {
 public:
  static constexpr size_t kMaxLine = 256;

  void feed(const uint8_t* data, size_t size, int64_t arrival_us, double byte_time_us, std::vector<SerialLine>* out);
  // Drops a partial line (device reopened); counts it as truncated.
  void reset();

  int64_t bytes() const { return bytes_; }
  int64_t overlong() const { return overlong_; }
  int64_t truncated() const { return truncated_; }

 private:
  std::string current_;
  uint64_t current_offset_ = 0;
  bool discarding_ = false;   // inside an overlong line, until its end
  uint64_t stream_offset_ = 0;
  int64_t bytes_ = 0;
  int64_t overlong_ = 0;
  int64_t truncated_ = 0;
};

}  // namespace nadir::ins_bridge
