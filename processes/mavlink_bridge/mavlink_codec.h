#pragma once
// Payload encoding and decoding of the messages in mavlink_messages.h, driven
// by each message's field list (visit): little-endian, wire order, arrays
// inline. Decoding reads a payload zero-extended to the full length, which is
// how MAVLink 2's truncated trailing zeros and MAVLink 1's missing extension
// fields are restored.

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstring>
#include <string>
#include <type_traits>
#include <vector>

#include "processes/mavlink_bridge/mavlink_crc.h"
#include "processes/mavlink_bridge/mavlink_messages.h"

namespace nadir::mavlink {

inline constexpr size_t kMaxPayload = 255;

// What the frame parser needs to know about a message id.
struct MessageInfo {
  uint32_t id = 0;
  const char* name = "";
  uint8_t crc_extra = 0;
  uint8_t base_length = 0;  // without extensions: a MAVLink 1 payload
  uint8_t length = 0;       // with extensions
};

// nullptr for an id nadir does not know.
const MessageInfo* find_message(uint32_t id);

namespace detail {

template <class T>
const char* wire_type_name() {
  if constexpr (std::is_same_v<T, uint8_t>) return "uint8_t";
  else if constexpr (std::is_same_v<T, int8_t>) return "int8_t";
  else if constexpr (std::is_same_v<T, uint16_t>) return "uint16_t";
  else if constexpr (std::is_same_v<T, int16_t>) return "int16_t";
  else if constexpr (std::is_same_v<T, uint32_t>) return "uint32_t";
  else if constexpr (std::is_same_v<T, int32_t>) return "int32_t";
  else if constexpr (std::is_same_v<T, uint64_t>) return "uint64_t";
  else if constexpr (std::is_same_v<T, int64_t>) return "int64_t";
  else if constexpr (std::is_same_v<T, float>) return "float";
  else if constexpr (std::is_same_v<T, double>) return "double";
}

template <size_t N>
struct UnsignedOfSize;
template <>
struct UnsignedOfSize<1> { using type = uint8_t; };
template <>
struct UnsignedOfSize<2> { using type = uint16_t; };
template <>
struct UnsignedOfSize<4> { using type = uint32_t; };
template <>
struct UnsignedOfSize<8> { using type = uint64_t; };

// Through an unsigned integer of the same size, so the byte order of the host
// does not matter: shifts see values, not memory.
template <class T>
void put_le(uint8_t* p, T value) {
  using U = typename UnsignedOfSize<sizeof(T)>::type;
  U bits;
  std::memcpy(&bits, &value, sizeof(T));
  for (size_t i = 0; i < sizeof(T); ++i) p[i] = static_cast<uint8_t>(static_cast<uint64_t>(bits) >> (8 * i));
}

template <class T>
T get_le(const uint8_t* p) {
  using U = typename UnsignedOfSize<sizeof(T)>::type;
  uint64_t bits = 0;
  for (size_t i = 0; i < sizeof(T); ++i) bits |= static_cast<uint64_t>(p[i]) << (8 * i);
  const U narrow = static_cast<U>(bits);
  T value;
  std::memcpy(&value, &narrow, sizeof(T));
  return value;
}

struct LengthVisitor {
  size_t offset = 0;
  size_t base = 0;
  bool in_extensions = false;
  void extensions() {
    base = offset;
    in_extensions = true;
  }
  template <class T>
  void operator()(const char*, const T&) { offset += sizeof(T); }
  template <class T, size_t N>
  void operator()(const char*, const std::array<T, N>&) { offset += sizeof(T) * N; }
};

struct WriteVisitor {
  uint8_t* out;
  size_t offset = 0;
  void extensions() {}
  template <class T>
  void operator()(const char*, const T& value) {
    put_le<T>(out + offset, value);
    offset += sizeof(T);
  }
  template <class T, size_t N>
  void operator()(const char* name, const std::array<T, N>& values) {
    for (const T& value : values) (*this)(name, value);
  }
};

struct ReadVisitor {
  const uint8_t* in;
  size_t offset = 0;
  void extensions() {}
  template <class T>
  void operator()(const char*, T& value) {
    value = get_le<T>(in + offset);
    offset += sizeof(T);
  }
  template <class T, size_t N>
  void operator()(const char* name, std::array<T, N>& values) {
    for (T& value : values) (*this)(name, value);
  }
};

// CRC_EXTRA as the MAVLink generator computes it: the message name, then per
// base field its type, its name and (arrays) its length, folded to 8 bits.
struct CrcExtraVisitor {
  uint16_t crc;
  bool in_extensions = false;
  void extensions() { in_extensions = true; }
  template <class T>
  void operator()(const char* name, const T&) {
    if (in_extensions) return;
    crc = crc_accumulate(std::string(wire_type_name<T>()) + " " + name + " ", crc);
  }
  template <class T, size_t N>
  void operator()(const char* name, const std::array<T, N>&) {
    if (in_extensions) return;
    crc = crc_accumulate(std::string(wire_type_name<T>()) + " " + name + " ", crc);
    crc = crc_accumulate(static_cast<uint8_t>(N), crc);
  }
};

}  // namespace detail

template <class M>
MessageInfo message_info() {
  detail::LengthVisitor v;
  const M m{};
  M::visit(m, v);
  MessageInfo info;
  info.id = M::kId;
  info.name = M::kName;
  info.crc_extra = M::kCrcExtra;
  info.length = static_cast<uint8_t>(v.offset);
  info.base_length = static_cast<uint8_t>(v.in_extensions ? v.base : v.offset);
  return info;
}

template <class M>
uint8_t crc_extra_of() {
  detail::CrcExtraVisitor v{crc_accumulate(std::string(M::kName) + " ", kCrcSeed)};
  const M m{};
  M::visit(m, v);
  return static_cast<uint8_t>((v.crc & 0xFF) ^ (v.crc >> 8));
}

// The full-length payload (extensions included, zeros not yet truncated).
template <class M>
std::vector<uint8_t> encode_payload(const M& msg) {
  std::vector<uint8_t> payload(message_info<M>().length, 0);
  detail::WriteVisitor v{payload.data()};
  M::visit(msg, v);
  return payload;
}

// `size` may be shorter than the message (truncated zeros, MAVLink 1 without
// extensions); bytes beyond the message are ignored.
template <class M>
M decode_payload(const uint8_t* payload, size_t size) {
  uint8_t full[kMaxPayload] = {};
  std::memcpy(full, payload, std::min(size, kMaxPayload));
  M msg;
  detail::ReadVisitor v{full};
  M::visit(msg, v);
  return msg;
}

}  // namespace nadir::mavlink
