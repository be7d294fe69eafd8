#include "processes/ins_bridge/novatel_parser.h"

#include <charconv>
#include <cstdio>
#include <cmath>
#include <string_view>

#include "processes/ins_bridge/crc32.h"
#include "processes/ins_bridge/little_endian.h"

namespace nadir::ins_bridge {
namespace {

constexpr uint8_t kSync0 = 0xAA, kSync1 = 0x44, kSyncLong = 0x12, kSyncShort = 0x13;

bool is_frame_start(uint8_t b) { return b == '#' || b == '%' || b == kSync0; }
// NovAtel ASCII is printable; anything else inside a frame means it was cut.
bool is_ascii_body(uint8_t b) { return b >= 0x20 && b < 0x7F && b != '#' && b != '%'; }
// NovAtel ASCII log names are upper case letters and digits ending in the
// format letter 'A' ("INSPVAA", "BESTPOSA").
bool is_log_name_char(uint8_t b) { return (b >= 'A' && b <= 'Z') || (b >= '0' && b <= '9'); }
// Shorter names do not exist; with the 'A' this keeps a '#' in line noise
// from counting as a sentence.
constexpr size_t kMinLogName = 3;
constexpr size_t kMaxLogName = 32;

int hex_value(uint8_t c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

std::vector<std::string_view> split(std::string_view text, char separator) {
  std::vector<std::string_view> fields;
  size_t begin = 0;
  while (true) {
    const size_t end = text.find(separator, begin);
    if (end == std::string_view::npos) {
      fields.push_back(text.substr(begin));
      return fields;
    }
    fields.push_back(text.substr(begin, end - begin));
    begin = end + 1;
  }
}

// Whole-field numeric conversions; false for empty, partial or overflowing text.
bool to_double(std::string_view s, double* v) {
  if (s.empty()) return false;
  if (s.front() == '+') s.remove_prefix(1);
  const auto r = std::from_chars(s.data(), s.data() + s.size(), *v);
  return r.ec == std::errc() && r.ptr == s.data() + s.size();
}
bool to_float(std::string_view s, float* v) {
  double d;
  if (!to_double(s, &d) || !(std::fabs(d) <= 3.4e38)) return false;
  *v = static_cast<float>(d);
  return true;
}
template <class T>
bool to_uint(std::string_view s, T* v, int base = 10) {
  if (s.empty()) return false;
  const auto r = std::from_chars(s.data(), s.data() + s.size(), *v, base);
  return r.ec == std::errc() && r.ptr == s.data() + s.size();
}

bool decode_pva_fields(const std::vector<std::string_view>& f, InsPva* pva, std::string* why) {
  if (f.size() != 12) {
    *why = "INSPVA body has " + std::to_string(f.size()) + " fields, expected 12";
    return false;
  }
  bool ok = to_uint(f[0], &pva->gps_week) && to_double(f[1], &pva->gps_seconds) &&
            to_double(f[2], &pva->latitude_deg) && to_double(f[3], &pva->longitude_deg) &&
            to_double(f[4], &pva->height_m) && to_double(f[5], &pva->north_velocity) &&
            to_double(f[6], &pva->east_velocity) && to_double(f[7], &pva->up_velocity) &&
            to_double(f[8], &pva->roll_deg) && to_double(f[9], &pva->pitch_deg) &&
            to_double(f[10], &pva->azimuth_deg);
  if (!ok) {
    *why = "INSPVA body has an unparsable number";
    return false;
  }
  if (!ins_status_from_name(std::string(f[11]), &pva->status)) {
    *why = "INSPVA status '" + std::string(f[11]) + "' is not an INS status";
    return false;
  }
  return true;
}

bool decode_stddev_fields(const std::vector<std::string_view>& f, InsStdDev* s, std::string* why) {
  if (f.size() != 14) {
    *why = "INSSTDEV body has " + std::to_string(f.size()) + " fields, expected 14";
    return false;
  }
  uint16_t reserved16 = 0;
  uint32_t reserved32 = 0;
  const bool ok = to_float(f[0], &s->latitude_m) && to_float(f[1], &s->longitude_m) && to_float(f[2], &s->height_m) &&
                  to_float(f[3], &s->north_velocity) && to_float(f[4], &s->east_velocity) &&
                  to_float(f[5], &s->up_velocity) && to_float(f[6], &s->roll_deg) && to_float(f[7], &s->pitch_deg) &&
                  to_float(f[8], &s->azimuth_deg) && to_uint(f[9], &s->extended_status, 16) &&
                  to_uint(f[10], &s->time_since_update) && to_uint(f[11], &reserved16, 16) &&
                  to_uint(f[12], &reserved32, 16) && to_uint(f[13], &reserved32, 16);
  if (!ok) *why = "INSSTDEV body has an unparsable number";
  return ok;
}

void decode_pva_binary(const uint8_t* b, InsPva* pva) {
  pva->gps_week = get_u32(b);
  pva->gps_seconds = get_f64(b + 4);
  pva->latitude_deg = get_f64(b + 12);
  pva->longitude_deg = get_f64(b + 20);
  pva->height_m = get_f64(b + 28);
  pva->north_velocity = get_f64(b + 36);
  pva->east_velocity = get_f64(b + 44);
  pva->up_velocity = get_f64(b + 52);
  pva->roll_deg = get_f64(b + 60);
  pva->pitch_deg = get_f64(b + 68);
  pva->azimuth_deg = get_f64(b + 76);
  pva->status = static_cast<int32_t>(get_u32(b + 84));
}

void decode_stddev_binary(const uint8_t* b, InsStdDev* s) {
  float* fields[] = {&s->latitude_m,    &s->longitude_m, &s->height_m,  &s->north_velocity, &s->east_velocity,
                     &s->up_velocity,   &s->roll_deg,    &s->pitch_deg, &s->azimuth_deg};
  for (int i = 0; i < 9; ++i) *fields[i] = get_f32(b + 4 * i);
  s->extended_status = get_u32(b + 36);
  s->time_since_update = get_u16(b + 40);
}

}  // namespace

void NovatelParser::reset() {
  if (buffer_.size() > start_) {
    const uint64_t left = buffer_.size() - start_;
    if (sentence_start() == Start::kSentence) {
      error(&counts_.truncated, stream_offset_, "partial frame dropped on reopen");
    } else {
      counts_.garbage_bytes += static_cast<int64_t>(left);
    }
    stream_offset_ += left;
  }
  buffer_.clear();
  start_ = 0;
}

NovatelParser::Start NovatelParser::sentence_start() const {
  const size_t n = buffer_.size() - start_;
  const uint8_t* p = buffer_.data() + start_;
  if (p[0] == kSync0) {
    if (n >= 2 && p[1] != kSync1) return Start::kNotASentence;
    if (n < 3) return Start::kNeedMore;
    return p[2] == kSyncLong || p[2] == kSyncShort ? Start::kSentence : Start::kNotASentence;
  }
  size_t end = 1;
  while (end < n && end <= kMaxLogName && is_log_name_char(p[end])) ++end;
  if (end > kMaxLogName) return Start::kNotASentence;
  if (end == n) return Start::kNeedMore;
  const size_t name_size = end - 1;
  const bool named = name_size >= kMinLogName && p[end - 1] == 'A';  // ASCII logs end in the format letter
  return named && (p[end] == ',' || p[end] == ';') ? Start::kSentence : Start::kNotASentence;
}

void NovatelParser::error(int64_t* counter, uint64_t offset, const std::string& what) {
  ++*counter;
  counts_.last_error = "byte " + std::to_string(offset) + ": " + what;
}

void NovatelParser::feed(const uint8_t* data, size_t size, int64_t arrival_us, double byte_time_us,
                         std::vector<NovatelFrame>* out) {
  counts_.bytes += static_cast<int64_t>(size);
  buffer_.insert(buffer_.end(), data, data + size);
  chunk_arrival_us_ = arrival_us;
  byte_time_us_ = byte_time_us;

  while (start_ < buffer_.size()) {
    const uint8_t b = buffer_[start_];
    size_t used = 0;
    Step step = Step::kConsumed;
    if (b == '\r' || b == '\n') {
      used = 1;  // line ends between ASCII frames are not garbage
    } else if (is_frame_start(b)) {
      const Start start = sentence_start();
      if (start == Start::kNeedMore) {
        step = Step::kNeedMore;
      } else if (start == Start::kNotASentence) {
        counts_.garbage_bytes += 1;  // a stray sync byte; what follows is rescanned
        used = 1;
      } else if (b == kSync0) {
        step = try_binary(buffer_[start_ + 2] == kSyncShort, out, &used);
      } else {
        step = try_ascii(out, &used);
      }
    } else {
      // Skip the whole run up to the next possible frame start at once.
      size_t end = start_ + 1;
      while (end < buffer_.size() && !is_frame_start(buffer_[end]) && buffer_[end] != '\r' && buffer_[end] != '\n')
        ++end;
      counts_.garbage_bytes += static_cast<int64_t>(end - start_);
      used = end - start_;
    }
    if (step == Step::kNeedMore) break;
    start_ += used;
    stream_offset_ += used;
  }
  // Compact: keep only the unconsumed tail.
  if (start_ > 0) {
    buffer_.erase(buffer_.begin(), buffer_.begin() + static_cast<long>(start_));
    start_ = 0;
  }
}

NovatelParser::Step NovatelParser::try_ascii(std::vector<NovatelFrame>* out, size_t* used) {
  const size_t n = buffer_.size() - start_;
  const uint8_t* p = buffer_.data() + start_;
  size_t star = 1;
  while (star < n && p[star] != '*') {
    if (!is_ascii_body(p[star])) {
      error(&counts_.truncated, stream_offset_, "ASCII frame cut off after " + std::to_string(star) + " bytes");
      *used = star;
      return Step::kConsumed;
    }
    if (star >= kMaxAsciiFrame) {
      error(&counts_.truncated, stream_offset_, "ASCII frame longer than " + std::to_string(kMaxAsciiFrame));
      *used = star;
      return Step::kConsumed;
    }
    ++star;
  }
  if (star >= n) return Step::kNeedMore;
  // Eight hex digits of CRC follow the '*'.
  uint32_t crc = 0;
  for (size_t i = 1; i <= 8; ++i) {
    if (star + i >= n) return Step::kNeedMore;
    const int digit = hex_value(p[star + i]);
    if (digit < 0) {
      error(&counts_.truncated, stream_offset_ + star + i, "ASCII CRC field cut off");
      *used = star + i;
      return Step::kConsumed;
    }
    crc = (crc << 4) | static_cast<uint32_t>(digit);
  }
  const size_t frame_size = star + 9;
  *used = frame_size;
  const uint32_t computed = novatel_crc32(p + 1, star - 1);
  if (computed != crc) {
    char text[96];
    std::snprintf(text, sizeof text, "ASCII CRC %08x, computed %08x", crc, computed);
    error(&counts_.crc_failures, stream_offset_, text);
    return Step::kConsumed;
  }
  decode_ascii(std::string(reinterpret_cast<const char*>(p), star), frame_size, out);
  return Step::kConsumed;
}

void NovatelParser::decode_ascii(const std::string& text, size_t frame_size, std::vector<NovatelFrame>* out) {
  const bool short_header = text[0] == '%';
  const size_t semicolon = text.find(';');
  if (semicolon == std::string::npos) {
    error(&counts_.field_errors, stream_offset_, "ASCII frame has no ';' between header and body");
    return;
  }
  const std::vector<std::string_view> header = split(std::string_view(text).substr(1, semicolon - 1), ',');
  const std::vector<std::string_view> body = split(std::string_view(text).substr(semicolon + 1), ',');
  const size_t expected_header = short_header ? 3 : 10;
  std::string name(header[0]);
  if (header.size() != expected_header) {
    error(&counts_.field_errors, stream_offset_,
          name + " header has " + std::to_string(header.size()) + " fields, expected " +
              std::to_string(expected_header));
    return;
  }
  name.pop_back();  // the format letter 'A' (sentence_start checked it)
  NovatelFrame frame;
  frame.format = short_header ? NovatelFormat::kShortAscii : NovatelFormat::kAscii;
  std::string why;
  if (name == "INSPVA" || name == "INSPVAS") {
    frame.kind = NovatelFrame::Kind::kInsPva;
    if (!decode_pva_fields(body, &frame.pva, &why) || !(why = check_limits(frame.pva)).empty()) {
      error(&counts_.field_errors, stream_offset_, why);
      return;
    }
  } else if (name == "INSSTDEV") {
    frame.kind = NovatelFrame::Kind::kInsStdDev;
    const std::string_view week = header[short_header ? 1 : 5];
    const std::string_view seconds = header[short_header ? 2 : 6];
    if (!to_uint(week, &frame.stddev.gps_week) || !to_double(seconds, &frame.stddev.gps_seconds)) {
      error(&counts_.field_errors, stream_offset_, "INSSTDEV header time is unparsable");
      return;
    }
    if (!decode_stddev_fields(body, &frame.stddev, &why) || !(why = check_limits(frame.stddev)).empty()) {
      error(&counts_.field_errors, stream_offset_, why);
      return;
    }
  } else {
    error(&counts_.unknown_messages, stream_offset_, "log '" + name + "' is not used by the bridge");
    return;
  }
  emit(frame, frame_size, out);
}

NovatelParser::Step NovatelParser::try_binary(bool short_header, std::vector<NovatelFrame>* out, size_t* used) {
  const size_t n = buffer_.size() - start_;
  const uint8_t* p = buffer_.data() + start_;
  const size_t min_header = short_header ? kShortBinaryHeaderSize : kBinaryHeaderSize;
  if (n < min_header) return Step::kNeedMore;
  size_t header_size = min_header;
  size_t body_size = 0;
  uint16_t id = 0;
  if (short_header) {
    body_size = p[3];
    id = get_u16(p + 4);
  } else {
    header_size = p[3];
    id = get_u16(p + 4);
    body_size = get_u16(p + 8);
    // Later firmware may grow the header; anything shorter or absurdly long is damage.
    if (header_size < kBinaryHeaderSize || header_size > 64) {
      error(&counts_.bad_length, stream_offset_, "binary header length " + std::to_string(header_size));
      *used = 1;
      return Step::kConsumed;
    }
  }
  const bool is_pva = id == kInspvaId || id == kInspvasId;
  const bool is_stddev = id == kInsstdevId;
  const size_t expected = is_pva ? kInspvaBodySize : is_stddev ? kInsstdevBodySize : 0;
  if ((expected != 0 && body_size != expected) || (expected == 0 && body_size > kMaxUnknownBinaryBody)) {
    error(&counts_.bad_length, stream_offset_,
          "binary log " + std::to_string(id) + " body length " + std::to_string(body_size) +
              (expected ? ", expected " + std::to_string(expected) : std::string(" too long")));
    *used = 1;  // the length may be the damaged part: rescan from the next byte
    return Step::kConsumed;
  }
  const size_t frame_size = header_size + body_size + 4;
  if (n < frame_size) return Step::kNeedMore;
  const uint32_t crc = get_u32(p + header_size + body_size);
  const uint32_t computed = novatel_crc32(p, header_size + body_size);
  if (crc != computed) {
    char text[96];
    std::snprintf(text, sizeof text, "binary CRC %08x, computed %08x", crc, computed);
    error(&counts_.crc_failures, stream_offset_, text);
    *used = 1;
    return Step::kConsumed;
  }
  *used = frame_size;
  if (expected == 0) {
    error(&counts_.unknown_messages, stream_offset_, "binary log " + std::to_string(id) + " is not used by the bridge");
    return Step::kConsumed;
  }
  decode_binary(id, short_header, p, header_size, body_size, out);
  return Step::kConsumed;
}

void NovatelParser::decode_binary(uint16_t id, bool short_header, const uint8_t* frame, size_t header_size,
                                  size_t body_size, std::vector<NovatelFrame>* out) {
  NovatelFrame decoded;
  decoded.format = short_header ? NovatelFormat::kShortBinary : NovatelFormat::kBinary;
  const uint8_t* body = frame + header_size;
  std::string why;
  if (id == kInsstdevId) {
    decoded.kind = NovatelFrame::Kind::kInsStdDev;
    decoded.stddev.gps_week = get_u16(frame + (short_header ? 6 : 14));
    decoded.stddev.gps_seconds = static_cast<double>(get_u32(frame + (short_header ? 8 : 16))) * 1e-3;
    decode_stddev_binary(body, &decoded.stddev);
    why = check_limits(decoded.stddev);
  } else {
    decoded.kind = NovatelFrame::Kind::kInsPva;
    decode_pva_binary(body, &decoded.pva);
    why = check_limits(decoded.pva);
  }
  if (!why.empty()) {
    error(&counts_.field_errors, stream_offset_, why);
    return;
  }
  emit(decoded, header_size + body_size + 4, out);
}

void NovatelParser::emit(NovatelFrame frame, size_t frame_size, std::vector<NovatelFrame>* out) {
  frame.size = frame_size;
  frame.offset = stream_offset_;
  // Bytes after this frame in the buffer arrived after it, one character time each.
  const size_t after = buffer_.size() - start_ - frame_size;
  frame.end_arrival_us = chunk_arrival_us_ - std::llround(static_cast<double>(after) * byte_time_us_);
  frame.start_arrival_us = frame.end_arrival_us - std::llround(static_cast<double>(frame_size) * byte_time_us_);
  ++counts_.frames;
  out->push_back(frame);
}

}  // namespace nadir::ins_bridge
