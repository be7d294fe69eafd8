#pragma once
// Byte-stream framer and decoder for NovAtel logs: ASCII ('#', 10-field
// header), short ASCII ('%', 3-field header), binary (AA 44 12, 28-byte
// header) and short binary (AA 44 13, 12-byte header), each with its CRC-32.
// Any byte sequence is accepted: what is not a valid frame is skipped and
// counted, so the stream resynchronises on the next sync. Counting is per
// sentence: a sentence begins with a binary sync (AA 44 12 / AA 44 13) or an
// ASCII sync ('#', '%') followed by a log name (3 or more of A-Z 0-9, the
// last one the format letter 'A') and ',' or ';'; each one ends accepted (a frame) or rejected for exactly one reason
// (CRC, length, fields, unknown log, truncated). Bytes that begin no sentence
// (a stray '#' in line noise included) are garbage, counted as bytes. A frame's time of arrival is
// reconstructed from the read's time and the line's character time.

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "processes/ins_bridge/novatel_messages.h"

namespace nadir::ins_bridge {

struct NovatelFrame {
  enum class Kind { kInsPva, kInsStdDev };
  Kind kind = Kind::kInsPva;
  NovatelFormat format = NovatelFormat::kAscii;
  InsPva pva;            // when kind == kInsPva
  InsStdDev stddev;      // when kind == kInsStdDev
  size_t size = 0;       // bytes on the wire (without trailing CR LF)
  uint64_t offset = 0;   // stream byte offset of its first byte
  int64_t end_arrival_us = 0;  // arrival of its last byte
  int64_t start_arrival_us = 0;  // end minus its transmission time
};

struct NovatelParserCounts {
  int64_t bytes = 0;
  int64_t frames = 0;            // sentences accepted: decoded INS frames handed out
  int64_t garbage_bytes = 0;     // bytes outside any frame (CR/LF between frames excluded)
  int64_t crc_failures = 0;
  int64_t bad_length = 0;        // binary header length / message length impossible
  int64_t truncated = 0;         // a frame cut off by a new sync, a line end or junk
  int64_t field_errors = 0;      // CRC good but wrong field count / unparsable / out of limits
  int64_t unknown_messages = 0;  // CRC good, a log the bridge does not use
  std::string last_error;        // "byte N: what"
  // Every sentence is either a frame or one of these.
  int64_t rejected() const { return crc_failures + bad_length + truncated + field_errors + unknown_messages; }
};

class NovatelParser {
 public:
  // Longest ASCII frame accepted before it is dropped as truncated.
  static constexpr size_t kMaxAsciiFrame = 2048;
  // Longest binary body accepted for logs the bridge does not decode.
  static constexpr size_t kMaxUnknownBinaryBody = 4096;

  // Appends `size` bytes whose last byte arrived at `arrival_us`; one
  // character lasts `byte_time_us` on the line. Completed frames go to `out`.
  void feed(const uint8_t* data, size_t size, int64_t arrival_us, double byte_time_us,
            std::vector<NovatelFrame>* out);
  // Forgets a partial frame (device reopened).
  void reset();
  const NovatelParserCounts& counts() const { return counts_; }

 private:
  enum class Step { kNeedMore, kConsumed };
  enum class Start { kSentence, kNotASentence, kNeedMore };
  // Whether the bytes at start_ begin a sentence (see the file comment).
  Start sentence_start() const;
  Step try_ascii(std::vector<NovatelFrame>* out, size_t* used);
  Step try_binary(bool short_header, std::vector<NovatelFrame>* out, size_t* used);
  void decode_ascii(const std::string& text, size_t frame_size, std::vector<NovatelFrame>* out);
  void decode_binary(uint16_t id, bool short_header, const uint8_t* frame, size_t header_size, size_t body_size,
                     std::vector<NovatelFrame>* out);
  void emit(NovatelFrame frame, size_t frame_size, std::vector<NovatelFrame>* out);
  void error(int64_t* counter, uint64_t offset, const std::string& what);

  std::vector<uint8_t> buffer_;
  size_t start_ = 0;              // first unconsumed byte in buffer_
  uint64_t stream_offset_ = 0;    // stream offset of buffer_[start_]
  int64_t chunk_arrival_us_ = 0;  // arrival of the newest byte
  double byte_time_us_ = 0;
  NovatelParserCounts counts_;
};

}  // namespace nadir::ins_bridge
