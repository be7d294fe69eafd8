#include "common/json_writer.h"

#include <cmath>
#include <cstdio>

namespace nadir {

std::string json_escape(const std::string& text) {
  std::string out;
  for (const char c : text) {
    switch (c) {
      case '"': out += "\\\""; break;
      case '\\': out += "\\\\"; break;
      case '\n': out += "\\n"; break;
      case '\t': out += "\\t"; break;
      default:
        if (static_cast<unsigned char>(c) < 0x20) {
          char buf[8];
          std::snprintf(buf, sizeof(buf), "\\u%04x", c);
          out += buf;
        } else {
          out += c;
        }
    }
  }
  return out;
}

void JsonWriter::separator() {
  if (after_key_) {
    after_key_ = false;
    return;
  }
  if (!first_.empty()) {
    if (!first_.back()) out_ << ",";
    first_.back() = false;
  }
}

JsonWriter& JsonWriter::begin_object() {
  separator();
  out_ << "{";
  first_.push_back(true);
  return *this;
}
JsonWriter& JsonWriter::end_object() {
  out_ << "}";
  first_.pop_back();
  return *this;
}
JsonWriter& JsonWriter::begin_array() {
  separator();
  out_ << "[";
  first_.push_back(true);
  return *this;
}
JsonWriter& JsonWriter::end_array() {
  out_ << "]";
  first_.pop_back();
  return *this;
}
JsonWriter& JsonWriter::key(const std::string& name) {
  separator();
  out_ << "\"" << json_escape(name) << "\":";
  after_key_ = true;
  return *this;
}
JsonWriter& JsonWriter::value(const std::string& text) {
  separator();
  out_ << "\"" << json_escape(text) << "\"";
  return *this;
}
JsonWriter& JsonWriter::value(double number) {
  separator();
  if (std::isfinite(number)) {
    char buf[32];
    std::snprintf(buf, sizeof(buf), "%.10g", number);
    out_ << buf;
  } else {
    out_ << "null";
  }
  return *this;
}
JsonWriter& JsonWriter::value(int64_t number) {
  separator();
  out_ << number;
  return *this;
}
JsonWriter& JsonWriter::value(bool flag) {
  separator();
  out_ << (flag ? "true" : "false");
  return *this;
}

}  // namespace nadir
