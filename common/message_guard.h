#pragma once
// Checks an encoded nadir message's declared lengths against its bytes before
// anything is allocated. lcm-gen's decoders resize a vector to the declared
// count before they check that the bytes are there, so a count of -1 throws
// and a count of 2^31-1 allocates gigabytes: a single hostile or corrupt
// message could kill or stall a process. Every decode goes through this first.

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace nadir {

// True when `data` starts with the fingerprint `expected_hash` and every
// length field (arrays, strings) fits exactly into `size` bytes. Otherwise
// false with `reason` saying which field and what it declared.
bool encoded_lengths_fit(int64_t expected_hash, const uint8_t* data, size_t size, std::string* reason);

// Runs `decode` (the generated decoder, returning the bytes it used) only
// when the declared lengths fit; false with the reason otherwise, also when
// the decoder fails, throws, or leaves bytes over. Never throws.
bool decode_checked(int64_t hash, const uint8_t* data, size_t size, std::string* reason,
                    const std::function<int()>& decode);

// decode_checked for a generated nadir type.
template <class Msg>
bool decode_message(const uint8_t* data, size_t size, Msg* msg, std::string* reason) {
  return decode_checked(Msg::getHash(), data, size, reason,
                        [&] { return msg->decode(data, 0, static_cast<int>(size)); });
}

// The LCM encoding of a generated nadir type (what decode_message reads).
template <class Msg>
std::vector<uint8_t> encode_message(const Msg& msg) {
  std::vector<uint8_t> bytes(static_cast<size_t>(msg.getEncodedSize()));
  msg.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
  return bytes;
}

}  // namespace nadir
