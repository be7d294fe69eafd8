#pragma once
// Little-endian field access for NovAtel binary logs, independent of the host.

#include <cstdint>
#include <cstring>

namespace nadir::ins_bridge {

inline uint16_t get_u16(const uint8_t* p) { return static_cast<uint16_t>(p[0] | (p[1] << 8)); }
inline uint32_t get_u32(const uint8_t* p) {
  return static_cast<uint32_t>(p[0]) | (static_cast<uint32_t>(p[1]) << 8) | (static_cast<uint32_t>(p[2]) << 16) |
         (static_cast<uint32_t>(p[3]) << 24);
}
inline uint64_t get_u64(const uint8_t* p) {
  return static_cast<uint64_t>(get_u32(p)) | (static_cast<uint64_t>(get_u32(p + 4)) << 32);
}
inline double get_f64(const uint8_t* p) {
  const uint64_t bits = get_u64(p);
  double value;
  std::memcpy(&value, &bits, sizeof value);
  return value;
}
inline float get_f32(const uint8_t* p) {
  const uint32_t bits = get_u32(p);
  float value;
  std::memcpy(&value, &bits, sizeof value);
  return value;
}

inline void put_u16(uint8_t* p, uint16_t v) {
  p[0] = static_cast<uint8_t>(v);
  p[1] = static_cast<uint8_t>(v >> 8);
}
inline void put_u32(uint8_t* p, uint32_t v) {
  for (int i = 0; i < 4; ++i) p[i] = static_cast<uint8_t>(v >> (8 * i));
}
inline void put_f64(uint8_t* p, double value) {
  uint64_t bits;
  std::memcpy(&bits, &value, sizeof bits);
  put_u32(p, static_cast<uint32_t>(bits));
  put_u32(p + 4, static_cast<uint32_t>(bits >> 32));
}
inline void put_f32(uint8_t* p, float value) {
  uint32_t bits;
  std::memcpy(&bits, &value, sizeof bits);
  put_u32(p, bits);
}

}  // namespace nadir::ins_bridge
