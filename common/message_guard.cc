#include "common/message_guard.h"

#include <exception>

#include "nadir/altimeter_t.hpp"
#include "nadir/config_t.hpp"
#include "nadir/ground_truth_t.hpp"
#include "nadir/image_t.hpp"
#include "nadir/ins_t.hpp"
#include "nadir/pose_t.hpp"
#include "nadir/status_t.hpp"
#include "nadir/tracks_t.hpp"
#include "nadir/trigger_t.hpp"
#include "nadir/vo_delta_t.hpp"

namespace nadir {
namespace {

// Walks an encoded message (big-endian, no padding) field by field.
class Walker {
 public:
  Walker(const uint8_t* data, size_t size, std::string* reason) : data_(data), size_(size), reason_(reason) {}

  bool skip(size_t bytes, const char* field) {
    if (bytes > size_ - pos_) return fail(std::string(field) + ": needs " + std::to_string(bytes) + " bytes at offset " +
                                          std::to_string(pos_) + ", " + std::to_string(size_ - pos_) + " left");
    pos_ += bytes;
    return true;
  }

  // An element count, which must not be negative.
  bool count(const char* count_field, int32_t* count) {
    if (!read_i32(count_field, count)) return false;
    if (*count < 0) return fail(std::string(count_field) + " is negative (" + std::to_string(*count) + ")");
    return true;
  }

  // An array count; the array's elements of `element_bytes` each must fit.
  bool array(const char* count_field, size_t element_bytes, int32_t* count) {
    if (!this->count(count_field, count)) return false;
    const uint64_t need = static_cast<uint64_t>(*count) * element_bytes;
    if (need > size_ - pos_) {
      return fail(std::string(count_field) + " " + std::to_string(*count) + " declares " + std::to_string(need) +
                  " bytes, " + std::to_string(size_ - pos_) + " left");
    }
    pos_ += static_cast<size_t>(need);
    return true;
  }

  // An LCM string: int32 length including the terminating zero, then bytes.
  bool string(const char* field) {
    int32_t length = 0;
    if (!read_i32(field, &length)) return false;
    if (length < 1) return fail(std::string(field) + ": string length " + std::to_string(length) + " < 1");
    return skip(static_cast<size_t>(length), field);
  }

  bool read_i32(const char* field, int32_t* value) {
    if (4 > size_ - pos_) return fail(std::string(field) + ": truncated at offset " + std::to_string(pos_));
    uint32_t v = 0;
    for (int i = 0; i < 4; ++i) v = (v << 8) | data_[pos_ + i];
    *value = static_cast<int32_t>(v);
    pos_ += 4;
    return true;
  }

  bool at_end() {
    if (pos_ != size_) return fail(std::to_string(size_ - pos_) + " bytes after the last field");
    return true;
  }

 private:
  bool fail(const std::string& why) {
    *reason_ = why;
    return false;
  }
  const uint8_t* data_;
  size_t size_;
  size_t pos_ = 8;  // after the fingerprint
  std::string* reason_;
};

bool walk_image(Walker& w) {
  int32_t count = 0;
  return w.skip(4 * 8 + 3 * 4 + 2 * 1 + 2 * 4, "image_t header") && w.array("image_t.size", 1, &count) && w.at_end();
}

bool walk_tracks(Walker& w) {
  // Per track: id (8), age (4), prev_px and curr_px (2 x 2 x 4), prev_norm and curr_norm (2 x 2 x 8).
  int32_t count = 0;
  return w.skip(3 * 8 + 3 * 4, "tracks_t header") && w.array("tracks_t.num_tracks", 8 + 4 + 16 + 32, &count) &&
         w.at_end();
}

bool walk_status(Walker& w) {
  if (!(w.skip(8, "status_t.utime") && w.string("status_t.name") && w.skip(4 + 1, "status_t.pid/state") &&
        w.string("status_t.detail") && w.skip(5 * 8 + 3 * 4, "status_t counters"))) {
    return false;
  }
  int32_t count = 0;
  if (!w.count("status_t.num_counters", &count)) return false;
  for (int32_t i = 0; i < count; ++i) {
    if (!w.string("status_t.counter_names")) return false;
  }
  return w.skip(static_cast<size_t>(count) * 8, "status_t.counter_values") && w.at_end();
}

bool walk_config(Walker& w) {
  return w.skip(8, "config_t.utime") && w.string("config_t.name") && w.string("config_t.source") &&
         w.string("config_t.yaml") && w.at_end();
}

bool walk_vo_delta(Walker& w) {
  return w.skip(2 * 8 + 6 * 8 + 36 * 8 + 8 + 2 * 4 + 8 + 2 * 4, "vo_delta_t fields") &&
         w.string("vo_delta_t.variant") && w.at_end();
}

template <class Msg>
bool is(int64_t hash) {
  return Msg::getHash() == hash;
}

}  // namespace

bool encoded_lengths_fit(int64_t expected_hash, const uint8_t* data, size_t size, std::string* reason) {
  if (size < 8) {
    *reason = "shorter than a fingerprint";
    return false;
  }
  uint64_t hash = 0;
  for (int i = 0; i < 8; ++i) hash = (hash << 8) | data[i];
  if (static_cast<int64_t>(hash) != expected_hash) {
    *reason = "wrong type (fingerprint does not match)";
    return false;
  }
  Walker w(data, size, reason);
  if (is<image_t>(expected_hash)) return walk_image(w);
  if (is<tracks_t>(expected_hash)) return walk_tracks(w);
  if (is<status_t>(expected_hash)) return walk_status(w);
  if (is<config_t>(expected_hash)) return walk_config(w);
  if (is<vo_delta_t>(expected_hash)) return walk_vo_delta(w);
  // The remaining types have no lengths: the decoder checks their size itself.
  return true;
}

bool decode_checked(int64_t hash, const uint8_t* data, size_t size, std::string* reason,
                    const std::function<int()>& decode) {
  if (!encoded_lengths_fit(hash, data, size, reason)) return false;
  int decoded = -1;
  try {
    decoded = decode();
  } catch (const std::exception& e) {
    *reason = std::string("decoder failed: ") + e.what();
    return false;
  }
  if (decoded < 0) {
    *reason = "does not decode (wrong type or fingerprint)";
    return false;
  }
  if (static_cast<size_t>(decoded) != size) {
    *reason = "only " + std::to_string(decoded) + " bytes decoded";
    return false;
  }
  return true;
}

}  // namespace nadir
