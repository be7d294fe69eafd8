#include "common/bus.h"

#include <exception>
#include <sstream>

namespace nadir {

void Bus::note_malformed(const std::string& channel, size_t size, const std::string& reason) {
  ++errors_.malformed;
  std::ostringstream text;
  text << "malformed message on " << channel << ": " << size << " bytes: " << reason;
  errors_.last_error = text.str();
}

void Bus::deliver_guarded(const std::string& channel, const std::function<void()>& call) {
  try {
    call();
  } catch (const std::exception& e) {
    ++errors_.handler_errors;
    errors_.last_error = "handler for " + channel + " failed: " + e.what();
  }
}

bool encoded_utime(const uint8_t* data, size_t size, int64_t* utime) {
  // Encoded LCM struct: 8-byte fingerprint, then fields in order, big-endian.
  if (size < 16) return false;
  uint64_t value = 0;
  for (int i = 0; i < 8; ++i) value = (value << 8) | data[8 + i];
  *utime = static_cast<int64_t>(value);
  return true;
}

}  // namespace nadir
