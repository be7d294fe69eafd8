#pragma once
// Reading and writing LCM log files (the lcm-logger format: a sequence of
// events, each: sync word 0xEDA1DA01, event number, timestamp, channel length,
// data length, channel, data; big-endian; no index).
//
// The reader survives damage: a record is accepted only when it is followed by
// the next sync word or the end of the file. Anything else is skipped up to
// the next sync word, counted, and reported with its byte offset. A record cut
// short by the end of the file is reported as truncation.

#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

namespace nadir {

struct LogEvent {
  int64_t event_number = 0;
  int64_t timestamp = 0;      // logger's receive time, microseconds
  std::string channel;
  const uint8_t* data = nullptr;  // valid until the reader is destroyed
  size_t size = 0;
  uint64_t offset = 0;        // byte offset of the record's sync word
};

struct LogDamage {
  uint64_t offset = 0;        // where the damage starts
  uint64_t skipped_bytes = 0; // bytes passed over to the next sync word (or end)
  std::string what;
};

class LogReader {
 public:
  // Throws std::runtime_error naming the file when it cannot be opened.
  explicit LogReader(const std::string& path);
  ~LogReader();
  LogReader(const LogReader&) = delete;
  LogReader& operator=(const LogReader&) = delete;

  // Next good event; false at the end of the file.
  bool next(LogEvent* event);
  void rewind() { position_ = 0; }

  const std::string& path() const { return path_; }
  uint64_t size() const { return size_; }
  uint64_t position() const { return position_; }
  const std::vector<LogDamage>& damage() const { return damage_; }
  int64_t corrupt_records() const { return static_cast<int64_t>(damage_.size()); }
  bool truncated() const { return truncated_; }
  // "FILE: byte N: what" lines, one per damage.
  std::string damage_report() const;

 private:
  bool record_fits_at(uint64_t offset, LogEvent* event, std::string* why) const;
  uint64_t find_sync(uint64_t from) const;

  std::string path_;
  const uint8_t* map_ = nullptr;
  uint64_t size_ = 0;
  uint64_t position_ = 0;
  bool truncated_ = false;
  std::vector<LogDamage> damage_;
};

class LogWriter {
 public:
  // Throws std::runtime_error naming the file when it cannot be created.
  explicit LogWriter(const std::string& path);
  ~LogWriter();
  LogWriter(const LogWriter&) = delete;
  LogWriter& operator=(const LogWriter&) = delete;

  void write(int64_t timestamp, const std::string& channel, const uint8_t* data, size_t size);
  void flush();
  int64_t events() const { return next_event_; }
  const std::string& path() const { return path_; }

 private:
  std::string path_;
  std::FILE* file_ = nullptr;
  int64_t next_event_ = 0;
};

}  // namespace nadir
